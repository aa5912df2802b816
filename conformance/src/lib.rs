//! Conformance and quality measurement for the blue-noise seed permutation.
//!
//! The tests live in `tests/`; this library holds what they share: the spectral and
//! perceptual measures of blue noise defined in `shared/notes/quality.md`.
//!
//! - [`Grid`] / [`Volume`]: 2D fields and stacks of slices (frames) of `f32` samples,
//!   treated as toroidal.
//! - [`spectrum`]: 2D power spectrum `|DFT|^2 / N` with DC removed ([`SpectrumAnalyzer`]).
//! - [`radial`]: radially averaged power spectrum and anisotropy in dB.
//! - [`low_frequency`]: power for `|f| <= 1/8` cycles per pixel, white noise = 1.
//! - [`blur`]: toroidal separable Gaussian blur.
//! - [`threshold`]: thresholded-mask RMS after a blur.
//! - [`temporal`]: EMA over frames, thresholded RMS after accumulation, temporal spectrum.
//!
//! ```
//! use conformance::{low_frequency_ratio, Grid, SpectrumAnalyzer};
//! // A checkerboard has all its power at the highest frequency: nothing below 1/8.
//! let g = Grid::from_fn(16, 16, |x, y| ((x + y) % 2) as f32).unwrap();
//! let ratio = low_frequency_ratio(&SpectrumAnalyzer::new().power_spectrum(&g));
//! assert!(ratio < 1e-12);
//! ```
//!
//! Every measurement takes its input as values and reports bad sizes or parameters as
//! an [`Error`]; nothing panics on user input.

pub mod blur;
pub mod error;
pub mod feature_diagnostics;
pub mod filtered;
pub mod fixtures;
pub mod grid;
pub mod history;
pub mod insets;
pub mod low_frequency;
pub mod motion_case;
pub mod motion_insets;
pub mod motion_study;
pub mod motion_tables;
pub mod permute_par;
pub mod plot;
pub mod radial;
pub mod reference;
pub mod regions;
pub mod render_study;
pub mod report;
pub mod report_filtered;
pub mod report_pictures;
pub mod report_spectra;
pub mod spectrum;
pub mod study_result;
pub mod study_scene;
pub mod temporal;
pub mod threshold;
pub mod volume;
pub mod walks;

pub use blur::GaussianBlur;
pub use error::Error;
pub use grid::Grid;
pub use low_frequency::{low_frequency_ratio, slice_low_frequency_ratios, LOW_FREQUENCY_CUTOFF};
pub use radial::{anisotropy_db, radial_power, RadialSpectrum, WEDGES};
pub use spectrum::{PowerSpectrum, SpectrumAnalyzer};
pub use temporal::{
    ema, ema_variance_factor, temporal_low_frequency_ratio, temporal_power, thresholded_ema_rms,
};
pub use threshold::{stratified_thresholds, thresholded_rms, white_noise_rms, DEFAULT_THRESHOLDS};
pub use volume::Volume;
