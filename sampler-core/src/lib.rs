//! Blue-noise distribution of Monte Carlo error by permuting pixel seeds
//! between frames (Heitz & Belcour, EGSR 2019), plus the low-discrepancy
//! sequences and offset walk it stands on.
//!
//! # Guide
//!
//! Each pixel renders with a **seed** ([`sequences::seed`]) that defines all its random
//! numbers. After frame `t` is rendered, [`permute_frame`] permutes seeds
//! inside small blocks so that the frame's pixel values follow the ranks of a
//! blue-noise dither tile shifted by the walk offset `o_t` ([`permutation::sort`],
//! [`sequences::walk`]), then scatters them with a precomputed retarget table so they
//! follow the tile of frame `t + 1` ([`permutation::retarget`]). Render frame `t + 1` with
//! the new seeds: its error is distributed as blue noise in screen space.
//!
//! # Capabilities (one folder each; imports flow down this list only)
//!
//! | module | what it offers | entry points |
//! |---|---|---|
//! | [`limits`], [`error`] | the size limits every input is checked against; the crate's [`Error`] | |
//! | [`sequences`] | R1/R2/R_d ([`sequences::r2`]), the tile's offset walk ([`sequences::walk`]), seeds and random streams ([`sequences::seed`]), Sobol ([`sequences::sobol`]), Owen scrambling ([`sequences::owen`]), the a-priori screen-space samplers ([`sequences::screen_sobol`], [`sequences::zsobol`]) and the spatiotemporal one ([`sequences::spatiotemporal`]) | [`walk_offset`], [`initial_seed`], [`RandomStream`], [`ScreenSobolKeys::sample`], [`zsobol_sample`] |
//! | [`permutation`] | the seed permutation: frame layout, dither tile, sorting pass ([`permutation::sort`]; per seed for GPUs, [`permutation::sort_pixel`]), retargeting pass ([`permutation::retarget`]), the frame passes and their CPU fast path ([`permutation::frame`]), the temporally blue permutation ([`permutation::temporal`]) | [`permute_frame`], [`permute_frame_temporal`], [`permute_frame_rows`], [`sort_block_in_frame`], [`sort_rank_pixel`], [`retarget_pixel`] |
//! | [`reprojection`] | bijective reprojection of seeds along motion vectors, on the CPU and as GPU passes ([`reprojection::passes`] per chunk, [`reprojection::seed_passes`] per seed) | [`reproject_frame`] |
//! | [`features`] | the feature-aware permutation: sort within one surface, never retarget across an edge ([`features::surface`], [`features::permute`], its sort per seed [`features::sort_pixel`], against the temporal target [`features::temporal`]) | [`permute_frame_features`], [`permute_frame_features_temporal`], [`same_surface`] |
//! | [`masks`] | spatiotemporal (STBN-style) and filter-adapted blue-noise masks | [`SpatiotemporalMask`] |
//! | [`distributions`] | piecewise-constant 1D/2D distributions sampled by inverse CDF from caller-provided tables ([`distributions::piecewise`]), importance sampling of equirectangular environment maps ([`distributions::environment`]) | [`Distribution1d`], [`Distribution2d`], [`EnvironmentMap`] |
//! | `defaults` (feature `defaults`) | the baked tiles, tables, masks and sampler keys | `defaults::tile_64`, `defaults::tables_64`, `defaults::stbn_128`, `defaults::stbn_64`, `defaults::temporal_target`, `defaults::screen_sobol_keys` |
//! | `bake` (feature `bake`, host only) | the generators of that data: void-and-cluster, spatiotemporal and filter-adapted masks, exact retarget tables, sampler keys | `bake::bake_mask`, `bake::bake_stbn`, `bake::bake_retarget_table` |
//!
//! Everything a shader needs is `u32`/`f32` arithmetic with `wrapping_*`
//! operations, fixed-size arrays and no allocation, and compiles with
//! rust-gpu; the GPU kernels call the same functions ([`sort_block_in_frame`],
//! [`retarget_pixel`]). Sizes are validated by [`FrameLayout`],
//! [`DitherTile`] and [`RetargetTables`]; bad input is an [`Error`], never a
//! panic.
//!
//! Ready-made data: the cargo feature `defaults` (on by default, off in the
//! workspace dependency) compiles in 64x64 and 128x128 dither tiles with
//! their retarget tables and a 128x128x64 [`SpatiotemporalMask`] (module
//! `defaults`); the feature `bake` adds the host-only generators that made
//! them (module `bake`, also behind the `bake` CLI).
//!
//! ```
//! use sampler_core::*;
//! // The walk of a 64x64 tile visits 1024 distinct offsets in its first 1024 frames
//! // (the fixed step (48, 36) would cycle through 16)...
//! let mut seen: Vec<_> = (0..1024).map(|t| (walk_offset(t, 6).x, walk_offset(t, 6).y)).collect();
//! seen.sort();
//! seen.dedup();
//! assert_eq!(seen.len(), 1024);
//! // ...and steps only ever take the STEP_COUNT values the retarget tables cover.
//! assert!((0..4096).all(|t| step_index(t, 6) < STEP_COUNT as u32));
//! ```
#![no_std]
#![warn(missing_docs)]

#[cfg(feature = "bake")]
extern crate alloc;

#[cfg(feature = "bake")]
pub mod bake;
#[cfg(feature = "defaults")]
pub mod defaults;
pub mod distributions;
pub mod error;
pub mod features;
pub mod limits;
pub mod masks;
pub mod permutation;
pub mod reprojection;
pub mod sequences;

pub use distributions::environment::{EnvironmentMap, EnvironmentParams};
pub use distributions::piecewise::{Distribution1d, Distribution2d};
pub use error::{Buffer, Error};
pub use features::permute::permute_frame_features;
pub use features::surface::{demodulated_luma, same_surface, FeatureThresholds, SurfaceFeature, NO_SURFACE};
pub use features::temporal::permute_frame_features_temporal;
pub use limits::{MAX_BLOCK, MAX_KEY_LEVELS, MAX_KEY_TILE, MAX_TILE, MIN_BLOCK, RETARGET_RADIUS};
pub use masks::spatiotemporal::SpatiotemporalMask;
pub use permutation::cpu::rows::{band_seed_range, permute_frame_rows, permute_frame_rows_isa};
pub use permutation::cpu::Isa;
pub use permutation::dither::{tile_texel, DitherTile};
pub use permutation::frame::{
    permute_frame, permute_frame_baseline_isa, retarget_frame, retarget_pixel, retarget_pixel_at_offset,
    sort_block_at_offset, sort_block_in_frame, sort_frame,
};
pub use permutation::layout::{FrameLayout, FrameParams};
pub use permutation::retarget::{
    pack_offset, retarget_destination, unpack_offset, RetargetTable, RetargetTables, IDENTITY_PACKED,
};
pub use permutation::sort::{intensity_key, luma, sort_block, Intensity, DEFAULT_BLOCK, MAX_BLOCK_PIXELS};
pub use permutation::sort_pixel::{
    sort_gather_pixel, sort_gather_pixel_in_groups, sort_rank_pixel, sort_rank_pixel_in_groups, PixelGroups,
};
pub use permutation::temporal::{permute_frame_temporal, SliceTables};
pub use reprojection::{reproject_frame, ReprojectStats, CLAIM_NONE};
pub use sequences::owen::{owen_scramble, owen_sobol, owen_sobol_u32, shuffle_index};
pub use sequences::r2::{r1, r2, Rd};
pub use sequences::screen_sobol::{
    key_sample_u32, screen_sobol_sample, screen_sobol_sample_u32, ScreenSobolKeys, ScreenSobolLayout,
};
pub use sequences::seed::{frame_salt, initial_seed, random_f32, random_u32, RandomStream};
pub use sequences::sobol::{sobol, sobol_u32, SOBOL_DIMENSIONS};
pub use sequences::spatiotemporal::{spatiotemporal_pair_u32, spatiotemporal_shift_u32};
pub use sequences::walk::{step_index, step_of_index, walk_offset, walk_step, STEP_COUNT};
pub use sequences::zsobol::{
    zsobol_frame_pair_u32, zsobol_frame_sample_u32, zsobol_sample, zsobol_sample_u32,
};
