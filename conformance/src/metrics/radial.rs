//! Radially averaged power spectrum (RAPS) and the anisotropy of a power spectrum.
//!
//! Radius of a bin: with signed indices `(sx, sy)` (see [`signed_index`]) and
//! `S = min(width, height)`, `r = sqrt((sx * S / width)^2 + (sy * S / height)^2)`, i.e. the
//! frequency in cycles per `S` pixels; for a square grid this is `|k|`. A bin belongs to
//! radial bin `round(r)`. DC (`r = 0`) is excluded everywhere.

use crate::metrics::spectrum::{signed_index, PowerSpectrum};

/// Number of angular wedges of the anisotropy measure (from quality.md: Ulichney's
/// and Peters' practice).
pub const WEDGES: usize = 32;

/// Radius (in cycles per `min(width, height)` pixels) and angle (radians in `(-pi, pi]`)
/// of DFT index `(kx, ky)` of a `width x height` transform.
fn polar(kx: usize, ky: usize, width: usize, height: usize) -> (f64, f64) {
    let s = width.min(height) as f64;
    let x = signed_index(kx, width) as f64 * s / width as f64;
    let y = signed_index(ky, height) as f64 * s / height as f64;
    (x.hypot(y), y.atan2(x))
}

/// A radially averaged power spectrum: entry `r` is the mean power of the bins whose
/// radius rounds to `r` (module doc), with the number of bins averaged.
///
/// Invariants: `mean.len() == count.len()`; entry 0 is empty (DC is excluded); an entry
/// with `count == 0` has `mean == 0`. The last entry is `round` of the largest radius,
/// `sqrt(2) * S / 2` for a square grid (annuli beyond `S / 2` are only partly inside
/// the spectrum).
#[derive(Clone, Debug, PartialEq)]
pub struct RadialSpectrum {
    mean: Vec<f64>,
    count: Vec<usize>,
}

impl RadialSpectrum {
    /// Mean power of each radial bin, indexed by radius (same units as [`PowerSpectrum`]).
    pub fn mean(&self) -> &[f64] {
        &self.mean
    }

    /// Number of DFT bins averaged into each radial bin.
    pub fn count(&self) -> &[usize] {
        &self.count
    }
}

/// Radially averaged power spectrum of `spectrum` (see [`RadialSpectrum`]).
pub fn radial_power(spectrum: &PowerSpectrum) -> RadialSpectrum {
    let (w, h) = (spectrum.width(), spectrum.height());
    let s = w.min(h) as f64;
    let max_bin = ((s / 2.0) * std::f64::consts::SQRT_2).round() as usize + 1;
    let mut sum = vec![0.0; max_bin + 1];
    let mut count = vec![0usize; max_bin + 1];
    for ky in 0..h {
        for kx in 0..w {
            if kx == 0 && ky == 0 {
                continue;
            }
            let bin = polar(kx, ky, w, h).0.round() as usize;
            sum[bin] += spectrum.get(kx, ky);
            count[bin] += 1;
        }
    }
    while count.len() > 1 && count[count.len() - 1] == 0 {
        count.pop();
        sum.pop();
    }
    let mean = sum
        .iter()
        .zip(&count)
        .map(|(&s, &c)| if c == 0 { 0.0 } else { s / c as f64 })
        .collect();
    RadialSpectrum { mean, count }
}

/// Anisotropy of `spectrum` in dB: how much the mean power in angular wedges departs from
/// the radial mean at the same radius, averaged over radii.
///
/// Definition: take the complete annuli `r = 1 ..= S / 2` (radial bins of the module doc)
/// and split each into [`WEDGES`] wedges by the angle of the frequency vector, wedge
/// `floor((angle + pi) / (2 pi) * WEDGES)`. In annulus `r`, with `c(r)` non-empty wedges of
/// mean power `m(r, w)` and the annulus mean `m(r)` (the [`radial_power`] entry),
///
/// `a(r) = (1 / c(r)) sum_w (m(r, w) / m(r) - 1)^2`
///
/// is the relative variance of the wedge means, and `A = 10 log10(mean_r a(r))` over the
/// annuli with non-zero power. An isotropic spectrum estimated from one periodogram does
/// not reach `-inf`: a wedge mean of `n` bins of exponentially distributed power carries
/// a relative variance of about `1 / n`, so i.i.d. noise on 128x128 measures about
/// -6 dB (quality.md quotes -5.6 dB with its implementation); directional structure
/// shows as values well above that. NaN if no annulus has power (constant input, or
/// `min(width, height) < 2`).
pub fn anisotropy_db(spectrum: &PowerSpectrum) -> f64 {
    let (w, h) = (spectrum.width(), spectrum.height());
    let rmax = w.min(h) / 2;
    if rmax == 0 {
        return f64::NAN;
    }
    // sum[r][wedge], count[r][wedge]
    let mut sum = vec![[0.0f64; WEDGES]; rmax + 1];
    let mut count = vec![[0usize; WEDGES]; rmax + 1];
    for ky in 0..h {
        for kx in 0..w {
            let (r, angle) = polar(kx, ky, w, h);
            let bin = r.round() as usize;
            if bin == 0 || bin > rmax {
                continue;
            }
            let t = (angle + std::f64::consts::PI) / std::f64::consts::TAU;
            let wedge = ((t * WEDGES as f64) as usize).min(WEDGES - 1);
            sum[bin][wedge] += spectrum.get(kx, ky);
            count[bin][wedge] += 1;
        }
    }
    let (mut total_a, mut annuli) = (0.0, 0usize);
    for (s, c) in sum.iter().zip(&count).skip(1) {
        let n: usize = c.iter().sum();
        let power: f64 = s.iter().sum();
        if n == 0 || power <= 0.0 {
            continue;
        }
        let ring = power / n as f64;
        let (mut dev, mut wedges) = (0.0, 0usize);
        for (&sw, &cw) in s.iter().zip(c) {
            if cw > 0 {
                let rel = sw / cw as f64 / ring - 1.0;
                dev += rel * rel;
                wedges += 1;
            }
        }
        total_a += dev / wedges as f64;
        annuli += 1;
    }
    if annuli == 0 {
        f64::NAN
    } else {
        10.0 * (total_a / annuli as f64).log10()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::grid::Grid;
    use crate::metrics::spectrum::SpectrumAnalyzer;

    #[test]
    fn radial_bins_cover_every_non_dc_bin() {
        let g = Grid::from_fn(16, 16, |x, y| ((x * 7 + y * 3) % 5) as f32).unwrap();
        let s = SpectrumAnalyzer::new().power_spectrum(&g);
        let r = radial_power(&s);
        assert_eq!(r.count()[0], 0);
        assert_eq!(r.count().iter().sum::<usize>(), 255);
        // r = 1 holds the 4 axis neighbours of DC and the 4 diagonals (radius 1.41).
        assert_eq!(r.count()[1], 8);
        let total: f64 = r.mean().iter().zip(r.count()).map(|(m, &c)| m * c as f64).sum();
        assert!((total - s.power().iter().sum::<f64>()).abs() < 1e-9 * total);
        assert_eq!(r.mean().len(), 12); // round(8 * sqrt 2) = 11
    }

    #[test]
    fn vertical_stripes_are_anisotropic() {
        // Power only on the kx axis: every wedge but two per annulus is empty of power.
        let g = Grid::from_fn(32, 32, |x, _| ((x * 13) % 7) as f32).unwrap();
        let s = SpectrumAnalyzer::new().power_spectrum(&g);
        assert!(anisotropy_db(&s) > 5.0, "{}", anisotropy_db(&s));
        let constant = SpectrumAnalyzer::new().power_spectrum(&Grid::zeros(8, 8).unwrap());
        assert!(anisotropy_db(&constant).is_nan());
    }
}
