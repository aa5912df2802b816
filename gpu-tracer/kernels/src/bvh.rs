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
use crate::trace_variant::TEXTURES;

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
    traverse_cut_outs(
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

/// [`closest_hit`] with every triangle opaque: the [`CUT_OUT`] flag is
/// ignored and no material is read. The same hit as [`closest_hit`] in a
/// scene without cut-outs, from a smaller kernel (the basic trace variant,
/// [`crate::trace`]).
#[inline]
pub fn closest_hit_opaque(
    nodes: &[BvhNodeGpu],
    triangles: &[TriangleGpu],
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<Hit> {
    let mut t = Traversal::new(nodes, ray, t_min, t_max);
    t.advance::<false>(nodes, triangles, ray, t_min, false);
    t.result()
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
    traverse_cut_outs(
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

/// [`any_hit`] with every triangle opaque (as [`closest_hit_opaque`]).
#[inline]
pub fn any_hit_opaque(
    nodes: &[BvhNodeGpu],
    triangles: &[TriangleGpu],
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> bool {
    let mut t = Traversal::new(nodes, ray, t_min, t_max);
    t.advance::<false>(nodes, triangles, ray, t_min, true);
    t.found()
}

/// [`closest_hit`] for the kernel variant of `FEATURES`
/// ([`crate::trace_variant`]): with [`TEXTURES`] cut-outs are honoured,
/// without it every triangle is opaque ([`closest_hit_opaque`]).
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn closest_hit_variant<const FEATURES: u32>(
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
    if FEATURES & TEXTURES != 0 {
        closest_hit(
            nodes,
            triangles,
            materials,
            attrs,
            images,
            image_count,
            ray,
            t_min,
            t_max,
        )
    } else {
        closest_hit_opaque(nodes, triangles, ray, t_min, t_max)
    }
}

/// [`any_hit`] for the kernel variant of `FEATURES` (as
/// [`closest_hit_variant`]).
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn any_hit_variant<const FEATURES: u32>(
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
    if FEATURES & TEXTURES != 0 {
        any_hit(
            nodes,
            triangles,
            materials,
            attrs,
            images,
            image_count,
            ray,
            t_min,
            t_max,
        )
    } else {
        any_hit_opaque(nodes, triangles, ray, t_min, t_max)
    }
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

/// Traversal honouring cut-outs: with `stop_at_first` the first surface
/// found is returned, otherwise the closest.
///
/// The cut-out test sits outside the node loop, as an any-hit stage: a hit
/// on a [`CUT_OUT`] triangle leaves the node loop
/// ([`Traversal::advance`]) as a *candidate*; its alpha is tested here, the
/// hit kept or dropped, and the traversal resumes where it left off (the
/// leaf's next triangle, then the stack). Scenes without cut-outs never
/// leave the node loop early. On SIMD back ends that run untaken branches
/// under a mask (llvmpipe runs every lane through both sides of a
/// divergent `if`), this keeps the texture lookup out of the per-triangle
/// loop: it costs once per query instead of once per triangle tested.
#[allow(clippy::too_many_arguments)]
#[inline]
fn traverse_cut_outs(
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
    let mut t = Traversal::new(nodes, ray, t_min, t_max);
    loop {
        let candidate = t.advance::<true>(nodes, triangles, ray, t_min, stop_at_first);
        if candidate.triangle == NO_NODE || (stop_at_first && t.found()) {
            break;
        }
        let tri = triangles[candidate.triangle as usize];
        if !in_hole(
            &tri,
            candidate.triangle,
            materials,
            attrs,
            images,
            image_count,
            candidate.u,
            candidate.v,
        ) {
            t.accept(candidate);
            if stop_at_first {
                break;
            }
        }
    }
    t.result()
}

/// The state of one BVH query, resumable after a cut-out candidate: the
/// closest hit so far, the node stack and the current leaf's remaining
/// triangles. `repr(C)` with 4-byte fields only, so that rust-gpu's layout
/// of this function-local struct is one naga accepts.
#[repr(C)]
struct Traversal {
    /// The closest hit accepted so far; `triangle` = [`NO_NODE`] (and `t`
    /// = the query's `t_max`) before the first.
    best: Hit,
    stack_node: [u32; STACK_SIZE],
    stack_t: [f32; STACK_SIZE],
    sp: u32,
    node_index: u32,
    /// Triangles of the current leaf still to test: `[leaf_next, leaf_end)`.
    leaf_next: u32,
    leaf_end: u32,
}

impl Traversal {
    /// A query for `ray` over `(t_min, t_max)`, at the root when the ray
    /// meets its box, finished otherwise.
    #[inline]
    fn new(nodes: &[BvhNodeGpu], ray: &Ray, t_min: f32, t_max: f32) -> Self {
        let root = nodes[0];
        let node_index = match intersect_aabb(
            ray.origin,
            ray.inv_dir(),
            root.min.truncate(),
            root.max.truncate(),
            t_min,
            t_max,
        ) {
            Some(_) => 0,
            None => NO_NODE,
        };
        Traversal {
            best: Hit {
                t: t_max,
                triangle: NO_NODE,
                u: 0.0,
                v: 0.0,
            },
            stack_node: [0u32; STACK_SIZE],
            stack_t: [0.0f32; STACK_SIZE],
            sp: 0,
            node_index,
            leaf_next: 0,
            leaf_end: 0,
        }
    }

    /// Whether a hit has been accepted.
    #[inline]
    fn found(&self) -> bool {
        self.best.triangle != NO_NODE
    }

    /// Makes `hit` the closest so far.
    #[inline]
    fn accept(&mut self, hit: Hit) {
        self.best = hit;
    }

    /// The closest hit accepted, if any.
    #[inline]
    fn result(&self) -> Option<Hit> {
        if self.found() {
            Some(self.best)
        } else {
            None
        }
    }

    /// Runs the node loop until the tree is exhausted, a hit is accepted
    /// with `stop_at_first`, or (with `CUT_OUTS`) a [`CUT_OUT`] triangle is
    /// hit: that hit is returned as a candidate for the caller to test and
    /// [`accept`](Self::accept). Returns a hit with `triangle == NO_NODE`
    /// otherwise. Opaque hits are accepted here; without `CUT_OUTS` every
    /// triangle is opaque.
    #[inline]
    fn advance<const CUT_OUTS: bool>(
        &mut self,
        nodes: &[BvhNodeGpu],
        triangles: &[TriangleGpu],
        ray: &Ray,
        t_min: f32,
        stop_at_first: bool,
    ) -> Hit {
        let inv_dir = ray.inv_dir();
        let mut candidate = Hit {
            t: 0.0,
            triangle: NO_NODE,
            u: 0.0,
            v: 0.0,
        };
        loop {
            while self.leaf_next < self.leaf_end {
                let index = self.leaf_next;
                self.leaf_next += 1;
                let tri = triangles[index as usize];
                if let Some(h) = intersect_triangle(
                    ray,
                    tri.v0.truncate(),
                    tri.v1.truncate(),
                    tri.v2.truncate(),
                    t_min,
                    self.best.t,
                ) {
                    let hit = Hit {
                        t: h.t,
                        triangle: index,
                        u: h.u,
                        v: h.v,
                    };
                    if CUT_OUTS && tri.v2.w == CUT_OUT {
                        candidate = hit;
                        break;
                    }
                    self.accept(hit);
                    if stop_at_first {
                        return candidate;
                    }
                }
            }
            if candidate.triangle != NO_NODE {
                return candidate;
            }
            if self.node_index == NO_NODE {
                if self.sp == 0 {
                    return candidate;
                }
                self.sp -= 1;
                if self.stack_t[self.sp as usize] < self.best.t {
                    self.node_index = self.stack_node[self.sp as usize];
                }
                continue;
            }
            let node = nodes[self.node_index as usize];
            let count = node.info.x;
            let first = node.info.y;
            self.node_index = NO_NODE;
            if count == 0 {
                let a = nodes[first as usize];
                let b = nodes[first.wrapping_add(1) as usize];
                let ta = intersect_aabb(
                    ray.origin,
                    inv_dir,
                    a.min.truncate(),
                    a.max.truncate(),
                    t_min,
                    self.best.t,
                );
                let tb = intersect_aabb(
                    ray.origin,
                    inv_dir,
                    b.min.truncate(),
                    b.max.truncate(),
                    t_min,
                    self.best.t,
                );
                match (ta, tb) {
                    (Some(ta), Some(tb)) => {
                        let (near, far, t_far) = if ta <= tb {
                            (first, first.wrapping_add(1), tb)
                        } else {
                            (first.wrapping_add(1), first, ta)
                        };
                        if (self.sp as usize) < STACK_SIZE {
                            self.stack_node[self.sp as usize] = far;
                            self.stack_t[self.sp as usize] = t_far;
                            self.sp += 1;
                        }
                        self.node_index = near;
                    }
                    (Some(_), None) => self.node_index = first,
                    (None, Some(_)) => self.node_index = first.wrapping_add(1),
                    (None, None) => {}
                }
            } else {
                self.leaf_next = first;
                self.leaf_end = first.wrapping_add(count);
            }
        }
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
        // One leaf holding all four triangles: the traversal resumes after
        // each dropped candidate within the leaf, whatever the order.
        let leaf = [node(Vec3::new(0.0, 0.0, -2.0), Vec3::new(1.0, 1.0, 0.0), 4, 0)];
        for order in [[0usize, 1, 2, 3], [2, 3, 0, 1], [2, 0, 3, 1]] {
            let t: Vec<TriangleGpu> = order.iter().map(|&i| tris[i]).collect();
            let a: Vec<TriangleAttrGpu> = order.iter().map(|&i| attrs[i]).collect();
            let hit = closest_hit(
                &leaf,
                &t,
                &materials,
                &a,
                &images,
                1,
                &down(0.75),
                0.0,
                f32::INFINITY,
            );
            assert_eq!(hit.map(|h| h.t), Some(7.0), "order {order:?}");
            assert!(!any_hit(
                &leaf,
                &t,
                &materials,
                &a,
                &images,
                1,
                &down(0.75),
                0.0,
                6.0
            ));
            assert!(any_hit(
                &leaf,
                &t,
                &materials,
                &a,
                &images,
                1,
                &down(0.75),
                0.0,
                8.0
            ));
        }
        // Unflagged triangles are not tested (opaque).
        let (_, opaque) = two_planes();
        assert_eq!(closest(&materials, &opaque, 0.25), Some(5.0));
        // The opaque queries ignore the flag: the hole is a surface again.
        let ray = down(0.25);
        assert_eq!(
            closest_hit_opaque(&nodes, &tris, &ray, 0.0, f32::INFINITY).map(|h| h.t),
            Some(5.0)
        );
        assert!(any_hit_opaque(&nodes, &tris, &ray, 0.0, 6.0));
    }

    #[test]
    fn single_leaf_root() {
        let (_, tris) = two_planes();
        let nodes = vec![node(Vec3::new(0.0, 0.0, -2.0), Vec3::new(1.0, 1.0, 0.0), 4, 0)];
        let ray = Ray::new(Vec3::new(0.7, 0.2, 1.0), -Vec3::Z);
        let hit = closest_hit(&nodes, &tris, &[], &[], &[], 0, &ray, 0.0, f32::INFINITY).expect("hit");
        assert!((hit.t - 1.0).abs() < 1e-6 && hit.triangle >= 2);
        assert_eq!(
            closest_hit_opaque(&nodes, &tris, &ray, 0.0, f32::INFINITY),
            Some(hit)
        );
    }
}
