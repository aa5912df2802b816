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

/// The fraction of pixel-frames of `a` and `b` (frames of the same size, in
/// the same order) that agree within `1e-3 * (1 + |a|)` in every channel,
/// and their number: the same seeds on the CPU and the GPU differ only by
/// float rounding.
fn fraction_close(a: &[Vec<glam::Vec4>], b: &[Vec<glam::Vec4>]) -> (f64, usize) {
    let (mut close, mut total) = (0usize, 0usize);
    for (fa, fb) in a.iter().zip(b) {
        for (p, q) in fa.iter().zip(fb) {
            total += 1;
            if (*p - *q).abs().max_element() <= 1e-3 * (1.0 + p.abs().max_element()) {
                close += 1;
            }
        }
    }
    (close as f64 / total.max(1) as f64, total)
}
