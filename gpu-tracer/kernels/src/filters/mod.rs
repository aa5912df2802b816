//! The real-time filters a renderer runs between the noisy frame and the
//! viewer, per pixel, shader-shaped (the CPU runs the same functions):
//!
//! - [`taa`]: a temporal exponential history reprojected by the motion
//!   vectors, with neighbourhood colour clamping and a reset where the point
//!   was not visible in the previous frame (TAA / the temporal stage of SVGF);
//! - [`gauss`]: a separable Gaussian, one axis per pass (the stand-in
//!   denoiser of the STBN and FAST papers);
//! - [`atrous`]: SVGF's edge-avoiding a-trous wavelet filter guided by the
//!   G-buffer's depth and normal and by the luminance, with its variance
//!   estimate and propagation;
//! - [`demodulate`]: radiance / albedo and back, so the filters smooth
//!   illumination and not texture.
//!
//! Colours are linear RGB in `xyz` of a `Vec4`; frames are `width * height`
//! row-major, `y` down. Out-of-frame taps are skipped (Gaussian: clamped to
//! the edge), so no filter reads outside its buffers.

pub mod atrous;
pub mod demodulate;
pub mod gauss;
pub mod taa;

/// Uniform of every filter pass, 32 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct FilterParams {
    /// Frame width in pixels, `>= 1`.
    pub width: u32,
    /// Frame height in pixels, `>= 1`.
    pub height: u32,
    /// TAA: weight of the current frame in the history, in `(0, 1]` (0.1 is
    /// the usual TAA blend). Gaussian: sigma in pixels, `> 0`.
    pub weight: f32,
    /// Bit set of [`FILTER_HISTORY_VALID`], [`FILTER_CLAMP`].
    pub flags: u32,
    /// A-trous: distance between taps in pixels, `2^iteration` (1, 2, 4,
    /// 8, 16). Gaussian: axis, 0 = along rows (x), 1 = along columns (y).
    pub step: u32,
    /// Zero (padding to 32 bytes; scalars, not an array: std140 gives
    /// uniform arrays a 16-byte stride).
    pub reserved0: u32,
    /// Zero.
    pub reserved1: u32,
    /// Zero.
    pub reserved2: u32,
}

const _: () = assert!(core::mem::size_of::<FilterParams>() == 32);

/// [`FilterParams::flags`]: the history buffer holds the previous frame's
/// output (clear on the first frame and after a cut: the history resets).
pub const FILTER_HISTORY_VALID: u32 = 1;
/// [`FilterParams::flags`]: clamp the reprojected history to the current
/// frame's 3x3 neighbourhood colour box.
pub const FILTER_CLAMP: u32 = 2;

/// Index of pixel `(x, y)` in a `width`-wide row-major frame.
#[inline]
pub(crate) fn index(x: u32, y: u32, width: u32) -> usize {
    y.wrapping_mul(width).wrapping_add(x) as usize
}
