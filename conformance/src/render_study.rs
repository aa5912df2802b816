//! End-to-end quality of the seed permutation on rendered frames (issue 5, part 2).
//!
//! The Cornell box (static camera) is rendered on the CPU for several frames with each
//! [`Method`]; every frame is compared with a high-sample reference on luma
//! (Rec. 709, `sampler_core::luma`):
//!
//! - `error_t = luma(frame_t) - luma(reference)`, per pixel;
//! - (a) low-frequency power ratio ([`low_frequency_ratio`]) of `error_t` on the flat
//!   [`Inset`]s, averaged over the insets;
//! - (b) RMS of `error_t` after a toroidal Gaussian blur of sigma 1 and 2 (a stand-in
//!   for a denoiser), whole image;
//! - (c) RMS of the temporally accumulated image (mean of frames `0..n`) minus the
//!   reference, whole image, for every `n`.
//!
//! - (d) per region ([`crate::regions`]: emitter zone, edges, interior, from the
//!   frame-0 G-buffer of the still camera): the sigma-1 blurred error's squared sum
//!   ([`StudyResult::pooled_region`]) and the accumulated error's.
//!
//! Figures are made relative to the [`Method::White`] run of the same configuration
//! (white = 1) by [`StudyResult::relative`]. All runs start from the same white-noise
//! seeds (salt [`StudyConfig::salt`]), so frame 0 is identical for every method except
//! the dither baseline.
//!
//! # Frame numbering
//!
//! Frame `t` (from 0) is rendered with the seeds after `t` permutation passes: frame 0
//! is the white-noise start. "By frame 8" in the goals means `t = 8`.
//!
//! # Reference noise
//!
//! The reference is the mean of two independent halves (`ref_spp / 2` samples each).
//! Its own noise adds to every squared error: `E[(acc - ref)^2] = var(acc) + var(ref)`.
//! `var(ref)` is estimated per image as `mean((A - B)^2) / 4` (A, B the halves' luma)
//! and [`MethodRun::acc_rmse_corrected`] subtracts it; without the correction every
//! accumulated ratio is pulled towards 1. Both are reported.
//!
//! # Flat insets
//!
//! Three square regions picked on the Cornell box where the reference is smooth: the
//! back wall right of the tall block, the red (left) and the green (right) wall. The
//! floor is not used: with this camera the only floor area tall enough for a
//! `size / 8` square lies next to the tall block, across its shadow edge (relative
//! reference gradient 0.9-1.4 per pixel, against 0.06-0.12 on the walls). They are
//! placed by fractions of the image size and
//! checked geometrically: [`Study::new`] casts the centre ray of every inset pixel and
//! fails unless all of them hit the intended surface (back wall: `z >= 559`, floor:
//! `y <= 0.5`, red / green wall: their material). [`Inset::max_gradient`] reports how
//! flat the reference is inside each.
//!
//! # The fixed-step comparison
//!
//! [`Method::FixedStep`] is the permutation with the dither tile moved by the fixed
//! integer step `floor(W * (a1, a2))` ((48, 36) for W = 64) every frame instead of the
//! aperiodic R2 walk: offset `o_t = t * step mod W`, sorted against `tile[(p + o_t) mod W]`
//! and retargeted with the table baked for that step (table 0, since the step is the
//! walk's base step). The frame loop is [`permute_with_offset`], which with the R2
//! walk's offsets reproduces `sampler_core::permute_frame` exactly (tested).
//!
//! # The feature-aware rows (issue 14)
//!
//! [`Method::FeaturePermute`] and [`Method::FeaturePermuteJitter`] render through the
//! tracer's own loop (`gpu_tracer::render::render_sequence_cpu` with
//! `SequenceOptions::features` on a still sequence): each frame's G-buffer gives the
//! `SurfaceFeature`s and the demodulated keys of `sampler_core::permute_frame_features`.
//! [`StudyResult::features`] says how much of the frame they treat differently from the
//! plain permutation, and [`MethodRun::seed_repeats`] (from a mirror of the seeds,
//! checked against frame 1) how often a pixel gets a seed it already had.
//!
//! # The blue-noise-dither baseline
//!
//! [`Method::Dither`]: fresh white-noise seeds every frame (as [`Method::White`]) and
//! `kernels::abi::SEED_MODE_BLUE_NOISE_DITHER`: the first vertex's BSDF direction is
//! drawn from the default 128x128x64 spatiotemporal blue-noise mask
//! (`sampler_core::defaults::stbn_128`), `(mask(x, y, t mod 64), mask(x + 64, y + 64,
//! t mod 64))`, through `kernels::trace::trace_pixel_dithered`. CPU only: the GPU
//! entry point has no mask binding.

pub use crate::insets::{crop, Inset, Surface};
pub use crate::reference::{default_cache_dir, Reference};
pub use crate::walks::{permute_with_offset, render_dither, render_walk, Walk};

use crate::insets::{check_inset, inset_layout, max_gradient};
use crate::regions::{classify_regions, region_shares, Region};
use crate::{low_frequency_ratio, radial_power, GaussianBlur, Grid, SpectrumAnalyzer};
use anyhow::{ensure, Result};
use glam::{Vec3, Vec4};
use gpu_tracer::cornell::cornell_box;
use gpu_tracer::render::{render_sequence_cpu, FrameView, SequenceOptions};
use gpu_tracer::scene::{SceneGpu, TraceSettings};
use gpu_tracer::timeline::SceneSequence;
use gpu_tracer::{cpu, PermuteMode, RenderJob, TileChoice};
use kernels::abi::{GBufferGpu, SEED_MODE_FIXED};
use kernels::surface_features::surface_feature;
use sampler_core::feature_permute::{block_groups, edge_is_cut, retarget_index};
use sampler_core::{
    step_index, walk_offset, FeatureThresholds, FrameLayout, Intensity, SurfaceFeature, MAX_BLOCK_PIXELS,
};
use std::path::Path;

/// The frame at which the goals on single frames are checked (module docs).
pub const GOAL_FRAME: u32 = 8;
/// Frame counts at which the accumulated RMSE is reported.
pub const ACCUMULATION_POINTS: [u32; 4] = [8, 32, 64, 128];

/// How the seeds (or random numbers) change between frames.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// Fresh white-noise seeds every frame.
    White,
    /// Sorting pass only (R2 walk), no retargeting.
    Sort,
    /// Sorting and retargeting with the aperiodic R2 walk: the method.
    Permute,
    /// [`Method::Permute`] with the position inside the pixel taken from the
    /// screen-space Sobol sampler (`--sampler screen-sobol-jitter`): the
    /// permutation for everything but the jitter.
    PermuteJitter,
    /// Sorting and retargeting with the fixed integer step `floor(W * (a1, a2))`.
    FixedStep,
    /// Fresh white seeds plus a spatiotemporal blue-noise mask driving the first
    /// bounce's direction.
    Dither,
    /// Fresh white seeds, the path's 2D decisions from the screen-space Sobol
    /// sampler with our optimised keys (`--sampler screen-sobol`, issue 6).
    ScreenSobol,
    /// Fresh white seeds, the path's 2D decisions from ZSobol (`--sampler zsobol`).
    ZSobol,
    /// The feature-aware permutation (issue 14, `SequenceOptions::features` of the
    /// tracer's CPU loop): demodulated sort keys, blocks sorted in groups of one
    /// surface, retarget moves cut at edges, features from the G-buffer.
    FeaturePermute,
    /// [`Method::FeaturePermute`] with the pixel jitter from screen-space Sobol, as
    /// [`Method::PermuteJitter`].
    FeaturePermuteJitter,
}

impl Method {
    /// Every method, white first.
    pub const ALL: [Method; 10] = [
        Method::White,
        Method::Sort,
        Method::Permute,
        Method::PermuteJitter,
        Method::FixedStep,
        Method::Dither,
        Method::ScreenSobol,
        Method::ZSobol,
        Method::FeaturePermute,
        Method::FeaturePermuteJitter,
    ];

    /// The rows of issue 14's comparison (`conformance study` defaults).
    pub const FEATURE_ROWS: [Method; 5] = [
        Method::White,
        Method::Permute,
        Method::PermuteJitter,
        Method::FeaturePermute,
        Method::FeaturePermuteJitter,
    ];

    /// The method called `name` ([`Method::name`]).
    pub fn from_name(name: &str) -> Option<Method> {
        Method::ALL.into_iter().find(|m| m.name() == name)
    }

    /// Short name used in tables, files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Method::White => "white",
            Method::Sort => "sort",
            Method::Permute => "permute",
            Method::PermuteJitter => "permute-jitter",
            Method::FixedStep => "fixed-step",
            Method::Dither => "bn-dither",
            Method::ScreenSobol => "screen-sobol",
            Method::ZSobol => "zsobol",
            Method::FeaturePermute => "feature-permute",
            Method::FeaturePermuteJitter => "feature-permute-jitter",
        }
    }

    /// One-line description.
    pub fn describe(self) -> &'static str {
        match self {
            Method::White => "fresh white-noise seeds every frame",
            Method::Sort => "sorting pass only (R2 walk), no retargeting",
            Method::Permute => "sorting + retargeting, aperiodic R2 offset walk",
            Method::PermuteJitter => "permute, with the pixel jitter from screen-space Sobol",
            Method::FixedStep => "sorting + retargeting, fixed integer step floor(W*(a1,a2))",
            Method::Dither => "white seeds + STBN mask on the first bounce direction",
            Method::ScreenSobol => "white seeds + screen-space Sobol (our keys) on every 2D decision",
            Method::ZSobol => "white seeds + ZSobol on every 2D decision",
            Method::FeaturePermute => {
                "feature-aware permute: demodulated keys, groups of one surface, cut retarget moves"
            }
            Method::FeaturePermuteJitter => {
                "feature-aware permute, with the pixel jitter from screen-space Sobol"
            }
        }
    }
}

/// What to render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StudyConfig {
    /// Image side in pixels (square frames).
    pub size: u32,
    /// Samples per pixel per frame.
    pub spp: u32,
    /// Frames per method.
    pub frames: u32,
    /// Samples per pixel of the reference (two halves of `ref_spp / 2`).
    pub ref_spp: u32,
    /// Block side of the sorting pass.
    pub block: u32,
    /// Dither tile.
    pub tile: TileChoice,
    /// Seed mode of the white / sort / permute / fixed-step runs
    /// (`SEED_MODE_FIXED` or `SEED_MODE_ADVANCE`).
    pub seed_mode: u32,
    /// Maximum path length in segments.
    pub max_depth: u32,
    /// Salt of the initial white-noise seeds.
    pub salt: u32,
}

impl StudyConfig {
    /// Defaults: 4x4 blocks, 64x64 tile, fixed seeds, depth 8, salt 1.
    pub fn new(size: u32, spp: u32, frames: u32, ref_spp: u32) -> Self {
        StudyConfig {
            size,
            spp,
            frames,
            ref_spp,
            block: 4,
            tile: TileChoice::Tile64,
            seed_mode: SEED_MODE_FIXED,
            max_depth: 8,
            salt: 1,
        }
    }

    pub(crate) fn settings(&self) -> TraceSettings {
        let mut s = TraceSettings::new(self.size, self.size);
        s.spp = self.spp;
        s.max_depth = self.max_depth;
        s.seed_mode = self.seed_mode;
        s
    }

    pub(crate) fn layout(&self) -> Result<FrameLayout> {
        Ok(FrameLayout::new(
            self.size,
            self.size,
            self.block,
            self.tile.side(),
        )?)
    }
}

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
    /// Per frame: RMS error, unblurred, whole image.
    pub rmse: Vec<f64>,
    /// Per frame: RMS error after a Gaussian blur of sigma 1.
    pub blur1: Vec<f64>,
    /// Per frame: RMS error after a Gaussian blur of sigma 2.
    pub blur2: Vec<f64>,
    /// Per frame: sum of the squared sigma-1-blurred error over each region
    /// ([`Region::ALL`] order; regions of [`Study::regions`]).
    pub blur1_regions: Vec<[f64; 3]>,
    /// Entry `n - 1`: sum over each region of the squared error of the mean of frames
    /// `0..n` (reference noise not removed).
    pub acc_regions: Vec<[f64; 3]>,
    /// For the permuting rows (permute, permute-jitter and the feature-aware ones):
    /// per region, the fraction of (pixel, frame) pairs whose seed the pixel already
    /// had in an earlier frame. With fixed seeds a repeated seed repeats the pixel's
    /// estimate (its jitter, for the rows without the sampler's jitter), so repeats
    /// stall the accumulation.
    pub seed_repeats: Option<[f64; 3]>,
    /// Entry `n - 1`: RMS of the mean of frames `0..n` minus the reference.
    pub acc_rmse: Vec<f64>,
    /// [`Self::acc_rmse`] with the reference's own noise removed (module docs).
    pub acc_rmse_corrected: Vec<f64>,
    /// Radially averaged power of the first inset's error, averaged over the frames
    /// from [`GOAL_FRAME`] on (or the last frame); index = radius in bins.
    pub radial: Vec<f64>,
    /// Frame [`GOAL_FRAME`] (or the last).
    pub snapshot: Snapshot,
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
    /// What the feature-aware permutation sees in this frame ([`FeatureDiagnostics`]).
    pub features: FeatureDiagnostics,
    /// The runs, in the order they were requested.
    pub runs: Vec<MethodRun>,
}

/// How much of the frame the feature-aware permutation treats differently from the
/// plain one, from the still camera's G-buffer with `FeatureThresholds::DEFAULT`
/// (the features do not change between frames; the retarget table and tile offset do).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FeatureDiagnostics {
    /// Fraction of sorting blocks (with a visible pixel) holding more than one group.
    pub split_blocks: f64,
    /// Fraction of visible pixels in such blocks.
    pub pixels_in_split_blocks: f64,
    /// Mean number of groups of a split block.
    pub groups_per_split_block: f64,
    /// Fraction of retarget moves (`p -> table(p)`, all seeds, mean over the study's
    /// frames) that are cut (not [`sampler_core::same_surface`], or padding / visible).
    pub cut_moves: f64,
    /// Fraction of retarget moves that stay in place (the table's fixed points).
    pub fixed_moves: f64,
    /// Per region ([`Region::ALL`] order): fraction of its pixels in split blocks.
    pub split_by_region: [f64; 3],
    /// Per region: fraction of the moves out of its pixels that are cut (mean over
    /// frames).
    pub cut_by_region: [f64; 3],
    /// Surface ids whose visible pixels have more than one albedo (where the
    /// demodulated key can order a group's pixels differently from the raw key; with
    /// none, demodulation only rescales each group's keys and the sort is the same).
    pub ids_with_varying_albedo: usize,
}

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
            "Cornell box {0}x{0}, {1} spp, depth {2}, {3} frames, reference {4} spp, block {5}, tile {6}, salt {7}; \
             white = 1, pooled over frames {from}..\n\n",
            c.size,
            c.spp,
            c.max_depth,
            c.frames,
            c.ref_spp,
            c.block,
            c.tile.side(),
            c.salt
        );
        s += "| method | LF @8 | LF mean 8.. | blur s1 8.. | blur s2 8..";
        for n in &points {
            s += &format!(" | acc {n}");
        }
        s += " |\n|---|---|---|---|---";
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
                "| {} | {} | {lf_mean:.3} | {} | {}",
                m.name(),
                cell(self.relative(m, Metric::LowFrequency, from)),
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
        let acc_region = |m: Method, n: usize, k: usize| -> Option<f64> {
            let get = |r: &MethodRun| r.acc_regions.get(n - 1).map(|v| v[k]);
            let (a, b) = (get(self.run(m)?)?, get(self.run(Method::White)?)?);
            (b > 0.0).then(|| (a / b).sqrt())
        };
        s += &format!(
            "\nAccumulated RMSE per region after {last} frames (raw, reference noise not removed), and the \
             fraction of (pixel, frame) pairs whose seed the pixel already had:\n\n\
             | method | acc emitter zone | acc edges | acc interior | repeated seeds emitter / edges / interior |\n\
             |---|---|---|---|---|\n"
        );
        for r in &self.runs {
            s += &format!("| {}", r.method.name());
            for k in 0..3 {
                s += &format!(" | {}", cell(acc_region(r.method, last, k)));
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
            "Cornell box {0}x{0}, {1} spp, {2} frames, reference {3} spp (noise var {4:.3e}), block {5}, tile {6}, seed mode {7}\n",
            c.size,
            c.spp,
            c.frames,
            c.ref_spp,
            self.reference_noise_var,
            c.block,
            c.tile.side(),
            c.seed_mode
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

/// The scene, reference and insets of one configuration.
#[derive(Debug)]
pub struct Study {
    /// The configuration.
    pub config: StudyConfig,
    /// The Cornell box buffers.
    pub scene: SceneGpu,
    /// The reference.
    pub reference: Reference,
    /// The flat insets, checked geometrically.
    pub insets: Vec<Inset>,
    /// The region of every pixel ([`crate::regions`]), from the frame-0 G-buffer.
    pub regions: Vec<Region>,
    /// The frame-0 G-buffer (centre rays; the camera does not move).
    pub gbuffer: Vec<GBufferGpu>,
}

impl Study {
    /// Builds the scene, renders or loads the reference and places the insets.
    ///
    /// # Errors
    /// Bad settings, or an inset that does not lie on its surface.
    pub fn new(
        config: StudyConfig,
        cache_dir: Option<&Path>,
        progress: impl FnMut(u32, u32),
    ) -> Result<Study> {
        ensure!(config.frames >= 1, "at least one frame");
        ensure!(config.size >= 32, "the insets need an image of at least 32x32");
        config.layout()?;
        let scene = SceneGpu::build(&cornell_box())?;
        let reference = Reference::get(&scene, &config, cache_dir, progress)?;
        let mut insets = inset_layout(config.size);
        let params = scene.trace_params(&config.settings(), 0)?;
        for inset in &mut insets {
            check_inset(&scene, &params, inset)?;
            inset.max_gradient = max_gradient(&reference.luma, config.size, inset);
        }
        let mut gbuffer = vec![GBufferGpu::default(); (config.size * config.size) as usize];
        cpu::gbuffer_frame(&scene, &params, &mut gbuffer)?;
        let regions = classify_regions(&gbuffer, config.size, config.size);
        Ok(Study {
            config,
            scene,
            reference,
            insets,
            regions,
            gbuffer,
        })
    }

    /// The feature diagnostics of this frame (see [`FeatureDiagnostics`]).
    ///
    /// # Errors
    /// Bad layout.
    pub fn feature_diagnostics(&self) -> Result<FeatureDiagnostics> {
        let layout = self.config.layout()?;
        let features: Vec<SurfaceFeature> = self.gbuffer.iter().map(surface_feature).collect();
        let thresholds = FeatureThresholds::DEFAULT;
        let params = layout.params(0);
        let mut d = FeatureDiagnostics::default();
        let (mut blocks, mut split, mut groups_total, mut split_pixels) = (0u64, 0u64, 0u64, 0u64);
        for by in 0..params.blocks_y() {
            for bx in 0..params.blocks_x() {
                let mut feats = [SurfaceFeature::default(); MAX_BLOCK_PIXELS];
                let mut len = 0usize;
                for y in by * params.block..((by + 1) * params.block).min(params.height) {
                    for x in bx * params.block..((bx + 1) * params.block).min(params.width) {
                        feats[len] = features[(y * params.width + x) as usize];
                        len += 1;
                    }
                }
                if len == 0 {
                    continue;
                }
                blocks += 1;
                let mut groups = [0u32; MAX_BLOCK_PIXELS];
                block_groups(len as u32, &feats, &thresholds, &mut groups);
                let count = (0..len).filter(|&i| groups[i] == i as u32).count() as u64;
                if count > 1 {
                    split += 1;
                    groups_total += count;
                    split_pixels += len as u64;
                    for y in by * params.block..((by + 1) * params.block).min(params.height) {
                        for x in bx * params.block..((bx + 1) * params.block).min(params.width) {
                            let r = self.regions[(y * params.width + x) as usize] as usize;
                            d.split_by_region[r] += 1.0;
                        }
                    }
                }
            }
        }
        d.split_blocks = split as f64 / blocks.max(1) as f64;
        d.pixels_in_split_blocks = split_pixels as f64 / params.pixel_count() as f64;
        d.groups_per_split_block = groups_total as f64 / split.max(1) as f64;
        let (_, tables) = self.config.tile.load();
        let region_pixels =
            Region::ALL.map(|r| self.regions.iter().filter(|&&x| x == r).count().max(1) as f64);
        for (v, n) in d.split_by_region.iter_mut().zip(region_pixels) {
            *v /= n;
        }
        let (mut cut, mut fixed, mut moves) = (0u64, 0u64, 0u64);
        for t in 0..self.config.frames {
            let params = layout.params(t);
            let offset = walk_offset(t, params.tile_log2);
            let table = tables.table(step_index(t, params.tile_log2)).packed();
            for p in 0..params.seed_count() {
                let q = retarget_index(&params, offset, table, p);
                moves += 1;
                fixed += u64::from(q == p);
                let is_cut = edge_is_cut(&params, &features, &thresholds, p, q);
                cut += u64::from(is_cut);
                let (x, y) = (p % params.padded_width, p / params.padded_width);
                if is_cut && x < params.width && y < params.height {
                    d.cut_by_region[self.regions[(y * params.width + x) as usize] as usize] += 1.0;
                }
            }
        }
        for (v, n) in d.cut_by_region.iter_mut().zip(region_pixels) {
            *v /= n * f64::from(self.config.frames);
        }
        let mut albedo: std::collections::HashMap<u32, Vec<[u32; 3]>> = std::collections::HashMap::new();
        for g in self
            .gbuffer
            .iter()
            .filter(|g| g.ids.w & kernels::abi::GBUFFER_HIT != 0)
        {
            let a = [g.albedo.x.to_bits(), g.albedo.y.to_bits(), g.albedo.z.to_bits()];
            let seen = albedo.entry(g.ids.x).or_default();
            if !seen.contains(&a) {
                seen.push(a);
            }
        }
        d.ids_with_varying_albedo = albedo.values().filter(|v| v.len() > 1).count();
        d.cut_moves = cut as f64 / moves.max(1) as f64;
        d.fixed_moves = fixed as f64 / moves.max(1) as f64;
        Ok(d)
    }

    /// Runs every method of `methods` and measures it. `progress(method, t)` is called
    /// after every frame.
    ///
    /// # Errors
    /// Rendering errors.
    pub fn run(&self, methods: &[Method], mut progress: impl FnMut(Method, u32)) -> Result<StudyResult> {
        let mut runs = Vec::new();
        for &m in methods {
            runs.push(self.run_method(m, |t| progress(m, t))?);
        }
        Ok(StudyResult {
            config: self.config,
            insets: self.insets.clone(),
            reference_noise_var: self.reference.noise_var,
            region_shares: region_shares(&self.regions),
            features: self.feature_diagnostics()?,
            runs,
        })
    }

    fn run_method(&self, method: Method, mut progress: impl FnMut(u32)) -> Result<MethodRun> {
        let mut meter = Meter::new(self, method)?;
        let mut tracker = SeedTracker::new(self, method)?;
        let mut tracker_error = None;
        let mut on_frame = |t: u32, color: &[Vec4]| {
            meter.frame(t, color);
            if let Some(tr) = tracker.as_mut() {
                if let Err(e) = tr.frame(self, t, color) {
                    tracker_error.get_or_insert(e);
                }
            }
            progress(t);
        };
        match method {
            Method::White | Method::Sort | Method::Permute | Method::PermuteJitter => {
                let mut settings = self.config.settings();
                if method == Method::PermuteJitter {
                    settings.sampler = kernels::abi::SAMPLER_SCREEN_SOBOL | kernels::abi::SAMPLER_JITTER_ONLY;
                }
                let job = RenderJob {
                    settings,
                    frames: self.config.frames,
                    mode: match method {
                        Method::White => PermuteMode::White,
                        Method::Sort => PermuteMode::Sort,
                        _ => PermuteMode::Permute,
                    },
                    block: self.config.block,
                    tile: self.config.tile,
                    salt: self.config.salt,
                };
                gpu_tracer::render_cpu(&self.scene, &job, &mut on_frame)?;
            }
            Method::FeaturePermute | Method::FeaturePermuteJitter => {
                let mut settings = self.config.settings();
                if method == Method::FeaturePermuteJitter {
                    settings.sampler = kernels::abi::SAMPLER_SCREEN_SOBOL | kernels::abi::SAMPLER_JITTER_ONLY;
                }
                let job = RenderJob {
                    settings,
                    frames: self.config.frames,
                    mode: PermuteMode::Permute,
                    block: self.config.block,
                    tile: self.config.tile,
                    salt: self.config.salt,
                };
                let options = SequenceOptions {
                    gbuffer: false,
                    reproject: false,
                    features: true,
                };
                let mut sequence = SceneSequence::still(&self.scene, self.config.size);
                render_sequence_cpu(&mut sequence, &job, options, |f: &FrameView<'_>| {
                    on_frame(f.index, f.color)
                })?;
            }
            Method::FixedStep => render_walk(self, Walk::FixedStep, &mut on_frame)?,
            Method::Dither => render_dither(self, &mut on_frame)?,
            Method::ScreenSobol | Method::ZSobol => {
                let mut settings = self.config.settings();
                settings.sampler = if method == Method::ScreenSobol {
                    kernels::abi::SAMPLER_SCREEN_SOBOL
                } else {
                    kernels::abi::SAMPLER_ZSOBOL
                };
                let job = RenderJob {
                    settings,
                    frames: self.config.frames,
                    mode: PermuteMode::White,
                    block: self.config.block,
                    tile: self.config.tile,
                    salt: self.config.salt,
                };
                gpu_tracer::render_cpu(&self.scene, &job, &mut on_frame)?;
            }
        }
        if let Some(e) = tracker_error {
            return Err(e);
        }
        let mut run = meter.finish()?;
        run.seed_repeats = tracker.map(|t| t.repeats(&self.regions));
        Ok(run)
    }
}

/// Mirrors the seeds of a permuting row from its frames (the same library calls as the
/// tracer's CPU loop) and records every visible pixel's seed per frame
/// ([`MethodRun::seed_repeats`]). Frame 1 is re-traced from the mirrored seeds and must
/// match the renderer's frame bit for bit.
struct SeedTracker {
    method: Method,
    layout: FrameLayout,
    seeds: Vec<u32>,
    next: Vec<u32>,
    sorted: Vec<u32>,
    sources: Vec<u32>,
    features: Vec<SurfaceFeature>,
    /// `history[pixel * frames + t]`.
    history: Vec<u32>,
    frames: usize,
}

impl SeedTracker {
    fn new(study: &Study, method: Method) -> Result<Option<SeedTracker>> {
        if !matches!(
            method,
            Method::Permute | Method::PermuteJitter | Method::FeaturePermute | Method::FeaturePermuteJitter
        ) {
            return Ok(None);
        }
        let c = &study.config;
        let layout = c.layout()?;
        let seeds = cpu::white_seeds(layout.padded_width(), layout.padded_height(), c.salt);
        let n = seeds.len();
        Ok(Some(SeedTracker {
            method,
            layout,
            next: vec![0; n],
            sorted: vec![0; n],
            sources: vec![0; n],
            seeds,
            features: study.gbuffer.iter().map(surface_feature).collect(),
            history: vec![0; (c.size * c.size * c.frames) as usize],
            frames: c.frames as usize,
        }))
    }

    fn frame(&mut self, study: &Study, t: u32, color: &[Vec4]) -> Result<()> {
        let (w, pw) = (self.layout.width() as usize, self.layout.padded_width() as usize);
        for (i, _) in color.iter().enumerate() {
            self.history[i * self.frames + t as usize] = self.seeds[(i / w) * pw + i % w];
        }
        if t == 1 {
            let mut settings = study.config.settings();
            settings.padded_width = self.layout.padded_width();
            if matches!(self.method, Method::PermuteJitter | Method::FeaturePermuteJitter) {
                settings.sampler = kernels::abi::SAMPLER_SCREEN_SOBOL | kernels::abi::SAMPLER_JITTER_ONLY;
            }
            let params = study.scene.trace_params(&settings, t)?;
            let mut check = vec![Vec4::ZERO; color.len()];
            cpu::render_frame(&study.scene, &params, &self.seeds, &mut check)?;
            ensure!(
                check == color,
                "{}: the mirrored seeds do not reproduce frame 1",
                self.method.name()
            );
        }
        let (tile, tables) = study.config.tile.load();
        if matches!(self.method, Method::FeaturePermute | Method::FeaturePermuteJitter) {
            let keys: Vec<f32> = color
                .iter()
                .zip(&study.gbuffer)
                .map(|(c, g)| kernels::surface_features::demodulated_intensity(*c, g))
                .collect();
            sampler_core::permute_frame_features(
                &self.layout,
                t,
                &keys,
                &self.features,
                &FeatureThresholds::DEFAULT,
                &tile,
                &tables,
                &self.seeds,
                &mut self.sorted,
                &mut self.sources,
                &mut self.next,
            )?;
        } else {
            sampler_core::permute_frame(
                &self.layout,
                t,
                color,
                &tile,
                &tables,
                &self.seeds,
                &mut self.next,
            )?;
        }
        std::mem::swap(&mut self.seeds, &mut self.next);
        Ok(())
    }

    /// Per region, the fraction of (pixel, frame) pairs with a seed seen before.
    fn repeats(&self, regions: &[Region]) -> [f64; 3] {
        let (mut rep, mut all) = ([0u64; 3], [0u64; 3]);
        for (i, r) in regions.iter().enumerate() {
            let mut v = self.history[i * self.frames..(i + 1) * self.frames].to_vec();
            v.sort_unstable();
            v.dedup();
            rep[*r as usize] += (self.frames - v.len()) as u64;
            all[*r as usize] += self.frames as u64;
        }
        [0, 1, 2].map(|k| rep[k] as f64 / all[k].max(1) as f64)
    }
}

/// Per-frame measurement of one method.
struct Meter<'a> {
    study: &'a Study,
    run: MethodRun,
    analyzer: SpectrumAnalyzer,
    blur1: GaussianBlur,
    blur2: GaussianBlur,
    sum: Vec<f64>,
    radial_frames: u32,
    snapshot_frame: u32,
}

impl<'a> Meter<'a> {
    fn new(study: &'a Study, method: Method) -> Result<Self> {
        let n = (study.config.size * study.config.size) as usize;
        let snapshot_frame = GOAL_FRAME.min(study.config.frames - 1);
        Ok(Meter {
            study,
            run: MethodRun {
                method,
                lf_insets: Vec::new(),
                rmse: Vec::new(),
                blur1: Vec::new(),
                blur2: Vec::new(),
                blur1_regions: Vec::new(),
                acc_regions: Vec::new(),
                seed_repeats: None,
                acc_rmse: Vec::new(),
                acc_rmse_corrected: Vec::new(),
                radial: Vec::new(),
                snapshot: Snapshot {
                    frame: snapshot_frame,
                    rgb: Vec::new(),
                    error: Vec::new(),
                },
            },
            analyzer: SpectrumAnalyzer::new(),
            blur1: GaussianBlur::new(1.0)?,
            blur2: GaussianBlur::new(2.0)?,
            sum: vec![0.0; n],
            radial_frames: 0,
            snapshot_frame,
        })
    }

    fn frame(&mut self, t: u32, color: &[Vec4]) {
        let size = self.study.config.size as usize;
        let reference = &self.study.reference;
        let error: Vec<f32> = color
            .iter()
            .zip(&reference.luma)
            .map(|(c, r)| c.intensity() - r)
            .collect();
        let grid = Grid::new(size, size, error.clone()).expect("frame size");
        self.run.rmse.push(grid.rms());
        let blurred = self.blur1.apply(&grid);
        self.run.blur1.push(blurred.rms());
        let mut sums = [0.0f64; 3];
        for (b, r) in blurred.data().iter().zip(&self.study.regions) {
            sums[*r as usize] += (*b as f64) * (*b as f64);
        }
        self.run.blur1_regions.push(sums);
        self.run.blur2.push(self.blur2.apply(&grid).rms());
        let mut lf = Vec::with_capacity(self.study.insets.len());
        for (k, inset) in self.study.insets.iter().enumerate() {
            let sub = crop(&error, size, inset);
            let spectrum = self.analyzer.power_spectrum(&sub);
            lf.push(low_frequency_ratio(&spectrum));
            if k == 0 && t >= self.snapshot_frame {
                let r = radial_power(&spectrum);
                if self.run.radial.is_empty() {
                    self.run.radial = vec![0.0; r.mean().len()];
                }
                for (a, b) in self.run.radial.iter_mut().zip(r.mean()) {
                    *a += b;
                }
                self.radial_frames += 1;
            }
        }
        self.run.lf_insets.push(lf);
        // Accumulation.
        let n = (t + 1) as f64;
        let mut mse = 0.0;
        let mut acc = [0.0f64; 3];
        for (((s, c), r), region) in self
            .sum
            .iter_mut()
            .zip(color)
            .zip(&reference.luma)
            .zip(&self.study.regions)
        {
            *s += c.intensity() as f64;
            let d = *s / n - *r as f64;
            mse += d * d;
            acc[*region as usize] += d * d;
        }
        self.run.acc_regions.push(acc);
        mse /= self.sum.len() as f64;
        self.run.acc_rmse.push(mse.sqrt());
        self.run
            .acc_rmse_corrected
            .push((mse - reference.noise_var).max(0.0).sqrt());
        if t == self.snapshot_frame {
            self.run.snapshot.rgb = color.iter().map(|c| c.truncate()).collect();
            self.run.snapshot.error = error;
        }
    }

    fn finish(mut self) -> Result<MethodRun> {
        ensure!(
            self.run.rmse.len() == self.study.config.frames as usize,
            "the renderer delivered {} of {} frames",
            self.run.rmse.len(),
            self.study.config.frames
        );
        let k = self.radial_frames.max(1) as f64;
        self.run.radial.iter_mut().for_each(|v| *v /= k);
        Ok(self.run)
    }
}
