//! The temporal render loop, on the CPU or the GPU: render frame `t` with
//! the current seeds, accumulate it, then turn the seeds into frame `t + 1`'s
//! according to the [`PermuteMode`].

use crate::cpu;
use crate::feature_keys::{FeatureKey, FeatureKeys};
use crate::gpu::{
    Gpu, GpuError, PermuteMode, PermutePipelines, ReprojectPipelines, SeedPermuter, SeedReprojector,
    TracePipelines, Tracer,
};
use crate::motion::{frame_motion_words, seed_motion_with, write_visibility};
use crate::scene::{SceneGpu, TraceSettings};
use crate::timeline::SceneSequence;
use glam::{UVec2, Vec4};
use kernels::abi::{
    GBufferGpu, SAMPLER_FOLLOW_HOMES, SAMPLER_JITTER_ONLY, SAMPLER_KIND_MASK, SAMPLER_SPATIOTEMPORAL,
    SEED_MODE_ADVANCE,
};
use kernels::motion::frame_follows;
use kernels::pan_offset::{advance_offset, FRAME_RIGID};
use sampler_core::sequences::spatiotemporal::write_initial_homes;
use sampler_core::{DitherTile, FeatureThresholds, FrameLayout, RetargetTables, SliceTables};
use std::fmt;

/// Which baked dither tile (and its retarget tables) the permutation uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TileChoice {
    /// `sampler_core::defaults::tile_64` (64 x 64).
    Tile64,
    /// `sampler_core::defaults::tile_128` (128 x 128).
    Tile128,
}

impl TileChoice {
    /// The tile the temporal mode ([`PermuteMode::Temporal`]) needs: the
    /// side of its target's slices (`sampler_core::defaults::temporal_target`,
    /// 64x64).
    pub const TEMPORAL: TileChoice = TileChoice::Tile64;

    /// The tile for a side of 64 or 128 texels.
    pub fn from_side(side: u32) -> Option<Self> {
        match side {
            64 => Some(TileChoice::Tile64),
            128 => Some(TileChoice::Tile128),
            _ => None,
        }
    }
    /// Side in texels.
    pub fn side(self) -> u32 {
        match self {
            TileChoice::Tile64 => 64,
            TileChoice::Tile128 => 128,
        }
    }
    /// The baked tile and its tables.
    pub fn load(self) -> (DitherTile<'static>, RetargetTables<'static>) {
        match self {
            TileChoice::Tile64 => (
                sampler_core::defaults::tile_64(),
                sampler_core::defaults::tables_64(),
            ),
            TileChoice::Tile128 => (
                sampler_core::defaults::tile_128(),
                sampler_core::defaults::tables_128(),
            ),
        }
    }
}

/// Receives frame `t`'s colour (`width * height`, row-major).
pub type FrameCallback<'a> = dyn FnMut(u32, &[Vec4]) + 'a;

/// One rendered frame, as the sequence renderers hand it to their callback.
#[derive(Clone, Copy, Debug)]
pub struct FrameView<'a> {
    /// Frame index `t`, from 0.
    pub index: u32,
    /// Colour, `width * height` linear RGB (`w` = 1), row-major.
    pub color: &'a [Vec4],
    /// The frame's G-buffer (`width * height`), when requested.
    pub gbuffer: Option<&'a [GBufferGpu]>,
}

/// What a sequence render does besides tracing and permuting.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SequenceOptions {
    /// Compute each frame's G-buffer and hand it to the frame callback.
    pub gbuffer: bool,
    /// Move the seeds along each frame's backward motion vectors before it
    /// is traced (`sampler_core::reproject_frame`, with disoccluded pixels
    /// from [`crate::motion::reprojection_motion`]; on the GPU the same
    /// code in `SeedReprojector`).
    /// Ignored in [`PermuteMode::White`] (fresh seeds every frame).
    pub reproject: bool,
    /// With [`Self::reproject`]: pixels whose surface moved less than this
    /// many pixels since the previous frame keep their seed instead of
    /// taking their surface's (`kernels::motion::seed_motion`, per pixel,
    /// the same on the GPU). Pixels per frame, finite and `>= 0`; 0 (the
    /// default here): every seed follows its surface. The command line's
    /// default is [`crate::method_choice::DEFAULT_REPROJECT_HOLD_BELOW`].
    pub reproject_hold_below: f32,
    /// With [`Self::reproject`]: every seed follows its surface, whatever
    /// [`Self::reproject_hold_below`] says, in a frame where at least this
    /// share of the pixels moves rigidly (`kernels::motion::moves_rigidly`:
    /// at least a pixel a frame, as its four neighbours within 0.05 px/frame
    /// or 2.5% of its speed; a camera pan); in such frames ZSobol's screen
    /// offset also advances by their mean motion (`kernels::pan_offset`),
    /// so that its points follow the picture. In `[0, 1]`; 0 (the default
    /// here): off. The command line's default is
    /// [`crate::method_choice::DEFAULT_REPROJECT_FOLLOW_SHARE`].
    pub reproject_follow_share: f32,
    /// With [`Self::reproject_follow_share`] above 0: in the frames that
    /// follow as a whole, ZSobol's points follow the frame's mean rigid
    /// motion (`kernels::pan_offset`: the trace reads ZSobol at the pixel
    /// plus the accumulated offset; `--sampler zsobol|zsobol-jitter` only).
    /// A history that follows a pan then sees each surface point's own
    /// ZSobol sequence, at a small cost to each raw frame (QUALITY.md,
    /// "ZSobol follows a pan"). `false` (the default here): ZSobol stays on
    /// the screen. The command line's default is on.
    pub pan_offset: bool,
    /// Feature-aware permutation (`sampler_core::permute_frame_features`
    /// with `FeatureThresholds::DEFAULT`): sort keys with the albedo divided
    /// out, blocks sorted in groups of one surface, retarget moves cut at
    /// edges, all from each frame's G-buffer. [`PermuteMode::Permute`] and
    /// [`PermuteMode::Temporal`] (`sampler_core::permute_frame_features_temporal`:
    /// the same against the temporal target) only, ignored by the other
    /// modes; the GPU runs the same code (`SeedPermuter::enable_features`).
    pub features: bool,
    /// The sort key of the feature-aware permutation
    /// ([`FeatureKey`]; demodulated by default). The GPU computes the
    /// demodulated key only and refuses the others.
    pub feature_key: FeatureKey,
}

impl SequenceOptions {
    /// Checks the options' ranges.
    ///
    /// # Errors
    /// [`RenderError::BadOption`] when [`Self::reproject_follow_share`] is
    /// outside `[0, 1]` or NaN, or [`Self::reproject_hold_below`] is NaN,
    /// infinite or negative.
    pub fn validate(&self) -> Result<(), RenderError> {
        let below = self.reproject_hold_below;
        if !(below.is_finite() && below >= 0.0) {
            return Err(RenderError::BadOption(format!(
                "reproject_hold_below must be finite and >= 0 pixels per frame, not {below}"
            )));
        }
        let share = self.reproject_follow_share;
        if !(0.0..=1.0).contains(&share) {
            return Err(RenderError::BadOption(format!(
                "reproject_follow_share must be in [0, 1], not {share}"
            )));
        }
        Ok(())
    }
}

/// What [`RenderJob::prepare`] hands the loops: layout, padded settings,
/// tile, tables, and the temporal target of [`PermuteMode::Temporal`].
type Prepared = (
    FrameLayout,
    TraceSettings,
    DitherTile<'static>,
    RetargetTables<'static>,
    Option<SliceTables<'static>>,
);

/// Receives every frame of a sequence render.
pub type SequenceCallback<'a> = dyn FnMut(&FrameView<'_>) + 'a;

/// Everything a render needs besides the scene.
#[derive(Clone, Copy, Debug)]
pub struct RenderJob {
    /// Frame size, samples per pixel, path depth, seed mode. Its
    /// `padded_width` is ignored: the loop sets it from the frame layout.
    pub settings: TraceSettings,
    /// Frames to render, `>= 1`.
    pub frames: u32,
    /// How seeds change between frames.
    pub mode: PermuteMode,
    /// Block side of the sorting pass, `2..=8`.
    pub block: u32,
    /// Dither tile.
    pub tile: TileChoice,
    /// Salt of the initial white-noise seeds.
    pub salt: u32,
}

/// What a render returns.
#[derive(Clone, Debug)]
pub struct RenderOutput {
    /// Colour of the last frame, `width * height`, row-major.
    pub last: Vec<Vec4>,
    /// Mean of all frames, `width * height`, row-major.
    pub mean: Vec<Vec4>,
    /// Which device rendered it.
    pub device: String,
}

/// Errors of the render loop.
#[derive(Debug)]
#[non_exhaustive]
pub enum RenderError {
    /// Bad frame geometry or permutation input.
    Layout(sampler_core::Error),
    /// Bad trace settings or scene.
    Trace(crate::Error),
    /// The GPU failed.
    Gpu(GpuError),
    /// `frames == 0`.
    NoFrames,
    /// A sequence option the GPU loop does not implement (e.g. a
    /// [`FeatureKey`] other than the demodulated one); names it.
    Unsupported(String),
    /// Settings that do not go together (e.g. [`PermuteMode::Hold`] with a
    /// sampler other than the spatiotemporal one); says which and why.
    Incompatible(String),
    /// A sequence option out of its range (e.g. a NaN or negative
    /// [`SequenceOptions::reproject_hold_below`]); names it.
    BadOption(String),
}

impl fmt::Display for RenderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RenderError::Layout(e) => write!(f, "{e}"),
            RenderError::Trace(e) => write!(f, "{e}"),
            RenderError::Gpu(e) => write!(f, "{e}"),
            RenderError::NoFrames => write!(f, "the number of frames must be at least 1"),
            RenderError::Unsupported(what) => write!(f, "not supported on the GPU: {what}"),
            RenderError::Incompatible(what) => write!(f, "incompatible settings: {what}"),
            RenderError::BadOption(what) => write!(f, "bad sequence option: {what}"),
        }
    }
}

impl std::error::Error for RenderError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            RenderError::Layout(e) => Some(e),
            RenderError::Trace(e) => Some(e),
            RenderError::Gpu(e) => Some(e),
            RenderError::NoFrames
            | RenderError::Unsupported(_)
            | RenderError::Incompatible(_)
            | RenderError::BadOption(_) => None,
        }
    }
}

impl From<sampler_core::Error> for RenderError {
    fn from(e: sampler_core::Error) -> Self {
        RenderError::Layout(e)
    }
}
impl From<crate::Error> for RenderError {
    fn from(e: crate::Error) -> Self {
        RenderError::Trace(e)
    }
}
impl From<GpuError> for RenderError {
    fn from(e: GpuError) -> Self {
        RenderError::Gpu(e)
    }
}

impl RenderJob {
    /// The frame layout of the seed buffer.
    ///
    /// # Errors
    /// [`RenderError::Layout`] for a zero size or a bad block.
    pub fn layout(&self) -> Result<FrameLayout, RenderError> {
        Ok(FrameLayout::new(
            self.settings.width,
            self.settings.height,
            self.block,
            self.tile.side(),
        )?)
    }

    /// Checks the job before any work: its layout, and the
    /// settings its mode needs. [`PermuteMode::Hold`] needs a sampler
    /// that draws every decision from per-pixel data a home can carry: the
    /// spatiotemporal one, or ZSobol without `SAMPLER_JITTER_ONLY`;
    /// [`PermuteMode::Temporal`] needs the
    /// [`TileChoice::TEMPORAL`] tile (the side of the slices of
    /// `sampler_core::defaults::temporal_target`, which it sorts against)
    /// and a sampler that reads the seeds (not the spatiotemporal one on
    /// every decision; its jitter alone, `SAMPLER_JITTER_ONLY`, is fine); it
    /// takes seed reprojection and the feature-aware permutation as
    /// [`PermuteMode::Permute`] does.
    ///
    /// # Errors
    /// [`RenderError::NoFrames`], [`RenderError::Layout`],
    /// [`RenderError::Incompatible`] naming the setting.
    pub fn validate(&self) -> Result<FrameLayout, RenderError> {
        if self.frames == 0 {
            return Err(RenderError::NoFrames);
        }
        let layout = self.layout()?;
        let spatiotemporal = self.settings.sampler & SAMPLER_KIND_MASK == SAMPLER_SPATIOTEMPORAL;
        let jitter_only = self.settings.sampler & SAMPLER_JITTER_ONLY != 0;
        let incompatible = |what: &str| Err(RenderError::Incompatible(what.into()));
        match self.mode {
            PermuteMode::Hold if !hold_takes(self.settings.sampler) => incompatible(
                "the hold mode keeps every pixel's numbers from frame to frame; only the spatiotemporal \
                 sampler and ZSobol on every decision, which advance their own sequence every frame, can \
                 use it",
            ),
            PermuteMode::Temporal if self.tile != TileChoice::TEMPORAL => incompatible(
                "the temporal mode sorts against the 64x64 slices of its default target: it needs the 64 \
                 tile",
            ),
            PermuteMode::Temporal if spatiotemporal && !jitter_only => incompatible(
                "the temporal mode permutes seeds, and the spatiotemporal sampler draws every number \
                 itself: use another sampler (or its jitter only)",
            ),
            _ => Ok(layout),
        }
    }

    /// Whether `options` make this job's permutation feature-aware: asked
    /// for, and a mode that permutes seeds ([`PermuteMode::Permute`],
    /// [`PermuteMode::Temporal`]; the other modes ignore it).
    fn feature_aware(&self, options: &SequenceOptions) -> bool {
        options.features && matches!(self.mode, PermuteMode::Permute | PermuteMode::Temporal)
    }

    /// Validates the job ([`validate`](Self::validate)) and returns its
    /// layout, trace settings (padded to the layout), tile and tables, and
    /// with [`PermuteMode::Temporal`] its target.
    fn prepare(&self) -> Result<Prepared, RenderError> {
        let layout = self.validate()?;
        let (tile, tables) = self.tile.load();
        let temporal = (self.mode == PermuteMode::Temporal).then(sampler_core::defaults::temporal_target);
        Ok((layout, self.settings_for(&layout), tile, tables, temporal))
    }

    /// The trace settings of this job on `layout`: padded to it, and with
    /// [`PermuteMode::Hold`] the sampler told that the seed buffer holds
    /// homes ([`SAMPLER_FOLLOW_HOMES`]) and the homes' streams advanced by
    /// frame ([`SEED_MODE_ADVANCE`]: a home is fixed, so the numbers the
    /// sampler leaves to the stream, ZSobol's Russian roulette, would
    /// otherwise repeat every frame; the spatiotemporal sampler reads none).
    fn settings_for(&self, layout: &FrameLayout) -> TraceSettings {
        let mut sampler = self.settings.sampler & !SAMPLER_FOLLOW_HOMES;
        let mut seed_mode = self.settings.seed_mode;
        if self.mode == PermuteMode::Hold {
            sampler |= SAMPLER_FOLLOW_HOMES;
            seed_mode = SEED_MODE_ADVANCE;
        }
        TraceSettings {
            padded_width: layout.padded_width(),
            sampler,
            seed_mode,
            ..self.settings
        }
    }
}

/// Whether [`PermuteMode::Hold`] takes `sampler` ([`TraceSettings::sampler`]
/// flags): one that reads its per-pixel data at a home
/// (`kernels::abi::sampler_reads_homes`) and draws every decision from it
/// (not [`SAMPLER_JITTER_ONLY`]).
pub fn hold_takes(sampler: u32) -> bool {
    kernels::abi::sampler_reads_homes(sampler) && sampler & SAMPLER_JITTER_ONLY == 0
}

/// Renders `job` on the CPU (rayon over rows) with the kernels' own
/// functions. `on_frame(t, colour)` sees every frame.
///
/// # Errors
/// [`RenderError`] for bad settings; nothing is rendered then.
pub fn render_cpu(
    scene: &SceneGpu,
    job: &RenderJob,
    mut on_frame: impl FnMut(u32, &[Vec4]),
) -> Result<RenderOutput, RenderError> {
    let mut sequence = SceneSequence::still(scene, job.settings.height);
    render_sequence_cpu(
        &mut sequence,
        job,
        SequenceOptions::default(),
        |f: &FrameView<'_>| on_frame(f.index, f.color),
    )
}

/// Renders `job` on the CPU over a [`SceneSequence`] (moving cameras and
/// objects), from its current frame on (normally frame 0). With
/// `options.gbuffer`, each frame's G-buffer is computed (before the trace,
/// as the GPU does) and handed to `on_frame` with the colour. With
/// `options.reproject`, frame `t + 1`'s order is: G-buffer (motion), seeds
/// reprojected from frame `t`'s screen, trace, sort + retarget.
///
/// # Errors
/// [`RenderError`] for bad settings or a scene that cannot be posed;
/// nothing is rendered after the error.
pub fn render_sequence_cpu(
    sequence: &mut SceneSequence<'_>,
    job: &RenderJob,
    options: SequenceOptions,
    mut on_frame: impl FnMut(&FrameView<'_>),
) -> Result<RenderOutput, RenderError> {
    options.validate()?;
    let (layout, settings, tile, tables, temporal) = job.prepare()?;
    let n = layout.pixel_count();
    let reproject = options.reproject && job.mode != PermuteMode::White;
    let features = job.feature_aware(&options);
    let gbuffer = options.gbuffer || reproject || features;
    let mut previous_vis = vec![UVec2::ZERO; if reproject { n } else { 0 }];
    let feature_scratch = if features { layout.seed_count() } else { 0 };
    let (mut sorted, mut sources) = (vec![0u32; feature_scratch], vec![0u32; feature_scratch]);
    let (w, h) = if features {
        (layout.width(), layout.height())
    } else {
        (0, 0)
    };
    let mut keys = FeatureKeys::new(options.feature_key, w, h, FeatureThresholds::DEFAULT);
    let mut claims = vec![0u32; if reproject { layout.seed_count() } else { 0 }];
    let hold = job.mode == PermuteMode::Hold;
    let mut seeds = cpu::white_seeds(layout.padded_width(), layout.padded_height(), job.salt);
    if hold {
        write_initial_homes(layout.padded_width(), layout.padded_height(), &mut seeds);
    }
    let mut next = vec![0u32; seeds.len()];
    let mut color = vec![Vec4::ZERO; n];
    let mut mean = vec![Vec4::ZERO; n];
    let mut gbuf = vec![GBufferGpu::default(); if gbuffer { n } else { 0 }];
    // ZSobol's screen offset in frames that follow as a whole
    // (`kernels::pan_offset`), fixed point.
    let mut pan_offset = [0u32; 2];
    for t in 0..job.frames {
        if t > 0 {
            sequence.advance()?;
        }
        let scene = sequence.scene();
        let mut params = scene.trace_params(&settings, t)?;
        if gbuffer {
            cpu::gbuffer_frame(scene, &params, &mut gbuf)?;
        }
        // The frame-wide rule and the pan offset from one count of the rigid
        // pixels, as the GPU's rigid-count and motion passes, every frame
        // (frame 0 moves nothing).
        let share = options.reproject_follow_share;
        let mut follows_all = false;
        if reproject && share > 0.0 {
            let (w, h) = (layout.width(), layout.height());
            let words = frame_motion_words(&gbuf, w, h);
            follows_all = frame_follows(words[FRAME_RIGID], w * h, share);
            pan_offset = advance_offset(pan_offset, &words, w * h, share);
        }
        if options.pan_offset {
            params.sampler_offset_x = pan_offset[0];
            params.sampler_offset_y = pan_offset[1];
        }
        if reproject && t > 0 {
            let (w, h, below) = (layout.width(), layout.height(), options.reproject_hold_below);
            let motion = seed_motion_with(&gbuf, &previous_vis, w, h, below, follows_all);
            // Seeds, or with the hold mode the homes: moved alike.
            sampler_core::reproject_frame(&layout, &motion, &seeds, &mut claims, &mut next)?;
            std::mem::swap(&mut seeds, &mut next);
        }
        if reproject {
            write_visibility(&gbuf, &mut previous_vis);
        }
        cpu::render_frame(scene, &params, &seeds, &mut color)?;
        cpu::accumulate_frame(&params, &color, &mut mean)?;
        on_frame(&FrameView {
            index: t,
            color: &color,
            gbuffer: options.gbuffer.then_some(&gbuf[..]),
        });
        match job.mode {
            PermuteMode::Hold => {}
            PermuteMode::White => {
                seeds = cpu::white_seeds(
                    layout.padded_width(),
                    layout.padded_height(),
                    sampler_core::frame_salt(job.salt, t + 1),
                )
            }
            PermuteMode::Sort => {
                sampler_core::sort_frame(&layout, t, &color, &tile, &seeds, &mut next)?;
                std::mem::swap(&mut seeds, &mut next);
            }
            PermuteMode::Permute | PermuteMode::Temporal if features => {
                keys.update(&color, &gbuf);
                let (k, f, th) = (keys.keys(), keys.features(), &FeatureThresholds::DEFAULT);
                let (s, src) = (&mut sorted, &mut sources);
                match &temporal {
                    Some(target) => sampler_core::permute_frame_features_temporal(
                        &layout, t, k, f, th, target, &seeds, s, src, &mut next,
                    )?,
                    None => sampler_core::permute_frame_features(
                        &layout, t, k, f, th, &tile, &tables, &seeds, s, src, &mut next,
                    )?,
                }
                std::mem::swap(&mut seeds, &mut next);
            }
            PermuteMode::Permute => {
                sampler_core::permute_frame(&layout, t, &color, &tile, &tables, &seeds, &mut next)?;
                std::mem::swap(&mut seeds, &mut next);
            }
            PermuteMode::Temporal => {
                let target = temporal.as_ref().expect("prepared for the temporal mode");
                sampler_core::permute_frame_temporal(&layout, t, &color, target, &seeds, &mut next)?;
                std::mem::swap(&mut seeds, &mut next);
            }
        }
    }
    Ok(RenderOutput {
        last: color,
        mean,
        device: "CPU".into(),
    })
}

/// Renders `job` on `gpu` with no read-back between frames (except when
/// `on_frame` is given: then every frame's colour is read back for it).
/// `on_submit(t)` is called once frame `t`'s work is submitted.
///
/// # Errors
/// [`RenderError`] for bad settings or a GPU failure.
pub fn render_gpu(
    gpu: &Gpu,
    scene: &SceneGpu,
    job: &RenderJob,
    on_submit: impl FnMut(u32),
    mut on_frame: Option<&mut FrameCallback<'_>>,
) -> Result<RenderOutput, RenderError> {
    let mut sequence = SceneSequence::still(scene, job.settings.height);
    match on_frame.as_mut() {
        Some(cb) => {
            let mut adapter = |f: &FrameView<'_>| cb(f.index, f.color);
            render_sequence_gpu(
                gpu,
                &mut sequence,
                job,
                SequenceOptions::default(),
                on_submit,
                Some(&mut adapter),
            )
        }
        None => render_sequence_gpu(
            gpu,
            &mut sequence,
            job,
            SequenceOptions::default(),
            on_submit,
            None,
        ),
    }
}

/// Renders `job` on `gpu` over a [`SceneSequence`]: per frame, the cameras
/// (and, when objects move, the scene's buffers) are updated, then the
/// G-buffer pass (with `options.gbuffer` or `options.reproject`), the
/// motion and seed-reprojection passes (with `options.reproject`, from
/// frame 1), the trace, the accumulation and the seed passes are
/// submitted, with no read-back unless `on_frame` is given (then every
/// frame's colour, and G-buffer with `options.gbuffer`, is read back for
/// it). The order and the seeds equal [`render_sequence_cpu`]'s.
/// The G-buffer stays on the device in [`Tracer::gbuffer`] for passes that
/// read it.
///
/// # Errors
/// [`RenderError`] for bad settings, a scene that cannot be posed, or a GPU
/// failure.
pub fn render_sequence_gpu(
    gpu: &Gpu,
    sequence: &mut SceneSequence<'_>,
    job: &RenderJob,
    options: SequenceOptions,
    mut on_submit: impl FnMut(u32),
    mut on_frame: Option<&mut SequenceCallback<'_>>,
) -> Result<RenderOutput, RenderError> {
    options.validate()?;
    let (layout, settings, tile, tables, temporal) = job.prepare()?;
    let reproject = options.reproject && job.mode != PermuteMode::White;
    let features = job.feature_aware(&options);
    if features && options.feature_key != FeatureKey::Demodulated {
        return Err(RenderError::Unsupported(format!(
            "the {} feature key (the GPU's feature pass computes the demodulated key)",
            options.feature_key.name()
        )));
    }
    let gbuffer = options.gbuffer || reproject || features;
    let params0 = sequence.scene().trace_params(&settings, 0)?;
    let trace_pipelines = TracePipelines::new(gpu)?;
    let permute_pipelines = PermutePipelines::new(gpu)?;
    // The permuter owns the seed buffer and reads the tracer's colour.
    let color = Tracer::color_buffer(gpu, layout.width(), layout.height());
    let mut permuter = SeedPermuter::new(gpu, &permute_pipelines, layout, &tile, &tables, &color)?;
    if features {
        permuter.enable_features(gpu, &permute_pipelines, &FeatureThresholds::DEFAULT);
    }
    if let Some(target) = &temporal {
        permuter.enable_temporal(gpu, &permute_pipelines, target)?;
    }
    let mut tracer = Tracer::new(
        gpu,
        &trace_pipelines,
        sequence.scene(),
        &params0,
        &permuter.seeds,
        color,
    )?;

    if let Some(f) = permuter.features() {
        tracer.enable_features(gpu, &trace_pipelines, f, &permuter.intensity);
    }
    let hold = job.mode == PermuteMode::Hold;
    let reprojection = if reproject {
        let pipelines = ReprojectPipelines::new(gpu)?;
        let reprojector = SeedReprojector::new(gpu, &pipelines, layout, &permuter.seeds)?;
        tracer.enable_motion(gpu, &trace_pipelines, &reprojector.motion);
        tracer.set_pan_offset(options.pan_offset);
        Some((pipelines, reprojector))
    } else {
        None
    };
    if hold {
        // The hold mode's homes, written once (moved by the reprojection).
        let mut homes = vec![0u32; layout.seed_count()];
        write_initial_homes(layout.padded_width(), layout.padded_height(), &mut homes);
        gpu.queue
            .write_buffer(&permuter.seeds, 0, bytemuck::cast_slice(&homes));
    } else {
        permuter.set_frame(gpu, job.salt);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        permuter.encode_seed_init(&mut encoder, &permute_pipelines);
        gpu.queue.submit([encoder.finish()]);
    }

    for t in 0..job.frames {
        if t > 0 && sequence.advance()? {
            tracer.update_scene(gpu, &trace_pipelines, sequence.scene())?;
        }
        let mut params = sequence.scene().trace_params(&settings, t)?;
        params.seed_hold_below = options.reproject_hold_below;
        params.seed_follow_share = options.reproject_follow_share;
        tracer.set_params(gpu, &params);
        let salt_or_frame = if job.mode == PermuteMode::White {
            sampler_core::frame_salt(job.salt, t + 1)
        } else {
            t
        };
        permuter.set_frame(gpu, salt_or_frame);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        if gbuffer {
            tracer.encode_gbuffer(&mut encoder, &trace_pipelines, None);
        }
        if let Some((pipelines, reprojector)) = &reprojection {
            tracer.encode_motion(&mut encoder, &trace_pipelines, None);
            if t > 0 {
                reprojector.encode(&mut encoder, pipelines, None);
            }
        }
        tracer.encode_trace(&mut encoder, &trace_pipelines, None);
        tracer.encode_accumulate(&mut encoder, &trace_pipelines);
        if features {
            tracer.encode_features(&mut encoder, &trace_pipelines, None);
        } else if job.mode != PermuteMode::White && !hold {
            permuter.encode_intensity(&mut encoder, &permute_pipelines);
        }
        permuter.encode_step(&mut encoder, &permute_pipelines, t, job.mode, None);
        gpu.queue.submit([encoder.finish()]);
        on_submit(t);
        if let Some(f) = on_frame.as_mut() {
            let color = tracer.read_color(gpu)?;
            let gbuf = if options.gbuffer {
                tracer.read_gbuffer(gpu)?
            } else {
                Vec::new()
            };
            f(&FrameView {
                index: t,
                color: &color,
                gbuffer: options.gbuffer.then_some(&gbuf[..]),
            });
        }
    }
    let last = tracer.read_color(gpu)?;
    let mean = tracer.read_accum(gpu)?;
    Ok(RenderOutput {
        last,
        mean,
        device: gpu.describe(),
    })
}

#[cfg(test)]
mod tests;
