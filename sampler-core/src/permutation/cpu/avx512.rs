//! The AVX-512 kernels for 4x4 blocks, sixteen blocks at a time.
//!
//! The permutation needs each block's order (the pixel of each rank),
//! not its ranks: [`order_words`] sorts eight blocks at once, one per
//! 64-bit lane, with a sorting network ([`network`](super::network): 63
//! comparators, a minimum and a maximum each), the pixel's key above its
//! index so that ties order by index, and [`sort_4x4`] builds each block's
//! ring line with one permute of its seeds. Against counting ranks with
//! mask registers and inverting them this took a 1080p frame from 1.6 to
//! 1.2 ms on Zen 5 (BENCHMARKS.md).
//!
//! Selected at run time ([`Isa`]: CPUID for AVX-512 F, XGETBV
//! for the OS saving the mask and ZMM registers; no `std`); the whole frame
//! loop is compiled with AVX-512 enabled so the key conversion vectorises
//! sixteen wide too. The output is bit-identical to the portable path
//! (tested in `rows` and by the conformance property tests on CPUs that
//! have AVX-512; they report a skip elsewhere).
//!
//! The AVX-512 intrinsics and `target_feature(enable = "avx512f")` are
//! stable since Rust 1.89, the crate's `rust-version`.

use super::network::{for_each_comparator, INPUTS};
use super::ranker::GroupSeeds;
use super::{Band, Isa, Strips, MAX_LANES};
use crate::permutation::layout::FrameParams;
use crate::permutation::retarget::RetargetTable;
use crate::permutation::sort::Intensity;
use core::arch::x86_64::{
    __m128i, __m512i, _mm256_loadu2_m128i, _mm512_add_epi32, _mm512_and_si512, _mm512_castsi256_si512,
    _mm512_inserti64x4, _mm512_loadu_epi32, _mm512_mask2_permutex2var_epi32, _mm512_mask_blend_epi32,
    _mm512_max_epi64, _mm512_min_epi64, _mm512_or_si512, _mm512_permutexvar_epi32, _mm512_set1_epi32,
    _mm512_set1_epi64, _mm512_setr_epi32, _mm512_setzero_si512, _mm512_sllv_epi64, _mm512_srlv_epi32,
    _mm512_storeu_epi32,
};

/// The gather formulation ([`gather`](super::gather)) for 4x4 blocks with
/// this ranker. Call only when the CPU has the instruction set.
pub(super) fn gather_4x4<T: Intensity>(
    params: &FrameParams,
    intensities: &[T],
    tile: &[u32],
    table: RetargetTable<'_>,
    seeds_in: &[u32],
    band: Band,
    seeds_out: &mut [u32],
) {
    assert!(Isa::Avx512.is_available() && params.block == 4);
    // SAFETY: the instruction set is available (checked above).
    unsafe { gather_4x4_avx512(params, intensities, tile, table, seeds_in, band, seeds_out) }
}

#[target_feature(enable = "avx2,avx512f")]
fn gather_4x4_avx512<T: Intensity>(
    params: &FrameParams,
    intensities: &[T],
    tile: &[u32],
    table: RetargetTable<'_>,
    seeds_in: &[u32],
    band: Band,
    seeds_out: &mut [u32],
) {
    super::gather::permute_gather::<T, Avx512Ranker, 4, 16>(
        params,
        intensities,
        tile,
        table,
        seeds_in,
        band,
        seeds_out,
    );
}

/// Only instantiated inside [`gather_4x4_avx512`], i.e. with AVX-512
/// present.
struct Avx512Ranker;

super::ranker::lane_ranker!(Avx512Ranker, 16, sort_4x4);

/// [`LaneRanker::sort_4x4`](super::LaneRanker::sort_4x4) for sixteen 4x4
/// blocks: each block's order by a sorting network ([`order_words`]), then
/// its ring line as one in-register permute of its sixteen seeds; no ranks
/// in between.
#[target_feature(enable = "avx2,avx512f")]
#[inline]
fn sort_4x4(strips: &Strips, _ranks: &mut [[u32; MAX_LANES]; 16], group: GroupSeeds<'_>, lines: &mut [u32]) {
    let (seeds, origin, pws) = group.checked_4x4(16, lines);
    let order = order_words(strips);
    // Dword `k` of block `m`'s permute index: the low (k < 8) or high
    // (k >= 8) half of its order word, shifted right by `4 (k mod 8)` so
    // that nibble `k` is in bits 0..4, the only bits the permute reads.
    let halves = _mm512_setr_epi32(0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1);
    let shifts = _mm512_setr_epi32(0, 4, 8, 12, 16, 20, 24, 28, 0, 4, 8, 12, 16, 20, 24, 28);
    for (l, line) in lines.chunks_exact_mut(16).enumerate() {
        let word = _mm512_add_epi32(halves, _mm512_set1_epi32(2 * (l % 8) as i32));
        let index = _mm512_srlv_epi32(_mm512_permutexvar_epi32(word, order[l / 8]), shifts);
        // SAFETY: rows `origin + r pws + 4 l .. + 4` lie in `seeds`
        // (`checked_4x4` above); `line` is sixteen writable u32.
        unsafe {
            let p = seeds.as_ptr().add(origin + 4 * l) as *const __m128i;
            let block = _mm512_inserti64x4::<1>(
                _mm512_castsi256_si512(_mm256_loadu2_m128i(p.byte_add(4 * pws), p)),
                _mm256_loadu2_m128i(p.byte_add(12 * pws), p.byte_add(8 * pws)),
            );
            _mm512_storeu_epi32(
                line.as_mut_ptr() as *mut i32,
                _mm512_permutexvar_epi32(index, block),
            );
        }
    }
}

/// The order of each of sixteen 4x4 blocks, as a 64-bit word whose nibble
/// `k` is the block's pixel of rank `k` (key, then index: the order of
/// [`block_ranks`](super::block_ranks)); block `8 h + m`'s word is lane `m`
/// of register `h`. Eight blocks at a time, one per
/// 64-bit lane: pixel `i` of block `m` enters its wire as `key << 32 | i`
/// (the signed key above the index, so a signed 64-bit comparison orders
/// by key, then index), the wires are sorted by [`NETWORK`](super::network::NETWORK) (a minimum
/// and a maximum for eight blocks a comparator), and the index in the low
/// bits of wire `k` goes to nibble `k`.
#[target_feature(enable = "avx512f")]
#[inline]
fn order_words(strips: &Strips) -> [__m512i; 2] {
    // Dword `2m + 1` picks column `c` of block `m` (element `4m + c` of a
    // strip row's pair of registers, bit 4 the second); dword `2m` keeps
    // the pixel index (the permute's mask leaves even dwords from the
    // index vector itself).
    let columns = _mm512_setr_epi32(0, 0, 0, 4, 0, 8, 0, 12, 0, 16, 0, 20, 0, 24, 0, 28);
    let mut words = [_mm512_setzero_si512(); 2];
    for (half, words) in words.iter_mut().enumerate() {
        let mut wires = [_mm512_setzero_si512(); INPUTS];
        for (r, row) in strips.iter().enumerate().take(4) {
            // SAFETY: offsets up to 32 + 16 + 16 = 64 lie inside the row.
            let (a, b) = unsafe {
                let row = row.as_ptr().add(32 * half);
                (_mm512_loadu_epi32(row), _mm512_loadu_epi32(row.add(16)))
            };
            for c in 0..4 {
                let i = 4 * r + c;
                let index = _mm512_mask_blend_epi32(
                    0xAAAA,
                    _mm512_set1_epi32(i as i32),
                    _mm512_add_epi32(columns, _mm512_set1_epi32(c as i32)),
                );
                wires[i] = _mm512_mask2_permutex2var_epi32(a, index, 0xAAAA, b);
            }
        }
        for_each_comparator!(|a: usize, b: usize| {
            let (x, y) = (wires[a], wires[b]);
            wires[a] = _mm512_min_epi64(x, y);
            wires[b] = _mm512_max_epi64(x, y);
        });
        let mut order = _mm512_setzero_si512();
        for (k, wire) in wires.iter().enumerate() {
            let at = 4 * k as i64;
            let nibble = _mm512_and_si512(
                _mm512_sllv_epi64(*wire, _mm512_set1_epi64(at)),
                _mm512_set1_epi64(0xF << at),
            );
            order = _mm512_or_si512(order, nibble);
        }
        *words = order;
    }
    words
}
