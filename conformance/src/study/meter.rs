//! Running a study: every method's frames through the tracer's loops, each frame
//! measured against the reference by the per-frame [`Meter`].

use super::config::{ACCUMULATION_SNAPSHOTS, GOAL_FRAME};
use super::feature_diagnostics::SeedTracker;
use super::filtered::{FilteredErrors, FilteredMeter};
use super::history::HistoryMeter;
use super::insets::crop;
use super::method::{white_control_salt, Method};
use super::result::{MethodRun, Snapshot, StudyResult};
use super::setup::{albedo_luma, Study};
use super::temporal_sort::{render_temporal_permute, render_temporal_sort};
use super::walks::{render_dither, render_walk, Walk};
use crate::metrics::regions::{region_shares, square_sums_by_region};
use crate::metrics::surfaces::glossy_interior_share;
use crate::{low_frequency_ratio, radial_power, GaussianBlur, Grid, SpectrumAnalyzer};
use anyhow::{ensure, Result};
use glam::{Vec2, Vec4};
use gpu_tracer::feature_keys::FeatureKey;
use gpu_tracer::render::{render_sequence_cpu, FrameView, SequenceOptions};
use gpu_tracer::timeline::SceneSequence;
use gpu_tracer::{PermuteMode, RenderJob, TileChoice};
use sampler_core::Intensity;

impl Study {
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
            glossy_interior_share: glossy_interior_share(&self.regions, &self.glossy),
            features: self.feature_diagnostics()?,
            runs,
            filter_bias,
            regularization: self.regularization.clone(),
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
        let mut meter = FilteredMeter::new(size, size, self.config.filter_settings(), None)?;
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
            Method::White
            | Method::WhiteControl
            | Method::Sort
            | Method::Permute
            | Method::PermuteJitter
            | Method::PermuteZSobolJitter => {
                let mut settings = self.config.settings();
                settings.sampler = method.jitter_sampler();
                let job = RenderJob {
                    settings,
                    frames: self.config.frames,
                    mode: match method {
                        Method::White | Method::WhiteControl => PermuteMode::White,
                        Method::Sort => PermuteMode::Sort,
                        _ => PermuteMode::Permute,
                    },
                    block: self.config.block,
                    tile: self.config.tile,
                    salt: match method {
                        Method::WhiteControl => white_control_salt(self.config.salt),
                        _ => self.config.salt,
                    },
                };
                gpu_tracer::render_cpu(&self.scene, &job, &mut on_frame)?;
            }
            Method::FeaturePermute
            | Method::FeaturePermuteJitter
            | Method::FeaturePermuteRawKey
            | Method::FeaturePermuteHistoryKey
            | Method::FeatureTemporalPermute
            | Method::FeatureTemporalPermuteJitter => {
                let mut settings = self.config.settings();
                settings.sampler = method.jitter_sampler();
                let temporal = matches!(
                    method,
                    Method::FeatureTemporalPermute | Method::FeatureTemporalPermuteJitter
                );
                let job = RenderJob {
                    settings,
                    frames: self.config.frames,
                    mode: if temporal {
                        PermuteMode::Temporal
                    } else {
                        PermuteMode::Permute
                    },
                    block: self.config.block,
                    tile: if temporal {
                        TileChoice::TEMPORAL
                    } else {
                        self.config.tile
                    },
                    salt: self.config.salt,
                };
                let options = SequenceOptions {
                    gbuffer: false,
                    reproject: false,
                    reproject_hold_below: 0.0,
                    reproject_follow_share: 0.0,
                    pan_offset: false,
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
            Method::TemporalSort | Method::TemporalSortAdvance => render_temporal_sort(
                self,
                sampler_core::defaults::stbn_128(),
                method == Method::TemporalSortAdvance,
                &mut on_frame,
            )?,
            Method::TemporalPermute
            | Method::TemporalPermuteJitter
            | Method::TemporalPermuteKroneckerJitter => {
                render_temporal_permute(self, method.jitter_sampler(), &mut on_frame)?
            }
            Method::DitherFilterAdapted => {
                render_dither(self, sampler_core::defaults::filter_adapted_128(), &mut on_frame)?
            }
            Method::ScreenSobol
            | Method::ZSobol
            | Method::Spatiotemporal
            | Method::SpatiotemporalKronecker => {
                let mut settings = self.config.settings();
                settings.sampler = match method {
                    Method::ScreenSobol => kernels::abi::SAMPLER_SCREEN_SOBOL,
                    Method::ZSobol => kernels::abi::SAMPLER_ZSOBOL,
                    Method::SpatiotemporalKronecker => {
                        kernels::abi::SAMPLER_SPATIOTEMPORAL | kernels::abi::SAMPLER_KRONECKER
                    }
                    _ => kernels::abi::SAMPLER_SPATIOTEMPORAL,
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
    /// The exponential history of the frames ([`super::history`]).
    history: HistoryMeter,
    /// Per inset: `1 / luma(albedo)` of each pixel's primary hit (1 below
    /// `ALBEDO_FLOOR`), from the still camera's G-buffer, for
    /// [`MethodRun::lf_demodulated`].
    inset_inverse_albedo: Vec<Grid>,
    /// Per inset: [`Study::modulation`] cropped, for [`MethodRun::lf_modulated`].
    inset_modulation: Option<Vec<Grid>>,
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
                lf_modulated: Vec::new(),
                rmse: Vec::new(),
                blur1: Vec::new(),
                blur2: Vec::new(),
                blur1_regions: Vec::new(),
                acc_regions: Vec::new(),
                acc_fourth: Vec::new(),
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
                history: Default::default(),
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
                        study.config.filter_settings(),
                        filter_targets.map(<[Vec<f32>]>::to_vec),
                    )?,
                    vec![Vec2::ZERO; n],
                )),
                false => None,
            },
            filter_error: None,
            history: HistoryMeter::new(study.config.size, study.glossy.clone())?,
            inset_inverse_albedo: {
                let inverse: Vec<f32> = study
                    .gbuffer
                    .iter()
                    .map(|g| albedo_luma(g).map_or(1.0, |a| 1.0 / a))
                    .collect();
                let size = study.config.size as usize;
                study.insets.iter().map(|i| crop(&inverse, size, i)).collect()
            },
            inset_modulation: study.modulation.as_ref().map(|m| {
                let size = study.config.size as usize;
                study.insets.iter().map(|i| crop(m, size, i)).collect()
            }),
        })
    }

    fn frame(&mut self, t: u32, color: &[Vec4]) {
        let size = self.study.config.size as usize;
        let reference = &self.study.reference;
        let luma: Vec<f32> = color.iter().map(|c| c.intensity()).collect();
        let error: Vec<f32> = luma.iter().zip(&reference.luma).map(|(l, r)| l - r).collect();
        let grid = Grid::new(size, size, error.clone()).expect("frame size");
        self.run.rmse.push(grid.rms());
        let blurred = self.blur1.apply(&grid);
        self.run.blur1.push(blurred.rms());
        self.run
            .blur1_regions
            .push(square_sums_by_region(blurred.data(), &self.study.regions));
        self.run.blur2.push(self.blur2.apply(&grid).rms());
        let mut lf = Vec::with_capacity(self.study.insets.len());
        let mut lf_demodulated = 0.0;
        let mut lf_modulated = 0.0;
        for (k, inset) in self.study.insets.iter().enumerate() {
            let sub = crop(&error, size, inset);
            let spectrum = self.analyzer.power_spectrum(&sub);
            lf.push(low_frequency_ratio(&spectrum));
            let mut scaled_lf = |scale: &Grid| {
                let scaled = Grid::from_fn(sub.width(), sub.height(), |x, y| sub.get(x, y) * scale.get(x, y))
                    .expect("inset size");
                low_frequency_ratio(&self.analyzer.power_spectrum(&scaled))
            };
            lf_demodulated += scaled_lf(&self.inset_inverse_albedo[k]);
            if let Some(modulation) = &self.inset_modulation {
                lf_modulated += scaled_lf(&modulation[k]);
            }
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
        if self.inset_modulation.is_some() {
            self.run
                .lf_modulated
                .push(lf_modulated / self.study.insets.len().max(1) as f64);
        }
        // Accumulation.
        let n = (t + 1) as f64;
        let mut mse = 0.0;
        let (mut acc, mut fourth) = ([0.0f64; 3], [0.0f64; 3]);
        for (((s, l), r), region) in self
            .sum
            .iter_mut()
            .zip(&luma)
            .zip(&reference.luma)
            .zip(&self.study.regions)
        {
            *s += *l as f64;
            let d = *s / n - *r as f64;
            mse += d * d;
            acc[*region as usize] += d * d;
            fourth[*region as usize] += d * d * d * d;
        }
        self.run.acc_regions.push(acc);
        self.run.acc_fourth.push(fourth);
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
        self.history.frame(&luma, &reference.luma, &self.study.regions);
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
        self.run.history = self.history.finish();
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
            self.run.temporal = crate::metrics::temporal::temporal_power(&mut self.analyzer, &volume);
        }
        Ok(self.run)
    }
}
