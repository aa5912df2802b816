//! What a ray that leaves the scene sees: the environment (issue 30).
//!
//! Either a constant radiance in every direction,
//! [`TraceParams::environment`] (a uniform sky), or an equirectangular
//! environment map ([`TraceParams::environment_map`] non-empty) whose
//! texels and sampling table the host binds at binding 10 of
//! [`TRACE_ENTRY`](crate::abi::TRACE_ENTRY) (the table first, then the
//! texels; `sampler_core::distributions::environment` has the conventions:
//! +Y up, `u = 0.5` looking down -Z, rotation in turns about +Y).
//!
//! The constant sky is found by BSDF sampling only and counted with weight
//! 1: for a Lambertian surface under a constant sky that is already the
//! optimal strategy (cosine sampling is proportional to the integrand). A
//! map is also an entry of the emitter list
//! ([`EMITTER_ENVIRONMENT`](crate::abi::EMITTER_ENVIRONMENT)), sampled in
//! proportion to luminance times solid angle ([`crate::lights`]), and a
//! BSDF sample that escapes is weighted against that strategy by the power
//! heuristic ([`environment_mis_weight`]). Radiance is looked up at the
//! nearest texel (no filtering), so that the radiance and the sampling
//! density are the same piecewise-constant function of direction.

use crate::abi::TraceParams;
use crate::mis::power_heuristic;
use glam::{Vec2, Vec3};
use sampler_core::distributions::environment::{direction_to_uv, pdf_environment};
use sampler_core::EnvironmentParams;

/// Radiance arriving along `-dir` from the environment for a ray leaving the
/// scene in direction `dir` (unit), linear RGB: the map's texel at `dir`
/// when [`TraceParams::environment_map`] has texels (`environment` is then
/// the buffer of binding 10), else the constant
/// [`TraceParams::environment`].
#[inline]
pub fn environment_radiance(params: &TraceParams, environment: &[f32], dir: Vec3) -> Vec3 {
    let map = params.environment_map;
    if map.width == 0 {
        return params.environment.truncate();
    }
    environment_texel(map, environment, direction_to_uv(dir, map.rotation_turns))
}

/// The texel of the map `map` covering the map coordinates `uv` (in
/// `[0, 1]^2`; clamped to the edge texels), read from `environment`: the
/// sampling table (`EnvironmentMap::table_len(width, height)` entries),
/// then `width * height` texels of three `f32` (linear RGB), row-major from
/// the top row. Black past the end of a short buffer.
#[inline]
pub fn environment_texel(map: EnvironmentParams, environment: &[f32], uv: Vec2) -> Vec3 {
    let (w, h) = (map.width.max(1), map.height.max(1));
    let x = ((uv.x.max(0.0) * w as f32) as u32).min(w - 1);
    let y = ((uv.y.max(0.0) * h as f32) as u32).min(h - 1);
    let table_len = 1u32.wrapping_add(h).wrapping_add(w.wrapping_mul(h));
    let first = table_len.wrapping_add(y.wrapping_mul(w).wrapping_add(x).wrapping_mul(3)) as usize;
    if first + 2 < environment.len() {
        Vec3::new(environment[first], environment[first + 1], environment[first + 2])
    } else {
        Vec3::ZERO
    }
}

/// MIS weight of a BSDF sample of solid-angle density `bsdf_pdf` that left
/// the scene in direction `dir` and sees an environment map: the power
/// heuristic against the map's light sampling (selection probability
/// [`TraceParams::environment`]`.w` times the map's density at `dir`). 1
/// for a camera ray (`bsdf_pdf` 0), a constant sky, or a map outside the
/// emitter list.
#[inline]
pub fn environment_mis_weight(params: &TraceParams, environment: &[f32], dir: Vec3, bsdf_pdf: f32) -> f32 {
    let select = params.environment.w;
    if params.environment_map.width == 0 || bsdf_pdf <= 0.0 || select <= 0.0 || params.emitter_count == 0 {
        return 1.0;
    }
    let light_pdf = select * pdf_environment(environment, params.environment_map, dir);
    power_heuristic(bsdf_pdf, light_pdf)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::abi::{BvhNodeGpu, EmitterGpu, MaterialGpu, TriangleAttrGpu, TriangleGpu};
    use crate::trace::trace_pixel;
    use glam::{UVec2, UVec4, Vec4};

    /// White furnace: a Lambertian floor of albedo 1 under a constant sky of
    /// radiance `L`, seen from above: every cosine-sampled direction leaves
    /// the scene, so every pixel of every sample reads `L` exactly (camera
    /// rays that miss the floor see the sky, the floor reflects all of it).
    #[test]
    fn a_white_floor_under_a_constant_sky_returns_the_sky() {
        let tri = |a: [f32; 3], b: [f32; 3], c: [f32; 3]| TriangleGpu {
            v0: Vec4::new(a[0], a[1], a[2], 0.0),
            v1: Vec4::new(b[0], b[1], b[2], 0.0),
            v2: Vec4::new(c[0], c[1], c[2], 0.0),
        };
        // One triangle covering the view, at y = 0, facing up.
        let floor = tri([-100.0, 0.0, 100.0], [100.0, 0.0, 100.0], [0.0, 0.0, -100.0]);
        let node = BvhNodeGpu {
            min: Vec4::new(-100.0, 0.0, -100.0, 0.0),
            max: Vec4::new(100.0, 0.0, 100.0, 0.0),
            info: UVec4::new(1, 0, 0, 0),
        };
        let material = MaterialGpu::untextured(Vec4::ONE, Vec4::ZERO);
        let sky = Vec3::new(0.5, 1.0, 2.0);
        let params = TraceParams {
            width: 8,
            height: 8,
            padded_width: 8,
            spp: 4,
            max_depth: 8,
            node_count: 1,
            triangle_count: 1,
            rr_depth: 1,
            tan_half_fov_y: 1.5,
            camera_origin: Vec4::new(0.0, 5.0, 0.0, 0.0),
            camera_forward: Vec4::new(0.0, -0.8, -0.6, 0.0),
            camera_right: Vec4::X,
            camera_up: Vec4::new(0.0, 0.6, -0.8, 0.0),
            environment: sky.extend(0.0),
            ..Default::default()
        };
        let attrs = [TriangleAttrGpu::default()];
        let trace = |params: &TraceParams, pixel: UVec2, seed: u32| {
            trace_pixel(
                params,
                pixel,
                seed,
                &[],
                &[node],
                &[floor],
                &[material],
                &[EmitterGpu::NONE],
                &attrs,
                &[0],
                &[0.0],
            )
        };
        let mut saw_floor = false;
        for (x, y) in [(0u32, 0u32), (3, 4), (7, 7), (5, 1)] {
            for seed in [1u32, 77, 123_456] {
                let c = trace(&params, UVec2::new(x, y), seed);
                let err = (c.truncate() - sky).abs().max_element();
                assert!(
                    err <= 1e-5 * sky.max_element(),
                    "pixel ({x}, {y}) seed {seed}: {c} against {sky}"
                );
                saw_floor |= y >= 4;
            }
        }
        assert!(saw_floor);
        // No environment: the same view is black.
        let dark = TraceParams {
            environment: Vec4::ZERO,
            ..params
        };
        let c = trace(&dark, UVec2::new(3, 6), 5);
        assert_eq!(c.truncate(), Vec3::ZERO);
    }
}
