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
//! [`Method::FeaturePermuteRawKey`] and [`Method::FeaturePermuteHistoryKey`] are the same
//! loop with another sort key (`gpu_tracer::feature_keys::FeatureKey`); they are not in
//! [`Method::REPORT`] and are measured by `conformance study --methods ...`.
//!
//! # Scenes
//!
//! [`StudyConfig::scene`] picks the Cornell box (default) or the checker-textured glTF
//! Cornell box and its untextured twin ([`StudyScene`]); all three share the camera,
//! the insets and the region definition. [`MethodRun::lf_demodulated`] measures the
//! insets' error with the albedo divided out, which separates the texture's share of a
//! textured inset's error from the irradiance noise the seeds arrange.
//!
//! # The blue-noise-dither baseline
//!
//! [`Method::Dither`]: fresh white-noise seeds every frame (as [`Method::White`]) and
//! `kernels::abi::SEED_MODE_BLUE_NOISE_DITHER`: the first vertex's BSDF direction is
//! drawn from the default 128x128x64 spatiotemporal blue-noise mask
//! (`sampler_core::defaults::stbn_128`), `(mask(x, y, t mod 64), mask(x + 64, y + 64,
//! t mod 64))`, through `kernels::trace::trace_pixel_dithered`. CPU only: the GPU
//! entry point has no mask binding.

pub use crate::feature_diagnostics::FeatureDiagnostics;
pub use crate::insets::{crop, Inset, Surface};
pub use crate::reference::{default_cache_dir, Reference};
pub use crate::study_result::Metric;
pub use crate::study_scene::StudyScene;
pub use crate::walks::{permute_with_offset, render_dither, render_walk, Walk};

use crate::feature_diagnostics::SeedTracker;
use crate::filtered::{FilteredErrors, FilteredMeter};
use crate::insets::{check_inset, inset_layout, max_gradient};
use crate::regions::{classify_regions, region_shares, Region};
use crate::{low_frequency_ratio, radial_power, GaussianBlur, Grid, SpectrumAnalyzer};
use anyhow::{ensure, Result};
use glam::{Vec2, Vec3, Vec4};
use gpu_tracer::feature_keys::FeatureKey;
use gpu_tracer::render::{render_sequence_cpu, FrameView, SequenceOptions};
use gpu_tracer::scene::{SceneGpu, TraceSettings};
use gpu_tracer::timeline::SceneSequence;
use gpu_tracer::{cpu, PermuteMode, RenderJob, TileChoice};
use kernels::abi::{GBufferGpu, SEED_MODE_FIXED};
use sampler_core::{FrameLayout, Intensity};
use std::path::Path;

/// The frame at which the goals on single frames are checked (module docs).
pub const GOAL_FRAME: u32 = 8;
/// Frame counts at which the accumulated RMSE is reported.
pub const ACCUMULATION_POINTS: [u32; 4] = [8, 32, 64, 128];
/// Frame counts whose accumulated mean image a run keeps (the report's pictures).
pub const ACCUMULATION_SNAPSHOTS: [u32; 2] = [8, 64];

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
    /// [`Method::Dither`] with the filter-adapted mask
    /// (`sampler_core::defaults::filter_adapted_128`, EMA 0.1 x Gaussian 1.3435,
    /// issue 15) instead of STBN.
    DitherFilterAdapted,
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
    /// [`Method::FeaturePermute`] ranking the raw radiance luma
    /// (`gpu_tracer::feature_keys::FeatureKey::Raw`): what demodulation buys.
    FeaturePermuteRawKey,
    /// [`Method::FeaturePermute`] ranking the demodulated value minus its smoothed
    /// running mean (`FeatureKey::HistoryResidual`): the noise without the signal.
    FeaturePermuteHistoryKey,
}

impl Method {
    /// Every method, white first.
    pub const ALL: [Method; 13] = [
        Method::White,
        Method::Sort,
        Method::Permute,
        Method::PermuteJitter,
        Method::FixedStep,
        Method::Dither,
        Method::DitherFilterAdapted,
        Method::ScreenSobol,
        Method::ZSobol,
        Method::FeaturePermute,
        Method::FeaturePermuteJitter,
        Method::FeaturePermuteRawKey,
        Method::FeaturePermuteHistoryKey,
    ];

    /// The rows of the report ([`crate::report`]): every method but the sort-key
    /// variants of the feature-aware permutation, which `conformance study`
    /// measures on request.
    pub const REPORT: [Method; 11] = [
        Method::White,
        Method::Sort,
        Method::Permute,
        Method::PermuteJitter,
        Method::FixedStep,
        Method::Dither,
        Method::DitherFilterAdapted,
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
            Method::DitherFilterAdapted => "bn-dither-fa",
            Method::ScreenSobol => "screen-sobol",
            Method::ZSobol => "zsobol",
            Method::FeaturePermute => "feature-permute",
            Method::FeaturePermuteJitter => "feature-permute-jitter",
            Method::FeaturePermuteRawKey => "feature-permute-raw-key",
            Method::FeaturePermuteHistoryKey => "feature-permute-history-key",
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
            Method::DitherFilterAdapted => {
                "white seeds + the filter-adapted mask (EMA 0.1 x Gaussian) on the first bounce direction"
            }
            Method::ScreenSobol => "white seeds + screen-space Sobol (our keys) on every 2D decision",
            Method::ZSobol => "white seeds + ZSobol on every 2D decision",
            Method::FeaturePermute => {
                "feature-aware permute: demodulated keys, groups of one surface, cut retarget moves"
            }
            Method::FeaturePermuteJitter => {
                "feature-aware permute, with the pixel jitter from screen-space Sobol"
            }
            Method::FeaturePermuteRawKey => {
                "feature-aware permute ranking the raw radiance (no demodulation)"
            }
            Method::FeaturePermuteHistoryKey => {
                "feature-aware permute ranking the demodulated value minus its smoothed running mean"
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
    /// Also measure every method after the real-time filters
    /// ([`crate::filtered::STUDY_FILTERS`]); on by default.
    pub filters: bool,
    /// The scene ([`StudyScene`]; the Cornell box by default).
    pub scene: StudyScene,
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
            filters: true,
            scene: StudyScene::Cornell,
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
    /// Per frame: mean over insets of the low-frequency power ratio of the error with
    /// the albedo divided out (error / albedo luma of the pixel's primary hit, from the
    /// frame-0 G-buffer): the irradiance error the seeds arrange, before the texture
    /// multiplies it. Equal to [`Self::lf`] on untextured insets.
    pub lf_demodulated: Vec<f64>,
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
    /// Power spectrum of the error (DFT order, `(kx, ky)` at `ky * side + kx`, DC
    /// at 0), averaged over the frames from [`GOAL_FRAME`] on and over every inset,
    /// each cropped to its central `spectrum_side` square (the smallest inset's
    /// side) so the spectra share one frequency grid; in units of luma².
    pub spectrum: Vec<f64>,
    /// Side of [`Self::spectrum`].
    pub spectrum_side: usize,
    /// Temporal power spectrum of a pixel's error ([`crate::temporal::temporal_power`]:
    /// entry `k` is `k / len` cycles per frame, entry 0 is 0), averaged over the first
    /// inset's pixels, over the frames from [`GOAL_FRAME`] on.
    pub temporal: Vec<f64>,
    /// The accumulated mean luma (mean of frames `0..n`, row-major) for each `n`
    /// of [`ACCUMULATION_SNAPSHOTS`] the run reached.
    pub accumulated: Vec<(u32, Vec<f32>)>,
    /// Frame [`GOAL_FRAME`] (or the last).
    pub snapshot: Snapshot,
    /// The error after each real-time filter chain
    /// ([`crate::filtered::STUDY_FILTERS`]; empty when the study's
    /// [`StudyConfig::filters`] is off).
    pub filtered: Vec<FilteredErrors>,
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
    /// The reference itself sent through each filter chain, one frame per
    /// study frame: the filters' own error floor ([`Self::filter_bias`]).
    pub filter_bias: Vec<FilteredErrors>,
}

/// The scene, reference and insets of one configuration.
#[derive(Debug)]
pub struct Study {
    /// The configuration.
    pub config: StudyConfig,
    /// The scene's buffers ([`StudyConfig::scene`]).
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
        let scene = SceneGpu::build(&config.scene.load()?)?;
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

    /// Runs every method of `methods` and measures it. `progress(method, t)` is called
    /// after every frame.
    ///
    /// # Errors
    /// Rendering errors.
    pub fn run(&self, methods: &[Method], mut progress: impl FnMut(Method, u32)) -> Result<StudyResult> {
        let (filter_bias, targets) = self.filter_bias()?;
        let mut runs = Vec::new();
        for &m in methods {
            runs.push(self.run_method(m, targets.as_deref(), |t| progress(m, t))?);
        }
        Ok(StudyResult {
            config: self.config,
            insets: self.insets.clone(),
            reference_noise_var: self.reference.noise_var,
            region_shares: region_shares(&self.regions),
            features: self.feature_diagnostics()?,
            runs,
            filter_bias,
        })
    }

    /// The reference sent through each filter chain for the study's frame
    /// count, and the luma of its last filtered frame per chain (the target
    /// of the noise part; a still reference converges in one frame). Empty
    /// and `None` without [`StudyConfig::filters`].
    #[allow(clippy::type_complexity)]
    fn filter_bias(&self) -> Result<(Vec<FilteredErrors>, Option<Vec<Vec<f32>>>)> {
        if !self.config.filters {
            return Ok((Vec::new(), None));
        }
        let size = self.config.size;
        let mut meter = FilteredMeter::new(size, size, None)?;
        let color: Vec<Vec4> = self.reference.rgb.iter().map(|c| c.extend(1.0)).collect();
        let still = vec![Vec2::ZERO; color.len()];
        for _ in 0..self.config.frames {
            meter.frame(&color, &self.gbuffer, &still, &self.reference.luma, &self.regions)?;
        }
        let targets = meter.last_luma();
        Ok((meter.finish(), Some(targets)))
    }

    fn run_method(
        &self,
        method: Method,
        filter_targets: Option<&[Vec<f32>]>,
        mut progress: impl FnMut(u32),
    ) -> Result<MethodRun> {
        let mut meter = Meter::new(self, method, filter_targets)?;
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
            Method::FeaturePermute
            | Method::FeaturePermuteJitter
            | Method::FeaturePermuteRawKey
            | Method::FeaturePermuteHistoryKey => {
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
                    feature_key: match method {
                        Method::FeaturePermuteRawKey => FeatureKey::Raw,
                        Method::FeaturePermuteHistoryKey => FeatureKey::HistoryResidual,
                        _ => FeatureKey::Demodulated,
                    },
                };
                let mut sequence = SceneSequence::still(&self.scene, self.config.size);
                render_sequence_cpu(&mut sequence, &job, options, |f: &FrameView<'_>| {
                    on_frame(f.index, f.color)
                })?;
            }
            Method::FixedStep => render_walk(self, Walk::FixedStep, &mut on_frame)?,
            Method::Dither => render_dither(self, sampler_core::defaults::stbn_128(), &mut on_frame)?,
            Method::DitherFilterAdapted => {
                render_dither(self, sampler_core::defaults::filter_adapted_128(), &mut on_frame)?
            }
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
    /// Spectra summed into `run.spectrum`.
    spectrum_count: u32,
    /// The first inset's error per frame from `snapshot_frame` on (frame-major).
    inset_series: Vec<f32>,
    /// The real-time filters ([`StudyConfig::filters`]), a still camera's
    /// zero motion, and the first filter error.
    filters: Option<(FilteredMeter, Vec<Vec2>)>,
    filter_error: Option<anyhow::Error>,
    /// Per inset: `1 / luma(albedo)` of each pixel's primary hit (1 below
    /// `ALBEDO_FLOOR`), from the still camera's G-buffer, for
    /// [`MethodRun::lf_demodulated`].
    inset_inverse_albedo: Vec<Grid>,
}

impl<'a> Meter<'a> {
    fn new(study: &'a Study, method: Method, filter_targets: Option<&[Vec<f32>]>) -> Result<Self> {
        let n = (study.config.size * study.config.size) as usize;
        let snapshot_frame = GOAL_FRAME.min(study.config.frames - 1);
        Ok(Meter {
            study,
            run: MethodRun {
                method,
                lf_insets: Vec::new(),
                lf_demodulated: Vec::new(),
                rmse: Vec::new(),
                blur1: Vec::new(),
                blur2: Vec::new(),
                blur1_regions: Vec::new(),
                acc_regions: Vec::new(),
                seed_repeats: None,
                acc_rmse: Vec::new(),
                acc_rmse_corrected: Vec::new(),
                radial: Vec::new(),
                spectrum: Vec::new(),
                spectrum_side: study.insets.iter().map(|i| i.side as usize).min().unwrap_or(0),
                temporal: Vec::new(),
                accumulated: Vec::new(),
                snapshot: Snapshot {
                    frame: snapshot_frame,
                    rgb: Vec::new(),
                    error: Vec::new(),
                },
                filtered: Vec::new(),
            },
            analyzer: SpectrumAnalyzer::new(),
            blur1: GaussianBlur::new(1.0)?,
            blur2: GaussianBlur::new(2.0)?,
            sum: vec![0.0; n],
            radial_frames: 0,
            snapshot_frame,
            spectrum_count: 0,
            inset_series: Vec::new(),
            filters: match study.config.filters {
                true => Some((
                    FilteredMeter::new(
                        study.config.size,
                        study.config.size,
                        filter_targets.map(<[Vec<f32>]>::to_vec),
                    )?,
                    vec![Vec2::ZERO; n],
                )),
                false => None,
            },
            filter_error: None,
            inset_inverse_albedo: {
                let inverse: Vec<f32> = study
                    .gbuffer
                    .iter()
                    .map(|g| {
                        let a = sampler_core::luma(g.albedo.truncate());
                        if a >= sampler_core::features::ALBEDO_FLOOR {
                            1.0 / a
                        } else {
                            1.0
                        }
                    })
                    .collect();
                let size = study.config.size as usize;
                study.insets.iter().map(|i| crop(&inverse, size, i)).collect()
            },
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
        let mut lf_demodulated = 0.0;
        for (k, inset) in self.study.insets.iter().enumerate() {
            let sub = crop(&error, size, inset);
            let spectrum = self.analyzer.power_spectrum(&sub);
            lf.push(low_frequency_ratio(&spectrum));
            let scale = &self.inset_inverse_albedo[k];
            let divided = Grid::from_fn(sub.width(), sub.height(), |x, y| sub.get(x, y) * scale.get(x, y))
                .expect("inset size");
            lf_demodulated += low_frequency_ratio(&self.analyzer.power_spectrum(&divided));
            if k == 0 && t >= self.snapshot_frame {
                let r = radial_power(&spectrum);
                if self.run.radial.is_empty() {
                    self.run.radial = vec![0.0; r.mean().len()];
                }
                for (a, b) in self.run.radial.iter_mut().zip(r.mean()) {
                    *a += b;
                }
                self.radial_frames += 1;
                self.inset_series.extend_from_slice(sub.data());
            }
            if t >= self.snapshot_frame {
                self.add_spectrum(&sub);
            }
        }
        self.run.lf_insets.push(lf);
        self.run
            .lf_demodulated
            .push(lf_demodulated / self.study.insets.len().max(1) as f64);
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
        if ACCUMULATION_SNAPSHOTS.contains(&(t + 1)) {
            let mean = self.sum.iter().map(|s| (*s / n) as f32).collect();
            self.run.accumulated.push((t + 1, mean));
        }
        mse /= self.sum.len() as f64;
        self.run.acc_rmse.push(mse.sqrt());
        self.run
            .acc_rmse_corrected
            .push((mse - reference.noise_var).max(0.0).sqrt());
        if t == self.snapshot_frame {
            self.run.snapshot.rgb = color.iter().map(|c| c.truncate()).collect();
            self.run.snapshot.error = error;
        }
        if let Some((filters, still)) = self.filters.as_mut() {
            let s = self.study;
            if let Err(e) = filters.frame(color, &s.gbuffer, still, &reference.luma, &s.regions) {
                self.filter_error.get_or_insert(e);
            }
        }
    }

    /// Adds the spectrum of the central `spectrum_side` square of `inset_error`.
    fn add_spectrum(&mut self, inset_error: &Grid) {
        let side = self.run.spectrum_side;
        let (x0, y0) = (
            (inset_error.width() - side) / 2,
            (inset_error.height() - side) / 2,
        );
        let centre =
            Grid::from_fn(side, side, |x, y| inset_error.get(x0 + x, y0 + y)).expect("spectrum side");
        let spectrum = self.analyzer.power_spectrum(&centre);
        if self.run.spectrum.is_empty() {
            self.run.spectrum = vec![0.0; side * side];
        }
        for (a, b) in self.run.spectrum.iter_mut().zip(spectrum.power()) {
            *a += b;
        }
        self.spectrum_count += 1;
    }

    fn finish(mut self) -> Result<MethodRun> {
        if let Some(e) = self.filter_error.take() {
            return Err(e.context("real-time filter"));
        }
        if let Some((filters, _)) = self.filters.take() {
            self.run.filtered = filters.finish();
        }
        ensure!(
            self.run.rmse.len() == self.study.config.frames as usize,
            "the renderer delivered {} of {} frames",
            self.run.rmse.len(),
            self.study.config.frames
        );
        let k = self.radial_frames.max(1) as f64;
        self.run.radial.iter_mut().for_each(|v| *v /= k);
        let k = self.spectrum_count.max(1) as f64;
        self.run.spectrum.iter_mut().for_each(|v| *v /= k);
        let side = self.study.insets.first().map_or(0, |i| i.side as usize);
        let depth = self.inset_series.len() / (side * side).max(1);
        if depth >= 2 {
            let series = std::mem::take(&mut self.inset_series);
            let volume = crate::Volume::new(side, side, depth, series)?;
            self.run.temporal = crate::temporal::temporal_power(&mut self.analyzer, &volume);
        }
        Ok(self.run)
    }
}
