//! BVH construction with obvhs 0.4 and conversion to the kernels' node form.
//!
//! `build_bvh2_from_tris` with `BvhBuildParams::medium_build()` (PLOC,
//! reinsertion, leaves of up to 8 triangles, no pre-splitting, so
//! `primitive_indices` is a permutation of the input triangles). Nodes are
//! converted to [`BvhNodeGpu`]; the caller reorders triangles by
//! [`BvhGpu::primitive_indices`] so leaves index them directly.
//!
//! Preset: measured with `cargo bench -p gpu-tracer --bench scale` (2-thread
//! AMD EPYC VM, obvhs without its `parallel` feature, so single-threaded):
//! on 244k triangles `medium_build` takes 0.14-0.17 s (1.15M: about 0.95 s),
//! `fast_build` about 10-20 % less and `very_fast_build` about 40 % less
//! but with 1-4 % more box tests per ray; `slow_build` 2.7x longer. The
//! build is far inside the 1 s budget for 200k triangles and tracing
//! dominates any render of more than a few dozen frames, so `medium_build`
//! is kept at every size.
//!
//! Depth: the kernels' traversal stack holds [`STACK_SIZE`] entries, so no
//! leaf may be deeper than that. PLOC trees are not balanced: on that
//! 244k-triangle scene the leaves sit at depth 14-30 (median 19) and the
//! deepest reach 30-32 from 244k to 1.15M triangles, at the limit (the
//! `fastest_build` preset, one triangle per leaf, exceeds it). When the tree
//! is too deep, `limit_depth` rebalances the smallest subtrees that must
//! change, so large scenes load instead of failing with
//! [`Error::BvhTooDeep`].

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
/// A tree deeper than [`STACK_SIZE`] (the most the kernels' traversal stack
/// handles) is rewritten by `limit_depth` to fit.
///
/// # Errors
/// [`Error::NoTriangles`] when `triangles` is empty; [`Error::BvhTooDeep`]
/// when even a balanced tree over the leaves would be deeper than
/// [`STACK_SIZE`] (more than `2^STACK_SIZE` leaves, beyond
/// `crate::scene::MAX_TRIANGLES`).
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

    let mut nodes: Vec<BvhNodeGpu> = bvh
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
    let mut depth = tree_depth(&nodes, primitive_indices.len());
    if depth > STACK_SIZE {
        nodes = limit_depth(&nodes, STACK_SIZE);
        depth = tree_depth(&nodes, primitive_indices.len());
    }
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

/// `ceil(log2(n))` for `n >= 1`: the height of a balanced binary tree with
/// `n` leaves.
fn balanced_height(n: usize) -> usize {
    n.next_power_of_two().trailing_zeros() as usize
}

/// The tree `nodes` (leaves at any depth) rewritten so that no leaf is
/// deeper than `limit`, in a fresh node array (root at 0, sibling pairs
/// adjacent, depth-first order). Leaves are kept as they are (same
/// triangle ranges, so `primitive_indices` stays valid); only the smallest
/// subtrees that must change are replaced, each by a balanced tree over its
/// leaves in their original depth-first order (spatially coherent runs, as
/// the builder clusters neighbours), with boxes recomputed from the leaves.
///
/// A subtree of `n` leaves rooted at depth `d` can be made to fit when
/// `d + ceil(log2(n)) <= limit`. Top-down: a node whose subtree already
/// fits, or whose two children can both be made to fit, is kept and its
/// children visited; otherwise the node's whole subtree is rebalanced
/// (possible, since it was only visited because it can be made to fit). The
/// root fits whenever `ceil(log2(leaves)) <= limit`; if not, the result is
/// still too deep and the caller reports it.
fn limit_depth(nodes: &[BvhNodeGpu], limit: usize) -> Vec<BvhNodeGpu> {
    // Height (deepest leaf below, leaf = 0) and leaf count of every node,
    // children before parents (reverse pre-order).
    let mut order = Vec::with_capacity(nodes.len());
    let mut stack = vec![0usize];
    while let Some(i) = stack.pop() {
        order.push(i);
        let info = nodes[i].info;
        if info.x == 0 {
            stack.push(info.y as usize);
            stack.push(info.y as usize + 1);
        }
    }
    let mut height = vec![0usize; nodes.len()];
    let mut leaves = vec![1usize; nodes.len()];
    for &i in order.iter().rev() {
        let info = nodes[i].info;
        if info.x == 0 {
            let (a, b) = (info.y as usize, info.y as usize + 1);
            height[i] = 1 + height[a].max(height[b]);
            leaves[i] = leaves[a] + leaves[b];
        }
    }
    let fits = |i: usize, depth: usize| depth + balanced_height(leaves[i]) <= limit;

    let mut out = vec![BvhNodeGpu::default()];
    // (old node, slot in `out`, depth)
    let mut work = vec![(0usize, 0usize, 0usize)];
    while let Some((old, slot, depth)) = work.pop() {
        let node = nodes[old];
        let (a, b) = (node.info.y as usize, node.info.y as usize + 1);
        let keep = node.info.x > 0
            || depth + height[old] <= limit
            || (fits(a, depth + 1) && fits(b, depth + 1))
            || !fits(old, depth);
        if !keep {
            let mut run = Vec::with_capacity(leaves[old]);
            let mut stack = vec![old];
            while let Some(i) = stack.pop() {
                let info = nodes[i].info;
                if info.x == 0 {
                    // Second child pushed first: leaves come out left to right.
                    stack.push(info.y as usize + 1);
                    stack.push(info.y as usize);
                } else {
                    run.push(i);
                }
            }
            emit_balanced(nodes, &run, slot, &mut out);
            continue;
        }
        out[slot] = node;
        if node.info.x == 0 {
            let first = out.len();
            out.extend([BvhNodeGpu::default(); 2]);
            out[slot].info.y = first as u32;
            work.push((b, first + 1, depth + 1));
            work.push((a, first, depth + 1));
        }
    }
    out
}

/// Writes a balanced tree over the leaves `run` (indices into `nodes`) to
/// `out[slot]`, appending its inner nodes' children to `out`; returns the
/// tree's box `(min, max)`.
fn emit_balanced(
    nodes: &[BvhNodeGpu],
    run: &[usize],
    slot: usize,
    out: &mut Vec<BvhNodeGpu>,
) -> (Vec3, Vec3) {
    if let [leaf] = run {
        out[slot] = nodes[*leaf];
        return (nodes[*leaf].min.truncate(), nodes[*leaf].max.truncate());
    }
    let first = out.len();
    out.extend([BvhNodeGpu::default(); 2]);
    let mid = run.len() / 2;
    let (min_a, max_a) = emit_balanced(nodes, &run[..mid], first, out);
    let (min_b, max_b) = emit_balanced(nodes, &run[mid..], first + 1, out);
    let (min, max) = (min_a.min(min_b), max_a.max(max_b));
    out[slot] = BvhNodeGpu {
        min: min.extend(0.0),
        max: max.extend(0.0),
        info: UVec4::new(0, first as u32, 0, 0),
    };
    (min, max)
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
        check_against_brute_force(&input, &bvh, &mut rng);
    }

    /// Closest and any hit through `bvh` equal brute force over `input` for
    /// random rays.
    fn check_against_brute_force(input: &[[Vec3; 3]], bvh: &BvhGpu, rng: &mut Rng) {
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
            let fast = closest_hit(&bvh.nodes, &tris, &[], &[], &[], 0, &ray, 0.0, t_max);
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
            assert_eq!(
                any_hit(&bvh.nodes, &tris, &[], &[], &[], 0, &ray, 0.0, t_max),
                brute.is_some()
            );
        }
        assert!(hits > 300, "too few hits to be a meaningful test: {hits}");
    }

    /// Leaf ranges `(first, count)` of a tree, sorted.
    fn leaf_ranges(nodes: &[BvhNodeGpu]) -> Vec<(u32, u32)> {
        let mut out = Vec::new();
        let mut stack = vec![0usize];
        while let Some(i) = stack.pop() {
            let info = nodes[i].info;
            if info.x == 0 {
                stack.extend([info.y as usize, info.y as usize + 1]);
            } else {
                out.push((info.y, info.x));
            }
        }
        out.sort_unstable();
        out
    }

    #[test]
    fn depth_limit_rebalances_only_what_it_must() {
        let mut rng = Rng(7, 0);
        // Clustered soup of very different triangle sizes: a deep tree.
        let mut input = soup(3000, &mut rng);
        for (i, t) in input.iter_mut().enumerate().filter(|(i, _)| i % 3 == 0) {
            let s = 1e-3 * (1 + i % 97) as f32;
            *t = [t[0], t[0] + Vec3::X * s, t[0] + Vec3::Y * s];
        }
        let full = build_bvh(&input).expect("bvh");
        let leaves = leaf_ranges(&full.nodes).len();
        assert!(
            full.depth > balanced_height(leaves) + 2,
            "test tree too shallow: {}",
            full.depth
        );
        // A limit above the depth changes nothing but the order of nodes.
        let same = limit_depth(&full.nodes, full.depth);
        assert_eq!(same.len(), full.nodes.len());
        assert_eq!(tree_depth(&same, input.len()), full.depth);
        for limit in [
            full.depth - 1,
            balanced_height(leaves) + 1,
            balanced_height(leaves),
        ] {
            let nodes = limit_depth(&full.nodes, limit);
            let depth = tree_depth(&nodes, input.len());
            assert!(depth <= limit, "limit {limit}: depth {depth}");
            assert_eq!(
                nodes.len(),
                full.nodes.len(),
                "a binary tree over the same leaves"
            );
            assert_eq!(leaf_ranges(&nodes), leaf_ranges(&full.nodes));
            let limited = BvhGpu {
                nodes,
                primitive_indices: full.primitive_indices.clone(),
                depth,
            };
            check_against_brute_force(&input, &limited, &mut rng);
        }
        // Below a balanced tree's height no tree fits: the caller reports it.
        let nodes = limit_depth(&full.nodes, balanced_height(leaves) - 1);
        assert!(tree_depth(&nodes, input.len()) >= balanced_height(leaves));
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
