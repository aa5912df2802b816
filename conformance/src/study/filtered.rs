//! What the viewer sees: each method's error after the real-time filters a
//! renderer runs between the frame and the screen (`gpu_tracer::filter`:
//! TAA, SVGF's a-trous, both), measured per region against the reference.
//!
//! The error of a filtered frame is `luma(filter(frames 0..=t)) -
//! luma(reference)`: it includes the filter's own bias (blurred detail,
//! clamped history), which is the same for every method, so ratios to
//! white noise are pulled towards 1 where the bias dominates.
//! [`StudyResult::filter_bias`] measures that floor: the reference
//! itself sent through the same chain. The
//! *noise part* leaves the bias out: `luma(filter(frames)) -
//! luma(filter(reference))`, what the seeds control after the filter
//! ([`StudyResult::pooled_filtered_noise`]).
//!
//! This module measures (`FilteredMeter`); the figures read off the
//! errors are [`StudyResult`]'s.
//!
//! [`StudyResult`]: super::result::StudyResult
//! [`StudyResult::filter_bias`]: super::result::StudyResult
//! [`StudyResult::pooled_filtered_noise`]: super::result::StudyResult::pooled_filtered_noise

use crate::metrics::regions::Region;
use anyhow::Result;
use glam::{Vec2, Vec4};
use gpu_tracer::filter::{FilterChain, FilterSettings, FrameFilter};
use kernels::abi::GBufferGpu;
use sampler_core::Intensity;

/// The chains the studies measure, the headline first.
pub const STUDY_FILTERS: [FilterChain; 3] = [FilterChain::TaaAtrous, FilterChain::Taa, FilterChain::Atrous];

/// Per frame, the sum of the squared luma error of the filtered frame over
/// each region ([`Region::ALL`] order).
#[derive(Clone, Debug, PartialEq)]
pub struct FilteredErrors {
    /// The filter chain.
    pub chain: FilterChain,
    /// Entry `t`: squared error sums of frame `t` per region.
    pub regions: Vec<[f64; 3]>,
    /// Entry `t`: squared sums per region of the filtered frame minus the
    /// filtered reference (empty where the filtered reference is not known).
    pub noise: Vec<[f64; 3]>,
}

/// Runs every chain of [`STUDY_FILTERS`] over a method's frames and sums the
/// error per region.
pub(crate) struct FilteredMeter {
    filters: Vec<FrameFilter>,
    errors: Vec<FilteredErrors>,
    /// Per chain, the filtered reference's luma (for the noise part).
    targets: Option<Vec<Vec<f32>>>,
    /// Per chain, the last filtered frame.
    last: Vec<Vec<Vec4>>,
}

impl FilteredMeter {
    /// Filters for `width x height` frames with `settings`;
    /// `targets`: per chain of [`STUDY_FILTERS`], the filtered reference's
    /// luma, to also record the noise part.
    pub(crate) fn new(
        width: u32,
        height: u32,
        settings: FilterSettings,
        targets: Option<Vec<Vec<f32>>>,
    ) -> Result<Self> {
        let filters = STUDY_FILTERS
            .iter()
            .map(|&c| FrameFilter::new(c, settings, width, height))
            .collect::<Result<Vec<_>, _>>()?;
        let errors = STUDY_FILTERS
            .iter()
            .map(|&chain| FilteredErrors {
                chain,
                regions: Vec::new(),
                noise: Vec::new(),
            })
            .collect();
        Ok(FilteredMeter {
            filters,
            errors,
            targets,
            last: vec![Vec::new(); STUDY_FILTERS.len()],
        })
    }

    /// Filters the next frame (`motion`: backward motion per pixel, zeros
    /// for a still camera) and records its error against `reference` luma.
    pub(crate) fn frame(
        &mut self,
        color: &[Vec4],
        gbuffer: &[GBufferGpu],
        motion: &[Vec2],
        reference: &[f32],
        regions: &[Region],
    ) -> Result<()> {
        for (k, (filter, errors)) in self.filters.iter_mut().zip(&mut self.errors).enumerate() {
            let out = filter.apply(color, gbuffer, motion)?;
            errors.regions.push(region_sums(&out, reference, regions));
            if let Some(targets) = &self.targets {
                errors.noise.push(region_sums(&out, &targets[k], regions));
            }
            self.last[k] = out;
        }
        Ok(())
    }

    /// Per chain, the luma of the last filtered frame.
    pub(crate) fn last_luma(&self) -> Vec<Vec<f32>> {
        self.last
            .iter()
            .map(|frame| frame.iter().map(|c| c.intensity()).collect())
            .collect()
    }

    /// The recorded errors, one entry per chain of [`STUDY_FILTERS`].
    pub(crate) fn finish(self) -> Vec<FilteredErrors> {
        self.errors
    }
}

/// Sum over each region of `(luma(frame) - reference)^2`.
pub(crate) fn region_sums(frame: &[Vec4], reference: &[f32], regions: &[Region]) -> [f64; 3] {
    let mut sums = [0.0f64; 3];
    for ((c, r), region) in frame.iter().zip(reference).zip(regions) {
        let d = (c.intensity() - r) as f64;
        sums[*region as usize] += d * d;
    }
    sums
}

/// Sum over frames `from..` of a region's (or the whole image's) squared
/// error sums `series`.
pub(super) fn pooled_sum(series: &[[f64; 3]], region: Option<Region>, from: usize) -> Option<f64> {
    let tail = series.get(from..).filter(|t| !t.is_empty())?;
    Some(
        tail.iter()
            .map(|v| match region {
                Some(r) => v[r as usize],
                None => v.iter().sum(),
            })
            .sum(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn region_sums_split_the_squared_error() {
        let frame = [Vec4::ONE, Vec4::splat(2.0), Vec4::splat(3.0)];
        let reference = [1.0, 1.0, 1.0];
        let regions = [Region::Interior, Region::Edge, Region::Interior];
        let s = region_sums(&frame, &reference, &regions);
        assert!((s[Region::Interior as usize] - 4.0).abs() < 1e-5, "{s:?}");
        assert!((s[Region::Edge as usize] - 1.0).abs() < 1e-5);
        assert_eq!(s[Region::Emitter as usize], 0.0);
        let e = FilteredErrors {
            chain: FilterChain::Taa,
            regions: vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]],
            noise: Vec::new(),
        };
        assert_eq!(pooled_sum(&e.regions, None, 1), Some(15.0));
        assert_eq!(pooled_sum(&e.regions, Some(Region::Edge), 0), Some(7.0));
        assert_eq!(pooled_sum(&e.regions, None, 2), None);
        assert_eq!(pooled_sum(&e.noise, None, 0), None);
    }

    /// The meter's settings reach its filters: TAA's clamp changes what a noisy
    /// still sequence leaves behind, and the unclamped history is the EMA.
    #[test]
    fn the_meters_settings_reach_its_filters() {
        let (w, h) = (8u32, 8u32);
        let n = (w * h) as usize;
        let gbuffer = vec![GBufferGpu::default(); n];
        let still = vec![Vec2::ZERO; n];
        let regions = vec![Region::Interior; n];
        let reference = vec![0.5f32; n];
        let taa_error = |clamp: bool| {
            let settings = FilterSettings {
                clamp,
                ..FilterSettings::default()
            };
            let mut meter = FilteredMeter::new(w, h, settings, None).unwrap();
            for t in 0..16u32 {
                // A flat frame flickering between 0 and 1 (mean 0.5): the clamp's
                // box is the current value, the EMA's history stays near 0.5.
                let color = vec![Vec4::splat((t & 1) as f32); n];
                meter
                    .frame(&color, &gbuffer, &still, &reference, &regions)
                    .unwrap();
            }
            let errors = meter.finish();
            let taa = errors.iter().find(|e| e.chain == FilterChain::Taa).unwrap();
            pooled_sum(&taa.regions, None, 15).unwrap()
        };
        let (clamped, unclamped) = (taa_error(true), taa_error(false));
        assert!(
            unclamped < 0.1 * clamped,
            "unclamped {unclamped}, clamped {clamped}"
        );
    }
}
