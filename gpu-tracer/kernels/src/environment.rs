//! What a ray that leaves the scene sees: the environment (issue 30).
//!
//! Today a constant radiance in every direction, [`TraceParams::environment`]
//! (a uniform sky). The tracer finds it by BSDF sampling only and counts it
//! with weight 1 (it is not light-sampled, so there is nothing to weight it
//! against); for a Lambertian surface under a constant sky that is the
//! optimal strategy already (cosine sampling is proportional to the
//! integrand). Environment maps, importance-sampled and combined with BSDF
//! sampling by MIS (`sampler_core::distributions::environment`), come next.

use crate::abi::TraceParams;
use glam::Vec3;

/// Radiance arriving along `-dir` from the environment for a ray leaving the
/// scene in direction `dir` (unit): the constant
/// [`TraceParams::environment`], linear RGB.
#[inline]
pub fn environment_radiance(params: &TraceParams, _dir: Vec3) -> Vec3 {
    params.environment.truncate()
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
