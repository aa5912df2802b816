//! The reflectance at one path vertex, for the integrator
//! ([`crate::trace`]): the material's model after its textures, in the
//! vertex's shading frame, evaluated for next-event estimation and sampled
//! for the continuation.
//!
//! Two models ([`crate::abi::MaterialGpu::model`]):
//! - [`MODEL_LAMBERT`](crate::abi::MODEL_LAMBERT): BRDF `albedo / pi`, cosine-weighted sampling. Every
//!   operation is the one the integrator performed before the
//!   metallic-roughness model existed, in the same order, so Lambertian
//!   scenes render bit for bit as they did.
//! - [`MODEL_METALLIC_ROUGHNESS`]: [`MetallicRoughness`] with base colour =
//!   the albedo after the base colour texture, metallic and roughness after
//!   the metallic-roughness texture ([`crate::surface::surface_metallic_roughness`]).
//!
//! Surfaces are two-sided: the shading normal is the geometric normal
//! flipped towards the outgoing direction `wo`, or the smooth normal of the
//! triangle's vertex normals on that side, or the normal map's normal in
//! that frame, which [`crate::normal_map::shading_normal`] keeps facing
//! `wo` (the caller passes it so), so `wo` is always in the upper
//! hemisphere of the local frame. With a normal map, Lambertian reflection
//! stays `albedo / pi` with its cosine taken against the shading normal
//! (the caller passes that cosine to [`Shading::eval_cos`]); sampling is
//! cosine-weighted about it, so `weight = albedo` and paths stay finite.
//!
//! # Lobe choice without a dimension
//!
//! [`MetallicRoughness::sample`] needs a third number to choose its lobe.
//! None is added to the path's layout ([`crate::numbers`]): the first number
//! `u.x` of the BSDF pair chooses the lobe (specular when `u.x < p`,
//! `p` = [`MetallicRoughness::specular_probability`]) and is reused,
//! rescaled to `[0, 1)` within the chosen lobe's interval
//! ([`reuse_lobe_number`]), as the first number of the direction inside the
//! lobe, just as [`crate::trace::select_emitter_reusing`] reuses the light
//! pair. The BSDF pair therefore always drives the BSDF decision, and a
//! stratified pair stays stratified within each lobe.

use crate::abi::{MaterialGpu, MODEL_METALLIC_ROUGHNESS};
use crate::bsdf::{to_local, BsdfSample, MetallicRoughness};
use crate::regularization::raised_roughness;
use crate::sampling::{cosine_hemisphere_pdf, sample_cosine_hemisphere, Frame};
use crate::surface::{surface_albedo_filtered, surface_metallic_roughness_filtered};
use crate::trace_variant::{FULL, SHADING, TEXTURES};
use core::f32::consts::FRAC_1_PI;
use glam::{Vec2, Vec3};

/// Perceptual roughness below which a metallic-roughness surface is sharp
/// ([`Shading::is_sharp`]): 0.75, the glossy first hits of the studies
/// (`conformance::metrics::surfaces`).
pub const SHARP_ROUGHNESS: f32 = 0.75;

/// The reflectance at one path vertex (see the module docs).
#[derive(Clone, Copy, Debug)]
pub struct Shading {
    /// `true` for [`MODEL_METALLIC_ROUGHNESS`], `false` for Lambertian.
    glossy: bool,
    /// Albedo (Lambertian) or base colour, linear RGB in `[0, 1]`.
    albedo: Vec3,
    /// The metallic-roughness parameters (read only when `glossy`).
    bsdf: MetallicRoughness,
    /// Shading frame, `z` along the unit shading normal.
    frame: Frame,
    /// Unit outgoing direction in `frame` (`z >= 0`; read only when `glossy`).
    wo: Vec3,
    /// [`MetallicRoughness::specular_probability`] of `wo`, in `[0, 1]`: the
    /// chance that [`Self::sample`] takes the specular lobe (0 for
    /// Lambertian surfaces; computed once, read by the sample and by
    /// [`Self::continuation_roughness`]).
    p_specular: f32,
}

impl Shading {
    /// The reflectance of `material` at texture coordinates `uv`, with unit
    /// shading `normal` (already facing `wo`) and unit outgoing direction
    /// `wo` (towards where the path came from), both in world space.
    #[inline]
    pub fn at(
        material: &MaterialGpu,
        images: &[u32],
        image_count: u32,
        uv: Vec2,
        normal: Vec3,
        wo: Vec3,
    ) -> Self {
        Self::at_filtered(material, images, image_count, uv, 0.0, normal, wo)
    }

    /// [`Shading::at`] with the material's textures filtered over a
    /// footprint of side `width` in texture coordinates
    /// ([`crate::footprint`]; 0: point lookups, exactly [`Shading::at`]).
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub fn at_filtered(
        material: &MaterialGpu,
        images: &[u32],
        image_count: u32,
        uv: Vec2,
        width: f32,
        normal: Vec3,
        wo: Vec3,
    ) -> Self {
        Self::at_variant::<FULL>(material, images, image_count, uv, width, normal, wo, 0.0)
    }

    /// [`Shading::at_filtered`] for the trace variant of `FEATURES`
    /// ([`crate::trace_variant`]): without [`TEXTURES`] the material's
    /// factors stand for its textures, without [`SHADING`] it is read as
    /// Lambertian: the same value, bit for bit, for a material the variant
    /// fits. (One constructor for every variant, so that no `Shading` value
    /// is chosen between branches: rust-gpu would lay such a variable out
    /// in a way naga refuses.) A metallic-roughness surface's perceptual
    /// roughness is raised to at least `min_roughness` (path regularisation,
    /// [`crate::regularization`]); `min_roughness <= 0` (or NaN) leaves it as
    /// it was, bit for bit.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub fn at_variant<const FEATURES: u32>(
        material: &MaterialGpu,
        images: &[u32],
        image_count: u32,
        uv: Vec2,
        width: f32,
        normal: Vec3,
        wo: Vec3,
        min_roughness: f32,
    ) -> Self {
        let textured = FEATURES & TEXTURES != 0;
        let albedo = if textured {
            surface_albedo_filtered(material, images, image_count, uv, width)
        } else {
            material.albedo.truncate()
        };
        let glossy = FEATURES & SHADING != 0 && material.model.x == MODEL_METALLIC_ROUGHNESS;
        let frame = Frame::from_normal(normal);
        let (mut bsdf, mut wo_local, mut p_specular) =
            (MetallicRoughness::new(albedo, 0.0, 1.0), Vec3::Z, 0.0);
        if glossy {
            let mr = if textured {
                surface_metallic_roughness_filtered(material, images, image_count, uv, width)
            } else {
                Vec2::new(material.pbr.x, material.pbr.y)
            };
            bsdf = MetallicRoughness::new(albedo, mr.x, raised_roughness(mr.y, min_roughness));
            wo_local = to_local(&frame, wo);
            p_specular = bsdf.specular_probability(wo_local);
        }
        Shading {
            glossy,
            albedo,
            bsdf,
            frame,
            wo: wo_local,
            p_specular,
        }
    }

    /// Whether the surface is sharp: metallic-roughness with a perceptual
    /// roughness below [`SHARP_ROUGHNESS`] (its reflection moves with every
    /// sample; `crate::numbers`, "sharp first hit"). Lambertian surfaces are not.
    #[inline]
    pub fn is_sharp(&self) -> bool {
        self.glossy && self.bsdf.roughness < SHARP_ROUGHNESS
    }

    /// The roughness, in `[0, 1]`, of the lobe that [`Self::sample`] chooses
    /// for the pair `u` ([`crate::regularization`]): 1 for Lambertian
    /// surfaces and for the metallic-roughness model's diffuse lobe, the
    /// perceptual roughness for its specular lobe.
    #[inline]
    #[allow(clippy::manual_clamp)]
    pub fn continuation_roughness(&self, u: Vec2) -> f32 {
        if self.glossy && u.x < self.p_specular {
            // Not `f32::clamp`: it asserts `min <= max`, a panic path in shaders.
            self.bsdf.roughness.max(0.0).min(1.0)
        } else {
            1.0
        }
    }

    /// The spread (radians) a bounce off this surface adds to the path's
    /// ray cone ([`crate::footprint::bounce_spread`]).
    #[inline]
    pub fn cone_spread(&self) -> f32 {
        crate::footprint::bounce_spread(self.glossy, self.bsdf.alpha())
    }

    /// Whether the surface can reflect at all (next-event estimation is
    /// skipped otherwise): a non-black albedo for Lambertian surfaces,
    /// always for metallic-roughness ones (their specular lobe never
    /// vanishes entirely).
    #[inline]
    pub fn reflects(&self) -> bool {
        self.glossy || self.albedo.max_element() > 0.0
    }

    /// `(f(wo, wi) cos, pdf)` for the unit world direction `wi` with
    /// `cos = wi . normal > 0`: the BRDF times the cosine per RGB channel
    /// (1/sr), and the density per steradian with which [`Self::sample`]
    /// would have produced `wi` (for the MIS weight of next-event
    /// estimation). Lambertian: `(albedo cos / pi, cos / pi)`.
    #[inline]
    pub fn eval_cos(&self, wi: Vec3, cos: f32) -> (Vec3, f32) {
        if self.glossy {
            let wi_local = to_local(&self.frame, wi);
            let f = self.bsdf.eval(self.wo, wi_local);
            (f * cos, self.bsdf.pdf(self.wo, wi_local))
        } else {
            (self.albedo * (FRAC_1_PI * cos), cosine_hemisphere_pdf(cos))
        }
    }

    /// A continuation direction from the BSDF pair `u` in `[0, 1)^2` (the
    /// lobe choice reuses `u.x`, module docs): `wi` in **world** space
    /// (unit), `weight = f cos / pdf` per RGB channel, and `pdf` per
    /// steradian; [`BsdfSample::NONE`] (`pdf` 0) when no direction results
    /// and the path ends. Lambertian: cosine-weighted, `weight = albedo`.
    #[inline]
    pub fn sample(&self, u: Vec2) -> BsdfSample {
        if self.glossy {
            let p = self.p_specular;
            let s = self
                .bsdf
                .sample_lobe(self.wo, reuse_lobe_number(u, p), u.x < p, p);
            if s.pdf <= 0.0 {
                return BsdfSample::NONE;
            }
            BsdfSample {
                wi: self.frame.to_world(s.wi).normalize(),
                ..s
            }
        } else {
            let local = sample_cosine_hemisphere(u);
            if local.z <= 0.0 {
                return BsdfSample::NONE;
            }
            BsdfSample {
                wi: self.frame.to_world(local).normalize(),
                weight: self.albedo,
                pdf: cosine_hemisphere_pdf(local.z),
            }
        }
    }
}

/// The BSDF pair for the direction inside the lobe `u.x` chooses with
/// specular probability `p` in `[0, 1]`: `u.x / p` for the specular lobe
/// (`u.x < p`), `(u.x - p) / (1 - p)` for the diffuse one, clamped to
/// `[0, 1)`; `u.y` unchanged.
#[inline]
pub fn reuse_lobe_number(u: Vec2, p: f32) -> Vec2 {
    let mut x = if u.x < p { u.x / p } else { (u.x - p) / (1.0 - p) };
    // Not `f32::clamp`: it asserts `min <= max`, a panic path in shaders.
    // `p == 1` with `u.x >= 1` (never for valid input) gives NaN, mapped to 0.
    #[allow(clippy::manual_clamp)]
    {
        x = x.max(0.0).min(0.999_999_94);
    }
    Vec2::new(x, u.y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::abi::TEXTURE_NONE;
    use glam::Vec4;

    #[test]
    fn lobe_number_spans_each_interval_in_order() {
        let p = 0.3;
        assert_eq!(reuse_lobe_number(Vec2::new(0.0, 0.7), p), Vec2::new(0.0, 0.7));
        assert!((reuse_lobe_number(Vec2::new(0.15, 0.0), p).x - 0.5).abs() < 1e-6);
        assert_eq!(reuse_lobe_number(Vec2::new(0.3, 0.0), p).x, 0.0);
        assert!((reuse_lobe_number(Vec2::new(0.65, 0.0), p).x - 0.5).abs() < 1e-6);
        assert!(reuse_lobe_number(Vec2::new(0.999_999_94, 0.0), p).x < 1.0);
        for p in [0.0f32, 1.0] {
            for i in 0..100 {
                let x = reuse_lobe_number(Vec2::new(i as f32 / 100.0, 0.0), p).x;
                assert!((x - i as f32 / 100.0).abs() < 1e-6, "{p} {i}: {x}");
            }
        }
        // Stratification carries over: 8 strata of u.x give 8 distinct
        // strata of the rescaled number within each lobe (p = 1/2).
        let mut cells: [u32; 8] = core::array::from_fn(|i| {
            let x = reuse_lobe_number(Vec2::new((i as f32 + 0.5) / 8.0, 0.0), 0.5).x;
            (x * 4.0) as u32 + if i < 4 { 0 } else { 4 }
        });
        cells.sort_unstable();
        assert_eq!(cells, [0, 1, 2, 3, 4, 5, 6, 7]);
    }

    /// The Lambertian shading reproduces the integrator's former arithmetic
    /// bit for bit, and the sample's density and weight agree with
    /// `eval_cos`.
    #[test]
    fn lambert_is_the_former_arithmetic() {
        let albedo = Vec4::new(0.7, 0.5, 0.2, 0.0);
        let m = MaterialGpu::untextured(albedo, Vec4::ZERO);
        let n = Vec3::new(0.2, 0.9, -0.1).normalize();
        let s = Shading::at(&m, &[0], 0, Vec2::ZERO, n, n);
        assert!(s.reflects());
        let u = Vec2::new(0.3, 0.8);
        let local = sample_cosine_hemisphere(u);
        let b = s.sample(u);
        assert_eq!(b.wi, Frame::from_normal(n).to_world(local).normalize());
        assert_eq!(b.pdf, cosine_hemisphere_pdf(local.z));
        assert_eq!(b.weight, albedo.truncate());
        let cos = 0.4;
        let (f, pdf) = s.eval_cos(b.wi, cos);
        assert_eq!(f, albedo.truncate() * (FRAC_1_PI * cos));
        assert_eq!(pdf, cosine_hemisphere_pdf(cos));
        assert!(!Shading::at(&MaterialGpu::default(), &[0], 0, Vec2::ZERO, n, n).reflects());
    }

    /// Path regularisation: a roughness floor raises a glossy surface's
    /// roughness (and widens its lobe) but never a rougher one's, leaves
    /// Lambertian surfaces alone, and the continuing lobe's roughness is the
    /// surface's for the specular lobe and 1 for the diffuse ones.
    #[test]
    fn regularisation_raises_glossy_roughness_only() {
        let n = Vec3::Z;
        let wo = Vec3::new(0.3, 0.0, 1.0).normalize();
        let at = |m: &MaterialGpu, floor: f32| {
            Shading::at_variant::<FULL>(m, &[0], 0, Vec2::ZERO, 0.0, n, wo, floor)
        };
        let metal = MaterialGpu::metallic_roughness(Vec4::new(0.9, 0.9, 0.9, 0.0), 1.0, 0.1);
        assert_eq!(at(&metal, 0.0).bsdf.roughness, 0.1);
        assert_eq!(at(&metal, 0.6).bsdf.roughness, 0.6);
        let rough = MaterialGpu::metallic_roughness(Vec4::new(0.9, 0.9, 0.9, 0.0), 1.0, 0.8);
        assert_eq!(at(&rough, 0.6).bsdf.roughness, 0.8);
        // Sharp: glossy below SHARP_ROUGHNESS, after any floor.
        assert!(at(&metal, 0.0).is_sharp());
        assert!(!at(&metal, 0.8).is_sharp());
        assert!(!at(&rough, 0.0).is_sharp());
        // The mirror's reflection of `wo` carries far more density unregularised.
        let mirror = Vec3::new(-wo.x, -wo.y, wo.z);
        let (_, sharp) = at(&metal, 0.0).eval_cos(mirror, mirror.z);
        let (_, wide) = at(&metal, 0.6).eval_cos(mirror, mirror.z);
        assert!(sharp > 10.0 * wide, "{sharp} {wide}");
        // Lambertian: untouched, bit for bit.
        let lambert = MaterialGpu::untextured(Vec4::new(0.5, 0.5, 0.5, 0.0), Vec4::ZERO);
        let u = Vec2::new(0.3, 0.8);
        assert_eq!(at(&lambert, 1.0).sample(u), at(&lambert, 0.0).sample(u));
        assert_eq!(at(&lambert, 1.0).continuation_roughness(u), 1.0);
        assert!(!at(&lambert, 0.0).is_sharp());
        // A metal's lobe is specular for every number: its roughness continues.
        assert_eq!(at(&metal, 0.0).continuation_roughness(u), 0.1);
        assert_eq!(at(&metal, 0.6).continuation_roughness(u), 0.6);
        // A dielectric: specular below its probability, diffuse (1) above.
        let plastic = MaterialGpu::metallic_roughness(Vec4::new(0.2, 0.4, 0.8, 0.0), 0.0, 0.3);
        let s = at(&plastic, 0.0);
        let p = s.p_specular;
        assert_eq!(p, s.bsdf.specular_probability(s.wo));
        assert!(p > 0.0 && p < 1.0, "{p}");
        assert_eq!(s.continuation_roughness(Vec2::new(0.5 * p, 0.5)), 0.3);
        assert_eq!(s.continuation_roughness(Vec2::new(0.5 + 0.5 * p, 0.5)), 1.0);
    }

    /// Metallic-roughness: the sample's world direction, weight and density
    /// agree with `eval_cos` for the same direction, and both lobes are
    /// reached.
    #[test]
    fn glossy_sample_agrees_with_eval() {
        let m = MaterialGpu::metallic_roughness(Vec4::new(0.8, 0.6, 0.3, 0.0), 0.4, 0.3);
        assert_eq!(m.model.y, TEXTURE_NONE);
        let n = Vec3::new(-0.3, 0.2, 0.9).normalize();
        let wo = (n + Vec3::new(0.5, 0.1, 0.0)).normalize();
        let s = Shading::at(&m, &[0], 0, Vec2::ZERO, n, wo);
        assert!(s.reflects());
        let mut near_mirror = 0;
        for i in 0..64 {
            let u = Vec2::new((i as f32 + 0.5) / 64.0, ((i * 37) % 64) as f32 / 64.0 + 0.005);
            let b = s.sample(u);
            assert!(b.pdf > 0.0, "{i}");
            let cos = b.wi.dot(n);
            assert!(cos > 0.0 && (b.wi.length() - 1.0).abs() < 1e-5);
            let (f, pdf) = s.eval_cos(b.wi, cos);
            assert!((pdf - b.pdf).abs() <= 1e-3 * pdf, "{i}: {pdf} {}", b.pdf);
            let w = f / pdf;
            assert!(
                (w - b.weight).abs().max_element() <= 1e-3 * (1.0 + w.max_element()),
                "{i}"
            );
            let mirror = (2.0 * wo.dot(n) * n - wo).normalize();
            if b.wi.dot(mirror) > 0.95 {
                near_mirror += 1;
            }
        }
        assert!(near_mirror > 4 && near_mirror < 60, "{near_mirror}");
    }
}
