//! The CPU fast path of [`permute_frame`](crate::permute_frame), used when
//! the block side divides the tile side (`B` in {2, 4, 8}) and the tile has
//! 16 to 128 texels a side.
//!
//! Output is identical to the per-block reference ([`sort_block`](crate::sort_block)
//! followed by [`retarget_pixel`](crate::retarget_pixel)); the speed comes from:
//!
//! - **Dither order and retarget offsets cached per frame.** With `B | W`,
//!   screen block `(bx, by)` reads the tile window starting at
//!   `((bx mod W/B) B + o_t) mod W`, so there are only `(W/B)^2` distinct
//!   windows per frame. For each, the pixel of dither rank `k` and that
//!   pixel's retarget offset are resolved once per frame into a stack array
//!   of `W * W` offset pairs (32 KiB for W = 128).
//! - **Eight blocks ranked at once.** Eight full blocks side by side are
//!   ranked together, one block per vector lane (`lane_ranks`): each of
//!   the `N (N - 1) / 2` pixel pairs costs one comparison and two updates
//!   per lane, ties rank by index for free, and no horizontal sums are
//!   needed. Keys are converted row by row in memory order, then transposed
//!   into lanes. For 4x4 blocks on CPUs with AVX2 (detected at run time)
//!   the eight lanes are one register and the transposition is done with
//!   unpacks ([`avx2`]); elsewhere the portable code vectorises for the
//!   build's baseline (SSE2 on x86_64).
//! - **Rows prefetched.** Each block row is the first to write `B` of the
//!   output rows, and reads `B` seed rows and `B` intensity rows: more
//!   streams than the hardware prefetchers follow. Their cache lines are
//!   requested a few lane groups ahead, so neither the scattered stores nor
//!   the loads wait on memory.
//! - **Linear destinations.** For blocks whose destinations cannot wrap
//!   (at least `B + 6` pixels from the padded frame's edge) the cached
//!   offsets are also stored as seed-index offsets, so each seed is one
//!   table load, one add and one store; seeds are read straight from the
//!   input rows.
//! - **No division.** Positions come from shifts; near the edge the
//!   toroidal wrap (`|offset| <= B + 6 < W <= padded size`) is one
//!   conditional add.
//!
//! Blocks clipped by the frame edge take the reference path.

use crate::dither::tile_texel;
use crate::frame::permute_block;
use crate::layout::FrameParams;
use crate::retarget::{unpack_offset, RetargetTable, RETARGET_RADIUS};
use crate::sort::{intensity_key, Intensity};
use crate::walk::walk_offset;
use glam::UVec2;

#[cfg(target_arch = "x86_64")]
pub(crate) mod avx2;

/// Largest tile side the cached dither order supports.
const MAX_CACHED_TILE: u32 = 128;
/// Smallest tile side: offsets (|d| <= 6) must wrap at most once.
const MIN_CACHED_TILE: u32 = 16;

/// True when [`permute_blocks_cached`] applies to `params`.
pub(crate) fn applies(params: &FrameParams) -> bool {
    let w = 1u32 << params.tile_log2;
    params.block.is_power_of_two()
        && w % params.block == 0
        && (MIN_CACHED_TILE..=MAX_CACHED_TILE).contains(&w)
}

/// Sorting + retargeting of a whole frame; see the module docs. Uses the
/// AVX2 ranker for 4x4 blocks where the CPU has it (checked once, at run
/// time), the portable one otherwise; both give identical output.
pub(crate) fn permute_blocks_cached<T: Intensity>(
    params: &FrameParams,
    intensities: &[T],
    tile: &[u32],
    table: RetargetTable<'_>,
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) {
    #[cfg(target_arch = "x86_64")]
    if params.block == 4 && avx2::available() {
        avx2::permute_4x4(params, intensities, tile, table, seeds_in, seeds_out);
        return;
    }
    permute_blocks_portable(params, intensities, tile, table, seeds_in, seeds_out);
}

/// [`permute_blocks_cached`] with the portable ranker only (baseline
/// instruction set); also the reference the AVX2 path is tested against.
pub(crate) fn permute_blocks_portable<T: Intensity>(
    params: &FrameParams,
    intensities: &[T],
    tile: &[u32],
    table: RetargetTable<'_>,
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) {
    type P = PortableRanker;
    match params.block {
        2 => permute_full_blocks::<T, P, 2, 4>(params, intensities, tile, table, seeds_in, seeds_out),
        4 => permute_full_blocks::<T, P, 4, 16>(params, intensities, tile, table, seeds_in, seeds_out),
        _ => permute_full_blocks::<T, P, 8, 64>(params, intensities, tile, table, seeds_in, seeds_out),
    }
}

/// Ranks `LANES` side-by-side `B x B` blocks at once.
trait LaneRanker {
    /// `strips[r][l * B + c]` is the signed key ([`signed_key`]) of pixel
    /// `(c, r)` of block `l`; rows `r >= B` are unused. Returns, for pixel
    /// `i = r * B + c` and block `l`, the pixel's rank in its block's total
    /// order (key, then index) at `[i][l]`.
    fn rank_strips<const B: u32, const N: usize>(
        strips: &[[i32; LANES * MAX_FAST_BLOCK]; MAX_FAST_BLOCK],
    ) -> [[u32; LANES]; N];
}

/// Scalar transposition and [`lane_ranks`]; the compiler vectorises the
/// lanes with whatever vector width the build targets.
struct PortableRanker;

impl LaneRanker for PortableRanker {
    #[inline(always)]
    fn rank_strips<const B: u32, const N: usize>(
        strips: &[[i32; LANES * MAX_FAST_BLOCK]; MAX_FAST_BLOCK],
    ) -> [[u32; LANES]; N] {
        let lane_keys: [[i32; LANES]; N] = core::array::from_fn(|i| {
            let (r, c) = (i / B as usize, i % B as usize);
            core::array::from_fn(|l| strips[r][l * B as usize + c])
        });
        lane_ranks(&lane_keys)
    }
}

/// [`permute_blocks_cached`] for block side `B` (`N = B * B` pixels).
// Lane loops index several lane arrays at once; iterators would hide that.
#[allow(clippy::needless_range_loop)]
#[inline(always)]
fn permute_full_blocks<T: Intensity, R: LaneRanker, const B: u32, const N: usize>(
    params: &FrameParams,
    intensities: &[T],
    tile: &[u32],
    table: RetargetTable<'_>,
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) {
    let log2 = params.tile_log2;
    let w = 1u32 << log2;
    let b_log2 = B.trailing_zeros();
    let classes = w / B;
    let offset = walk_offset(params.frame, log2);
    let (pw, ph) = (params.padded_width, params.padded_height);
    let packed = table.packed();

    // Per window class and dither rank k: where, relative to the block's
    // origin, the seed of intensity rank k ends up after the sort (the
    // pixel of dither rank k) and the retarget scatter (its table offset),
    // as a 2D offset (for blocks near the frame edge, which wrap) and as a
    // linear seed-index offset (for interior blocks).
    let mut dest = [(0i8, 0i8); (MAX_CACHED_TILE * MAX_CACHED_TILE) as usize];
    let mut dest_linear = [0i32; (MAX_CACHED_TILE * MAX_CACHED_TILE) as usize];
    // Smallest and largest destination offset on each axis over all cached
    // entries (within `-RETARGET_RADIUS..B + RETARGET_RADIUS` for a valid
    // table); the unchecked interior stores below rely on these bounds.
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
            for (k, &j) in pixel_of_rank.iter().enumerate() {
                let (jx, jy) = (j & (B - 1), j >> b_log2);
                let d = unpack_offset(packed[texels[j as usize] as usize]);
                let (ox, oy) = (jx as i32 + d.x, jy as i32 + d.y);
                lo = lo.min(ox).min(oy);
                hi = hi.max(ox).max(oy);
                dest[base + k] = (ox as i8, oy as i8);
                dest_linear[base + k] = oy * pw as i32 + ox;
            }
        }
    }

    let full_x = params.width / B; // blocks fully inside the visible frame
    let full_y = params.height / B;
    // Blocks whose destinations cannot wrap: every cached offset, on each
    // axis, lies in `lo..=hi` (measured above, not assumed), so the block
    // origin plus any offset stays inside the padded frame.
    debug_assert!(-lo <= RETARGET_RADIUS && hi < B as i32 + RETARGET_RADIUS);
    let (before, after) = ((-lo) as u32, (hi + 1) as u32);
    let interior = |x0: u32, y0: u32| x0 >= before && y0 >= before && x0 + after <= pw && y0 + after <= ph;
    let w = params.width as usize;
    for by in 0..params.blocks_y() {
        let y0 = by * B;
        let class_row = ((by & (classes - 1)) * classes) as usize;
        let mut bx = 0u32;
        if by < full_y {
            // LANES full blocks at a time, one block per vector lane.
            while bx + LANES as u32 <= full_x {
                let x_start = (bx * B) as usize;
                // Convert each strip row in memory order (vectorises); the
                // ranker transposes the strips into lanes.
                let mut strips = [[0i32; LANES * MAX_FAST_BLOCK]; MAX_FAST_BLOCK];
                for (r, strip) in strips.iter_mut().enumerate().take(B as usize) {
                    let at = (y0 as usize + r) * w + x_start;
                    let row = &intensities[at..at + LANES * B as usize];
                    for (k, v) in strip.iter_mut().zip(row) {
                        *k = signed_key(v.intensity());
                    }
                }
                // The output rows no earlier block row has written
                // (`y0 + hi - B + 1 ..= y0 + hi`) arrive from memory on the
                // first store: ask for them a few groups ahead.
                for r in (y0 as i32 + hi + 1 - B as i32).max(0)..=y0 as i32 + hi {
                    if (r as u32) < ph {
                        let at = r as usize * pw as usize + x_start + PREFETCH_AHEAD;
                        prefetch(seeds_out, at, true);
                        prefetch(seeds_out, at + LINE_SEEDS, true);
                    }
                }
                // The block row's input rows, as far ahead (eight read
                // streams plus the output rows are more than the hardware
                // prefetchers follow).
                for r in 0..B as usize {
                    let at = (y0 as usize + r) * pw as usize + x_start + PREFETCH_AHEAD;
                    prefetch(seeds_in, at, false);
                    prefetch(seeds_in, at + LINE_SEEDS, false);
                    let at = (y0 as usize + r) * w + x_start + PREFETCH_AHEAD;
                    prefetch(intensities, at, false);
                    prefetch(intensities, at + LINE_SEEDS, false);
                }
                let ranks = R::rank_strips::<B, N>(&strips);
                for l in 0..LANES {
                    let b = bx + l as u32;
                    let x0 = b * B;
                    let class = (class_row + (b & (classes - 1)) as usize) * N;
                    let origin = y0 as usize * pw as usize + x0 as usize;
                    if interior(x0, y0) {
                        // Seeds read straight from the input rows; destinations
                        // are linear offsets from the block origin.
                        let dest = &dest_linear[class..class + N];
                        let out = seeds_out.as_mut_ptr();
                        for r in 0..B as usize {
                            let src = &seeds_in[origin + r * pw as usize..][..B as usize];
                            for (c, &seed) in src.iter().enumerate() {
                                let rank = ranks[r * B as usize + c][l] as usize & (N - 1);
                                let at = (origin as isize + dest[rank] as isize) as usize;
                                debug_assert!(at < seeds_out.len());
                                // SAFETY: `interior` holds for this block, so
                                // with `lo <= dx, dy <= hi` the destination
                                // lies inside the padded frame, whose
                                // `pw * ph` seeds `seeds_out` holds (checked
                                // by `permute_frame`).
                                unsafe { *out.add(at) = seed };
                            }
                        }
                    } else {
                        scatter_block::<B, N>(
                            x0,
                            y0,
                            pw,
                            ph,
                            false,
                            &dest[class..class + N],
                            &dest_linear[class..class + N],
                            core::array::from_fn(|i| ranks[i][l]),
                            core::array::from_fn(|i| {
                                seeds_in[origin + (i >> b_log2) * pw as usize + (i & (B as usize - 1))]
                            }),
                            seeds_out,
                        );
                    }
                }
                bx += LANES as u32;
            }
        }
        while bx < params.blocks_x() {
            if bx >= full_x || by >= full_y {
                permute_block(params, bx, by, intensities, tile, packed, seeds_in, seeds_out);
                bx += 1;
                continue;
            }
            let x0 = bx * B;
            let mut block_keys = [0u32; N];
            let mut seeds = [0u32; N];
            for r in 0..B as usize {
                let at = (y0 as usize + r) * w + x0 as usize;
                let row = &intensities[at..at + B as usize];
                let s_at = (y0 as usize + r) * pw as usize + x0 as usize;
                let s_row = &seeds_in[s_at..s_at + B as usize];
                for c in 0..B as usize {
                    block_keys[r * B as usize + c] = intensity_key(row[c].intensity());
                    seeds[r * B as usize + c] = s_row[c];
                }
            }
            let class = (class_row + (bx & (classes - 1)) as usize) * N;
            scatter_block::<B, N>(
                x0,
                y0,
                pw,
                ph,
                interior(x0, y0),
                &dest[class..class + N],
                &dest_linear[class..class + N],
                block_ranks(&block_keys),
                seeds,
                seeds_out,
            );
            bx += 1;
        }
    }
}

/// Blocks ranked side by side, one per vector lane.
const LANES: usize = 8;
/// How far ahead of the current lane group, in seeds, the output rows are
/// prefetched (measured best of 128 / 256 / 512 / 1024 at 1920x1080).
const PREFETCH_AHEAD: usize = 128;
/// Seeds per 64-byte cache line.
const LINE_SEEDS: usize = 16;

/// Hints that `buffer[at]` will be read, or `write`-ten, soon (x86_64; a
/// no-op elsewhere). `at` may lie past the end: a prefetch never faults.
#[inline(always)]
pub(crate) fn prefetch<E>(buffer: &[E], at: usize, write: bool) {
    #[cfg(target_arch = "x86_64")]
    {
        use core::arch::x86_64::{_mm_prefetch, _MM_HINT_ET0, _MM_HINT_T0};
        let p = buffer.as_ptr().wrapping_add(at) as *const i8;
        // SAFETY: prefetches never fault and do not change memory; the
        // pointer is only formed (`wrapping_add`), never dereferenced.
        unsafe {
            if write {
                _mm_prefetch::<_MM_HINT_ET0>(p)
            } else {
                _mm_prefetch::<_MM_HINT_T0>(p)
            }
        };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (buffer, at, write);
}

/// Largest block side of the fast path.
const MAX_FAST_BLOCK: usize = 8;

/// [`intensity_key`] with the sign bit flipped: the same order as `i32`
/// (baseline x86-64 vectors compare signed integers only).
#[inline(always)]
fn signed_key(value: f32) -> i32 {
    (intensity_key(value) ^ 0x8000_0000) as i32
}

/// Writes the `N` seeds of the block at `(x0, y0)`: the seed of intensity
/// rank `ranks[i]` goes to the block origin plus `dest[rank]` (wrapped on the
/// padded frame) or, for an `interior` block, plus `dest_linear[rank]`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn scatter_block<const B: u32, const N: usize>(
    x0: u32,
    y0: u32,
    pw: u32,
    ph: u32,
    interior: bool,
    dest: &[(i8, i8)],
    dest_linear: &[i32],
    ranks: [u32; N],
    seeds: [u32; N],
    seeds_out: &mut [u32],
) {
    if interior {
        let base = (y0 * pw + x0) as i32;
        for (&r, &seed) in ranks.iter().zip(&seeds) {
            seeds_out[(base + dest_linear[r as usize & (N - 1)]) as usize] = seed;
        }
    } else {
        for (&r, &seed) in ranks.iter().zip(&seeds) {
            let (ox, oy) = dest[r as usize & (N - 1)];
            let nx = wrap(x0 as i32 + ox as i32, pw);
            let ny = wrap(y0 as i32 + oy as i32, ph);
            seeds_out[(ny * pw + nx) as usize] = seed;
        }
    }
}

/// Ranks of `LANES` independent blocks at once: `keys[i][l]` is pixel `i`
/// of block `l`; the result is each pixel's rank in its block's total order
/// (key, then index). Each unordered pair `i < j` costs one comparison and
/// two updates per lane: pixel `j` starts with rank `j` (every `i < j`
/// counted as smaller) and gives one back to `i` when `key_i > key_j`. Ties
/// therefore rank by index with no extra work.
#[inline(always)]
fn lane_ranks<const N: usize>(keys: &[[i32; LANES]; N]) -> [[u32; LANES]; N] {
    let mut ranks: [[u32; LANES]; N] = core::array::from_fn(|j| [j as u32; LANES]);
    for i in 0..N {
        // Pixel i's rank stays in a register across the inner loop (an
        // update through memory would chain store-to-load latencies).
        let ki = keys[i];
        let mut acc = ranks[i];
        for j in i + 1..N {
            for l in 0..LANES {
                let g = (ki[l] > keys[j][l]) as u32;
                acc[l] += g;
                ranks[j][l] -= g;
            }
        }
        ranks[i] = acc;
    }
    ranks
}

/// `v mod m` for `v` in `-m..2m` (one conditional add or subtract).
#[inline(always)]
fn wrap(v: i32, m: u32) -> u32 {
    let m = m as i32;
    (if v < 0 {
        v + m
    } else if v >= m {
        v - m
    } else {
        v
    }) as u32
}

/// Rank of each key in the block's total order (key, then index): branch-free
/// all-pairs counting. The loop over `i` is the inner one, so every rank
/// accumulates in a vector lane (no horizontal sums) and each key `j` costs
/// one broadcast, one greater-than and one equality test per lane group.
/// Keys are compared as `i32` after flipping the sign bit (same order as
/// `u32`), since baseline x86-64 vectors only compare signed integers.
#[inline(always)]
fn block_ranks<const N: usize>(keys: &[u32; N]) -> [u32; N] {
    let signed: [i32; N] = core::array::from_fn(|i| (keys[i] ^ 0x8000_0000) as i32);
    let mut ranks = [0u32; N];
    for j in 0..N {
        let kj = signed[j];
        for i in 0..N {
            let ki = signed[i];
            ranks[i] += (ki > kj) as u32 + ((ki == kj) & (i > j)) as u32;
        }
    }
    ranks
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lane_ranks_equal_block_ranks() {
        let mut state = 99u32;
        for _ in 0..300 {
            let mut lanes = [[0i32; LANES]; 16];
            for row in lanes.iter_mut() {
                for k in row.iter_mut() {
                    state = crate::seed::hash_u32(state);
                    *k = ((state % 7) as i32 - 3).wrapping_add(if state & 8 != 0 { i32::MIN } else { 0 });
                }
            }
            let ranks = lane_ranks(&lanes);
            for l in 0..LANES {
                let keys: [u32; 16] = core::array::from_fn(|i| lanes[i][l] as u32 ^ 0x8000_0000);
                let want = block_ranks(&keys);
                let got: [u32; 16] = core::array::from_fn(|i| ranks[i][l]);
                assert_eq!(got, want, "lane {l}");
            }
        }
    }

    #[test]
    fn block_ranks_follow_key_then_index() {
        let mut state = 12345u32;
        for _ in 0..500 {
            let mut keys = [0u32; 16];
            for k in keys.iter_mut() {
                state = crate::seed::hash_u32(state);
                *k = state % 5; // many ties
            }
            let ranks = block_ranks(&keys);
            let mut order: [usize; 16] = core::array::from_fn(|i| i);
            order.sort_by_key(|&i| (keys[i], i));
            for (r, &i) in order.iter().enumerate() {
                assert_eq!(ranks[i] as usize, r);
            }
        }
    }
}
