//! The AVX2 ranker for 4x4 blocks: eight blocks, one per 32-bit lane of a
//! 256-bit register, so each pixel pair of the all-pairs ranking
//! ([`rank_sixteen`]) is one compare, one subtract and one add for all
//! eight blocks, and the strips are transposed into lanes with eight
//! unpacks per row instead of scalar moves. Each block's ring line is then
//! built in registers from its inverse permutation ([`place_seeds_4x4`]).
//!
//! Selected at run time ([`Isa`](super::Isa): CPUID and XGETBV, no `std` needed);
//! the whole frame loop is compiled with AVX2 enabled so the key conversion
//! vectorises eight wide too. The output is bit-identical to the portable
//! path (tested in `rows` on this CPU when it has AVX2, and by the
//! conformance property tests).

use super::inverse::{inverse_nibbles, rank_order};
use super::ranker::GroupSeeds;
use super::{detect, Band, Strips, MAX_LANES};
use crate::permutation::layout::FrameParams;
use crate::permutation::retarget::RetargetTable;
use crate::permutation::sort::Intensity;
use core::arch::x86_64::{
    __m128i, __m256i, _mm256_add_epi32, _mm256_blendv_ps, _mm256_castps_si256, _mm256_castsi256_ps,
    _mm256_cmpgt_epi32, _mm256_cvtepu8_epi32, _mm256_loadu2_m128i, _mm256_permutevar8x32_epi32,
    _mm256_set1_epi32, _mm256_slli_epi32, _mm256_storeu_si256, _mm256_sub_epi32, _mm256_unpackhi_epi32,
    _mm256_unpackhi_epi64, _mm256_unpacklo_epi32, _mm256_unpacklo_epi64, _mm_srli_si128,
};

/// True when the CPU and the operating system support AVX2 (checked once,
/// by [`detect`]).
pub(crate) fn available() -> bool {
    detect::avx2_available()
}

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
    assert!(available() && params.block == 4);
    // SAFETY: the instruction set is available (checked above).
    unsafe { gather_4x4_avx2(params, intensities, tile, table, seeds_in, band, seeds_out) }
}

#[target_feature(enable = "avx2")]
fn gather_4x4_avx2<T: Intensity>(
    params: &FrameParams,
    intensities: &[T],
    tile: &[u32],
    table: RetargetTable<'_>,
    seeds_in: &[u32],
    band: Band,
    seeds_out: &mut [u32],
) {
    super::gather::permute_gather::<T, Avx2Ranker, 4, 16>(
        params,
        intensities,
        tile,
        table,
        seeds_in,
        band,
        seeds_out,
    );
}

/// Only instantiated inside [`gather_4x4_avx2`], i.e. with AVX2 present.
struct Avx2Ranker;

super::ranker::lane_ranker!(Avx2Ranker, 8, sort_4x4);

/// [`LaneRanker::sort_4x4`](super::LaneRanker::sort_4x4) for eight 4x4
/// blocks: [`rank_4x4`], then [`place_seeds_4x4`].
#[target_feature(enable = "avx2")]
#[inline]
fn sort_4x4(strips: &Strips, ranks: &mut [[u32; MAX_LANES]; 16], group: GroupSeeds<'_>, lines: &mut [u32]) {
    rank_4x4(strips, ranks);
    place_seeds_4x4(ranks, group, lines);
}

/// Places eight 4x4 blocks' seeds by rank into their ring lines (see
/// [`LaneRanker::sort_group`](super::LaneRanker::sort_group)), with no scattered store: each block's inverse permutation as
/// nibbles ([`inverse`](super::inverse)), then its line as two in-register
/// permutes of its sixteen seeds.
#[target_feature(enable = "avx2")]
#[inline]
fn place_seeds_4x4(ranks: &[[u32; MAX_LANES]; 16], group: GroupSeeds<'_>, lines: &mut [u32]) {
    let (seeds, origin, pws) = group.checked_4x4(8, lines);
    let (low, high) = inverse_nibbles(ranks);
    for (l, line) in lines.chunks_exact_mut(16).enumerate() {
        let order = rank_order(low[l] as u64 | (high[l] as u64) << 32);
        let first = _mm256_cvtepu8_epi32(order);
        let second = _mm256_cvtepu8_epi32(_mm_srli_si128::<8>(order));
        // SAFETY: rows `origin + r pws + 4 l .. + 4` lie in `seeds`
        // (`checked_4x4` above); `line` is sixteen writable u32.
        unsafe {
            let p = seeds.as_ptr().add(origin + 4 * l) as *const __m128i;
            let rows01 = _mm256_loadu2_m128i(p.byte_add(4 * pws), p);
            let rows23 = _mm256_loadu2_m128i(p.byte_add(12 * pws), p.byte_add(8 * pws));
            let pick = |index: __m256i| {
                let from01 = _mm256_castsi256_ps(_mm256_permutevar8x32_epi32(rows01, index));
                let from23 = _mm256_castsi256_ps(_mm256_permutevar8x32_epi32(rows23, index));
                // Pixels 8..16 (index bit 3) come from rows 2 and 3.
                let upper = _mm256_castsi256_ps(_mm256_slli_epi32::<28>(index));
                _mm256_castps_si256(_mm256_blendv_ps(from01, from23, upper))
            };
            let out = line.as_mut_ptr() as *mut __m256i;
            _mm256_storeu_si256(out, pick(first));
            _mm256_storeu_si256(out.add(1), pick(second));
        }
    }
}

/// Ranks of eight 4x4 blocks ([`rank_sixteen`]): `out[i][l]` is pixel
/// `i`'s rank in block `l` (lanes `8..` are left as they are).
/// Kept out of line: inlined into the frame loop it spilled (8% slower).
#[target_feature(enable = "avx2")]
#[inline(never)]
fn rank_4x4(strips: &Strips, out: &mut [[u32; MAX_LANES]; 16]) {
    let mut keys = [_mm256_set1_epi32(0); 16];
    for r in 0..4 {
        let row = strips[r].as_ptr();
        // Block l in the low half and block l + 4 in the high half: the
        // in-half 4x4 transposition below then leaves the lanes in block
        // order 0..8 with no cross-half shuffle.
        // SAFETY: offsets up to (l + 4) * 4 + 4 <= 32 lie inside the row.
        let v: [__m256i; 4] = core::array::from_fn(|l| unsafe {
            _mm256_loadu2_m128i(
                row.add((l + 4) * 4) as *const __m128i,
                row.add(l * 4) as *const __m128i,
            )
        });
        let t0 = _mm256_unpacklo_epi32(v[0], v[1]); // b0c0 b1c0 b0c1 b1c1 | b4.. b5..
        let t1 = _mm256_unpackhi_epi32(v[0], v[1]); // b0c2 b1c2 b0c3 b1c3 | ...
        let t2 = _mm256_unpacklo_epi32(v[2], v[3]); // b2c0 b3c0 b2c1 b3c1 | ...
        let t3 = _mm256_unpackhi_epi32(v[2], v[3]);
        keys[r * 4] = _mm256_unpacklo_epi64(t0, t2); // column 0 of blocks 0..8
        keys[r * 4 + 1] = _mm256_unpackhi_epi64(t0, t2);
        keys[r * 4 + 2] = _mm256_unpacklo_epi64(t1, t3);
        keys[r * 4 + 3] = _mm256_unpackhi_epi64(t1, t3);
    }
    let ranks = rank_sixteen(&keys);
    for (o, r) in out.iter_mut().zip(&ranks) {
        // SAFETY: `o` is sixteen u32, at least 32 writable bytes.
        unsafe { _mm256_storeu_si256(o.as_mut_ptr() as *mut __m256i, *r) };
    }
}

/// Each pixel's rank in its block's total order (key, then pixel index):
/// `keys[i]` holds pixel `i` of eight blocks, one a 32-bit lane, as signed
/// keys. Each unordered pair `i < j` costs one compare and two updates for
/// the eight: pixel `j` starts at rank `j` (every `i < j` counted below
/// it) and gives one back to `i` where `key_i > key_j` (the compare mask
/// is -1 there), so ties rank by index for free. Pixels are taken four at
/// a time, their keys and ranks kept in registers, so each later pixel's
/// rank is read and written once per quad, not once per pair.
#[target_feature(enable = "avx2")]
#[inline]
fn rank_sixteen(keys: &[__m256i; 16]) -> [__m256i; 16] {
    let mut ranks: [__m256i; 16] = core::array::from_fn(|j| _mm256_set1_epi32(j as i32));
    rank_quad::<0>(keys, &mut ranks);
    rank_quad::<4>(keys, &mut ranks);
    rank_quad::<8>(keys, &mut ranks);
    rank_quad::<12>(keys, &mut ranks);
    ranks
}

/// Pixels `Q..Q + 4` against each other and against every later pixel
/// (`Q` a constant, so the loop over later pixels unrolls).
#[target_feature(enable = "avx2")]
#[inline]
fn rank_quad<const Q: usize>(keys: &[__m256i; 16], ranks: &mut [__m256i; 16]) {
    let k: [__m256i; 4] = core::array::from_fn(|a| keys[Q + a]);
    let mut acc: [__m256i; 4] = core::array::from_fn(|a| ranks[Q + a]);
    for a in 0..4 {
        for b in a + 1..4 {
            let greater = _mm256_cmpgt_epi32(k[a], k[b]);
            acc[a] = _mm256_sub_epi32(acc[a], greater);
            acc[b] = _mm256_add_epi32(acc[b], greater);
        }
    }
    for j in Q + 4..16 {
        let kj = keys[j];
        let g: [__m256i; 4] = core::array::from_fn(|a| _mm256_cmpgt_epi32(k[a], kj));
        for a in 0..4 {
            acc[a] = _mm256_sub_epi32(acc[a], g[a]);
        }
        let given = _mm256_add_epi32(_mm256_add_epi32(g[0], g[1]), _mm256_add_epi32(g[2], g[3]));
        ranks[j] = _mm256_add_epi32(ranks[j], given);
    }
    ranks[Q..Q + 4].copy_from_slice(&acc);
}
