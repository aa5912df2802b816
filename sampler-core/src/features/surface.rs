//! What a pixel shows, for the feature-aware permutation
//! ([`crate::features::permute`]): a compact per-pixel record of the primary
//! hit (surface id, depth, normal), the rule that decides whether two
//! pixels show the same surface, and a sort key with the albedo divided
//! out.
//!
//! Renderers with their own G-buffer fill a [`SurfaceFeature`] per visible
//! pixel (`width * height`, row-major) with [`SurfaceFeature::new`]; the
//! tracer builds it from its G-buffer.

use crate::permutation::layout::FrameParams;
use crate::permutation::sort::luma;
use glam::{Vec2, Vec3};

/// [`SurfaceFeature::id`] of a pixel whose primary ray hits nothing
/// (background, sky). Such pixels are all one surface.
pub const NO_SURFACE: u32 = u32::MAX;

/// Albedo luma below which [`demodulated_luma`] does not divide (emitters,
/// black surfaces, background): their key stays the radiance's luma.
pub const ALBEDO_FLOOR: f32 = 1.0e-3;

/// The primary hit of one pixel, 16 bytes (`u32`/`f32` only: a storage
/// buffer element as it is).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct SurfaceFeature {
    /// Object (or material) id of the primary hit; [`NO_SURFACE`] for none.
    pub id: u32,
    /// Linear depth of the hit: its distance along the camera's forward
    /// axis, world units, `> 0`. Ignored for [`NO_SURFACE`].
    pub depth: f32,
    /// Unit shading normal, octahedral-encoded ([`encode_normal`]): two
    /// 16-bit signed-normalised components, `x` in bits 0-15, `y` in 16-31.
    pub normal: u32,
    /// Reserved, 0.
    pub reserved: u32,
}

impl SurfaceFeature {
    /// The feature of a hit on surface `id` (below [`NO_SURFACE`]) at linear
    /// depth `depth` with unit normal `normal`.
    ///
    /// # Example
    ///
    /// ```
    /// use sampler_core::{same_surface, FeatureThresholds, SurfaceFeature};
    /// use glam::Vec3;
    /// let floor = SurfaceFeature::new(3, 10.0, Vec3::Y);
    /// let near = SurfaceFeature::new(3, 10.5, Vec3::Y);
    /// let wall = SurfaceFeature::new(4, 10.0, Vec3::X);
    /// let t = FeatureThresholds::DEFAULT;
    /// assert!(same_surface(&floor, &near, &t));
    /// assert!(!same_surface(&floor, &wall, &t));
    /// ```
    #[inline]
    pub fn new(id: u32, depth: f32, normal: Vec3) -> Self {
        SurfaceFeature {
            id,
            depth,
            normal: encode_normal(normal),
            reserved: 0,
        }
    }

    /// The feature of a pixel that shows no surface.
    #[inline]
    pub fn none() -> Self {
        SurfaceFeature {
            id: NO_SURFACE,
            depth: 0.0,
            normal: 0,
            reserved: 0,
        }
    }
}

/// When two pixels count as the same surface ([`same_surface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct FeatureThresholds {
    /// Largest depth difference relative to the larger depth, `>= 0`.
    pub depth_relative: f32,
    /// Smallest cosine between the two normals, in `[-1, 1]`.
    pub normal_cos: f32,
}

impl FeatureThresholds {
    /// Defaults: 10% of the depth, normals within about 25 degrees
    /// (cos = 0.9). A planar surface seen at 6 px distance (the retarget
    /// radius) at the grazing angles of a room-scale scene changes depth by
    /// a few percent; a crease of a box is 90 degrees; a sphere of 20 px
    /// radius turns by about 17 degrees over 6 px.
    pub const DEFAULT: FeatureThresholds = FeatureThresholds {
        depth_relative: 0.1,
        normal_cos: 0.9,
    };
}

impl Default for FeatureThresholds {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Whether `a` and `b` show the same surface: the same id, and (for a hit)
/// depths within `t.depth_relative` of the larger one and normals within
/// `t.normal_cos` (equal normal encodings always match). Symmetric; not
/// transitive. NaN depths are never the same.
#[inline]
pub fn same_surface(a: &SurfaceFeature, b: &SurfaceFeature, t: &FeatureThresholds) -> bool {
    if a.id != b.id {
        return false;
    }
    if a.id == NO_SURFACE {
        return true;
    }
    let larger = if a.depth > b.depth { a.depth } else { b.depth };
    // Written so that NaN depths fail.
    let close = libm::fabsf(a.depth - b.depth) <= t.depth_relative * larger;
    if !close {
        return false;
    }
    // Equal encodings (every pixel of a flat face) match without decoding.
    a.normal == b.normal || decode_normal(a.normal).dot(decode_normal(b.normal)) >= t.normal_cos
}

/// The sort key with the albedo divided out: `luma(radiance) / luma(albedo)`
/// (as SVGF-style denoisers demodulate), or `luma(radiance)` where the
/// albedo's luma is below [`ALBEDO_FLOOR`]. On a textured surface the key
/// then follows the noise, not the texture.
///
/// # Example
///
/// ```
/// use sampler_core::demodulated_luma;
/// use glam::Vec3;
/// // The same irradiance on a dark and a bright texel gives the same key.
/// let light = Vec3::splat(0.5);
/// let (dark, bright) = (Vec3::splat(0.2), Vec3::splat(0.8));
/// let a = demodulated_luma(light * dark, dark);
/// let b = demodulated_luma(light * bright, bright);
/// assert!((a - b).abs() < 1e-6);
/// ```
#[inline]
pub fn demodulated_luma(radiance: Vec3, albedo: Vec3) -> f32 {
    let a = luma(albedo);
    if a >= ALBEDO_FLOOR {
        luma(radiance) / a
    } else {
        luma(radiance)
    }
}

/// Octahedral encoding of a unit vector into two 16-bit snorm components
/// (`x` in the low half). Error below 1e-4 rad.
#[inline]
pub fn encode_normal(n: Vec3) -> u32 {
    let l1 = libm::fabsf(n.x) + libm::fabsf(n.y) + libm::fabsf(n.z);
    let inv = if l1 > 0.0 { 1.0 / l1 } else { 0.0 };
    let mut p = Vec2::new(n.x * inv, n.y * inv);
    if n.z < 0.0 {
        p = Vec2::new(
            (1.0 - libm::fabsf(p.y)) * sign(p.x),
            (1.0 - libm::fabsf(p.x)) * sign(p.y),
        );
    }
    snorm16(p.x) | (snorm16(p.y) << 16)
}

/// Inverse of [`encode_normal`]: a unit vector.
#[inline]
pub fn decode_normal(v: u32) -> Vec3 {
    let x = unsnorm16(v & 0xFFFF);
    let y = unsnorm16(v >> 16);
    let z = 1.0 - libm::fabsf(x) - libm::fabsf(y);
    let (x, y) = if z < 0.0 {
        ((1.0 - libm::fabsf(y)) * sign(x), (1.0 - libm::fabsf(x)) * sign(y))
    } else {
        (x, y)
    };
    let n = Vec3::new(x, y, z);
    let len = libm::sqrtf(n.dot(n));
    if len > 0.0 {
        n / len
    } else {
        Vec3::Z
    }
}

#[inline]
fn sign(v: f32) -> f32 {
    if v < 0.0 {
        -1.0
    } else {
        1.0
    }
}

#[inline]
fn snorm16(v: f32) -> u32 {
    let c = v.clamp(-1.0, 1.0);
    let q = libm::roundf(c * 32767.0) as i32;
    (q as u32) & 0xFFFF
}

#[inline]
fn unsnorm16(bits: u32) -> f32 {
    let q = ((bits << 16) as i32) >> 16;
    let v = q as f32 / 32767.0;
    if v < -1.0 {
        -1.0
    } else {
        v
    }
}

/// Whether the retarget edge from padded-buffer index `p` to index `q` is
/// cut: one end is padding and the other visible, or both are visible and
/// not [`same_surface`].
#[inline]
pub fn edge_is_cut(
    params: &FrameParams,
    features: &[SurfaceFeature],
    thresholds: &FeatureThresholds,
    p: u32,
    q: u32,
) -> bool {
    let pw = params.padded_width;
    let (px, py, qx, qy) = (p % pw, p / pw, q % pw, q / pw);
    let p_visible = px < params.width && py < params.height;
    let q_visible = qx < params.width && qy < params.height;
    if p_visible != q_visible {
        return true;
    }
    if !p_visible {
        return false;
    }
    let a = &features[(py * params.width + px) as usize];
    let b = &features[(qy * params.width + qx) as usize];
    !same_surface(a, b, thresholds)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normals_round_trip() {
        let dirs = [
            Vec3::X,
            -Vec3::Y,
            Vec3::Z,
            -Vec3::Z,
            Vec3::new(0.3, -0.5, -0.81).normalize(),
            Vec3::new(-0.7, 0.1, 0.7).normalize(),
        ];
        for d in dirs {
            let r = decode_normal(encode_normal(d));
            assert!(r.dot(d) > 0.999_999, "{d:?} -> {r:?}");
        }
    }

    #[test]
    fn same_surface_follows_id_depth_and_normal() {
        let t = FeatureThresholds::DEFAULT;
        let a = SurfaceFeature::new(3, 10.0, Vec3::Y);
        assert!(same_surface(&a, &SurfaceFeature::new(3, 10.9, Vec3::Y), &t));
        assert!(!same_surface(&a, &SurfaceFeature::new(3, 11.2, Vec3::Y), &t));
        assert!(!same_surface(&a, &SurfaceFeature::new(4, 10.0, Vec3::Y), &t));
        assert!(!same_surface(&a, &SurfaceFeature::new(3, 10.0, Vec3::X), &t));
        assert!(!same_surface(&a, &SurfaceFeature::none(), &t));
        assert!(same_surface(&SurfaceFeature::none(), &SurfaceFeature::none(), &t));
        assert!(!same_surface(&a, &SurfaceFeature::new(3, f32::NAN, Vec3::Y), &t));
    }

    #[test]
    fn demodulation_divides_by_albedo_luma_above_the_floor() {
        let white = Vec3::ONE;
        assert!((demodulated_luma(Vec3::splat(0.25), Vec3::splat(0.5)) - 0.5).abs() < 1e-6);
        assert_eq!(demodulated_luma(white, Vec3::ZERO), luma(white));
    }
}
