//! The CPU fast path of [`permute_frame`](crate::permute_frame), used when
//! the block side divides the tile side (`B` in {2, 4, 8}) and the tile has
//! 16 to 128 texels a side.
//!
//! Output is identical to the per-block reference ([`sort_block`](crate::sort_block)
//! followed by [`retarget_pixel`](crate::retarget_pixel)); the speed comes from:
//!
//! - **Eight or sixteen blocks sorted at once** ([`ranker`]). Full blocks
//!   side by side are sorted together, one block per vector lane. Keys are
//!   converted row by row in memory order, then transposed into lanes. For
//!   4x4 blocks the instruction set is chosen at run time ([`Isa`],
//!   [`detect`]): with AVX-512 each block's order comes from a sorting
//!   network ([`network`]: 63 comparators, a 64-bit minimum and maximum
//!   each, eight blocks a register, the key above the pixel index so that
//!   ties order by index; [`avx512`]); with AVX2 and SSE2 (the baseline
//!   instruction set on x86_64) each pixel's rank is counted, each of the
//!   `N (N - 1) / 2` pixel pairs one comparison and two updates per lane,
//!   ties by index for free (eight 32-bit lanes a register with AVX2,
//!   [`avx2`]; with SSE2 the compares of two registers of four blocks
//!   packed into one of eight 16-bit counts, [`sse2`]); other block
//!   sizes and targets take the portable ranker, which the compiler
//!   vectorises for the build's baseline.
//! - **Gathered, not scattered** ([`gather`]). Each block row is ranked
//!   into a ring of the last `2 ceil(6 / B) + 1` block rows (at most 192
//!   KiB, on the stack): a block's sorted seeds as one line of `N` seeds,
//!   indexed by the dither rank of the pixel they are sorted into (with
//!   AVX2 and AVX-512 a line is built in registers, one or two permutes of
//!   the block's seeds by its order: [`LaneRanker::sort_group`]; with AVX2
//!   the order is each block's inverse permutation as sixteen nibbles,
//!   [`inverse`]). Then each output row is written in order, every output
//!   pixel fetching its seed from the ring through the inverse of the
//!   retarget table, resolved once per frame for each of the `W x W`
//!   positions in the tile (`SourceCache`). The stores are sequential (and
//!   non-temporal on x86_64: whole lines written without first reading
//!   them); the scattered loads hit the ring, in the L2 cache, at
//!   addresses that depend on the tables only (scalar loads: the gather
//!   instruction measured slower on Zen 5). A block row's `B` output rows
//!   are written a tile period at a time, so the ring lines a period reads
//!   come into L1 once for all of them, and each period as soon as the
//!   block row being ranked has passed the blocks it reads, so the
//!   output's stores overlap the ranking's loads. Frames wider than one
//!   ring (padded widths above 3498, 2441 and 2032 seeds for 2x2, 4x4 and
//!   8x8 blocks) are cut into column strips of whole tile periods. This
//!   replaced a scatter of each block's seeds to their destinations, whose
//!   scattered stores were its largest cost (BENCHMARKS.md, issue 18).
//! - **Rows prefetched.** Each block row reads `B` seed rows and `B`
//!   intensity rows: more streams than the hardware prefetchers follow.
//!   Their cache lines are requested a few lane groups ahead, every line a
//!   lane group reads (sixteen 4x4 blocks read four lines of each row).
//! - **No division.** Positions come from shifts; the toroidal wrap
//!   (`|offset| <= B + 6 < W <= padded size`) is a copy of the ring row's
//!   end lines to its other end (one strip) or the neighbouring blocks
//!   ranked into the strip's ring from the other end of the row.
//!
//! Blocks clipped by the frame edge take the reference sort (in
//! [`gather`]).
//!
//! **Bands.** The loop runs over a band of block rows and writes only the
//! output rows of that band ([`rows`], [`Band`]): the blocks within
//! `RETARGET_RADIUS` rows of the band are ranked too (their seeds may move
//! into it). Bands therefore write disjoint slices of the output and can
//! run on any threads; the whole frame is the band of every block row.

#[cfg(target_arch = "x86_64")]
pub(crate) mod avx2;
#[cfg(target_arch = "x86_64")]
mod avx512;
pub(crate) mod detect;
mod edge;
mod gather;
#[cfg(target_arch = "x86_64")]
mod inverse;
#[cfg(target_arch = "x86_64")]
mod network;
mod ranker;
pub(crate) mod rows;
#[cfg(target_arch = "x86_64")]
mod sse2;

/// The ranker of the baseline instruction set: SSE2 on x86_64, the
/// portable one elsewhere.
#[cfg(target_arch = "x86_64")]
type BaselineRanker = sse2::Sse2Ranker;
#[cfg(not(target_arch = "x86_64"))]
type BaselineRanker = ranker::PortableRanker;

pub use detect::Isa;
use ranker::{LaneRanker, Strips, MAX_FAST_BLOCK, MAX_LANES};

use crate::permutation::layout::FrameParams;
use crate::permutation::retarget::RetargetTable;
use crate::permutation::sort::Intensity;
use core::ops::Range;

/// Largest tile side the cached dither order supports.
const MAX_CACHED_TILE: u32 = 128;
/// Smallest tile side: offsets (|d| <= 6) must wrap at most once.
const MIN_CACHED_TILE: u32 = 16;

/// True when the fast path ([`permute_band_cached`]) applies to `params`.
pub(crate) fn applies(params: &FrameParams) -> bool {
    let w = 1u32 << params.tile_log2;
    params.block.is_power_of_two()
        && w.is_multiple_of(params.block)
        && (MIN_CACHED_TILE..=MAX_CACHED_TILE).contains(&w)
}

/// Output rows `row0..row_end` of the padded frame, held by a `seeds_out`
/// slice whose element 0 is seed `(0, row0)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Band {
    /// First output row.
    pub row0: u32,
    /// One past the last output row (`<= padded_height`).
    pub row_end: u32,
}

impl Band {
    /// Every row of the padded frame.
    pub fn whole(params: &FrameParams) -> Band {
        Band {
            row0: 0,
            row_end: params.padded_height,
        }
    }

    /// The output rows of block rows `rows` (clipped to the padded frame;
    /// empty when `rows` is).
    pub fn of_block_rows(params: &FrameParams, rows: Range<u32>) -> Band {
        let row = |block_row: u32| (block_row.saturating_mul(params.block)).min(params.padded_height);
        Band {
            row0: row(rows.start),
            row_end: row(rows.end).max(row(rows.start)),
        }
    }

    /// Index in the band's slice of seed `(x, y)`, if row `y` is in the band.
    #[inline(always)]
    pub fn index(self, padded_width: u32, x: u32, y: u32) -> Option<usize> {
        (y >= self.row0 && y < self.row_end).then(|| ((y - self.row0) * padded_width + x) as usize)
    }

    /// The block rows whose seeds can land in the band when seeds move at
    /// most `reach` rows: those meeting rows `row0 - reach ..= row_end - 1 +
    /// reach`, toroidally. Up to two ranges (one when the rows do not wrap,
    /// all block rows in order when they cover the frame). A block row in
    /// both ranges is harmless: it writes the same seeds twice.
    pub fn source_block_rows(self, params: &FrameParams, reach: i32) -> [Range<u32>; 2] {
        let (ph, block) = (params.padded_height as i32, params.block as i32);
        let all = 0..params.blocks_y();
        let (lo, hi) = (self.row0 as i32 - reach, self.row_end as i32 - 1 + reach);
        if self.row0 == 0 && self.row_end == params.padded_height || hi - lo + 1 >= ph {
            return [all, 0..0];
        }
        let (lo, hi) = (lo.rem_euclid(ph), hi.rem_euclid(ph));
        if lo <= hi {
            [(lo / block) as u32..(hi / block + 1) as u32, 0..0]
        } else {
            [0..(hi / block + 1) as u32, (lo / block) as u32..all.end]
        }
    }
}

/// The gather formulation with the portable ranker.
#[inline(never)]
fn gather_portable<T: Intensity, const B: u32, const N: usize>(
    params: &FrameParams,
    intensities: &[T],
    tile: &[u32],
    table: RetargetTable<'_>,
    seeds_in: &[u32],
    band: Band,
    seeds_out: &mut [u32],
) {
    let (i, t, s) = (intensities, tile, seeds_in);
    gather::permute_gather::<T, BaselineRanker, B, N>(params, i, t, table, s, band, seeds_out)
}

/// Sorting + retargeting of the seeds that land in `band` with the ranker
/// of `isa` (or the best available below it) for 4x4 blocks, the portable
/// one otherwise, in the gather formulation ([`gather`]); every choice
/// gives identical output. `applies(params)` must hold.
#[allow(clippy::too_many_arguments)]
pub(crate) fn permute_band_cached<T: Intensity>(
    isa: Isa,
    params: &FrameParams,
    intensities: &[T],
    tile: &[u32],
    table: RetargetTable<'_>,
    seeds_in: &[u32],
    band: Band,
    seeds_out: &mut [u32],
) {
    #[cfg(target_arch = "x86_64")]
    if params.block == 4 {
        match isa.min(Isa::best()) {
            Isa::Avx512 => {
                return avx512::gather_4x4(params, intensities, tile, table, seeds_in, band, seeds_out)
            }
            Isa::Avx2 => {
                return avx2::gather_4x4(params, intensities, tile, table, seeds_in, band, seeds_out)
            }
            Isa::Baseline => {}
        }
    }
    let _ = isa;
    let (i, t, s) = (intensities, tile, seeds_in);
    match params.block {
        2 => gather_portable::<T, 2, 4>(params, i, t, table, s, band, seeds_out),
        4 => gather_portable::<T, 4, 16>(params, i, t, table, s, band, seeds_out),
        _ => gather_portable::<T, 8, 64>(params, i, t, table, s, band, seeds_out),
    }
}

/// The whole frame with the best instruction set ([`permute_band_cached`]).
pub(crate) fn permute_blocks_cached<T: Intensity>(
    params: &FrameParams,
    intensities: &[T],
    tile: &[u32],
    table: RetargetTable<'_>,
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) {
    let band = Band::whole(params);
    permute_band_cached(
        Isa::best(),
        params,
        intensities,
        tile,
        table,
        seeds_in,
        band,
        seeds_out,
    );
}

/// The whole frame with the portable ranker only (baseline instruction
/// set); also the reference the vector paths are tested against.
pub(crate) fn permute_blocks_portable<T: Intensity>(
    params: &FrameParams,
    intensities: &[T],
    tile: &[u32],
    table: RetargetTable<'_>,
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) {
    let band = Band::whole(params);
    permute_band_cached(
        Isa::Baseline,
        params,
        intensities,
        tile,
        table,
        seeds_in,
        band,
        seeds_out,
    );
}

/// How far ahead of the current lane group, in elements, the input rows
/// are prefetched (measured best of 64 / 128 / 256 / 512 / 1024 at
/// 1920x1080).
const PREFETCH_AHEAD: usize = 128;

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

/// [`intensity_key`](crate::intensity_key) with the sign bit flipped: the same order as `i32`
/// (baseline x86-64 vectors compare signed integers only). Written as
/// the bits with all but the sign flipped where the sign is set (two
/// shifts and a xor a vector, not `intensity_key`'s select of two
/// expressions); the tests hold the two equal.
#[inline(always)]
fn signed_key(value: f32) -> i32 {
    let bits = value.to_bits() as i32;
    bits ^ ((bits >> 31) as u32 >> 1) as i32
}

/// Hints that elements `at..at + len` of `buffer` will be read soon: one
/// prefetch per 64-byte line they span (x86_64; a no-op elsewhere). A lane
/// group of `LANES` blocks reads `LANES * B` elements of each of its rows,
/// one to sixteen lines, so every line is requested, not just the first.
#[inline(always)]
pub(crate) fn prefetch_span<E>(buffer: &[E], at: usize, len: usize) {
    let bytes = len * core::mem::size_of::<E>();
    let per_line = (64 / core::mem::size_of::<E>().max(1)).max(1);
    for line in 0..bytes.div_ceil(64) {
        prefetch(buffer, at + line * per_line, false);
    }
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
    use crate::permutation::sort::intensity_key;

    #[test]
    fn signed_key_is_intensity_key_with_the_sign_flipped() {
        let special = [
            0.0f32,
            -0.0,
            1.0,
            -1.0,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -f32::NAN,
        ];
        let mut state = 777u32;
        let random = (0..100_000).map(|_| {
            state = crate::sequences::seed::hash_u32(state);
            f32::from_bits(state)
        });
        for v in special.into_iter().chain(random) {
            assert_eq!(
                signed_key(v) as u32,
                intensity_key(v) ^ 0x8000_0000,
                "{:#x}",
                v.to_bits()
            );
        }
    }

    #[test]
    fn block_ranks_follow_key_then_index() {
        let mut state = 12345u32;
        for _ in 0..500 {
            let mut keys = [0u32; 16];
            for k in keys.iter_mut() {
                state = crate::sequences::seed::hash_u32(state);
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
