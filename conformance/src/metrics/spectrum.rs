//! The 2D power spectrum `|DFT|^2` of a grid, with the mean (DC) removed.
//!
//! Conventions used by every spectral measurement in this crate:
//! - Frequency index `(kx, ky)` with `0 <= kx < width`, `0 <= ky < height` (unshifted DFT
//!   order). Its signed value is `kx` for `kx < width / 2` and `kx - width` otherwise
//!   ([`signed_index`]); its frequency in cycles per pixel is `signed / width`.
//! - Power is normalised by the number of samples, `P(k) = |X(k)|^2 / (width * height)`,
//!   and `P(0) = 0`. By Parseval the non-DC powers then sum to `sum (v - mean)^2`, so for
//!   i.i.d. noise of variance `s^2` every non-DC bin has expected power `s^2`, and the
//!   mean over all non-DC bins is the unbiased sample variance.

use crate::metrics::error::Error;
use crate::metrics::grid::Grid;
use rustfft::num_complex::Complex;
use rustfft::{FftDirection, FftPlanner};
use std::fmt;

/// Signed value of DFT index `k` of a transform of length `n`: `k` for `k < n / 2`, else
/// `k - n` (so the Nyquist index of an even length is negative, `-n / 2`).
pub fn signed_index(k: usize, n: usize) -> i64 {
    if k < n / 2 {
        k as i64
    } else {
        k as i64 - n as i64
    }
}

/// Computes power spectra with `rustfft`, reusing one planner (and its cached plans)
/// and the work buffers across calls. Create one and feed it many grids.
///
/// 2D transforms run as all rows in one `process_with_scratch` call, a transpose, and
/// all columns (now rows) in a second call, in `f64`.
pub struct SpectrumAnalyzer {
    planner: FftPlanner<f64>,
    rows: Vec<Complex<f64>>,
    columns: Vec<Complex<f64>>,
    scratch: Vec<Complex<f64>>,
}

impl fmt::Debug for SpectrumAnalyzer {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("SpectrumAnalyzer")
            .field("buffer_len", &self.rows.len())
            .finish_non_exhaustive()
    }
}

impl Default for SpectrumAnalyzer {
    fn default() -> Self {
        Self::new()
    }
}

impl SpectrumAnalyzer {
    /// An analyzer with an empty plan cache.
    pub fn new() -> Self {
        SpectrumAnalyzer {
            planner: FftPlanner::new(),
            rows: Vec::new(),
            columns: Vec::new(),
            scratch: Vec::new(),
        }
    }

    /// In-place forward DFTs of every consecutive run of `len` values in `buffer`
    /// (`buffer.len()` must be a multiple of `len`), in one planner call.
    pub(crate) fn forward_rows(&mut self, buffer: &mut [Complex<f64>], len: usize) {
        debug_assert!(len > 0 && buffer.len().is_multiple_of(len));
        let fft = self.planner.plan_fft(len, FftDirection::Forward);
        let need = fft.get_inplace_scratch_len();
        if self.scratch.len() < need {
            self.scratch.resize(need, Complex::default());
        }
        fft.process_with_scratch(buffer, &mut self.scratch[..need]);
    }

    /// Power spectrum of `grid` with its mean removed (see the module conventions).
    pub fn power_spectrum(&mut self, grid: &Grid) -> PowerSpectrum {
        let (w, h) = (grid.width(), grid.height());
        let mean = grid.mean();
        let mut rows = std::mem::take(&mut self.rows);
        rows.clear();
        rows.extend(grid.data().iter().map(|&v| Complex::new(v as f64 - mean, 0.0)));
        self.forward_rows(&mut rows, w);
        // Transpose: columns[kx * h + y] = rows[y * w + kx].
        let mut columns = std::mem::take(&mut self.columns);
        columns.clear();
        columns.resize(w * h, Complex::default());
        transpose(&rows, &mut columns, w, h);
        self.forward_rows(&mut columns, h);
        let scale = 1.0 / (w * h) as f64;
        let mut power = vec![0.0; w * h];
        for kx in 0..w {
            for ky in 0..h {
                power[ky * w + kx] = columns[kx * h + ky].norm_sqr() * scale;
            }
        }
        power[0] = 0.0;
        self.rows = rows;
        self.columns = columns;
        PowerSpectrum {
            width: w,
            height: h,
            power,
        }
    }
}

/// Writes the `width x height` row-major `src` transposed into `dst` (`height` fastest),
/// in cache-friendly blocks.
fn transpose(src: &[Complex<f64>], dst: &mut [Complex<f64>], width: usize, height: usize) {
    const B: usize = 16;
    for y0 in (0..height).step_by(B) {
        for x0 in (0..width).step_by(B) {
            for y in y0..(y0 + B).min(height) {
                for x in x0..(x0 + B).min(width) {
                    dst[x * height + y] = src[y * width + x];
                }
            }
        }
    }
}

/// A 2D power spectrum: `P(kx, ky) = |X(kx, ky)|^2 / (width * height)` with `P(0, 0) = 0`,
/// stored row-major by `ky` then `kx` in unshifted DFT order (see the module doc).
///
/// Invariants: `power.len() == width * height`; every value is finite and `>= 0` for
/// finite input; `P(k) = P(-k)` (real input).
#[derive(Clone, Debug, PartialEq)]
pub struct PowerSpectrum {
    width: usize,
    height: usize,
    power: Vec<f64>,
}

impl PowerSpectrum {
    /// A spectrum from powers already computed elsewhere (for example averaged
    /// over frames), `width x height`, row-major in DFT order like
    /// [`PowerSpectrum::power`]. The DC entry is set to 0, as for a computed
    /// spectrum.
    ///
    /// # Errors
    /// [`Error::ZeroSize`] for an empty shape, [`Error::DataLength`] if `power`
    /// does not hold `width * height` values, [`Error::Parameter`] (`power`) for
    /// a negative or non-finite power.
    pub fn from_power(width: usize, height: usize, mut power: Vec<f64>) -> Result<Self, Error> {
        let expected = width
            .checked_mul(height)
            .filter(|&n| n > 0)
            .ok_or(Error::ZeroSize {
                width,
                height,
                depth: 1,
            })?;
        if power.len() != expected {
            return Err(Error::DataLength {
                expected,
                actual: power.len(),
            });
        }
        if let Some(&bad) = power.iter().find(|p| !p.is_finite() || **p < 0.0) {
            return Err(Error::Parameter {
                name: "power",
                value: bad,
            });
        }
        power[0] = 0.0;
        Ok(PowerSpectrum { width, height, power })
    }

    /// Width of the transformed grid (number of `kx` indices).
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height of the transformed grid (number of `ky` indices).
    pub fn height(&self) -> usize {
        self.height
    }

    /// All powers, row-major: `(kx, ky)` at `ky * width + kx`.
    pub fn power(&self) -> &[f64] {
        &self.power
    }

    /// Power at DFT index `(kx, ky)`.
    ///
    /// # Panics
    /// If `kx >= width` or `ky >= height`.
    pub fn get(&self, kx: usize, ky: usize) -> f64 {
        assert!(
            kx < self.width && ky < self.height,
            "({kx}, {ky}) outside {}x{}",
            self.width,
            self.height
        );
        self.power[ky * self.width + kx]
    }

    /// Frequency of DFT index `(kx, ky)` in cycles per pixel, each component in
    /// `[-0.5, 0.5)`.
    pub fn frequency(&self, kx: usize, ky: usize) -> (f64, f64) {
        (
            signed_index(kx, self.width) as f64 / self.width as f64,
            signed_index(ky, self.height) as f64 / self.height as f64,
        )
    }

    /// Mean power over all non-DC bins: the unbiased sample variance of the grid
    /// (divisor `width * height - 1`), which is also the expected power of every bin of
    /// white noise with that variance. NaN for a 1x1 grid.
    pub fn mean_power(&self) -> f64 {
        self.power.iter().sum::<f64>() / (self.power.len() as f64 - 1.0)
    }

    /// Iterates `(fx, fy, power)` over all non-DC bins, frequencies in cycles per pixel.
    pub fn bins(&self) -> impl Iterator<Item = (f64, f64, f64)> + '_ {
        (0..self.height)
            .flat_map(move |ky| (0..self.width).map(move |kx| (kx, ky)))
            .skip(1)
            .map(move |(kx, ky)| {
                let (fx, fy) = self.frequency(kx, ky);
                (fx, fy, self.get(kx, ky))
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Direct O(N^2) DFT power, the reference the FFT path must match.
    fn naive_power(grid: &Grid) -> Vec<f64> {
        let (w, h) = (grid.width(), grid.height());
        let mean = grid.mean();
        let mut out = vec![0.0; w * h];
        for ky in 0..h {
            for kx in 0..w {
                let mut acc = Complex::new(0.0, 0.0);
                for y in 0..h {
                    for x in 0..w {
                        let phase = -2.0
                            * std::f64::consts::PI
                            * ((kx * x) as f64 / w as f64 + (ky * y) as f64 / h as f64);
                        acc += Complex::from_polar(grid.get(x, y) as f64 - mean, phase);
                    }
                }
                out[ky * w + kx] = acc.norm_sqr() / (w * h) as f64;
            }
        }
        out
    }

    #[test]
    fn matches_naive_dft_on_odd_size() {
        let g = Grid::from_fn(7, 5, |x, y| {
            ((x * 31 + y * 17) % 11) as f32 * 0.1 + (x * y) as f32 * 0.01
        })
        .unwrap();
        let mut a = SpectrumAnalyzer::new();
        let s = a.power_spectrum(&g);
        let n = naive_power(&g);
        for (i, (&p, &q)) in s.power().iter().zip(&n).enumerate() {
            assert!((p - q).abs() < 1e-9 * (1.0 + q), "bin {i}: {p} vs {q}");
        }
        // Reuse with another size: cached plans must not leak between shapes.
        let g2 = Grid::from_fn(4, 6, |x, y| (x + 2 * y) as f32).unwrap();
        let s2 = a.power_spectrum(&g2);
        let n2 = naive_power(&g2);
        assert!(s2
            .power()
            .iter()
            .zip(&n2)
            .all(|(p, q)| (p - q).abs() < 1e-9 * (1.0 + q)));
    }

    #[test]
    fn from_power_checks_its_input_and_zeroes_dc() {
        let s = PowerSpectrum::from_power(2, 2, vec![5.0, 1.0, 2.0, 3.0]).unwrap();
        assert_eq!(s.power(), &[0.0, 1.0, 2.0, 3.0]);
        assert_eq!((s.width(), s.height()), (2, 2));
        assert!(matches!(
            PowerSpectrum::from_power(2, 2, vec![0.0; 3]),
            Err(Error::DataLength {
                expected: 4,
                actual: 3
            })
        ));
        assert!(matches!(
            PowerSpectrum::from_power(0, 2, vec![]),
            Err(Error::ZeroSize { .. })
        ));
        for bad in [f64::NAN, -1.0, f64::INFINITY] {
            assert!(matches!(
                PowerSpectrum::from_power(1, 2, vec![0.0, bad]),
                Err(Error::Parameter { name: "power", .. })
            ));
        }
    }

    #[test]
    fn parseval_and_cosine_peak() {
        // cos(2 pi 3 x / 16): all power at kx = 3 and kx = 13, each (A^2 / 4) * N / ... :
        // X(3) = N / 2, so P(3) = N / 4 with N = 16 * 8.
        let g = Grid::from_fn(16, 8, |x, _| {
            (2.0 * std::f32::consts::PI * 3.0 * x as f32 / 16.0).cos()
        })
        .unwrap();
        let s = SpectrumAnalyzer::new().power_spectrum(&g);
        let n = 128.0;
        assert!((s.get(3, 0) - n / 4.0).abs() < 1e-4, "{}", s.get(3, 0));
        assert!((s.get(13, 0) - n / 4.0).abs() < 1e-4);
        let total: f64 = s.power().iter().sum();
        let energy = g.variance() * n;
        assert!((total - energy).abs() < 1e-6 * energy);
        assert_eq!(s.frequency(13, 5), (-3.0 / 16.0, -3.0 / 8.0));
        assert_eq!(signed_index(8, 16), -8);
    }
}
