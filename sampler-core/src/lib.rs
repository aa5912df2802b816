//! Blue-noise distribution of Monte Carlo error by permuting pixel seeds
//! between frames (Heitz & Belcour, EGSR 2019), plus the low-discrepancy
//! sequences and offset walk it stands on.
//!
//! # Guide
//!
//! Each pixel renders with a **seed** ([`seed`]) that defines all its random
//! numbers. After frame `t` is rendered, [`permute_frame`] permutes seeds
//! inside small blocks so that the frame's pixel values follow the ranks of a
//! blue-noise dither tile shifted by the walk offset `o_t` ([`sort`],
//! [`walk`]), then scatters them with a precomputed retarget table so they
//! follow the tile of frame `t + 1` ([`retarget`]). Render frame `t + 1` with
//! the new seeds: its error is distributed as blue noise in screen space.
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
pub mod dither;
pub mod error;
pub mod feature_permute;
mod feature_permute_cpu;
pub mod features;
pub mod frame;
pub mod layout;
pub mod owen;
mod permute_cpu;
pub mod r2;
pub mod reproject;
mod reproject_batch;
pub mod reproject_passes;
mod reproject_sweep;
#[cfg(test)]
mod reproject_tests;
mod reproject_two_sweeps;
pub mod retarget;
pub mod screen_sobol;
pub mod seed;
pub mod sobol;
pub mod sort;
pub mod stbn_mask;
pub mod walk;
pub mod zsobol;

pub use dither::{tile_texel, DitherTile};
pub use error::{Buffer, Error};
pub use feature_permute::permute_frame_features;
pub use features::{demodulated_luma, same_surface, FeatureThresholds, SurfaceFeature, NO_SURFACE};
pub use frame::{
    permute_frame, permute_frame_baseline_isa, retarget_frame, retarget_pixel, retarget_pixel_at_offset,
    sort_block_at_offset, sort_block_in_frame, sort_frame,
};
pub use layout::{FrameLayout, FrameParams};
pub use owen::{owen_scramble, owen_sobol, owen_sobol_u32, shuffle_index};
pub use permute_cpu::rows::{band_seed_range, permute_frame_rows, permute_frame_rows_isa};
pub use permute_cpu::Isa;
pub use r2::{r1, r2, Rd};
pub use reproject::{reproject_frame, ReprojectStats, CLAIM_NONE};
pub use retarget::{
    pack_offset, retarget_destination, unpack_offset, RetargetTable, RetargetTables, IDENTITY_PACKED,
    RETARGET_RADIUS,
};
pub use screen_sobol::{
    key_sample_u32, screen_sobol_sample, screen_sobol_sample_u32, ScreenSobolKeys, ScreenSobolLayout,
};
pub use seed::{initial_seed, random_f32, random_u32, RandomStream};
pub use sobol::{sobol, sobol_u32, SOBOL_DIMENSIONS};
pub use sort::{
    intensity_key, luma, sort_block, Intensity, DEFAULT_BLOCK, MAX_BLOCK, MAX_BLOCK_PIXELS, MIN_BLOCK,
};
pub use stbn_mask::SpatiotemporalMask;
pub use walk::{step_index, step_of_index, walk_offset, walk_step, MAX_TILE, STEP_COUNT};
pub use zsobol::{zsobol_sample, zsobol_sample_u32};
