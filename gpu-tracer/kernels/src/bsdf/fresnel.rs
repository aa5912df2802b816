//! Schlick's approximation of the Fresnel reflectance (Schlick 1994, "An
//! Inexpensive BRDF Model for Physically-based Rendering", eq. 15), in the
//! form the glTF 2.0 specification (appendix B, "Fresnel") uses:
//! `F = F0 + (1 - F0) (1 - |cos|)^5`.
//!
//! `cos` is the cosine between the direction and the microfacet normal (the
//! half vector `h`): `|wo . h|`, which equals `|wi . h|` for a reflection.

use glam::Vec3;

/// Normal-incidence reflectance of the glTF dielectric, `((ior - 1) / (ior +
/// 1))^2` with `ior = 1.5` (glTF 2.0 specification, appendix B, "Metal BRDF
/// and Dielectric BRDF": "the dielectric index of refraction `ior = 1.5` is
/// now `f0 = 0.04`"; also `KHR_materials_ior`'s default).
pub const DIELECTRIC_F0: f32 = 0.04;

/// Schlick's weight `(1 - |cos|)^5`, in `[0, 1]`: 0 at normal incidence
/// (`|cos| = 1`), 1 at grazing (`cos = 0`). `|cos| > 1` from rounding gives 0.
#[inline]
pub fn schlick_weight(cos: f32) -> f32 {
    let m = (1.0 - libm::fabsf(cos)).max(0.0);
    let m2 = m * m;
    m2 * m2 * m
}

/// Schlick's Fresnel reflectance per RGB channel, `f0 + (1 - f0) w` with
/// `w =` [`schlick_weight`]`(cos)`. `f0` in `[0, 1]` per channel gives a result
/// in `[f0, 1]`; `cos` is the cosine to the half vector (sign ignored).
#[inline]
pub fn fresnel_schlick(f0: Vec3, cos: f32) -> Vec3 {
    let w = schlick_weight(cos);
    f0 + (Vec3::ONE - f0) * w
}

/// Scalar form of [`fresnel_schlick`] (one channel, or a mean reflectance).
#[inline]
pub fn fresnel_schlick_scalar(f0: f32, cos: f32) -> f32 {
    f0 + (1.0 - f0) * schlick_weight(cos)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schlick_endpoints_and_monotonicity() {
        assert_eq!(schlick_weight(1.0), 0.0);
        assert_eq!(schlick_weight(0.0), 1.0);
        assert_eq!(schlick_weight(-1.0), 0.0, "sign is ignored");
        assert_eq!(schlick_weight(1.0 + 1e-6), 0.0, "rounding above 1 is clamped");
        let f0 = Vec3::new(DIELECTRIC_F0, 0.5, 1.0);
        assert_eq!(fresnel_schlick(f0, 1.0), f0);
        assert_eq!(fresnel_schlick(f0, 0.0), Vec3::ONE);
        let mut last = 0.0;
        for i in 0..=100 {
            let w = schlick_weight(1.0 - i as f32 / 100.0);
            assert!(w >= last, "weight grows towards grazing");
            last = w;
            let f = fresnel_schlick_scalar(DIELECTRIC_F0, 1.0 - i as f32 / 100.0);
            assert!((DIELECTRIC_F0..=1.0).contains(&f));
        }
    }

    #[test]
    fn dielectric_f0_is_that_of_ior_1_5() {
        let ior = 1.5f32;
        let f0 = ((ior - 1.0) / (ior + 1.0)).powi(2);
        assert!((f0 - DIELECTRIC_F0).abs() < 1e-7);
    }
}
