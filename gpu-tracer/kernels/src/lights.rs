//! Next-event estimation's light sampling: which emitter a path vertex
//! asks for light ([`select_emitter_reusing`]), and where on it
//! ([`sample_emitter`]).
//!
//! The emitter list ([`EmitterGpu`]) mixes emissive triangles with the
//! punctual lights of glTF's `KHR_lights_punctual` (point, spot,
//! directional). Triangles are area lights: a uniform point on the
//! triangle, combined with BSDF sampling by multiple importance sampling
//! in [`crate::trace`]. Point and spot lights are delta lights, reached by
//! light sampling only. A directional light is a delta light too, or with
//! an angular radius a sun disk of uniform radiance sampled uniformly in
//! its cone; BSDF rays that escape see the environment, not the disk, so
//! the disk is also found by light sampling only (unbiased, since that
//! strategy covers the whole disk).
//!
//! Falloffs follow the extension's recommendations: the inverse square of
//! the distance, windowed to zero at the light's `range`
//! ([`range_window`]), and for spot lights the smooth cone falloff
//! ([`spot_falloff`]).

use crate::abi::{
    EmitterGpu, MaterialGpu, TraceParams, TriangleAttrGpu, TriangleGpu, EMITTER_DIRECTIONAL,
    EMITTER_ENVIRONMENT, EMITTER_SPOT, EMITTER_TRIANGLE,
};
use crate::environment::environment_texel;
use crate::geometry::{normal_and_area, surface_offset};
use crate::sampling::{sample_triangle_barycentrics, sample_uniform_cone, Frame};
use crate::surface::{surface_emission, triangle_uv};
use crate::trace_variant::{FULL, SHADING, TEXTURES};
use glam::{Vec2, Vec3};
use sampler_core::distributions::environment::sample_environment;

/// One light sample seen from a shading point: the estimator of the light
/// it carries is `f(wi) cos * radiance * mis_weight / pdf`, counted when
/// the shadow ray `(origin, wi, t_max)` is unoccluded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Unit direction from the shading point towards the light.
    pub wi: Vec3,
    /// Length of the free segment the shadow ray checks, in world units
    /// (`f32::MAX` for a directional light): stops short of the light's
    /// surface or position by the surface offset.
    pub t_max: f32,
    /// Triangles: the emitted radiance `Le` at the sampled point, towards
    /// the shading point. Point and spot lights: intensity times falloff
    /// over the squared distance (the irradiance on a surface facing the
    /// light). Directional lights: the illuminance (delta) or the disk's
    /// radiance times its solid angle (the sample's inverse directional
    /// density). Linear RGB, `>= 0`.
    pub radiance: Vec3,
    /// Density of the sample: selection probability times the solid-angle
    /// density of the point for triangles (what MIS compares with the BSDF's
    /// density), the selection probability alone for the other kinds.
    /// `> 0` for a sample that carries light; 0 for [`LightSample::NONE`].
    pub pdf: f32,
    /// Whether BSDF sampling can find this light too (triangles): weight
    /// the sample by MIS; otherwise its weight is 1.
    pub mis: bool,
}

impl LightSample {
    /// A sample that carries no light (`pdf` 0). The kernels return this
    /// rather than `Option<LightSample>`, which rust-gpu cannot lay out.
    pub const NONE: LightSample = LightSample {
        wi: Vec3::ZERO,
        t_max: 0.0,
        radiance: Vec3::ZERO,
        pdf: 0.0,
        mis: false,
    };

    /// Whether the sample carries light (`pdf > 0`).
    #[inline]
    pub fn is_some(&self) -> bool {
        self.pdf > 0.0
    }
}

/// Index of the emitter whose cumulative-probability interval
/// `[cdf[i - 1], cdf[i])` contains `u` in `[0, 1)`: the first `i` with
/// `u < cdf[i]`, found by binary search over the first `count` entries
/// (`count >= 1`); `count - 1` if none (rounding in the last `cdf`).
#[inline]
pub fn select_emitter(emitters: &[EmitterGpu], count: u32, u: f32) -> u32 {
    let mut lo = 0u32;
    let mut hi = count.max(1) - 1;
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        if u < emitters[mid as usize].cdf {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    lo
}

/// [`select_emitter`] with `u.x`, and the pair for the point on that
/// emitter: `u.x` rescaled to `[0, 1)` within the emitter's interval
/// `[cdf - pdf, cdf)` (sample reuse, so `u`'s stratification carries over to
/// the whole set of emitters), and `u.y` unchanged.
#[inline]
pub fn select_emitter_reusing(emitters: &[EmitterGpu], count: u32, u: Vec2) -> (u32, Vec2) {
    let index = select_emitter(emitters, count, u.x);
    let e = emitters[index as usize];
    let mut x = 0.0f32;
    if e.pdf > 0.0 {
        x = (u.x - (e.cdf - e.pdf)) / e.pdf;
    }
    // f32 rounding of the cumulative sums can land just outside [0, 1).
    // Not `f32::clamp`: it asserts `min <= max`, a panic path in shaders.
    #[allow(clippy::manual_clamp)]
    {
        x = x.max(0.0).min(0.999_999_94);
    }
    (index, Vec2::new(x, u.y))
}

/// A light sample on emissive triangle `e` (module docs of
/// [`sample_emitter`]), its radiance read through the material's emission
/// texture when `FEATURES` has [`TEXTURES`], the emission factor alone
/// otherwise.
#[allow(clippy::too_many_arguments)]
#[inline]
fn sample_triangle<const FEATURES: u32>(
    e: &EmitterGpu,
    origin: Vec3,
    u: Vec2,
    triangles: &[TriangleGpu],
    materials: &[MaterialGpu],
    attrs: &[TriangleAttrGpu],
    images: &[u32],
    image_count: u32,
) -> LightSample {
    if e.pdf <= 0.0 {
        return LightSample::NONE;
    }
    let lt = triangles[e.triangle as usize];
    let (l0, l1, l2) = (lt.v0.truncate(), lt.v1.truncate(), lt.v2.truncate());
    let (light_normal, light_area) = normal_and_area(l0, l1, l2);
    let b = sample_triangle_barycentrics(u);
    let q = l0 + (l1 - l0) * b.x + (l2 - l0) * b.y;
    let to_light = q - origin;
    let dist2 = to_light.length_squared();
    let dist = libm::sqrtf(dist2);
    if dist <= 0.0 {
        return LightSample::NONE;
    }
    let wi = to_light / dist;
    let cos_light = -wi.dot(light_normal);
    if cos_light <= 0.0 {
        return LightSample::NONE;
    }
    let material = &materials[lt.v0.w as u32 as usize];
    let radiance = if FEATURES & TEXTURES != 0 {
        let light_uv = triangle_uv(&attrs[e.triangle as usize], b.x, b.y);
        surface_emission(material, images, image_count, light_uv)
    } else {
        material.emission.truncate()
    };
    LightSample {
        wi,
        t_max: dist - 2.0 * surface_offset(q),
        radiance,
        pdf: e.pdf * dist2 / (light_area * cos_light),
        mis: true,
    }
}

/// A light sample from emitter `e` (one entry of the emitter list) for the
/// shading point `origin` (already offset from its surface), with `u` in
/// `[0, 1)^2` (after [`select_emitter_reusing`]). `environment` is the
/// environment map's buffer (binding 10), read for
/// [`EMITTER_ENVIRONMENT`] (a direction drawn in proportion to luminance
/// times solid angle, combined with BSDF sampling by MIS like triangles). [`LightSample::NONE`]
/// when the sample carries no light: the point is behind the emitting triangle or on the
/// light, outside the spot cone or beyond the range, or the entry has
/// probability 0.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn sample_emitter(
    e: &EmitterGpu,
    origin: Vec3,
    u: Vec2,
    triangles: &[TriangleGpu],
    materials: &[MaterialGpu],
    attrs: &[TriangleAttrGpu],
    images: &[u32],
    params: &TraceParams,
    environment: &[f32],
) -> LightSample {
    sample_emitter_variant::<FULL>(
        e,
        origin,
        u,
        triangles,
        materials,
        attrs,
        images,
        params,
        environment,
    )
}

/// [`sample_emitter`] for the trace variant of `FEATURES`
/// ([`crate::trace_variant`]): without [`TEXTURES`] an emissive
/// triangle's radiance is its emission factor, without [`SHADING`] every
/// emitter is taken for an emissive triangle. The same sample, bit for
/// bit, on the emitters of a scene the variant fits.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn sample_emitter_variant<const FEATURES: u32>(
    e: &EmitterGpu,
    origin: Vec3,
    u: Vec2,
    triangles: &[TriangleGpu],
    materials: &[MaterialGpu],
    attrs: &[TriangleAttrGpu],
    images: &[u32],
    params: &TraceParams,
    environment: &[f32],
) -> LightSample {
    if e.pdf <= 0.0 {
        return LightSample::NONE;
    }
    if FEATURES & SHADING == 0 || e.kind == EMITTER_TRIANGLE {
        return sample_triangle::<FEATURES>(
            e,
            origin,
            u,
            triangles,
            materials,
            attrs,
            images,
            params.image_count,
        );
    }
    if e.kind == EMITTER_ENVIRONMENT {
        let map = params.environment_map;
        let s = sample_environment(environment, map, u);
        if s.pdf <= 0.0 {
            return LightSample::NONE;
        }
        return LightSample {
            wi: s.direction,
            t_max: f32::MAX,
            radiance: environment_texel(map, environment, s.uv),
            pdf: e.pdf * s.pdf,
            mis: true,
        };
    }
    let intensity = e.intensity.truncate();
    if e.kind == EMITTER_DIRECTIONAL {
        let travel = e.direction.truncate();
        let one_minus_cos_max = e.shape.x;
        let (wi, radiance) = if one_minus_cos_max > 0.0 {
            // Uniform radiance L = E / (pi sin^2) over the solid angle
            // 2 pi (1 - cos): L / density = E * 2 / (1 + cos) = E * 2 / (2 - (1 - cos)).
            let local = sample_uniform_cone(u, one_minus_cos_max);
            let wi = Frame::from_normal(-travel).to_world(local).normalize();
            (wi, intensity * (2.0 / (2.0 - one_minus_cos_max)))
        } else {
            (-travel, intensity)
        };
        return LightSample {
            wi,
            t_max: f32::MAX,
            radiance,
            pdf: e.pdf,
            mis: false,
        };
    }
    // Point and spot lights.
    let position = e.position.truncate();
    let to_light = position - origin;
    let dist2 = to_light.length_squared();
    let dist = libm::sqrtf(dist2);
    if dist <= 0.0 {
        return LightSample::NONE;
    }
    let wi = to_light / dist;
    let mut scale = range_window(dist, e.position.w) / dist2;
    if e.kind == EMITTER_SPOT {
        scale *= spot_falloff(-wi.dot(e.direction.truncate()), e.shape.x, e.shape.y);
    }
    if scale <= 0.0 {
        return LightSample::NONE;
    }
    LightSample {
        wi,
        t_max: dist - surface_offset(position),
        radiance: intensity * scale,
        pdf: e.pdf,
        mis: false,
    }
}

/// The window `KHR_lights_punctual` recommends for a light of finite
/// `range` (world units) at distance `dist`: `clamp(1 - (dist / range)^4,
/// 0, 1)`, which brings the inverse-square falloff smoothly to zero at the
/// range; 1 for `range <= 0` (an unbounded light).
#[inline]
pub fn range_window(dist: f32, range: f32) -> f32 {
    if range > 0.0 {
        let r = dist / range;
        let r2 = r * r;
        // Not `f32::clamp` (asserts min <= max: a panic path in shaders).
        #[allow(clippy::manual_clamp)]
        (1.0 - r2 * r2).max(0.0).min(1.0)
    } else {
        1.0
    }
}

/// The spot light's angular falloff of `KHR_lights_punctual`: `t^2` with
/// `t = clamp((cos_angle - cos_outer) * scale, 0, 1)`, where `cos_angle` is
/// the cosine between the cone's axis and the direction from the light to
/// the lit point, and `scale = 1 / max(1e-3, cos_inner - cos_outer)`
/// ([`EmitterGpu::shape`]). 1 inside the inner cone, 0 outside the outer.
#[inline]
pub fn spot_falloff(cos_angle: f32, cos_outer: f32, scale: f32) -> f32 {
    #[allow(clippy::manual_clamp)]
    let t = ((cos_angle - cos_outer) * scale).max(0.0).min(1.0);
    t * t
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::abi::{EMITTER_POINT, EMITTER_SPOT};
    use glam::Vec4;

    #[test]
    fn emitter_selection_follows_the_cdf() {
        let e = |cdf: f32| EmitterGpu {
            cdf,
            ..EmitterGpu::NONE
        };
        let list = [e(0.1), e(0.1), e(0.6), e(1.0)];
        assert_eq!(select_emitter(&list, 4, 0.0), 0);
        assert_eq!(select_emitter(&list, 4, 0.0999), 0);
        // Entry 1 has probability 0: never chosen.
        assert_eq!(select_emitter(&list, 4, 0.1), 2);
        assert_eq!(select_emitter(&list, 4, 0.5999), 2);
        assert_eq!(select_emitter(&list, 4, 0.6), 3);
        assert_eq!(select_emitter(&list, 4, 0.999_999_9), 3);
        assert_eq!(select_emitter(&list, 1, 0.7), 0);
    }

    /// The reused number spans `[0, 1)` inside each emitter's interval, in
    /// order, and the second number passes through.
    #[test]
    fn emitter_selection_reuses_the_number() {
        let e = |cdf: f32, pdf: f32| EmitterGpu {
            cdf,
            pdf,
            ..EmitterGpu::NONE
        };
        let list = [e(0.25, 0.25), e(1.0, 0.75)];
        let pick = |x: f32| select_emitter_reusing(&list, 2, Vec2::new(x, 0.3));
        assert_eq!(pick(0.0), (0, Vec2::new(0.0, 0.3)));
        assert_eq!(pick(0.125), (0, Vec2::new(0.5, 0.3)));
        assert_eq!(pick(0.25), (1, Vec2::new(0.0, 0.3)));
        assert_eq!(pick(0.625), (1, Vec2::new(0.5, 0.3)));
        let mut last = (0u32, -1.0f32);
        for i in 0..1000 {
            let (k, u) = pick(i as f32 / 1000.0);
            assert!((0.0..1.0).contains(&u.x), "{i}: {u}");
            if k == last.0 {
                assert!(u.x > last.1, "{i}: not increasing");
            }
            last = (k, u.x);
        }
        assert_eq!(pick(0.999_999_94).0, 1);
        assert!(pick(0.999_999_94).1.x < 1.0);
    }

    fn punctual(kind: u32, position: Vec3, direction: Vec3, intensity: Vec3) -> EmitterGpu {
        EmitterGpu {
            kind,
            cdf: 1.0,
            pdf: 0.5,
            position: position.extend(0.0),
            direction: direction.extend(0.0),
            intensity: intensity.extend(0.0),
            ..EmitterGpu::NONE
        }
    }

    fn sample(e: &EmitterGpu, origin: Vec3, u: Vec2) -> Option<LightSample> {
        let s = sample_emitter_for_test(e, origin, u);
        s.is_some().then_some(s)
    }

    fn sample_emitter_for_test(e: &EmitterGpu, origin: Vec3, u: Vec2) -> LightSample {
        let tri = [TriangleGpu::default()];
        let attrs = [TriangleAttrGpu::default()];
        let materials = [MaterialGpu::default()];
        sample_emitter(
            e,
            origin,
            u,
            &tri,
            &materials,
            &attrs,
            &[0],
            &TraceParams::default(),
            &[0.0],
        )
    }

    /// Point light: intensity over the squared distance, towards the light,
    /// the selection probability as density, no MIS.
    #[test]
    fn point_light_follows_the_inverse_square_law() {
        let i = Vec3::new(2.0, 4.0, 8.0);
        let e = punctual(EMITTER_POINT, Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, i);
        let s = sample(&e, Vec3::ZERO, Vec2::new(0.3, 0.7)).unwrap();
        assert_eq!(s.wi, Vec3::Z);
        assert!(
            (s.radiance - i / 25.0).abs().max_element() < 1e-6,
            "{}",
            s.radiance
        );
        assert_eq!((s.pdf, s.mis), (0.5, false));
        assert!(s.t_max < 5.0 && s.t_max > 4.99, "{}", s.t_max);
        // With a range of 10 at distance 5: window 1 - (1/2)^4.
        let ranged = EmitterGpu {
            position: Vec4::new(0.0, 0.0, 5.0, 10.0),
            ..e
        };
        let s = sample(&ranged, Vec3::ZERO, Vec2::ZERO).unwrap();
        assert!((s.radiance - i / 25.0 * (15.0 / 16.0)).abs().max_element() < 1e-6);
        // At or beyond the range: no light. On the light: no sample.
        assert!(sample(&ranged, Vec3::new(0.0, 0.0, -5.0), Vec2::ZERO).is_none());
        assert!(sample(&e, Vec3::new(0.0, 0.0, 5.0), Vec2::ZERO).is_none());
        assert_eq!(range_window(3.0, 0.0), 1.0);
    }

    /// Spot light: the extension's falloff inside the outer cone, full
    /// intensity inside the inner one, nothing outside.
    #[test]
    fn spot_light_follows_the_extension_cone() {
        let (inner, outer) = (0.2f32, 0.4f32);
        let scale = 1.0 / (inner.cos() - outer.cos()).max(1e-3);
        let i = Vec3::splat(3.0);
        let e = EmitterGpu {
            shape: Vec4::new(outer.cos(), scale, 0.0, 0.0),
            ..punctual(EMITTER_SPOT, Vec3::new(0.0, 0.0, 4.0), -Vec3::Z, i)
        };
        // A point on the ground seen from the light at angle `a` off the axis.
        let at = |a: f32| Vec3::new(4.0 * a.tan(), 0.0, 0.0);
        for a in [0.0f32, 0.1, 0.25, 0.3, 0.35, 0.39] {
            let p = at(a);
            let d2 = (Vec3::new(0.0, 0.0, 4.0) - p).length_squared();
            let t = ((a.cos() - outer.cos()) * scale).clamp(0.0, 1.0);
            let want = i * (t * t) / d2;
            let s = sample(&e, p, Vec2::ZERO).unwrap();
            assert!(
                (s.radiance - want).abs().max_element() < 1e-5 * want.x.max(1e-3),
                "{a}: {} vs {want}",
                s.radiance
            );
            if a <= inner {
                assert!((s.radiance - i / d2).abs().max_element() < 1e-5, "{a}");
            }
        }
        assert!(sample(&e, at(0.41), Vec2::ZERO).is_none());
        assert!(
            sample(&e, Vec3::new(0.0, 0.0, 8.0), Vec2::ZERO).is_none(),
            "behind the light"
        );
    }

    /// Directional light: a delta light gives its illuminance from the
    /// opposite of its travel direction; a sun disk gives the same
    /// irradiance on a surface facing it, from directions inside its cone.
    #[test]
    fn directional_light_gives_its_illuminance() {
        let e_lux = Vec3::new(1.0, 2.0, 3.0);
        let travel = Vec3::new(0.0, -0.6, -0.8);
        let delta = punctual(EMITTER_DIRECTIONAL, Vec3::ZERO, travel, e_lux);
        let s = sample(&delta, Vec3::ONE, Vec2::new(0.5, 0.5)).unwrap();
        assert_eq!(
            (s.wi, s.radiance, s.t_max, s.mis),
            (-travel, e_lux, f32::MAX, false)
        );
        for radius in [0.004_65f64, 0.05, 0.3] {
            let sun = EmitterGpu {
                shape: Vec4::new((1.0 - radius.cos()) as f32, 0.0, 0.0, 0.0),
                ..delta
            };
            let n = 4096;
            let mut irradiance = Vec3::ZERO;
            for k in 0..n {
                let u = Vec2::new((k as f32 + 0.5) / n as f32, ((k * 97) % n) as f32 / n as f32);
                let s = sample(&sun, Vec3::ZERO, u).unwrap();
                let cos = s.wi.dot(-travel);
                assert!(cos as f64 >= radius.cos() - 1e-6, "outside the disk at {radius}");
                irradiance += s.radiance * cos / n as f32;
            }
            assert!(
                (irradiance - e_lux).abs().max_element() < 2e-3 * 3.0,
                "{radius}: {irradiance}"
            );
        }
    }

    /// A zero-probability entry never gives light.
    #[test]
    fn zero_probability_entries_are_skipped() {
        let e = EmitterGpu {
            pdf: 0.0,
            ..punctual(EMITTER_POINT, Vec3::Z, Vec3::ZERO, Vec3::ONE)
        };
        assert!(sample(&e, Vec3::ZERO, Vec2::ZERO).is_none());
    }
}
