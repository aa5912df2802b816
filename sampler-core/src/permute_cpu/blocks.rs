//! The fast path's loop over the block rows of one band: ranks
//! [`LaneRanker::LANES`] full blocks at a time and scatters their seeds
//! through the [`DestCache`]; clipped edge blocks take
//! [`permute_block_in_band`].

use super::dest_cache::DestCache;
use super::edge::permute_block_in_band;
use super::{
    block_ranks, prefetch, signed_key, wrap, Band, LaneRanker, Strips, LINE_SEEDS, MAX_LANES, PREFETCH_AHEAD,
};
use crate::layout::FrameParams;
use crate::retarget::{RetargetTable, RETARGET_RADIUS};
use crate::sort::{intensity_key, Intensity};

/// Sorting + retargeting of the seeds that land in `band`, for block side
/// `B` (`N = B * B` pixels); `seeds_out` holds the band's rows.
// Lane loops index several lane arrays at once; iterators would hide that.
#[allow(clippy::needless_range_loop, clippy::too_many_arguments)]
#[inline(always)]
pub(super) fn permute_full_blocks<T: Intensity, R: LaneRanker, const B: u32, const N: usize>(
    params: &FrameParams,
    intensities: &[T],
    tile: &[u32],
    table: RetargetTable<'_>,
    seeds_in: &[u32],
    band: Band,
    seeds_out: &mut [u32],
) {
    let mut cache = DestCache::new();
    cache.fill::<B, N>(params, tile, table);
    let (lo, hi) = (cache.lo, cache.hi);
    let classes = (1u32 << params.tile_log2) / B;
    let (pw, ph) = (params.padded_width, params.padded_height);
    debug_assert_eq!(seeds_out.len(), ((band.row_end - band.row0) * pw) as usize);
    let lanes = R::LANES;
    let full_x = params.width / B; // blocks fully inside the visible frame
    let full_y = params.height / B;
    // Blocks whose destinations cannot wrap: every cached offset, on each
    // axis, lies in `lo..=hi` (measured above, not assumed), so the block
    // origin plus any offset stays inside the padded frame.
    debug_assert!(-lo <= RETARGET_RADIUS && hi < B as i32 + RETARGET_RADIUS);
    let (before, after) = ((-lo) as u32, (hi + 1) as u32);
    let interior_x = |x0: u32| x0 >= before && x0 + after <= pw;
    let w = params.width as usize;
    let pws = pw as usize;
    // Index in the padded frame of `seeds_out[0]`.
    let band_start = band.row0 as isize * pws as isize;
    // A lane group's keys and ranks, reused by every group (each writes the
    // entries it reads).
    let mut strips: Strips = [[0; MAX_LANES * super::MAX_FAST_BLOCK]; super::MAX_FAST_BLOCK];
    let mut ranks = [[0u32; MAX_LANES]; N];
    for rows in band.source_block_rows(params, RETARGET_RADIUS) {
        for by in rows {
            let y0 = by * B;
            // Every destination row of this block row lies in the band, and
            // none wraps: its interior blocks store unchecked.
            let rows_inside = y0 >= before
                && y0 + after <= ph
                && y0 as i32 + lo >= band.row0 as i32
                && y0 as i32 + hi < band.row_end as i32;
            // No destination of this block row wraps vertically: for its
            // blocks with `interior_x`, a destination lies in the band
            // exactly when its index in `seeds_out` is in range.
            let rows_plain = y0 >= before && y0 + after <= ph;
            let class_row = ((by & (classes - 1)) * classes) as usize;
            let mut bx = 0u32;
            if by < full_y {
                // `lanes` full blocks at a time, one block per vector lane.
                while bx + lanes as u32 <= full_x {
                    let x_start = (bx * B) as usize;
                    // Convert each strip row in memory order (vectorises);
                    // the ranker transposes the strips into lanes.
                    for (r, strip) in strips.iter_mut().enumerate().take(B as usize) {
                        let at = (y0 as usize + r) * w + x_start;
                        let row = &intensities[at..at + lanes * B as usize];
                        for (k, v) in strip.iter_mut().zip(row) {
                            *k = signed_key(v.intensity());
                        }
                    }
                    // The output rows no earlier block row has written
                    // (`y0 + hi - B + 1 ..= y0 + hi`) arrive from memory on
                    // the first store: ask for them a few groups ahead.
                    let first = (y0 as i32 + hi + 1 - B as i32).max(band.row0 as i32);
                    for r in first..=(y0 as i32 + hi).min(band.row_end as i32 - 1) {
                        let at = (r as usize - band.row0 as usize) * pws + x_start + PREFETCH_AHEAD;
                        prefetch(seeds_out, at, true);
                        prefetch(seeds_out, at + LINE_SEEDS, true);
                    }
                    // The block row's input rows, as far ahead (the read
                    // streams plus the output rows are more than the hardware
                    // prefetchers follow).
                    for r in 0..B as usize {
                        let at = (y0 as usize + r) * pws + x_start + PREFETCH_AHEAD;
                        prefetch(seeds_in, at, false);
                        prefetch(seeds_in, at + LINE_SEEDS, false);
                        let at = (y0 as usize + r) * w + x_start + PREFETCH_AHEAD;
                        prefetch(intensities, at, false);
                        prefetch(intensities, at + LINE_SEEDS, false);
                    }
                    R::rank_strips::<B, N>(&strips, &mut ranks);
                    let last_x0 = (bx + lanes as u32 - 1) * B;
                    let group_inside = rows_inside && interior_x(bx * B) && interior_x(last_x0);
                    for l in 0..lanes {
                        let b = bx + l as u32;
                        let x0 = b * B;
                        let class = (class_row + (b & (classes - 1)) as usize) * N;
                        let origin = y0 as usize * pws + x0 as usize;
                        // Index in `seeds_out` of the block's origin (may be
                        // negative for a block above the band).
                        let out_origin = origin as isize - band_start;
                        if group_inside || (rows_inside && interior_x(x0)) {
                            // Seeds read straight from the input rows into
                            // intensity-rank order, then stored in increasing
                            // order of destination (faster than pixel order).
                            let mut by_rank = [0u32; N];
                            let src = seeds_in[origin..].as_ptr();
                            debug_assert!(origin + (B as usize - 1) * (pws + 1) < seeds_in.len());
                            for r in 0..B as usize {
                                for c in 0..B as usize {
                                    let rank = ranks[r * B as usize + c][l] as usize & (N - 1);
                                    // SAFETY: the block lies inside the
                                    // visible frame (`b < full_x`,
                                    // `by < full_y`), so its `B` rows of `B`
                                    // seeds are inside `seeds_in`
                                    // (`padded_width * padded_height`,
                                    // checked by the caller).
                                    by_rank[rank] = unsafe { *src.add(r * pws + c) };
                                }
                            }
                            let dest = &cache.ascending[class..class + N];
                            let rank_of = &cache.ascending_rank[class..class + N];
                            let out = seeds_out.as_mut_ptr();
                            for j in 0..N {
                                let at = (out_origin + dest[j] as isize) as usize;
                                debug_assert!(at < seeds_out.len());
                                // SAFETY: `rows_inside` and `interior_x(x0)`
                                // hold, so with `lo <= dx, dy <= hi` the
                                // destination is inside the band's rows,
                                // which `seeds_out` holds.
                                unsafe { *out.add(at) = by_rank[rank_of[j] as usize & (N - 1)] };
                            }
                        } else if rows_plain && interior_x(x0) {
                            // A halo block of a band: same, dropping the
                            // destinations outside the band.
                            let by_rank = seeds_by_rank::<N>(
                                core::array::from_fn(|i| ranks[i][l]),
                                core::array::from_fn(|i| {
                                    seeds_in[origin + i / B as usize * pws + i % B as usize]
                                }),
                            );
                            store_ascending_in_band::<N>(&cache, class, out_origin, by_rank, seeds_out);
                        } else {
                            scatter_block_in_band::<B, N>(
                                params,
                                x0,
                                y0,
                                band,
                                &cache.offsets[class..class + N],
                                core::array::from_fn(|i| ranks[i][l]),
                                core::array::from_fn(|i| {
                                    seeds_in[origin + i / B as usize * pws + i % B as usize]
                                }),
                                seeds_out,
                            );
                        }
                    }
                    bx += lanes as u32;
                }
            }
            while bx < params.blocks_x() {
                if bx >= full_x || by >= full_y {
                    permute_block_in_band(
                        params,
                        bx,
                        by,
                        intensities,
                        tile,
                        table.packed(),
                        seeds_in,
                        band,
                        seeds_out,
                    );
                    bx += 1;
                    continue;
                }
                let x0 = bx * B;
                let mut block_keys = [0u32; N];
                let mut seeds = [0u32; N];
                for r in 0..B as usize {
                    let at = (y0 as usize + r) * w + x0 as usize;
                    let row = &intensities[at..at + B as usize];
                    let s_at = (y0 as usize + r) * pws + x0 as usize;
                    let s_row = &seeds_in[s_at..s_at + B as usize];
                    for c in 0..B as usize {
                        block_keys[r * B as usize + c] = intensity_key(row[c].intensity());
                        seeds[r * B as usize + c] = s_row[c];
                    }
                }
                let class = (class_row + (bx & (classes - 1)) as usize) * N;
                let ranks = block_ranks(&block_keys);
                if rows_plain && interior_x(x0) {
                    let out_origin = (y0 as usize * pws + x0 as usize) as isize - band_start;
                    let by_rank = seeds_by_rank::<N>(ranks, seeds);
                    store_ascending_in_band::<N>(&cache, class, out_origin, by_rank, seeds_out);
                } else {
                    let dest = &cache.offsets[class..class + N];
                    scatter_block_in_band::<B, N>(params, x0, y0, band, dest, ranks, seeds, seeds_out);
                }
                bx += 1;
            }
        }
    }
}

/// `seeds` (in pixel order) rearranged into the order of their `ranks`.
#[inline(always)]
fn seeds_by_rank<const N: usize>(ranks: [u32; N], seeds: [u32; N]) -> [u32; N] {
    let mut by_rank = [0u32; N];
    for (&r, &seed) in ranks.iter().zip(&seeds) {
        by_rank[r as usize & (N - 1)] = seed;
    }
    by_rank
}

/// Stores a block's seeds (`by_rank`, in intensity-rank order) whose
/// destinations cannot wrap, at `out_origin` (the block origin's index in
/// `seeds_out`, negative above the band) plus the class's ascending
/// destinations, dropping those outside `seeds_out`.
#[inline(always)]
fn store_ascending_in_band<const N: usize>(
    cache: &DestCache,
    class: usize,
    out_origin: isize,
    by_rank: [u32; N],
    seeds_out: &mut [u32],
) {
    let dest = &cache.ascending[class..class + N];
    let rank_of = &cache.ascending_rank[class..class + N];
    for j in 0..N {
        let at = (out_origin + dest[j] as isize) as usize;
        if let Some(slot) = seeds_out.get_mut(at) {
            *slot = by_rank[rank_of[j] as usize & (N - 1)];
        }
    }
}

/// Writes those of the `N` seeds of the block at `(x0, y0)` that land in
/// `band`: the seed of intensity rank `ranks[i]` goes to the block origin
/// plus `dest[rank]`, wrapped on the padded frame.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn scatter_block_in_band<const B: u32, const N: usize>(
    params: &FrameParams,
    x0: u32,
    y0: u32,
    band: Band,
    dest: &[(i8, i8)],
    ranks: [u32; N],
    seeds: [u32; N],
    seeds_out: &mut [u32],
) {
    let (pw, ph) = (params.padded_width, params.padded_height);
    for (&r, &seed) in ranks.iter().zip(&seeds) {
        let (ox, oy) = dest[r as usize & (N - 1)];
        let nx = wrap(x0 as i32 + ox as i32, pw);
        let ny = wrap(y0 as i32 + oy as i32, ph);
        if let Some(at) = band.index(pw, nx, ny) {
            seeds_out[at] = seed;
        }
    }
}
