//! The visual report (issue 5, part 3): the still-camera study ([`crate::study`]) as
//! an HTML page a reader can compare the methods on, with PNG images, SVG plots and
//! the data of every plot and table beside it as CSV.
//!
//! Entry point: [`write_report`] with a [`ReportConfig`] (`conformance report`).
//!
//! - [`plot`]: line plots with axes, ticks, legends and labelled goal lines.
//! - [`chance`]: what the null row says about the tables (how far luck moves a row).
//! - [`filtered`]: the headline table, the error after the real-time filters.
//! - [`pictures`]: zoomed crops, blurred errors, accumulated means and the region map.
//! - [`spectra`]: the error's power spectra and the temporal spectrum.
//! - [`page`]: runs the study and writes `index.html` from the above.
//!
//! Each module uses only those listed above it, the study and the metrics.

pub mod chance;
pub mod filtered;
pub mod page;
pub mod pictures;
pub mod plot;
pub mod spectra;

pub use page::{write_report, ReportConfig};
