//! **Features**: the feature-aware permutation, which never moves a seed to
//! a surface it did not sample.
//!
//! - [`surface`]: what a pixel shows ([`SurfaceFeature`](crate::SurfaceFeature):
//!   surface id, depth, normal), the rule that decides whether two pixels show
//!   the same surface ([`same_surface`](crate::same_surface)), and the sort key
//!   with the albedo divided out ([`demodulated_luma`](crate::demodulated_luma)).
//! - [`permute`]: the permutation in groups of one surface inside each block
//!   and retargeting cut at edges
//!   ([`permute_frame_features`](crate::permute_frame_features)), and the
//!   per-block / per-seed functions the GPU kernels call.
//! - [`sort_pixel`]: the grouped sorting pass as three passes of one call per
//!   seed (the surface group of each pixel, then the plain per-seed sort's
//!   rank and gather in groups), the form hardware GPUs run.
//! - [`temporal`]: the same against the temporally blue permutation's
//!   target ([`permute_frame_features_temporal`](crate::permute_frame_features_temporal)).
//! - [`isolated`]: the fresh seed of a position that cannot move without
//!   crossing an edge ([`refresh_isolated_seed`](isolated::refresh_isolated_seed)).
//! - `cpu` (private): its CPU fast path, identical output; `step` (private):
//!   one step's checked inputs, shared by both paths.

mod cpu;
pub mod isolated;
pub mod permute;
pub mod sort_pixel;
mod step;
pub mod surface;
pub mod temporal;
