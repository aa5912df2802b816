//! The glTF 2.0 metallic-roughness BRDF (specification, appendix B):
//! evaluation, importance sampling and its density.
//!
//! ```text
//! material        = mix(dielectric_brdf, metal_brdf, metallic)
//! metal_brdf      = F_metal D V,                F_metal = schlick(f0 = base_color, |wo . h|)
//! dielectric_brdf = (1 - F_diel) base_color / pi + F_diel D V,
//!                                               F_diel  = schlick(f0 = 0.04, |wo . h|)
//! ```
//!
//! with `D` and `V = G2 / (4 |wo.z| |wi.z|)` the GGX terms of
//! [`super::ggx`] (`alpha = roughness^2`, height-correlated Smith `G2`), and
//! `h = normalize(wo + wi)`. Expanded, as [`MetallicRoughness::eval`]
//! computes it:
//!
//! ```text
//! f = F D V + (1 - metallic) (1 - F_diel) base_color / pi,
//! F = f0 + (1 - f0) (1 - |wo . h|)^5,  f0 = mix(0.04, base_color, metallic)
//! ```
//!
//! (`mix` of the two Schlick terms is Schlick's form with the mixed `f0`).
//!
//! # Conventions
//!
//! - Directions are unit vectors in the local shading frame, `z` along the
//!   shading normal (build it with `crate::sampling::Frame::from_normal` and
//!   move vectors in with [`super::to_local`]); both point away from the
//!   surface. The BRDF is one-sided: `wo.z <= 0` or `wi.z <= 0` gives a zero
//!   BRDF and a zero density. A two-sided surface flips its normal towards
//!   `wo` first, as the tracer does for its Lambertian materials.
//! - [`MetallicRoughness::eval`] is the BRDF `f` in 1/sr, **not** multiplied
//!   by `cos(theta_i) = wi.z`; [`BsdfSample::weight`] is `f wi.z / pdf`.
//! - The material is reciprocal: `eval(wo, wi) = eval(wi, wo)` (every term
//!   depends on `h`, `|wo . h| = |wi . h|`, and `V` is symmetric).
//! - It is the specification's model, which is not energy conserving (the
//!   specification says so: appendix B, "Coupling Diffuse and Specular
//!   Reflection"): the diffuse weight `1 - F(|wo . h|)` is near 0.96 for most
//!   `wi` while the specular lobe reflects up to `F(wo.z)`, so a white
//!   dielectric reflects more than it receives at grazing `wo` and low
//!   roughness (measured albedo 1.30 at roughness 0.1, `wo.z = 0.2`; 1.03 at
//!   `wo.z = 0.5`; at most 1 at `wo.z = 0.9` for every tested roughness: the test
//!   `dielectric_white_furnace_gains_only_at_grazing` in `tests/bsdf.rs`).
//!   Single scattering also loses energy at high roughness (no
//!   multiple-scattering compensation: a white metal of roughness 1 reflects
//!   0.33 to 0.64 for `wo.z` from 0.9 to 0.2).
//!
//! # Sampling
//!
//! [`MetallicRoughness::sample`] picks the specular lobe (GGX visible normals,
//! [`super::ggx::sample_visible_normal`], then a mirror reflection) with
//! probability [`MetallicRoughness::specular_probability`]`(wo)` and the
//! diffuse lobe (cosine-weighted hemisphere) otherwise, and returns the
//! density of the mixture of both (one-sample MIS with the balance
//! heuristic), which is what [`MetallicRoughness::pdf`] returns for the same
//! pair: `p_s reflected_pdf(wo, wi) + (1 - p_s) wi.z / pi`.

use super::fresnel::{schlick_weight, DIELECTRIC_F0};
use super::ggx::{
    alpha_from_roughness, distribution, reflect, reflected_pdf, sample_visible_normal, visibility,
};
use crate::sampling::{cosine_hemisphere_pdf, sample_cosine_hemisphere};
use core::f32::consts::FRAC_1_PI;
use glam::{Vec2, Vec3};

/// The glTF metallic-roughness parameters at one surface point, after
/// texture lookups (`baseColorTexture`, `metallicRoughnessTexture`) have been
/// multiplied in. Values outside their ranges are clamped where used.
///
/// A per-hit value, not a buffer structure: the material buffer's form
/// belongs in `crate::abi` with the other Pod structures.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MetallicRoughness {
    /// Linear RGB base colour (glTF `baseColorFactor.rgb` times the texture),
    /// each channel in `[0, 1]`: the diffuse albedo of the dielectric and the
    /// normal-incidence reflectance of the metal.
    pub base_color: Vec3,
    /// glTF `metallicFactor` (times the texture's blue channel), in `[0, 1]`:
    /// 0 dielectric, 1 metal, linear blend between.
    pub metallic: f32,
    /// glTF perceptual `roughnessFactor` (times the texture's green channel),
    /// in `[0, 1]`; the GGX width is `alpha = roughness^2`, at least
    /// [`super::ggx::ALPHA_MIN`].
    pub roughness: f32,
}

/// One direction drawn by [`MetallicRoughness::sample`].
///
/// A sample that failed (`wo` below the horizon, or a reflection that left
/// below it) is [`BsdfSample::NONE`]: `pdf` and `weight` 0, and the path ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    /// Incident direction in the local frame, unit, `wi.z > 0` when `pdf > 0`.
    pub wi: Vec3,
    /// `f(wo, wi) wi.z / pdf` per RGB channel, `>= 0`: the throughput factor of
    /// the path through this vertex.
    pub weight: Vec3,
    /// Density per steradian of `wi` under the mixture of both lobes, equal to
    /// [`MetallicRoughness::pdf`]`(wo, wi)`; 0 for a failed sample.
    pub pdf: f32,
}

impl BsdfSample {
    /// The failed sample: direction `+z`, zero weight and density.
    pub const NONE: BsdfSample = BsdfSample {
        wi: Vec3::Z,
        weight: Vec3::ZERO,
        pdf: 0.0,
    };
}

impl MetallicRoughness {
    /// Parameters as glTF names them; no clamping here (see the fields).
    #[inline]
    pub const fn new(base_color: Vec3, metallic: f32, roughness: f32) -> Self {
        MetallicRoughness {
            base_color,
            metallic,
            roughness,
        }
    }

    /// `base_color` clamped to `[0, 1]` per channel.
    #[inline]
    fn base(&self) -> Vec3 {
        self.base_color.max(Vec3::ZERO).min(Vec3::ONE)
    }

    /// `metallic` clamped to `[0, 1]` (NaN to 0). Not `f32::clamp`: it
    /// asserts `min <= max`, a panic path in shaders.
    #[inline]
    #[allow(clippy::manual_clamp)]
    fn metal(&self) -> f32 {
        self.metallic.max(0.0).min(1.0)
    }

    /// GGX width, [`alpha_from_roughness`]`(roughness)`, in
    /// `[ALPHA_MIN, 1]`.
    #[inline]
    pub fn alpha(&self) -> f32 {
        alpha_from_roughness(self.roughness)
    }

    /// Normal-incidence specular reflectance per channel,
    /// `mix(0.04, base_color, metallic)`, in `[0, 1]`.
    #[inline]
    pub fn f0(&self) -> Vec3 {
        Vec3::splat(DIELECTRIC_F0).lerp(self.base(), self.metal())
    }

    /// The BRDF `f(wo, wi)` per RGB channel, in 1/sr, **without** the cosine
    /// `wi.z`; `>= 0`, and 0 when `wo.z <= 0` or `wi.z <= 0`. Finite and
    /// never NaN for unit vectors, grazing ones included; the largest values,
    /// near the mirror direction of a smooth surface, are of the order of
    /// `D`'s peak `1 / (pi alpha^2)`.
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let alpha = self.alpha();
        // wo + wi has z > 0, so h is well defined and h.z > 0.
        let h = (wo + wi).normalize();
        let w = schlick_weight(wo.dot(h));
        let f0 = self.f0();
        let fresnel = f0 + (Vec3::ONE - f0) * w;
        let specular = fresnel * (distribution(h, alpha) * visibility(wo, wi, alpha));
        let diffuse_weight = (1.0 - self.metal()) * (1.0 - (DIELECTRIC_F0 + (1.0 - DIELECTRIC_F0) * w));
        specular + self.base() * (diffuse_weight * FRAC_1_PI)
    }

    /// Probability in `[0, 1]` that [`Self::sample`] picks the specular lobe
    /// for `wo`: `s / (s + d)` with the lobes' reflectance estimates at
    /// `wo` (the Fresnel term evaluated at `|wo . h| = wo.z`, mean over RGB)
    /// `s = mean(f0) + (1 - mean(f0)) (1 - wo.z)^5` and
    /// `d = (1 - metallic) (1 - F_diel(wo.z)) mean(base_color)`.
    ///
    /// It is positive whenever the specular lobe is not identically zero
    /// (`s >= 0.04 (1 - metallic) + metallic mean(base_color)`), and 1 when the
    /// diffuse lobe is zero (metal, black base colour), so no lobe that
    /// contributes is ever left unsampled.
    #[inline]
    pub fn specular_probability(&self, wo: Vec3) -> f32 {
        let w = schlick_weight(wo.z);
        let f0 = self.f0();
        let f0_mean = (f0.x + f0.y + f0.z) * (1.0 / 3.0);
        let base = self.base();
        let specular = f0_mean + (1.0 - f0_mean) * w;
        let diffuse = (1.0 - self.metal())
            * (1.0 - (DIELECTRIC_F0 + (1.0 - DIELECTRIC_F0) * w))
            * ((base.x + base.y + base.z) * (1.0 / 3.0));
        let total = specular + diffuse;
        if total <= 0.0 {
            return 1.0;
        }
        (specular / total).min(1.0)
    }

    /// Density per steradian of [`Self::sample`] producing `wi` from `wo`:
    /// `p_s reflected_pdf(wo, wi) + (1 - p_s) wi.z / pi` with `p_s =`
    /// [`Self::specular_probability`]`(wo)`. 0 when `wo.z <= 0` or
    /// `wi.z <= 0`; over the upper hemisphere it integrates to `1 - p_s P`,
    /// `P` the probability that a specular reflection falls below the
    /// horizon.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        self.mixture_pdf(self.specular_probability(wo), wo, wi)
    }

    /// `p_s reflected_pdf + (1 - p_s) cos / pi`, for `wo.z, wi.z > 0`.
    #[inline]
    fn mixture_pdf(&self, p_specular: f32, wo: Vec3, wi: Vec3) -> f32 {
        p_specular * reflected_pdf(wo, wi, self.alpha()) + (1.0 - p_specular) * cosine_hemisphere_pdf(wi.z)
    }

    /// Draws `wi` for `wo` from `u` in `[0, 1)^2` (the direction within the
    /// lobe) and `u_lobe` in `[0, 1)` (the lobe: specular when `u_lobe <
    /// p_s`, [`Self::specular_probability`]). Returns
    /// [`BsdfSample::NONE`] when `wo.z <= 0`, when the specular reflection
    /// falls at or below the horizon, or when the density underflows to 0;
    /// otherwise `pdf = `[`Self::pdf`]`(wo, wi) > 0` and `weight = eval(wo,
    /// wi) wi.z / pdf`, finite.
    #[inline]
    pub fn sample(&self, wo: Vec3, u: Vec2, u_lobe: f32) -> BsdfSample {
        if wo.z <= 0.0 {
            return BsdfSample::NONE;
        }
        let p_specular = self.specular_probability(wo);
        self.sample_lobe(wo, u, u_lobe < p_specular, p_specular)
    }

    /// [`Self::sample`] with the lobe already chosen: the specular one when
    /// `specular`, which the caller drew with probability `p_specular` =
    /// [`Self::specular_probability`]`(wo)` (passed so that a caller that
    /// needed it to choose does not compute it twice). The same sample as
    /// `sample(wo, u, u_lobe)` with `specular = u_lobe < p_specular`.
    #[inline]
    pub fn sample_lobe(&self, wo: Vec3, u: Vec2, specular: bool, p_specular: f32) -> BsdfSample {
        if wo.z <= 0.0 {
            return BsdfSample::NONE;
        }
        let wi = if specular {
            reflect(wo, sample_visible_normal(wo, self.alpha(), u))
        } else {
            sample_cosine_hemisphere(u)
        };
        if wi.z <= 0.0 {
            return BsdfSample::NONE;
        }
        let pdf = self.mixture_pdf(p_specular, wo, wi);
        if pdf <= 0.0 {
            return BsdfSample::NONE;
        }
        BsdfSample {
            wi,
            weight: self.eval(wo, wi) * (wi.z / pdf),
            pdf,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f32::consts::TAU;
    use sampler_core::random_f32;

    /// Uniform direction on the upper hemisphere from stream `seed`, index `i`.
    fn hemisphere(seed: u32, i: u32) -> Vec3 {
        let z = random_f32(seed, 2 * i);
        let phi = TAU * random_f32(seed, 2 * i + 1);
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }

    fn random_material(i: u32) -> MetallicRoughness {
        MetallicRoughness::new(
            Vec3::new(random_f32(11, i), random_f32(12, i), random_f32(13, i)),
            random_f32(14, i),
            random_f32(15, i),
        )
    }

    #[test]
    fn brdf_is_reciprocal() {
        let mut worst = 0.0f32;
        for i in 0..20_000 {
            let m = random_material(i);
            let (wo, wi) = (hemisphere(1, i), hemisphere(2, i));
            let (a, b) = (m.eval(wo, wi), m.eval(wi, wo));
            let rel = (a - b).abs().max_element() / a.max_element().max(1e-30);
            worst = worst.max(rel);
            assert!(rel <= 1e-4, "{m:?} {wo} {wi}: {a} vs {b}");
        }
        println!("reciprocity: worst relative difference {worst:.2e} over 20000 pairs");
    }

    #[test]
    fn below_the_horizon_is_zero() {
        let m = MetallicRoughness::new(Vec3::splat(0.8), 0.5, 0.5);
        let (up, down) = (Vec3::new(0.6, 0.0, 0.8), Vec3::new(0.6, 0.0, -0.8));
        assert_eq!(m.eval(up, down), Vec3::ZERO);
        assert_eq!(m.eval(down, up), Vec3::ZERO);
        assert_eq!(m.pdf(up, down), 0.0);
        assert_eq!(m.pdf(down, up), 0.0);
        assert_eq!(m.eval(Vec3::X, up), Vec3::ZERO, "wo at the horizon");
        assert_eq!(m.sample(down, Vec2::splat(0.5), 0.5), BsdfSample::NONE);
        assert_eq!(m.sample(Vec3::X, Vec2::splat(0.5), 0.5), BsdfSample::NONE);
    }

    #[test]
    fn sample_agrees_with_pdf_and_eval() {
        for i in 0..20_000 {
            let m = random_material(i);
            let wo = hemisphere(3, i);
            let u = Vec2::new(random_f32(4, i), random_f32(5, i));
            let s = m.sample(wo, u, random_f32(6, i));
            if s.pdf == 0.0 {
                assert_eq!(s, BsdfSample::NONE);
                continue;
            }
            assert!(s.wi.z > 0.0 && (s.wi.length() - 1.0).abs() < 1e-5);
            let pdf = m.pdf(wo, s.wi);
            assert!((s.pdf - pdf).abs() <= 1e-6 * pdf, "{} vs {pdf}", s.pdf);
            let expected = m.eval(wo, s.wi) * s.wi.z / pdf;
            assert!(
                (s.weight - expected).abs().max_element() <= 1e-5 * expected.max_element().max(1e-30),
                "{} vs {expected}",
                s.weight
            );
        }
    }

    #[test]
    fn lobe_probability_covers_every_contributing_lobe() {
        let up = Vec3::Z;
        let white_dielectric = MetallicRoughness::new(Vec3::ONE, 0.0, 0.5);
        let p = white_dielectric.specular_probability(up);
        assert!((p - 0.04 / (0.04 + 0.96)).abs() < 1e-6, "{p}");
        let metal = MetallicRoughness::new(Vec3::new(0.9, 0.6, 0.3), 1.0, 0.5);
        assert_eq!(metal.specular_probability(up), 1.0);
        let black_metal = MetallicRoughness::new(Vec3::ZERO, 1.0, 0.5);
        assert_eq!(black_metal.specular_probability(up), 1.0);
        let black_dielectric = MetallicRoughness::new(Vec3::ZERO, 0.0, 0.5);
        assert_eq!(black_dielectric.specular_probability(up), 1.0);
        for i in 0..1000 {
            let p = random_material(i).specular_probability(hemisphere(7, i));
            assert!(p > 0.0 && p <= 1.0, "{p}");
        }
    }

    #[test]
    fn degenerate_inputs_are_finite() {
        let grazing = Vec3::new(1.0, 0.0, 1e-6).normalize();
        let grazing_other = Vec3::new(-0.3, 1.0, 1e-6).normalize();
        let dirs = [
            Vec3::Z,
            grazing,
            grazing_other,
            Vec3::new(0.6, 0.0, 0.8),
            Vec3::X,
            -Vec3::Z,
        ];
        for roughness in [0.0, 1e-6, 0.03, 0.5, 1.0, -1.0, 2.0] {
            for metallic in [0.0, 0.5, 1.0] {
                for base in [Vec3::ZERO, Vec3::ONE, Vec3::new(2.0, -1.0, 0.5)] {
                    let m = MetallicRoughness::new(base, metallic, roughness);
                    for wo in dirs {
                        for wi in dirs {
                            let f = m.eval(wo, wi);
                            assert!(f.is_finite() && f.min_element() >= 0.0, "{m:?} {wo} {wi}: {f}");
                            let p = m.pdf(wo, wi);
                            assert!(p.is_finite() && p >= 0.0, "{m:?} {wo} {wi}: {p}");
                        }
                        for k in 0..64 {
                            let u = Vec2::new(random_f32(8, k), random_f32(9, k));
                            for u_lobe in [0.0, 0.5, 1.0 - f32::EPSILON] {
                                let s = m.sample(wo, u, u_lobe);
                                assert!(s.wi.is_finite() && s.weight.is_finite() && s.pdf.is_finite());
                                assert!(s.weight.min_element() >= 0.0 && s.pdf >= 0.0);
                            }
                        }
                    }
                }
            }
        }
        // A mirror-like metal reflects the normal direction onto itself.
        let mirror = MetallicRoughness::new(Vec3::ONE, 1.0, 0.0);
        let s = mirror.sample(Vec3::Z, Vec2::new(0.3, 0.7), 0.0);
        assert!(s.wi.z > 0.9999, "{}", s.wi);
        assert!((s.weight - Vec3::ONE).abs().max_element() < 1e-3, "{}", s.weight);
    }
}
