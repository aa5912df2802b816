//! The emitter list next-event estimation picks from
//! ([`kernels::abi::EmitterGpu`]): every front-emitting triangle with
//! positive area and emission whose material cuts no holes (a cut-out
//! emitter stays out: light samples would land in its holes; BSDF sampling
//! finds it, weight 1), then every punctual light with positive
//! power, then the environment map if it is not black, each picked with
//! probability proportional to its power.
//!
//! Powers are compared divided by pi: an emissive triangle's is `area *
//! mean(emission rgb)`, a light's is [`Light::power`], an environment map's
//! `4 pi r^2 L` with `L` its mean radiance over directions and `r` the
//! radius of the scene's bounding sphere (pbrt-v4's estimate for infinite
//! lights). The selection
//! probability of each emissive triangle is also written to its
//! `TriangleGpu::v1.w`, for the MIS weight of BSDF samples that hit it.

use super::Light;
use glam::Vec3;
use kernels::abi::{EmitterGpu, MaterialGpu, TriangleGpu, CUT_OUT, EMITTER_ENVIRONMENT, EMITTER_TRIANGLE};
use kernels::trace::normal_and_area;

/// The emitter list of `triangles` (leaf order, material index in
/// `v0.w`), `lights` (validated) and an environment map of mean radiance
/// `environment_mean` (0: none, or black), and the number of meaningful entries
/// (0 when nothing emits: the list then holds one [`EmitterGpu::NONE`],
/// as wgpu refuses empty buffers). Sets each triangle's `v1.w` to its
/// selection probability (0 for triangles that are not in the list).
pub(super) fn emitter_list(
    triangles: &mut [TriangleGpu],
    materials: &[MaterialGpu],
    lights: &[Light],
    environment_mean: f64,
) -> (Vec<EmitterGpu>, u32) {
    let mut emitters = Vec::new();
    let mut powers = Vec::new();
    for (i, t) in triangles.iter_mut().enumerate() {
        t.v1.w = 0.0;
        let emission = materials[t.v0.w as usize].emission.truncate();
        let (_, area) = normal_and_area(t.v0.truncate(), t.v1.truncate(), t.v2.truncate());
        let power = area as f64 * (emission.x as f64 + emission.y as f64 + emission.z as f64) / 3.0;
        if power > 0.0 && t.v2.w != CUT_OUT {
            emitters.push(EmitterGpu {
                kind: EMITTER_TRIANGLE,
                triangle: i as u32,
                intensity: glam::Vec4::new(0.0, 0.0, 0.0, area),
                ..EmitterGpu::NONE
            });
            powers.push(power);
        }
    }
    let radius = scene_radius(triangles);
    for light in lights {
        let power = light.power(radius);
        if power > 0.0 {
            emitters.push(light.emitter());
            powers.push(power);
        }
    }
    if environment_mean > 0.0 {
        emitters.push(EmitterGpu {
            kind: EMITTER_ENVIRONMENT,
            ..EmitterGpu::NONE
        });
        powers.push(environment_power(radius, environment_mean));
    }

    let total: f64 = powers.iter().sum();
    let n = emitters.len();
    let mut running = 0.0f64;
    for (k, (e, power)) in emitters.iter_mut().zip(&powers).enumerate() {
        let p = power / total;
        running += p;
        e.pdf = p as f32;
        e.cdf = if k + 1 == n { 1.0 } else { running as f32 };
        if e.kind == EMITTER_TRIANGLE {
            triangles[e.triangle as usize].v1.w = e.pdf;
        }
    }
    if emitters.is_empty() {
        emitters.push(EmitterGpu::NONE);
    }
    (emitters, n as u32)
}

/// The power over pi of an environment map of mean radiance `mean` around
/// a scene of bounding radius `radius`: `4 pi r^2 L` (module docs).
pub(super) fn environment_power(radius: f32, mean: f64) -> f64 {
    4.0 * std::f64::consts::PI * (radius as f64).powi(2) * mean
}

/// Radius of the sphere around the centre of the triangles' bounding box
/// that holds the box (half its diagonal), in world units: the scale a
/// directional light's power is measured on.
pub(super) fn scene_radius(triangles: &[TriangleGpu]) -> f32 {
    let (lo, hi) = triangles.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), t| {
            let (a, b, c) = (t.v0.truncate(), t.v1.truncate(), t.v2.truncate());
            (lo.min(a).min(b).min(c), hi.max(a).max(b).max(c))
        },
    );
    if lo.cmple(hi).all() {
        0.5 * (hi - lo).length()
    } else {
        0.0
    }
}
