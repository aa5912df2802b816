//! Void-and-cluster dither masks (Ulichney 1993), toroidal, with exact
//! histograms.
//!
//! 1. Initial pattern: `max(1, n / 10)` ones at seeded random texels, then
//!    repeatedly move the tightest cluster (the one with the largest energy)
//!    to the largest void (the zero with the smallest energy) until that
//!    stops lowering the energy.
//! 2. Ranks below the initial count: remove tightest clusters one by one,
//!    ranking them downwards from `ones - 1` to 0.
//! 3. Ranks from the initial count up: from the initial pattern, fill the
//!    largest void one at a time up to `n - 1` (for a Gaussian energy,
//!    Ulichney's third phase — the tightest cluster of the inverted pattern —
//!    is the same texel, so one loop serves both).
//!
//! Energies are exact integers (see `energy`), ties go to the lowest
//! index: a given size, sigma and seed always give the same mask.

use super::energy::Kernel;
use super::extrema::{Extrema, Track, ONE_BIAS};
use super::{check_sigma, check_size, BakeError, Progress, SplitMix64, Throttle};
use alloc::vec;
use alloc::vec::Vec;

/// Parameters of a 2D void-and-cluster mask.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaskParams {
    /// Width in texels: a power of two in `1..=`[`MAX_MASK_SIDE`](super::MAX_MASK_SIDE).
    pub width: u32,
    /// Height in texels: a power of two in `1..=`[`MAX_MASK_SIDE`](super::MAX_MASK_SIDE).
    pub height: u32,
    /// Standard deviation of the Gaussian energy in texels, in
    /// [`MIN_SIGMA`](super::MIN_SIGMA)`..=`[`MAX_SIGMA`](super::MAX_SIGMA);
    /// 1.5 and 1.9 are common (1.9 corresponds to a filter sigma of
    /// `1.9 / sqrt(2)`).
    pub sigma: f64,
    /// Seed of the random initial pattern.
    pub seed: u64,
}

/// Bakes a toroidal void-and-cluster mask: `width * height` ranks,
/// row-major, each of `0..width * height` exactly once.
///
/// # Errors
/// [`BakeError::Size`] for a side that is zero, not a power of two or too
/// large; [`BakeError::Sigma`] for a sigma out of range.
///
/// ```
/// use sampler_core::bake::{bake_mask, no_progress, MaskParams};
/// let ranks = bake_mask(&MaskParams { width: 16, height: 8, sigma: 1.5, seed: 1 }, &mut no_progress)?;
/// let mut sorted = ranks.clone();
/// sorted.sort();
/// assert!(sorted.iter().enumerate().all(|(i, &r)| r == i as u32));
/// # Ok::<(), sampler_core::bake::BakeError>(())
/// ```
pub fn bake_mask(params: &MaskParams, progress: Progress<'_>) -> Result<Vec<u32>, BakeError> {
    check_size(params.width, params.height, 1)?;
    check_sigma(params.sigma)?;
    let kernel = Kernel::new(params.width, params.height, 1, params.sigma, params.sigma);
    Ok(rank_texels(&kernel, params.seed, progress))
}

/// Void-and-cluster over the kernel's volume: the rank of every texel.
pub(crate) fn rank_texels(kernel: &Kernel, seed: u64, progress: Progress<'_>) -> Vec<u32> {
    let n = kernel.len();
    let total = n as u64;
    let mut throttle = Throttle::new(total);
    // Energy plus ONE_BIAS for the ones (see `extrema`).
    let mut keys = vec![0i32; n];
    let mut extrema = Extrema::new(n);
    let mut rng = SplitMix64::new(seed);
    let initial = (n / 10).max(1);
    let mut placed = 0;
    while placed < initial {
        let i = rng.below(n as u64) as usize;
        if keys[i] < ONE_BIAS {
            keys[i] += ONE_BIAS;
            kernel.splat(i, 1, &mut keys, &mut extrema);
            placed += 1;
        }
    }
    extrema.refresh(&keys);
    relax(kernel, &mut keys, &mut extrema);

    let mut ranks = vec![0u32; n];
    // Phase 2 and 3 start from the initial pattern: keep a copy.
    let (mut keys2, mut extrema2) = (keys.clone(), extrema.clone());
    extrema.track(Track::Clusters);
    extrema2.track(Track::Voids);
    let mut done = 0u64;
    for rank in (0..initial).rev() {
        let c = extrema.tightest_cluster().expect("ones remain while rank >= 0");
        set(kernel, c, false, &mut keys, &mut extrema);
        ranks[c] = rank as u32;
        done += 1;
        throttle.tick(done, total, progress);
    }
    for rank in initial..n {
        let v = extrema2.largest_void().expect("zeros remain while rank < n");
        set(kernel, v, true, &mut keys2, &mut extrema2);
        ranks[v] = rank as u32;
        done += 1;
        throttle.tick(done, total, progress);
    }
    ranks
}

/// Makes texel `i` a one (`on`) or a zero and refreshes the cache.
#[inline]
fn set(kernel: &Kernel, i: usize, on: bool, keys: &mut [i32], extrema: &mut Extrema) {
    let sign = if on { 1 } else { -1 };
    keys[i] += sign * ONE_BIAS;
    kernel.splat(i, sign, keys, extrema);
    extrema.touch(i);
    extrema.refresh(keys);
}

/// Phase 1: moves tightest clusters into largest voids while that strictly
/// lowers the mover's energy (so the total energy strictly decreases and the
/// loop ends); capped at `16 n` moves as a guard.
fn relax(kernel: &Kernel, keys: &mut [i32], extrema: &mut Extrema) {
    let cap = 16 * keys.len();
    for _ in 0..cap {
        let Some(c) = extrema.tightest_cluster() else {
            return;
        };
        set(kernel, c, false, keys, extrema);
        let v = extrema.largest_void().expect("c is a zero now");
        // Both are zeros here, so their keys are their energies.
        if v == c || keys[v] >= keys[c] {
            set(kernel, c, true, keys, extrema);
            return;
        }
        set(kernel, v, true, keys, extrema);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bake::no_progress;

    fn is_exact_histogram(ranks: &[u32]) -> bool {
        let mut seen = vec![false; ranks.len()];
        ranks
            .iter()
            .all(|&r| (r as usize) < seen.len() && !core::mem::replace(&mut seen[r as usize], true))
    }

    #[test]
    fn every_rank_once_on_many_shapes() {
        for (w, h) in [
            (1, 1),
            (2, 1),
            (1, 8),
            (2, 2),
            (4, 16),
            (8, 8),
            (32, 16),
            (64, 64),
        ] {
            for sigma in [0.5, 1.5, 1.9, 4.0] {
                let p = MaskParams {
                    width: w,
                    height: h,
                    sigma,
                    seed: 9,
                };
                let ranks = bake_mask(&p, &mut no_progress).unwrap();
                assert_eq!(ranks.len(), (w * h) as usize);
                assert!(is_exact_histogram(&ranks), "{w}x{h} sigma {sigma}");
            }
        }
    }

    #[test]
    fn deterministic_and_seed_dependent() {
        let p = MaskParams {
            width: 32,
            height: 32,
            sigma: 1.9,
            seed: 5,
        };
        let a = bake_mask(&p, &mut no_progress).unwrap();
        assert_eq!(a, bake_mask(&p, &mut no_progress).unwrap());
        let b = bake_mask(&MaskParams { seed: 6, ..p }, &mut no_progress).unwrap();
        assert_ne!(a, b);
    }

    #[test]
    fn bad_parameters_are_errors() {
        let p = MaskParams {
            width: 24,
            height: 32,
            sigma: 1.9,
            seed: 5,
        };
        assert!(matches!(
            bake_mask(&p, &mut no_progress),
            Err(BakeError::Size { .. })
        ));
        let p = MaskParams { width: 0, ..p };
        assert!(matches!(
            bake_mask(&p, &mut no_progress),
            Err(BakeError::Size { .. })
        ));
        let p = MaskParams {
            width: 32,
            sigma: f64::NAN,
            ..p
        };
        assert!(matches!(
            bake_mask(&p, &mut no_progress),
            Err(BakeError::Sigma { .. })
        ));
    }

    #[test]
    fn progress_reaches_the_total() {
        let p = MaskParams {
            width: 16,
            height: 16,
            sigma: 1.9,
            seed: 1,
        };
        let mut last = (0, 0);
        let mut calls = 0;
        bake_mask(&p, &mut |d, t| {
            assert!(d >= last.0);
            last = (d, t);
            calls += 1;
        })
        .unwrap();
        assert_eq!(last, (256, 256));
        assert!(calls <= 1001);
    }

    /// Blue noise has little low-frequency power: a direct DFT of the
    /// 32x32 mask over |f| <= 1/8 cycles/texel (excluding DC) holds far less
    /// power than white noise (whose expected power per bin is n * var).
    #[test]
    fn low_frequencies_are_suppressed() {
        let (w, h) = (32usize, 32usize);
        let ranks = bake_mask(
            &MaskParams {
                width: 32,
                height: 32,
                sigma: 1.9,
                seed: 3,
            },
            &mut no_progress,
        )
        .unwrap();
        let n = (w * h) as f64;
        let v: Vec<f64> = ranks.iter().map(|&r| (r as f64 + 0.5) / n - 0.5).collect();
        let var = v.iter().map(|x| x * x).sum::<f64>() / n;
        let (mut power, mut bins) = (0.0, 0);
        for ky in -4i32..=4 {
            for kx in -4i32..=4 {
                if (kx == 0 && ky == 0) || kx * kx + ky * ky > 16 {
                    continue;
                }
                let (mut re, mut im) = (0.0, 0.0);
                for y in 0..h {
                    for x in 0..w {
                        let a = -2.0
                            * core::f64::consts::PI
                            * (kx as f64 * x as f64 / w as f64 + ky as f64 * y as f64 / h as f64);
                        re += v[y * w + x] * libm::cos(a);
                        im += v[y * w + x] * libm::sin(a);
                    }
                }
                power += re * re + im * im;
                bins += 1;
            }
        }
        let ratio = power / bins as f64 / (n * var);
        assert!(ratio < 0.02, "low-frequency power ratio {ratio}");
    }
}
