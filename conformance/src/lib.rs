//! Conformance and quality measurement for the blue-noise seed permutation.
//!
//! The tests live in `tests/`; this library holds what they share: the spectral and
//! perceptual measures of blue noise defined in `shared/notes/quality.md`, the
//! rendered-quality studies built on them, and the report that shows a study.
//! Imports flow one way: [`metrics`] <- [`study`] <- [`motion`], and
//! [`metrics`] <- [`study`] <- [`report`].
//!
//! - [`metrics`]: grids and volumes of samples and every measure on them (spectra,
//!   low-frequency ratio, blur, thresholded RMS, temporal figures, frame regions).
//! - [`study`]: the still-camera rendered-quality study ([`study::Study`]).
//! - [`motion`]: the study in motion, with seed reprojection ([`motion::run_study`]).
//! - [`report`]: the still-camera study as an HTML page ([`report::write_report`]).
//! - [`fixtures`]: deterministic test inputs (tiles, retarget tables, feature frames).
//! - [`permute_par`]: `sampler_core::permute_frame` on a rayon thread pool.
//!
//! The measures most tests use are re-exported here: [`Grid`] / [`Volume`],
//! [`SpectrumAnalyzer`], [`low_frequency_ratio`], [`radial_power`], [`GaussianBlur`],
//! [`thresholded_rms`], [`temporal_power`] and the [`Error`] they report.
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

pub mod fixtures;
pub mod metrics;
pub mod motion;
pub mod permute_par;
pub mod report;
pub mod study;

pub use metrics::blur::GaussianBlur;
pub use metrics::error::Error;
pub use metrics::grid::Grid;
pub use metrics::low_frequency::{low_frequency_ratio, slice_low_frequency_ratios, LOW_FREQUENCY_CUTOFF};
pub use metrics::radial::{anisotropy_db, radial_power, RadialSpectrum, WEDGES};
pub use metrics::spectrum::{PowerSpectrum, SpectrumAnalyzer};
pub use metrics::temporal::{
    ema, ema_variance_factor, temporal_low_frequency_ratio, temporal_power, thresholded_ema_rms,
};
pub use metrics::threshold::{stratified_thresholds, thresholded_rms, white_noise_rms, DEFAULT_THRESHOLDS};
pub use metrics::volume::Volume;
