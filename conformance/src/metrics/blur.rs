//! Toroidal (wrap-around), separable Gaussian blur: the stand-in for a denoiser.

use crate::metrics::error::Error;
use crate::metrics::grid::Grid;

/// Kernel half-width in units of sigma: taps at `|i| <= ceil(TRUNCATION * sigma)`. The
/// discarded tail of a Gaussian beyond 4 sigma holds under 1e-4 of its weight.
pub const TRUNCATION: f64 = 4.0;

/// A normalised, sampled 1D Gaussian applied along rows, then columns, with toroidal
/// wrap-around.
///
/// Kernel: `g(i) = exp(-i^2 / (2 sigma^2)) / sum_j exp(-j^2 / (2 sigma^2))` for
/// `|i| <= ceil(TRUNCATION * sigma)`, so the taps sum to 1 and a blur preserves the mean.
/// Sigma is in pixels. A kernel wider than the grid wraps more than once (each tap lands
/// at `(x + i) mod width`), which keeps it a convolution on the torus.
#[derive(Clone, Debug, PartialEq)]
pub struct GaussianBlur {
    sigma: f64,
    taps: Vec<f32>,
}

impl GaussianBlur {
    /// The blur of standard deviation `sigma` pixels.
    ///
    /// # Errors
    /// [`Error::Parameter`] if `sigma` is not finite and positive, or above 1e4.
    pub fn new(sigma: f64) -> Result<Self, Error> {
        if !(sigma.is_finite() && sigma > 0.0 && sigma <= 1e4) {
            return Err(Error::Parameter {
                name: "sigma",
                value: sigma,
            });
        }
        let radius = (TRUNCATION * sigma).ceil() as i64;
        let raw: Vec<f64> = (-radius..=radius)
            .map(|i| (-((i * i) as f64) / (2.0 * sigma * sigma)).exp())
            .collect();
        let total: f64 = raw.iter().sum();
        let taps = raw.iter().map(|&g| (g / total) as f32).collect();
        Ok(GaussianBlur { sigma, taps })
    }

    /// Standard deviation in pixels.
    pub fn sigma(&self) -> f64 {
        self.sigma
    }

    /// The 1D taps, index `i + radius` for offset `i` in `-radius..=radius`; they sum to 1.
    pub fn taps(&self) -> &[f32] {
        &self.taps
    }

    /// `sum g^2` of the 2D kernel `g(x) g(y)` (the taps' squared sum, squared), in `f64`.
    ///
    /// For i.i.d. input of variance `s^2`, the blurred output has variance
    /// `s^2 * sum g^2` (on a grid at least as large as the kernel, where no tap wraps onto
    /// another). It approaches `1 / (4 pi sigma^2)` for large sigma.
    pub fn sum_of_squares_2d(&self) -> f64 {
        let s: f64 = self.taps.iter().map(|&g| (g as f64).powi(2)).sum();
        s * s
    }

    /// Blurs `src` into `dst` (same size), using `tmp` as the intermediate row pass.
    /// Every sample of `dst` and `tmp` is overwritten.
    ///
    /// # Errors
    /// [`Error::ShapeMismatch`] if `dst` or `tmp` differs in size from `src`.
    pub fn apply_into(&self, src: &Grid, tmp: &mut Grid, dst: &mut Grid) -> Result<(), Error> {
        let (w, h) = (src.width(), src.height());
        for g in [&*tmp, &*dst] {
            if (g.width(), g.height()) != (w, h) {
                return Err(Error::ShapeMismatch {
                    expected: [w, h, 1],
                    actual: [g.width(), g.height(), 1],
                });
            }
        }
        let radius = self.taps.len() / 2;
        // Row pass: tmp(x, y) = sum_i g(i) src((x + i) mod w, y).
        let offsets_x: Vec<usize> = (0..self.taps.len()).map(|j| wrap_offset(j, radius, w)).collect();
        for (srow, trow) in src.data().chunks_exact(w).zip(tmp.data_mut().chunks_exact_mut(w)) {
            for (x, out) in trow.iter_mut().enumerate() {
                let mut acc = 0.0f32;
                for (&g, &o) in self.taps.iter().zip(&offsets_x) {
                    let xi = x + o;
                    acc += g * srow[if xi >= w { xi - w } else { xi }];
                }
                *out = acc;
            }
        }
        // Column pass, a whole row at a time: dst(., y) = sum_i g(i) tmp(., (y + i) mod h).
        let offsets_y: Vec<usize> = (0..self.taps.len()).map(|j| wrap_offset(j, radius, h)).collect();
        let t = tmp.data();
        for (y, drow) in dst.data_mut().chunks_exact_mut(w).enumerate() {
            drow.fill(0.0);
            for (&g, &o) in self.taps.iter().zip(&offsets_y) {
                let yi = (y + o) % h;
                for (d, &s) in drow.iter_mut().zip(&t[yi * w..(yi + 1) * w]) {
                    *d += g * s;
                }
            }
        }
        Ok(())
    }

    /// Blurred copy of `src`.
    pub fn apply(&self, src: &Grid) -> Grid {
        let mut tmp = src.clone();
        let mut dst = src.clone();
        self.apply_into(src, &mut tmp, &mut dst)
            .expect("buffers cloned from src have its shape");
        dst
    }
}

/// Offset of tap `j` (signed offset `j - radius`) as a non-negative shift below `n`.
fn wrap_offset(j: usize, radius: usize, n: usize) -> usize {
    (j as i64 - radius as i64).rem_euclid(n as i64) as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Direct 2D toroidal convolution with the outer-product kernel.
    fn naive(blur: &GaussianBlur, src: &Grid) -> Grid {
        let (w, h) = (src.width() as i64, src.height() as i64);
        let r = (blur.taps().len() / 2) as i64;
        Grid::from_fn(src.width(), src.height(), |x, y| {
            let mut acc = 0.0f64;
            for dy in -r..=r {
                for dx in -r..=r {
                    let g = blur.taps()[(dx + r) as usize] as f64 * blur.taps()[(dy + r) as usize] as f64;
                    let xs = (x as i64 + dx).rem_euclid(w) as usize;
                    let ys = (y as i64 + dy).rem_euclid(h) as usize;
                    acc += g * src.get(xs, ys) as f64;
                }
            }
            acc as f32
        })
        .unwrap()
    }

    #[test]
    fn separable_matches_direct_on_odd_sizes() {
        let src = Grid::from_fn(9, 5, |x, y| ((x * 7 + y * 11) % 13) as f32 / 13.0).unwrap();
        for sigma in [0.6, 1.5, 3.0] {
            let blur = GaussianBlur::new(sigma).unwrap();
            let a = blur.apply(&src);
            let b = naive(&blur, &src);
            for (p, q) in a.data().iter().zip(b.data()) {
                assert!((p - q).abs() < 1e-5, "sigma {sigma}: {p} vs {q}");
            }
            assert!((a.mean() - src.mean()).abs() < 1e-5);
        }
    }

    #[test]
    fn kernel_properties() {
        let blur = GaussianBlur::new(1.0).unwrap();
        assert_eq!(blur.taps().len(), 9);
        let sum: f32 = blur.taps().iter().sum();
        assert!((sum - 1.0).abs() < 1e-6);
        let expected = 1.0 / (4.0 * std::f64::consts::PI);
        assert!((blur.sum_of_squares_2d() - expected).abs() < 1e-3 * expected);
        assert!(GaussianBlur::new(0.0).is_err());
        assert!(GaussianBlur::new(f64::NAN).is_err());
        let mut wrong = Grid::zeros(3, 3).unwrap();
        let src = Grid::zeros(4, 4).unwrap();
        let mut dst = src.clone();
        assert!(blur.apply_into(&src, &mut wrong, &mut dst).is_err());
    }
}
