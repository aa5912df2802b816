//! What a field of per-pixel samples does to the error a viewer sees, on
//! Heaviside integrands, without a renderer: the blurred error of each
//! frame, the error of an exponential history, and that history blurred
//! (FAST's rendered metric). Used to compare shift tiles
//! ([`bake_shift_tile`](super::bake_shift_tile)) with held-out integrands
//! and pairs, and against white noise.

use super::filters::SpatialFilter;
use super::keys::HeavisideIntegrand;
use alloc::vec;
use glam::UVec2;

/// Root-mean-square errors over pixels, frames and integrands (one value
/// per integrand's sample, in the integrand's units).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FieldQuality {
    /// Each frame's error after a Gaussian blur of sigma 1 (all frames).
    pub raw_blur: f64,
    /// The exponential history's error (frames `skip..`).
    pub history: f64,
    /// The history's error after a Gaussian blur of sigma 1 (frames `skip..`).
    pub history_blur: f64,
}

impl FieldQuality {
    /// Each figure divided by `white`'s.
    pub fn relative_to(&self, white: &FieldQuality) -> FieldQuality {
        FieldQuality {
            raw_blur: self.raw_blur / white.raw_blur,
            history: self.history / white.history,
            history_blur: self.history_blur / white.history_blur,
        }
    }
}

/// Blur with the normalised 1D `taps` (centred) along both axes of a
/// `side x side` torus, in place.
fn blur(side: usize, taps: &[f64], image: &mut [f64], scratch: &mut [f64]) {
    let r = (taps.len() / 2) as i32;
    let wrap = |i: usize, d: i32| (i as i32 + d).rem_euclid(side as i32) as usize;
    for y in 0..side {
        for x in 0..side {
            scratch[y * side + x] = (-r..=r)
                .zip(taps)
                .map(|(d, w)| w * image[y * side + wrap(x, d)])
                .sum();
        }
    }
    for y in 0..side {
        for x in 0..side {
            image[y * side + x] = (-r..=r)
                .zip(taps)
                .map(|(d, w)| w * scratch[wrap(y, d) * side + x])
                .sum();
        }
    }
}

/// The errors of `sample(pixel, pair, frame)` (a point of `[0, 1)^2` in
/// 0.32 fixed point) over a `side x side` torus of pixels, `frames` frames
/// (at least `skip + 1`), every pair of `pairs` and every integrand: the
/// history is `h_0 = e_0`, `h_t = (1 - alpha) h_(t-1) + alpha e_t`.
pub fn field_quality(
    side: u32,
    pairs: core::ops::Range<u32>,
    frames: u32,
    skip: u32,
    alpha: f64,
    integrands: &[HeavisideIntegrand],
    sample: impl Fn(UVec2, u32, u32) -> [u32; 2],
) -> FieldQuality {
    let n = (side * side) as usize;
    let q = 1.0 / 4_294_967_296.0;
    let (mut raw, mut hist, mut hist_blur) = (0.0, 0.0, 0.0);
    let (mut raw_count, mut hist_count) = (0u64, 0u64);
    let mut e = vec![0.0; n];
    let mut h = vec![0.0; n];
    let mut work = vec![0.0; n];
    let mut scratch = vec![0.0; n];
    let taps = SpatialFilter::Gaussian { sigma: 1.0 }.taps();
    for pair in pairs {
        for f in integrands {
            let integral = f.integral();
            for t in 0..frames {
                for (i, v) in e.iter_mut().enumerate() {
                    let p = UVec2::new(i as u32 % side, i as u32 / side);
                    let [x, y] = sample(p, pair, t);
                    *v = f.eval(x as f64 * q, y as f64 * q) - integral;
                }
                for (hv, ev) in h.iter_mut().zip(&e) {
                    *hv = if t == 0 { *ev } else { *hv + alpha * (ev - *hv) };
                }
                work.copy_from_slice(&e);
                blur(side as usize, &taps, &mut work, &mut scratch);
                raw += work.iter().map(|v| v * v).sum::<f64>();
                raw_count += n as u64;
                if t >= skip {
                    hist += h.iter().map(|v| v * v).sum::<f64>();
                    work.copy_from_slice(&h);
                    blur(side as usize, &taps, &mut work, &mut scratch);
                    hist_blur += work.iter().map(|v| v * v).sum::<f64>();
                    hist_count += n as u64;
                }
            }
        }
    }
    let rms = |s: f64, c: u64| libm::sqrt(s / c.max(1) as f64);
    FieldQuality {
        raw_blur: rms(raw, raw_count),
        history: rms(hist, hist_count),
        history_blur: rms(hist_blur, hist_count),
    }
}
