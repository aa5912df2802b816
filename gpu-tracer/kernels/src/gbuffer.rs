//! The G-buffer: what the ray through each pixel's centre sees first
//! (depth, normal, albedo, ids) and where that point was in the previous
//! frame (backward motion vectors), for the temporal passes of a renderer.
//!
//! The ray goes through the pixel centre `(x + 0.5, y + 0.5)`, whatever the
//! trace pass's jitter: the G-buffer depends on the scene and the cameras
//! only, never on seeds, so it is the same for every sampler and mode.

use crate::abi::{
    BvhNodeGpu, GBufferGpu, MaterialGpu, TraceParams, TriangleAttrGpu, TriangleGpu, GBUFFER_EMITTER,
    GBUFFER_HIT, GBUFFER_NO_HIT, GBUFFER_PREV_IN_FRONT,
};
use crate::bvh::closest_hit_variant;
use crate::camera::{primary_ray, CameraView};
use crate::footprint::primary_footprint;
use crate::surface::{has_textures, surface_albedo, surface_albedo_filtered, surface_emission, triangle_uv};
use crate::trace::normal_and_area;
use crate::trace_variant::{FULL, TEXTURES};
use glam::{UVec2, UVec4, Vec2, Vec4};

/// The G-buffer texel of `pixel` (see [`GBufferGpu`] for every field and
/// the no-hit value). Identical to what
/// [`GBUFFER_ENTRY`](crate::abi::GBUFFER_ENTRY) computes on the GPU.
///
/// Motion: the hit point `p` at barycentrics `(u, v)` of its triangle was at
/// the same barycentrics of the triangle's previous positions (`previous`,
/// parallel to `triangles`), `p'`; the motion is the previous camera's
/// raster position of `p'` minus the current camera's raster position of
/// `p` (the pixel centre up to rounding: projecting both points keeps the
/// rounding of the intersection out of the difference). A background
/// pixel's motion is that of its ray direction (a point at infinity: camera
/// rotation only).
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn gbuffer_pixel(
    params: &TraceParams,
    pixel: UVec2,
    nodes: &[BvhNodeGpu],
    triangles: &[TriangleGpu],
    materials: &[MaterialGpu],
    attrs: &[TriangleAttrGpu],
    images: &[u32],
    previous: &[TriangleGpu],
) -> GBufferGpu {
    gbuffer_pixel_variant::<FULL>(
        params, pixel, nodes, triangles, materials, attrs, images, previous,
    )
}

/// [`gbuffer_pixel`] for the kernel variant of `FEATURES`
/// ([`crate::trace_variant`]; the G-buffer reads no shading normal, light
/// or glossy lobe, so only [`TEXTURES`] matters): without it, no cut-out
/// test and the material's albedo and emission factors stand for its
/// textures. The same texel, bit for bit, on a scene without textures,
/// normal maps or cut-outs.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn gbuffer_pixel_variant<const FEATURES: u32>(
    params: &TraceParams,
    pixel: UVec2,
    nodes: &[BvhNodeGpu],
    triangles: &[TriangleGpu],
    materials: &[MaterialGpu],
    attrs: &[TriangleAttrGpu],
    images: &[u32],
    previous: &[TriangleGpu],
) -> GBufferGpu {
    let textured = FEATURES & TEXTURES != 0;
    let (w, h) = (params.width, params.height);
    let ray = primary_ray(params, pixel.x, pixel.y, Vec2::splat(0.5));
    let current = CameraView::current(params);
    let prev = CameraView::previous(params);
    let hit = closest_hit_variant::<FEATURES>(
        nodes,
        triangles,
        materials,
        attrs,
        images,
        params.image_count,
        &ray,
        0.0,
        f32::MAX,
    );
    let hit = match hit {
        Some(hit) => hit,
        None => {
            let mut motion = Vec4::ZERO;
            if let (Some((now, _)), Some((then, _))) = (
                current.project_offset(w, h, ray.dir),
                prev.project_offset(w, h, ray.dir),
            ) {
                motion = (then - now).extend(0.0).extend(0.0);
            }
            return GBufferGpu {
                normal_depth: Vec4::ZERO,
                albedo: Vec4::ZERO,
                motion,
                ids: UVec4::new(GBUFFER_NO_HIT, GBUFFER_NO_HIT, GBUFFER_NO_HIT, 0),
            };
        }
    };
    let index = hit.triangle as usize;
    let tri = triangles[index];
    let attr = attrs[index];
    let (v0, v1, v2) = (tri.v0.truncate(), tri.v1.truncate(), tri.v2.truncate());
    let (geo_normal, _) = normal_and_area(v0, v1, v2);
    let point = v0 + (v1 - v0) * hit.u + (v2 - v0) * hit.v;
    let material_index = tri.v0.w as u32;
    let material = materials[material_index as usize];
    let uv = triangle_uv(&attr, hit.u, hit.v);
    let cos_out = -ray.dir.dot(geo_normal);
    let normal = if cos_out > 0.0 { geo_normal } else { -geo_normal };
    // The albedo the camera ray's first hit shades with: filtered over the
    // pixel's footprint (`crate::footprint`), as the trace pass reads it.
    let albedo = if !textured {
        material.albedo.truncate()
    } else if has_textures(&material) {
        let (uv_centre, width) = primary_footprint(params, pixel, (v0, v1, v2), &attr, uv, hit.t);
        surface_albedo_filtered(&material, images, params.image_count, uv_centre, width)
    } else {
        surface_albedo(&material, images, params.image_count, uv)
    };
    let emission = if textured {
        surface_emission(&material, images, params.image_count, uv)
    } else {
        material.emission.truncate()
    };
    let mut flags = GBUFFER_HIT;
    if cos_out > 0.0 && emission.max_element() > 0.0 {
        flags |= GBUFFER_EMITTER;
    }
    let depth = (point - current.origin).dot(current.forward);

    let p = previous[index];
    let (p0, p1, p2) = (p.v0.truncate(), p.v1.truncate(), p.v2.truncate());
    let then_point = p0 + (p1 - p0) * hit.u + (p2 - p0) * hit.v;
    let mut motion = Vec4::ZERO;
    if let (Some((now, _)), Some((then, then_depth))) =
        (current.project(w, h, point), prev.project(w, h, then_point))
    {
        motion = Vec4::new(then.x - now.x, then.y - now.y, then_depth, 0.0);
        flags |= GBUFFER_PREV_IN_FRONT;
    }
    GBufferGpu {
        normal_depth: normal.extend(depth),
        albedo: albedo.extend(0.0),
        motion,
        ids: UVec4::new(attr.ids.x, material_index, attr.ids.y, flags),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::abi::MaterialGpu;
    use glam::Vec3;

    /// A fronto-parallel plane `z = -depth` (two triangles, object 3,
    /// material 0), seen by a camera at the origin looking along `-z`.
    struct Plane {
        nodes: [BvhNodeGpu; 1],
        triangles: [TriangleGpu; 2],
        materials: [MaterialGpu; 1],
        attrs: [TriangleAttrGpu; 2],
    }

    fn plane(depth: f32, shift: Vec3) -> Plane {
        let v = |x: f32, y: f32| (Vec3::new(x, y, -depth) + shift).extend(0.0);
        let t0 = TriangleGpu {
            v0: v(-100.0, -100.0),
            v1: v(100.0, -100.0),
            v2: v(100.0, 100.0),
        };
        let t1 = TriangleGpu {
            v0: v(-100.0, -100.0),
            v1: v(100.0, 100.0),
            v2: v(-100.0, 100.0),
        };
        let attr = |i: u32| TriangleAttrGpu {
            ids: UVec4::new(3, i, 0, 0),
            ..Default::default()
        };
        Plane {
            nodes: [BvhNodeGpu {
                min: (Vec3::new(-100.0, -100.0, -depth) + shift).extend(0.0),
                max: (Vec3::new(100.0, 100.0, -depth) + shift).extend(0.0),
                info: UVec4::new(2, 0, 0, 0),
            }],
            triangles: [t0, t1],
            materials: [MaterialGpu::untextured(
                Vec4::new(0.25, 0.5, 0.75, 0.0),
                Vec4::ZERO,
            )],
            attrs: [attr(0), attr(1)],
        }
    }

    fn params(prev_origin: Vec3) -> TraceParams {
        TraceParams {
            width: 64,
            height: 48,
            padded_width: 64,
            spp: 1,
            max_depth: 1,
            node_count: 1,
            triangle_count: 2,
            tan_half_fov_y: 0.5,
            camera_origin: Vec4::ZERO,
            camera_forward: Vec4::new(0.0, 0.0, -1.0, 0.0),
            camera_right: Vec4::X,
            camera_up: Vec4::Y,
            prev_camera_origin: prev_origin.extend(0.0),
            prev_camera_forward: Vec4::new(0.0, 0.0, -1.0, 0.0),
            prev_camera_right: Vec4::X,
            prev_camera_up: Vec4::Y,
            prev_tan_half_fov_y: 0.5,
            ..Default::default()
        }
    }

    fn texel(p: &TraceParams, scene: &Plane, previous: &[TriangleGpu], x: u32, y: u32) -> GBufferGpu {
        gbuffer_pixel(
            p,
            UVec2::new(x, y),
            &scene.nodes,
            &scene.triangles,
            &scene.materials,
            &scene.attrs,
            &[0],
            previous,
        )
    }

    /// A camera that moved by `s` along x sees a plane at depth `d` shifted
    /// by `s * height / (2 d tan(fov/2))` pixels: the previous position is
    /// that far to the left for a camera that moved right.
    #[test]
    fn camera_translation_gives_the_analytic_shift() {
        let depth = 10.0;
        let scene = plane(depth, Vec3::ZERO);
        for s in [0.0f32, 0.05, -0.3, 1.7] {
            let p = params(Vec3::new(-s, 0.0, 0.0));
            let expected = s * 48.0 / (2.0 * depth * 0.5);
            for (x, y) in [(0u32, 0u32), (31, 20), (63, 47), (10, 40)] {
                let g = texel(&p, &scene, &scene.triangles, x, y);
                assert_eq!(g.ids.w, GBUFFER_HIT | GBUFFER_PREV_IN_FRONT);
                assert_eq!((g.ids.x, g.ids.y), (3, 0));
                assert!(
                    (g.motion.x - expected).abs() < 1e-3,
                    "s {s} ({x},{y}): {}",
                    g.motion
                );
                assert!(g.motion.y.abs() < 1e-3, "{}", g.motion);
                assert!((g.normal_depth.w - depth).abs() < 1e-4);
                assert!((g.motion.z - depth).abs() < 1e-4);
                assert_eq!(g.normal_depth.truncate(), Vec3::Z);
                assert_eq!(g.albedo, Vec4::new(0.25, 0.5, 0.75, 0.0));
            }
        }
    }

    /// Object motion: the plane moved down by `m` since the previous frame,
    /// so its points were `m * scale` pixels higher (smaller raster y).
    #[test]
    fn object_motion_uses_the_previous_positions() {
        let depth = 8.0;
        let m = 0.4;
        let now = plane(depth, Vec3::new(0.0, -m, 0.0));
        let before = plane(depth, Vec3::ZERO);
        let p = params(Vec3::ZERO);
        let expected = -m * 48.0 / (2.0 * depth * 0.5);
        let g = texel(&p, &now, &before.triangles, 20, 30);
        assert!((g.motion.y - expected).abs() < 1e-3, "{}", g.motion);
        assert!(g.motion.x.abs() < 1e-3);
        // A still scene: exactly zero.
        let g = texel(&p, &now, &now.triangles, 20, 30);
        assert_eq!(g.motion, Vec4::new(0.0, 0.0, g.motion.z, 0.0));
    }

    /// Background pixels: the no-hit value, with the motion of the view
    /// direction (zero for a translating camera, non-zero for a rotation).
    #[test]
    fn background_is_the_no_hit_value() {
        let scene = plane(10.0, Vec3::new(0.0, 0.0, 100.0)); // behind the camera
        let p = params(Vec3::new(-1.0, 0.0, 0.0));
        let g = texel(&p, &scene, &scene.triangles, 5, 5);
        assert_eq!(
            g.ids,
            UVec4::new(GBUFFER_NO_HIT, GBUFFER_NO_HIT, GBUFFER_NO_HIT, 0)
        );
        assert_eq!(
            (g.normal_depth, g.albedo, g.motion),
            (Vec4::ZERO, Vec4::ZERO, Vec4::ZERO)
        );
        // Previous camera turned: its right axis rotated about y.
        let (s, c) = libm::sincosf(0.05);
        let turned = TraceParams {
            prev_camera_forward: Vec4::new(-s, 0.0, -c, 0.0),
            prev_camera_right: Vec4::new(c, 0.0, -s, 0.0),
            ..p
        };
        let g = texel(&turned, &scene, &scene.triangles, 32, 24);
        assert!(g.motion.x.abs() > 1.0 && g.motion.y.abs() < 1e-3, "{}", g.motion);
    }
}
