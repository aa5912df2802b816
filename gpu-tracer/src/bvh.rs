//! BVH construction with obvhs 0.4 and conversion to the kernels' node form.
//!
//! `build_bvh2_from_tris` with `BvhBuildParams::medium_build()` (PLOC,
//! reinsertion, leaves of up to 8 triangles, no pre-splitting, so
//! `primitive_indices` is a permutation of the input triangles). Nodes are
//! converted to [`BvhNodeGpu`]; the caller reorders triangles by
//! [`BvhGpu::primitive_indices`] so leaves index them directly.

use crate::error::{Error, Result};
use glam::{UVec4, Vec3};
use kernels::abi::BvhNodeGpu;
use kernels::bvh::STACK_SIZE;
use obvhs::bvh2::builder::build_bvh2_from_tris;
use obvhs::triangle::Triangle as ObvhsTriangle;
use obvhs::BvhBuildParams;
use std::time::Duration;

/// A BVH2 in the kernels' form.
#[derive(Clone, Debug, PartialEq)]
pub struct BvhGpu {
    /// Nodes, root at index 0 (see [`BvhNodeGpu`] for the encoding).
    pub nodes: Vec<BvhNodeGpu>,
    /// `primitive_indices[i]` = input triangle stored at leaf position `i`;
    /// a permutation of `0..triangle count`.
    pub primitive_indices: Vec<u32>,
    /// Depth of the deepest leaf (root = 0), `<= STACK_SIZE`.
    pub depth: usize,
}

/// Builds the BVH of `triangles` (vertices in world units, all finite).
///
/// # Errors
/// [`Error::NoTriangles`] when `triangles` is empty; [`Error::BvhTooDeep`]
/// when a leaf is deeper than [`STACK_SIZE`], the most the kernels'
/// traversal stack handles.
///
/// # Panics
/// Only on a bug in the builder: if obvhs returns a tree whose indices are
/// out of range or whose `primitive_indices` is not a permutation.
pub fn build_bvh(triangles: &[[Vec3; 3]]) -> Result<BvhGpu> {
    if triangles.is_empty() {
        return Err(Error::NoTriangles {
            path: "<scene>".into(),
        });
    }
    let tris: Vec<ObvhsTriangle> = triangles
        .iter()
        .map(|[a, b, c]| ObvhsTriangle {
            v0: (*a).into(),
            v1: (*b).into(),
            v2: (*c).into(),
        })
        .collect();
    let mut build_time = Duration::default();
    let bvh = build_bvh2_from_tris(&tris, BvhBuildParams::medium_build(), &mut build_time);

    let nodes: Vec<BvhNodeGpu> = bvh
        .nodes
        .iter()
        .map(|n| BvhNodeGpu {
            min: Vec3::from(n.aabb().min).extend(0.0),
            max: Vec3::from(n.aabb().max).extend(0.0),
            info: UVec4::new(n.prim_count, n.first_index, 0, 0),
        })
        .collect();
    let primitive_indices = bvh.primitive_indices.clone();
    let mut seen = vec![false; triangles.len()];
    assert_eq!(primitive_indices.len(), triangles.len(), "obvhs: primitive count");
    for &p in &primitive_indices {
        assert!(
            !std::mem::replace(&mut seen[p as usize], true),
            "obvhs: duplicate primitive"
        );
    }
    let depth = tree_depth(&nodes, primitive_indices.len());
    if depth > STACK_SIZE {
        return Err(Error::BvhTooDeep {
            depth,
            limit: STACK_SIZE,
        });
    }
    Ok(BvhGpu {
        nodes,
        primitive_indices,
        depth,
    })
}

/// Depth of the deepest leaf (root = 0), walking the tree with an explicit
/// stack. Checks every index against the array sizes and that no node is
/// reached twice.
fn tree_depth(nodes: &[BvhNodeGpu], primitives: usize) -> usize {
    let mut deepest = 0;
    let mut visited = 0usize;
    let mut stack = vec![(0usize, 0usize)];
    while let Some((index, depth)) = stack.pop() {
        visited += 1;
        assert!(visited <= nodes.len(), "obvhs: node visited twice (not a tree)");
        let info = nodes[index].info;
        let (count, first) = (info.x as usize, info.y as usize);
        if count == 0 {
            assert!(first + 1 < nodes.len(), "obvhs: child index");
            stack.push((first, depth + 1));
            stack.push((first + 1, depth + 1));
        } else {
            assert!(first + count <= primitives, "obvhs: leaf range");
            deepest = deepest.max(depth);
        }
    }
    deepest
}

#[cfg(test)]
mod tests {
    use super::*;
    use kernels::abi::TriangleGpu;
    use kernels::bvh::{any_hit, closest_hit};
    use kernels::intersect::{intersect_triangle, Ray};
    use sampler_core::random_f32;

    struct Rng(u32, u32);
    impl Rng {
        fn f(&mut self) -> f32 {
            self.1 += 1;
            random_f32(self.0, self.1)
        }
        fn v(&mut self, lo: f32, hi: f32) -> Vec3 {
            Vec3::new(self.f(), self.f(), self.f()) * (hi - lo) + Vec3::splat(lo)
        }
    }

    /// Random triangle soup: small triangles scattered in a cube, plus a few large ones.
    fn soup(n: usize, rng: &mut Rng) -> Vec<[Vec3; 3]> {
        (0..n)
            .map(|i| {
                let c = rng.v(-10.0, 10.0);
                let s = if i % 50 == 0 { 8.0 } else { 1.0 };
                [c + rng.v(-s, s), c + rng.v(-s, s), c + rng.v(-s, s)]
            })
            .collect()
    }

    #[test]
    fn traversal_agrees_with_brute_force() {
        let mut rng = Rng(99, 0);
        let input = soup(2000, &mut rng);
        let bvh = build_bvh(&input).expect("bvh");
        assert!(bvh.nodes.len() > 1 && bvh.depth >= 1);
        let tris: Vec<TriangleGpu> = bvh
            .primitive_indices
            .iter()
            .map(|&p| {
                let [a, b, c] = input[p as usize];
                TriangleGpu {
                    v0: a.extend(0.0),
                    v1: b.extend(0.0),
                    v2: c.extend(0.0),
                }
            })
            .collect();
        let mut hits = 0;
        for _ in 0..3000 {
            let origin = rng.v(-15.0, 15.0);
            let dir = (rng.v(-1.0, 1.0) + Vec3::splat(1e-3)).normalize();
            let ray = Ray::new(origin, dir);
            let t_max = if rng.f() < 0.3 { 5.0 } else { f32::INFINITY };
            let mut brute: Option<(f32, usize)> = None;
            for (i, [a, b, c]) in input.iter().enumerate() {
                if let Some(h) = intersect_triangle(&ray, *a, *b, *c, 0.0, t_max) {
                    if brute.is_none_or(|(t, _)| h.t < t) {
                        brute = Some((h.t, i));
                    }
                }
            }
            let fast = closest_hit(&bvh.nodes, &tris, &ray, 0.0, t_max);
            match (brute, fast) {
                (None, None) => {}
                (Some((t, i)), Some(h)) => {
                    hits += 1;
                    assert_eq!(h.t, t, "distance");
                    let got = bvh.primitive_indices[h.triangle as usize] as usize;
                    // Exact ties (equal t) may pick either triangle.
                    if got != i {
                        let [a, b, c] = input[got];
                        let other = intersect_triangle(&ray, a, b, c, 0.0, t_max).expect("hit");
                        assert_eq!(other.t, t);
                    }
                }
                (b, f) => panic!("brute force {b:?} vs BVH {f:?}"),
            }
            assert_eq!(any_hit(&bvh.nodes, &tris, &ray, 0.0, t_max), brute.is_some());
        }
        assert!(hits > 300, "too few hits to be a meaningful test: {hits}");
    }

    #[test]
    fn single_triangle_and_empty_input() {
        let bvh = build_bvh(&[[Vec3::ZERO, Vec3::X, Vec3::Y]]).expect("bvh");
        assert_eq!(bvh.primitive_indices, vec![0]);
        assert_eq!(bvh.depth, 0);
        assert_eq!(bvh.nodes[0].info.x, 1);
        assert!(matches!(build_bvh(&[]), Err(Error::NoTriangles { .. })));
    }
}
