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

use crate::abi::{BvhNodeGpu, TriangleGpu};
use crate::intersect::{intersect_aabb, intersect_triangle, Ray};

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

/// Closest triangle the ray meets at a distance in `(t_min, t_max)`, or
/// `None`. Ties in distance go to the triangle tested first.
#[inline]
pub fn closest_hit(
    nodes: &[BvhNodeGpu],
    triangles: &[TriangleGpu],
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<Hit> {
    traverse(nodes, triangles, ray, t_min, t_max, false)
}

/// Whether any triangle meets the ray at a distance in `(t_min, t_max)`
/// (shadow-ray visibility test; stops at the first hit found).
#[inline]
pub fn any_hit(nodes: &[BvhNodeGpu], triangles: &[TriangleGpu], ray: &Ray, t_min: f32, t_max: f32) -> bool {
    traverse(nodes, triangles, ray, t_min, t_max, true).is_some()
}

/// Shared traversal: with `stop_at_first` the first hit found is returned,
/// otherwise the closest.
#[inline]
fn traverse(
    nodes: &[BvhNodeGpu],
    triangles: &[TriangleGpu],
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
        let hit = closest_hit(&nodes, &tris, &down, 0.0, f32::INFINITY).expect("hit");
        assert!((hit.t - 5.0).abs() < 1e-5);
        assert!(hit.triangle >= 2);
        let up = Ray::new(Vec3::new(0.3, 0.6, -5.0), Vec3::Z);
        let hit = closest_hit(&nodes, &tris, &up, 0.0, f32::INFINITY).expect("hit");
        assert!((hit.t - 3.0).abs() < 1e-5);
        assert!(hit.triangle < 2);
        // Between the planes going down: only the lower one, and t_max can exclude it.
        let mid = Ray::new(Vec3::new(0.3, 0.6, -1.0), -Vec3::Z);
        assert!((closest_hit(&nodes, &tris, &mid, 0.0, 10.0).expect("hit").t - 1.0).abs() < 1e-5);
        assert_eq!(closest_hit(&nodes, &tris, &mid, 0.0, 0.9), None);
        assert!(!any_hit(&nodes, &tris, &mid, 0.0, 0.9));
        assert!(any_hit(&nodes, &tris, &mid, 0.0, 1.1));
        // Missing the root box.
        let away = Ray::new(Vec3::new(3.0, 0.5, 5.0), -Vec3::Z);
        assert_eq!(closest_hit(&nodes, &tris, &away, 0.0, f32::INFINITY), None);
    }

    #[test]
    fn single_leaf_root() {
        let (_, tris) = two_planes();
        let nodes = vec![node(Vec3::new(0.0, 0.0, -2.0), Vec3::new(1.0, 1.0, 0.0), 4, 0)];
        let ray = Ray::new(Vec3::new(0.7, 0.2, 1.0), -Vec3::Z);
        let hit = closest_hit(&nodes, &tris, &ray, 0.0, f32::INFINITY).expect("hit");
        assert!((hit.t - 1.0).abs() < 1e-6 && hit.triangle >= 2);
    }
}
