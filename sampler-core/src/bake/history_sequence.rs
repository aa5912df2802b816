//! A free periodic sequence of 2D points for the spatiotemporal sampler's
//! pairs, optimised for the error an exponential history keeps (the idea of
//! FAST, Donnelly et al. 2024, applied to a pixel's sequence in time instead
//! of a dither mask).
//!
//! # Objective
//!
//! A pixel's pair at frame `t` is `x_(t mod P) + s`, the sequence point
//! rotated by the pixel's shift `s` (wrapping). Over `R` training rows, each
//! a random Heaviside integrand with a random shift, the value error of
//! frame `t` is `e_r(t) = f_r(x_t + s_r) - I_r`. The sequence is scored by:
//! - the **history**: the steady-state exponential history of the periodic
//!   error, `h_r(t) = sum_k w_k e_r(t - k)` with `w_k = alpha (1 - alpha)^k /
//!   (1 - (1 - alpha)^P)` (indices mod `P`), its mean square over every `t`
//!   of the period (so every window counts, as a history's sliding window
//!   does), relative to white noise's `alpha / (2 - alpha) I (1 - I)`;
//! - the **running means** of the first 8, 32 and `P` frames, relative to
//!   white noise's `I (1 - I) / n`, with weight [`MEAN_WEIGHT`] each.
//!
//! # Optimiser
//!
//! Annealed point moves: a point is displaced by a random vector whose
//! scale shrinks over the run (or redrawn uniformly), and the move is kept
//! if it lowers the score or, rarely, by the Metropolis rule. A move changes
//! only the rows whose step separates the old and new point, so its effect
//! on the history is computed exactly in `O(P)` per changed row.

use super::keys::HeavisideIntegrand;
use super::SplitMix64;
use super::{BakeError, MAX_MASK_SIDE, MEAN_WEIGHT};
use alloc::vec;
use alloc::vec::Vec;

/// Parameters of a history-sequence bake (the period is the start's length).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HistorySequenceParams {
    /// Random shifts per integrand.
    pub shifts: u32,
    /// The history's blend factor (`0 < alpha < 1`).
    pub alpha: f64,
    /// Proposed moves in all.
    pub moves: u32,
    /// Weight of each running mean's figure in the score (the history's is 1).
    pub mean_weight: f64,
    /// Seed of the start, the rows and the moves.
    pub seed: u64,
}

impl Default for HistorySequenceParams {
    fn default() -> Self {
        HistorySequenceParams {
            shifts: 24,
            alpha: 0.1,
            moves: 400_000,
            mean_weight: MEAN_WEIGHT,
            seed: 1,
        }
    }
}

const Q: f64 = 1.0 / 4_294_967_296.0;

struct Rows {
    integrands: Vec<HeavisideIntegrand>,
    integral: Vec<f64>,
    shift: Vec<[u32; 2]>,
}

impl Rows {
    fn value(&self, r: usize, p: [u32; 2]) -> f64 {
        let s = self.shift[r];
        let x = p[0].wrapping_add(s[0]) as f64 * Q;
        let y = p[1].wrapping_add(s[1]) as f64 * Q;
        self.integrands[r].eval(x, y)
    }
}

/// Lengths of the running means scored: 8, 32 and the period `p` frames
/// (none longer than the period).
fn mean_lengths(p: usize) -> [usize; 3] {
    [8.min(p), 32.min(p), p]
}

/// Row `r`'s error at every frame of the period: `e[t] = f_r(x_t + s_r) - I_r`.
fn row_errors(rows: &Rows, r: usize, points: &[[u32; 2]], e: &mut [f64]) {
    for (et, &x) in e.iter_mut().zip(points) {
        *et = rows.value(r, x) - rows.integral[r];
    }
}

/// The steady-state history of the periodic error `e` at every frame of the
/// period: `h[t] = sum_k w[k] e[t - k]` (indices mod the period).
fn periodic_history(e: &[f64], w: &[f64], h: &mut [f64]) {
    let p = e.len();
    for (t, ht) in h.iter_mut().enumerate() {
        *ht = (0..p).map(|k| w[k] * e[(t + p - k) % p]).sum();
    }
}

/// White noise's figures for an integrand of mean `integral` over a period
/// of `p` frames: the history's summed square over the period, and the
/// running means' squares ([`mean_lengths`]).
fn white_norms(integral: f64, p: usize, alpha: f64) -> (f64, [f64; 3]) {
    let v = integral * (1.0 - integral);
    (
        v * p as f64 * alpha / (2.0 - alpha),
        mean_lengths(p).map(|n| v / n as f64),
    )
}

/// The figures of a periodic sequence on rows, relative to white noise:
/// history, mean 8, mean 32, mean of the period.
fn figures(points: &[[u32; 2]], rows: &Rows, alpha: f64) -> [f64; 4] {
    let p = points.len();
    let (w, lengths) = (history_weights(p, alpha), mean_lengths(p));
    let (mut sq, mut white) = ([0.0f64; 4], [0.0f64; 4]);
    let (mut e, mut h) = (vec![0.0; p], vec![0.0; p]);
    for r in 0..rows.shift.len() {
        row_errors(rows, r, points, &mut e);
        periodic_history(&e, &w, &mut h);
        sq[0] += h.iter().map(|x| x * x).sum::<f64>();
        let (white_history, white_means) = white_norms(rows.integral[r], p, alpha);
        white[0] += white_history;
        for j in 0..3 {
            let m = e[..lengths[j]].iter().sum::<f64>() / lengths[j] as f64;
            sq[j + 1] += m * m;
            white[j + 1] += white_means[j];
        }
    }
    [0, 1, 2, 3].map(|j| libm::sqrt(sq[j] / white[j].max(1e-300)))
}

fn history_weights(p: usize, alpha: f64) -> Vec<f64> {
    let norm = 1.0 - libm::pow(1.0 - alpha, p as f64);
    (0..p)
        .map(|k| alpha * libm::pow(1.0 - alpha, k as f64) / norm)
        .collect()
}

/// Scores `points` (a periodic sequence, 0.32 fixed point) on `integrands`
/// with `shifts` random shifts each (drawn from `seed`): history, mean 8,
/// mean 32, mean of the period, each relative to white noise.
pub fn history_sequence_figures(
    points: &[[u32; 2]],
    integrands: &[HeavisideIntegrand],
    shifts: u32,
    alpha: f64,
    seed: u64,
) -> [f64; 4] {
    let rows = make_rows(integrands, shifts, seed);
    figures(points, &rows, alpha)
}

fn make_rows(integrands: &[HeavisideIntegrand], shifts: u32, seed: u64) -> Rows {
    let mut rng = SplitMix64::new(seed ^ 0x5348_4946_5453_0001);
    let mut rows = Rows {
        integrands: Vec::new(),
        integral: Vec::new(),
        shift: Vec::new(),
    };
    for f in integrands {
        let i = f.integral();
        for _ in 0..shifts {
            let r = rng.next_u64();
            rows.integrands.push(*f);
            rows.integral.push(i);
            rows.shift.push([r as u32, (r >> 32) as u32]);
        }
    }
    rows
}

/// Bakes a sequence: starts from `start` (0.32 fixed-point points; its
/// length is the period `P`), moves points as the module docs say on the
/// rows made of `integrands` and [`HistorySequenceParams::shifts`] random
/// shifts each, and returns the final sequence and its training figures
/// ([`history_sequence_figures`]'s order). Deterministic for given inputs.
///
/// # Errors
/// [`BakeError::Size`] unless `P` is a power of two in
/// `8..=`[`MAX_MASK_SIDE`] (reported as the width); [`BakeError::Filter`]
/// unless `0 < alpha < 1`; [`BakeError::Weight`] for a negative or
/// non-finite mean weight.
pub fn bake_history_sequence(
    params: &HistorySequenceParams,
    integrands: &[HeavisideIntegrand],
    start: &[[u32; 2]],
) -> Result<(Vec<[u32; 2]>, [f64; 4]), BakeError> {
    let p = start.len();
    if !(8..=MAX_MASK_SIDE as usize).contains(&p) || !p.is_power_of_two() {
        return Err(BakeError::Size {
            width: p.min(u32::MAX as usize) as u32,
            height: 1,
            depth: 1,
        });
    }
    if !(params.alpha > 0.0 && params.alpha < 1.0) {
        return Err(BakeError::Filter {
            parameter: "alpha",
            value: params.alpha,
        });
    }
    if !(params.mean_weight >= 0.0 && params.mean_weight.is_finite()) {
        return Err(BakeError::Weight {
            weight: params.mean_weight,
        });
    }
    let rows = make_rows(integrands, params.shifts, params.seed);
    let n_rows = rows.shift.len();
    let alpha = params.alpha;
    let w = history_weights(p, alpha);
    let w2: f64 = w.iter().map(|x| x * x).sum();
    let mut points = start.to_vec();
    // Per row: the history over the period and the running means' sums;
    // white noise's normalisers.
    let mean_n = mean_lengths(p);
    let mut h = vec![0.0f64; n_rows * p];
    let mut sums = vec![[0.0f64; 3]; n_rows];
    let (mut hist_norm, mut mean_norm) = (0.0, [0.0f64; 3]);
    let mut e = vec![0.0f64; p];
    for r in 0..n_rows {
        row_errors(&rows, r, &points, &mut e);
        periodic_history(&e, &w, &mut h[r * p..(r + 1) * p]);
        sums[r] = mean_n.map(|n| e[..n].iter().sum());
        let (white_history, white_means) = white_norms(rows.integral[r], p, alpha);
        hist_norm += white_history;
        for j in 0..3 {
            mean_norm[j] += white_means[j];
        }
    }
    let mut hist_sq: f64 = h.iter().map(|x| x * x).sum();
    let mut mean_sq = [0.0f64; 3];
    for row in &sums {
        for j in 0..3 {
            mean_sq[j] += (row[j] / mean_n[j] as f64) * (row[j] / mean_n[j] as f64);
        }
    }
    let score = |hist_sq: f64, mean_sq: &[f64; 3]| {
        libm::sqrt(hist_sq / hist_norm)
            + params.mean_weight * (0..3).map(|j| libm::sqrt(mean_sq[j] / mean_norm[j])).sum::<f64>()
    };
    let mut current = score(hist_sq, &mean_sq);
    let mut rng = SplitMix64::new(params.seed ^ 0x4849_5354_5345_5130);
    let mut changed: Vec<(usize, f64)> = Vec::new();
    for m in 0..params.moves {
        let progress = m as f64 / params.moves.max(1) as f64;
        let t0 = rng.below(p as u64) as usize;
        let old = points[t0];
        let new = if rng.below(16) == 0 {
            let r = rng.next_u64();
            [r as u32, (r >> 32) as u32]
        } else {
            let scale = 0.25 * libm::pow(0.02, progress);
            let dx = ((rng.unit_f64() - 0.5) * 2.0 * scale * 4_294_967_296.0) as i64;
            let dy = ((rng.unit_f64() - 0.5) * 2.0 * scale * 4_294_967_296.0) as i64;
            [old[0].wrapping_add(dx as u32), old[1].wrapping_add(dy as u32)]
        };
        changed.clear();
        for r in 0..n_rows {
            let d = rows.value(r, new) - rows.value(r, old);
            if d != 0.0 {
                changed.push((r, d));
            }
        }
        let mut new_hist = hist_sq;
        let mut new_mean = mean_sq;
        for &(r, d) in &changed {
            let hr = &h[r * p..(r + 1) * p];
            let c: f64 = (0..p).map(|k| hr[(t0 + k) % p] * w[k]).sum();
            new_hist += 2.0 * d * c + d * d * w2;
            for j in 0..3 {
                if t0 < mean_n[j] {
                    let n = mean_n[j] as f64;
                    let (a, b) = (sums[r][j] / n, (sums[r][j] + d) / n);
                    new_mean[j] += b * b - a * a;
                }
            }
        }
        let candidate = score(new_hist, &new_mean);
        let temperature = 2e-4 * (1.0 - progress);
        let accept = candidate < current
            || (temperature > 0.0 && rng.unit_f64() < libm::exp((current - candidate) / temperature));
        if accept {
            points[t0] = new;
            for &(r, d) in &changed {
                let hr = &mut h[r * p..(r + 1) * p];
                for k in 0..p {
                    hr[(t0 + k) % p] += d * w[k];
                }
                for j in 0..3 {
                    if t0 < mean_n[j] {
                        sums[r][j] += d;
                    }
                }
            }
            hist_sq = new_hist;
            mean_sq = new_mean;
            current = candidate;
        }
    }
    let f = figures(&points, &rows, alpha);
    // The incremental sums agree with the recomputation.
    debug_assert!((libm::sqrt(hist_sq.max(0.0) / hist_norm) - f[0]).abs() < 1e-6);
    Ok((points, f))
}

#[cfg(test)]
mod tests {
    use super::super::heaviside_integrands;
    use super::*;

    fn random_points(n: u32, seed: u32) -> Vec<[u32; 2]> {
        (0..n)
            .map(|i| {
                let a = crate::sequences::seed::hash_u32(i.wrapping_mul(2).wrapping_add(seed));
                [a, crate::sequences::seed::hash_u32(a)]
            })
            .collect()
    }

    /// Independent random points score like white noise (1 within the
    /// rows' scatter); the Kronecker sequence scores well below.
    #[test]
    fn white_points_score_one_and_kronecker_less() {
        let steps = heaviside_integrands(48, 5);
        let white = history_sequence_figures(&random_points(128, 3), &steps, 32, 0.1, 2);
        assert!((0.85..1.15).contains(&white[0]), "{white:?}");
        let kronecker: Vec<[u32; 2]> = (0..128)
            .map(|n| crate::sequences::kronecker::kronecker_point_u32(n, 0))
            .collect();
        let k = history_sequence_figures(&kronecker, &steps, 32, 0.1, 2);
        assert!(k[0] < 0.7 && k[3] < 0.5, "{k:?}");
    }

    /// The bake lowers its training score from a random start, and its
    /// incremental bookkeeping matches a recomputation (the debug
    /// assertion at its end; tests build with debug assertions).
    #[test]
    fn bake_lowers_the_training_history() {
        let steps = heaviside_integrands(32, 11);
        let params = HistorySequenceParams {
            shifts: 8,
            moves: 20_000,
            mean_weight: 0.0,
            ..Default::default()
        };
        let start = random_points(16, 7);
        let before = history_sequence_figures(&start, &steps, params.shifts, params.alpha, params.seed);
        let (points, after) = bake_history_sequence(&params, &steps, &start).unwrap();
        assert_eq!(points.len(), 16);
        assert!(after[0] < 0.8 * before[0], "{before:?} -> {after:?}");
        let again = bake_history_sequence(&params, &steps, &start).unwrap();
        assert_eq!(again.0, points);
    }

    #[test]
    fn bad_parameters_are_errors() {
        let steps = heaviside_integrands(4, 1);
        let p = HistorySequenceParams::default();
        assert!(matches!(
            bake_history_sequence(&p, &steps, &random_points(12, 1)),
            Err(BakeError::Size { width: 12, .. })
        ));
        let bad = HistorySequenceParams { alpha: 1.0, ..p };
        assert!(matches!(
            bake_history_sequence(&bad, &steps, &random_points(16, 1)),
            Err(BakeError::Filter { .. })
        ));
        let bad = HistorySequenceParams {
            mean_weight: f64::NAN,
            ..p
        };
        assert!(matches!(
            bake_history_sequence(&bad, &steps, &random_points(16, 1)),
            Err(BakeError::Weight { .. })
        ));
    }
}
