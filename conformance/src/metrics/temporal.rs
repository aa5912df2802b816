//! Measurements along the time (slice) axis: exponential moving average (EMA) of frames,
//! thresholded-mask RMS after accumulation, and the per-pixel temporal power spectrum.

use crate::metrics::blur::GaussianBlur;
use crate::metrics::error::Error;
use crate::metrics::grid::Grid;
use crate::metrics::low_frequency::LOW_FREQUENCY_CUTOFF;
use crate::metrics::spectrum::{signed_index, SpectrumAnalyzer};
use crate::metrics::threshold::{dither_error, mean_square};
use crate::metrics::volume::Volume;
use rustfft::num_complex::Complex;

/// Checks an EMA factor: finite and in `(0, 1]`.
fn check_alpha(alpha: f64) -> Result<(), Error> {
    if alpha.is_finite() && alpha > 0.0 && alpha <= 1.0 {
        Ok(())
    } else {
        Err(Error::Parameter {
            name: "alpha",
            value: alpha,
        })
    }
}

/// Checks that `last_frame` indexes `volume`.
fn check_frame(volume: &Volume, last_frame: usize) -> Result<(), Error> {
    if last_frame < volume.depth() {
        Ok(())
    } else {
        Err(Error::FrameIndex {
            frame: last_frame,
            depth: volume.depth(),
        })
    }
}

/// Exponential moving average of slices `0..=last_frame` of `volume` with factor
/// `alpha`: `a_0 = v_0`, `a_z = (1 - alpha) a_{z-1} + alpha v_z`. Returns `a_last_frame`.
///
/// # Errors
/// [`Error::Parameter`] if `alpha` is not in `(0, 1]`, [`Error::FrameIndex`] if
/// `last_frame >= depth`.
pub fn ema(volume: &Volume, alpha: f64, last_frame: usize) -> Result<Grid, Error> {
    check_alpha(alpha)?;
    check_frame(volume, last_frame)?;
    let (a, b) = (alpha as f32, (1.0 - alpha) as f32);
    let mut acc = volume.slice(0)?;
    for z in 1..=last_frame {
        for (s, &v) in acc.data_mut().iter_mut().zip(volume.slice_data(z)?) {
            *s = b * *s + a * v;
        }
    }
    Ok(acc)
}

/// Variance of [`ema`] after `last_frame` steps, relative to the variance of temporally
/// white input: with `beta = 1 - alpha`,
/// `alpha / (2 - alpha) * (1 - beta^(2 n)) + beta^(2 n)`, `n = last_frame`
/// (the sum `alpha^2 sum_{j<n} beta^(2j)` plus the weight `beta^n` of frame 0). It tends
/// to `alpha / (2 - alpha)` (quality.md: RMS factor 0.229 for `alpha = 0.1`). Analytic
/// oracle, in `(0, 1]` for `alpha` in `(0, 1]`.
pub fn ema_variance_factor(alpha: f64, last_frame: usize) -> f64 {
    let beta2n = (1.0 - alpha).powi(2 * last_frame as i32);
    alpha / (2.0 - alpha) * (1.0 - beta2n) + beta2n
}

/// Thresholded-mask RMS after temporal accumulation: for each threshold `t`, the dither
/// errors `[v_z < t] - t` of slices `z = 0..=last_frame` are accumulated with [`ema`]
/// (factor `alpha`), optionally blurred, and the mean square over pixels is averaged over
/// thresholds; the result is its root (the definition of [`crate::metrics::threshold`] with an EMA
/// before the blur). White-noise expectation:
/// `sqrt(ema_variance_factor * sum g^2 / 6)`.
///
/// # Errors
/// [`Error::Parameter`] for a bad `alpha` or empty `thresholds`, [`Error::FrameIndex`] if
/// `last_frame >= depth`.
pub fn thresholded_ema_rms(
    volume: &Volume,
    alpha: f64,
    last_frame: usize,
    blur: Option<&GaussianBlur>,
    thresholds: &[f32],
) -> Result<f64, Error> {
    check_alpha(alpha)?;
    check_frame(volume, last_frame)?;
    if thresholds.is_empty() {
        return Err(Error::Parameter {
            name: "thresholds",
            value: 0.0,
        });
    }
    let (w, h) = (volume.width(), volume.height());
    let (a, b) = (alpha as f32, (1.0 - alpha) as f32);
    let mut acc = Grid::zeros(w, h)?;
    let mut tmp = Grid::zeros(w, h)?;
    let mut out = Grid::zeros(w, h)?;
    let mut total = 0.0;
    for &t in thresholds {
        dither_error(volume.slice_data(0)?, t, acc.data_mut());
        for z in 1..=last_frame {
            for (s, &v) in acc.data_mut().iter_mut().zip(volume.slice_data(z)?) {
                let e = if v < t { 1.0 - t } else { -t };
                *s = b * *s + a * e;
            }
        }
        total += match blur {
            Some(g) => {
                g.apply_into(&acc, &mut tmp, &mut out)?;
                mean_square(out.data())
            }
            None => mean_square(acc.data()),
        };
    }
    Ok((total / thresholds.len() as f64).sqrt())
}

/// Pixels transformed per planner call by [`temporal_power`] (bounds the work buffer to
/// `4096 * depth` complex values).
const PIXELS_PER_BATCH: usize = 4096;

/// Per-pixel temporal power spectrum of `volume`, averaged over pixels: entry `k` (in
/// `0..depth`, unshifted DFT order, `k / depth` cycles per frame) is the mean over pixels
/// of `|X_p(k)|^2 / depth`, where `X_p` is the DFT along `z` of pixel `p`'s series with its
/// own mean removed. Entry 0 is 0. Same normalisation as [`crate::metrics::spectrum`]: for
/// temporally white series every non-DC entry expects the per-pixel variance.
pub fn temporal_power(analyzer: &mut SpectrumAnalyzer, volume: &Volume) -> Vec<f64> {
    let (n, d) = (volume.width() * volume.height(), volume.depth());
    let data = volume.data();
    let mut sum = vec![0.0f64; d];
    let mut buffer: Vec<Complex<f64>> = Vec::with_capacity(PIXELS_PER_BATCH.min(n) * d);
    for start in (0..n).step_by(PIXELS_PER_BATCH) {
        let end = (start + PIXELS_PER_BATCH).min(n);
        buffer.clear();
        buffer.resize((end - start) * d, Complex::default());
        // Gather: buffer[(p - start) * d + z] = v(p, z).
        for z in 0..d {
            let slice = &data[z * n + start..z * n + end];
            for (i, &v) in slice.iter().enumerate() {
                buffer[i * d + z].re = v as f64;
            }
        }
        for series in buffer.chunks_exact_mut(d) {
            let mean = series.iter().map(|c| c.re).sum::<f64>() / d as f64;
            series.iter_mut().for_each(|c| c.re -= mean);
        }
        analyzer.forward_rows(&mut buffer, d);
        for series in buffer.chunks_exact(d) {
            for (s, c) in sum.iter_mut().zip(series) {
                *s += c.norm_sqr();
            }
        }
    }
    let scale = 1.0 / (n as f64 * d as f64);
    let mut power: Vec<f64> = sum.iter().map(|s| s * scale).collect();
    power[0] = 0.0;
    power
}

/// Temporal low-frequency ratio, white = 1, from [`temporal_power`]'s output: the mean
/// power of the non-DC entries with `|signed k| <= depth * LOW_FREQUENCY_CUTOFF` (i.e.
/// `k <= D/8` and its mirror `D - k`; 16 of 63 entries for `D = 64`), divided by the mean
/// over all non-DC entries (the expected power of white noise with the same per-pixel
/// variance; see [`crate::metrics::low_frequency::low_frequency_ratio`]).
///
/// NaN if no entry qualifies (`depth < 8`) or every series is constant.
pub fn temporal_low_frequency_ratio(power: &[f64]) -> f64 {
    let d = power.len();
    let limit = d as f64 * LOW_FREQUENCY_CUTOFF;
    let (mut low, mut n_low, mut all) = (0.0, 0usize, 0.0);
    for (k, &p) in power.iter().enumerate().skip(1) {
        all += p;
        if (signed_index(k, d).unsigned_abs() as f64) <= limit {
            low += p;
            n_low += 1;
        }
    }
    (low / n_low as f64) / (all / (d as f64 - 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ema_matches_closed_form_on_a_step() {
        // v_z = 1 for every z: the average stays 1. v_0 = 0, then 1: a_n = 1 - beta^n.
        let v = Volume::from_fn(2, 1, 10, |_, _, z| if z == 0 { 0.0 } else { 1.0 }).unwrap();
        let a = ema(&v, 0.25, 9).unwrap();
        assert!((a.get(0, 0) as f64 - (1.0 - 0.75f64.powi(9))).abs() < 1e-6);
        assert!(ema(&v, 0.0, 9).is_err());
        assert_eq!(ema(&v, 0.5, 10), Err(Error::FrameIndex { frame: 10, depth: 10 }));
        assert!((ema_variance_factor(0.1, 10_000) - 0.1 / 1.9).abs() < 1e-12);
        assert_eq!(ema_variance_factor(0.3, 0), 1.0);
    }

    #[test]
    fn thresholded_ema_of_one_frame_is_spatial() {
        let v = Volume::from_fn(8, 8, 3, |x, y, z| {
            ((x * 5 + y * 3 + z * 7) % 64) as f32 / 64.0 + 1.0 / 128.0
        })
        .unwrap();
        let t = crate::metrics::threshold::stratified_thresholds(16).unwrap();
        let a = thresholded_ema_rms(&v, 0.5, 0, None, &t).unwrap();
        let b = crate::metrics::threshold::thresholded_rms(&v.slice(0).unwrap(), None, &t).unwrap();
        assert!((a - b).abs() < 1e-12);
    }

    #[test]
    fn temporal_power_of_a_sinusoid() {
        // Pixel series cos(2 pi 2 z / 16): all power at k = 2 and 14, none elsewhere.
        let v = Volume::from_fn(3, 2, 16, |x, _, z| {
            (std::f32::consts::TAU * 2.0 * z as f32 / 16.0 + x as f32).cos()
        })
        .unwrap();
        let p = temporal_power(&mut SpectrumAnalyzer::new(), &v);
        assert!((p[2] - 4.0).abs() < 1e-5 && (p[14] - 4.0).abs() < 1e-5, "{p:?}");
        assert!(p.iter().enumerate().all(|(k, &x)| k == 2 || k == 14 || x < 1e-9));
        // LF disc |k| <= 2: entries 1, 2, 14, 15 hold all power (8) -> 8/4 / (8/15) = 3.75.
        assert!((temporal_low_frequency_ratio(&p) - 3.75).abs() < 1e-6);
    }
}
