//! The `#[spirv]` entry points of the seed reprojection: one per pass of
//! `sampler_core::reprojection::passes`, thin wrappers so the GPU runs the
//! code the CPU runs (conformance compares them bit for bit with
//! `sampler_core::reproject_frame`).
//!
//! Bindings (descriptor set 0; `FrameParams` is a uniform, the rest storage
//! buffers; sizes in elements):
//!
//! | entry | 0 | 1 | 2 | 3 | 4 | 5 | 6 |
//! |---|---|---|---|---|---|---|---|
//! | [`CLEAR_CLAIMS_ENTRY`] | params | claims `[u32]` (out, `seed_count`) | | | | | |
//! | [`CLAIM_ENTRY`] | params | motion `[Vec2]` (`width * height`) | claims (atomic) | | | | |
//! | [`TAKE_ENTRY`] | params | motion | claims | seeds in `[u32]` | seeds out `[u32]` | counts `[u32]` (out, `2 * chunks`) | |
//! | [`SCAN_ENTRY`] | params | counts (in place) | | | | | |
//! | [`LIST_FREE_ENTRY`] | params | claims | counts | free `[u32]` (out, `seed_count`) | | | |
//! | [`RECYCLE_ENTRY`] | params | motion | claims | counts | free | seeds in | seeds out |
//!
//! Dispatch, in this order, each with `permute_entry::linear_dispatch(n)`:
//! clear `n = seed_count`, claim `n = width * height`, take `n = chunks`,
//! scan `n = 1` (one workgroup), list `n = chunks`, recycle `n = chunks`,
//! where `chunks = sampler_core::reprojection::passes::chunk_count(params)`.
//!
//! The per-seed form (`sampler_core::reprojection::seed_passes`, the same
//! output; faster on hardware GPUs) replaces take, list and recycle, with a
//! `flags` buffer (`[u32]`, `seed_count`):
//!
//! | entry | 0 | 1 | 2 | 3 | 4 | 5 | 6 |
//! |---|---|---|---|---|---|---|---|
//! | [`TAKE_SEED_ENTRY`] (`n = seed_count`) | params | motion | claims | seeds in | seeds out | flags (out) | |
//! | [`COUNT_FLAGS_ENTRY`] (`n = 64 * chunks`: a workgroup per chunk) | params | flags | counts (out) | | | | |
//! | [`LIST_FREE_SEED_ENTRY`] (`n = seed_count`, after scan) | params | flags | counts | free (out) | | | |
//! | [`RECYCLE_SEED_ENTRY`] (`n = seed_count`) | params | flags | counts | free | seeds in | seeds out | |

use crate::permute_entry::linear_id;
use glam::{UVec3, Vec2};
use sampler_core::reprojection::passes::{
    chunk_count, claim_pixel, clear_claim, list_free_chunk, offset_chunk_counts, recycle_chunk, scan_segment,
    sum_chunk_counts, take_chunk, SCAN_LANES,
};
use sampler_core::reprojection::seed_passes::{
    count_lane_flags, list_free_seed, recycle_seed, take_seed, COUNT_LANES,
};
use sampler_core::{FrameParams, CLAIM_NONE};
use spirv_std::arch::{atomic_u_min, workgroup_memory_barrier_with_group_sync};
use spirv_std::memory::{Scope, Semantics};
use spirv_std::spirv;

/// Entry point name of [`clear_claims_cs`].
pub const CLEAR_CLAIMS_ENTRY: &str = "reproject_entry::clear_claims_cs";
/// Entry point name of [`claim_cs`].
pub const CLAIM_ENTRY: &str = "reproject_entry::claim_cs";
/// Entry point name of [`take_cs`].
pub const TAKE_ENTRY: &str = "reproject_entry::take_cs";
/// Entry point name of [`scan_cs`].
pub const SCAN_ENTRY: &str = "reproject_entry::scan_cs";
/// Entry point name of [`list_free_cs`].
pub const LIST_FREE_ENTRY: &str = "reproject_entry::list_free_cs";
/// Entry point name of [`recycle_cs`].
pub const RECYCLE_ENTRY: &str = "reproject_entry::recycle_cs";
/// Entry point name of [`take_seed_cs`].
pub const TAKE_SEED_ENTRY: &str = "reproject_entry::take_seed_cs";
/// Entry point name of [`count_flags_cs`].
pub const COUNT_FLAGS_ENTRY: &str = "reproject_entry::count_flags_cs";
/// Entry point name of [`list_free_seed_cs`].
pub const LIST_FREE_SEED_ENTRY: &str = "reproject_entry::list_free_seed_cs";
/// Entry point name of [`recycle_seed_cs`].
pub const RECYCLE_SEED_ENTRY: &str = "reproject_entry::recycle_seed_cs";

/// Pass 1, one invocation per seed: every claims entry to `CLAIM_NONE`.
#[spirv(compute(threads(64)))]
pub fn clear_claims_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FrameParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] claims: &mut [u32],
) {
    let i = linear_id(id);
    if i < params.seed_count() {
        claims[i as usize] = clear_claim();
    }
}

/// Pass 2, one invocation per visible pixel (row-major): an atomic minimum
/// of the pixel's key into its source's claims entry (`claim_pixel`).
#[spirv(compute(threads(64)))]
pub fn claim_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FrameParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] motion: &[Vec2],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] claims: &mut [u32],
) {
    let i = linear_id(id);
    if i < params.pixel_count() {
        let (source, key) = claim_pixel(params, i % params.width, i / params.width, motion);
        if source != CLAIM_NONE {
            // SAFETY: an atomic on a storage-buffer element in bounds (`source`
            // is a visible pixel's index of the padded buffer). Queue-family
            // scope: every invocation of the dispatch is covered, and under the
            // Vulkan memory model it needs no extra capability (device scope
            // would need VulkanMemoryModelDeviceScope). No ordering semantics:
            // the result is read only by later dispatches, after a barrier.
            unsafe {
                atomic_u_min::<u32, { Scope::QueueFamily as u32 }, { Semantics::NONE.bits() }>(
                    &mut claims[source as usize],
                    key,
                );
            }
        }
    }
}

/// Pass 3, one invocation per chunk: `take_chunk`.
#[spirv(compute(threads(64)))]
pub fn take_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FrameParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] motion: &[Vec2],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] claims: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] seeds_in: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] seeds_out: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] counts: &mut [u32],
) {
    let c = linear_id(id);
    if c < chunk_count(params) {
        take_chunk(params, c, motion, claims, seeds_in, seeds_out, counts);
    }
}

const _: () = assert!(
    SCAN_LANES == crate::permute_entry::PERMUTE_WORKGROUP,
    "scan_cs is one 64-wide workgroup"
);

/// Pass 4, one workgroup of `SCAN_LANES` (= 64) invocations:
/// `scan_chunk_counts` in segments. Each lane sums its segment of chunks
/// (`scan_segment`, `sum_chunk_counts`), lane 0 turns the 64 sums into
/// exclusive offsets in workgroup memory, and each lane writes its
/// segment's offsets (`offset_chunk_counts`): the same integers as the
/// one-thread scan, in `2 * ceil(chunks / 64) + 64` serial steps instead
/// of `chunks`.
#[spirv(compute(threads(64)))]
pub fn scan_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(local_invocation_index)] lane: u32,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FrameParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] counts: &mut [u32],
    #[spirv(workgroup)] need: &mut [u32; SCAN_LANES as usize],
    #[spirv(workgroup)] free: &mut [u32; SCAN_LANES as usize],
) {
    // Only the first workgroup scans (uniform within each workgroup, so
    // the barriers below are reached by all of its invocations or none).
    if linear_id(id) >= SCAN_LANES {
        return;
    }
    let chunks = chunk_count(params);
    let (first, end) = scan_segment(chunks, lane);
    let (n, f) = sum_chunk_counts(counts, first, end);
    need[lane as usize] = n;
    free[lane as usize] = f;
    workgroup_memory_barrier_with_group_sync();
    if lane == 0 {
        let (mut n_sum, mut f_sum) = (0u32, 0u32);
        let mut l = 0usize;
        while l < SCAN_LANES as usize {
            let (n, f) = (need[l], free[l]);
            need[l] = n_sum;
            free[l] = f_sum;
            n_sum = n_sum.wrapping_add(n);
            f_sum = f_sum.wrapping_add(f);
            l += 1;
        }
    }
    workgroup_memory_barrier_with_group_sync();
    offset_chunk_counts(counts, first, end, need[lane as usize], free[lane as usize]);
}

/// Pass 5, one invocation per chunk: `list_free_chunk`.
#[spirv(compute(threads(64)))]
pub fn list_free_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FrameParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] claims: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] counts: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] free: &mut [u32],
) {
    let c = linear_id(id);
    if c < chunk_count(params) {
        list_free_chunk(params, c, claims, counts, free);
    }
}

/// Pass 6, one invocation per chunk: `recycle_chunk`.
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(64)))]
pub fn recycle_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FrameParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] motion: &[Vec2],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] claims: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counts: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] free: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] seeds_in: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 6)] seeds_out: &mut [u32],
) {
    let c = linear_id(id);
    if c < chunk_count(params) {
        recycle_chunk(params, c, motion, claims, counts, free, seeds_in, seeds_out);
    }
}

/// Pass 3a of the per-seed form, one invocation per seed: `take_seed`.
#[spirv(compute(threads(64)))]
pub fn take_seed_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FrameParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] motion: &[Vec2],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] claims: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] seeds_in: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] seeds_out: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] flags: &mut [u32],
) {
    let i = linear_id(id);
    if i < params.seed_count() {
        take_seed(params, i, motion, claims, seeds_in, seeds_out, flags);
    }
}

const _: () = assert!(
    COUNT_LANES == crate::permute_entry::PERMUTE_WORKGROUP,
    "count_flags_cs is one 64-wide workgroup per chunk"
);

/// Pass 3b of the per-seed form, one 64-wide workgroup per chunk (`n = 64 *
/// chunks`): each lane sums its segment of the chunk's flags
/// (`count_lane_flags`), lane 0 adds the 64 sums and writes the chunk's
/// counts: what `count_chunk_flags` writes, in 4 + 64 steps instead of 256.
#[spirv(compute(threads(64)))]
pub fn count_flags_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(local_invocation_index)] lane: u32,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FrameParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] flags: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] counts: &mut [u32],
    #[spirv(workgroup)] need: &mut [u32; COUNT_LANES as usize],
    #[spirv(workgroup)] free: &mut [u32; COUNT_LANES as usize],
) {
    // The chunk is the workgroup's (uniform within it, so every invocation
    // of a workgroup reaches the barrier or none does).
    let chunk = linear_id(id) / COUNT_LANES;
    if chunk >= chunk_count(params) {
        return;
    }
    let (n, f) = count_lane_flags(params, chunk, lane, flags);
    need[lane as usize] = n;
    free[lane as usize] = f;
    workgroup_memory_barrier_with_group_sync();
    if lane == 0 {
        let (mut n_sum, mut f_sum) = (0u32, 0u32);
        let mut l = 0usize;
        while l < COUNT_LANES as usize {
            n_sum = n_sum.wrapping_add(need[l]);
            f_sum = f_sum.wrapping_add(free[l]);
            l += 1;
        }
        counts[(chunk * 2) as usize] = n_sum;
        counts[(chunk * 2 + 1) as usize] = f_sum;
    }
}

/// Pass 5 of the per-seed form, one invocation per seed: `list_free_seed`.
#[spirv(compute(threads(64)))]
pub fn list_free_seed_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FrameParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] flags: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] counts: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] free: &mut [u32],
) {
    let i = linear_id(id);
    if i < params.seed_count() {
        list_free_seed(i, flags, counts, free);
    }
}

/// Pass 6 of the per-seed form, one invocation per seed: `recycle_seed`.
#[spirv(compute(threads(64)))]
pub fn recycle_seed_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FrameParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] flags: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] counts: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] free: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] seeds_in: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] seeds_out: &mut [u32],
) {
    let i = linear_id(id);
    if i < params.seed_count() {
        recycle_seed(i, flags, counts, free, seeds_in, seeds_out);
    }
}
