//! What path regularisation ([`StudyConfig::glossy_regularization`]) costs in
//! bias and saves in noise, per region.
//!
//! A study with regularisation measures its rows against the *regularised*
//! reference, relative to white noise rendered with the same regularisation:
//! how blue the error is. What the regularisation changes besides is measured
//! here, from the two references (regularised and unbiased, same seeds):
//! - **bias**: the RMS luma difference of the two references, relative to
//!   white's error after the history (EMA) *without* regularisation. The two
//!   references share their seeds, so their noise is correlated and partly
//!   cancels: the figure is an upper bound of the bias in expectation
//!   (`E[d^2] = bias^2 + Var(noise difference)`), not an estimate of it.
//! - **white's noise**: the per-sample standard deviation of the regularised
//!   image over the unbiased one's (each from its reference's two halves).
//!
//! White's EMA error is `sqrt(v * alpha / (2 - alpha))` for per-sample
//! variance `v` (`super::history`), so a row that reads `r` of the
//! regularised white after the EMA has, against the unbiased reference, about
//! `sqrt((r * n)^2 + b^2)` of the unbiased white's EMA error (`n` the noise
//! ratio and `b` the bias figure below; the bias adds in quadrature since it
//! does not average away).
//!
//! [`StudyConfig::glossy_regularization`]: super::config::StudyConfig::glossy_regularization

use super::history::EMA_ALPHA;
use super::reference::Reference;
use crate::metrics::regions::Region;
use anyhow::{ensure, Result};

/// The regularisation's effect, per region ([`Region::ALL`] order) and on the
/// whole image.
#[derive(Clone, Debug, PartialEq)]
pub struct RegularizationEffect {
    /// The regularisation strength, in `(0, 1]`.
    pub strength: f32,
    /// Upper bound of the bias's RMS luma over white's EMA error without
    /// regularisation (module docs): emitter zone, edges, interior.
    pub bias: [f64; 3],
    /// The same on the whole image.
    pub bias_whole: f64,
    /// White's per-sample standard deviation with regularisation over without:
    /// emitter zone, edges, interior.
    pub noise: [f64; 3],
    /// The same on the whole image.
    pub noise_whole: f64,
}

impl RegularizationEffect {
    /// Compares the `regularized` reference with the `unbiased` one (same size,
    /// same samples per pixel) over `regions` (one per pixel).
    ///
    /// # Errors
    /// References of different sizes or sample counts, or `regions` of another
    /// length.
    pub fn measure(
        strength: f32,
        regularized: &Reference,
        unbiased: &Reference,
        regions: &[Region],
    ) -> Result<RegularizationEffect> {
        ensure!(
            regularized.luma.len() == unbiased.luma.len() && regularized.spp == unbiased.spp,
            "the references differ in size or samples per pixel"
        );
        ensure!(
            regions.len() == unbiased.luma.len(),
            "{} regions for {} pixels",
            regions.len(),
            unbiased.luma.len()
        );
        // Per region (and the whole image, index 3): sums of the squared
        // difference and of each reference's noise variance, and pixel counts.
        let mut diff = [0.0f64; 4];
        let mut noise_reg = [0.0f64; 4];
        let mut noise_unb = [0.0f64; 4];
        let mut count = [0usize; 4];
        for (i, region) in regions.iter().enumerate() {
            let d = f64::from(regularized.luma[i] - unbiased.luma[i]);
            for k in [*region as usize, 3] {
                diff[k] += d * d;
                noise_reg[k] += f64::from(regularized.noise[i]);
                noise_unb[k] += f64::from(unbiased.noise[i]);
                count[k] += 1;
            }
        }
        // Per-sample variance = the reference's variance of its mean times its spp.
        let spp = f64::from(unbiased.spp);
        let alpha = f64::from(EMA_ALPHA);
        let white_ema = |k: usize| (noise_unb[k] / count[k] as f64 * spp * alpha / (2.0 - alpha)).sqrt();
        let bias = |k: usize| {
            if count[k] == 0 {
                return 0.0;
            }
            (diff[k] / count[k] as f64).sqrt() / white_ema(k)
        };
        let noise = |k: usize| {
            if count[k] == 0 {
                return 0.0;
            }
            (noise_reg[k] / noise_unb[k]).sqrt()
        };
        Ok(RegularizationEffect {
            strength,
            bias: [bias(0), bias(1), bias(2)],
            bias_whole: bias(3),
            noise: [noise(0), noise(1), noise(2)],
            noise_whole: noise(3),
        })
    }

    /// A markdown paragraph and table of the effect.
    pub fn markdown(&self) -> String {
        let mut s = format!(
            "Glossy regularisation {} (rows, white and reference regularised; figures above relative to the \
             regularised white): its bias (upper bound: RMS luma of the regularised reference minus the unbiased \
             one, same seeds) over white's EMA error without regularisation, and white's per-sample noise with \
             over without it:\n\n",
            self.strength
        );
        s += "| figure | whole | emitter zone | edges | interior |\n|---|---|---|---|---|\n";
        s += &format!(
            "| bias / white's EMA error | {:.3} | {:.3} | {:.3} | {:.3} |\n",
            self.bias_whole, self.bias[0], self.bias[1], self.bias[2]
        );
        s += &format!(
            "| white's noise, with / without | {:.3} | {:.3} | {:.3} | {:.3} |\n",
            self.noise_whole, self.noise[0], self.noise[1], self.noise[2]
        );
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reference(luma: Vec<f32>, noise: Vec<f32>) -> Reference {
        let n = luma.len() as f64;
        Reference {
            size: 2,
            spp: 64,
            rgb: luma.iter().map(|&l| glam::Vec3::splat(l)).collect(),
            noise_var: noise.iter().map(|&v| f64::from(v)).sum::<f64>() / n,
            luma,
            noise,
        }
    }

    #[test]
    fn bias_is_the_difference_over_whites_history_error() {
        let regions = [Region::Emitter, Region::Edge, Region::Interior, Region::Interior];
        let unbiased = reference(vec![1.0; 4], vec![1e-3; 4]);
        // The interior darker by 0.05, its noise variance a quarter.
        let regularized = reference(vec![1.0, 1.0, 0.95, 0.95], vec![1e-3, 1e-3, 2.5e-4, 2.5e-4]);
        let e = RegularizationEffect::measure(0.5, &regularized, &unbiased, &regions).unwrap();
        let white_ema = (1e-3f64 * 64.0 * 0.1 / 1.9).sqrt();
        assert!((e.bias[2] - 0.05 / white_ema).abs() < 1e-4, "{e:?}");
        assert_eq!((e.bias[0], e.bias[1]), (0.0, 0.0));
        assert!(
            (e.bias_whole - (0.05f64.powi(2) / 2.0).sqrt() / white_ema).abs() < 1e-4,
            "{e:?}"
        );
        assert!((e.noise[2] - 0.5).abs() < 1e-6, "{e:?}");
        assert!((e.noise[0] - 1.0).abs() < 1e-6, "{e:?}");
        assert!(e.markdown().contains("| bias / white's EMA error |"));
    }

    #[test]
    fn mismatched_inputs_are_refused() {
        let a = reference(vec![1.0; 4], vec![1e-3; 4]);
        let b = reference(vec![1.0; 3], vec![1e-3; 3]);
        assert!(RegularizationEffect::measure(1.0, &a, &b, &[Region::Interior; 4]).is_err());
        assert!(RegularizationEffect::measure(1.0, &a, &a, &[Region::Interior; 3]).is_err());
    }
}
