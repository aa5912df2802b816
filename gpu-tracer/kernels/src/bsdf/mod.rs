//! Reflectance models (BRDFs) of surfaces, shader-shaped (the CPU renderer
//! runs the same functions):
//!
//! - [`fresnel`]: Schlick's Fresnel reflectance and the glTF dielectric's
//!   `F0 = 0.04`;
//! - [`ggx`]: the Trowbridge-Reitz (GGX) microfacet distribution, Smith's
//!   masking and height-correlated masking-shadowing, and the sampling of
//!   visible normals with its density;
//! - [`metallic_roughness`]: the glTF 2.0 metallic-roughness BRDF built from
//!   those two (evaluation, lobe-selecting sampler, mixture density).
//!
//! Imports flow one way: `metallic_roughness` uses `ggx` and `fresnel`,
//! which use nothing of each other. Every function works in the local
//! shading frame, `z` along the shading normal, with unit directions pointing
//! away from the surface; [`to_local`] moves a world vector into a
//! [`Frame`].

pub mod fresnel;
pub mod ggx;
pub mod metallic_roughness;

pub use metallic_roughness::{BsdfSample, MetallicRoughness};

use crate::sampling::Frame;
use glam::Vec3;

/// Coordinates of the world vector `w` in `frame` (`x` along the tangent,
/// `z` along the normal): the inverse of [`Frame::to_world`] for the
/// orthonormal frames [`Frame::from_normal`] builds. Length is preserved.
#[inline]
pub fn to_local(frame: &Frame, w: Vec3) -> Vec3 {
    Vec3::new(frame.tangent.dot(w), frame.bitangent.dot(w), frame.normal.dot(w))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn to_local_inverts_to_world() {
        let n = Vec3::new(0.3, -0.5, 0.8).normalize();
        let frame = Frame::from_normal(n);
        assert!((to_local(&frame, n) - Vec3::Z).length() < 1e-6);
        let v = Vec3::new(-0.2, 0.7, 0.1);
        assert!((frame.to_world(to_local(&frame, v)) - v).length() < 1e-6);
    }
}
