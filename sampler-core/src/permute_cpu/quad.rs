//! The all-pairs ranking of sixteen pixels held one per register, a block
//! per 32-bit lane, generic over the x86 vector width ([`Lanes`]: SSE2's
//! four lanes, AVX2's eight). Each unordered pair `i < j` costs one compare
//! and two updates for every lane: pixel `j` starts at rank `j` (every
//! `i < j` counted below it) and gives one back to `i` when `key_i >
//! key_j` (the compare mask is -1 there), so ties rank by index for free.
//! Pixels are taken four at a time, their keys and ranks kept in
//! registers, so each later pixel's rank is read and written once per quad,
//! not once per pair. The AVX-512 ranker has its own form (mask registers).

use core::arch::x86_64::{
    __m128i, __m256i, _mm256_add_epi32, _mm256_cmpgt_epi32, _mm256_set1_epi32, _mm256_sub_epi32,
    _mm_add_epi32, _mm_cmpgt_epi32, _mm_set1_epi32, _mm_sub_epi32,
};

/// The 32-bit lane operations of one x86 vector register that the ranking
/// uses.
///
/// # Safety
/// Each function executes the register's instruction set (SSE2 for
/// `__m128i`, AVX2 for `__m256i`): call them only where the CPU has it.
pub(super) trait Lanes: Copy {
    /// `v` in every lane.
    unsafe fn splat(v: i32) -> Self;
    /// -1 in the lanes where `a > b` (signed), 0 elsewhere.
    unsafe fn greater(a: Self, b: Self) -> Self;
    /// Lane-wise wrapping `a + b`.
    unsafe fn add(a: Self, b: Self) -> Self;
    /// Lane-wise wrapping `a - b`.
    unsafe fn sub(a: Self, b: Self) -> Self;
}

impl Lanes for __m128i {
    #[inline(always)]
    unsafe fn splat(v: i32) -> Self {
        // SAFETY: the caller's contract (the trait's).
        unsafe { _mm_set1_epi32(v) }
    }
    #[inline(always)]
    unsafe fn greater(a: Self, b: Self) -> Self {
        // SAFETY: the caller's contract (the trait's).
        unsafe { _mm_cmpgt_epi32(a, b) }
    }
    #[inline(always)]
    unsafe fn add(a: Self, b: Self) -> Self {
        // SAFETY: the caller's contract (the trait's).
        unsafe { _mm_add_epi32(a, b) }
    }
    #[inline(always)]
    unsafe fn sub(a: Self, b: Self) -> Self {
        // SAFETY: the caller's contract (the trait's).
        unsafe { _mm_sub_epi32(a, b) }
    }
}

impl Lanes for __m256i {
    #[inline(always)]
    unsafe fn splat(v: i32) -> Self {
        // SAFETY: the caller's contract (the trait's).
        unsafe { _mm256_set1_epi32(v) }
    }
    #[inline(always)]
    unsafe fn greater(a: Self, b: Self) -> Self {
        // SAFETY: the caller's contract (the trait's).
        unsafe { _mm256_cmpgt_epi32(a, b) }
    }
    #[inline(always)]
    unsafe fn add(a: Self, b: Self) -> Self {
        // SAFETY: the caller's contract (the trait's).
        unsafe { _mm256_add_epi32(a, b) }
    }
    #[inline(always)]
    unsafe fn sub(a: Self, b: Self) -> Self {
        // SAFETY: the caller's contract (the trait's).
        unsafe { _mm256_sub_epi32(a, b) }
    }
}

/// Each pixel's rank in its lane's total order (key, then pixel index):
/// `keys[i]` holds pixel `i` of every lane, as signed keys.
///
/// # Safety
/// The CPU has `V`'s instruction set ([`Lanes`]).
#[inline(always)]
pub(super) unsafe fn rank_sixteen<V: Lanes>(keys: &[V; 16]) -> [V; 16] {
    // SAFETY: the caller's contract.
    unsafe {
        let mut ranks: [V; 16] = core::array::from_fn(|j| V::splat(j as i32));
        rank_quad::<V, 0>(keys, &mut ranks);
        rank_quad::<V, 4>(keys, &mut ranks);
        rank_quad::<V, 8>(keys, &mut ranks);
        rank_quad::<V, 12>(keys, &mut ranks);
        ranks
    }
}

/// Pixels `Q..Q + 4` against each other and against every later pixel
/// (`Q` a constant, so the loop over later pixels unrolls).
///
/// # Safety
/// As for [`rank_sixteen`].
#[inline(always)]
unsafe fn rank_quad<V: Lanes, const Q: usize>(keys: &[V; 16], ranks: &mut [V; 16]) {
    // SAFETY: the caller's contract (as for `rank_sixteen`).
    unsafe {
        let k: [V; 4] = core::array::from_fn(|a| keys[Q + a]);
        let mut acc: [V; 4] = core::array::from_fn(|a| ranks[Q + a]);
        for a in 0..4 {
            for b in a + 1..4 {
                let greater = V::greater(k[a], k[b]);
                acc[a] = V::sub(acc[a], greater);
                acc[b] = V::add(acc[b], greater);
            }
        }
        for j in Q + 4..16 {
            let kj = keys[j];
            let g: [V; 4] = core::array::from_fn(|a| V::greater(k[a], kj));
            for a in 0..4 {
                acc[a] = V::sub(acc[a], g[a]);
            }
            let given = V::add(V::add(g[0], g[1]), V::add(g[2], g[3]));
            ranks[j] = V::add(ranks[j], given);
        }
        ranks[Q..Q + 4].copy_from_slice(&acc);
    }
}
