//! The report's spectra a reader can compare across methods: each method's
//! power spectrum of the error averaged over frames and insets
//! ([`MethodRun::spectrum`](crate::study::MethodRun)), DC at the
//! centre, all on one logarithmic colour scale (a colour bar with values
//! beside them), and the temporal spectrum of a pixel's error as a plot.

use super::plot::{Curve, LinePlot};
use crate::metrics::radial::radial_power;
use crate::metrics::spectrum::PowerSpectrum;
use crate::study::{Method, StudyResult};
use anyhow::{anyhow, Context, Result};
use plotters::prelude::*;
use plotters::style::colors::colormaps::{ColorMap, ViridisRGB};
use std::path::Path;

/// The shared colour scale: `log10(power / white's mean power)` from `lo`
/// (darkest) to `hi` (brightest).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LogScale {
    /// `log10` of the power ratio at the bottom of the scale.
    pub lo: f64,
    /// `log10` of the power ratio at the top of the scale.
    pub hi: f64,
}

impl LogScale {
    fn colour(&self, ratio: f64) -> RGBColor {
        let l = ratio.max(1e-12).log10();
        let t = ((l - self.lo) / (self.hi - self.lo)).clamp(0.0, 1.0);
        ViridisRGB.get_color(t)
    }
}

/// Mean of the non-DC entries of a DFT-order spectrum.
fn mean_non_dc(power: &[f64]) -> f64 {
    let n = power.len().saturating_sub(1).max(1);
    (power.iter().skip(1).sum::<f64>() / n as f64).max(1e-30)
}

/// `power` (DFT order, `side x side`) shifted so DC is at the centre.
fn centred(power: &[f64], side: usize) -> Vec<f64> {
    let mut out = vec![0.0; side * side];
    for y in 0..side {
        for x in 0..side {
            let (kx, ky) = ((x + side - side / 2) % side, (y + side - side / 2) % side);
            out[y * side + x] = power[ky * side + kx];
        }
    }
    out
}

/// The colour bar's file name for `r` (`spp<N>-spectrum-scale.svg`).
pub fn scale_file(r: &StudyResult) -> String {
    format!("spp{}-spectrum-scale.svg", r.config.spp)
}

/// Writes `<prefix>-spectrum-avg.png` per method (`prefix(method)`), the
/// colour bar [`scale_file`] and returns the shared scale. Powers are
/// relative to white noise's mean power, so white noise is 1 on average.
///
/// # Errors
/// No white run or no spectrum; I/O errors.
pub fn write_spectra(r: &StudyResult, out: &Path, prefix: impl Fn(Method) -> String) -> Result<LogScale> {
    let white = r.run(Method::White).context("white run")?;
    let side = white.spectrum_side;
    if side == 0 || white.spectrum.len() != side * side {
        return Err(anyhow!("no averaged spectrum in the study"));
    }
    let norm = mean_non_dc(&white.spectrum);
    // One scale for every method: from the lowest to the highest 2nd/98th
    // percentile of any method's non-DC bins, in quarter decades.
    let (mut lo, mut hi) = (f64::MAX, f64::MIN);
    for run in &r.runs {
        let mut l: Vec<f64> = run
            .spectrum
            .iter()
            .skip(1)
            .map(|p| (p / norm).max(1e-12).log10())
            .collect();
        if l.is_empty() {
            continue;
        }
        l.sort_by(f64::total_cmp);
        lo = lo.min(l[l.len() * 2 / 100]);
        hi = hi.max(l[(l.len() * 98 / 100).min(l.len() - 1)]);
    }
    let scale = LogScale {
        lo: (lo * 4.0).floor() / 4.0,
        hi: ((hi * 4.0).ceil() / 4.0).max((lo * 4.0).floor() / 4.0 + 0.25),
    };
    for run in &r.runs {
        if run.spectrum.len() != side * side {
            continue;
        }
        let c = centred(&run.spectrum, side);
        let rgb: Vec<u8> = c
            .iter()
            .flat_map(|p| {
                let RGBColor(r, g, b) = scale.colour(p / norm);
                [r, g, b]
            })
            .collect();
        let path = out.join(format!("{}-spectrum-avg.png", prefix(run.method)));
        image::save_buffer(
            &path,
            &rgb,
            side as u32,
            side as u32,
            image::ExtendedColorType::Rgb8,
        )
        .with_context(|| format!("cannot write {}", path.display()))?;
    }
    colour_bar(&out.join(scale_file(r)), scale)?;
    Ok(scale)
}

/// Size of each method's radial plot beside its averaged spectrum, pixels.
pub const RADIAL_PLOT_SIZE: (u32, u32) = (440, 300);

/// The radially averaged power of a method's averaged spectrum
/// ([`MethodRun::spectrum`](crate::study::MethodRun)) relative to
/// `norm`: `(frequency in cycles per pixel, power / norm)` for the complete
/// annuli `r = 1 ..= side / 2` (frequency `r / side`).
///
/// # Errors
/// A spectrum that is not `side x side` finite, non-negative powers.
pub fn radial_of_average(spectrum: &[f64], side: usize, norm: f64) -> Result<Vec<(f64, f64)>> {
    let s = PowerSpectrum::from_power(side, side, spectrum.to_vec())
        .map_err(|e| anyhow!("averaged spectrum: {e}"))?;
    let radial = radial_power(&s);
    Ok((1..=side / 2)
        .filter(|&r| r < radial.mean().len() && radial.count()[r] > 0)
        .map(|r| (r as f64 / side as f64, radial.mean()[r] / norm))
        .collect())
}

/// Writes `<prefix>-spectrum-radial.svg` and `.csv` per method: the radially
/// averaged power of its averaged spectrum (the image beside it), white
/// noise's curve in grey and the white-noise mean as a labelled line at 1.
///
/// # Errors
/// No white run or spectrum; I/O or drawing errors.
pub fn write_radial_plots(
    r: &StudyResult,
    out: &Path,
    prefix: impl Fn(Method) -> String,
    colour: impl Fn(Method) -> RGBColor,
) -> Result<()> {
    let white = r.run(Method::White).context("white run")?;
    let side = white.spectrum_side;
    let norm = mean_non_dc(&white.spectrum);
    let white_curve = Curve {
        label: "white".to_string(),
        colour: RGBColor(150, 150, 150),
        points: radial_of_average(&white.spectrum, side, norm)?,
    };
    for run in r.runs.iter().filter(|run| run.spectrum.len() == side * side) {
        let mut curves = Vec::new();
        if run.method != Method::White {
            curves.push(white_curve.clone());
        }
        curves.push(Curve {
            label: run.method.name().to_string(),
            colour: colour(run.method),
            points: radial_of_average(&run.spectrum, side, norm)?,
        });
        let title = format!("{}: radial power", run.method.name());
        let p = prefix(run.method);
        LinePlot {
            title: &title,
            x_title: "frequency (cycles per pixel)",
            y_title: "power / white's mean",
            log_y: true,
            lines: &[(1.0, "white mean")],
            curves: &curves,
        }
        .write_sized(
            &out.join(format!("{p}-spectrum-radial.svg")),
            &out.join(format!("{p}-spectrum-radial.csv")),
            RADIAL_PLOT_SIZE,
        )?;
    }
    Ok(())
}

/// A horizontal colour bar for `scale`, ticks labelled with the power ratio.
fn colour_bar(path: &Path, scale: LogScale) -> Result<()> {
    let err = |e: &dyn std::fmt::Display| anyhow!("colour bar: {e}");
    let (w, h) = (520u32, 70u32);
    let root = SVGBackend::new(path, (w, h)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let (x0, x1) = (20i32, w as i32 - 20);
    let steps = 100;
    for i in 0..steps {
        let t = i as f64 / steps as f64;
        let xa = x0 + ((x1 - x0) as f64 * t) as i32;
        let xb = x0 + ((x1 - x0) as f64 * (t + 1.0 / steps as f64)).ceil() as i32;
        let l = scale.lo + t * (scale.hi - scale.lo);
        let c = scale.colour(10f64.powf(l));
        root.draw(&Rectangle::new([(xa, 8), (xb, 30)], c.filled()))
            .map_err(|e| err(&e))?;
    }
    let mut l = (scale.lo * 2.0).ceil() / 2.0;
    while l <= scale.hi + 1e-9 {
        let x = x0 + ((x1 - x0) as f64 * (l - scale.lo) / (scale.hi - scale.lo)) as i32;
        root.draw(&PathElement::new([(x, 30), (x, 36)], BLACK))
            .map_err(|e| err(&e))?;
        let label = super::plot::tick(&10f64.powf(l));
        root.draw(&Text::new(label, (x - 12, 40), ("sans-serif", 12)))
            .map_err(|e| err(&e))?;
        l += 0.5;
    }
    root.draw(&Text::new(
        "power / white noise's mean power (log scale)",
        (x0 + 110, 56),
        ("sans-serif", 12),
    ))
    .map_err(|e| err(&e))?;
    root.present().map_err(|e| err(&e))?;
    Ok(())
}

/// Writes `plot-temporal.svg` and `.csv`: each method's temporal spectrum of a
/// pixel's error (first inset, frames from 8 on) relative to white's mean.
///
/// # Errors
/// No white run; I/O or drawing errors.
pub fn write_temporal_plot(r: &StudyResult, out: &Path, colour: impl Fn(Method) -> RGBColor) -> Result<()> {
    let white = r.run(Method::White).context("white run")?;
    let norm = mean_non_dc(&white.temporal);
    let curves: Vec<Curve> = r
        .runs
        .iter()
        .filter(|run| run.temporal.len() >= 2)
        .map(|run| {
            let d = run.temporal.len();
            Curve {
                label: run.method.name().to_string(),
                colour: colour(run.method),
                points: (1..=d / 2)
                    .map(|k| (k as f64 / d as f64, run.temporal[k] / norm))
                    .collect(),
            }
        })
        .collect();
    LinePlot {
        title: "Temporal power spectrum of a pixel's error",
        x_title: "frequency (cycles per frame)",
        y_title: "power / white's mean power",
        log_y: true,
        lines: &[(1.0, "white noise")],
        curves: &curves,
    }
    .write(&out.join("plot-temporal.svg"), &out.join("plot-temporal.csv"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centring_puts_dc_in_the_middle_and_the_scale_is_monotone() {
        let side = 4;
        let mut p = vec![0.0; 16];
        p[0] = 9.0; // DC
        let c = centred(&p, side);
        assert_eq!(c[2 * side + 2], 9.0);
        assert_eq!(c.iter().filter(|v| **v == 9.0).count(), 1);
        let s = LogScale { lo: -1.0, hi: 1.0 };
        assert_eq!(s.colour(1e-5), s.colour(0.1));
        assert_ne!(s.colour(0.5), s.colour(2.0));
        assert_eq!(mean_non_dc(&[100.0, 1.0, 3.0]), 2.0);
    }

    #[test]
    fn radial_of_a_flat_spectrum_is_flat_and_spans_up_to_half_a_cycle() {
        let side = 16;
        let curve = radial_of_average(&vec![2.0; side * side], side, 2.0).unwrap();
        assert_eq!(curve.len(), side / 2);
        assert_eq!(curve.first().unwrap().0, 1.0 / side as f64);
        assert_eq!(curve.last().unwrap().0, 0.5);
        assert!(curve.iter().all(|&(_, p)| (p - 1.0).abs() < 1e-12));
        assert!(radial_of_average(&[1.0; 10], side, 1.0).is_err());
    }
}
