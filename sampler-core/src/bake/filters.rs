//! Filters a mask can be adapted to, and their autocorrelations on the
//! torus (the coupling kernels of the filter-adapted energy, see
//! [`bake_filter_adapted`](super::bake_filter_adapted)).
//!
//! The filtered energy of a field `x` under a linear filter `g` on a torus
//! is `|g * x|^2 = sum_ij (g * g~)(i - j) <x_i, x_j>`, where `g * g~` is the
//! circular autocorrelation of `g`. Every filter here is a normalised 1D
//! impulse response (taps sum to 1); 2D spatial filters are separable
//! (`g(x) g(y)`), so their autocorrelation is the product of the two axes'.
//!
//! Units: spatial sizes and sigmas in texels, temporal ones in slices
//! (frames).

use super::BakeError;
use alloc::vec;
use alloc::vec::Vec;

/// Gaussian taps reach `ceil(GAUSSIAN_TRUNCATION * sigma)` either side, as
/// the Gaussian blur of the conformance crate (the tail beyond 4 sigma holds
/// under 1e-4 of the weight).
pub const GAUSSIAN_TRUNCATION: f64 = 4.0;
/// Largest box size or binomial order (taps per axis up to 65).
pub const MAX_FILTER_TAPS: u32 = 64;
/// Largest Gaussian filter sigma, in texels or slices.
pub const MAX_FILTER_SIGMA: f64 = 16.0;

/// A separable spatial low-pass filter (applied along x, then y).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SpatialFilter {
    /// Sampled Gaussian of standard deviation `sigma` texels, in
    /// `(0, `[`MAX_FILTER_SIGMA`]`]`, truncated at [`GAUSSIAN_TRUNCATION`]
    /// sigma and normalised.
    Gaussian {
        /// Standard deviation in texels.
        sigma: f64,
    },
    /// Box of `size` texels per axis (`3` is a 3x3 box), `1..=`[`MAX_FILTER_TAPS`].
    Box {
        /// Width in texels.
        size: u32,
    },
    /// Binomial `C(n, k) / 2^n`, `k = 0..=n`: `n + 1` taps per axis (`n = 2`
    /// is the 3x3 `[1 2 1] / 4` filter), `n` in `1..=`[`MAX_FILTER_TAPS`].
    Binomial {
        /// Order `n`.
        n: u32,
    },
}

/// A temporal filter, applied along the slices at each pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TemporalFilter {
    /// Sampled Gaussian of `sigma` slices (as [`SpatialFilter::Gaussian`]).
    Gaussian {
        /// Standard deviation in slices.
        sigma: f64,
    },
    /// Mean of `size` consecutive slices, `1..=`[`MAX_FILTER_TAPS`].
    Box {
        /// Number of slices.
        size: u32,
    },
    /// Binomial of order `n` (`n + 1` slices).
    Binomial {
        /// Order `n`.
        n: u32,
    },
    /// Exponential moving average (TAA-like history) `a_z = (1 - alpha)
    /// a_{z-1} + alpha v_z` over a history of the whole depth `D`, started
    /// with `a_0 = v_0`: weights `alpha (1 - alpha)^k` for the `k`-th slice
    /// back (`k < D - 1`) and `(1 - alpha)^(D-1)` for the oldest, as the
    /// EMA metric of `shared/notes/quality.md` at frame `D - 1`. Every slice
    /// is treated as the last one (the torus), so all frames are served
    /// alike. `alpha` in `(0, 1]`.
    Exponential {
        /// History weight of the new frame, in `(0, 1]`.
        alpha: f64,
    },
    /// The exponential average over a history of random length `m` in
    /// `1..=D` (the history is reset by disocclusions), with FAST's
    /// weighting (Donnelly et al. 2024): `P(m)` proportional to
    /// `beta (1 - beta)^(m - 1)`, uniform for `beta = 0`. `alpha` in
    /// `(0, 1]`, `beta` in `[0, 1]`.
    WeightedExponential {
        /// History weight of the new frame, in `(0, 1]`.
        alpha: f64,
        /// Parameter of the geometric law of the history length, in `[0, 1]`.
        beta: f64,
    },
}

fn filter_error(parameter: &'static str, value: f64) -> BakeError {
    BakeError::Filter { parameter, value }
}

fn check_sigma(sigma: f64) -> Result<(), BakeError> {
    if sigma.is_finite() && sigma > 0.0 && sigma <= MAX_FILTER_SIGMA {
        Ok(())
    } else {
        Err(filter_error("sigma", sigma))
    }
}

fn check_taps(name: &'static str, n: u32) -> Result<(), BakeError> {
    if (1..=MAX_FILTER_TAPS).contains(&n) {
        Ok(())
    } else {
        Err(filter_error(name, n as f64))
    }
}

fn check_alpha(alpha: f64) -> Result<(), BakeError> {
    if alpha.is_finite() && alpha > 0.0 && alpha <= 1.0 {
        Ok(())
    } else {
        Err(filter_error("alpha", alpha))
    }
}

/// Normalised Gaussian taps for offsets `-r..=r`, `r = ceil(4 sigma)`.
fn gaussian_taps(sigma: f64) -> Vec<f64> {
    let r = libm::ceil(GAUSSIAN_TRUNCATION * sigma) as i64;
    let raw: Vec<f64> = (-r..=r)
        .map(|d| libm::exp(-((d * d) as f64) / (2.0 * sigma * sigma)))
        .collect();
    let total: f64 = raw.iter().sum();
    raw.into_iter().map(|w| w / total).collect()
}

/// `C(n, k) / 2^n` for `k = 0..=n`.
fn binomial_taps(n: u32) -> Vec<f64> {
    let mut row = vec![1.0f64];
    for _ in 0..n {
        let mut next = vec![0.5 * row[0]];
        for k in 1..row.len() {
            next.push(0.5 * (row[k - 1] + row[k]));
        }
        next.push(0.5 * row[row.len() - 1]);
        row = next;
    }
    row
}

impl SpatialFilter {
    /// Checks the parameters.
    ///
    /// # Errors
    /// [`BakeError::Filter`] naming the bad parameter.
    pub fn check(&self) -> Result<(), BakeError> {
        match *self {
            SpatialFilter::Gaussian { sigma } => check_sigma(sigma),
            SpatialFilter::Box { size } => check_taps("box size", size),
            SpatialFilter::Binomial { n } => check_taps("binomial order", n),
        }
    }

    /// The 1D taps (sum 1), first tap at offset `-(len - 1) / 2`.
    pub fn taps(&self) -> Vec<f64> {
        match *self {
            SpatialFilter::Gaussian { sigma } => gaussian_taps(sigma),
            SpatialFilter::Box { size } => vec![1.0 / size as f64; size as usize],
            SpatialFilter::Binomial { n } => binomial_taps(n),
        }
    }
}

impl TemporalFilter {
    /// Checks the parameters.
    ///
    /// # Errors
    /// [`BakeError::Filter`] naming the bad parameter (NaN or out-of-range
    /// alpha or beta, sigma, size or order).
    pub fn check(&self) -> Result<(), BakeError> {
        match *self {
            TemporalFilter::Gaussian { sigma } => check_sigma(sigma),
            TemporalFilter::Box { size } => check_taps("box size", size),
            TemporalFilter::Binomial { n } => check_taps("binomial order", n),
            TemporalFilter::Exponential { alpha } => check_alpha(alpha),
            TemporalFilter::WeightedExponential { alpha, beta } => {
                check_alpha(alpha)?;
                if beta.is_finite() && (0.0..=1.0).contains(&beta) {
                    Ok(())
                } else {
                    Err(filter_error("beta", beta))
                }
            }
        }
    }

    /// Circular autocorrelation on a torus of `depth` slices: entry `d` is
    /// the coupling of two slices `d` apart (`d` in `0..depth`); symmetric
    /// (`a[d] == a[depth - d]`), summing to 1 (the filters are normalised).
    pub fn autocorrelation(&self, depth: u32) -> Vec<f64> {
        let symmetric = |taps: Vec<f64>| circular_autocorrelation(&wrap(&taps, depth));
        match *self {
            TemporalFilter::Gaussian { sigma } => symmetric(gaussian_taps(sigma)),
            TemporalFilter::Box { size } => symmetric(vec![1.0 / size as f64; size as usize]),
            TemporalFilter::Binomial { n } => symmetric(binomial_taps(n)),
            TemporalFilter::Exponential { alpha } => {
                circular_autocorrelation(&ema_response(alpha, depth, depth))
            }
            TemporalFilter::WeightedExponential { alpha, beta } => {
                let d = depth as usize;
                let mut acc = vec![0.0; d];
                let weight = |m: u32| {
                    if beta > 0.0 {
                        beta * libm::pow(1.0 - beta, (m - 1) as f64)
                    } else {
                        1.0
                    }
                };
                let total: f64 = (1..=depth).map(weight).sum();
                for m in 1..=depth {
                    let p = weight(m) / total;
                    let a = circular_autocorrelation(&ema_response(alpha, m, depth));
                    for (s, v) in acc.iter_mut().zip(a) {
                        *s += p * v;
                    }
                }
                acc
            }
        }
    }
}

/// Spatial autocorrelation of `filter` on an axis of `len` texels (see
/// [`TemporalFilter::autocorrelation`]).
pub fn spatial_autocorrelation(filter: &SpatialFilter, len: u32) -> Vec<f64> {
    circular_autocorrelation(&wrap(&filter.taps(), len))
}

/// The EMA's impulse response over a history of `m` slices (`1..=len`),
/// zero-padded to `len`: entry `k` weighs the `k`-th slice back.
fn ema_response(alpha: f64, m: u32, len: u32) -> Vec<f64> {
    let mut h = vec![0.0; len as usize];
    for (k, w) in h.iter_mut().enumerate().take(m as usize) {
        *w = if k + 1 < m as usize {
            alpha * libm::pow(1.0 - alpha, k as f64)
        } else {
            libm::pow(1.0 - alpha, k as f64)
        };
    }
    h
}

/// Folds centred taps (first at offset `-(n - 1) / 2`) onto a torus of
/// `len`: entry `r` sums the taps at offsets congruent to `r`.
fn wrap(taps: &[f64], len: u32) -> Vec<f64> {
    let mut out = vec![0.0; len as usize];
    let first = -((taps.len() as i64 - 1) / 2);
    for (i, &w) in taps.iter().enumerate() {
        out[(first + i as i64).rem_euclid(len as i64) as usize] += w;
    }
    out
}

/// `a[d] = sum_k h[k] h[(k + d) mod n]`.
fn circular_autocorrelation(h: &[f64]) -> Vec<f64> {
    let n = h.len();
    (0..n)
        .map(|d| (0..n).map(|k| h[k] * h[(k + d) % n]).sum())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12
    }

    #[test]
    fn box_and_binomial_autocorrelations_are_exact() {
        // Box 3: [1 1 1]/3 correlated with itself = [3 2 1]/9 at offsets 0, 1, 2.
        let a = spatial_autocorrelation(&SpatialFilter::Box { size: 3 }, 16);
        for (d, v) in [(0, 3.0), (1, 2.0), (2, 1.0), (3, 0.0), (14, 1.0), (15, 2.0)] {
            assert!(close(a[d], v / 9.0), "box offset {d}: {}", a[d]);
        }
        // Binomial 2: [1 2 1]/4 with itself = [6 4 1]/16 (binomial 4).
        let b = spatial_autocorrelation(&SpatialFilter::Binomial { n: 2 }, 8);
        for (d, v) in [(0, 6.0), (1, 4.0), (2, 1.0), (3, 0.0), (6, 1.0), (7, 4.0)] {
            assert!(close(b[d], v / 16.0), "binomial offset {d}: {}", b[d]);
        }
        // Temporal box 8 on 64 slices: the triangle (8 - |d|) / 64.
        let t = TemporalFilter::Box { size: 8 }.autocorrelation(64);
        for (d, &v) in t.iter().enumerate() {
            let s = d.min(64 - d) as f64;
            assert!(close(v, (8.0 - s).max(0.0) / 64.0), "offset {d}");
        }
        // A box wider than the torus wraps: 4 of 1/4 on 2 slices = [1/2 1/2] -> [1/2 1/2].
        let w = TemporalFilter::Box { size: 4 }.autocorrelation(2);
        assert!(close(w[0], 0.5) && close(w[1], 0.5));
    }

    #[test]
    fn autocorrelations_sum_to_one_and_are_symmetric() {
        let temporal = [
            TemporalFilter::Gaussian { sigma: 1.9 },
            TemporalFilter::Box { size: 5 },
            TemporalFilter::Binomial { n: 4 },
            TemporalFilter::Exponential { alpha: 0.1 },
            TemporalFilter::WeightedExponential {
                alpha: 0.2,
                beta: 0.2,
            },
            TemporalFilter::WeightedExponential {
                alpha: 0.5,
                beta: 0.0,
            },
        ];
        for f in temporal {
            for depth in [1u32, 2, 8, 64] {
                let a = f.autocorrelation(depth);
                assert_eq!(a.len(), depth as usize);
                assert!((a.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{f:?} depth {depth}");
                for d in 1..depth as usize {
                    assert!(close(a[d], a[depth as usize - d]), "{f:?} depth {depth}");
                }
                // The peak is at offset 0 (Cauchy-Schwarz).
                assert!(a.iter().all(|&v| v <= a[0] + 1e-15), "{f:?}");
            }
        }
        for f in [
            SpatialFilter::Gaussian { sigma: 1.3435 },
            SpatialFilter::Box { size: 4 },
            SpatialFilter::Binomial { n: 3 },
        ] {
            let a = spatial_autocorrelation(&f, 32);
            assert!((a.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{f:?}");
            for d in 1..32 {
                assert!(close(a[d], a[32 - d]), "{f:?}");
            }
        }
    }

    #[test]
    fn exponential_autocorrelation_matches_its_geometric_law() {
        // alpha = 1 keeps only the newest frame: white in time.
        let a = TemporalFilter::Exponential { alpha: 1.0 }.autocorrelation(16);
        assert!(close(a[0], 1.0) && a[1..].iter().all(|&v| v == 0.0));
        // Far from the oldest frame, a[d] / a[d - 1] = 1 - alpha.
        let a = TemporalFilter::Exponential { alpha: 0.25 }.autocorrelation(64);
        assert!(((a[5] / a[4]) - 0.75).abs() < 1e-3, "{}", a[5] / a[4]);
        // The history of one frame (beta = 1) is white too.
        let w = TemporalFilter::WeightedExponential {
            alpha: 0.1,
            beta: 1.0,
        }
        .autocorrelation(8);
        assert!(close(w[0], 1.0) && w[1..].iter().all(|&v| v == 0.0));
    }

    #[test]
    fn bad_parameters_are_errors() {
        for f in [
            TemporalFilter::Exponential { alpha: f64::NAN },
            TemporalFilter::Exponential { alpha: 0.0 },
            TemporalFilter::Exponential { alpha: 1.5 },
            TemporalFilter::WeightedExponential {
                alpha: 0.1,
                beta: -0.1,
            },
            TemporalFilter::Box { size: 0 },
            TemporalFilter::Gaussian { sigma: f64::INFINITY },
        ] {
            assert!(matches!(f.check(), Err(BakeError::Filter { .. })), "{f:?}");
        }
        assert!(SpatialFilter::Binomial { n: 65 }.check().is_err());
        assert!(SpatialFilter::Gaussian { sigma: -1.0 }.check().is_err());
        assert!(SpatialFilter::Box { size: 3 }.check().is_ok());
        assert!(TemporalFilter::Exponential { alpha: 1.0 }.check().is_ok());
    }
}
