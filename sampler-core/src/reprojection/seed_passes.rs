//! The reprojection's take, list and recycle passes one seed at a time: the
//! form for hardware GPUs.
//!
//! [`passes`](super::passes) runs passes 3, 5 and 6 as one invocation per
//! chunk of [`REPROJECT_CHUNK`] seeds walking its chunk in order (a running
//! count gives each pixel without a seed, and each unclaimed source, its
//! place in the recycling order). That is a few thousand invocations with
//! long serial loops, each step recomputing a claim: cheap on a CPU
//! rasteriser, slow on a GPU. The same output, bit for bit, comes from one
//! invocation per seed and a flags word per seed:
//!
//! | pass | invocations | reads | writes |
//! |---|---|---|---|
//! | 3a. take | one per seed | motion, claims, seeds in | winners' and padding seeds out; `flags[i]` ([`take_seed`]) |
//! | 3b. count | one workgroup of [`COUNT_LANES`] per chunk | flags | the chunk's two counts ([`count_chunk_flags`], in lane segments: [`count_lane_flags`]) |
//! | 4. scan | as in [`passes`](super::passes) | | |
//! | 5. list | one per seed | flags, offsets | `free[k]` for an unclaimed source ([`list_free_seed`]) |
//! | 6. recycle | one per seed | flags, offsets, free list, seeds in | the seed of a pixel without one ([`recycle_seed`]) |
//!
//! A flagged seed finds its place by counting the same flag on the seeds
//! before it in its chunk: the running count of the chunk passes. The count
//! pass reads one word per seed instead of recomputing claims. Clear, claim
//! and scan are the chunk form's.

use super::claims::{index_bits, CLAIM_NONE};
use super::passes::{chunk_range, claim_of, is_visible, REPROJECT_CHUNK};
use crate::permutation::layout::FrameParams;
use glam::Vec2;

/// Flag of a visible pixel that took no seed in pass 3a (it lost its claim,
/// or had no source): it gets a recycled seed in pass 6.
pub const FLAG_NEEDS_SEED: u32 = 1;
/// Flag of a visible pixel that nobody claimed: its seed is recycled.
pub const FLAG_FREE_SOURCE: u32 = 2;

/// Pass 3a for padded-buffer index `i` (`< params.seed_count()`): a winner
/// takes its source's seed and a padding seed stays (both into
/// `seeds_out[i]`); `flags[i]` gets [`FLAG_NEEDS_SEED`] and
/// [`FLAG_FREE_SOURCE`] as they hold (`0` for padding). `claims` holds every
/// claim (pass 2 done).
#[inline]
pub fn take_seed(
    params: &FrameParams,
    i: u32,
    motion: &[Vec2],
    claims: &[u32],
    seeds_in: &[u32],
    seeds_out: &mut [u32],
    flags: &mut [u32],
) {
    if !is_visible(params, i) {
        seeds_out[i as usize] = seeds_in[i as usize];
        flags[i as usize] = 0;
        return;
    }
    let (source, key) = claim_of(params, index_bits(params.seed_count()), i, motion);
    let mut flag = 0;
    if source != CLAIM_NONE && claims[source as usize] == key {
        seeds_out[i as usize] = seeds_in[source as usize];
    } else {
        flag |= FLAG_NEEDS_SEED;
    }
    if claims[i as usize] == CLAIM_NONE {
        flag |= FLAG_FREE_SOURCE;
    }
    flags[i as usize] = flag;
}

/// The first index of the chunk holding `i`, and the chunk.
#[inline]
fn chunk_of(i: u32) -> (u32, u32) {
    let chunk = i / REPROJECT_CHUNK;
    (chunk.wrapping_mul(REPROJECT_CHUNK), chunk)
}

/// Invocations that count one chunk's flags on the GPU (one workgroup,
/// `kernels::reproject_entry::count_flags_cs`): each sums
/// `REPROJECT_CHUNK / COUNT_LANES` consecutive flags ([`count_lane_flags`]),
/// then one lane adds the lanes' sums.
pub const COUNT_LANES: u32 = 64;

const _: () = assert!(REPROJECT_CHUNK.is_multiple_of(COUNT_LANES));

/// The sums `(pixels without a seed, unclaimed sources)` of the flags at
/// indices `[start, end)`.
#[inline]
fn sum_flags(flags: &[u32], start: u32, end: u32) -> (u32, u32) {
    let mut need = 0u32;
    let mut free = 0u32;
    let mut j = start;
    while j < end {
        let f = flags[j as usize];
        need = need.wrapping_add(f & FLAG_NEEDS_SEED);
        free = free.wrapping_add((f & FLAG_FREE_SOURCE) >> 1);
        j = j.wrapping_add(1);
    }
    (need, free)
}

/// Pass 3b for chunk `chunk`: `counts[2 * chunk]` = its pixels without a
/// seed, `counts[2 * chunk + 1]` = its unclaimed sources (what the chunk
/// form's take pass writes), from the flags of pass 3a.
#[inline]
pub fn count_chunk_flags(params: &FrameParams, chunk: u32, flags: &[u32], counts: &mut [u32]) {
    let (start, end) = chunk_range(params, chunk);
    let (need, free) = sum_flags(flags, start, end);
    counts[(chunk * 2) as usize] = need;
    counts[(chunk * 2 + 1) as usize] = free;
}

/// Lane `lane` (`< COUNT_LANES`) of pass 3b on the GPU: the sums of its
/// segment of chunk `chunk`'s flags. The lanes' sums add up to what
/// [`count_chunk_flags`] writes.
#[inline]
pub fn count_lane_flags(params: &FrameParams, chunk: u32, lane: u32, flags: &[u32]) -> (u32, u32) {
    let per = REPROJECT_CHUNK / COUNT_LANES;
    let (chunk_start, chunk_end) = chunk_range(params, chunk);
    let start = chunk_start.wrapping_add(lane.wrapping_mul(per));
    sum_flags(flags, start, start.wrapping_add(per).min(chunk_end))
}

/// Pass 5 for index `i`: an unclaimed source writes itself to `free[k]`,
/// `k` = its chunk's offset (`counts[2 * chunk + 1]` after the scan) plus
/// the unclaimed sources before it in the chunk.
#[inline]
pub fn list_free_seed(i: u32, flags: &[u32], counts: &[u32], free: &mut [u32]) {
    if flags[i as usize] & FLAG_FREE_SOURCE != 0 {
        let (start, chunk) = chunk_of(i);
        let k = counts[(chunk * 2 + 1) as usize].wrapping_add(sum_flags(flags, start, i).1);
        free[k as usize] = i;
    }
}

/// Pass 6 for index `i`: a pixel without a seed takes `seeds_in[free[k]]`,
/// `k` = its chunk's offset (`counts[2 * chunk]` after the scan) plus the
/// pixels without a seed before it in the chunk.
#[inline]
pub fn recycle_seed(
    i: u32,
    flags: &[u32],
    counts: &[u32],
    free: &[u32],
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) {
    if flags[i as usize] & FLAG_NEEDS_SEED != 0 {
        let (start, chunk) = chunk_of(i);
        let k = counts[(chunk * 2) as usize].wrapping_add(sum_flags(flags, start, i).0);
        seeds_out[i as usize] = seeds_in[free[k as usize] as usize];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::permutation::layout::FrameLayout;

    /// The lanes' sums add up to the chunk's counts, short last chunk included.
    #[test]
    fn lane_sums_add_up_to_the_chunk_counts() {
        let layout = FrameLayout::new(70, 5, 4, 64).unwrap();
        let params = layout.params(0);
        let n = layout.seed_count();
        let mut flags = [0u32; 128 * 64];
        for (i, f) in flags[..n].iter_mut().enumerate() {
            *f = (i as u32).wrapping_mul(0x9e37_79b9) >> 30;
        }
        let chunks = super::super::passes::chunk_count(&params);
        let mut counts = [0u32; 2 * 32];
        for c in 0..chunks {
            count_chunk_flags(&params, c, &flags[..n], &mut counts);
            let (mut need, mut free) = (0, 0);
            for lane in 0..COUNT_LANES {
                let (a, b) = count_lane_flags(&params, c, lane, &flags[..n]);
                need += a;
                free += b;
            }
            assert_eq!(
                (need, free),
                (counts[2 * c as usize], counts[2 * c as usize + 1]),
                "chunk {c}"
            );
            assert!(need > 0 && free > 0, "chunk {c} must count something");
        }
    }
}
