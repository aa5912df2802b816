//! What a history buffer keeps: each method's error after an exponential
//! moving average of its frames (issue 29, "Measure what TAA sees").
//!
//! A real-time renderer shows a history, not a raw frame. With a still camera
//! no reprojection and no neighbourhood clamp are needed, so the plain EMA
//! isolates what the frames' temporal structure buys:
//!
//! ```text
//! h_0 = luma(frame_0),  h_t = (1 - alpha) h_{t-1} + alpha luma(frame_t),  alpha = EMA_ALPHA
//! ```
//!
//! Per frame, per region ([`Region::ALL`] order), `HistoryMeter` records the
//! squared sum of `h_t - luma(reference)` (the EMA alone) and of the same
//! error after a toroidal Gaussian blur of sigma 1 (EMA then Gaussian: FAST's
//! rendered metric, the stand-in for a history followed by a denoiser). On
//! temporally white input the EMA keeps `alpha / (2 - alpha)` of the per-frame
//! variance (0.229 of the RMS for alpha 0.1); it keeps less only where each
//! pixel's error is anti-correlated from frame to frame (blue in time).
//! Figures pool frames [`EMA_FROM`].. so that the start (`h_0` is one frame)
//! has faded: `0.9^16 = 0.19`.

use crate::metrics::regions::{square_sums_by_region, Region};
use crate::{GaussianBlur, Grid};
use anyhow::Result;

/// Weight of the new frame in the history (TAA's usual 0.1).
pub const EMA_ALPHA: f32 = 0.1;
/// First frame pooled into the history figures.
pub const EMA_FROM: usize = 16;

/// Per frame, the squared error sums of the history per region.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HistoryErrors {
    /// Entry `t`: sum over each region of `(h_t - reference)^2`.
    pub ema: Vec<[f64; 3]>,
    /// Entry `t`: the same after a Gaussian blur of sigma 1 of the whole error image.
    pub ema_blur1: Vec<[f64; 3]>,
    /// Entry `t`: sum of `(h_t - reference)^2` over the interior pixels whose
    /// first hit is glossy (`[0]`) and diffuse (`[1]`) ([`super::surfaces`]).
    pub ema_interior_by_surface: Vec<[f64; 2]>,
}

/// Runs the EMA over a method's frames and records [`HistoryErrors`].
pub(crate) struct HistoryMeter {
    size: usize,
    /// Per pixel: the first hit is glossy ([`super::surfaces::glossy_first_hits`]).
    glossy: Vec<bool>,
    history: Vec<f32>,
    blur: GaussianBlur,
    errors: HistoryErrors,
}

impl HistoryMeter {
    /// A meter for `size x size` frames whose pixels' first hits are glossy
    /// where `glossy` says so (`size * size` entries).
    pub(crate) fn new(size: u32, glossy: Vec<bool>) -> Result<Self> {
        anyhow::ensure!(
            glossy.len() == (size * size) as usize,
            "the glossy mask must be size * size"
        );
        Ok(HistoryMeter {
            size: size as usize,
            glossy,
            history: Vec::new(),
            blur: GaussianBlur::new(1.0)?,
            errors: HistoryErrors::default(),
        })
    }

    /// Adds the next frame's luma and records the history's error against
    /// `reference` luma in each region.
    pub(crate) fn frame(&mut self, luma: &[f32], reference: &[f32], regions: &[Region]) {
        if self.history.is_empty() {
            self.history = luma.to_vec();
        } else {
            for (h, l) in self.history.iter_mut().zip(luma) {
                *h += EMA_ALPHA * (l - *h);
            }
        }
        let error: Vec<f32> = self.history.iter().zip(reference).map(|(h, r)| h - r).collect();
        self.errors.ema.push(square_sums_by_region(&error, regions));
        self.errors
            .ema_interior_by_surface
            .push(interior_sums(&error, regions, &self.glossy));
        let grid = Grid::new(self.size, self.size, error).expect("frame size");
        self.errors
            .ema_blur1
            .push(square_sums_by_region(self.blur.apply(&grid).data(), regions));
    }

    /// The recorded errors.
    pub(crate) fn finish(self) -> HistoryErrors {
        self.errors
    }
}

/// Squared sums of `error` over the interior pixels whose first hit is
/// glossy (`[0]`) and diffuse (`[1]`).
fn interior_sums(error: &[f32], regions: &[Region], glossy: &[bool]) -> [f64; 2] {
    let mut sums = [0.0f64; 2];
    for ((e, r), g) in error.iter().zip(regions).zip(glossy) {
        if *r == Region::Interior {
            sums[usize::from(!g)] += (*e as f64) * (*e as f64);
        }
    }
    sums
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interior_sums_split_by_surface_and_skip_other_regions() {
        let error = [1.0f32, 2.0, 3.0, 4.0];
        let regions = [Region::Interior, Region::Interior, Region::Edge, Region::Interior];
        let glossy = [true, false, true, false];
        assert_eq!(interior_sums(&error, &regions, &glossy), [1.0, 4.0 + 16.0]);
    }

    /// White noise through the EMA keeps `alpha / (2 - alpha)` of its variance;
    /// its first difference over frames (blue in time, same variance) keeps
    /// `alpha` times that.
    #[test]
    fn the_ema_keeps_the_analytic_share_of_white_noise_and_less_of_blue() {
        let size = 32;
        let n = size * size;
        let regions = vec![Region::Interior; n];
        let reference = vec![0.0f32; n];
        let glossy: Vec<bool> = (0..n).map(|i| i % 3 == 0).collect();
        let mut white = HistoryMeter::new(size as u32, glossy.clone()).unwrap();
        let mut blue = HistoryMeter::new(size as u32, glossy).unwrap();
        let mut state = 1u32;
        let mut previous = vec![0.0f32; n];
        let frames = 400;
        for _ in 0..frames {
            let frame: Vec<f32> = (0..n)
                .map(|_| {
                    state = sampler_core::sequences::seed::hash_u32(state);
                    (state >> 8) as f32 / (1 << 24) as f32 - 0.5
                })
                .collect();
            white.frame(&frame, &reference, &regions);
            let difference: Vec<f32> = frame
                .iter()
                .zip(&previous)
                .map(|(v, p)| (v - p) * std::f32::consts::FRAC_1_SQRT_2)
                .collect();
            blue.frame(&difference, &reference, &regions);
            previous = frame;
        }
        let (w, b) = (white.finish(), blue.finish());
        let mean = |e: &HistoryErrors| {
            e.ema[EMA_FROM..].iter().map(|v| v[2]).sum::<f64>() / ((frames as usize - EMA_FROM) * n) as f64
        };
        let expected = (1.0 / 12.0) * (EMA_ALPHA / (2.0 - EMA_ALPHA)) as f64;
        let measured = mean(&w);
        assert!(
            (measured / expected - 1.0).abs() < 0.05,
            "white EMA variance {measured} vs {expected}"
        );
        let ratio = mean(&b) / measured;
        assert!(
            (ratio / EMA_ALPHA as f64 - 1.0).abs() < 0.15,
            "blue-in-time EMA keeps {ratio} of white's"
        );
        // The blur removes most of white noise's (spatially white) error.
        let blurred = w.ema_blur1[EMA_FROM..].iter().map(|v| v[2]).sum::<f64>();
        let plain = w.ema[EMA_FROM..].iter().map(|v| v[2]).sum::<f64>();
        assert!(blurred < 0.2 * plain, "{blurred} vs {plain}");
        // The interior split by surface adds up to the interior.
        for (whole, split) in w.ema.iter().zip(&w.ema_interior_by_surface) {
            assert!((whole[2] - split[0] - split[1]).abs() <= 1e-9 * whole[2].max(1.0));
            assert!(split[0] > 0.0 && split[1] > split[0]);
        }
    }
}
