//! The search behind the spatiotemporal sampler's Kronecker generators
//! ([`KRONECKER_GENERATORS`](crate::sequences::kronecker::KRONECKER_GENERATORS)).
//!
//! # Score
//!
//! A pixel's pair over frames is `frac(n g + s)`, `n` the sample index, `g`
//! the pair's generator and `s` the pixel's shift. For each candidate `g`
//! (a pair of 0.32 fixed-point words drawn from the seed), random shifts
//! and random Heaviside integrands ([`heaviside_integrands`]) give, relative
//! to white noise's exact figures (independent uniform samples, an
//! integrand `f` of mean `I` has per-sample variance `I (1 - I)`):
//! - the RMSE of an exponential history (`alpha` [`HISTORY_ALPHA`], first
//!   frame as the start) over frames `16..`[`SCORE_FRAMES`], and
//! - the RMSE of the running mean after 8, 32 and 128 frames.
//!
//! The score is the history's figure plus [`MEAN_WEIGHT`] times the sum of
//! the three means': a history should keep little error, and the mean should
//! still converge faster than white noise. Lower is better.
//!
//! # Choice
//!
//! Candidates are sorted by score and taken in that order, pair 0 (the pixel
//! jitter) first, skipping a candidate whose two words, together with those
//! of any of the [`RESONANCE_NEIGHBOURS`] pairs chosen before it, have an
//! integer combination with coefficients in `{-1, 0, 1}` (not all zero)
//! closer than [`RESONANCE_GAP`] to an integer: such points would lie near a
//! few hyperplanes of the pairs' joint 4D space instead of filling it.
//!
//! The shipped table takes pairs 1.. from this search and replaces its
//! pair 0 by a fixed generator
//! ([`JITTER_GENERATOR`](crate::sequences::kronecker::JITTER_GENERATOR)),
//! which keeps less after the history on held-out steps than the search's
//! first choice: 24 training steps and the means' weight pick a winner
//! that is not the best history.

use super::keys::{heaviside_integrands, HeavisideIntegrand};
use super::SplitMix64;
use alloc::vec::Vec;

/// The history's blend factor in the score.
pub const HISTORY_ALPHA: f64 = 0.1;
/// Frames scored.
pub const SCORE_FRAMES: u32 = 128;
/// Weight of the running means in the score.
pub const MEAN_WEIGHT: f64 = 0.3;
/// Pairs chosen before a candidate that it must not resonate with.
pub const RESONANCE_NEIGHBOURS: usize = 3;
/// Smallest accepted distance of a `{-1, 0, 1}` combination from an
/// integer, in 0.32 fixed point (`2^-10`).
pub const RESONANCE_GAP: u32 = 1 << 22;

/// Parameters of a generator search.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct KroneckerSearch {
    /// Generators (pairs) to choose.
    pub pairs: u32,
    /// Candidates drawn and scored (at least `pairs`).
    pub candidates: u32,
    /// Random shifts per candidate.
    pub shifts: u32,
    /// Random Heaviside integrands per candidate.
    pub integrands: u32,
    /// Seed of the candidates, shifts and integrands.
    pub seed: u64,
}

/// White noise's RMSE of the history at frame `t` and of the running mean
/// after `n` frames, per unit of per-sample standard deviation.
fn white_history_factor(t: u32) -> f64 {
    let a = HISTORY_ALPHA;
    let b = (1.0 - a) * (1.0 - a);
    // h_t = (1-a)^t e_0 + sum_{k=1..t} a (1-a)^(t-k) e_k.
    let mut var = libm::pow(b, t as f64);
    let mut w = a * a;
    for _ in 0..t {
        var += w;
        w *= b;
    }
    var
}

/// The score of generator `g` and its four figures (history, mean 8, 32,
/// 128), each relative to white noise.
pub fn kronecker_score(
    g: [u32; 2],
    shifts: &[[u32; 2]],
    integrands: &[HeavisideIntegrand],
) -> (f64, [f64; 4]) {
    let q = 1.0 / 4_294_967_296.0;
    let (mut sq, mut white) = ([0.0f64; 4], [0.0f64; 4]);
    let white_hist: Vec<f64> = (0..SCORE_FRAMES).map(white_history_factor).collect();
    for f in integrands {
        let integral = f.integral();
        let v = integral * (1.0 - integral);
        for s in shifts {
            let (mut h, mut sum) = (0.0, 0.0);
            for t in 0..SCORE_FRAMES {
                let x = t.wrapping_mul(g[0]).wrapping_add(s[0]) as f64 * q;
                let y = t.wrapping_mul(g[1]).wrapping_add(s[1]) as f64 * q;
                let e = f.eval(x, y) - integral;
                h = if t == 0 { e } else { h + HISTORY_ALPHA * (e - h) };
                sum += e;
                if t >= 16 {
                    sq[0] += h * h;
                    white[0] += v * white_hist[t as usize];
                }
                for (k, n) in [(1usize, 8u32), (2, 32), (3, 128)] {
                    if t + 1 == n {
                        let m = sum / n as f64;
                        sq[k] += m * m;
                        white[k] += v / n as f64;
                    }
                }
            }
        }
    }
    let rel = [0, 1, 2, 3].map(|k| libm::sqrt(sq[k] / white[k].max(1e-300)));
    (rel[0] + MEAN_WEIGHT * (rel[1] + rel[2] + rel[3]), rel)
}

/// Whether two generator pairs (or one, `b = [0, 0]`) have a `{-1, 0, 1}`
/// combination within [`RESONANCE_GAP`] of an integer.
pub fn resonates(a: [u32; 2], b: [u32; 2]) -> bool {
    let words = [a[0], a[1], b[0], b[1]];
    for code in 1..81u32 {
        let mut c = code;
        let mut sum = 0u32;
        let mut used = false;
        for &w in &words {
            match c % 3 {
                1 => {
                    sum = sum.wrapping_add(w);
                    used = true;
                }
                2 => {
                    sum = sum.wrapping_sub(w);
                    used = true;
                }
                _ => {}
            }
            c /= 3;
        }
        let gap = sum.min(sum.wrapping_neg());
        if used && gap < RESONANCE_GAP && (code % 9 != 0 || b != [0, 0]) {
            return true;
        }
    }
    false
}

/// Runs the search: `pairs` generators, two words each, in pair order, and
/// the figures of each ([`kronecker_score`]). `None` if fewer than `pairs`
/// candidates survive the resonance test.
pub fn search_kronecker_generators(params: &KroneckerSearch) -> Option<(Vec<u32>, Vec<[f64; 4]>)> {
    let mut rng = SplitMix64::new(params.seed ^ 0x4B52_4F4E_4543_4B52);
    let shifts: Vec<[u32; 2]> = (0..params.shifts)
        .map(|_| {
            let r = rng.next_u64();
            [r as u32, (r >> 32) as u32]
        })
        .collect();
    let integrands = heaviside_integrands(params.integrands, params.seed);
    let mut scored: Vec<(f64, [u32; 2], [f64; 4])> = (0..params.candidates)
        .map(|_| {
            let r = rng.next_u64();
            let g = [r as u32 | 1, (r >> 32) as u32 | 1];
            let (score, figures) = kronecker_score(g, &shifts, &integrands);
            (score, g, figures)
        })
        .collect();
    scored.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let mut chosen: Vec<[u32; 2]> = Vec::new();
    let mut figures = Vec::new();
    for (_, g, f) in scored {
        if chosen.len() == params.pairs as usize {
            break;
        }
        let recent = &chosen[chosen.len().saturating_sub(RESONANCE_NEIGHBOURS)..];
        if resonates(g, [0, 0]) || recent.iter().any(|&c| resonates(g, c)) {
            continue;
        }
        chosen.push(g);
        figures.push(f);
    }
    (chosen.len() == params.pairs as usize).then(|| (chosen.concat(), figures))
}
