//! The measures of blue noise defined in `shared/notes/quality.md`, on plain values:
//! 2D fields and stacks of frames in, numbers out. Nothing here renders.
//!
//! Entry points (re-exported at the crate root): [`Grid`](grid::Grid) and
//! [`Volume`](volume::Volume) hold the samples;
//! [`SpectrumAnalyzer`](spectrum::SpectrumAnalyzer) gives the power spectrum that
//! [`low_frequency_ratio`](low_frequency::low_frequency_ratio) and
//! [`radial_power`](radial::radial_power) read; [`GaussianBlur`](blur::GaussianBlur),
//! [`thresholded_rms`](threshold::thresholded_rms) and [`temporal`]'s EMA measure what a
//! denoiser or an accumulation leaves; [`classify_regions`](regions::classify_regions)
//! splits a rendered frame into the regions every per-region figure uses.
//!
//! - [`error`]: the one error type ([`Error`](error::Error)).
//! - [`grid`] / [`volume`]: 2D fields and stacks of slices (frames) of `f32`
//!   samples, treated as toroidal.
//! - [`blur`]: toroidal separable Gaussian blur.
//! - [`spectrum`]: 2D power spectrum `|DFT|^2 / N` with DC removed.
//! - [`radial`]: radially averaged power spectrum and anisotropy in dB.
//! - [`low_frequency`]: power for `|f| <= 1/8` cycles per pixel, white noise = 1.
//! - [`threshold`]: thresholded-mask RMS after a blur.
//! - [`temporal`]: EMA over frames, thresholded RMS after accumulation, temporal spectrum.
//! - [`regions`]: emitter zone, edges and interior of a frame, from its G-buffer.
//! - [`surfaces`]: which pixels see a glossy surface first, from a G-buffer and the
//!   scene's materials.
//!
//! Every measurement takes its input as values and reports bad sizes or parameters as
//! an [`Error`](error::Error); nothing panics on user input.

pub mod blur;
pub mod error;
pub mod grid;
pub mod low_frequency;
pub mod radial;
pub mod regions;
pub mod spectrum;
pub mod surfaces;
pub mod temporal;
pub mod threshold;
pub mod volume;
