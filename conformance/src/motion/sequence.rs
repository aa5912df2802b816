//! The posed sequences of the motion study ([`MotionSequence`]: per-frame references,
//! regions, motion and insets) and the runs that measure every method over them
//! ([`run_study`]).

use super::case::{self as motion_case, MotionCase};
use super::config::MotionConfig;
use super::history::{ReprojectedHistory, HISTORY_ALPHA};
use super::insets::{fit_insets, place_insets, InsetAnchor};
use super::method::MotionMethod;
use super::result::{slot, CaseResult, MotionRun, SequenceStats, WHOLE};
use crate::metrics::regions::{classify_regions, Region};
use crate::study::filtered::region_sums;
use crate::study::insets::{check_inset, crop, Inset};
use crate::study::reference::{pose_key, Reference};
use crate::{low_frequency_ratio, GaussianBlur, Grid, SpectrumAnalyzer};
use anyhow::{ensure, Context, Result};
use glam::{UVec2, Vec2};
use gpu_tracer::cornell::cornell_box;
use gpu_tracer::cpu;
use gpu_tracer::filter::{FilterChain, FilterSettings, FrameFilter};
use gpu_tracer::method_choice::DEFAULT_REPROJECT_FOLLOW_SHARE;
use gpu_tracer::motion::{frame_motion_words, reprojection_motion, write_visibility};
use gpu_tracer::render::{render_sequence_cpu, FrameView};
use gpu_tracer::scene::Scene;
use gpu_tracer::timeline::{SceneSequence, Timeline};
use kernels::abi::GBufferGpu;
use kernels::motion::frame_follows;
use kernels::pan_offset::{motion_spread, moves_alike, spread_speed, FRAME_RIGID};
use sampler_core::{FrameLayout, Intensity};
use std::collections::HashMap;
use std::path::Path;
use std::rc::Rc;

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
        // Homes carried from frame 0 by every frame's reprojection (`--mode hold`).
        let mut homes = identity.clone();
        let mut homes_next = vec![0u32; identity.len()];
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
                        settings.environment,
                        settings.glossy_regularization,
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
            // Insets: following their surface (`crate::motion` docs, "Figures").
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
                sampler_core::reproject_frame(&layout, &motion, &homes, &mut claims, &mut homes_next)?;
                std::mem::swap(&mut homes, &mut homes_next);
                stats.homes_in_order += homes_in_order(&homes, size, pw) / k;
                let words = frame_motion_words(&gbuf, size, size);
                let rigid = words[FRAME_RIGID];
                stats.rigid_share += rigid as f64 / n as f64 / k;
                let spread = motion_spread(&words);
                let speed = spread_speed(spread);
                if spread[0] > 0 && speed > 0 {
                    let relative = spread[3] as f64 / speed as f64;
                    stats.rigid_spread += relative;
                    stats.frames_sampled += 1.0;
                }
                if frame_follows(rigid, n as u32, DEFAULT_REPROJECT_FOLLOW_SHARE) {
                    stats.frames_following += 1.0 / k;
                    if moves_alike(spread) {
                        stats.frames_moving_offset += 1.0 / k;
                    }
                }
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
        if stats.frames_sampled > 0.0 {
            stats.rigid_spread /= stats.frames_sampled;
        }
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
        let mut history =
            ReprojectedHistory::new(size, size, HISTORY_ALPHA).with_fetch(self.config.history_fetch);
        // The same history of the per-frame error (frame minus its pose's
        // reference): the history's error without its resampling lag.
        let mut error_history =
            ReprojectedHistory::new(size, size, HISTORY_ALPHA).with_fetch(self.config.history_fetch);
        let still = self.case == MotionCase::Still;
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
            let mut ema = [0.0f64; 4];
            for (((v, r), noise), region) in h.iter().zip(reference).zip(noise).zip(&pose.regions) {
                let d = (*v - *r) as f64;
                let e = d * d - *noise as f64;
                ema[0] += e;
                if *region == Region::Interior {
                    ema[1] += e;
                }
            }
            let (he, _) = error_history.update(&error, &pose.motion);
            for ((v, noise), region) in he.iter().zip(noise).zip(&pose.regions) {
                // Still: one reference, its noise in every frame's error as
                // in the EMA above. Moving: a reference per pose, whose
                // independent noises the history averages down to
                // alpha / (2 - alpha) of one, left in (< 2% of white's).
                let e = (*v as f64) * (*v as f64) - if still { *noise as f64 } else { 0.0 };
                ema[2] += e;
                if *region == Region::Interior {
                    ema[3] += e;
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

/// Fraction of horizontally and vertically adjacent pixel pairs of the `size`-square
/// image (seed buffer rows `padded_width` long, homes as buffer indices) whose homes
/// are still adjacent in the same order (`home(x + 1, y) = home(x, y) + 1`,
/// `home(x, y + 1) = home(x, y) + padded_width`): where a sampler that reads its
/// points at the homes (ZSobol's Morton order) keeps its arrangement.
fn homes_in_order(homes: &[u32], size: u32, padded_width: usize) -> f64 {
    let size = size as usize;
    let pairs = (0..size).flat_map(|a| (0..size - 1).map(move |b| (a, b)));
    let kept = pairs
        .map(|(a, b)| {
            let (h, v) = (a * padded_width + b, b * padded_width + a);
            usize::from(homes[h + 1] == homes[h].wrapping_add(1))
                + usize::from(homes[v + padded_width] == homes[v].wrapping_add(padded_width as u32))
        })
        .sum::<usize>();
    kept as f64 / (2 * size * (size - 1)) as f64
}
