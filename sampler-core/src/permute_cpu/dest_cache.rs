//! The per-frame cache of where each seed goes: for each of the `(W/B)^2`
//! tile windows a block can read, and each dither rank `k`, the offset from
//! the block's origin of the pixel of rank `k` plus that pixel's retarget
//! offset (see the [module docs](super)).

use super::{block_ranks, MAX_CACHED_TILE};
use crate::dither::tile_texel;
use crate::layout::FrameParams;
use crate::retarget::{unpack_offset, RetargetTable};
use crate::walk::walk_offset;
use glam::UVec2;

/// Entries of the cache: one per texel of the largest cached tile.
const ENTRIES: usize = (MAX_CACHED_TILE * MAX_CACHED_TILE) as usize;

/// Destinations of one frame, for block side `B`.
pub(super) struct DestCache {
    /// `offsets[class * N + k]`: 2D offset from the block origin (for blocks
    /// whose destinations may wrap around the padded frame).
    pub offsets: [(i8, i8); ENTRIES],
    /// For blocks whose destinations cannot wrap, the same destinations as
    /// seed-index offsets `dy * padded_width + dx`, sorted in increasing
    /// order within each class: `ascending[class * N + j]` is the `j`-th
    /// smallest. Storing a block's seeds in this order rather than in pixel
    /// order measured faster (BENCHMARKS.md, issue 18).
    pub ascending: [i32; ENTRIES],
    /// `ascending_rank[class * N + j]`: the intensity rank whose seed goes to
    /// `ascending[class * N + j]`.
    pub ascending_rank: [u8; ENTRIES],
    /// Smallest offset over both axes and all entries (`>= -RETARGET_RADIUS`
    /// for a valid table).
    pub lo: i32,
    /// Largest offset over both axes and all entries
    /// (`< B + RETARGET_RADIUS`).
    pub hi: i32,
}

impl DestCache {
    /// Fills the cache for frame `params.frame` (`N = B * B`; `B` must divide
    /// the tile side, which is `MIN_CACHED_TILE..=MAX_CACHED_TILE`).
    #[inline(always)]
    pub fn fill<const B: u32, const N: usize>(
        &mut self,
        params: &FrameParams,
        tile: &[u32],
        table: RetargetTable<'_>,
    ) {
        let log2 = params.tile_log2;
        let classes = (1u32 << log2) / B;
        let b_log2 = B.trailing_zeros();
        let offset = walk_offset(params.frame, log2);
        let packed = table.packed();
        let pw = params.padded_width as i32;
        let (mut lo, mut hi) = (0i32, B as i32 - 1);
        for cy in 0..classes {
            for cx in 0..classes {
                // Dither ranks (value, then index: the sorting pass's order),
                // inverted into the pixel of each rank.
                let mut texels = [0u32; N];
                for (i, t) in texels.iter_mut().enumerate() {
                    let i = i as u32;
                    *t = tile_texel(
                        UVec2::new(cx * B + (i & (B - 1)), cy * B + (i >> b_log2)),
                        offset,
                        log2,
                    );
                }
                let values: [u32; N] = core::array::from_fn(|i| tile[texels[i] as usize]);
                let ranks = block_ranks(&values);
                let mut pixel_of_rank = [0u32; N];
                for (i, &r) in ranks.iter().enumerate() {
                    pixel_of_rank[r as usize & (N - 1)] = i as u32;
                }
                let base = ((cy * classes + cx) as usize) * N;
                let mut linear = [0i32; N];
                for (k, &j) in pixel_of_rank.iter().enumerate() {
                    let (jx, jy) = (j & (B - 1), j >> b_log2);
                    let d = unpack_offset(packed[texels[j as usize] as usize]);
                    let (ox, oy) = (jx as i32 + d.x, jy as i32 + d.y);
                    lo = lo.min(ox).min(oy);
                    hi = hi.max(ox).max(oy);
                    self.offsets[base + k] = (ox as i8, oy as i8);
                    linear[k] = oy * pw + ox;
                }
                // Ranks in increasing order of destination (destinations of
                // one block are distinct: the retarget map is a bijection).
                let mut order: [u8; N] = core::array::from_fn(|k| k as u8);
                order.sort_unstable_by_key(|&k| linear[k as usize]);
                for (j, &k) in order.iter().enumerate() {
                    self.ascending[base + j] = linear[k as usize];
                    self.ascending_rank[base + j] = k;
                }
            }
        }
        self.lo = lo;
        self.hi = hi;
    }

    /// An empty cache, to [`fill`](Self::fill).
    #[inline(always)]
    pub fn new() -> Self {
        DestCache {
            offsets: [(0, 0); ENTRIES],
            ascending: [0; ENTRIES],
            ascending_rank: [0; ENTRIES],
            lo: 0,
            hi: 0,
        }
    }
}
