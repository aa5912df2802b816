//! Texture lookups filtered over a footprint: the area of the texture a
//! pixel covers at a camera ray's first hit ([`crate::footprint`]), so that
//! a texture's detail is averaged over the pixel instead of point-sampled
//! at a jittered position (which makes a pixel straddling a texel edge
//! flicker between two texels: noise the seed permutation cannot predict,
//! `QUALITY.md`, issue 14).
//!
//! # Mip levels
//!
//! The host stores each image's mip chain ([`IMAGE_HEADER_WORDS`] header
//! word 3 = the number of levels, at least 1; 0 reads as 1): level 0 is the
//! image, level `l + 1` the 2x2 box average of level `l` (half the size
//! rounded down, at least 1; the last row or column of an odd size is
//! clamped), colour averaged in linear light and stored sRGB-encoded, data
//! images averaged as stored; the levels follow one another from the
//! image's first texel word.
//!
//! # Filter
//!
//! For a footprint of `f` texels of level 0 (the footprint's side in
//! texture space times `sqrt(width * height)`):
//! - `f <= 1`: a box of side `f` around the point over the nearest texels
//!   (their overlaps weight them: a smooth blend across texel edges that
//!   becomes the nearest texel as `f -> 0`) for nearest-filtered textures;
//!   the bilinear lookup for bilinear ones (already continuous);
//! - `f > 1`: trilinear: bilinear lookups on the two levels around
//!   `log2 f`, blended linearly (the last level for larger footprints).

use crate::abi::{FILTER_BILINEAR, IMAGE_HEADER_WORDS};
use crate::texture::{locate, sample_image};
use glam::{Vec2, Vec3};

/// Most mip levels read (a side of 2^15 texels has 16).
pub const MAX_MIP_LEVELS: u32 = 16;

/// Linear RGB of image `image` at `uv` with `flags` (as
/// [`sample_image`]), averaged over a square footprint of side `width` in
/// texture coordinates (`uv` units; see the module docs for the filter).
/// `width <= 0` (or NaN) is exactly [`sample_image`].
#[inline]
pub fn sample_image_filtered(
    images: &[u32],
    image_count: u32,
    image: u32,
    flags: u32,
    uv: Vec2,
    width: f32,
) -> Vec3 {
    // `!(width > 0)` is also true for NaN.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    if !(width > 0.0) || image >= image_count {
        return sample_image(images, image_count, image, flags, uv);
    }
    // Not `u32::clamp`: it asserts `min <= max`, a panic path in shaders.
    #[allow(clippy::manual_clamp)]
    let levels = images[(image.wrapping_mul(IMAGE_HEADER_WORDS) + 3) as usize]
        .max(1)
        .min(MAX_MIP_LEVELS);
    let (base, x, y) = locate(images, image, flags, uv);
    let texels = width * libm::sqrtf((base.width * base.height) as f32);
    if texels <= 1.0 {
        if flags & FILTER_BILINEAR != 0 {
            return base.bilinear(images, x, y);
        }
        return box_nearest(images, &base, x, y, texels);
    }
    let lod = libm::log2f(texels).min((levels - 1) as f32);
    let l0 = libm::floorf(lod) as u32;
    let t = lod - l0 as f32;
    // Position as a fraction of the image (after the wrap reduction).
    let (u, v) = (x / base.width as f32, y / base.height as f32);
    let a = base.level(l0);
    let ca = a.bilinear(images, u * a.width as f32, v * a.height as f32);
    if t <= 0.0 || l0 + 1 >= levels {
        return ca;
    }
    let b = base.level(l0 + 1);
    let cb = b.bilinear(images, u * b.width as f32, v * b.height as f32);
    ca * (1.0 - t) + cb * t
}

/// A box of side `f` texels (`0 < f <= 1`) centred at `(x, y)` (texel
/// units) over the nearest texels of `image`: each of the (at most) 2 x 2
/// texels it overlaps weighted by the overlap.
#[inline]
fn box_nearest(images: &[u32], image: &crate::texture::ImageRef, x: f32, y: f32, f: f32) -> Vec3 {
    let (i, wx) = overlap(x, f);
    let (j, wy) = overlap(y, f);
    let top = image.fetch(images, i, j) * wx + image.fetch(images, i + 1, j) * (1.0 - wx);
    let bottom = image.fetch(images, i, j + 1) * wx + image.fetch(images, i + 1, j + 1) * (1.0 - wx);
    top * wy + bottom * (1.0 - wy)
}

/// The first texel `i` that the interval `[c - f/2, c + f/2]` (`0 < f <=
/// 1`) overlaps, and the share of the interval inside it (the rest is in
/// texel `i + 1`).
#[inline]
fn overlap(c: f32, f: f32) -> (i32, f32) {
    let lo = c - 0.5 * f;
    let first = libm::floorf(lo);
    let inside = ((first + 1.0 - lo) / f).min(1.0);
    (first as i32, inside)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::abi::{WRAP_CLAMP, WRAP_REPEAT};

    /// A 4x2 image with a 2-level chain: level 0 columns black, white,
    /// black, white (linear data), level 1 (2x1) both mid grey.
    fn images() -> Vec<u32> {
        let (k, w) = (0xFF00_0000u32, 0xFFFF_FFFFu32);
        let grey = 0xFF80_8080u32;
        vec![4, 4, 2, 2, k, w, k, w, k, w, k, w, grey, grey]
    }

    const DATA: u32 = crate::abi::TEXEL_LINEAR;

    #[test]
    fn no_footprint_is_the_point_lookup() {
        let img = images();
        for (u, v) in [(0.1f32, 0.3f32), (0.6, 0.9), (-3.2, 7.7)] {
            let uv = Vec2::new(u, v);
            for flags in [WRAP_REPEAT | DATA, WRAP_REPEAT | FILTER_BILINEAR | DATA] {
                let point = sample_image(&img, 1, 0, flags, uv);
                assert_eq!(sample_image_filtered(&img, 1, 0, flags, uv, 0.0), point);
                assert_eq!(sample_image_filtered(&img, 1, 0, flags, uv, f32::NAN), point);
            }
        }
    }

    /// A box straddling a texel edge blends the two texels by overlap; a
    /// box inside one texel is that texel.
    #[test]
    fn a_small_box_blends_by_overlap() {
        let img = images();
        let flags = WRAP_CLAMP | WRAP_CLAMP << 2 | DATA;
        // Texel 0 covers u in [0, 0.25): centre of the edge at u = 0.25.
        // Footprint 0.1 (texels: 0.1 * sqrt(8) = 0.283) centred at the edge: half each.
        let at_edge = sample_image_filtered(&img, 1, 0, flags, Vec2::new(0.25, 0.5), 0.1);
        assert!(
            (at_edge - Vec3::splat(0.5)).abs().max_element() < 1e-5,
            "{at_edge}"
        );
        // A quarter of the box over the edge: 3/4 black.
        let f = 0.1 * 8f32.sqrt();
        let x = 1.0 - 0.25 * f; // texel units: box [1 - 0.75 f, 1 + 0.25 f]
        let c = sample_image_filtered(&img, 1, 0, flags, Vec2::new(x / 4.0, 0.5), 0.1);
        assert!((c.x - 0.25).abs() < 1e-5, "{c}");
        let inside = sample_image_filtered(&img, 1, 0, flags, Vec2::new(0.375, 0.5), 0.05);
        assert_eq!(inside, Vec3::ONE);
    }

    /// A footprint of two texels reads level 1 (the average); between one
    /// and two texels, a blend of level 0's bilinear value and level 1.
    #[test]
    fn larger_footprints_read_the_mip_levels() {
        let img = images();
        let flags = WRAP_REPEAT | DATA;
        let grey = 128.0 / 255.0;
        let two_texels = 2.0 / 8f32.sqrt();
        let c = sample_image_filtered(&img, 1, 0, flags, Vec2::new(0.3, 0.5), two_texels);
        assert!((c - Vec3::splat(grey)).abs().max_element() < 1e-5, "{c}");
        // Beyond the last level: still the last level.
        let c = sample_image_filtered(&img, 1, 0, flags, Vec2::new(0.3, 0.5), 10.0);
        assert!((c - Vec3::splat(grey)).abs().max_element() < 1e-5, "{c}");
        // sqrt(2) texels: lod 0.5, half level 0 (bilinear at a texel centre: white) and half level 1.
        let c = sample_image_filtered(
            &img,
            1,
            0,
            flags,
            Vec2::new(0.375, 0.25),
            2f32.sqrt() / 8f32.sqrt(),
        );
        assert!(
            (c - Vec3::splat(0.5 * (1.0 + grey))).abs().max_element() < 1e-5,
            "{c}"
        );
    }
}
