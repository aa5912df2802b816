//! One block's groups and grouped sort, with the work the usual split
//! block needs rather than all pairs: identical results to
//! [`block_groups`](crate::feature_permute::block_groups) and
//! [`sort_block_grouped`](crate::feature_permute::sort_block_grouped).

use crate::features::{same_surface, FeatureThresholds, SurfaceFeature, NO_SURFACE};
use crate::sort::MAX_BLOCK_PIXELS;

/// The connected components of `feats[..n]` under [`same_surface`], each
/// labelled by its smallest index (as `block_groups` labels them), grown
/// one component at a time from its smallest unassigned pixel. A member
/// is only compared with unassigned pixels of the component's id (other
/// ids are never the same surface), and a component stops growing when
/// none is left: about `n` tests for a block on two surfaces instead of
/// `n (n - 1) / 2`. Returns whether the block is one group.
#[inline]
pub(super) fn groups_of(
    n: usize,
    feats: &[SurfaceFeature; MAX_BLOCK_PIXELS],
    thresholds: &FeatureThresholds,
    groups: &mut [u32; MAX_BLOCK_PIXELS],
) -> bool {
    let all: u64 = if n >= 64 { u64::MAX } else { (1u64 << n) - 1 };
    let mut assigned: u64 = 0;
    let mut components = 0;
    while assigned != all {
        let root = (!assigned & all).trailing_zeros() as usize;
        components += 1;
        let id = feats[root].id;
        assigned |= 1 << root;
        groups[root] = root as u32;
        // Unassigned pixels that may still join: those with the root's id.
        let mut candidates = 0u64;
        let mut rest = !assigned & all;
        while rest != 0 {
            let j = rest.trailing_zeros() as usize;
            rest &= rest - 1;
            candidates |= ((feats[j].id == id) as u64) << j;
        }
        let mut frontier = 1u64 << root;
        while frontier != 0 && candidates != 0 {
            let m = frontier.trailing_zeros() as usize;
            frontier &= frontier - 1;
            let mut look = candidates;
            while look != 0 {
                let j = look.trailing_zeros() as usize;
                look &= look - 1;
                if same_surface_fast(&feats[j], &feats[m], thresholds) {
                    candidates &= !(1 << j);
                    assigned |= 1 << j;
                    frontier |= 1 << j;
                    groups[j] = root as u32;
                }
            }
        }
    }
    components <= 1
}

/// Rank of each of `values[..n]` in the order (value, index).
#[inline(always)]
fn ranks_of(n: usize, values: &[u32; MAX_BLOCK_PIXELS]) -> [u32; MAX_BLOCK_PIXELS] {
    let mut ranks = [0u32; MAX_BLOCK_PIXELS];
    for i in 0..n {
        let vi = values[i];
        let mut r = 0u32;
        for (j, &vj) in values[..n].iter().enumerate() {
            r += ((vj < vi) | ((vj == vi) & (j < i))) as u32;
        }
        ranks[i] = r;
    }
    ranks
}

/// Rank of each of `values[..n]` (all distinct).
#[inline(always)]
fn ranks_distinct(n: usize, values: &[u32; MAX_BLOCK_PIXELS]) -> [u32; MAX_BLOCK_PIXELS] {
    let mut ranks = [0u32; MAX_BLOCK_PIXELS];
    for i in 0..n {
        let vi = values[i];
        ranks[i] = values[..n].iter().map(|&vj| (vj < vi) as u32).sum();
    }
    ranks
}

/// [`sort_block_grouped`](crate::feature_permute::sort_block_grouped) of
/// `n` pixels: `out[j]` is the seed that moves to pixel `j`. Ranks by
/// (group, key, index) are ranks by (group, rank by (key, index)), which
/// pack into one distinct `u32` (group `< 64` above 8 bits of rank).
#[allow(clippy::needless_range_loop)]
#[inline]
pub(super) fn sort_grouped(
    n: usize,
    groups: &[u32; MAX_BLOCK_PIXELS],
    keys: &[u32; MAX_BLOCK_PIXELS],
    dither: &[u32; MAX_BLOCK_PIXELS],
    seeds: &[u32; MAX_BLOCK_PIXELS],
    out: &mut [u32; MAX_BLOCK_PIXELS],
) {
    let (rk, rd) = (ranks_of(n, keys), ranks_of(n, dither));
    let mut ck = [0u32; MAX_BLOCK_PIXELS];
    let mut cd = [0u32; MAX_BLOCK_PIXELS];
    for i in 0..n {
        ck[i] = (groups[i] << 8) | rk[i];
        cd[i] = (groups[i] << 8) | rd[i];
    }
    let (gk, gd) = (ranks_distinct(n, &ck), ranks_distinct(n, &cd));
    let mut position_of_rank = [0u32; MAX_BLOCK_PIXELS];
    for j in 0..n {
        position_of_rank[gd[j] as usize & (MAX_BLOCK_PIXELS - 1)] = j as u32;
    }
    for i in 0..n {
        out[position_of_rank[gk[i] as usize & (MAX_BLOCK_PIXELS - 1)] as usize] = seeds[i];
    }
}

/// [`same_surface`], identical result, with the usual case inlined: equal
/// ids and equal normal encodings (a flat face) need only the depth test;
/// other normals take [`same_surface`] itself.
#[inline(always)]
pub(super) fn same_surface_fast(
    a: &SurfaceFeature,
    b: &SurfaceFeature,
    thresholds: &FeatureThresholds,
) -> bool {
    if a.id != b.id {
        return false;
    }
    if a.id == NO_SURFACE {
        return true;
    }
    if a.normal != b.normal {
        return same_surface(a, b, thresholds);
    }
    let larger = if a.depth > b.depth { a.depth } else { b.depth };
    // `libm::fabsf`, as `same_surface` computes it: the sign bit cleared.
    let difference = f32::from_bits((a.depth - b.depth).to_bits() & 0x7FFF_FFFF);
    difference <= thresholds.depth_relative * larger
}
