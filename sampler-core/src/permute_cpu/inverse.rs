//! Each block's inverse permutation (for every rank `k`, the pixel that
//! holds it) as sixteen 4-bit nibbles, built for a whole lane group of
//! 4x4 blocks at once with variable shifts (AVX2, AVX-512): pixel `i` adds
//! `i << 4 rank_i` to a low word for ranks 0..8 and to a high word for
//! ranks 8..16 (a variable shift by 32 or more gives 0, which leaves the
//! other word alone). [`rank_order`] then spreads one block's nibbles into
//! bytes, the permute indices that build its ring line in registers.

use super::MAX_LANES;
use core::arch::x86_64::{
    __m128i, __m256i, __m512i, _mm256_loadu_si256, _mm256_or_si256, _mm256_set1_epi32, _mm256_slli_epi32,
    _mm256_sllv_epi32, _mm256_storeu_si256, _mm256_sub_epi32, _mm512_loadu_epi32, _mm512_or_si512,
    _mm512_set1_epi32, _mm512_slli_epi32, _mm512_sllv_epi32, _mm512_storeu_epi32, _mm512_sub_epi32,
    _mm_and_si128, _mm_cvtsi64_si128, _mm_set1_epi8, _mm_srli_epi16, _mm_unpacklo_epi8,
};

/// The 32-bit lane operations of a register with variable shifts.
///
/// # Safety
/// Each function executes the register's instruction set (AVX2 for
/// `__m256i`, AVX-512 F for `__m512i`): call them only where the CPU has it.
pub(super) trait ShiftLanes: Copy {
    /// `v` in every lane.
    unsafe fn splat(v: i32) -> Self;
    /// Lanes `0..LANES` of `ranks` (a rank row of a lane group).
    unsafe fn load(ranks: &[u32; MAX_LANES]) -> Self;
    /// Lane-wise `a << (4 * rank)` for `rank` the lanes of `ranks`, less
    /// `word` bits: 0 where that is 32 or more, or negative.
    unsafe fn nibble_at(a: Self, ranks: Self, word: i32) -> Self;
    /// Lane-wise `a | b`.
    unsafe fn or(a: Self, b: Self) -> Self;
    /// Writes the lanes to `out[..LANES]`.
    unsafe fn store(v: Self, out: &mut [u32; MAX_LANES]);
}

impl ShiftLanes for __m256i {
    #[inline(always)]
    unsafe fn splat(v: i32) -> Self {
        // SAFETY (this impl): the caller's contract (the trait's); the
        // loads and stores stay inside the 16-entry arrays.
        unsafe { _mm256_set1_epi32(v) }
    }
    #[inline(always)]
    unsafe fn load(ranks: &[u32; MAX_LANES]) -> Self {
        unsafe { _mm256_loadu_si256(ranks.as_ptr() as *const __m256i) }
    }
    #[inline(always)]
    unsafe fn nibble_at(a: Self, ranks: Self, word: i32) -> Self {
        unsafe {
            _mm256_sllv_epi32(
                a,
                _mm256_sub_epi32(_mm256_slli_epi32::<2>(ranks), _mm256_set1_epi32(word)),
            )
        }
    }
    #[inline(always)]
    unsafe fn or(a: Self, b: Self) -> Self {
        unsafe { _mm256_or_si256(a, b) }
    }
    #[inline(always)]
    unsafe fn store(v: Self, out: &mut [u32; MAX_LANES]) {
        unsafe { _mm256_storeu_si256(out.as_mut_ptr() as *mut __m256i, v) }
    }
}

impl ShiftLanes for __m512i {
    #[inline(always)]
    unsafe fn splat(v: i32) -> Self {
        // SAFETY (this impl): as for `__m256i`.
        unsafe { _mm512_set1_epi32(v) }
    }
    #[inline(always)]
    unsafe fn load(ranks: &[u32; MAX_LANES]) -> Self {
        unsafe { _mm512_loadu_epi32(ranks.as_ptr() as *const i32) }
    }
    #[inline(always)]
    unsafe fn nibble_at(a: Self, ranks: Self, word: i32) -> Self {
        unsafe {
            _mm512_sllv_epi32(
                a,
                _mm512_sub_epi32(_mm512_slli_epi32::<2>(ranks), _mm512_set1_epi32(word)),
            )
        }
    }
    #[inline(always)]
    unsafe fn or(a: Self, b: Self) -> Self {
        unsafe { _mm512_or_si512(a, b) }
    }
    #[inline(always)]
    unsafe fn store(v: Self, out: &mut [u32; MAX_LANES]) {
        unsafe { _mm512_storeu_epi32(out.as_mut_ptr() as *mut i32, v) }
    }
}

/// The nibble-packed inverse permutations of a lane group's blocks:
/// `(low, high)`, where nibble `k` of block `l`'s `low[l]` is the pixel of
/// rank `k < 8` and nibble `k - 8` of `high[l]` the pixel of rank `k >= 8`
/// (`ranks[i][l]` is pixel `i`'s rank; each block's a permutation of
/// `0..16`).
///
/// # Safety
/// The CPU has `V`'s instruction set ([`ShiftLanes`]).
#[inline(always)]
pub(super) unsafe fn inverse_nibbles<V: ShiftLanes>(
    ranks: &[[u32; MAX_LANES]; 16],
) -> ([u32; MAX_LANES], [u32; MAX_LANES]) {
    // SAFETY: the caller's contract.
    unsafe {
        let (mut low, mut high) = (V::splat(0), V::splat(0));
        for (i, rank) in ranks.iter().enumerate().skip(1) {
            let (pixel, rank) = (V::splat(i as i32), V::load(rank));
            low = V::or(low, V::nibble_at(pixel, rank, 0));
            high = V::or(high, V::nibble_at(pixel, rank, 32));
        }
        let (mut low_words, mut high_words) = ([0u32; MAX_LANES], [0u32; MAX_LANES]);
        V::store(low, &mut low_words);
        V::store(high, &mut high_words);
        (low_words, high_words)
    }
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
