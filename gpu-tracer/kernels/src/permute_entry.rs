//! The `#[spirv]` entry points of the seed permutation: thin wrappers over
//! `sampler_core`'s per-block and per-seed functions, so the GPU runs exactly
//! the code the CPU runs (and the conformance tests compare them bit for bit).
//!
//! Bindings (descriptor set 0):
//!
//! | entry | 0 | 1 | 2 | 3 | 4 |
//! |---|---|---|---|---|---|
//! | [`INTENSITY_ENTRY`] | `FrameParams` (uniform) | colour `[Vec4]` | intensity `[f32]` (out) | | |
//! | [`SORT_ENTRY`] | `FrameParams` (uniform) | intensity `[f32]` | tile `[u32]` | seeds in `[u32]` | seeds out `[u32]` |
//! | [`SORT_RANK_ENTRY`] | `FrameParams` (uniform) | intensity `[f32]` | seeds in `[u32]` | ranked `[u32]` (out) | |
//! | [`SORT_GATHER_ENTRY`] | `FrameParams` (uniform) | tile `[u32]` | ranked `[u32]` | seeds out `[u32]` | |
//! | [`RETARGET_ENTRY`] | `FrameParams` (uniform) | table `[u32]` | seeds in `[u32]` | seeds out `[u32]` | |
//! | [`SEED_INIT_ENTRY`] | `FrameParams` (uniform; `frame` = salt) | seeds out `[u32]` | | | |
//!
//! The sorting pass comes in two forms that write the same seeds: [`SORT_ENTRY`]
//! (one invocation per block: the simplest to integrate, and the faster on a
//! CPU rasteriser) and [`SORT_RANK_ENTRY`] then [`SORT_GATHER_ENTRY`] (one
//! invocation per seed each, `sampler_core::sort_pixel`'s two passes: 2.4x
//! faster on an NVIDIA H100, where per-invocation arrays live in scratch
//! memory). The tracer picks by adapter (`gpu_tracer::gpu::PassForm`).
//!
//! The feature-aware permutation (`sampler_core::features::permute`) replaces
//! the sort and retarget passes with these (storage buffers after the
//! uniform `FrameParams` at binding 0; `thresholds` is one
//! `FeatureThresholds`, `features` `width * height` `SurfaceFeature`,
//! `links` and `links_b` `seed_count` `u32` scratch):
//!
//! | entry | 1 | 2 | 3 | 4 | 5 | 6 |
//! |---|---|---|---|---|---|---|
//! | [`SORT_FEATURES_ENTRY`] (per block) | intensity `[f32]` | features | thresholds | tile `[u32]` | seeds in | seeds out (sorted) |
//! | [`RECORD_LINK_ENTRY`] (per seed) | table `[u32]` | features | thresholds | links (out) | | |
//! | [`JUMP_LINK_ENTRY`] (per seed, `JUMP_ROUNDS` times, `links` and `links_b` in turn) | links in | links out | | | | |
//! | [`RETARGET_FEATURES_ENTRY`] (per seed) | table | links | features | thresholds | seeds in (sorted) | seeds out |
//!
//! (`JUMP_ROUNDS` is `sampler_core::features::permute::JUMP_ROUNDS`, even,
//! so the last round writes `links` again.)
//!
//! The feature-aware sort per seed (`sampler_core::features::sort_pixel`; the
//! seeds [`SORT_FEATURES_ENTRY`] writes), one invocation per seed each, with
//! `groups` and `ranked` `seed_count` `u32` scratch:
//!
//! | entry | 1 | 2 | 3 | 4 | 5 |
//! |---|---|---|---|---|---|
//! | [`SURFACE_GROUP_ENTRY`] | features | thresholds | groups (out) | | |
//! | [`SORT_RANK_FEATURES_ENTRY`] | intensity `[f32]` | groups | seeds in | ranked (out) | |
//! | [`SORT_GATHER_FEATURES_ENTRY`] | tile `[u32]` | groups | ranked | seeds out (sorted) | |

use glam::{UVec3, Vec4};
use sampler_core::features::permute::{
    jump_link, record_link, retarget_features_linked, sort_block_features_at_offset,
};
use sampler_core::features::sort_pixel::surface_group_pixel;
use sampler_core::{
    initial_seed, luma, retarget_pixel, sort_block_in_frame, sort_gather_pixel, sort_gather_pixel_in_groups,
    sort_rank_pixel, sort_rank_pixel_in_groups, walk_offset, FeatureThresholds, FrameParams, SurfaceFeature,
};
use spirv_std::spirv;

/// Entry point name of [`intensity_cs`].
pub const INTENSITY_ENTRY: &str = "permute_entry::intensity_cs";
/// Entry point name of [`sort_cs`].
pub const SORT_ENTRY: &str = "permute_entry::sort_cs";
/// Entry point name of [`sort_rank_cs`].
pub const SORT_RANK_ENTRY: &str = "permute_entry::sort_rank_cs";
/// Entry point name of [`sort_gather_cs`].
pub const SORT_GATHER_ENTRY: &str = "permute_entry::sort_gather_cs";
/// Entry point name of [`retarget_cs`].
pub const RETARGET_ENTRY: &str = "permute_entry::retarget_cs";
/// Entry point name of [`seed_init_cs`].
pub const SEED_INIT_ENTRY: &str = "permute_entry::seed_init_cs";
/// Entry point name of [`sort_features_cs`].
pub const SORT_FEATURES_ENTRY: &str = "permute_entry::sort_features_cs";
/// Entry point name of [`surface_group_cs`].
pub const SURFACE_GROUP_ENTRY: &str = "permute_entry::surface_group_cs";
/// Entry point name of [`sort_rank_features_cs`].
pub const SORT_RANK_FEATURES_ENTRY: &str = "permute_entry::sort_rank_features_cs";
/// Entry point name of [`sort_gather_features_cs`].
pub const SORT_GATHER_FEATURES_ENTRY: &str = "permute_entry::sort_gather_features_cs";
/// Entry point name of [`record_link_cs`].
pub const RECORD_LINK_ENTRY: &str = "permute_entry::record_link_cs";
/// Entry point name of [`jump_link_cs`].
pub const JUMP_LINK_ENTRY: &str = "permute_entry::jump_link_cs";
/// Entry point name of [`retarget_features_cs`].
pub const RETARGET_FEATURES_ENTRY: &str = "permute_entry::retarget_features_cs";
/// Invocations per workgroup of every permutation entry point.
pub const PERMUTE_WORKGROUP: u32 = 64;
/// Most workgroups a dispatch may have along one axis (Vulkan's guaranteed
/// minimum of `maxComputeWorkGroupCount`).
pub const MAX_GROUPS_X: u32 = 65535;

/// Dispatch size `(x, y)` in workgroups for `n` invocations of a linear
/// entry point: rows of `MAX_GROUPS_X` groups once one row is not enough.
pub fn linear_dispatch(n: u32) -> (u32, u32) {
    let groups = n.div_ceil(PERMUTE_WORKGROUP);
    if groups <= MAX_GROUPS_X {
        (groups.max(1), 1)
    } else {
        (MAX_GROUPS_X, groups.div_ceil(MAX_GROUPS_X))
    }
}

/// Linear invocation index of a [`linear_dispatch`] grid.
#[inline]
pub fn linear_id(id: UVec3) -> u32 {
    id.y.wrapping_mul(MAX_GROUPS_X * PERMUTE_WORKGROUP)
        .wrapping_add(id.x)
}

/// One invocation per visible pixel (linear index, see [`linear_dispatch`]): the sorting key of a
/// frame, Rec. 709 luma of its colour (`sampler_core::luma`).
#[spirv(compute(threads(64)))]
pub fn intensity_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FrameParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] color: &[Vec4],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] intensity: &mut [f32],
) {
    let i = linear_id(id);
    if i < params.width.wrapping_mul(params.height) {
        intensity[i as usize] = luma(color[i as usize].truncate());
    }
}

/// One invocation per block (linear index, row-major over
/// `blocks_x * blocks_y`): the sorting pass, `sampler_core::sort_block_in_frame`.
#[spirv(compute(threads(64)))]
pub fn sort_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FrameParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] intensity: &[f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] tile: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] seeds_in: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] seeds_out: &mut [u32],
) {
    let blocks_x = params.blocks_x();
    let i = linear_id(id);
    if i < blocks_x.wrapping_mul(params.blocks_y()) {
        let bx = i % blocks_x;
        let by = i / blocks_x;
        sort_block_in_frame(params, bx, by, intensity, tile, seeds_in, seeds_out);
    }
}

/// One invocation per seed (linear index over the padded buffer): pass 1 of
/// the two-pass sort, `sampler_core::sort_rank_pixel`.
#[spirv(compute(threads(64)))]
pub fn sort_rank_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FrameParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] intensity: &[f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] seeds_in: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] ranked: &mut [u32],
) {
    let i = linear_id(id);
    if i < params.seed_count() {
        sort_rank_pixel(params, i, intensity, seeds_in, ranked);
    }
}

/// One invocation per seed: pass 2 of the two-pass sort,
/// `sampler_core::sort_gather_pixel` at the walk's offset of `params.frame`
/// (what [`sort_cs`] writes, after [`sort_rank_cs`]).
#[spirv(compute(threads(64)))]
pub fn sort_gather_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FrameParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] tile: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] ranked: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] seeds_out: &mut [u32],
) {
    let i = linear_id(id);
    if i < params.seed_count() {
        let offset = walk_offset(params.frame, params.tile_log2);
        sort_gather_pixel(params, offset, i, tile, ranked, seeds_out);
    }
}

/// One invocation per seed (linear index over the padded buffer): the
/// retargeting scatter, `sampler_core::retarget_pixel`.
#[spirv(compute(threads(64)))]
pub fn retarget_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FrameParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] table: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] seeds_in: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] seeds_out: &mut [u32],
) {
    let i = linear_id(id);
    if i < params.seed_count() {
        retarget_pixel(params, i, table, seeds_in, seeds_out);
    }
}

/// One invocation per seed: white-noise seeds, `sampler_core::initial_seed`
/// with `params.frame` as the salt. Used for frame 0 and for the `white`
/// mode's fresh seeds every frame.
#[spirv(compute(threads(64)))]
pub fn seed_init_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FrameParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] seeds_out: &mut [u32],
) {
    let i = linear_id(id);
    if i < params.seed_count() {
        let x = i % params.padded_width;
        let y = i / params.padded_width;
        seeds_out[i as usize] = initial_seed(x, y, params.padded_width, params.frame);
    }
}

/// One invocation per block: the feature-aware sorting pass,
/// `sampler_core::features::permute::sort_block_features_at_offset` at the
/// walk's offset of `params.frame`.
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(64)))]
pub fn sort_features_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FrameParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] intensity: &[f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] features: &[SurfaceFeature],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] thresholds: &[FeatureThresholds],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] tile: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] seeds_in: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 6)] seeds_out: &mut [u32],
) {
    let blocks_x = params.blocks_x();
    let i = linear_id(id);
    if i < blocks_x.wrapping_mul(params.blocks_y()) {
        let offset = walk_offset(params.frame, params.tile_log2);
        sort_block_features_at_offset(
            params,
            offset,
            i % blocks_x,
            i / blocks_x,
            intensity,
            features,
            &thresholds[0],
            tile,
            seeds_in,
            seeds_out,
        );
    }
}

/// One invocation per seed: pass 1 of the feature-aware per-seed sort,
/// `sampler_core::features::sort_pixel::surface_group_pixel`.
#[spirv(compute(threads(64)))]
pub fn surface_group_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FrameParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] features: &[SurfaceFeature],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] thresholds: &[FeatureThresholds],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] groups: &mut [u32],
) {
    let i = linear_id(id);
    if i < params.seed_count() {
        surface_group_pixel(params, i, features, &thresholds[0], groups);
    }
}

/// One invocation per seed: pass 2 of the feature-aware per-seed sort,
/// `sampler_core::sort_rank_pixel_in_groups` with the groups of pass 1.
#[spirv(compute(threads(64)))]
pub fn sort_rank_features_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FrameParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] intensity: &[f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] groups: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] seeds_in: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] ranked: &mut [u32],
) {
    let i = linear_id(id);
    if i < params.seed_count() {
        sort_rank_pixel_in_groups(params, i, intensity, groups, seeds_in, ranked);
    }
}

/// One invocation per seed: pass 3 of the feature-aware per-seed sort,
/// `sampler_core::sort_gather_pixel_in_groups` at the walk's offset of
/// `params.frame` (what [`sort_features_cs`] writes).
#[spirv(compute(threads(64)))]
pub fn sort_gather_features_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FrameParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] tile: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] groups: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] ranked: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] seeds_out: &mut [u32],
) {
    let i = linear_id(id);
    if i < params.seed_count() {
        let offset = walk_offset(params.frame, params.tile_log2);
        sort_gather_pixel_in_groups(params, offset, i, tile, groups, ranked, seeds_out);
    }
}

/// One invocation per seed: the links of the frame's retarget permutation
/// cut at edges, `sampler_core::features::permute::record_link`.
#[spirv(compute(threads(64)))]
pub fn record_link_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FrameParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] table: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] features: &[SurfaceFeature],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] thresholds: &[FeatureThresholds],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] links: &mut [u32],
) {
    let i = linear_id(id);
    if i < params.seed_count() {
        let offset = walk_offset(params.frame, params.tile_log2);
        record_link(params, offset, table, features, &thresholds[0], i, links);
    }
}

/// One invocation per seed: one pointer-jumping round over the links,
/// `sampler_core::features::permute::jump_link`.
#[spirv(compute(threads(64)))]
pub fn jump_link_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FrameParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] links_in: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] links_out: &mut [u32],
) {
    let i = linear_id(id);
    if i < params.seed_count() {
        jump_link(i, links_in, links_out);
    }
}

/// One invocation per seed: the retarget cut at edges, following the
/// links to each chain's start,
/// `sampler_core::features::permute::retarget_features_linked`.
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(64)))]
pub fn retarget_features_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FrameParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] table: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] links: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] features: &[SurfaceFeature],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] thresholds: &[FeatureThresholds],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] seeds_in: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 6)] seeds_out: &mut [u32],
) {
    let i = linear_id(id);
    if i < params.seed_count() {
        let offset = walk_offset(params.frame, params.tile_log2);
        retarget_features_linked(
            params,
            offset,
            table,
            links,
            features,
            &thresholds[0],
            i,
            seeds_in,
            seeds_out,
        );
    }
}
