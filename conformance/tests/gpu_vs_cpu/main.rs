//! The GPU permutation kernels (rust-gpu SPIR-V on wgpu) against
//! `sampler_core` on the CPU: seeds must match bit for bit.
//!
//! Needs a GPU adapter (Mesa's lavapipe counts). Without one each test
//! prints `SKIPPED` with the reason; `BLUENOISE_REQUIRE_GPU=1` (set in CI)
//! turns that into a failure.
//!
//! - [`permute`]: seed init, sort and retarget, and the feature-aware
//!   passes, bit for bit.
//! - [`trace`]: traced frames (statistically, and with the same seeds),
//!   the G-buffer of a textured moving scene, and the feature pass.
//! - [`reprojection`]: the seed reprojection passes and the motion pass.
//! - [`trace_variant`]: the smaller trace kernels against the CPU.

mod permute;
mod reprojection;
mod trace;
mod trace_variant;
