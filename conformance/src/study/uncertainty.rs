//! How far one run's accumulated figures can be trusted.
//!
//! A region's accumulated error is a sum of per-pixel squared errors, and a
//! few pixels can carry most of it: on the Cornell box at 256x256 the ten
//! worst of the emitter zone's 756 pixels (the light's silhouette) carry
//! 36-43% of its error after 128 frames, in every row. Treating the pixels as
//! independent, the relative standard error of a region's mean squared error
//! is `sqrt((E[d^4] - E[d^2]^2) / count) / E[d^2]`, and that of a ratio of
//! two runs' RMSEs (a method against white) half the root of the two squared.
//! Pixels of a blue-noise error are anti-correlated, and every pixel of an
//! a-priori sampler shares each frame's randomisation, so this is a guide to
//! the scatter, not a bound (QUALITY.md, "ZSobol in time").

use super::method::Method;
use super::result::{MethodRun, StudyResult, TEMPORAL_MEANS};
use crate::metrics::regions::Region;

/// Relative standard error of a mean square from the sums of squares `sum2`
/// and fourth powers `sum4` of `count` independent terms; `None` without
/// terms or error.
pub fn relative_standard_error(sum2: f64, sum4: f64, count: f64) -> Option<f64> {
    if count < 1.0 || sum2 <= 0.0 {
        return None;
    }
    let mean2 = sum2 / count;
    let var = (sum4 / count - mean2 * mean2).max(0.0);
    Some((var / count).sqrt() / mean2)
}

impl StudyResult {
    /// One standard error of [`StudyResult::accumulated_region`]'s ratio for
    /// `method`, relative to the ratio, from the spread of both runs'
    /// per-pixel squared errors (module docs). `None` for a missing run,
    /// frame count or empty region.
    pub fn accumulated_uncertainty(&self, method: Method, n: usize, region: Option<Region>) -> Option<f64> {
        let pixels = (self.config.size as f64).powi(2);
        let rel = |r: &MethodRun| -> Option<f64> {
            let i = n.checked_sub(1)?;
            let (s2, s4) = (r.acc_regions.get(i)?, r.acc_fourth.get(i)?);
            let (sum2, sum4, share) = match region {
                Some(k) => (s2[k as usize], s4[k as usize], self.region_shares[k as usize]),
                None => (s2.iter().sum(), s4.iter().sum(), 1.0),
            };
            relative_standard_error(sum2, sum4, share * pixels)
        };
        let (m, w) = (rel(self.run(method)?)?, rel(self.run(Method::White)?)?);
        Some(0.5 * (m * m + w * w).sqrt())
    }

    /// Markdown table of [`Self::accumulated_uncertainty`] for the mean of
    /// the most frames of [`TEMPORAL_MEANS`] the study rendered, per region;
    /// empty if it rendered fewer than the first.
    pub fn uncertainty_markdown(&self) -> String {
        let Some(&n) = TEMPORAL_MEANS.iter().rev().find(|&&n| n <= self.config.frames) else {
            return String::new();
        };
        let cell = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{:.1}%", 100.0 * v));
        let mut s = format!(
            "\nOne run's uncertainty of the mean-{n} ratios (one standard error relative to the figure, from the \
             spread of the per-pixel squared errors; a guide, not a bound):\n\n| method | whole | emitter zone | \
             edges | interior |\n|---|---|---|---|---|\n"
        );
        for r in self.runs.iter().filter(|r| r.method != Method::White) {
            let m = r.method;
            s += &format!(
                "| {} | {}",
                m.name(),
                cell(self.accumulated_uncertainty(m, n as usize, None))
            );
            for region in Region::ALL {
                s += &format!(
                    " | {}",
                    cell(self.accumulated_uncertainty(m, n as usize, Some(region)))
                );
            }
            s += " |\n";
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Equal terms have no spread; one term carrying everything has the
    /// spread of a single draw; many equal-variance Gaussian terms give
    /// `sqrt(2 / count)`.
    #[test]
    fn the_standard_error_follows_the_spread_of_the_terms() {
        assert_eq!(relative_standard_error(4.0, 4.0, 4.0), Some(0.0));
        let one = relative_standard_error(100.0, 100.0 * 100.0, 100.0).unwrap();
        assert!((one - 0.99f64.sqrt()).abs() < 1e-12, "{one}");
        let count = 40_000;
        let mut state = 7u32;
        let (mut s2, mut s4) = (0.0, 0.0);
        for _ in 0..count {
            // Box-Muller from two hashed uniforms.
            state = sampler_core::sequences::seed::hash_u32(state);
            let u1 = ((state >> 8) as f64 + 0.5) / (1u32 << 24) as f64;
            state = sampler_core::sequences::seed::hash_u32(state);
            let u2 = (state >> 8) as f64 / (1u32 << 24) as f64;
            let g = (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos();
            s2 += g * g;
            s4 += g * g * g * g;
        }
        let se = relative_standard_error(s2, s4, count as f64).unwrap();
        let expected = (2.0 / count as f64).sqrt();
        assert!((se / expected - 1.0).abs() < 0.1, "{se} vs {expected}");
        assert_eq!(relative_standard_error(0.0, 0.0, 10.0), None);
        assert_eq!(relative_standard_error(1.0, 1.0, 0.0), None);
    }
}
