//! A measured rendered-quality study ([`StudyResult`]: one [`MethodRun`] per method)
//! and every figure read off it: the relative figures (white = 1), before and after
//! the real-time filters, and the tables and summaries that print them.

use super::config::{StudyConfig, ACCUMULATION_POINTS, GOAL_FRAME};
use super::feature_diagnostics::FeatureDiagnostics;
use super::filtered::{pooled_sum, FilteredErrors, STUDY_FILTERS};
use super::history::{HistoryErrors, EMA_ALPHA, EMA_FROM};
use super::insets::Inset;
use super::method::Method;
use super::regularization::RegularizationEffect;
use crate::metrics::regions::Region;
use glam::Vec3;
use gpu_tracer::filter::FilterChain;

/// A frame kept for pictures.
#[derive(Clone, Debug)]
pub struct Snapshot {
    /// Frame index.
    pub frame: u32,
    /// The frame's colour.
    pub rgb: Vec<Vec3>,
    /// Its luma error against the reference.
    pub error: Vec<f32>,
}

/// Everything measured for one method.
#[derive(Clone, Debug)]
pub struct MethodRun {
    /// The method.
    pub method: Method,
    /// Per frame, per inset: low-frequency power ratio of the error (white noise = 1).
    pub lf_insets: Vec<Vec<f64>>,
    /// Per frame: mean over insets of the low-frequency power ratio of the error with
    /// the albedo divided out (error / albedo luma of the pixel's primary hit, from the
    /// frame-0 G-buffer): the irradiance error the seeds arrange, before the texture
    /// multiplies it. Equal to [`Self::lf`] on untextured insets.
    pub lf_demodulated: Vec<f64>,
    /// Per frame, with [`StudyConfig::modulate_by`](super::config::StudyConfig::modulate_by)
    /// (else empty): mean over insets of the low-frequency power ratio of the error
    /// multiplied by the other scene's albedo over this one's
    /// ([`Study::modulation`](super::setup::Study::modulation)).
    pub lf_modulated: Vec<f64>,
    /// Per frame: RMS error, unblurred, whole image.
    pub rmse: Vec<f64>,
    /// Per frame: RMS error after a Gaussian blur of sigma 1.
    pub blur1: Vec<f64>,
    /// Per frame: RMS error after a Gaussian blur of sigma 2.
    pub blur2: Vec<f64>,
    /// Per frame: sum of the squared sigma-1-blurred error over each region
    /// ([`Region::ALL`] order; regions of [`Study::regions`](super::setup::Study::regions)).
    pub blur1_regions: Vec<[f64; 3]>,
    /// Entry `n - 1`: sum over each region of the squared error of the mean of frames
    /// `0..n` (reference noise not removed).
    pub acc_regions: Vec<[f64; 3]>,
    /// Entry `n - 1`: the same sums of the fourth power of that error, for the
    /// one-run uncertainty of the accumulated figures ([`super::uncertainty`]).
    pub acc_fourth: Vec<[f64; 3]>,
    /// For the permuting rows (permute, permute-jitter and the feature-aware ones):
    /// per region, the fraction of (pixel, frame) pairs whose seed the pixel already
    /// had in an earlier frame. With fixed seeds a repeated seed repeats the pixel's
    /// estimate (its jitter, for the rows without the sampler's jitter), so repeats
    /// stall the accumulation.
    pub seed_repeats: Option<[f64; 3]>,
    /// Entry `n - 1`: RMS of the mean of frames `0..n` minus the reference.
    pub acc_rmse: Vec<f64>,
    /// [`Self::acc_rmse`] with the reference's own noise removed ([`crate::study`],
    /// "Reference noise").
    pub acc_rmse_corrected: Vec<f64>,
    /// Radially averaged power of the first inset's error, averaged over the frames
    /// from [`GOAL_FRAME`] on (or the last frame); index = radius in bins.
    pub radial: Vec<f64>,
    /// Power spectrum of the error (DFT order, `(kx, ky)` at `ky * side + kx`, DC
    /// at 0), averaged over the frames from [`GOAL_FRAME`] on and over every inset,
    /// each cropped to its central `spectrum_side` square (the smallest inset's
    /// side) so the spectra share one frequency grid; in units of luma².
    pub spectrum: Vec<f64>,
    /// Side of [`Self::spectrum`].
    pub spectrum_side: usize,
    /// Temporal power spectrum of a pixel's error ([`crate::metrics::temporal::temporal_power`]:
    /// entry `k` is `k / len` cycles per frame, entry 0 is 0), averaged over the first
    /// inset's pixels, over the frames from [`GOAL_FRAME`] on.
    pub temporal: Vec<f64>,
    /// The accumulated mean luma (mean of frames `0..n`, row-major) for each `n`
    /// of [`ACCUMULATION_SNAPSHOTS`](super::config::ACCUMULATION_SNAPSHOTS) the run reached.
    pub accumulated: Vec<(u32, Vec<f32>)>,
    /// Frame [`GOAL_FRAME`] (or the last).
    pub snapshot: Snapshot,
    /// The error after each real-time filter chain
    /// ([`STUDY_FILTERS`]; empty when the study's
    /// [`StudyConfig::filters`] is off).
    pub filtered: Vec<FilteredErrors>,
    /// The error after the exponential history alone and after the history
    /// then a Gaussian blur ([`super::history`]).
    pub history: HistoryErrors,
}

impl MethodRun {
    /// Mean over insets of the low-frequency ratio at frame `t`.
    pub fn lf(&self, t: usize) -> f64 {
        let v = &self.lf_insets[t];
        v.iter().sum::<f64>() / v.len() as f64
    }
}

/// A measured study: the reference and one run per method.
#[derive(Debug)]
pub struct StudyResult {
    /// The configuration.
    pub config: StudyConfig,
    /// The insets used.
    pub insets: Vec<Inset>,
    /// Reference noise variance (luma, per pixel).
    pub reference_noise_var: f64,
    /// Share of the image of each region ([`Region::ALL`] order).
    pub region_shares: [f64; 3],
    /// Share of the interior's pixels whose first hit is glossy
    /// ([`super::surfaces`]); 0 on a scene without glossy surfaces.
    pub glossy_interior_share: f64,
    /// What the feature-aware permutation sees in this frame ([`FeatureDiagnostics`]).
    pub features: FeatureDiagnostics,
    /// The runs, in the order they were requested.
    pub runs: Vec<MethodRun>,
    /// The reference itself sent through each filter chain, one frame per
    /// study frame: the filters' own error floor ([`Self::filter_bias`]).
    pub filter_bias: Vec<FilteredErrors>,
    /// With [`StudyConfig::glossy_regularization`] above 0: its bias and its
    /// effect on white's noise ([`RegularizationEffect`]).
    pub regularization: Option<RegularizationEffect>,
}

/// Which error of the history ([`super::history`]) a figure reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HistoryMetric {
    /// The exponential history alone.
    Ema,
    /// The history, then a Gaussian blur of sigma 1.
    EmaBlur1,
}

/// Frame counts at which the temporal table reports the accumulated mean.
pub const TEMPORAL_MEANS: [u32; 3] = [8, 32, 128];

/// A relative figure: `method / white` for one metric.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Metric {
    /// Low-frequency power ratio on the insets at a frame.
    LowFrequency,
    /// Blurred (sigma 1) RMSE at a frame.
    Blur1,
    /// Blurred (sigma 2) RMSE at a frame.
    Blur2,
    /// Unblurred RMSE at a frame.
    Rmse,
    /// Accumulated RMSE after `n` frames (index `n - 1`), reference noise removed.
    Accumulated,
    /// Accumulated RMSE, raw.
    AccumulatedRaw,
}

impl StudyResult {
    /// The run of `method`, if measured.
    pub fn run(&self, method: Method) -> Option<&MethodRun> {
        self.runs.iter().find(|r| r.method == method)
    }

    /// Blurred (sigma 1) RMSE over frames `from..` of `method` in `region` (`None`: the
    /// whole image), relative to white's: as [`Self::pooled`] with [`Metric::Blur1`],
    /// restricted to the region's pixels. `None` for a missing run, no frames or an
    /// empty region.
    pub fn pooled_region(&self, method: Method, region: Option<Region>, from: usize) -> Option<f64> {
        let Some(region) = region else {
            return self.pooled(method, Metric::Blur1, from);
        };
        let k = region as usize;
        let sum = |r: &MethodRun| -> Option<f64> {
            let tail = r.blur1_regions.get(from..).filter(|t| !t.is_empty())?;
            Some(tail.iter().map(|v| v[k]).sum())
        };
        let (m, w) = (sum(self.run(method)?)?, sum(self.run(Method::White)?)?);
        (w > 0.0).then(|| (m / w).sqrt())
    }

    /// Mean over frames `from..` of `method`'s [`MethodRun::lf_demodulated`] divided by
    /// white's at the same frame.
    pub fn lf_demodulated_mean(&self, method: Method, from: usize) -> Option<f64> {
        self.per_frame_ratio_mean(method, from, |r| &r.lf_demodulated)
    }

    /// Mean over frames `from..` of `method`'s [`MethodRun::lf_modulated`] divided by
    /// white's at the same frame (`None` without
    /// [`StudyConfig::modulate_by`](super::config::StudyConfig::modulate_by)).
    pub fn lf_modulated_mean(&self, method: Method, from: usize) -> Option<f64> {
        self.per_frame_ratio_mean(method, from, |r| &r.lf_modulated)
    }

    fn per_frame_ratio_mean(
        &self,
        method: Method,
        from: usize,
        series: impl Fn(&MethodRun) -> &Vec<f64>,
    ) -> Option<f64> {
        let (m, w) = (series(self.run(method)?), series(self.run(Method::White)?));
        let n = m.len().min(w.len());
        (n > from).then(|| (from..n).map(|i| m[i] / w[i]).sum::<f64>() / (n - from) as f64)
    }

    /// Markdown tables of the study (white = 1): whole-image figures, the blurred RMSE
    /// per region, and the feature diagnostics.
    pub fn markdown(&self) -> String {
        let c = &self.config;
        let from = (GOAL_FRAME.min(c.frames - 1)) as usize;
        let points: Vec<u32> = ACCUMULATION_POINTS
            .iter()
            .copied()
            .filter(|&n| n <= c.frames && n >= 64)
            .collect();
        let cell = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.3}"));
        let mut s = format!(
            "{8} {0}x{0}, {1} spp, depth {2}, {3} frames, reference {4} spp, block {5}, tile {6}, salt {7}{9}; \
             white = 1, pooled over frames {from}..\n\n",
            c.size,
            c.spp,
            c.max_depth,
            c.frames,
            c.ref_spp,
            c.block,
            c.tile.side(),
            c.salt,
            c.scene.name(),
            if c.taa_clamp { "" } else { ", TAA without its clamp" }
        );
        let modulated = c.modulate_by.is_some();
        s += "| method | LF @8 | LF mean 8.. | LF demodulated mean 8..";
        if let Some(other) = c.modulate_by {
            s += &format!(" | LF modulated by {} mean 8..", other.name());
        }
        s += " | blur s1 8.. | blur s2 8..";
        for n in &points {
            s += &format!(" | acc {n}");
        }
        s += " |\n|---|---|---|---|---|---";
        if modulated {
            s += "|---";
        }
        s += &"|---".repeat(points.len());
        s += "|\n";
        for r in &self.runs {
            let m = r.method;
            let frames = r.rmse.len();
            let lf_mean = (from..frames)
                .map(|i| self.relative(m, Metric::LowFrequency, i).unwrap_or(f64::NAN))
                .sum::<f64>()
                / (frames - from).max(1) as f64;
            s += &format!(
                "| {} | {} | {lf_mean:.3} | {}",
                m.name(),
                cell(self.relative(m, Metric::LowFrequency, from)),
                cell(self.lf_demodulated_mean(m, from)),
            );
            if modulated {
                s += &format!(" | {}", cell(self.lf_modulated_mean(m, from)));
            }
            s += &format!(
                " | {} | {}",
                cell(self.pooled(m, Metric::Blur1, from)),
                cell(self.pooled(m, Metric::Blur2, from)),
            );
            for &n in &points {
                s += &format!(
                    " | {}",
                    cell(self.relative(m, Metric::Accumulated, n as usize - 1))
                );
            }
            s += " |\n";
        }
        let sh = self.region_shares;
        s += &format!(
            "\nBlurred RMSE (sigma 1) per region, frames {from}.. (regions from the frame-0 G-buffer: \
             emitter zone {:.2}%, edges {:.2}%, interior {:.2}% of the image):\n\n\
             | method | whole | emitter zone | edges | interior |\n|---|---|---|---|---|\n",
            100.0 * sh[0],
            100.0 * sh[1],
            100.0 * sh[2]
        );
        for r in &self.runs {
            s += &format!(
                "| {} | {}",
                r.method.name(),
                cell(self.pooled_region(r.method, None, from))
            );
            for region in Region::ALL {
                s += &format!(" | {}", cell(self.pooled_region(r.method, Some(region), from)));
            }
            s += " |\n";
        }
        let last = c.frames as usize;
        s += &format!(
            "\nAccumulated RMSE per region after {last} frames (raw, reference noise not removed), and the \
             fraction of (pixel, frame) pairs whose seed the pixel already had:\n\n\
             | method | acc emitter zone | acc edges | acc interior | repeated seeds emitter / edges / interior |\n\
             |---|---|---|---|---|\n"
        );
        for r in &self.runs {
            s += &format!("| {}", r.method.name());
            for region in Region::ALL {
                s += &format!(
                    " | {}",
                    cell(self.accumulated_region(r.method, last, Some(region)))
                );
            }
            s += &match r.seed_repeats {
                Some(v) => format!(
                    " | {:.1}% / {:.1}% / {:.1}% |\n",
                    100.0 * v[0],
                    100.0 * v[1],
                    100.0 * v[2]
                ),
                None => " | - |\n".to_string(),
            };
        }
        // Share of white's blurred squared error per region.
        if let Some(w) = self.run(Method::White) {
            let tail = &w.blur1_regions[from.min(w.blur1_regions.len())..];
            let total: f64 = tail.iter().map(|v| v.iter().sum::<f64>()).sum();
            if total > 0.0 {
                let part = |k: usize| 100.0 * tail.iter().map(|v| v[k]).sum::<f64>() / total;
                s += &format!(
                    "\nWhite's blurred squared error by region: emitter zone {:.1}%, edges {:.1}%, interior {:.1}%.\n",
                    part(0),
                    part(1),
                    part(2)
                );
            }
        }
        if c.frames as usize > EMA_FROM {
            s += &format!(
                "\nWhat a history keeps (still camera; EMA alpha {EMA_ALPHA} from frame 0, no clamp, RMSE over frames \
                 {EMA_FROM}..; EMA + G1: then a Gaussian blur of sigma 1; mean n: the mean of the first n frames, \
                 reference noise not removed; white = 1):\n\n"
            );
            s += &self.temporal_markdown();
            s += &self.uncertainty_markdown();
            s += &self.surfaces_markdown();
        }
        if self.runs.iter().any(|r| !r.filtered.is_empty()) {
            s += &format!(
                "\nAfter the real-time filters (RMSE of the filtered frame against the reference over frames {from}.., \
                 white after the same filter = 1; the last row is the reference itself filtered: the filter's bias):\n\n"
            );
            s += &self.filtered_markdown(from);
        }
        if let Some(effect) = &self.regularization {
            s += "\n";
            s += &effect.markdown();
        }
        let f = &self.features;
        s += &format!(
            "\nFeature diagnostics (still camera, default thresholds): {:.1}% of blocks hold several groups \
             ({:.1}% of pixels, {:.2} groups each); {:.1}% of retarget moves are cut, {:.1}% stay in place.\n",
            100.0 * f.split_blocks,
            100.0 * f.pixels_in_split_blocks,
            f.groups_per_split_block,
            100.0 * f.cut_moves,
            100.0 * f.fixed_moves
        );
        s += &format!(
            "Per region (emitter zone / edges / interior): pixels in split blocks {:.1}% / {:.1}% / {:.1}%, \
             moves out of its pixels cut {:.1}% / {:.1}% / {:.1}%. Surface ids with more than one albedo: {}.\n",
            100.0 * f.split_by_region[0],
            100.0 * f.split_by_region[1],
            100.0 * f.split_by_region[2],
            100.0 * f.cut_by_region[0],
            100.0 * f.cut_by_region[1],
            100.0 * f.cut_by_region[2],
            f.ids_with_varying_albedo
        );
        s
    }

    /// RMS over frames `from..` of a per-frame RMSE `metric` ([`Metric::Blur1`],
    /// [`Metric::Blur2`] or [`Metric::Rmse`]) of `method`, divided by white's: the
    /// method's RMSE over all those frames relative to white's. Unlike the mean of the
    /// per-frame ratios it is not pulled up by frames in which white's error happens to
    /// be small (a 1-spp frame's error is dominated by a few pixels, so single frames
    /// vary a lot). `None` for other metrics, a missing run or no frames.
    pub fn pooled(&self, method: Method, metric: Metric, from: usize) -> Option<f64> {
        let series = |r: &MethodRun| -> Option<f64> {
            let v = match metric {
                Metric::Blur1 => &r.blur1,
                Metric::Blur2 => &r.blur2,
                Metric::Rmse => &r.rmse,
                _ => return None,
            };
            let tail = v.get(from..).filter(|t| !t.is_empty())?;
            Some(tail.iter().map(|x| x * x).sum())
        };
        let m = series(self.run(method)?)?;
        let w = series(self.run(Method::White)?)?;
        Some((m / w).sqrt())
    }

    /// `metric` of `method` divided by white's at frame index `i` (for the accumulated
    /// metrics: after `i + 1` frames). `None` if either run is missing or `i` is out of
    /// range.
    pub fn relative(&self, method: Method, metric: Metric, i: usize) -> Option<f64> {
        let m = self.run(method)?;
        let w = self.run(Method::White)?;
        let get = |r: &MethodRun| -> Option<f64> {
            Some(match metric {
                Metric::LowFrequency => {
                    r.lf_insets.get(i)?;
                    r.lf(i)
                }
                Metric::Blur1 => *r.blur1.get(i)?,
                Metric::Blur2 => *r.blur2.get(i)?,
                Metric::Rmse => *r.rmse.get(i)?,
                Metric::Accumulated => *r.acc_rmse_corrected.get(i)?,
                Metric::AccumulatedRaw => *r.acc_rmse.get(i)?,
            })
        };
        Some(get(m)? / get(w)?)
    }

    /// A plain-text table of the headline figures (relative to white).
    pub fn summary(&self) -> String {
        let c = &self.config;
        let t = (GOAL_FRAME.min(c.frames - 1)) as usize;
        let mut s = format!(
            "{8} {0}x{0}, {1} spp, {2} frames, reference {3} spp (noise var {4:.3e}), block {5}, tile {6}, seed mode {7}\n",
            c.size,
            c.spp,
            c.frames,
            c.ref_spp,
            self.reference_noise_var,
            c.block,
            c.tile.side(),
            c.seed_mode,
            c.scene.name()
        );
        s += &format!(
            "{:<14} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8}",
            "method",
            format!("LF@{t}"),
            "LFmean",
            format!("blur1@{t}"),
            format!("blur2@{t}"),
            "blur1avg",
            "blur1rms"
        );
        let points: Vec<u32> = ACCUMULATION_POINTS
            .iter()
            .copied()
            .filter(|&n| n <= c.frames)
            .collect();
        for n in &points {
            s += &format!(" {:>13}", format!("acc{n} (raw)"));
        }
        s += "\n";
        for r in &self.runs {
            let rel = |m, i| self.relative(r.method, m, i).unwrap_or(f64::NAN);
            let frames = r.rmse.len();
            let from = t.min(frames - 1);
            let avg = |m| (from..frames).map(|i| rel(m, i)).sum::<f64>() / (frames - from) as f64;
            s += &format!(
                "{:<14} {:>8.3} {:>8.3} {:>8.3} {:>8.3} {:>8.3} {:>8.3}",
                r.method.name(),
                rel(Metric::LowFrequency, t),
                avg(Metric::LowFrequency),
                rel(Metric::Blur1, t),
                rel(Metric::Blur2, t),
                avg(Metric::Blur1),
                self.pooled(r.method, Metric::Blur1, from).unwrap_or(f64::NAN)
            );
            for &n in &points {
                let i = n as usize - 1;
                s += &format!(
                    " {:>13}",
                    format!(
                        "{:.3} ({:.3})",
                        rel(Metric::Accumulated, i),
                        rel(Metric::AccumulatedRaw, i)
                    )
                );
            }
            s += "\n";
        }
        s += "insets (x0, y0, side, max relative gradient of the reference):";
        for i in &self.insets {
            s += &format!(
                " {} ({}, {}, {}, {:.3});",
                i.name, i.x0, i.y0, i.side, i.max_gradient
            );
        }
        s += "\n";
        s
    }
}

impl MethodRun {
    /// The errors after `chain`, if measured.
    pub fn filtered(&self, chain: FilterChain) -> Option<&FilteredErrors> {
        self.filtered.iter().find(|f| f.chain == chain)
    }
}

impl StudyResult {
    /// RMSE of `method`'s history ([`HistoryMetric`]) over frames
    /// [`EMA_FROM`].. in `region` (`None`: the whole image), relative to white
    /// noise's history. `None` for a missing run, too few frames or an empty region.
    pub fn pooled_history(
        &self,
        method: Method,
        metric: HistoryMetric,
        region: Option<Region>,
    ) -> Option<f64> {
        let series = |r: &MethodRun| -> Option<f64> {
            let h = &r.history;
            pooled_sum(
                match metric {
                    HistoryMetric::Ema => &h.ema,
                    HistoryMetric::EmaBlur1 => &h.ema_blur1,
                },
                region,
                EMA_FROM,
            )
        };
        let (m, w) = (series(self.run(method)?)?, series(self.run(Method::White)?)?);
        (w > 0.0).then(|| (m / w).sqrt())
    }

    /// RMSE of the mean of `method`'s first `n` frames in `region` (`None`:
    /// the whole image; reference noise not removed), relative to white's.
    pub fn accumulated_region(&self, method: Method, n: usize, region: Option<Region>) -> Option<f64> {
        let get = |r: &MethodRun| -> Option<f64> {
            let v = r.acc_regions.get(n.checked_sub(1)?)?;
            Some(match region {
                Some(k) => v[k as usize],
                None => v.iter().sum(),
            })
        };
        let (m, w) = (get(self.run(method)?)?, get(self.run(Method::White)?)?);
        (w > 0.0).then(|| (m / w).sqrt())
    }

    /// Markdown table of what a history keeps (issue 29): per method, the
    /// RMSE after the EMA alone per region, after the EMA then a Gaussian
    /// blur, and of the mean of the first 8 / 32 / 128 frames, white = 1.
    pub fn temporal_markdown(&self) -> String {
        let cell = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.3}"));
        let mut s = format!(
            "| method | EMA {EMA_ALPHA} whole | EMA emitter zone | EMA edges | EMA interior | EMA + G1 whole | EMA + G1 interior"
        );
        for n in TEMPORAL_MEANS {
            s += &format!(" | mean {n} whole | mean {n} interior");
        }
        s += " |
|---|---|---|---|---|---|---";
        s += &"|---|---".repeat(TEMPORAL_MEANS.len());
        s += "|\n";
        for r in &self.runs {
            let m = r.method;
            s += &format!(
                "| {} | {}",
                m.name(),
                cell(self.pooled_history(m, HistoryMetric::Ema, None))
            );
            for region in Region::ALL {
                s += &format!(
                    " | {}",
                    cell(self.pooled_history(m, HistoryMetric::Ema, Some(region)))
                );
            }
            s += &format!(
                " | {} | {}",
                cell(self.pooled_history(m, HistoryMetric::EmaBlur1, None)),
                cell(self.pooled_history(m, HistoryMetric::EmaBlur1, Some(Region::Interior)))
            );
            for n in TEMPORAL_MEANS {
                s += &format!(
                    " | {} | {}",
                    cell(self.accumulated_region(m, n as usize, None)),
                    cell(self.accumulated_region(m, n as usize, Some(Region::Interior)))
                );
            }
            s += " |\n";
        }
        s
    }
}

impl StudyResult {
    /// RMSE of `method` after `chain` over frames `from..` in `region`
    /// (`None`: the whole image), relative to white noise's after the same
    /// chain. `None` for a missing run or chain, no frames or an empty region.
    pub fn pooled_filtered(
        &self,
        method: Method,
        chain: FilterChain,
        region: Option<Region>,
        from: usize,
    ) -> Option<f64> {
        self.pooled_ratio(method, chain, region, from, |e| &e.regions)
    }

    /// As [`Self::pooled_filtered`] for the noise part: the filtered frame
    /// minus the filtered reference (the filter's bias left out).
    pub fn pooled_filtered_noise(
        &self,
        method: Method,
        chain: FilterChain,
        region: Option<Region>,
        from: usize,
    ) -> Option<f64> {
        self.pooled_ratio(method, chain, region, from, |e| &e.noise)
    }

    /// `sqrt(sum of series(method) / sum of series(white))` over frames
    /// `from..` after `chain`.
    fn pooled_ratio(
        &self,
        method: Method,
        chain: FilterChain,
        region: Option<Region>,
        from: usize,
        series: impl Fn(&FilteredErrors) -> &[[f64; 3]],
    ) -> Option<f64> {
        let m = pooled_sum(series(self.run(method)?.filtered(chain)?), region, from)?;
        let w = pooled_sum(series(self.run(Method::White)?.filtered(chain)?), region, from)?;
        (w > 0.0).then(|| (m / w).sqrt())
    }

    /// The filter's bias floor relative to white noise after the chain: the
    /// RMSE of the reference itself sent through `chain` (as many frames as
    /// the study) over frames `from..`, divided by white's filtered RMSE.
    pub fn filter_bias(&self, chain: FilterChain, region: Option<Region>, from: usize) -> Option<f64> {
        let bias = self.filter_bias.iter().find(|f| f.chain == chain)?;
        let b = pooled_sum(&bias.regions, region, from)?;
        let w = pooled_sum(&self.run(Method::White)?.filtered(chain)?.regions, region, from)?;
        (w > 0.0).then(|| (b / w).sqrt())
    }

    /// Markdown table: every method's RMSE after each chain of
    /// [`STUDY_FILTERS`], whole image and interior, relative to white = 1,
    /// and the bias floor row.
    pub fn filtered_markdown(&self, from: usize) -> String {
        let cell = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.3}"));
        let mut s = String::from("| method");
        for c in STUDY_FILTERS {
            s += &format!(" | {c} whole | {c} interior");
        }
        let head = STUDY_FILTERS[0];
        s += &format!(" | {head} noise part whole | noise part interior");
        s += " |\n|---";
        s += &"|---|---".repeat(STUDY_FILTERS.len() + 1);
        s += "|\n";
        for r in &self.runs {
            s += &format!("| {}", r.method.name());
            for c in STUDY_FILTERS {
                s += &format!(
                    " | {} | {}",
                    cell(self.pooled_filtered(r.method, c, None, from)),
                    cell(self.pooled_filtered(r.method, c, Some(Region::Interior), from))
                );
            }
            s += &format!(
                " | {} | {}",
                cell(self.pooled_filtered_noise(r.method, head, None, from)),
                cell(self.pooled_filtered_noise(r.method, head, Some(Region::Interior), from))
            );
            s += " |\n";
        }
        s += "| *filter bias (reference filtered)*";
        for c in STUDY_FILTERS {
            s += &format!(
                " | {} | {}",
                cell(self.filter_bias(c, None, from)),
                cell(self.filter_bias(c, Some(Region::Interior), from))
            );
        }
        s += " | - | - |\n";
        s
    }
}
