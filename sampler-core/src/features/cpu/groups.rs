//! One block's groups and grouped sort, with the work the usual split
//! block needs rather than all pairs: identical results to
//! [`block_groups`](crate::features::permute::block_groups) and
//! [`sort_block_grouped`](crate::features::permute::sort_block_grouped).

#[cfg(doc)]
use crate::features::surface::same_surface;
use crate::features::surface::{decode_normal, FeatureThresholds, SurfaceFeature, NO_SURFACE};
use crate::permutation::sort::MAX_BLOCK_PIXELS;

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
    test: &mut SurfaceTest<'_>,
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
                if test.same(&feats[j], &feats[m]) {
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

/// [`sort_block_grouped`](crate::features::permute::sort_block_grouped) of
/// `n` pixels: `out[j]` is the seed that moves to pixel `j`. Ranks by
/// (group, key, index) are ranks by (group, rank by (key, index)), which
/// pack into one distinct `u32` (group `< 64` above 8 bits of rank).
#[allow(clippy::needless_range_loop)]
#[inline(always)]
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

/// Entries of [`SurfaceTest`]'s memo of normal pairs (a power of two).
const MEMO: usize = 64;

/// [`same_surface`] with an identical result, faster on the usual pairs:
/// the id and depth tests inlined, equal normal encodings (a flat face)
/// accepted at once, and the outcome of decoding two different normals
/// remembered per pair of encodings (a frame has few: a crease's two
/// faces, a box's six), in a small direct-mapped memo. The normal test is a
/// pure function of the two encodings and `normal_cos`, so a remembered
/// outcome is the outcome.
pub(super) struct SurfaceTest<'a> {
    thresholds: &'a FeatureThresholds,
    /// `(a.normal, b.normal)` of each remembered pair; `(0, 0)` (equal
    /// encodings, never looked up) marks an empty entry.
    pairs: [u64; MEMO],
    /// Whether the pair's normals are within `normal_cos`.
    within: [bool; MEMO],
}

impl<'a> SurfaceTest<'a> {
    /// An empty memo for `thresholds`.
    #[inline]
    pub fn new(thresholds: &'a FeatureThresholds) -> Self {
        SurfaceTest {
            thresholds,
            pairs: [0; MEMO],
            within: [false; MEMO],
        }
    }

    /// The thresholds' `depth_relative`.
    #[inline(always)]
    pub fn depth_relative(&self) -> f32 {
        self.thresholds.depth_relative
    }

    /// `same_surface(a, b, thresholds)`.
    #[inline(always)]
    pub fn same(&mut self, a: &SurfaceFeature, b: &SurfaceFeature) -> bool {
        if a.id != b.id {
            return false;
        }
        if a.id == NO_SURFACE {
            return true;
        }
        let larger = if a.depth > b.depth { a.depth } else { b.depth };
        // `libm::fabsf`, as `same_surface` computes it: the sign bit cleared.
        let difference = f32::from_bits((a.depth - b.depth).to_bits() & 0x7FFF_FFFF);
        // Written as `same_surface` writes it, so that NaN depths fail.
        let close = difference <= self.thresholds.depth_relative * larger;
        if !close {
            return false;
        }
        a.normal == b.normal || self.normals_within(a.normal, b.normal)
    }

    /// `decode_normal(a).dot(decode_normal(b)) >= normal_cos`, remembered.
    #[inline(never)]
    fn normals_within(&mut self, a: u32, b: u32) -> bool {
        let pair = (a as u64) << 32 | b as u64;
        let slot = (pair.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 58) as usize & (MEMO - 1);
        if self.pairs[slot] == pair {
            return self.within[slot];
        }
        let within = decode_normal(a).dot(decode_normal(b)) >= self.thresholds.normal_cos;
        self.pairs[slot] = pair;
        self.within[slot] = within;
        within
    }
}
