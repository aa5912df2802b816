//! The baseline x86_64 ranker for 4x4 blocks: SSE2, which every x86_64 CPU
//! has, so it needs no detection. Eight blocks at a time: their keys are
//! transposed into lanes by unpacks (a 4x4 transposition per strip row and
//! group of four blocks), each pixel pair compared in two registers of
//! four 32-bit lanes and the two masks packed into one register of eight
//! 16-bit lanes, so each count update serves all eight blocks
//! ([`rank_eight`]); then each seed is stored at its rank in its block's
//! ring line, one scalar store a seed ([`sort_4x4`]). Those 128 stores per
//! eight blocks are most of what the baseline spends beyond the ranking:
//! building the lines in registers, as the AVX2 and AVX-512 kernels do,
//! needs a permute by run-time indices, which SSE2 lacks (BENCHMARKS.md).
//! Output is bit-identical to the portable ranker (`quad_ranks` in
//! [`ranker`](super::ranker); tested below and by the conformance property
//! tests).

use super::ranker::GroupSeeds;
use super::{Strips, MAX_LANES};
use core::arch::x86_64::{
    __m128i, _mm_add_epi16, _mm_cmpgt_epi32, _mm_extract_epi16, _mm_loadu_si128, _mm_packs_epi32,
    _mm_set1_epi16, _mm_setzero_si128, _mm_sub_epi16, _mm_unpackhi_epi32, _mm_unpackhi_epi64,
    _mm_unpacklo_epi32, _mm_unpacklo_epi64,
};

/// The ranker of the baseline instruction set on x86_64 (4x4 blocks; the
/// portable ranker for the other sizes).
pub(super) struct Sse2Ranker;

super::ranker::lane_ranker!(Sse2Ranker, 8, sort_4x4);

/// [`LaneRanker::sort_4x4`](super::LaneRanker::sort_4x4) for eight 4x4
/// blocks: [`rank_eight`], then each seed stored at its rank in its
/// block's line, the rank taken from its pixel's register of eight.
#[target_feature(enable = "sse2")]
#[inline]
fn sort_4x4(strips: &Strips, _ranks: &mut [[u32; MAX_LANES]; 16], group: GroupSeeds<'_>, lines: &mut [u32]) {
    let (seeds, origin, pws) = group.checked_4x4(8, lines);
    let ranks = rank_eight(&transposed_keys(strips));
    for (i, &rank) in ranks.iter().enumerate() {
        let at = origin + (i / 4) * pws + i % 4;
        let ranks: [usize; 8] = [
            _mm_extract_epi16::<0>(rank) as usize,
            _mm_extract_epi16::<1>(rank) as usize,
            _mm_extract_epi16::<2>(rank) as usize,
            _mm_extract_epi16::<3>(rank) as usize,
            _mm_extract_epi16::<4>(rank) as usize,
            _mm_extract_epi16::<5>(rank) as usize,
            _mm_extract_epi16::<6>(rank) as usize,
            _mm_extract_epi16::<7>(rank) as usize,
        ];
        for (l, &k) in ranks.iter().enumerate() {
            // SAFETY: `at + 4 l` for `l < 8` lies in `seeds` and `16 l +
            // k` (`k < 16`) in `lines` (both checked by `checked_4x4` above).
            unsafe { *lines.get_unchecked_mut(16 * l + (k & 15)) = *seeds.get_unchecked(at + 4 * l) };
        }
    }
}

/// The keys of eight 4x4 blocks in lanes: `keys[i][g]` holds pixel `i`
/// (`r * 4 + c`) of blocks `4 g..4 g + 4`, one block a 32-bit lane.
#[target_feature(enable = "sse2")]
#[inline]
fn transposed_keys(strips: &Strips) -> [[__m128i; 2]; 16] {
    let mut keys = [[_mm_setzero_si128(); 2]; 16];
    for (r, row) in strips.iter().enumerate().take(4) {
        for g in 0..2 {
            let row = &row[g * 16..g * 16 + 16];
            // SAFETY: each load reads four i32 of `row` (16 entries).
            let v: [__m128i; 4] =
                core::array::from_fn(|l| unsafe { _mm_loadu_si128(row[l * 4..].as_ptr() as *const __m128i) });
            let t0 = _mm_unpacklo_epi32(v[0], v[1]); // b0c0 b1c0 b0c1 b1c1
            let t1 = _mm_unpackhi_epi32(v[0], v[1]); // b0c2 b1c2 b0c3 b1c3
            let t2 = _mm_unpacklo_epi32(v[2], v[3]); // b2c0 b3c0 b2c1 b3c1
            let t3 = _mm_unpackhi_epi32(v[2], v[3]);
            keys[r * 4][g] = _mm_unpacklo_epi64(t0, t2); // column 0 of blocks 0..4
            keys[r * 4 + 1][g] = _mm_unpackhi_epi64(t0, t2);
            keys[r * 4 + 2][g] = _mm_unpacklo_epi64(t1, t3);
            keys[r * 4 + 3][g] = _mm_unpackhi_epi64(t1, t3);
        }
    }
    keys
}

/// Each pixel's rank in its block (key, then index) for eight blocks, as
/// 16-bit lanes (block `l` in lane `l`): the all-pairs counting of the AVX2
/// ranker (`rank_sixteen` in [`avx2`](super::avx2)), its 32-bit compares
/// of blocks 0..4 and 4..8 packed into one register of eight 16-bit masks
/// (a pack keeps -1 and 0) so that each update counts for eight blocks.
/// Kept out of line: inlined into the frame loop, with sixteen XMM
/// registers, the ranking spilled.
#[target_feature(enable = "sse2")]
#[inline(never)]
fn rank_eight(keys: &[[__m128i; 2]; 16]) -> [__m128i; 16] {
    // Each pixel's rank less its index (its starting rank), added last.
    let mut ranks = [_mm_setzero_si128(); 16];
    rank_quad::<0>(keys, &mut ranks);
    rank_quad::<4>(keys, &mut ranks);
    rank_quad::<8>(keys, &mut ranks);
    rank_quad::<12>(keys, &mut ranks);
    core::array::from_fn(|j| _mm_add_epi16(ranks[j], _mm_set1_epi16(j as i16)))
}

/// Pixels `Q..Q + 4` against each other and against every later pixel:
/// where `key_a > key_j` (mask -1), `a` gains one and `j` gives one back.
#[target_feature(enable = "sse2")]
#[inline]
fn rank_quad<const Q: usize>(keys: &[[__m128i; 2]; 16], ranks: &mut [__m128i; 16]) {
    let greater = |a: [__m128i; 2], b: [__m128i; 2]| {
        _mm_packs_epi32(_mm_cmpgt_epi32(a[0], b[0]), _mm_cmpgt_epi32(a[1], b[1]))
    };
    let k: [[__m128i; 2]; 4] = core::array::from_fn(|a| keys[Q + a]);
    let mut acc: [__m128i; 4] = core::array::from_fn(|a| ranks[Q + a]);
    for a in 0..4 {
        for b in a + 1..4 {
            let g = greater(k[a], k[b]);
            acc[a] = _mm_sub_epi16(acc[a], g);
            acc[b] = _mm_add_epi16(acc[b], g);
        }
    }
    for j in Q + 4..16 {
        // The quad's keys are read again for each later pixel rather than
        // held: held, its eight key registers, four accumulators and the
        // later pixel's two keys outnumber SSE2's sixteen registers, and
        // LLVM spilled an accumulator, putting a store and its reload on
        // the loop's critical path (the baseline frame ran 7% slower). The
        // read is volatile so that it is not hoisted back; it adds no
        // instruction, since each compare overwrites a copy of the quad's
        // key anyway (SSE2's two-operand form), and the load is that copy.
        // SAFETY: a read through a reference, of a `Copy` value.
        let k: [[__m128i; 2]; 4] =
            core::array::from_fn(|a| unsafe { core::ptr::read_volatile(&keys[Q + a]) });
        let g: [__m128i; 4] = core::array::from_fn(|a| greater(k[a], keys[j]));
        for a in 0..4 {
            acc[a] = _mm_sub_epi16(acc[a], g[a]);
        }
        let given = _mm_add_epi16(_mm_add_epi16(g[0], g[1]), _mm_add_epi16(g[2], g[3]));
        ranks[j] = _mm_add_epi16(ranks[j], given);
    }
    ranks[Q..Q + 4].copy_from_slice(&acc);
}

#[cfg(test)]
mod tests {
    use super::super::ranker::portable_rank_strips;
    use super::*;
    use core::arch::x86_64::_mm_storeu_si128;

    #[test]
    fn sse2_ranks_equal_portable_ranks() {
        let mut state = 7u32;
        for _ in 0..300 {
            let mut strips: Strips =
                [[0; MAX_LANES * super::super::MAX_FAST_BLOCK]; super::super::MAX_FAST_BLOCK];
            for row in strips.iter_mut().take(4) {
                for k in row.iter_mut().take(32) {
                    state = crate::sequences::seed::hash_u32(state);
                    // Few distinct keys (ties) across the whole i32 range.
                    *k = ((state % 5) as i32 - 2).wrapping_add(if state & 16 != 0 { i32::MIN } else { 0 });
                }
            }
            let mut want = [[0u32; MAX_LANES]; 16];
            portable_rank_strips::<4, 16>(&strips, &mut want);
            // SAFETY: SSE2 is part of x86_64.
            let got = unsafe { rank_eight(&transposed_keys(&strips)) };
            for (i, (got, want)) in got.iter().zip(&want).enumerate() {
                let mut lanes = [0u16; 8];
                // SAFETY: eight u16 are 16 writable bytes.
                unsafe { _mm_storeu_si128(lanes.as_mut_ptr() as *mut __m128i, *got) };
                let want: [u16; 8] = core::array::from_fn(|l| want[l] as u16);
                assert_eq!(lanes, want, "pixel {i}");
            }
        }
    }
}
