//! The rendered-quality study in motion (issue 13, part 4): the seed permutation with
//! and without the bijective seed reprojection (`sampler_core::reproject_frame`) on
//! moving Cornell-box sequences, against a reference rendered at every frame's pose.
//!
//! Sequences ([`crate::motion_case`]): the camera swaying on an orbit at about 0.5 and
//! 2 px/frame at the image centre, the short block rising and sinking, and the still
//! camera (the static figures every moving figure is compared with, measured by the
//! same code). Every method renders through `gpu_tracer::render::render_sequence_cpu`
//! (per frame: G-buffer, reprojection, trace, sort + retarget), 1 spp, starting from
//! the same white seeds ([`MotionConfig::salt`]).
//!
//! # Rows ([`MotionMethod`])
//! white (fresh seeds), permute without reprojection, permute with reprojection,
//! permute-jitter (`SAMPLER_SCREEN_SOBOL | SAMPLER_JITTER_ONLY`) with reprojection,
//! feature-aware permute with reprojection (`SequenceOptions::features`, issue 14:
//! demodulated keys, blocks sorted in groups of one surface, retarget moves cut at
//! edges), screen-sobol (white seeds, every 2D decision from the screen-space sampler).
//!
//! # Per-frame reference
//! Every frame is compared with a reference of the same pose
//! ([`crate::reference::Reference::get_named`], two halves of `ref_spp / 2` samples),
//! cached in [`crate::reference::default_cache_dir`] under a name holding
//! [`crate::reference::pose_key`] (camera, geometry, settings). The sway repeats its
//! poses, so a sequence renders only its distinct poses.
//!
//! # Figures (all relative to white's run of the same sequence: white = 1)
//! Error `e_t = luma(frame_t) - luma(reference_t)`; figures pooled over frames
//! `t >= GOAL_FRAME` (8) like the static study's "LF mean 8.." and "blur s1 rms":
//! - **LF**: low-frequency power (`|f| <= 1/8`) of `e_t` on the three flat insets of the
//!   static study ([`crate::insets`]), mean over insets, divided by white's at the same
//!   frame, mean over frames. The insets follow their surface: each is placed at frame 0
//!   and moved every frame so that the world point under its centre stays under its
//!   centre (rounded to whole pixels); every pixel's centre ray is checked against the
//!   inset's surface in every frame and the study fails if one misses it.
//! - **blur**: RMS of `e_t` after a toroidal Gaussian blur of sigma 1, over frames, as
//!   `sqrt(sum_t sum_p b^2 / same for white)`, for the whole image and per region
//!   ([`crate::regions`]: emitter zone, edges, interior as issue 14 defines them; from
//!   each frame's G-buffer).
//! - **EMA**: RMSE of a reprojecting exponential history ([`crate::history`], alpha
//!   0.1, reset on disocclusion) against the frame's reference, over frames
//!   `t >= EMA_FROM` (16, once the history has settled), whole image and interior, with
//!   the reference's own noise subtracted (per pixel, from its halves).
//!
//! [`CaseResult::versus_static`] divides a moving sequence's figure by the same method's
//! figure on the still sequence: the goals of issue 13 ("within 1.1x of static at 0.5
//! px/frame, 1.25x at 2 px/frame") read off directly.
//!
//! # Diagnostics ([`SequenceStats`])
//! Measured image-centre speed, the fractions of pixels whose seed followed its point,
//! was recycled (`sampler_core::ReprojectStats`) or stayed in its pixel, history resets,
//! and the regions' shares of the image.

use crate::filtered::region_sums;
use crate::history::{ReprojectedHistory, HISTORY_ALPHA};
use crate::insets::crop;
use crate::insets::{check_inset, Inset};
use crate::motion_case::{self, MotionCase};
use crate::motion_insets::place_insets;
pub use crate::motion_insets::{fit_insets, InsetAnchor, MIN_INSET_SIDE};
pub use crate::motion_tables::markdown;
use crate::reference::{pose_key, Reference};
use crate::regions::{classify_regions, Region};
use crate::render_study::GOAL_FRAME;
use crate::{low_frequency_ratio, GaussianBlur, Grid, SpectrumAnalyzer};
use anyhow::{ensure, Context, Result};
use glam::{UVec2, Vec2};
use gpu_tracer::cornell::cornell_box;
use gpu_tracer::filter::{FilterChain, FilterSettings, FrameFilter};
use gpu_tracer::motion::{reprojection_motion, write_visibility};
use gpu_tracer::render::{render_sequence_cpu, FrameView, SequenceOptions};
use gpu_tracer::scene::{Scene, TraceSettings};
use gpu_tracer::timeline::{SceneSequence, Timeline};
use gpu_tracer::{cpu, PermuteMode, RenderJob, TileChoice};
use kernels::abi::{GBufferGpu, SEED_MODE_FIXED};
use sampler_core::{FrameLayout, Intensity};
use std::collections::HashMap;
use std::path::Path;
use std::rc::Rc;

/// First frame of the pooled EMA figures: the history (alpha 0.1) has then reached
/// `1 - 0.9^16 = 81%` of its weight.
pub const EMA_FROM: u32 = 16;

/// Which seeds and sampler a row uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MotionMethod {
    /// Fresh white-noise seeds every frame.
    White,
    /// The permutation, seeds left at their pixels when things move.
    Permute,
    /// The permutation with the seeds reprojected along the motion vectors.
    PermuteReproject,
    /// The permutation with the pixel jitter from screen-space Sobol, reprojected.
    PermuteJitterReproject,
    /// The feature-aware permutation (issue 14), reprojected.
    FeaturePermuteReproject,
    /// White seeds and screen-space Sobol on every 2D decision.
    ScreenSobol,
}

impl MotionMethod {
    /// Every row, white first.
    pub const ALL: [MotionMethod; 6] = [
        MotionMethod::White,
        MotionMethod::Permute,
        MotionMethod::PermuteReproject,
        MotionMethod::PermuteJitterReproject,
        MotionMethod::FeaturePermuteReproject,
        MotionMethod::ScreenSobol,
    ];

    /// Name used in tables.
    pub fn name(self) -> &'static str {
        match self {
            MotionMethod::White => "white",
            MotionMethod::Permute => "permute, no reprojection",
            MotionMethod::PermuteReproject => "permute + reprojection",
            MotionMethod::PermuteJitterReproject => "permute-jitter + reprojection",
            MotionMethod::FeaturePermuteReproject => "feature-aware permute + reprojection",
            MotionMethod::ScreenSobol => "screen-sobol",
        }
    }

    /// The render job and sequence options of this row.
    fn job(self, config: &MotionConfig) -> (RenderJob, SequenceOptions) {
        let mut settings = config.settings();
        settings.spp = 1;
        let features = self == MotionMethod::FeaturePermuteReproject;
        let (mode, reproject) = match self {
            MotionMethod::White => (PermuteMode::White, false),
            MotionMethod::FeaturePermuteReproject => (PermuteMode::Permute, true),
            MotionMethod::Permute => (PermuteMode::Permute, false),
            MotionMethod::PermuteReproject => (PermuteMode::Permute, true),
            MotionMethod::PermuteJitterReproject => {
                settings.sampler = kernels::abi::SAMPLER_SCREEN_SOBOL | kernels::abi::SAMPLER_JITTER_ONLY;
                (PermuteMode::Permute, true)
            }
            MotionMethod::ScreenSobol => {
                settings.sampler = kernels::abi::SAMPLER_SCREEN_SOBOL;
                (PermuteMode::White, false)
            }
        };
        let job = RenderJob {
            settings,
            frames: config.frames,
            mode,
            block: config.block,
            tile: config.tile,
            salt: config.salt,
        };
        let options = SequenceOptions {
            gbuffer: false,
            reproject,
            features,
            ..SequenceOptions::default()
        };
        (job, options)
    }
}

/// What to render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionConfig {
    /// Image side in pixels (square frames), at least 32.
    pub size: u32,
    /// Frames per sequence and method (1 spp each).
    pub frames: u32,
    /// Samples per pixel of each pose's reference (two halves).
    pub ref_spp: u32,
    /// Maximum path length in segments.
    pub max_depth: u32,
    /// Block side of the sorting pass.
    pub block: u32,
    /// Dither tile.
    pub tile: TileChoice,
    /// Salt of the initial white-noise seeds.
    pub salt: u32,
    /// Sway period in frames (a multiple of 4), `None` for
    /// [`motion_case::sway_period`] (`size / 4`).
    pub sway_period: Option<u32>,
}

impl MotionConfig {
    /// Defaults: depth 8, 4x4 blocks, 64x64 tile, salt 1, sway period `size / 4`.
    pub fn new(size: u32, frames: u32, ref_spp: u32) -> Self {
        MotionConfig {
            size,
            frames,
            ref_spp,
            max_depth: 8,
            block: 4,
            tile: TileChoice::Tile64,
            salt: 1,
            sway_period: None,
        }
    }

    pub(crate) fn settings(&self) -> TraceSettings {
        let mut s = TraceSettings::new(self.size, self.size);
        s.max_depth = self.max_depth;
        s.seed_mode = SEED_MODE_FIXED;
        s
    }
}

/// What the pose pass measured about a sequence (method independent).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SequenceStats {
    /// Mean length of the backward motion vector at the image centre over frames
    /// `1..`, pixels per frame (0 for a still sequence).
    pub centre_speed: f64,
    /// Mean length of the backward motion vector over the pixels that have a previous
    /// position, mean over frames `1..`, pixels per frame.
    pub mean_speed: f64,
    /// Mean over frames `1..` of the fraction of pixels whose seed followed its point
    /// (`ReprojectStats::followed / pixels`).
    pub followed: f64,
    /// Same for recycled seeds (disoccluded, off screen, or lost claims).
    pub recycled: f64,
    /// Mean fraction of pixels that keep the seed of their own pixel after the
    /// reprojection (the reprojection is the identity there).
    pub stayed: f64,
    /// Mean fraction of pixels whose history is reset (frames `1..`).
    pub history_resets: f64,
    /// Mean share of the image of each region ([`Region::ALL`] order).
    pub region_share: [f64; 3],
    /// Distinct poses (references) of the sequence.
    pub poses: usize,
}

/// A pose's reference luma and per-pixel noise variance, shared by the frames of that
/// pose.
type PoseReference = Rc<(Vec<f32>, Vec<f32>)>;

/// One frame's method-independent data.
#[derive(Debug)]
struct PoseFrame {
    /// Reference luma and per-pixel reference noise variance (shared by equal poses).
    reference: PoseReference,
    regions: Vec<Region>,
    /// Backward motion with NaN at disocclusions (for the history).
    motion: Vec<[f32; 2]>,
    /// The insets at this frame.
    insets: Vec<Inset>,
}

/// A posed sequence: its timeline, per-frame references, regions, motion and insets.
#[derive(Debug)]
pub struct MotionSequence {
    /// The case.
    pub case: MotionCase,
    /// What moves and how fast (degrees or units per frame).
    pub description: String,
    /// Method-independent measurements.
    pub stats: SequenceStats,
    config: MotionConfig,
    scene: Scene,
    timeline: Timeline,
    frames: Vec<PoseFrame>,
    own_insets: Vec<bool>,
}

/// Index of a whole-image or region figure in the per-frame sums.
const WHOLE: usize = 0;
fn slot(r: Region) -> usize {
    1 + r as usize
}

/// Per-frame sums of one method.
#[derive(Clone, Debug)]
pub struct MotionRun {
    /// The method.
    pub method: MotionMethod,
    /// Per frame, per inset ([`CaseResult::insets`] order): the error's low-frequency
    /// ratio (white noise = 1).
    pub lf: Vec<Vec<f64>>,
    /// Per frame: sum of squared blurred (sigma 1) error over the whole image and each
    /// region (`[whole, emitter, edges, interior]`).
    pub blur: Vec<[f64; 4]>,
    /// Per frame: sum of squared history error minus the reference's noise variance,
    /// whole image and interior.
    pub ema: Vec<[f64; 2]>,
    /// Per frame: sum of squared error after the real-time filter
    /// (`taa+atrous` of `gpu_tracer::filter`, reprojected by the motion vectors,
    /// reset at disocclusions), whole image and interior.
    pub filtered: Vec<[f64; 2]>,
}

/// One of the study's figures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Figure {
    /// Inset low-frequency power, mean over frames of the ratio to white.
    LowFrequency,
    /// Blurred RMSE, whole image (`None`) or one region.
    Blur(Option<Region>),
    /// History RMSE (reference noise removed), whole image or interior.
    Ema {
        /// Interior only.
        interior: bool,
    },
    /// RMSE after the real-time filter (TAA + a-trous), whole image or interior,
    /// over frames from [`EMA_FROM`].
    Filtered {
        /// Interior only.
        interior: bool,
    },
}

/// A measured sequence: every method's run.
#[derive(Debug)]
pub struct CaseResult {
    /// The case.
    pub case: MotionCase,
    /// What moves.
    pub description: String,
    /// The configuration.
    pub config: MotionConfig,
    /// Method-independent measurements.
    pub stats: SequenceStats,
    /// The insets at frame 0 (the LF series' order).
    pub insets: Vec<Inset>,
    /// Which insets are this sequence's own (its LF figure); the still sequence also
    /// measures the moving sequences' smaller insets for [`Self::versus_static`].
    pub own_insets: Vec<bool>,
    /// One run per method, in the order requested.
    pub runs: Vec<MotionRun>,
}

impl CaseResult {
    /// The run of `method`, if measured.
    pub fn run(&self, method: MotionMethod) -> Option<&MotionRun> {
        self.runs.iter().find(|r| r.method == method)
    }

    /// `figure` of `method` relative to white's (module docs). `None` when a run is
    /// missing or no frame is pooled.
    pub fn relative(&self, method: MotionMethod, figure: Figure) -> Option<f64> {
        let own: Vec<usize> = (0..self.insets.len()).filter(|&i| self.own_insets[i]).collect();
        self.relative_on(method, figure, &own)
    }

    /// [`Self::relative`], with the LF figure over the insets `insets` (indices into
    /// [`Self::insets`]).
    fn relative_on(&self, method: MotionMethod, figure: Figure, insets: &[usize]) -> Option<f64> {
        let m = self.run(method)?;
        let w = self.run(MotionMethod::White)?;
        let frames = m.lf.len().min(w.lf.len());
        let from = (GOAL_FRAME as usize).min(frames.saturating_sub(1));
        match figure {
            Figure::LowFrequency => {
                if insets.is_empty() {
                    return None;
                }
                let mean = |v: &[f64]| insets.iter().map(|&i| v[i]).sum::<f64>() / insets.len() as f64;
                let v: Vec<f64> = (from..frames).map(|t| mean(&m.lf[t]) / mean(&w.lf[t])).collect();
                (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
            }
            Figure::Blur(region) => {
                let k = region.map_or(WHOLE, slot);
                let sum = |r: &MotionRun| (from..frames).map(|t| r.blur[t][k]).sum::<f64>();
                ratio(sum(m), sum(w))
            }
            Figure::Ema { interior } => {
                let from = (EMA_FROM as usize).min(frames.saturating_sub(1));
                let k = usize::from(interior);
                let sum = |r: &MotionRun| (from..frames).map(|t| r.ema[t][k]).sum::<f64>();
                ratio(sum(m).max(0.0), sum(w))
            }
            Figure::Filtered { interior } => {
                let from = (EMA_FROM as usize).min(frames.saturating_sub(1));
                let k = usize::from(interior);
                let sum = |r: &MotionRun| {
                    (from..r.filtered.len().min(frames))
                        .map(|t| r.filtered[t][k])
                        .sum::<f64>()
                };
                ratio(sum(m), sum(w))
            }
        }
    }

    /// `figure` of `method` here divided by the same method's figure in `still` (both
    /// relative to white). The LF figure of `still` is taken on the insets of the same
    /// name and side as this sequence's (the still sequence measures every case's
    /// insets: [`run_study`]).
    pub fn versus_static(&self, still: &CaseResult, method: MotionMethod, figure: Figure) -> Option<f64> {
        let same: Vec<usize> = self
            .insets
            .iter()
            .zip(&self.own_insets)
            .filter(|(_, own)| **own)
            .filter_map(|(i, _)| {
                still
                    .insets
                    .iter()
                    .position(|s| s.name == i.name && s.side == i.side)
            })
            .collect();
        Some(self.relative(method, figure)? / still.relative_on(method, figure, &same)?)
    }
}

fn ratio(a: f64, b: f64) -> Option<f64> {
    (b > 0.0 && a.is_finite()).then(|| (a / b).sqrt())
}

impl MotionSequence {
    /// Poses the sequence of `case`: per frame the G-buffer, regions, motion, the insets
    /// of `anchors` (checked; [`fit_insets`] finds insets that pass; the flag marks the
    /// sequence's own insets, the others are measured for comparisons only) and the
    /// reference (rendered or loaded from `cache_dir`).
    /// `progress(message)` reports reference renders.
    ///
    /// # Errors
    /// Bad settings, rendering errors, or an inset that leaves its surface in some frame
    /// (the message names the frame, the inset and the pixel).
    pub fn new(
        config: MotionConfig,
        case: MotionCase,
        anchors: &[(InsetAnchor, bool)],
        cache_dir: Option<&Path>,
        mut progress: impl FnMut(&str),
    ) -> Result<MotionSequence> {
        ensure!(config.frames >= 1, "at least one frame");
        ensure!(config.size >= 32, "the insets need an image of at least 32x32");
        let (size, n) = (config.size, (config.size * config.size) as usize);
        let layout = FrameLayout::new(size, size, config.block, config.tile.side())?;
        let scene = cornell_box();
        let (timeline, description) =
            motion_case::timeline(case, &scene, size, config.frames, config.sway_period)?;
        let mut sequence = SceneSequence::new(&scene, timeline.clone(), size)?;
        let own_insets: Vec<bool> = anchors.iter().map(|a| a.1).collect();
        let anchors: Vec<InsetAnchor> = anchors.iter().map(|a| a.0.clone()).collect();
        let settings = config.settings();
        let mut gbuf = vec![GBufferGpu::default(); n];
        let mut previous = vec![UVec2::ZERO; n];
        let mut references: HashMap<u64, PoseReference> = HashMap::new();
        let identity: Vec<u32> = (0..layout.seed_count() as u32).collect();
        let mut claims = vec![0u32; identity.len()];
        let mut reprojected = vec![0u32; identity.len()];
        let mut stats = SequenceStats::default();
        let mut frames = Vec::with_capacity(config.frames as usize);
        for t in 0..config.frames {
            if t > 0 {
                sequence.advance()?;
            }
            let scene_t = sequence.scene();
            let params = scene_t.trace_params(&settings, t)?;
            cpu::gbuffer_frame(scene_t, &params, &mut gbuf)?;
            // Reference of this pose.
            let key = pose_key(scene_t, size, config.ref_spp, config.max_depth);
            let reference = match references.get(&key) {
                Some(r) => r.clone(),
                None => {
                    let name = format!(
                        "cornell-pose-{size}x{size}-spp{}-depth{}-{key:016x}.bin",
                        config.ref_spp / 2 * 2,
                        config.max_depth
                    );
                    let mut rendered = false;
                    let r = Reference::get_named(
                        scene_t,
                        size,
                        config.max_depth,
                        config.ref_spp,
                        &name,
                        cache_dir,
                        |_, _| rendered = true,
                    )?;
                    progress(&format!(
                        "{}: frame {t}: reference {} ({name})",
                        case.name(),
                        if rendered { "rendered" } else { "from the cache" }
                    ));
                    let r = Rc::new((r.luma, r.noise));
                    references.insert(key, r.clone());
                    r
                }
            };
            // Insets: following their surface (module docs).
            let insets = place_insets(&anchors, &params, size)?;
            for inset in &insets {
                check_inset(scene_t, &params, inset)
                    .with_context(|| format!("{}: frame {t}: the inset left its surface", case.name()))?;
            }
            let regions = classify_regions(&gbuf, size, size);
            for r in Region::ALL {
                stats.region_share[r as usize] +=
                    regions.iter().filter(|&&x| x == r).count() as f64 / n as f64 / config.frames as f64;
            }
            let motion = if t == 0 {
                vec![[f32::NAN; 2]; n]
            } else {
                let motion = reprojection_motion(&gbuf, &previous, size, size);
                let s = sampler_core::reproject_frame(
                    &layout,
                    &motion,
                    &identity,
                    &mut claims,
                    &mut reprojected,
                )?;
                let pw = layout.padded_width() as usize;
                let stayed = (0..n)
                    .filter(|&i| {
                        let j = (i / size as usize) * pw + i % size as usize;
                        reprojected[j] == j as u32
                    })
                    .count();
                let k = (config.frames - 1) as f64;
                stats.followed += s.followed as f64 / n as f64 / k;
                stats.recycled += s.recycled as f64 / n as f64 / k;
                stats.stayed += stayed as f64 / n as f64 / k;
                let resets = (0..n).filter(|&i| !has_source(i, motion[i], size)).count();
                let moving: f64 = (0..n)
                    .filter(|&i| has_source(i, motion[i], size))
                    .map(|i| (motion[i][0] as f64).hypot(motion[i][1] as f64))
                    .sum();
                stats.mean_speed += moving / (n - resets).max(1) as f64 / k;
                stats.history_resets += resets as f64 / n as f64 / k;
                let c = gbuf[(size / 2 * size + size / 2) as usize].motion;
                stats.centre_speed += (c.x as f64).hypot(c.y as f64) / k;
                motion
            };
            write_visibility(&gbuf, &mut previous);
            frames.push(PoseFrame {
                reference,
                regions,
                motion,
                insets,
            });
        }
        stats.poses = references.len();
        Ok(MotionSequence {
            case,
            description,
            stats,
            config,
            scene,
            timeline,
            frames,
            own_insets,
        })
    }

    /// The insets of every frame (frame 0's placement first).
    pub fn insets(&self, t: usize) -> &[Inset] {
        &self.frames[t].insets
    }

    /// The regions of frame `t`.
    pub fn regions(&self, t: usize) -> &[Region] {
        &self.frames[t].regions
    }

    /// Renders `methods` over the sequence and measures them. `progress(method, t)` is
    /// called after every frame.
    ///
    /// # Errors
    /// Rendering errors.
    pub fn run(
        &self,
        methods: &[MotionMethod],
        mut progress: impl FnMut(MotionMethod, u32),
    ) -> Result<CaseResult> {
        let mut runs = Vec::new();
        for &method in methods {
            runs.push(self.run_method(method, |t| progress(method, t))?);
        }
        Ok(CaseResult {
            case: self.case,
            description: self.description.clone(),
            config: self.config,
            stats: self.stats.clone(),
            insets: self.frames.first().map(|f| f.insets.clone()).unwrap_or_default(),
            own_insets: self.own_insets.clone(),
            runs,
        })
    }

    fn run_method(&self, method: MotionMethod, mut progress: impl FnMut(u32)) -> Result<MotionRun> {
        let size = self.config.size;
        let n = (size * size) as usize;
        let (job, mut options) = method.job(&self.config);
        // The a-trous filter reads each frame's G-buffer.
        options.gbuffer = true;
        let mut filter = FrameFilter::new(FilterChain::TaaAtrous, FilterSettings::default(), size, size)?;
        let mut filter_error = None;
        let mut sequence = SceneSequence::new(&self.scene, self.timeline.clone(), size)?;
        let blur = GaussianBlur::new(1.0)?;
        let mut analyzer = SpectrumAnalyzer::new();
        let mut history = ReprojectedHistory::new(size, size, HISTORY_ALPHA);
        let mut run = MotionRun {
            method,
            lf: Vec::new(),
            blur: Vec::new(),
            ema: Vec::new(),
            filtered: Vec::new(),
        };
        let mut luma = vec![0.0f32; n];
        render_sequence_cpu(&mut sequence, &job, options, |f: &FrameView<'_>| {
            let pose = &self.frames[f.index as usize];
            let (reference, noise) = (&pose.reference.0, &pose.reference.1);
            for (l, c) in luma.iter_mut().zip(f.color) {
                *l = c.intensity();
            }
            let error: Vec<f32> = luma.iter().zip(reference).map(|(a, b)| a - b).collect();
            let grid = Grid::new(size as usize, size as usize, error.clone()).expect("frame size");
            let blurred = blur.apply(&grid);
            let mut sums = [0.0f64; 4];
            for (b, r) in blurred.data().iter().zip(&pose.regions) {
                let b2 = (*b as f64) * (*b as f64);
                sums[WHOLE] += b2;
                sums[slot(*r)] += b2;
            }
            run.blur.push(sums);
            let lf: Vec<f64> = pose
                .insets
                .iter()
                .map(|inset| {
                    low_frequency_ratio(&analyzer.power_spectrum(&crop(&error, size as usize, inset)))
                })
                .collect();
            run.lf.push(lf);
            let (h, _) = history.update(&luma, &pose.motion);
            let mut ema = [0.0f64; 2];
            for (((v, r), noise), region) in h.iter().zip(reference).zip(noise).zip(&pose.regions) {
                let d = (*v - *r) as f64;
                let e = d * d - *noise as f64;
                ema[0] += e;
                if *region == Region::Interior {
                    ema[1] += e;
                }
            }
            run.ema.push(ema);
            let motion: Vec<Vec2> = pose.motion.iter().map(|m| Vec2::from(*m)).collect();
            let filtered = f
                .gbuffer
                .ok_or_else(|| anyhow::anyhow!("the renderer returned no G-buffer"))
                .and_then(|g| Ok(filter.apply(f.color, g, &motion)?));
            match filtered {
                Ok(out) => {
                    let sums = region_sums(&out, reference, &pose.regions);
                    run.filtered
                        .push([sums.iter().sum(), sums[Region::Interior as usize]]);
                }
                Err(e) => {
                    filter_error.get_or_insert(e);
                }
            }
            progress(f.index);
        })?;
        if let Some(e) = filter_error {
            return Err(e.context("real-time filter"));
        }
        ensure!(
            run.lf.len() == self.config.frames as usize,
            "the renderer delivered {} of {} frames",
            run.lf.len(),
            self.config.frames
        );
        Ok(run)
    }
}

/// Whether pixel `i` of a `size x size` frame with backward motion `m` has a previous
/// position inside the frame (false for NaN and `kernels::motion::DISOCCLUDED`): the
/// test of [`ReprojectedHistory::update`] and of `sampler_core::reproject_frame`.
fn has_source(i: usize, m: [f32; 2], size: u32) -> bool {
    let s = size as usize;
    let px = (i % s) as f32 + 0.5 + m[0];
    let py = (i / s) as f32 + 0.5 + m[1];
    px >= 0.0 && py >= 0.0 && px < size as f32 && py < size as f32
}

/// Runs `cases` (the still sequence first if it is not among them, since every moving
/// figure is also divided by the static one) with `methods`. `progress` receives
/// one-line messages.
///
/// # Errors
/// As [`MotionSequence::new`] and [`MotionSequence::run`].
pub fn run_study(
    config: MotionConfig,
    cases: &[MotionCase],
    methods: &[MotionMethod],
    cache_dir: Option<&Path>,
    mut progress: impl FnMut(&str),
) -> Result<Vec<CaseResult>> {
    let mut all = vec![MotionCase::Still];
    all.extend(cases.iter().copied().filter(|c| *c != MotionCase::Still));
    // Each case's insets; the still sequence measures its own and every other case's.
    let mut fitted = Vec::new();
    for &case in &all {
        let anchors = fit_insets(&config, &[case])?;
        progress(&format!(
            "{}: insets (x0, y0, side at frame 0): {}",
            case.name(),
            anchors
                .iter()
                .map(|a| format!(
                    "{} ({}, {}, {})",
                    a.inset.name, a.inset.x0, a.inset.y0, a.inset.side
                ))
                .collect::<Vec<_>>()
                .join(", ")
        ));
        fitted.push(anchors);
    }
    let mut still_anchors: Vec<(InsetAnchor, bool)> = fitted[0].iter().map(|a| (a.clone(), true)).collect();
    for a in fitted.iter().skip(1).flatten() {
        if !still_anchors
            .iter()
            .any(|(s, _)| s.inset.name == a.inset.name && s.inset.side == a.inset.side)
        {
            still_anchors.push((a.clone(), false));
        }
    }
    let mut results = Vec::new();
    for (k, &case) in all.iter().enumerate() {
        let start = std::time::Instant::now();
        let anchors: Vec<(InsetAnchor, bool)> = if k == 0 {
            still_anchors.clone()
        } else {
            fitted[k].iter().map(|a| (a.clone(), true)).collect()
        };
        let sequence = MotionSequence::new(config, case, &anchors, cache_dir, &mut progress)?;
        progress(&format!(
            "{}: {} poses ready in {:.1} s",
            case.name(),
            sequence.stats.poses,
            start.elapsed().as_secs_f64()
        ));
        let start = std::time::Instant::now();
        let result = sequence.run(methods, |_, _| {})?;
        progress(&format!(
            "{}: {} methods x {} frames in {:.1} s",
            case.name(),
            methods.len(),
            config.frames,
            start.elapsed().as_secs_f64()
        ));
        results.push(result);
    }
    Ok(results)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::insets::inset_layout;

    #[test]
    fn figures_pool_over_frames_relative_to_white() {
        let run = |method, lf: f64, blur: f64| MotionRun {
            method,
            lf: vec![vec![lf]; 20],
            blur: vec![[blur, blur, 0.0, 0.0]; 20],
            ema: vec![[blur, 0.0]; 20],
            filtered: vec![[blur, blur]; 20],
        };
        let r = CaseResult {
            case: MotionCase::Still,
            description: String::new(),
            config: MotionConfig::new(32, 20, 4),
            stats: SequenceStats::default(),
            insets: inset_layout(32)[..1].to_vec(),
            own_insets: vec![true],
            runs: vec![
                run(MotionMethod::White, 2.0, 4.0),
                run(MotionMethod::Permute, 1.0, 1.0),
            ],
        };
        assert_eq!(
            r.relative(MotionMethod::Permute, Figure::Filtered { interior: true }),
            Some(0.5)
        );
        assert_eq!(r.relative(MotionMethod::Permute, Figure::LowFrequency), Some(0.5));
        assert_eq!(r.relative(MotionMethod::Permute, Figure::Blur(None)), Some(0.5));
        assert_eq!(
            r.relative(MotionMethod::Permute, Figure::Ema { interior: false }),
            Some(0.5)
        );
        assert_eq!(
            r.relative(MotionMethod::Permute, Figure::Blur(Some(Region::Edge))),
            None
        );
        assert_eq!(
            r.versus_static(&r, MotionMethod::Permute, Figure::LowFrequency),
            Some(1.0)
        );
        assert!(markdown(&[r]).contains("| still | permute, no reprojection | 0.500 | 0.500 |"));
    }
}
