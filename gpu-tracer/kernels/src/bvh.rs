//! BVH2 traversal over the flat node array: closest hit and any hit
//! (shadow rays).
//!
//! The tree is obvhs 0.4's `Bvh2` in [`BvhNodeGpu`] form, root at index 0.
//! Traversal is iterative with a fixed stack of [`STACK_SIZE`] entries,
//! nearest child first; a popped node is skipped when its entry distance is
//! beyond the closest hit found so far. A push is dropped when the stack is
//! full, so the host must only upload trees whose leaves are at depth
//! `<= STACK_SIZE` (root at depth 0): at most one entry per level is pushed
//! along the current root-to-node path, so such trees never overflow.
//! `gpu-tracer`'s BVH builder checks this.
//!
//! # Alpha cut-outs
//!
//! A triangle flagged [`CUT_OUT`] (its material has an alpha cutoff, glTF
//! `MASK`) is tested at every candidate hit: where the base colour alpha
//! (`crate::surface::surface_alpha`) is below the cutoff there is no
//! surface, and the traversal goes on as if the triangle had been missed.
//! Both queries do this, so holes let camera, continuation and shadow rays
//! through alike. Unflagged (opaque) triangles cost one comparison of a word
//! already loaded. The queries take the material, attribute and image
//! buffers for this; a scene without cut-outs never reads them (empty
//! slices are fine then).

use crate::abi::{BvhNodeGpu, MaterialGpu, TriangleAttrGpu, TriangleGpu, CUT_OUT};
use crate::intersect::{intersect_aabb, intersect_triangle, Ray};
use crate::surface::{surface_alpha, triangle_uv};

/// Entries of the traversal stack, and the largest leaf depth (root = 0)
/// a tree may have.
pub const STACK_SIZE: usize = 32;

/// Sentinel for "no node" in the traversal loop.
const NO_NODE: u32 = u32::MAX;

/// Closest intersection of a ray with the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the ray, in `(t_min, t_max)` of the query.
    pub t: f32,
    /// Index of the triangle in the triangle buffer.
    pub triangle: u32,
    /// Barycentric weight of the triangle's `v1`.
    pub u: f32,
    /// Barycentric weight of the triangle's `v2`.
    pub v: f32,
}

/// Closest surface the ray meets at a distance in `(t_min, t_max)`, or
/// `None`: the closest triangle, holes of cut-out triangles excepted
/// (module docs). Ties in distance go to the triangle tested first.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn closest_hit(
    nodes: &[BvhNodeGpu],
    triangles: &[TriangleGpu],
    materials: &[MaterialGpu],
    attrs: &[TriangleAttrGpu],
    images: &[u32],
    image_count: u32,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<Hit> {
    traverse(
        nodes,
        triangles,
        materials,
        attrs,
        images,
        image_count,
        ray,
        t_min,
        t_max,
        false,
    )
}

/// Whether any surface meets the ray at a distance in `(t_min, t_max)`
/// (shadow-ray visibility test; stops at the first hit found; holes of
/// cut-out triangles let the ray through).
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn any_hit(
    nodes: &[BvhNodeGpu],
    triangles: &[TriangleGpu],
    materials: &[MaterialGpu],
    attrs: &[TriangleAttrGpu],
    images: &[u32],
    image_count: u32,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> bool {
    traverse(
        nodes,
        triangles,
        materials,
        attrs,
        images,
        image_count,
        ray,
        t_min,
        t_max,
        true,
    )
    .is_some()
}

/// Whether barycentrics `(u, v)` of triangle `index` (flagged [`CUT_OUT`])
/// fall in a hole: base colour alpha below the material's cutoff.
#[allow(clippy::too_many_arguments)]
#[inline]
fn in_hole(
    tri: &TriangleGpu,
    index: u32,
    materials: &[MaterialGpu],
    attrs: &[TriangleAttrGpu],
    images: &[u32],
    image_count: u32,
    u: f32,
    v: f32,
) -> bool {
    let material = materials[tri.v0.w as u32 as usize];
    let uv = triangle_uv(&attrs[index as usize], u, v);
    surface_alpha(&material, images, image_count, uv) < material.alpha.x
}

/// Shared traversal: with `stop_at_first` the first hit found is returned,
/// otherwise the closest.
#[allow(clippy::too_many_arguments)]
#[inline]
fn traverse(
    nodes: &[BvhNodeGpu],
    triangles: &[TriangleGpu],
    materials: &[MaterialGpu],
    attrs: &[TriangleAttrGpu],
    images: &[u32],
    image_count: u32,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
    stop_at_first: bool,
) -> Option<Hit> {
    let inv_dir = ray.inv_dir();
    let mut best_t = t_max;
    let mut best = Hit {
        t: t_max,
        triangle: 0,
        u: 0.0,
        v: 0.0,
    };
    let mut found = false;
    let mut stack_node = [0u32; STACK_SIZE];
    let mut stack_t = [0.0f32; STACK_SIZE];
    let mut sp = 0usize;

    let root = nodes[0];
    let mut node_index = match intersect_aabb(
        ray.origin,
        inv_dir,
        root.min.truncate(),
        root.max.truncate(),
        t_min,
        best_t,
    ) {
        Some(_) => 0,
        None => NO_NODE,
    };

    loop {
        if node_index == NO_NODE {
            if sp == 0 {
                break;
            }
            sp -= 1;
            if stack_t[sp] < best_t {
                node_index = stack_node[sp];
            }
            continue;
        }
        let node = nodes[node_index as usize];
        let count = node.info.x;
        let first = node.info.y;
        node_index = NO_NODE;
        if count == 0 {
            let a = nodes[first as usize];
            let b = nodes[first.wrapping_add(1) as usize];
            let ta = intersect_aabb(
                ray.origin,
                inv_dir,
                a.min.truncate(),
                a.max.truncate(),
                t_min,
                best_t,
            );
            let tb = intersect_aabb(
                ray.origin,
                inv_dir,
                b.min.truncate(),
                b.max.truncate(),
                t_min,
                best_t,
            );
            match (ta, tb) {
                (Some(ta), Some(tb)) => {
                    let (near, far, t_far) = if ta <= tb {
                        (first, first.wrapping_add(1), tb)
                    } else {
                        (first.wrapping_add(1), first, ta)
                    };
                    if sp < STACK_SIZE {
                        stack_node[sp] = far;
                        stack_t[sp] = t_far;
                        sp += 1;
                    }
                    node_index = near;
                }
                (Some(_), None) => node_index = first,
                (None, Some(_)) => node_index = first.wrapping_add(1),
                (None, None) => {}
            }
        } else {
            let mut i = 0u32;
            while i < count {
                let index = first.wrapping_add(i);
                let tri = triangles[index as usize];
                if let Some(h) = intersect_triangle(
                    ray,
                    tri.v0.truncate(),
                    tri.v1.truncate(),
                    tri.v2.truncate(),
                    t_min,
                    best_t,
                ) {
                    if tri.v2.w == CUT_OUT
                        && in_hole(&tri, index, materials, attrs, images, image_count, h.u, h.v)
                    {
                        i += 1;
                        continue;
                    }
                    best_t = h.t;
                    best = Hit {
                        t: h.t,
                        triangle: index,
                        u: h.u,
                        v: h.v,
                    };
                    found = true;
                    if stop_at_first {
                        return Some(best);
                    }
                }
                i += 1;
            }
        }
    }
    if found {
        Some(best)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{UVec4, Vec3};

    fn tri(a: Vec3, b: Vec3, c: Vec3) -> TriangleGpu {
        TriangleGpu {
            v0: a.extend(0.0),
            v1: b.extend(0.0),
            v2: c.extend(0.0),
        }
    }

    fn node(min: Vec3, max: Vec3, count: u32, first: u32) -> BvhNodeGpu {
        BvhNodeGpu {
            min: min.extend(0.0),
            max: max.extend(0.0),
            info: UVec4::new(count, first, 0, 0),
        }
    }

    /// Two unit squares facing +z at z = 0 and z = -2, one leaf each
    /// (hand-built tree: root, then leaves at nodes 1 and 2).
    fn two_planes() -> (Vec<BvhNodeGpu>, Vec<TriangleGpu>) {
        let square = |z: f32| {
            let (a, b, c, d) = (
                Vec3::new(0.0, 0.0, z),
                Vec3::new(1.0, 0.0, z),
                Vec3::new(1.0, 1.0, z),
                Vec3::new(0.0, 1.0, z),
            );
            [tri(a, b, c), tri(a, c, d)]
        };
        let mut tris = Vec::new();
        tris.extend(square(-2.0));
        tris.extend(square(0.0));
        let nodes = vec![
            node(Vec3::new(0.0, 0.0, -2.0), Vec3::new(1.0, 1.0, 0.0), 0, 1),
            node(Vec3::new(0.0, 0.0, -2.0), Vec3::new(1.0, 1.0, -2.0), 2, 0),
            node(Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), 2, 2),
        ];
        (nodes, tris)
    }

    #[test]
    fn closest_hit_picks_the_nearer_leaf_from_both_sides() {
        let (nodes, tris) = two_planes();
        let down = Ray::new(Vec3::new(0.3, 0.6, 5.0), -Vec3::Z);
        let hit = closest_hit(&nodes, &tris, &[], &[], &[], 0, &down, 0.0, f32::INFINITY).expect("hit");
        assert!((hit.t - 5.0).abs() < 1e-5);
        assert!(hit.triangle >= 2);
        let up = Ray::new(Vec3::new(0.3, 0.6, -5.0), Vec3::Z);
        let hit = closest_hit(&nodes, &tris, &[], &[], &[], 0, &up, 0.0, f32::INFINITY).expect("hit");
        assert!((hit.t - 3.0).abs() < 1e-5);
        assert!(hit.triangle < 2);
        // Between the planes going down: only the lower one, and t_max can exclude it.
        let mid = Ray::new(Vec3::new(0.3, 0.6, -1.0), -Vec3::Z);
        assert!(
            (closest_hit(&nodes, &tris, &[], &[], &[], 0, &mid, 0.0, 10.0)
                .expect("hit")
                .t
                - 1.0)
                .abs()
                < 1e-5
        );
        assert_eq!(closest_hit(&nodes, &tris, &[], &[], &[], 0, &mid, 0.0, 0.9), None);
        assert!(!any_hit(&nodes, &tris, &[], &[], &[], 0, &mid, 0.0, 0.9));
        assert!(any_hit(&nodes, &tris, &[], &[], &[], 0, &mid, 0.0, 1.1));
        // Missing the root box.
        let away = Ray::new(Vec3::new(3.0, 0.5, 5.0), -Vec3::Z);
        assert_eq!(
            closest_hit(&nodes, &tris, &[], &[], &[], 0, &away, 0.0, f32::INFINITY),
            None
        );
    }

    /// The near square of [`two_planes`] cut out by material 1 (cutoff
    /// 0.5), its base colour texture a 2x1 image whose left texel has alpha
    /// 0 and right texel alpha 255 (UVs = `xy`): rays through the left half
    /// reach the far square, rays through the right half stop; shadow rays
    /// likewise. With the alpha factor at 0.25 the whole square is a hole;
    /// unflagged, the same triangles are opaque.
    #[test]
    fn cut_out_holes_let_both_queries_through() {
        use crate::abi::{MaterialGpu, TEXTURE_NONE};
        use glam::Vec4;
        let (nodes, mut tris) = two_planes();
        for t in &mut tris[2..] {
            t.v0.w = 1.0;
            t.v2.w = CUT_OUT;
        }
        let attrs: Vec<TriangleAttrGpu> = tris
            .iter()
            .map(|t| TriangleAttrGpu {
                uv01: Vec4::new(t.v0.x, t.v0.y, t.v1.x, t.v1.y),
                uv2: Vec4::new(t.v2.x, t.v2.y, 0.0, 0.0),
                ids: UVec4::ZERO,
                ..Default::default()
            })
            .collect();
        let images = [4u32, 2, 1, 0, 0x00FF_FFFF, 0xFFFF_FFFF];
        let mut mask = MaterialGpu::untextured(Vec4::ONE, Vec4::ZERO);
        mask.textures = UVec4::new(0, 0, TEXTURE_NONE, 0);
        mask.alpha = Vec4::new(0.5, 1.0, 0.0, 0.0);
        let mut materials = [MaterialGpu::untextured(Vec4::ONE, Vec4::ZERO), mask];
        let down = |x: f32| Ray::new(Vec3::new(x, 0.5, 5.0), -Vec3::Z);
        let closest = |m: &[MaterialGpu], t: &[TriangleGpu], x: f32| {
            closest_hit(&nodes, t, m, &attrs, &images, 1, &down(x), 0.0, f32::INFINITY).map(|h| h.t)
        };
        let blocked =
            |m: &[MaterialGpu], x: f32| any_hit(&nodes, &tris, m, &attrs, &images, 1, &down(x), 0.0, 6.0);
        assert_eq!(closest(&materials, &tris, 0.25), Some(7.0), "through the hole");
        assert_eq!(closest(&materials, &tris, 0.75), Some(5.0), "on the opaque half");
        assert!(!blocked(&materials, 0.25) && blocked(&materials, 0.75));
        // Alpha factor 0.25: everything is below the cutoff.
        materials[1].alpha.y = 0.25;
        assert_eq!(closest(&materials, &tris, 0.75), Some(7.0));
        assert!(!blocked(&materials, 0.75));
        // Unflagged triangles are not tested (opaque).
        let (_, opaque) = two_planes();
        assert_eq!(closest(&materials, &opaque, 0.25), Some(5.0));
    }

    #[test]
    fn single_leaf_root() {
        let (_, tris) = two_planes();
        let nodes = vec![node(Vec3::new(0.0, 0.0, -2.0), Vec3::new(1.0, 1.0, 0.0), 4, 0)];
        let ray = Ray::new(Vec3::new(0.7, 0.2, 1.0), -Vec3::Z);
        let hit = closest_hit(&nodes, &tris, &[], &[], &[], 0, &ray, 0.0, f32::INFINITY).expect("hit");
        assert!((hit.t - 1.0).abs() < 1e-6 && hit.triangle >= 2);
    }
}
