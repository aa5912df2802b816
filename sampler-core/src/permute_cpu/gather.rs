//! The gather formulation of the fast path: blocks are ranked into a ring
//! of the last `2 reach + 1` block rows, each block's sorted seeds kept
//! as one `N`-seed line indexed by the dither rank of the pixel that holds
//! them, and each output row is then written in order, every output pixel
//! fetching its seed from the ring through the inverse of the retarget
//! table ([`SourceCache`]). The scattered stores of [`blocks`](super::blocks)
//! become sequential ones; the loads are scattered within a ring that
//! stays in the L2 cache, at addresses that depend on the tables only.
//!
//! The ring is a stack array of [`RING_SEEDS`] seeds: frames whose ring
//! does not fit ([`fits`]) take the scatter path.

use super::ranker::GroupSeeds;
use super::{block_ranks, prefetch_span, signed_key, Band, LaneRanker, Strips, MAX_CACHED_TILE};
use super::{MAX_FAST_BLOCK, MAX_LANES, PREFETCH_AHEAD};
use crate::dither::tile_texel;
use crate::layout::FrameParams;
use crate::retarget::{unpack_offset, RetargetTable, RETARGET_RADIUS};
use crate::sort::{intensity_key, sort_block, Intensity, MAX_BLOCK_PIXELS};
use crate::walk::walk_offset;
use core::ops::Range;
use glam::UVec2;

/// Entries of the source cache: one per texel of the largest cached tile.
const ENTRIES: usize = (MAX_CACHED_TILE * MAX_CACHED_TILE) as usize;

/// Seeds the ring holds (192 KiB): `2 reach + 1` block rows of
/// `blocks_x + 2 reach` lines of `B * B` seeds, i.e. a padded width of up
/// to 3498 (B = 2: 7 rows of `2 pw + 24`), 2441 (B = 4: 5 rows of
/// `4 pw + 64`) or 2032 (B = 8: 3 rows of `8 pw + 128`) seeds: 1920-wide
/// frames with every block size, 2560-wide ones with 2x2 blocks.
pub(super) const RING_SEEDS: usize = 48 * 1024;

/// Block rows (and columns) a seed can move: `ceil(RETARGET_RADIUS / B)`.
#[inline(always)]
const fn reach(block: u32) -> u32 {
    (RETARGET_RADIUS as u32).div_ceil(block)
}

/// Seeds of one ring row: `blocks_x + 2 reach` lines of `B * B` seeds (the
/// `reach` lines on each side repeat the other end of the row: the wrap).
#[inline(always)]
fn ring_row_len(params: &FrameParams) -> usize {
    let b = params.block;
    ((params.padded_width / b + 2 * reach(b)) * b * b) as usize
}

/// True when the ring of `params` fits in [`RING_SEEDS`].
pub(super) fn fits(params: &FrameParams) -> bool {
    (2 * reach(params.block) + 1) as usize * ring_row_len(params) <= RING_SEEDS
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

/// Sorting + retargeting of the seeds that land in `band`, gathered;
/// `fits(params)` must hold.
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
    debug_assert!(fits(params));
    let mut cache = SourceCache::new();
    cache.fill::<B, N>(params, tile, table);
    let mut ring = [0u32; RING_SEEDS];
    let reach = reach(B) as usize;
    let slots = 2 * reach + 1;
    let row_len = ring_row_len(params);
    let ring = &mut ring[..slots * row_len];
    let blocks_y = params.blocks_y() as usize;
    let (c0, c1) = ((band.row0 / B) as usize, (band.row_end / B) as usize);
    let w = 1usize << params.tile_log2;
    let pw = params.padded_width as usize;
    let mut strips: Strips = [[0; MAX_LANES * MAX_FAST_BLOCK]; MAX_FAST_BLOCK];
    let mut ranks = [[0u32; MAX_LANES]; N];
    let mut row_sources = [[0u32; MAX_CACHED_TILE as usize]; MAX_FAST_BLOCK];
    let stream = (seeds_out.as_ptr() as usize).is_multiple_of(16);
    for s in 0..c1 - c0 + 2 * reach {
        let by = (c0 + blocks_y - reach + s) % blocks_y;
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
                    let e = cache.source[ty * w + x];
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
        // Tile periods 1.. are written as soon as row `s` is ranked past
        // the blocks they read (`reach` beyond the period), so the output's
        // stores overlap the ranking's loads; period 0 reads the wrap lines
        // of the row's end, written last.
        let periods = pw / w;
        let period_blocks = w / B as usize;
        let mut written = 1;
        let mut write_ready = |ring: &[u32], ranked: usize| {
            while output && written < periods && (written + 1) * period_blocks + reach <= ranked {
                gather_period::<R, B, N>(out_rows, ring, &row_sources, w, written, stream);
                written += 1;
            }
        };
        rank_block_row::<T, R, B, N>(
            params,
            &cache,
            intensities,
            tile,
            seeds_in,
            by as u32,
            ring,
            slot * row_len..(slot + 1) * row_len,
            &mut strips,
            &mut ranks,
            &mut write_ready,
        );
        if output {
            for i in (0..1).chain(written..periods) {
                gather_period::<R, B, N>(out_rows, ring, &row_sources, w, i, stream);
            }
        }
    }
    if stream {
        end_streaming();
    }
}

/// Writes tile period `i` of the `B` output rows of one block row (`out`,
/// rows of `pw = out.len() / B` seeds): `out[r][x0 + x] = ring[(x0 / B) *
/// N + sources[r][x]]` for `x0 = i w`, `x < w` and every row `r`, so the
/// ring lines the period reads are loaded into L1 once for all `B` rows.
/// With `stream` (x86_64, `out` 16-byte aligned) the stores are
/// non-temporal: whole lines written without reading them first
/// ([`end_streaming`] must follow).
#[inline(always)]
fn gather_period<R: LaneRanker, const B: u32, const N: usize>(
    out: &mut [u32],
    ring: &[u32],
    sources: &[[u32; MAX_CACHED_TILE as usize]; MAX_FAST_BLOCK],
    w: usize,
    i: usize,
    stream: bool,
) {
    let pw = out.len() / B as usize;
    let src = &ring[i * (w / B as usize) * N..];
    for (r, sources) in sources.iter().enumerate().take(B as usize) {
        let chunk = &mut out[r * pw + i * w..][..w];
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

/// Ranks block row `by` into `row` (one ring row): block `bx`'s line at
/// `(bx + reach) * N`, the seed sorted into its pixel `i` at the line's
/// entry of `i`'s dither rank; then the wrap lines on both sides.
#[allow(clippy::needless_range_loop, clippy::too_many_arguments)]
#[inline(always)]
fn rank_block_row<T: Intensity, R: LaneRanker, const B: u32, const N: usize>(
    params: &FrameParams,
    cache: &SourceCache,
    intensities: &[T],
    tile: &[u32],
    seeds_in: &[u32],
    by: u32,
    ring: &mut [u32],
    row: Range<usize>,
    strips: &mut Strips,
    ranks: &mut [[u32; MAX_LANES]; N],
    after_group: &mut impl FnMut(&[u32], usize),
) {
    let row_start = row.start;
    let reach = reach(B) as usize;
    let classes = (1u32 << params.tile_log2) / B;
    let lanes = R::LANES;
    let full_x = params.width / B;
    let full_y = params.height / B;
    let (w, pws) = (params.width as usize, params.padded_width as usize);
    let blocks_x = params.blocks_x() as usize;
    let y0 = by * B;
    let mut bx = 0u32;
    if by < full_y {
        while bx + lanes as u32 <= full_x {
            let x_start = (bx * B) as usize;
            for (r, strip) in strips.iter_mut().enumerate().take(B as usize) {
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
            let lines = &mut ring[row_start + (bx as usize + reach) * N..][..lanes * N];
            let group = GroupSeeds {
                seeds: seeds_in,
                origin,
                pitch: pws,
            };
            R::sort_group::<B, N>(strips, ranks, group, lines);
            bx += lanes as u32;
            after_group(ring, bx as usize);
        }
    }
    let row = &mut ring[row];
    let class_row = (by & (classes - 1)) * classes;
    while (bx as usize) < blocks_x {
        let x0 = bx * B;
        let class = (class_row + (bx & (classes - 1))) as usize * N;
        let line = &mut row[(bx as usize + reach) * N..][..N];
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
    // The wrap: lines `-reach..0` repeat the row's last blocks, lines
    // `blocks_x..blocks_x + reach` its first.
    row.copy_within(blocks_x * N..(blocks_x + reach) * N, 0);
    row.copy_within(reach * N..2 * reach * N, (blocks_x + reach) * N);
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
    let offset = walk_offset(params.frame, params.tile_log2);
    let pw = params.padded_width;
    let mut keys = [0u32; MAX_BLOCK_PIXELS];
    let mut dither = [0u32; MAX_BLOCK_PIXELS];
    let mut seeds = [0u32; MAX_BLOCK_PIXELS];
    let mut pixel = [0usize; MAX_BLOCK_PIXELS];
    let mut len = 0usize;
    let (x0, y0) = (bx * B, by * B);
    for i in 0..N {
        let (x, y) = (x0 + i as u32 % B, y0 + i as u32 / B);
        let s = seeds_in[(y * pw + x) as usize];
        if x < params.width && y < params.height {
            keys[len] = intensity_key(intensities[(y * params.width + x) as usize].intensity());
            dither[len] = tile[tile_texel(UVec2::new(x, y), offset, params.tile_log2) as usize];
            seeds[len] = s;
            pixel[len] = i;
            len += 1;
        } else {
            line[rank_of_pixel[i] as usize & (N - 1)] = s;
        }
    }
    if len == 0 {
        return;
    }
    let mut sorted = [0u32; MAX_BLOCK_PIXELS];
    sort_block(len as u32, &keys, &dither, &seeds, &mut sorted);
    for i in 0..len {
        line[rank_of_pixel[pixel[i]] as usize & (N - 1)] = sorted[i];
    }
}
