//! Texture lookup: RGBA8 images in one `u32` buffer, sampled with a
//! wrap mode per axis and nearest or bilinear filtering (glTF samplers
//! without mipmaps). Texels are sRGB-encoded colour, decoded per texel
//! before filtering, unless the sampler flags carry
//! [`crate::abi::TEXEL_LINEAR`] (data textures such as glTF's
//! metallic-roughness texture: channel `c` reads as `c / 255`).
//!
//! Texture space: `uv = (0, 0)` is the top-left corner of the image's first
//! texel, `(1, 1)` the bottom-right corner of its last (glTF's convention);
//! texel `(i, j)` covers `[i / w, (i + 1) / w) x [j / h, (j + 1) / h)` and
//! its centre is at `((i + 0.5) / w, (j + 0.5) / h)`. Layout of the buffer
//! and of the sampler flags: [`crate::abi::IMAGE_HEADER_WORDS`],
//! [`crate::abi::WRAP_REPEAT`].

use crate::abi::{FILTER_BILINEAR, IMAGE_HEADER_WORDS, TEXEL_LINEAR, WRAP_CLAMP, WRAP_MIRROR};
use glam::{Vec2, Vec3};

/// sRGB decoding (IEC 61966-2-1) of an 8-bit channel: linear value in `[0, 1]`.
#[inline]
pub fn srgb_to_linear(byte: u32) -> f32 {
    let c = byte as f32 * (1.0 / 255.0);
    if c <= 0.040_45 {
        c * (1.0 / 12.92)
    } else {
        libm::powf((c + 0.055) * (1.0 / 1.055), 2.4)
    }
}

/// Linear RGB of a packed texel `r | g << 8 | b << 16 | a << 24` (sRGB).
#[inline]
pub fn decode_texel(texel: u32) -> Vec3 {
    Vec3::new(
        srgb_to_linear(texel & 0xFF),
        srgb_to_linear((texel >> 8) & 0xFF),
        srgb_to_linear((texel >> 16) & 0xFF),
    )
}

/// RGB of a packed texel `r | g << 8 | b << 16 | a << 24` holding linear
/// data: each channel `c` as `c / 255`, in `[0, 1]`.
#[inline]
pub fn decode_texel_linear(texel: u32) -> Vec3 {
    Vec3::new(
        (texel & 0xFF) as f32,
        ((texel >> 8) & 0xFF) as f32,
        ((texel >> 16) & 0xFF) as f32,
    ) * (1.0 / 255.0)
}

/// `uv` coordinate reduced to the range the wrap mode needs before scaling
/// by the image size: `[0, 1)` for repeat, `[0, 2)` for mirror, `[0, 1]`
/// for clamp. NaN and values beyond `±2^24` (where f32 has no fraction)
/// become 0, so the texel index below never overflows.
#[inline]
pub(crate) fn reduce(u: f32, wrap: u32) -> f32 {
    // `!(|u| <= 2^24)` is true for NaN and infinities too.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    let u = if !(libm::fabsf(u) <= 16_777_216.0) { 0.0 } else { u };
    if wrap == WRAP_CLAMP {
        // Not `f32::clamp`: it asserts `min <= max`, a panic path in shaders.
        #[allow(clippy::manual_clamp)]
        u.max(0.0).min(1.0)
    } else if wrap == WRAP_MIRROR {
        u - 2.0 * libm::floorf(u * 0.5)
    } else {
        u - libm::floorf(u)
    }
}

/// Texel index along an axis of `size` texels for integer coordinate `i`
/// (which lies in `[-1, 2 size]` after [`reduce`]), by the wrap mode.
#[inline]
fn wrap_index(i: i32, size: i32, wrap: u32) -> i32 {
    if wrap == WRAP_CLAMP {
        i.max(0).min(size - 1)
    } else if wrap == WRAP_MIRROR {
        let period = 2 * size;
        let m = ((i % period) + period) % period;
        if m >= size {
            period - 1 - m
        } else {
            m
        }
    } else {
        ((i % size) + size) % size
    }
}

/// Linear RGB of image `image` of `images` at `uv`, sampled with `flags`
/// (wrap modes, filter, and [`TEXEL_LINEAR`] for data textures). An image index at or beyond `image_count`
/// returns white (1, 1, 1), so a bad index never reads outside the buffer
/// (the host validates indices; this keeps the kernel safe regardless).
#[inline]
pub fn sample_image(images: &[u32], image_count: u32, image: u32, flags: u32, uv: Vec2) -> Vec3 {
    if image >= image_count {
        return Vec3::ONE;
    }
    let (image, x, y) = locate(images, image, flags, uv);
    if flags & FILTER_BILINEAR == 0 {
        image.fetch(images, libm::floorf(x) as i32, libm::floorf(y) as i32)
    } else {
        image.bilinear(images, x, y)
    }
}

/// Alpha (linear, `a / 255`, in `[0, 1]`) of image `image` of `images` at
/// `uv`, sampled with `flags` like [`sample_image`] (same texels, same
/// bilinear weights). An image index at or beyond `image_count` returns 1.
#[inline]
pub fn sample_alpha(images: &[u32], image_count: u32, image: u32, flags: u32, uv: Vec2) -> f32 {
    if image >= image_count {
        return 1.0;
    }
    let (image, x, y) = locate(images, image, flags, uv);
    if flags & FILTER_BILINEAR == 0 {
        image.fetch_alpha(images, libm::floorf(x) as i32, libm::floorf(y) as i32)
    } else {
        let (fx, fy) = (x - 0.5, y - 0.5);
        let (x0, y0) = (libm::floorf(fx), libm::floorf(fy));
        let (tx, ty) = (fx - x0, fy - y0);
        let (i, j) = (x0 as i32, y0 as i32);
        let top = image.fetch_alpha(images, i, j) * (1.0 - tx) + image.fetch_alpha(images, i + 1, j) * tx;
        let bottom =
            image.fetch_alpha(images, i, j + 1) * (1.0 - tx) + image.fetch_alpha(images, i + 1, j + 1) * tx;
        top * (1.0 - ty) + bottom * ty
    }
}

/// Image `image`'s header (`image < image_count`) and `uv` in texel units
/// after the wrap modes' reduction (before filtering).
#[inline]
pub(crate) fn locate(images: &[u32], image: u32, flags: u32, uv: Vec2) -> (ImageRef, f32, f32) {
    let h = (image.wrapping_mul(IMAGE_HEADER_WORDS)) as usize;
    let offset = images[h];
    let width = images[h + 1].max(1) as i32;
    let height = images[h + 2].max(1) as i32;
    let (wrap_u, wrap_v) = (flags & 3, (flags >> 2) & 3);
    let x = reduce(uv.x, wrap_u) * width as f32;
    let y = reduce(uv.y, wrap_v) * height as f32;
    let image = ImageRef {
        offset,
        width,
        height,
        wrap_u,
        wrap_v,
        linear: flags & TEXEL_LINEAR != 0,
    };
    (image, x, y)
}

/// One image's header and wrap modes (of one mip level: the texels of
/// level `l` start at `offset` and are `width x height`).
#[derive(Clone, Copy)]
pub(crate) struct ImageRef {
    pub(crate) offset: u32,
    pub(crate) width: i32,
    pub(crate) height: i32,
    wrap_u: u32,
    wrap_v: u32,
    /// [`TEXEL_LINEAR`]: texels are data, not sRGB.
    linear: bool,
}

impl ImageRef {
    /// The packed texel `(i, j)` after wrapping.
    #[inline]
    pub(crate) fn texel(&self, images: &[u32], i: i32, j: i32) -> u32 {
        let i = wrap_index(i, self.width, self.wrap_u);
        let j = wrap_index(j, self.height, self.wrap_v);
        let k = self.offset.wrapping_add((j * self.width + i) as u32);
        images[k as usize]
    }

    /// Alpha of texel `(i, j)` after wrapping: `a / 255`.
    #[inline]
    fn fetch_alpha(&self, images: &[u32], i: i32, j: i32) -> f32 {
        (self.texel(images, i, j) >> 24) as f32 * (1.0 / 255.0)
    }

    /// Bilinear interpolation between the four texel centres around `(x,
    /// y)` (texel units of this level, after the wrap modes' reduction).
    #[inline]
    pub(crate) fn bilinear(&self, images: &[u32], x: f32, y: f32) -> Vec3 {
        let (fx, fy) = (x - 0.5, y - 0.5);
        let (x0, y0) = (libm::floorf(fx), libm::floorf(fy));
        let (tx, ty) = (fx - x0, fy - y0);
        let (i, j) = (x0 as i32, y0 as i32);
        let top = self.fetch(images, i, j) * (1.0 - tx) + self.fetch(images, i + 1, j) * tx;
        let bottom = self.fetch(images, i, j + 1) * (1.0 - tx) + self.fetch(images, i + 1, j + 1) * tx;
        top * (1.0 - ty) + bottom * ty
    }

    /// Mip level `level` of this image (level 0 is the image itself): the
    /// levels follow each other in the buffer, each half the size of the
    /// one before, rounded down, at least 1 (`crate::texture_filter` has
    /// the layout).
    #[inline]
    pub(crate) fn level(&self, level: u32) -> ImageRef {
        let mut r = *self;
        let mut l = 0u32;
        while l < level {
            r.offset = r.offset.wrapping_add((r.width * r.height) as u32);
            r.width = (r.width / 2).max(1);
            r.height = (r.height / 2).max(1);
            l += 1;
        }
        r
    }

    /// Linear RGB (or data) of texel `(i, j)` after wrapping.
    #[inline]
    pub(crate) fn fetch(&self, images: &[u32], i: i32, j: i32) -> Vec3 {
        let texel = self.texel(images, i, j);
        if self.linear {
            decode_texel_linear(texel)
        } else {
            decode_texel(texel)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::abi::WRAP_REPEAT;

    /// A 2x2 image: black, white / red, (64, 128, 255).
    fn images() -> [u32; 8] {
        [4, 2, 2, 0, 0xFF00_0000, 0xFFFF_FFFF, 0xFF00_00FF, 0xFFFF_8040]
    }

    #[test]
    fn srgb_decoding_matches_the_standard() {
        assert_eq!(srgb_to_linear(0), 0.0);
        assert!((srgb_to_linear(255) - 1.0).abs() < 1e-6);
        // 0.5 encoded is 0.214 linear; byte 10 is in the linear segment.
        assert!((srgb_to_linear(128) - 0.2158605).abs() < 1e-5);
        assert!((srgb_to_linear(10) - 10.0 / 255.0 / 12.92).abs() < 1e-7);
    }

    /// [`TEXEL_LINEAR`] reads the bytes as data (`c / 255`), nearest and
    /// bilinear, and leaves sRGB decoding alone without the flag.
    #[test]
    fn linear_texels_read_as_data() {
        let img = images();
        let at = Vec2::new(0.75, 0.75);
        let data = sample_image(&img, 1, 0, WRAP_REPEAT | TEXEL_LINEAR, at);
        assert_eq!(data, Vec3::new(64.0, 128.0, 255.0) / 255.0);
        assert_eq!(
            sample_image(&img, 1, 0, WRAP_REPEAT, at),
            decode_texel(0xFFFF_8040)
        );
        let mid = sample_image(&img, 1, 0, FILTER_BILINEAR | TEXEL_LINEAR, Vec2::new(0.5, 0.25));
        assert!((mid - Vec3::splat(0.5)).abs().max_element() < 1e-6, "{mid}");
    }

    #[test]
    fn nearest_lookup_returns_the_texel_under_uv() {
        let img = images();
        let at = |u: f32, v: f32, flags: u32| sample_image(&img, 1, 0, flags, Vec2::new(u, v));
        assert_eq!(at(0.25, 0.25, WRAP_REPEAT), Vec3::ZERO);
        assert_eq!(at(0.75, 0.25, WRAP_REPEAT), Vec3::ONE);
        assert_eq!(at(0.25, 0.75, WRAP_REPEAT), Vec3::new(1.0, 0.0, 0.0));
        let c = at(0.75, 0.75, WRAP_REPEAT);
        assert_eq!(c, decode_texel(0xFFFF_8040));
        // Repeat: one period further is the same texel; clamp: the edge texel.
        assert_eq!(at(1.75, -0.25, WRAP_REPEAT), at(0.75, 0.75, WRAP_REPEAT));
        assert_eq!(at(1.75, -0.25, WRAP_CLAMP | WRAP_CLAMP << 2), Vec3::ONE);
        // Mirror: (1.25) mirrors to 0.75.
        assert_eq!(at(1.25, 0.25, WRAP_MIRROR), Vec3::ONE);
        assert_eq!(at(2.25, 0.25, WRAP_MIRROR), Vec3::ZERO);
        // NaN and huge coordinates read a texel, never out of bounds.
        assert_eq!(at(f32::NAN, f32::INFINITY, WRAP_REPEAT), Vec3::ZERO);
        // (u reduces to 0: between texel columns 0 and its mirror, both black;
        // v reduces to 0 with repeat: half row 0, half row 1 -> half red.)
        assert_eq!(
            at(1e30, -1e30, WRAP_MIRROR | FILTER_BILINEAR),
            Vec3::new(0.5, 0.0, 0.0)
        );
        // Bad image index: white.
        assert_eq!(sample_image(&img, 1, 1, 0, Vec2::ZERO), Vec3::ONE);
    }

    /// Alpha reads the top byte as `a / 255`, at the texels and with the
    /// weights of the colour lookup.
    #[test]
    fn alpha_lookup_reads_the_alpha_byte() {
        let mut img = images();
        img[4] = 0x0000_0000; // top left: alpha 0
        let at = |u: f32, v: f32, flags: u32| sample_alpha(&img, 1, 0, flags, Vec2::new(u, v));
        assert_eq!(at(0.25, 0.25, WRAP_REPEAT), 0.0);
        assert_eq!(at(0.75, 0.25, WRAP_REPEAT), 1.0);
        let clamp = WRAP_CLAMP | WRAP_CLAMP << 2 | FILTER_BILINEAR;
        assert!((at(0.5, 0.25, clamp) - 0.5).abs() < 1e-6);
        assert_eq!(sample_alpha(&img, 1, 3, 0, Vec2::ZERO), 1.0);
    }

    #[test]
    fn bilinear_lookup_interpolates_between_texel_centres() {
        let img = images();
        let at =
            |u: f32, v: f32, flags: u32| sample_image(&img, 1, 0, flags | FILTER_BILINEAR, Vec2::new(u, v));
        // At a texel centre: that texel.
        assert_eq!(at(0.75, 0.25, WRAP_CLAMP | WRAP_CLAMP << 2), Vec3::ONE);
        // Half-way between black and white centres on the top row.
        let mid = at(0.5, 0.25, WRAP_CLAMP | WRAP_CLAMP << 2);
        assert!((mid - Vec3::splat(0.5)).abs().max_element() < 1e-6, "{mid}");
        // Repeat wraps across the edge: u = 0 is half black (texel 0), half white (texel 1).
        let edge = at(0.0, 0.25, WRAP_REPEAT);
        assert!((edge - Vec3::splat(0.5)).abs().max_element() < 1e-6, "{edge}");
    }
}
