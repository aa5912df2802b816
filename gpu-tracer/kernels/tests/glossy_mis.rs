//! The integrator with metallic-roughness materials: next-event estimation
//! combined with BSDF sampling by MIS must estimate the same direct light as
//! BSDF sampling alone (which counts emitters it hits with weight 1 when the
//! emitter list is empty), for near-specular and rough, metal and dielectric
//! floors. A wrong MIS weight, a density that does not match the sampler
//! (lobe choice, reused number, frame), or a missing `cos` shows up as a
//! difference of many standard errors.
//!
//! Scene: a floor `y = 0` of the material under test, a small emitter at
//! `y = 1` facing down, and a camera looking at the floor where the
//! emitter's mirror reflection lands. `max_depth` 2: direct light only.

use glam::{UVec2, UVec4, Vec3, Vec4};
use kernels::abi::{BvhNodeGpu, EmitterGpu, MaterialGpu, TraceParams, TriangleAttrGpu, TriangleGpu};
use kernels::trace_pixel;
use sampler_core::sequences::seed::hash_u32;

struct Scene {
    nodes: [BvhNodeGpu; 1],
    triangles: [TriangleGpu; 4],
    materials: [MaterialGpu; 2],
    emitters: [EmitterGpu; 2],
    attrs: [TriangleAttrGpu; 4],
}

fn scene(floor: MaterialGpu) -> Scene {
    let v = |x: f32, y: f32, z: f32, w: f32| Vec4::new(x, y, z, w);
    let tri = |a: Vec4, b: Vec4, c: Vec4| TriangleGpu { v0: a, v1: b, v2: c };
    let (x0, x1, z0, z1) = (0.2, 0.6, -0.2, 0.2);
    // v0.w = material, v1.w = the emitter's selection probability.
    let triangles = [
        tri(
            v(-5.0, 0.0, -5.0, 0.0),
            v(-5.0, 0.0, 5.0, 0.0),
            v(5.0, 0.0, -5.0, 0.0),
        ),
        tri(
            v(5.0, 0.0, -5.0, 0.0),
            v(-5.0, 0.0, 5.0, 0.0),
            v(5.0, 0.0, 5.0, 0.0),
        ),
        tri(v(x0, 1.0, z0, 1.0), v(x1, 1.0, z0, 0.5), v(x1, 1.0, z1, 0.0)),
        tri(v(x0, 1.0, z0, 1.0), v(x1, 1.0, z1, 0.5), v(x0, 1.0, z1, 0.0)),
    ];
    let area = 0.5 * (x1 - x0) * (z1 - z0);
    let e = |triangle: u32, cdf: f32| EmitterGpu {
        triangle,
        cdf,
        pdf: 0.5,
        intensity: Vec4::new(0.0, 0.0, 0.0, area),
        ..EmitterGpu::NONE
    };
    Scene {
        nodes: [BvhNodeGpu {
            min: v(-5.0, 0.0, -5.0, 0.0),
            max: v(5.0, 1.0, 5.0, 0.0),
            info: UVec4::new(4, 0, 0, 0),
        }],
        triangles,
        materials: [
            floor,
            MaterialGpu::untextured(Vec4::ZERO, Vec4::new(5.0, 4.0, 3.0, 0.0)),
        ],
        emitters: [e(2, 0.5), e(3, 1.0)],
        attrs: [TriangleAttrGpu::default(); 4],
    }
}

fn params(emitter_count: u32) -> TraceParams {
    let forward = Vec3::new(0.3, -0.6, 0.0).normalize();
    let right = Vec3::Z;
    let up = right.cross(forward);
    TraceParams {
        width: 12,
        height: 12,
        padded_width: 12,
        spp: 1,
        max_depth: 2,
        triangle_count: 4,
        emitter_count,
        node_count: 1,
        rr_depth: 3,
        tan_half_fov_y: 0.25,
        camera_origin: Vec4::new(-0.4, 0.6, 0.0, 0.0),
        camera_forward: forward.extend(0.0),
        camera_right: right.extend(0.0),
        camera_up: up.extend(0.0),
        ..Default::default()
    }
}

/// Mean luma over the image and its standard error, from `n` independent
/// one-sample paths per pixel.
fn estimate(s: &Scene, p: &TraceParams, salt: u32, n: u32) -> (f64, f64) {
    let (mut sum, mut sum_sq, mut count) = (0.0f64, 0.0f64, 0.0f64);
    for y in 0..p.height {
        for x in 0..p.width {
            for i in 0..n {
                let seed = hash_u32(((y * p.width + x) * n + i) ^ hash_u32(salt));
                let c = trace_pixel(
                    p,
                    UVec2::new(x, y),
                    seed,
                    &[],
                    &s.nodes,
                    &s.triangles,
                    &s.materials,
                    &s.emitters,
                    &s.attrs,
                    &[0],
                    &[0.0],
                );
                let l = f64::from(c.x + c.y + c.z) / 3.0;
                sum += l;
                sum_sq += l * l;
                count += 1.0;
            }
        }
    }
    let mean = sum / count;
    let var = (sum_sq / count - mean * mean).max(0.0) * count / (count - 1.0);
    (mean, (var / count).sqrt())
}

#[test]
fn mis_and_bsdf_sampling_alone_agree_on_glossy_floors() {
    let floors = [
        (
            "metal r0.1",
            MaterialGpu::metallic_roughness(Vec4::new(0.95, 0.8, 0.5, 0.0), 1.0, 0.1),
        ),
        (
            "metal r0.3",
            MaterialGpu::metallic_roughness(Vec4::new(0.95, 0.8, 0.5, 0.0), 1.0, 0.3),
        ),
        (
            "dielectric r0.1",
            MaterialGpu::metallic_roughness(Vec4::new(0.2, 0.4, 0.8, 0.0), 0.0, 0.1),
        ),
        (
            "dielectric r0.6",
            MaterialGpu::metallic_roughness(Vec4::new(0.2, 0.4, 0.8, 0.0), 0.0, 0.6),
        ),
        (
            "half metal r1",
            MaterialGpu::metallic_roughness(Vec4::new(0.7, 0.7, 0.7, 0.0), 0.5, 1.0),
        ),
    ];
    for (name, floor) in floors {
        let s = scene(floor);
        let (mis, mis_se) = estimate(&s, &params(2), 1, 96);
        let (bsdf, bsdf_se) = estimate(&s, &params(0), 2, 96);
        let z = (mis - bsdf) / (mis_se * mis_se + bsdf_se * bsdf_se).sqrt();
        eprintln!("{name}: MIS {mis:.5} +- {mis_se:.5}, BSDF only {bsdf:.5} +- {bsdf_se:.5}, z {z:.2}");
        assert!(mis > 0.01, "{name}: the floor reflects the emitter");
        assert!(
            z.abs() < 4.0,
            "{name}: MIS and BSDF sampling disagree (z = {z:.2})"
        );
        // MIS never does much worse than BSDF sampling alone.
        assert!(mis_se < 1.5 * bsdf_se, "{name}: {mis_se} vs {bsdf_se}");
    }
}
