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
//! # The blue-noise-dither baseline
//!
//! [`Method::Dither`]: fresh white-noise seeds every frame (as [`Method::White`]) and
//! `kernels::abi::SEED_MODE_BLUE_NOISE_DITHER`: the first vertex's BSDF direction is
//! drawn from the default 128x128x64 spatiotemporal blue-noise mask
//! (`sampler_core::defaults::stbn_128`), `(mask(x, y, t mod 64), mask(x + 64, y + 64,
//! t mod 64))`, through `kernels::trace::trace_pixel_dithered`. CPU only: the GPU
//! entry point has no mask binding.

use crate::{low_frequency_ratio, radial_power, GaussianBlur, Grid, SpectrumAnalyzer};
use anyhow::{bail, ensure, Context, Result};
use glam::{UVec2, Vec2, Vec3, Vec4};
use gpu_tracer::cornell::{cornell_box, GREEN, RED};
use gpu_tracer::scene::{SceneGpu, TraceSettings};
use gpu_tracer::{cpu, PermuteMode, RenderJob, TileChoice};
use kernels::abi::{TraceParams, SEED_MODE_BLUE_NOISE_DITHER, SEED_MODE_FIXED};
use rayon::prelude::*;
use sampler_core::{
    luma, retarget_pixel_at_offset, sort_block_at_offset, walk_offset, DitherTile, FrameLayout, Intensity,
    RetargetTable,
};
use std::path::{Path, PathBuf};

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
}

impl Method {
    /// Every method, white first.
    pub const ALL: [Method; 8] = [
        Method::White,
        Method::Sort,
        Method::Permute,
        Method::PermuteJitter,
        Method::FixedStep,
        Method::Dither,
        Method::ScreenSobol,
        Method::ZSobol,
    ];

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

    fn settings(&self) -> TraceSettings {
        let mut s = TraceSettings::new(self.size, self.size);
        s.spp = self.spp;
        s.max_depth = self.max_depth;
        s.seed_mode = self.seed_mode;
        s
    }

    fn layout(&self) -> Result<FrameLayout> {
        Ok(FrameLayout::new(
            self.size,
            self.size,
            self.block,
            self.tile.side(),
        )?)
    }
}

/// Which surface an inset must show.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Surface {
    /// The back wall (`z = 559.2`).
    BackWall,
    /// The floor (`y = 0`).
    Floor,
    /// The red (left) wall.
    RedWall,
    /// The green (right) wall.
    GreenWall,
}

/// A square region of the image on one flat surface.
#[derive(Clone, Debug, PartialEq)]
pub struct Inset {
    /// Name used in reports.
    pub name: &'static str,
    /// Surface every pixel of the inset sees.
    pub surface: Surface,
    /// Left column.
    pub x0: u32,
    /// Top row.
    pub y0: u32,
    /// Side in pixels.
    pub side: u32,
    /// Largest relative central-difference gradient of the reference luma inside the
    /// inset, `max |grad L| / mean L` per pixel (set by [`Study::new`]).
    pub max_gradient: f64,
}

/// The insets for an image of `size` pixels: (name, surface, x0, y0, side) as
/// fractions of the size, read off a map of the surfaces the centre rays hit (the
/// back wall right of the tall block, both side walls at mid height);
/// [`check_inset`] verifies them at every size. [`Surface::Floor`] is kept for callers
/// that place their own insets.
fn inset_layout(size: u32) -> Vec<Inset> {
    let f = |v: f64| (v * size as f64).round() as u32;
    let big = (size * 3 / 16).max(4);
    let small = (size / 8).max(4);
    let mk = |name, surface, x: f64, y: f64, side| Inset {
        name,
        surface,
        x0: f(x),
        y0: f(y),
        side,
        max_gradient: f64::NAN,
    };
    vec![
        mk("back wall", Surface::BackWall, 0.54, 0.25, big),
        mk("red wall", Surface::RedWall, 0.05, 0.4, small),
        mk("green wall", Surface::GreenWall, 0.8, 0.4, small),
    ]
}

/// The reference image: two independent halves.
#[derive(Clone, Debug)]
pub struct Reference {
    /// Side in pixels.
    pub size: u32,
    /// Total samples per pixel.
    pub spp: u32,
    /// Mean of both halves, linear RGB, row-major.
    pub rgb: Vec<Vec3>,
    /// Luma of [`Self::rgb`].
    pub luma: Vec<f32>,
    /// Estimated variance of the reference's luma per pixel, averaged over the image:
    /// `mean((A - B)^2) / 4`.
    pub noise_var: f64,
}

const CACHE_MAGIC: &[u8; 8] = b"BNREF01\0";

impl Reference {
    /// Renders (or loads from `cache_dir`) the reference for `config`. The file name
    /// holds every setting the image depends on.
    ///
    /// # Errors
    /// Rendering errors; cache I/O errors are ignored (the image is then rendered).
    pub fn get(
        scene: &SceneGpu,
        config: &StudyConfig,
        cache_dir: Option<&Path>,
        mut progress: impl FnMut(u32, u32),
    ) -> Result<Reference> {
        ensure!(
            config.ref_spp >= 2,
            "the reference needs at least 2 samples per pixel"
        );
        let half_spp = config.ref_spp / 2;
        let name = format!(
            "cornell-ref-{s}x{s}-spp{r}-depth{d}-rr{rr}.bin",
            s = config.size,
            r = 2 * half_spp,
            d = config.max_depth,
            rr = TraceSettings::new(1, 1).rr_depth
        );
        let path = cache_dir.map(|d| d.join(&name));
        let n = (config.size * config.size) as usize;
        if let Some(p) = &path {
            if let Some((a, b)) = read_cache(p, n) {
                return Ok(Reference::from_halves(config.size, 2 * half_spp, &a, &b));
            }
        }
        let pass_spp = half_spp.min(64);
        let passes = half_spp.div_ceil(pass_spp);
        let mut settings = TraceSettings::new(config.size, config.size);
        settings.max_depth = config.max_depth;
        settings.seed_mode = SEED_MODE_FIXED;
        let mut halves = [vec![Vec3::ZERO; n], vec![Vec3::ZERO; n]];
        let mut color = vec![Vec4::ZERO; n];
        let total = 2 * passes;
        let mut done = 0;
        for (h, half) in halves.iter_mut().enumerate() {
            let mut left = half_spp;
            for pass in 0..passes {
                settings.spp = pass_spp.min(left);
                left -= settings.spp;
                let params = scene.trace_params(&settings, 0)?;
                // Salts far from the study's, one per pass and half.
                let salt = 0x5EED_0000 ^ ((h as u32) << 12) ^ pass;
                let seeds = cpu::white_seeds(config.size, config.size, salt);
                cpu::render_frame(scene, &params, &seeds, &mut color)?;
                let w = settings.spp as f32 / half_spp as f32;
                for (acc, c) in half.iter_mut().zip(&color) {
                    *acc += c.truncate() * w;
                }
                done += 1;
                progress(done, total);
            }
        }
        if let Some(p) = &path {
            // Best effort: a failed write only costs a re-render next time.
            let _ = write_cache(p, &halves[0], &halves[1]);
        }
        Ok(Reference::from_halves(
            config.size,
            2 * half_spp,
            &halves[0],
            &halves[1],
        ))
    }

    fn from_halves(size: u32, spp: u32, a: &[Vec3], b: &[Vec3]) -> Reference {
        let rgb: Vec<Vec3> = a.iter().zip(b).map(|(x, y)| (*x + *y) * 0.5).collect();
        let luma_image: Vec<f32> = rgb.iter().map(|c| luma(*c)).collect();
        let noise_var = a
            .iter()
            .zip(b)
            .map(|(x, y)| {
                let d = (luma(*x) - luma(*y)) as f64;
                d * d / 4.0
            })
            .sum::<f64>()
            / a.len() as f64;
        Reference {
            size,
            spp,
            rgb,
            luma: luma_image,
            noise_var,
        }
    }
}

fn read_cache(path: &Path, n: usize) -> Option<(Vec<Vec3>, Vec<Vec3>)> {
    let bytes = std::fs::read(path).ok()?;
    if bytes.len() != 8 + 2 * n * 12 || &bytes[..8] != CACHE_MAGIC {
        return None;
    }
    let floats: Vec<f32> = bytes[8..]
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    let v: Vec<Vec3> = floats.chunks_exact(3).map(Vec3::from_slice).collect();
    let (a, b) = v.split_at(n);
    Some((a.to_vec(), b.to_vec()))
}

fn write_cache(path: &Path, a: &[Vec3], b: &[Vec3]) -> std::io::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let mut bytes = Vec::with_capacity(8 + (a.len() + b.len()) * 12);
    bytes.extend_from_slice(CACHE_MAGIC);
    for c in a.iter().chain(b) {
        for v in c.to_array() {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    let tmp = path.with_extension(format!("tmp{}", std::process::id()));
    std::fs::write(&tmp, bytes)?;
    std::fs::rename(&tmp, path)
}

/// The default reference cache: `target/quality-cache` of this workspace.
pub fn default_cache_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/quality-cache")
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
    /// The runs, in the order they were requested.
    pub runs: Vec<MethodRun>,
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
        Ok(Study {
            config,
            scene,
            reference,
            insets,
        })
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
            runs,
        })
    }

    fn run_method(&self, method: Method, mut progress: impl FnMut(u32)) -> Result<MethodRun> {
        let mut meter = Meter::new(self, method)?;
        let mut on_frame = |t: u32, color: &[Vec4]| {
            meter.frame(t, color);
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
        meter.finish()
    }
}

fn check_inset(scene: &SceneGpu, params: &TraceParams, inset: &Inset) -> Result<()> {
    ensure!(
        inset.x0 + inset.side <= params.width && inset.y0 + inset.side <= params.height,
        "inset {} lies outside the image",
        inset.name
    );
    for y in inset.y0..inset.y0 + inset.side {
        for x in inset.x0..inset.x0 + inset.side {
            let ray = kernels::camera::primary_ray(params, x, y, Vec2::splat(0.5));
            let hit = kernels::bvh::closest_hit(&scene.nodes, &scene.triangles, &ray, 0.0, f32::MAX)
                .with_context(|| format!("inset {}: pixel ({x}, {y}) sees nothing", inset.name))?;
            let tri = scene.triangles[hit.triangle as usize];
            let p = ray.origin + ray.dir * hit.t;
            let material = tri.v0.w as u32;
            let ok = match inset.surface {
                Surface::BackWall => p.z >= 559.0,
                Surface::Floor => p.y <= 0.5,
                Surface::RedWall => material == RED,
                Surface::GreenWall => material == GREEN,
            };
            if !ok {
                bail!(
                    "inset {} ({}, {}, side {}): pixel ({x}, {y}) sees {p} (material {material}), not the {:?}",
                    inset.name,
                    inset.x0,
                    inset.y0,
                    inset.side,
                    inset.surface
                );
            }
        }
    }
    Ok(())
}

fn max_gradient(luma: &[f32], size: u32, inset: &Inset) -> f64 {
    let s = size as usize;
    let at = |x: u32, y: u32| luma[y as usize * s + x as usize] as f64;
    let mut worst: f64 = 0.0;
    for y in inset.y0 + 1..inset.y0 + inset.side - 1 {
        for x in inset.x0 + 1..inset.x0 + inset.side - 1 {
            let gx = (at(x + 1, y) - at(x - 1, y)) / 2.0;
            let gy = (at(x, y + 1) - at(x, y - 1)) / 2.0;
            worst = worst.max(gx.hypot(gy) / at(x, y).max(1e-6));
        }
    }
    worst
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
        self.run.blur1.push(self.blur1.apply(&grid).rms());
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
        for ((s, c), r) in self.sum.iter_mut().zip(color).zip(&reference.luma) {
            *s += c.intensity() as f64;
            let d = *s / n - *r as f64;
            mse += d * d;
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

/// The inset's part of a `size x size` row-major image.
pub fn crop(image: &[f32], size: usize, inset: &Inset) -> Grid {
    let s = inset.side as usize;
    Grid::from_fn(s, s, |x, y| {
        image[(inset.y0 as usize + y) * size + inset.x0 as usize + x]
    })
    .expect("inset size")
}

/// Offset sequence of the dither tile.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Walk {
    /// The aperiodic R2 walk (`sampler_core::walk_offset`), table per step.
    R2,
    /// `o_t = t * base_step mod W`, always table 0.
    FixedStep,
}

impl Walk {
    /// Offset of frame `t` and the index of the retarget table for the step after it.
    pub fn offset_and_table(self, t: u32, tile_log2: u32) -> (UVec2, u32) {
        match self {
            Walk::R2 => (walk_offset(t, tile_log2), sampler_core::step_index(t, tile_log2)),
            Walk::FixedStep => {
                let mask = (1u32 << tile_log2) - 1;
                let step = sampler_core::walk::base_step(tile_log2);
                (
                    UVec2::new(t.wrapping_mul(step.x) & mask, t.wrapping_mul(step.y) & mask),
                    0,
                )
            }
        }
    }
}

/// One permutation step with an explicit tile offset: sorting pass against
/// `tile[(p + offset) mod W]` in every block, then the retargeting scatter with `table`
/// read at `(p + offset) mod W`. Same conventions and tie-breaking as
/// `sampler_core::permute_frame`: `sampler_core::sort_block_at_offset` per block,
/// then `sampler_core::retarget_pixel_at_offset` per seed.
///
/// # Panics
/// If a buffer does not match `layout`.
pub fn permute_with_offset<T: Intensity>(
    layout: &FrameLayout,
    offset: UVec2,
    intensities: &[T],
    tile: &DitherTile<'_>,
    table: RetargetTable<'_>,
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) {
    let p = layout.params(0);
    assert_eq!(seeds_in.len(), layout.seed_count());
    assert_eq!(seeds_out.len(), layout.seed_count());
    assert_eq!(intensities.len(), layout.pixel_count());
    let mut sorted = seeds_in.to_vec();
    for by in 0..p.blocks_y() {
        for bx in 0..p.blocks_x() {
            sort_block_at_offset(
                &p,
                offset,
                bx,
                by,
                intensities,
                tile.values(),
                seeds_in,
                &mut sorted,
            );
        }
    }
    for i in 0..p.seed_count() {
        retarget_pixel_at_offset(&p, offset, i, table.packed(), &sorted, seeds_out);
    }
}

/// Renders `study.config.frames` frames permuting with `walk` (CPU), calling
/// `on_frame(t, colour)` for each.
///
/// # Errors
/// Rendering errors.
pub fn render_walk(study: &Study, walk: Walk, on_frame: &mut impl FnMut(u32, &[Vec4])) -> Result<()> {
    let c = &study.config;
    let layout = c.layout()?;
    let (tile, tables) = c.tile.load();
    let mut settings = c.settings();
    settings.padded_width = layout.padded_width();
    let mut seeds = cpu::white_seeds(layout.padded_width(), layout.padded_height(), c.salt);
    let mut next = vec![0u32; seeds.len()];
    let mut color = vec![Vec4::ZERO; layout.pixel_count()];
    for t in 0..c.frames {
        let params = study.scene.trace_params(&settings, t)?;
        cpu::render_frame(&study.scene, &params, &seeds, &mut color)?;
        on_frame(t, &color);
        let (offset, table) = walk.offset_and_table(t, tile.tile_log2());
        permute_with_offset(
            &layout,
            offset,
            &color,
            &tile,
            tables.table(table),
            &seeds,
            &mut next,
        );
        std::mem::swap(&mut seeds, &mut next);
    }
    Ok(())
}

/// The blue-noise-dither baseline (module docs), CPU only.
///
/// # Errors
/// Rendering errors.
pub fn render_dither(study: &Study, on_frame: &mut impl FnMut(u32, &[Vec4])) -> Result<()> {
    let c = &study.config;
    let mask = sampler_core::defaults::stbn_128();
    let mut settings = c.settings();
    settings.seed_mode = SEED_MODE_FIXED;
    let layout = c.layout()?;
    settings.padded_width = layout.padded_width();
    let (w, pw) = (c.size, layout.padded_width());
    let mut color = vec![Vec4::ZERO; layout.pixel_count()];
    let scene = &study.scene;
    for t in 0..c.frames {
        // The host's settings only accept the modes the GPU implements; the dither mode
        // is set on the kernel parameters directly.
        let params = TraceParams {
            seed_mode: SEED_MODE_BLUE_NOISE_DITHER,
            ..scene.trace_params(&settings, t)?
        };
        // The same seeds as the white run's frame t (`render_cpu` uses salt + t).
        let seeds = cpu::white_seeds(pw, layout.padded_height(), c.salt.wrapping_add(t));
        let z = t % mask.depth();
        color.par_chunks_mut(w as usize).enumerate().for_each(|(y, row)| {
            let y = y as u32;
            for (x, out) in row.iter_mut().enumerate() {
                let x = x as u32;
                let dither = Vec2::new(mask.value(x, y, z), mask.value(x + 64, y + 64, z));
                *out = kernels::trace::trace_pixel_dithered(
                    &params,
                    UVec2::new(x, y),
                    seeds[(y * pw + x) as usize],
                    dither,
                    &scene.nodes,
                    &scene.triangles,
                    &scene.materials,
                    &scene.emitters,
                    &scene.attrs,
                    &scene.images,
                );
            }
        });
        on_frame(t, &color);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_step_repeats_every_16_frames_and_r2_does_not() {
        let fixed: Vec<UVec2> = (0..40)
            .map(|t| Walk::FixedStep.offset_and_table(t, 6).0)
            .collect();
        assert_eq!(fixed[1], UVec2::new(48, 36));
        assert_eq!(fixed[16], UVec2::ZERO);
        assert_eq!(fixed[17], fixed[1]);
        let distinct: std::collections::HashSet<_> = fixed.iter().collect();
        assert_eq!(distinct.len(), 16);
        let r2: std::collections::HashSet<_> = (0..64).map(|t| Walk::R2.offset_and_table(t, 6).0).collect();
        assert!(r2.len() > 60, "{}", r2.len());
    }

    #[test]
    fn permute_with_r2_offsets_equals_permute_frame() {
        let layout = FrameLayout::new(70, 45, 4, 64).unwrap();
        let (tile, tables) = TileChoice::Tile64.load();
        let image: Vec<f32> = (0..layout.pixel_count())
            .map(|i| sampler_core::random_f32(i as u32, 99))
            .collect();
        let seeds: Vec<u32> = (0..layout.seed_count() as u32).map(|i| i * 7 + 3).collect();
        for t in [0u32, 1, 5, 17, 63] {
            let mut want = vec![0; seeds.len()];
            sampler_core::permute_frame(&layout, t, &image, &tile, &tables, &seeds, &mut want).unwrap();
            let (o, k) = Walk::R2.offset_and_table(t, 6);
            let mut got = vec![0; seeds.len()];
            permute_with_offset(&layout, o, &image, &tile, tables.table(k), &seeds, &mut got);
            assert_eq!(got, want, "frame {t}");
        }
    }
}
