//! The baseline x86_64 ranker for 4x4 blocks: SSE2, which every x86_64 CPU
//! has, so it needs no detection. Eight blocks are ranked as two groups of
//! four, one block per 32-bit lane of a 128-bit register: the same
//! all-pairs ranking as [`avx2`](super::avx2), half as wide, with the
//! strips transposed into lanes by unpacks (a 4x4 transposition per strip
//! row and group) rather than the scalar moves the portable form leaves to
//! the compiler. Output is bit-identical to the portable ranker
//! (`quad_ranks` in [`ranker`](super::ranker); tested below and by the conformance
//! property tests).

use super::ranker::GroupSeeds;
use super::{Strips, MAX_LANES};
use core::arch::x86_64::{
    __m128i, _mm_extract_epi16, _mm_loadu_si128, _mm_set1_epi32, _mm_storeu_si128, _mm_unpackhi_epi32,
    _mm_unpackhi_epi64, _mm_unpacklo_epi32, _mm_unpacklo_epi64,
};

/// The ranker of the baseline instruction set on x86_64 (4x4 blocks; the
/// portable ranker for the other sizes).
pub(super) struct Sse2Ranker;

super::ranker::lane_ranker!(Sse2Ranker, 8, rank_4x4_both, place_seeds_4x4);

/// [`LaneRanker::place_4x4`](super::LaneRanker::place_4x4) for eight 4x4 blocks. Each pixel's eight
/// ranks are read as the two 128-bit words [`rank_4x4`] stored (a load at
/// a store's own address is forwarded from it; a 32-bit load from inside
/// it may wait for it to reach the cache) and taken apart in registers.
#[target_feature(enable = "sse2")]
#[inline]
fn place_seeds_4x4(ranks: &[[u32; MAX_LANES]; 16], group: GroupSeeds<'_>, lines: &mut [u32]) {
    assert!(lines.len() == 8 * 16 && group.covers(8, 4));
    let GroupSeeds {
        seeds,
        origin,
        pitch: pws,
    } = group;
    for (i, rank) in ranks.iter().enumerate() {
        let at = origin + (i / 4) * pws + i % 4;
        // SAFETY: `rank` holds sixteen u32 (two 16-byte loads); `at + 4 l`
        // for `l < 8` lies in `seeds` and `16 l + rank` (rank < 16) in
        // `lines` (both asserted above).
        unsafe {
            let low = _mm_loadu_si128(rank.as_ptr() as *const __m128i);
            let high = _mm_loadu_si128(rank.as_ptr().add(4) as *const __m128i);
            let ranks: [usize; 8] = [
                _mm_extract_epi16::<0>(low) as usize,
                _mm_extract_epi16::<2>(low) as usize,
                _mm_extract_epi16::<4>(low) as usize,
                _mm_extract_epi16::<6>(low) as usize,
                _mm_extract_epi16::<0>(high) as usize,
                _mm_extract_epi16::<2>(high) as usize,
                _mm_extract_epi16::<4>(high) as usize,
                _mm_extract_epi16::<6>(high) as usize,
            ];
            for (l, &k) in ranks.iter().enumerate() {
                *lines.get_unchecked_mut(16 * l + (k & 15)) = *seeds.get_unchecked(at + 4 * l);
            }
        }
    }
}

/// Ranks of eight 4x4 blocks, as two groups of four; see
/// [`LaneRanker::rank_strips`](super::LaneRanker::rank_strips).
#[target_feature(enable = "sse2")]
#[inline]
fn rank_4x4_both(strips: &Strips, out: &mut [[u32; MAX_LANES]; 16]) {
    rank_4x4::<0>(strips, out);
    rank_4x4::<1>(strips, out);
}

/// Ranks of the four 4x4 blocks of group `G` (blocks `4 G..4 G + 4` of the
/// strips, lanes `4 G..4 G + 4` of `out`); see [`LaneRanker::rank_strips`](super::LaneRanker::rank_strips).
#[target_feature(enable = "sse2")]
#[inline]
fn rank_4x4<const G: usize>(strips: &Strips, out: &mut [[u32; MAX_LANES]; 16]) {
    let mut keys = [_mm_set1_epi32(0); 16];
    for r in 0..4 {
        let row = &strips[r][G * 16..G * 16 + 16];
        // SAFETY: each load reads four i32 of `row` (16 entries).
        let v: [__m128i; 4] =
            core::array::from_fn(|l| unsafe { _mm_loadu_si128(row[l * 4..].as_ptr() as *const __m128i) });
        let t0 = _mm_unpacklo_epi32(v[0], v[1]); // b0c0 b1c0 b0c1 b1c1
        let t1 = _mm_unpackhi_epi32(v[0], v[1]); // b0c2 b1c2 b0c3 b1c3
        let t2 = _mm_unpacklo_epi32(v[2], v[3]); // b2c0 b3c0 b2c1 b3c1
        let t3 = _mm_unpackhi_epi32(v[2], v[3]);
        keys[r * 4] = _mm_unpacklo_epi64(t0, t2); // column 0 of blocks 0..4
        keys[r * 4 + 1] = _mm_unpackhi_epi64(t0, t2);
        keys[r * 4 + 2] = _mm_unpacklo_epi64(t1, t3);
        keys[r * 4 + 3] = _mm_unpackhi_epi64(t1, t3);
    }
    let ranks = rank_sixteen(&keys);
    for (o, r) in out.iter_mut().zip(&ranks) {
        // SAFETY: `o[4 G..4 G + 4]` is four writable u32 (G < 2).
        unsafe { _mm_storeu_si128(o[G * 4..G * 4 + 4].as_mut_ptr() as *mut __m128i, *r) };
    }
}

/// [`rank_sixteen`](super::quad::rank_sixteen) for SSE2, kept out of line:
/// inlined into [`rank_4x4`], with sixteen XMM registers, it measured 5-8%
/// slower on the whole frame (spills).
#[target_feature(enable = "sse2")]
#[inline(never)]
fn rank_sixteen(keys: &[__m128i; 16]) -> [__m128i; 16] {
    // SAFETY: this function is compiled for SSE2.
    unsafe { super::quad::rank_sixteen(keys) }
}

#[cfg(test)]
mod tests {
    use super::super::ranker::{LaneRanker, PortableRanker};
    use super::*;

    #[test]
    fn sse2_ranks_equal_portable_ranks() {
        let mut state = 7u32;
        for _ in 0..300 {
            let mut strips: Strips =
                [[0; MAX_LANES * super::super::MAX_FAST_BLOCK]; super::super::MAX_FAST_BLOCK];
            for row in strips.iter_mut().take(4) {
                for k in row.iter_mut().take(32) {
                    state = crate::seed::hash_u32(state);
                    // Few distinct keys (ties) across the whole i32 range.
                    *k = ((state % 5) as i32 - 2).wrapping_add(if state & 16 != 0 { i32::MIN } else { 0 });
                }
            }
            let (mut got, mut want) = ([[0u32; MAX_LANES]; 16], [[0u32; MAX_LANES]; 16]);
            Sse2Ranker::rank_strips::<4, 16>(&strips, &mut got);
            PortableRanker::rank_strips::<4, 16>(&strips, &mut want);
            assert_eq!(got, want);
        }
    }
}
