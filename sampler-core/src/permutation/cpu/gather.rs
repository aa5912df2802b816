//! The gathered fast path: blocks are ranked into a ring of the last
//! `2 reach + 1` block rows, each block's sorted seeds kept as one
//! `N`-seed line indexed by the dither rank of the pixel that holds them,
//! and each output row is then written in order, every output pixel
//! fetching its seed from the ring through the inverse of the retarget
//! table ([`SourceCache`]). The stores are sequential; the loads are
//! scattered within a ring that stays in the L2 cache, at addresses that
//! depend on the tables only.
//!
//! The ring is a stack array of [`RING_SEEDS`] seeds. Frames too wide for
//! it are cut into column strips of whole tile periods, each with its own
//! ring: a strip also ranks the `reach` block columns on each side of it
//! (across the frame's sides, the other end of the row): with 4x4 blocks
//! 4 more block columns per strip of at least 304, at most 1.3% more
//! blocks ranked.

use super::ranker::GroupSeeds;
use super::{block_ranks, prefetch_span, signed_key, Band, LaneRanker, Strips, MAX_CACHED_TILE};
use super::{MAX_FAST_BLOCK, MAX_LANES, PREFETCH_AHEAD};
use crate::permutation::dither::tile_texel;
use crate::permutation::layout::FrameParams;
use crate::permutation::retarget::{unpack_offset, RetargetTable, RETARGET_RADIUS};
use crate::permutation::sort::{intensity_key, sort_block, Intensity, MAX_BLOCK_PIXELS};
use crate::sequences::walk::walk_offset;
use core::ops::Range;
use glam::UVec2;

/// Entries of the source cache: one per texel of the largest cached tile.
const ENTRIES: usize = (MAX_CACHED_TILE * MAX_CACHED_TILE) as usize;

/// Seeds the ring holds (192 KiB, on the stack): `2 reach + 1` block rows
/// of a strip's `strip + 2 reach` lines of `B * B` seeds. One strip covers
/// a padded width of up to 3498 (B = 2: 7 rows of `2 pw + 24`), 2441 (B =
/// 4: 5 rows of `4 pw + 64`) or 2032 (B = 8: 3 rows of `8 pw + 128`)
/// seeds; wider frames take more strips ([`strip_periods`]).
pub(super) const RING_SEEDS: usize = 48 * 1024;

/// The ring's storage, aligned so that each block's line of 16 seeds
/// (4x4 blocks) is one cache line: one store writes it, and the output's
/// loads of a line touch one cache line, not two.
#[repr(C, align(64))]
struct Ring([u32; RING_SEEDS]);

/// Block rows (and columns) a seed can move: `ceil(RETARGET_RADIUS / B)`.
#[inline(always)]
const fn reach(block: u32) -> u32 {
    (RETARGET_RADIUS as u32).div_ceil(block)
}

/// Where each output pixel's seed comes from, for one frame.
pub(super) struct SourceCache {
    /// For output pixel `(x, y)` (screen position mod `W`, row-major):
    /// `(dby + reach) << 16 | ((x / B + dbx + reach) * N + k)`: the seed
    /// comes from the block `(dbx, dby)` blocks away from the output
    /// pixel's block, where it is the `k`-th in dither-rank order.
    source: [u32; ENTRIES],
    /// `rank_of_pixel[class * N + i]`: the dither rank of pixel `i` in
    /// window class `class`.
    rank_of_pixel: [u8; ENTRIES],
}

impl SourceCache {
    /// An empty cache, to [`fill`](Self::fill).
    #[inline(always)]
    pub fn new() -> Self {
        SourceCache {
            source: [0; ENTRIES],
            rank_of_pixel: [0; ENTRIES],
        }
    }

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
        let w = 1i32 << log2;
        let classes = (1u32 << log2) / B;
        let b_log2 = B.trailing_zeros();
        let offset = walk_offset(params.frame, log2);
        let packed = table.packed();
        let reach = reach(B) as i32;
        for cy in 0..classes {
            for cx in 0..classes {
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
                let class = (cy * classes + cx) as usize;
                for (i, &k) in ranks.iter().enumerate() {
                    self.rank_of_pixel[class * N + i] = k as u8;
                    let d = unpack_offset(packed[texels[i] as usize]);
                    let qx = (cx * B) as i32 + (i as u32 & (B - 1)) as i32;
                    let qy = (cy * B) as i32 + (i as u32 >> b_log2) as i32;
                    let (tx, ty) = (qx + d.x, qy + d.y);
                    let (px, py) = (tx.rem_euclid(w), ty.rem_euclid(w));
                    let dbx = cx as i32 - tx.div_euclid(B as i32);
                    let dby = cy as i32 - ty.div_euclid(B as i32);
                    debug_assert!(dbx.abs() <= reach && dby.abs() <= reach);
                    let col = (px / B as i32 + dbx + reach) as u32 * N as u32 + k;
                    self.source[(py * w + px) as usize] = ((dby + reach) as u32) << 16 | col;
                }
            }
        }
    }
}

/// Sorting + retargeting of the seeds that land in `band`, gathered, in
/// column strips as wide as the ring allows ([`strip_periods`]).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(super) fn permute_gather<T: Intensity, R: LaneRanker, const B: u32, const N: usize>(
    params: &FrameParams,
    intensities: &[T],
    tile: &[u32],
    table: RetargetTable<'_>,
    seeds_in: &[u32],
    band: Band,
    seeds_out: &mut [u32],
) {
    let strip_periods = strip_periods::<N>(params);
    let mut cache = SourceCache::new();
    cache.fill::<B, N>(params, tile, table);
    let mut ring = Ring([0u32; RING_SEEDS]);
    let mut scratch = RankScratch::<N> {
        strips: [[0; MAX_LANES * MAX_FAST_BLOCK]; MAX_FAST_BLOCK],
        ranks: [[0u32; MAX_LANES]; N],
    };
    let inputs = Inputs {
        params,
        cache: &cache,
        intensities,
        tile,
        seeds_in,
    };
    let stream = (seeds_out.as_ptr() as usize).is_multiple_of(16);
    let periods = params.blocks_x() as usize / ((1usize << params.tile_log2) / B as usize);
    let mut first = 0;
    while first < periods {
        let end = (first + strip_periods).min(periods);
        gather_strip::<T, R, B, N>(
            &inputs,
            band,
            first..end,
            seeds_out,
            &mut ring.0,
            &mut scratch,
            stream,
        );
        first = end;
    }
    if stream {
        end_streaming();
    }
}

/// Tile periods (`W / B` block columns each) of the strips the frame's
/// block rows are cut into: as few strips as keep each strip's ring, `2
/// reach + 1` rows of `strip + 2 reach` lines, within [`RING_SEEDS`], of
/// equal width but the last. At least 15 periods fit with every block
/// and tile size, so 1920-wide frames with 4x4 blocks and 64x64 tiles
/// (30 periods of 16 blocks, ring rows of 484 lines: 155 KiB) take one
/// strip, 2560 and 3840-wide ones two.
fn strip_periods<const N: usize>(params: &FrameParams) -> usize {
    let reach = reach(params.block) as usize;
    let period_blocks = ((1u32 << params.tile_log2) / params.block) as usize;
    let periods = params.blocks_x() as usize / period_blocks;
    let lines = RING_SEEDS / ((2 * reach + 1) * N);
    let most = (lines - 2 * reach) / period_blocks;
    debug_assert!(most >= 1);
    periods.div_ceil(periods.div_ceil(most))
}

/// What every strip reads.
struct Inputs<'a, T> {
    params: &'a FrameParams,
    cache: &'a SourceCache,
    intensities: &'a [T],
    tile: &'a [u32],
    seeds_in: &'a [u32],
}

/// A lane group's keys and ranks (scratch of [`rank_run`]).
struct RankScratch<const N: usize> {
    strips: Strips,
    ranks: [[u32; MAX_LANES]; N],
}

/// The output rows of `band` in the tile periods `periods` (block columns
/// `periods.start * W / B .. periods.end * W / B`), through a ring of the
/// strip's block columns and `reach` more on each side (toroidally).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn gather_strip<T: Intensity, R: LaneRanker, const B: u32, const N: usize>(
    inputs: &Inputs<'_, T>,
    band: Band,
    periods: Range<usize>,
    seeds_out: &mut [u32],
    ring: &mut [u32; RING_SEEDS],
    scratch: &mut RankScratch<N>,
    stream: bool,
) {
    let params = inputs.params;
    let reach = reach(B) as usize;
    let slots = 2 * reach + 1;
    let w = 1usize << params.tile_log2;
    let period_blocks = w / B as usize;
    let blocks_x = params.blocks_x() as usize;
    let (xs, xe) = (periods.start * period_blocks, periods.end * period_blocks);
    let whole = xs == 0 && xe == blocks_x;
    let row_len = (xe - xs + 2 * reach) * N;
    let ring = &mut ring[..slots * row_len];
    let blocks_y = params.blocks_y() as usize;
    let (c0, c1) = ((band.row0 / B) as usize, (band.row_end / B) as usize);
    let pw = params.padded_width as usize;
    let mut row_sources = [[0u32; MAX_CACHED_TILE as usize]; MAX_FAST_BLOCK];
    for s in 0..c1 - c0 + 2 * reach {
        let by = ((c0 + blocks_y - reach + s) % blocks_y) as u32;
        let slot = s % slots;
        // Output block row `c` reads the block rows of sequence numbers
        // `s - 2 reach ..= s` (slot `s mod slots` held row `c - 1`, which
        // it does not read).
        let output = s >= 2 * reach;
        let c = (c0 + s).wrapping_sub(2 * reach);
        if output {
            let mut slot_base = [0u32; 2 * 3 + 1];
            for (d, base) in slot_base.iter_mut().enumerate().take(slots) {
                *base = (((s - 2 * reach + d) % slots) * row_len) as u32;
            }
            for (r, sources) in row_sources.iter_mut().enumerate().take(B as usize) {
                let ty = (c * B as usize + r) & (w - 1);
                for (x, src) in sources[..w].iter_mut().enumerate() {
                    let e = inputs.cache.source[ty * w + x];
                    *src = slot_base[(e >> 16) as usize & 7] + (e & 0xFFFF);
                }
            }
        }
        let out_rows: &mut [u32] = if output {
            let y0 = c * B as usize - band.row0 as usize;
            &mut seeds_out[y0 * pw..(y0 + B as usize) * pw]
        } else {
            &mut []
        };
        // The strip's periods are written as soon as row `s` is ranked
        // past the lines they read (`reach` beyond the period), so the
        // output's stores overlap the ranking's loads. Ring line `l` holds
        // block `xs - reach + l`. With the whole row in one strip, period 0
        // reads the wrap lines copied from the row's end last, so it waits.
        let count = periods.len();
        let mut written = usize::from(whole);
        let mut write_ready = |ring: &[u32], lines: usize| {
            while output && written < count && (written + 1) * period_blocks + 2 * reach <= lines {
                let (local, global) = (written, periods.start + written);
                gather_period::<B, N>(out_rows, ring, &row_sources, w, local, global, stream);
                written += 1;
            }
        };
        let row = slot * row_len;
        let run = |first_line: usize, blocks: Range<usize>| RingRun {
            row,
            first_line,
            blocks: blocks.start as u32..blocks.end as u32,
        };
        // The strip's blocks and those within `reach` of it that do not
        // wrap, in one run a lane group at a time; neighbours across the
        // frame's left or right side, the other end of the row, one block
        // at a time before and after it. With the whole row in one strip
        // those are copies of its own end lines instead.
        let main = if whole {
            run(reach, 0..blocks_x)
        } else {
            let first_line = if xs == 0 { reach } else { 0 };
            run(first_line, xs.saturating_sub(reach)..(xe + reach).min(blocks_x))
        };
        if xs == 0 && !whole {
            let left = run(0, blocks_x - reach..blocks_x);
            rank_run::<T, R, B, N, false>(inputs, by, ring, left, scratch, &mut |_, _| {});
        }
        rank_run::<T, R, B, N, true>(inputs, by, ring, main, scratch, &mut write_ready);
        if xe == blocks_x && !whole {
            let right = run(reach + xe - xs, 0..reach);
            rank_run::<T, R, B, N, false>(inputs, by, ring, right, scratch, &mut |_, _| {});
        }
        if whole {
            // The wrap: lines `0..reach` repeat the row's last blocks,
            // lines `reach + blocks_x..` its first.
            let ring_row = &mut ring[row..row + row_len];
            ring_row.copy_within(blocks_x * N..(blocks_x + reach) * N, 0);
            ring_row.copy_within(reach * N..2 * reach * N, (blocks_x + reach) * N);
        }
        if output {
            let late = (0..usize::from(whole)).chain(written..count);
            for local in late {
                let global = periods.start + local;
                gather_period::<B, N>(out_rows, ring, &row_sources, w, local, global, stream);
            }
        }
    }
}

/// Writes tile period `global` of the `B` output rows of one block row
/// (`out`, rows of `pw = out.len() / B` seeds), the strip's period
/// `local`: `out[r][x0 + x] = ring[(local W / B) N + sources[r][x]]` for
/// `x0 = global W`, `x < W` and every row `r`, so the ring lines the
/// period reads are loaded into L1 once for all `B` rows. With `stream`
/// (x86_64, `out` 16-byte aligned) the stores are non-temporal: whole
/// lines written without reading them first ([`end_streaming`] must
/// follow).
#[inline(always)]
fn gather_period<const B: u32, const N: usize>(
    out: &mut [u32],
    ring: &[u32],
    sources: &[[u32; MAX_CACHED_TILE as usize]; MAX_FAST_BLOCK],
    w: usize,
    local: usize,
    global: usize,
    stream: bool,
) {
    let pw = out.len() / B as usize;
    let src = &ring[local * (w / B as usize) * N..];
    for (r, sources) in sources.iter().enumerate().take(B as usize) {
        let chunk = &mut out[r * pw + global * w..][..w];
        gather_chunk(chunk, src, &sources[..w], stream);
    }
}

/// `out[x] = src[sources[x]]`, non-temporal with `stream` (see
/// [`gather_period`]).
#[inline(always)]
fn gather_chunk(out: &mut [u32], src: &[u32], sources: &[u32], stream: bool) {
    #[cfg(target_arch = "x86_64")]
    if stream {
        use core::arch::x86_64::{__m128i, _mm_set_epi32, _mm_stream_si128};
        debug_assert!((out.as_ptr() as usize).is_multiple_of(16));
        for (o, s) in out.chunks_exact_mut(4).zip(sources.chunks_exact(4)) {
            debug_assert!(s.iter().all(|&s| (s as usize) < src.len()));
            // The four sources are read as two 64-bit words (two loads,
            // not four: the loads, not the arithmetic, bound this loop).
            // SAFETY: as below for the loads; `s` is four u32 (16 readable
            // bytes); `o` is four seeds at a 16-byte aligned address (`out`
            // is aligned, and its length and offset are multiples of 4).
            unsafe {
                let pair = |k: usize| (s.as_ptr().add(k) as *const u64).read_unaligned();
                let (low, high) = (pair(0), pair(2));
                let v = _mm_set_epi32(
                    *src.get_unchecked((high >> 32) as usize) as i32,
                    *src.get_unchecked(high as u32 as usize) as i32,
                    *src.get_unchecked((low >> 32) as usize) as i32,
                    *src.get_unchecked(low as u32 as usize) as i32,
                );
                _mm_stream_si128(o.as_mut_ptr() as *mut __m128i, v);
            }
        }
        return;
    }
    let _ = stream;
    for (o, &s) in out.iter_mut().zip(sources) {
        debug_assert!((s as usize) < src.len());
        // SAFETY: every source is below `(2 reach) * row_len + (W / B +
        // 2 reach) * N`, and `src` starts `i * chunk_step <= (blocks_x -
        // W / B) * N` into the ring, so the index is below `(2 reach + 1)
        // * row_len = ring.len()`.
        *o = unsafe { *src.get_unchecked(s as usize) };
    }
}

/// Orders the non-temporal stores of [`gather_chunk`] before any later store
/// (x86_64; a no-op elsewhere).
#[inline(always)]
fn end_streaming() {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: SSE2 is part of x86_64; a fence has no other effect.
    unsafe {
        core::arch::x86_64::_mm_sfence()
    };
}

/// Where [`rank_run`] writes: blocks `blocks` of a block row (in frame
/// block columns, not wrapping) go to the ring row starting at `row`,
/// block `blocks.start` at line `first_line`, the next at the next line.
struct RingRun {
    row: usize,
    first_line: usize,
    blocks: Range<u32>,
}

/// Ranks the blocks `run.blocks` of block row `by` into their ring lines:
/// the seed sorted into the block's pixel `i` at the line's entry of `i`'s
/// dither rank. With `GROUPS`, full blocks go a lane group at a time and
/// after each group `after_group(ring, lines)` is told that the run's
/// lines up to `lines` (exclusive, counted from the ring row's start) are
/// written; without, one block at a time (the few blocks across the
/// frame's sides: no lane-group code instantiated for them).
#[allow(clippy::needless_range_loop)]
#[inline(always)]
fn rank_run<T: Intensity, R: LaneRanker, const B: u32, const N: usize, const GROUPS: bool>(
    inputs: &Inputs<'_, T>,
    by: u32,
    ring: &mut [u32],
    run: RingRun,
    scratch: &mut RankScratch<N>,
    after_group: &mut impl FnMut(&[u32], usize),
) {
    let Inputs {
        params,
        cache,
        intensities,
        tile,
        seeds_in,
    } = *inputs;
    let classes = (1u32 << params.tile_log2) / B;
    let lanes = R::LANES;
    let full_x = params.width / B;
    let full_y = params.height / B;
    let (w, pws) = (params.width as usize, params.padded_width as usize);
    let y0 = by * B;
    // Block `bx`'s line is `bx + shift` (`shift` may be "negative": the
    // sums wrap back into range).
    let shift = run.first_line.wrapping_sub(run.blocks.start as usize);
    let line_of = |bx: u32| run.row + (bx as usize).wrapping_add(shift) * N;
    let mut bx = run.blocks.start;
    if GROUPS && by < full_y {
        while bx + lanes as u32 <= full_x.min(run.blocks.end) {
            let x_start = (bx * B) as usize;
            for (r, strip) in scratch.strips.iter_mut().enumerate().take(B as usize) {
                let at = (y0 as usize + r) * w + x_start;
                let src = &intensities[at..at + lanes * B as usize];
                for (k, v) in strip.iter_mut().zip(src) {
                    *k = signed_key(v.intensity());
                }
            }
            for r in 0..B as usize {
                let span = lanes * B as usize;
                prefetch_span(seeds_in, (y0 as usize + r) * pws + x_start + PREFETCH_AHEAD, span);
                prefetch_span(
                    intensities,
                    (y0 as usize + r) * w + x_start + PREFETCH_AHEAD,
                    span,
                );
            }
            let origin = y0 as usize * pws + x_start;
            let lines = &mut ring[line_of(bx)..][..lanes * N];
            let group = GroupSeeds {
                seeds: seeds_in,
                origin,
                pitch: pws,
            };
            R::sort_group::<B, N>(&scratch.strips, &mut scratch.ranks, group, lines);
            bx += lanes as u32;
            after_group(ring, (bx as usize).wrapping_add(shift));
        }
    }
    let class_row = (by & (classes - 1)) * classes;
    while bx < run.blocks.end {
        let x0 = bx * B;
        let class = (class_row + (bx & (classes - 1))) as usize * N;
        let line = &mut ring[line_of(bx)..][..N];
        if bx < full_x && by < full_y {
            let mut block_keys = [0u32; N];
            for r in 0..B as usize {
                let at = (y0 as usize + r) * w + x0 as usize;
                for c in 0..B as usize {
                    block_keys[r * B as usize + c] = intensity_key(intensities[at + c].intensity());
                }
            }
            let ranks = block_ranks(&block_keys);
            for (i, &k) in ranks.iter().enumerate() {
                let at = (y0 as usize + i / B as usize) * pws + x0 as usize + i % B as usize;
                line[k as usize & (N - 1)] = seeds_in[at];
            }
        } else {
            sort_edge_block::<T, B, N>(
                params,
                bx,
                by,
                intensities,
                tile,
                seeds_in,
                &cache.rank_of_pixel[class..class + N],
                line,
            );
        }
        bx += 1;
    }
}

/// The reference sort ([`sort_block`]) of block `(bx, by)`, clipped by the
/// frame edge or in the padding: the seed it leaves at pixel `i` goes to
/// `line[rank_of_pixel[i]]` (padding pixels keep their own seeds).
#[allow(clippy::too_many_arguments)]
#[inline(never)]
fn sort_edge_block<T: Intensity, const B: u32, const N: usize>(
    params: &FrameParams,
    bx: u32,
    by: u32,
    intensities: &[T],
    tile: &[u32],
    seeds_in: &[u32],
    rank_of_pixel: &[u8],
    line: &mut [u32],
) {
    let pw = params.padded_width;
    let (x0, y0) = (bx * B, by * B);
    // The seed left at pixel `i` goes to the line's entry of `i`'s dither
    // rank; a padding pixel keeps its own.
    let mut place = |i: usize, seed: u32| line[rank_of_pixel[i] as usize & (N - 1)] = seed;
    let own_seed = |i: usize| seeds_in[((y0 + i as u32 / B) * pw + x0 + i as u32 % B) as usize];
    if x0 >= params.width || y0 >= params.height {
        // Wholly in the padding (the frame's bottom padding rows: 2 of 272
        // block rows at 1080p): nothing to sort, and none of the set-up
        // below is needed (it cost 1% of an AVX-512 frame and 2% of a
        // baseline one).
        for i in 0..N {
            place(i, own_seed(i));
        }
        return;
    }
    let offset = walk_offset(params.frame, params.tile_log2);
    let mut keys = [0u32; MAX_BLOCK_PIXELS];
    let mut dither = [0u32; MAX_BLOCK_PIXELS];
    let mut seeds = [0u32; MAX_BLOCK_PIXELS];
    let mut pixel = [0usize; MAX_BLOCK_PIXELS];
    let mut len = 0usize;
    for i in 0..N {
        let (x, y) = (x0 + i as u32 % B, y0 + i as u32 / B);
        let s = own_seed(i);
        if x < params.width && y < params.height {
            keys[len] = intensity_key(intensities[(y * params.width + x) as usize].intensity());
            dither[len] = tile[tile_texel(UVec2::new(x, y), offset, params.tile_log2) as usize];
            seeds[len] = s;
            pixel[len] = i;
            len += 1;
        } else {
            place(i, s);
        }
    }
    if len == 0 {
        return;
    }
    let mut sorted = [0u32; MAX_BLOCK_PIXELS];
    sort_block(len as u32, &keys, &dither, &seeds, &mut sorted);
    for i in 0..len {
        place(pixel[i], sorted[i]);
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::defaults::{tables_64, tile_64};
    use crate::sequences::seed::hash_u32;
    use crate::{band_seed_range, permute_frame_rows_isa, retarget_frame, sort_frame, FrameLayout, Isa};
    use std::vec::Vec;

    /// Frames wider than one ring give the reference output with every
    /// instruction set, bands included: two strips (5000 wide: three,
    /// the last narrower), the neighbours across a strip's sides ranked
    /// into its ring, across the frame's sides wrapped.
    #[test]
    fn strips_equal_the_reference() {
        let (tile, tables) = (tile_64(), tables_64());
        let mut state = 3u32;
        for (width, height, strips) in [(2600, 9, 2), (5000, 5, 3)] {
            let layout = FrameLayout::new(width, height, 4, 64).unwrap();
            let params = layout.params(7);
            let periods = params.blocks_x() as usize / 16;
            assert_eq!(periods.div_ceil(strip_periods::<16>(&params)), strips);
            let intensities: Vec<f32> = (0..layout.pixel_count())
                .map(|_| {
                    state = hash_u32(state);
                    (state % 13) as f32
                })
                .collect();
            let seeds: Vec<u32> = (0..layout.seed_count() as u32).map(hash_u32).collect();
            let mut sorted = std::vec![0u32; seeds.len()];
            let mut want = std::vec![0u32; seeds.len()];
            sort_frame(&layout, 7, &intensities, &tile, &seeds, &mut sorted).unwrap();
            retarget_frame(&layout, 7, &tables, &sorted, &mut want).unwrap();
            let blocks_y = params.blocks_y();
            for isa in Isa::ALL.into_iter().filter(|isa| isa.is_available()) {
                for bands in [1u32, 3] {
                    let mut got = std::vec![u32::MAX; seeds.len()];
                    for k in 0..bands {
                        let rows = blocks_y * k / bands..blocks_y * (k + 1) / bands;
                        let out = &mut got[band_seed_range(&layout, rows.clone())];
                        let (i, s) = (&intensities, &seeds);
                        permute_frame_rows_isa(isa, &layout, 7, i, &tile, &tables, s, rows, out).unwrap();
                    }
                    assert!(got == want, "{width}x{height}, {isa:?}, {bands} bands");
                }
            }
        }
    }
}
