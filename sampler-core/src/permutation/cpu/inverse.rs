//! Each block's inverse permutation (for every rank `k`, the pixel that
//! holds it) as sixteen 4-bit nibbles, built for a whole lane group of
//! 4x4 blocks at once with AVX2 variable shifts: pixel `i` adds
//! `i << 4 rank_i` to a low word for ranks 0..8 and to a high word for
//! ranks 8..16 (a variable shift by 32 or more gives 0, which leaves the
//! other word alone). [`rank_order`] then spreads one block's nibbles into
//! bytes, the permute indices that build its ring line in registers.

use super::MAX_LANES;
use core::arch::x86_64::{
    __m128i, __m256i, _mm256_loadu_si256, _mm256_or_si256, _mm256_set1_epi32, _mm256_setzero_si256,
    _mm256_slli_epi32, _mm256_sllv_epi32, _mm256_storeu_si256, _mm256_sub_epi32, _mm_and_si128,
    _mm_cvtsi64_si128, _mm_set1_epi8, _mm_srli_epi16, _mm_unpacklo_epi8,
};

/// The nibble-packed inverse permutations of a lane group of eight blocks:
/// `(low, high)`, where nibble `k` of block `l`'s `low[l]` is the pixel of
/// rank `k < 8` and nibble `k - 8` of `high[l]` the pixel of rank `k >= 8`
/// (`ranks[i][l]` is pixel `i`'s rank; each block's a permutation of
/// `0..16`; lanes `8..` of the result are 0).
#[target_feature(enable = "avx2")]
#[inline]
pub(super) fn inverse_nibbles(ranks: &[[u32; MAX_LANES]; 16]) -> ([u32; MAX_LANES], [u32; MAX_LANES]) {
    // Pixel `i`'s value `i` shifted to nibble `rank` of the low word, less
    // `word` bits: 0 where that is 32 or more, or negative.
    let nibble_at = |pixel: __m256i, rank: __m256i, word: i32| {
        _mm256_sllv_epi32(
            pixel,
            _mm256_sub_epi32(_mm256_slli_epi32::<2>(rank), _mm256_set1_epi32(word)),
        )
    };
    let (mut low, mut high) = (_mm256_setzero_si256(), _mm256_setzero_si256());
    for (i, rank) in ranks.iter().enumerate().skip(1) {
        // SAFETY: `rank` holds sixteen u32 (32 readable bytes).
        let rank = unsafe { _mm256_loadu_si256(rank.as_ptr() as *const __m256i) };
        let pixel = _mm256_set1_epi32(i as i32);
        low = _mm256_or_si256(low, nibble_at(pixel, rank, 0));
        high = _mm256_or_si256(high, nibble_at(pixel, rank, 32));
    }
    let (mut low_words, mut high_words) = ([0u32; MAX_LANES], [0u32; MAX_LANES]);
    // SAFETY: each array holds sixteen u32 (32 writable bytes).
    unsafe {
        _mm256_storeu_si256(low_words.as_mut_ptr() as *mut __m256i, low);
        _mm256_storeu_si256(high_words.as_mut_ptr() as *mut __m256i, high);
    }
    (low_words, high_words)
}

/// Byte `k` of the result: the pixel of rank `k` in the block whose
/// order word is `word` (nibble `k` the pixel of rank `k`: the nibble
/// words of [`inverse_nibbles`] as `low | high << 32`).
#[target_feature(enable = "sse2")]
#[inline]
pub(super) fn rank_order(word: u64) -> __m128i {
    let x = _mm_cvtsi64_si128(word as i64);
    let nibble = _mm_set1_epi8(0x0F);
    // Low nibbles hold the even ranks, high nibbles the odd ones.
    _mm_unpacklo_epi8(
        _mm_and_si128(x, nibble),
        _mm_and_si128(_mm_srli_epi16::<4>(x), nibble),
    )
}
