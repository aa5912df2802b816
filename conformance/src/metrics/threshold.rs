//! Thresholded-mask RMS after a blur (FAST; Belcour & Heitz 2021): how much error a
//! mask leaves when it dithers a constant, after a denoiser-like filter.
//!
//! For a threshold `t` in `[0, 1)`, dithering the constant `t` with a mask `v` gives the
//! binary image `[v < t]`; its error is `[v < t] - t`. The measure is
//!
//! `E = sqrt( mean_t mean_pixels (B([v < t] - t))^2 )`
//!
//! with `B` a toroidal Gaussian blur (or the identity) and `t` over a deterministic
//! stratified set ([`stratified_thresholds`]). The root is taken after averaging over
//! thresholds so that for i.i.d. uniform `v` (`[v < t]` is Bernoulli(t), variance
//! `t (1 - t)`, mean `1/6` over `t`) the expectation of `E^2` is `sum g^2 / 6`
//! ([`white_noise_rms`]); averaging per-threshold RMS values instead would give
//! `pi / 8 * ...`, not the baselines of quality.md.

use crate::metrics::blur::GaussianBlur;
use crate::metrics::error::Error;
use crate::metrics::grid::Grid;

/// Number of thresholds used by the quality tests (quality.md's figures use 64).
pub const DEFAULT_THRESHOLDS: usize = 64;

/// The `count` thresholds `(i + 0.5) / count`, `i = 0..count`: midpoints of equal strata of
/// `[0, 1)`. Their mean of `t (1 - t)` is `1/6 + 1/(12 count^2)`.
///
/// # Errors
/// [`Error::Parameter`] if `count` is zero.
pub fn stratified_thresholds(count: usize) -> Result<Vec<f32>, Error> {
    if count == 0 {
        return Err(Error::Parameter {
            name: "count",
            value: 0.0,
        });
    }
    Ok((0..count)
        .map(|i| ((i as f64 + 0.5) / count as f64) as f32)
        .collect())
}

/// Expected thresholded-mask RMS of i.i.d. uniform noise: `sqrt(sum g^2 / 6)` with
/// `sum g^2` of `blur`'s 2D kernel, or `sqrt(1/6) = 0.408` unblurred. The analytic
/// baseline of quality.md (valid while the kernel does not wrap onto itself).
pub fn white_noise_rms(blur: Option<&GaussianBlur>) -> f64 {
    (blur.map_or(1.0, GaussianBlur::sum_of_squares_2d) / 6.0).sqrt()
}

/// Writes `[v < t] - t` of every sample `v` of `values` into `out` (same length).
pub(crate) fn dither_error(values: &[f32], t: f32, out: &mut [f32]) {
    for (o, &v) in out.iter_mut().zip(values) {
        *o = if v < t { 1.0 - t } else { -t };
    }
}

/// Mean of the squared samples, in `f64`.
pub(crate) fn mean_square(values: &[f32]) -> f64 {
    values.iter().map(|&v| (v as f64) * (v as f64)).sum::<f64>() / values.len() as f64
}

/// Thresholded-mask RMS of `mask` (values in `[0, 1)`) after `blur` (none: unfiltered),
/// over `thresholds` (see the module doc for the definition). Unitless, in `[0, 0.5]`.
///
/// # Errors
/// [`Error::Parameter`] if `thresholds` is empty.
pub fn thresholded_rms(mask: &Grid, blur: Option<&GaussianBlur>, thresholds: &[f32]) -> Result<f64, Error> {
    if thresholds.is_empty() {
        return Err(Error::Parameter {
            name: "thresholds",
            value: 0.0,
        });
    }
    let (w, h) = (mask.width(), mask.height());
    let mut err = Grid::zeros(w, h)?;
    let mut tmp = Grid::zeros(w, h)?;
    let mut out = Grid::zeros(w, h)?;
    let mut total = 0.0;
    for &t in thresholds {
        dither_error(mask.data(), t, err.data_mut());
        total += match blur {
            Some(b) => {
                b.apply_into(&err, &mut tmp, &mut out)?;
                mean_square(out.data())
            }
            None => mean_square(err.data()),
        };
    }
    Ok((total / thresholds.len() as f64).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checkerboard_dithers_one_half_exactly() {
        // A 2-level mask: 0.25 and 0.75 in a checkerboard. At t in (0.25, 0.75] the error
        // is +-1/2 per pixel; a blur wide enough averages the checkerboard to zero.
        let m = Grid::from_fn(8, 8, |x, y| if (x + y) % 2 == 0 { 0.25 } else { 0.75 }).unwrap();
        let half = [0.5f32];
        assert!((thresholded_rms(&m, None, &half).unwrap() - 0.5).abs() < 1e-9);
        let wide = GaussianBlur::new(2.0).unwrap();
        assert!(thresholded_rms(&m, Some(&wide), &half).unwrap() < 1e-3);
        assert!(thresholded_rms(&m, None, &[]).is_err());
    }

    #[test]
    fn stratified_set_is_midpoints() {
        assert_eq!(
            stratified_thresholds(4).unwrap(),
            vec![0.125, 0.375, 0.625, 0.875]
        );
        assert!(stratified_thresholds(0).is_err());
        assert!((white_noise_rms(None) - (1.0f64 / 6.0).sqrt()).abs() < 1e-15);
    }
}
