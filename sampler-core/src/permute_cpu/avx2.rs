//! The AVX2 ranker for 4x4 blocks: eight blocks, one per 32-bit lane of a
//! 256-bit register, so each pixel pair of the all-pairs ranking is one
//! compare, one subtract and one add for all eight blocks (twice the work
//! per instruction of the baseline SSE2 build), and the strips are
//! transposed into lanes with eight unpacks per row instead of scalar moves.
//!
//! Selected at run time ([`available`]: CPUID and XGETBV, no `std` needed);
//! the whole frame loop is compiled with AVX2 enabled so the key conversion
//! vectorises eight wide too. The output is bit-identical to the portable
//! path (tested below on this CPU when it has AVX2).

use super::{permute_full_blocks, LaneRanker, PortableRanker, LANES, MAX_FAST_BLOCK};
use crate::layout::FrameParams;
use crate::retarget::RetargetTable;
use crate::sort::Intensity;
use core::arch::x86_64::{
    __cpuid, __cpuid_count, __m128i, __m256i, _mm256_add_epi32, _mm256_cmpgt_epi32, _mm256_loadu2_m128i,
    _mm256_set1_epi32, _mm256_storeu_si256, _mm256_sub_epi32, _mm256_unpackhi_epi32, _mm256_unpackhi_epi64,
    _mm256_unpacklo_epi32, _mm256_unpacklo_epi64, _xgetbv,
};
use core::sync::atomic::{AtomicU8, Ordering};

/// Detection state: 0 not yet checked, 1 absent, 2 present.
static AVX2_STATE: AtomicU8 = AtomicU8::new(0);

/// True when the CPU and the operating system support AVX2 (checked once).
pub(crate) fn available() -> bool {
    match AVX2_STATE.load(Ordering::Relaxed) {
        1 => false,
        2 => true,
        _ => {
            let present = detect();
            AVX2_STATE.store(if present { 2 } else { 1 }, Ordering::Relaxed);
            present
        }
    }
}

/// CPUID leaf 1 (AVX and OSXSAVE), XCR0 (the OS saves the YMM state) and
/// CPUID leaf 7 (AVX2), as the Intel manual prescribes.
#[allow(unused_unsafe)] // CPUID is a safe intrinsic in newer toolchains
fn detect() -> bool {
    const ECX_OSXSAVE: u32 = 1 << 27;
    const ECX_AVX: u32 = 1 << 28;
    const XCR0_SSE_AVX: u64 = 0b110;
    const EBX_AVX2: u32 = 1 << 5;
    // SAFETY: every x86_64 CPU has CPUID.
    let max_leaf = unsafe { __cpuid(0) }.eax;
    if max_leaf < 7 {
        return false;
    }
    // SAFETY: as above.
    let leaf1 = unsafe { __cpuid(1) };
    if leaf1.ecx & (ECX_OSXSAVE | ECX_AVX) != ECX_OSXSAVE | ECX_AVX {
        return false;
    }
    // SAFETY: OSXSAVE is set, so XGETBV is available.
    let xcr0 = unsafe { _xgetbv(0) };
    if xcr0 & XCR0_SSE_AVX != XCR0_SSE_AVX {
        return false;
    }
    // SAFETY: leaf 7 exists (max_leaf >= 7).
    unsafe { __cpuid_count(7, 0) }.ebx & EBX_AVX2 != 0
}

/// The fast path for 4x4 blocks with the AVX2 ranker. Call only when
/// [`available`] is true.
pub(super) fn permute_4x4<T: Intensity>(
    params: &FrameParams,
    intensities: &[T],
    tile: &[u32],
    table: RetargetTable<'_>,
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) {
    debug_assert!(available() && params.block == 4);
    // SAFETY: the caller checked `available()`.
    unsafe { permute_4x4_avx2(params, intensities, tile, table, seeds_in, seeds_out) }
}

#[target_feature(enable = "avx2")]
fn permute_4x4_avx2<T: Intensity>(
    params: &FrameParams,
    intensities: &[T],
    tile: &[u32],
    table: RetargetTable<'_>,
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) {
    permute_full_blocks::<T, Avx2Ranker, 4, 16>(params, intensities, tile, table, seeds_in, seeds_out);
}

/// Only instantiated inside [`permute_4x4_avx2`], i.e. with AVX2 present.
struct Avx2Ranker;

impl LaneRanker for Avx2Ranker {
    #[inline(always)]
    fn rank_strips<const B: u32, const N: usize>(
        strips: &[[i32; LANES * MAX_FAST_BLOCK]; MAX_FAST_BLOCK],
    ) -> [[u32; LANES]; N] {
        if B != 4 || N != 16 {
            return PortableRanker::rank_strips::<B, N>(strips);
        }
        // SAFETY: this ranker only runs inside `permute_4x4_avx2`, which is
        // only called when AVX2 is available.
        let ranks = unsafe { rank_4x4(strips) };
        core::array::from_fn(|i| ranks[i])
    }
}

/// Ranks of eight 4x4 blocks; see [`LaneRanker::rank_strips`].
#[target_feature(enable = "avx2")]
#[inline]
fn rank_4x4(strips: &[[i32; LANES * MAX_FAST_BLOCK]; MAX_FAST_BLOCK]) -> [[u32; LANES]; 16] {
    let mut keys = [_mm256_set1_epi32(0); 16];
    for r in 0..4 {
        let row = strips[r].as_ptr();
        // Block l in the low half and block l + 4 in the high half: the
        // in-half 4x4 transposition below then leaves the lanes in block
        // order 0..8 with no cross-half shuffle.
        // SAFETY: offsets up to (l + 4) * 4 + 4 <= 32 lie inside the 64-entry row.
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
    // Pixel j starts at rank j (every i < j counted below it) and gives one
    // back to i when key_i > key_j: the compare mask is -1 there. Pixels are
    // taken four at a time, their keys and ranks kept in registers, so each
    // later pixel's rank is read and written once per quad, not per pair.
    let mut ranks: [__m256i; 16] = core::array::from_fn(|j| _mm256_set1_epi32(j as i32));
    for q in (0..16).step_by(4) {
        let k: [__m256i; 4] = core::array::from_fn(|a| keys[q + a]);
        let mut acc: [__m256i; 4] = core::array::from_fn(|a| ranks[q + a]);
        for a in 0..4 {
            for b in a + 1..4 {
                let greater = _mm256_cmpgt_epi32(k[a], k[b]);
                acc[a] = _mm256_sub_epi32(acc[a], greater);
                acc[b] = _mm256_add_epi32(acc[b], greater);
            }
        }
        for j in q + 4..16 {
            let kj = keys[j];
            let g: [__m256i; 4] = core::array::from_fn(|a| _mm256_cmpgt_epi32(k[a], kj));
            for a in 0..4 {
                acc[a] = _mm256_sub_epi32(acc[a], g[a]);
            }
            let given = _mm256_add_epi32(_mm256_add_epi32(g[0], g[1]), _mm256_add_epi32(g[2], g[3]));
            ranks[j] = _mm256_add_epi32(ranks[j], given);
        }
        ranks[q..q + 4].copy_from_slice(&acc);
    }
    let mut out = [[0u32; LANES]; 16];
    for (o, r) in out.iter_mut().zip(&ranks) {
        // SAFETY: `o` is eight u32, 32 writable bytes.
        unsafe { _mm256_storeu_si256(o.as_mut_ptr() as *mut __m256i, *r) };
    }
    out
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::defaults::{tables_64, tile_64};
    use crate::layout::FrameLayout;
    use crate::seed::hash_u32;
    use std::vec::Vec;

    #[test]
    fn avx2_path_equals_portable_path() {
        if !available() {
            std::println!("skipped: this CPU has no AVX2");
            return;
        }
        let tile = tile_64();
        let tables = tables_64();
        let mut state = 7u32;
        for (width, height) in [(64, 64), (200, 77), (1920 / 4, 1080 / 4), (37, 128)] {
            let layout = FrameLayout::new(width, height, 4, 64).unwrap();
            for frame in [0u32, 1, 5, 1000] {
                let params = layout.params(frame);
                let table = tables.table(crate::walk::step_index(frame, params.tile_log2));
                // Many ties, negative values, NaN and infinities.
                let intensities: Vec<f32> = (0..layout.pixel_count())
                    .map(|_| {
                        state = hash_u32(state);
                        match state % 11 {
                            0 => f32::NAN,
                            1 => f32::INFINITY,
                            2 => f32::NEG_INFINITY,
                            3 => -0.0,
                            4 => (state >> 28) as f32,
                            _ => f32::from_bits(state >> 2) - 1.0,
                        }
                    })
                    .collect();
                let seeds: Vec<u32> = (0..layout.seed_count() as u32).map(hash_u32).collect();
                let mut fast = std::vec![0u32; seeds.len()];
                let mut portable = std::vec![0u32; seeds.len()];
                permute_4x4(&params, &intensities, tile.values(), table, &seeds, &mut fast);
                super::super::permute_blocks_portable(
                    &params,
                    &intensities,
                    tile.values(),
                    table,
                    &seeds,
                    &mut portable,
                );
                assert_eq!(fast, portable, "{width}x{height} frame {frame}");
            }
        }
    }
}
