//! Low-frequency power ratio of a 2D grid: how much of white noise's power remains at
//! low frequencies (blue noise: close to 0; white noise: 1; low-pass noise: above 1).

use crate::metrics::error::Error;
use crate::metrics::spectrum::{PowerSpectrum, SpectrumAnalyzer};
use crate::metrics::volume::Volume;

/// Radius of the low-frequency disc in cycles per pixel (quality.md): `|f| <= 1/8`.
pub const LOW_FREQUENCY_CUTOFF: f64 = 0.125;

/// Low-frequency power ratio of `spectrum`, white = 1.
///
/// Definition: the mean power of the non-DC bins with `|f| <= LOW_FREQUENCY_CUTOFF`
/// (`f = (fx, fy)` in cycles per pixel, see [`PowerSpectrum::frequency`]) divided by
/// the expected power of one bin of white noise with the grid's own variance. With the
/// spectrum's normalisation that expectation is the mean power over all non-DC bins
/// ([`PowerSpectrum::mean_power`], the unbiased sample variance), so i.i.d. noise of any
/// distribution gives 1 in expectation, and the ratio does not depend on the scale or
/// offset of the values. For 128x128, the disc holds 804 bins (`|k| <= 16`).
///
/// NaN if no bin lies in the disc (both sides shorter than 8) or the grid is constant.
pub fn low_frequency_ratio(spectrum: &PowerSpectrum) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for (fx, fy, p) in spectrum.bins() {
        if fx.hypot(fy) <= LOW_FREQUENCY_CUTOFF {
            sum += p;
            n += 1;
        }
    }
    sum / n as f64 / spectrum.mean_power()
}

/// [`low_frequency_ratio`] of every slice of `volume`, in slice order.
///
/// # Errors
/// None in practice (every slice index is in range); kept as a `Result` so slicing
/// errors surface as values.
pub fn slice_low_frequency_ratios(
    analyzer: &mut SpectrumAnalyzer,
    volume: &Volume,
) -> Result<Vec<f64>, Error> {
    (0..volume.depth())
        .map(|z| Ok(low_frequency_ratio(&analyzer.power_spectrum(&volume.slice(z)?))))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::grid::Grid;

    #[test]
    fn cosine_below_and_above_cutoff() {
        // A cosine at 1/16 cycles per pixel is all low frequency; one at 1/4 has none.
        let mut a = SpectrumAnalyzer::new();
        let low = Grid::from_fn(32, 32, |x, _| (std::f32::consts::TAU * x as f32 / 16.0).cos()).unwrap();
        let high = Grid::from_fn(32, 32, |x, _| (std::f32::consts::TAU * x as f32 / 4.0).cos()).unwrap();
        let r_low = low_frequency_ratio(&a.power_spectrum(&low));
        let r_high = low_frequency_ratio(&a.power_spectrum(&high));
        // Disc |k| <= 4 on 32x32 holds 48 non-DC bins; 2 carry all 1023 bins' worth of power.
        assert!((r_low - 1023.0 / 48.0).abs() < 1e-6, "{r_low}");
        assert!(r_high.abs() < 1e-9, "{r_high}");
    }
}
