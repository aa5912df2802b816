//! The command line: `gpu-tracer render` and its options, parsed by clap,
//! with the parsers of the values clap does not know (`x,y,z`, `--env`,
//! `--tile`).

use clap::{Parser, Subcommand, ValueEnum};
use gpu_tracer::filter::FilterChain;
use gpu_tracer::{PermuteMode, TileChoice};
use kernels::abi::{
    MAX_DEPTH_LIMIT, SAMPLER_JITTER_ONLY, SAMPLER_SCREEN_SOBOL, SAMPLER_SEEDS, SAMPLER_ZSOBOL,
};
use std::path::PathBuf;

#[derive(Parser, Debug)]
#[command(
    name = "gpu-tracer",
    version,
    about = "Path tracer with blue-noise error through seed permutation"
)]
pub(crate) struct Cli {
    #[command(subcommand)]
    pub(crate) command: Command,
}

#[derive(Subcommand, Debug)]
pub(crate) enum Command {
    /// Render frames and write the last frame and the accumulated mean.
    Render(RenderArgs),
}

#[derive(clap::Args, Debug)]
pub(crate) struct RenderArgs {
    /// `cornell` for the built-in Cornell box, `cornell-glossy` for the same
    /// room with three GGX spheres (roughness 0.1, 0.3, 0.6), `sun-sky` for
    /// objects on open ground under a sun with a disk and a sky (the sky is
    /// its default `--env`), the path of a glTF 2.0 file (`.gltf` or `.glb`:
    /// meshes, metallic-roughness materials, textures, cameras, node
    /// animation, KHR_lights_punctual lights), or of an OBJ file
    /// (materials from its MTL: Kd diffuse, Ke emission, Ks/Ns specular).
    #[arg(long, default_value = "cornell")]
    pub(crate) scene: String,
    /// glTF: which camera (0-based, in scene order); default the first.
    #[arg(long)]
    pub(crate) camera_index: Option<usize>,
    /// Camera position `x,y,z` (world units); replaces the scene's camera
    /// (needs `--camera-at`).
    #[arg(long, value_parser = parse_vec3, requires = "camera_at")]
    pub(crate) camera_from: Option<glam::Vec3>,
    /// Point the camera looks at, `x,y,z` (needs `--camera-from`).
    #[arg(long, value_parser = parse_vec3, requires = "camera_from")]
    pub(crate) camera_at: Option<glam::Vec3>,
    /// Vertical field of view in degrees for `--camera-from/--camera-at`.
    #[arg(long, default_value_t = 40.0)]
    pub(crate) fov: f32,
    /// Environment seen by rays that leave the scene: `r,g,b`, a constant sky
    /// of that linear radiance (each finite, >= 0), or an equirectangular
    /// environment map (`FILE.exr` or `FILE.hdr`, linear radiance, +Y up,
    /// the image's centre looking down -Z), importance-sampled.
    #[arg(long, value_parser = parse_environment, allow_hyphen_values = true)]
    pub(crate) env: Option<EnvArg>,
    /// Rotation of the `--env` map about +Y in degrees (a positive angle
    /// turns its content to the viewer's right).
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) env_rotation: Option<f32>,
    /// Camera motion on top of the scene's: `orbit` (about the looked-at
    /// point, `--camera-speed` in degrees per frame), `dolly` (forward,
    /// scene units per frame) or `pan` (right, pixels per frame at the
    /// looked-at point's depth).
    #[arg(long, value_enum)]
    pub(crate) camera_path: Option<CameraPathArg>,
    /// Speed of `--camera-path`, in its unit per frame (any sign).
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    pub(crate) camera_speed: f32,
    /// Frames per second: frame `t` shows the glTF animation at
    /// `start-time + t / fps` seconds.
    #[arg(long, default_value_t = 30.0)]
    pub(crate) fps: f32,
    /// Animation time of the first frame, seconds.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub(crate) start_time: f32,
    /// Move the seeds along the motion vectors between frames (seeds follow
    /// the surfaces they sampled; no seed duplicated): `on` by default when
    /// the camera or objects move.
    #[arg(long, value_enum)]
    pub(crate) reproject: Option<OnOff>,
    /// With reprojection: pixels whose surface moved less than this many
    /// pixels since the previous frame keep their seed (slow surfaces keep
    /// the sorting pass's prediction; fast ones carry their seeds along).
    /// Pixels per frame, >= 0; 0: every seed follows its surface. Default 6
    /// in `--mode temporal`, 4 in `--mode permute|sort`, 0 in `--mode hold`.
    #[arg(long, value_parser = parse_pixels_per_frame, allow_hyphen_values = true)]
    pub(crate) reproject_hold_below: Option<f32>,
    /// With reprojection: in a frame where at least this share of the pixels
    /// moves rigidly (at least 1 px/frame, as their four neighbours within
    /// 0.05 px/frame or 2.5% of their speed: a camera pan), every seed
    /// follows its surface whatever `--reproject-hold-below` says, and
    /// ZSobol's points (`--sampler zsobol|zsobol-jitter`) follow the frame's
    /// mean motion. In [0, 1]; 0: off. Default 0.5 in `--mode temporal`, 0
    /// in the other modes.
    #[arg(long, value_parser = parse_share, allow_hyphen_values = true)]
    pub(crate) reproject_follow_share: Option<f32>,
    /// With a follow share above 0: whether ZSobol's points
    /// (`--sampler zsobol|zsobol-jitter`) follow the frames that follow as a
    /// whole and whose rigid pixels move alike, as in a camera pan (`on`,
    /// the default: a history that follows the pan keeps ZSobol's gain in
    /// time, at a small cost to each raw frame; an orbit's frames leave them
    /// where they are) or stay on the screen (`off`). QUALITY.md, "ZSobol
    /// follows a pan".
    #[arg(long, value_enum, default_value = "on")]
    pub(crate) pan_offset: OnOff,
    /// Feature-aware permutation in `--mode permute` and `--mode temporal`: sort keys with the
    /// albedo divided out, each block sorted in groups of one surface, and
    /// no retarget move across an edge (object id, normal, depth from the
    /// G-buffer).
    #[arg(long, value_enum, default_value = "off")]
    pub(crate) features: OnOff,
    /// What the feature-aware sorting pass ranks (with `--features on`):
    /// `demodulated` (radiance luma / albedo luma; the default and the only
    /// key the GPU computes), `raw` (radiance luma), `history` (demodulated
    /// value minus its smoothed running mean; CPU only).
    #[arg(long, value_enum, default_value = "demodulated")]
    pub(crate) feature_key: FeatureKeyArg,
    /// Real-time filter after each frame, as a renderer shows it: `taa`
    /// (reprojected exponential history, 3x3 colour clamp), `gauss`
    /// (Gaussian, sigma 1 px), `atrous` (SVGF's edge-avoiding a-trous, 5
    /// iterations), `taa+atrous` (both, SVGF's order). Writes
    /// `last_filtered.png|exr`, and `frames/filtered_NNNNN.exr|png` beside
    /// the raw frames with `--save-frames`. Runs on the CPU from the
    /// read-back frame and G-buffer.
    #[arg(long, default_value = "none")]
    pub(crate) filter: FilterChain,
    /// Weight of the current frame in the `taa` history, in (0, 1].
    #[arg(long, default_value_t = 0.1)]
    pub(crate) taa_alpha: f32,
    /// Whether `taa` clamps its history to the current frame's 3x3 colour
    /// box: `on` (the default, a TAA's guard against ghosting) or `off` (a
    /// plain reprojected exponential history, as SVGF's temporal pass
    /// accumulates). With `off` and neither `--mode`, `--sampler` nor
    /// `--tile` named, the render takes `--mode hold --sampler
    /// spatiotemporal-kronecker`, which keeps least error behind such a
    /// history (QUALITY.md, "Without TAA's clamp").
    #[arg(long, value_enum, default_value = "on")]
    pub(crate) taa_clamp: OnOff,
    /// Write every frame to `<out>/frames/frame_NNNNN.exr` (linear) and
    /// `.png` (tone-mapped).
    #[arg(long)]
    pub(crate) save_frames: bool,
    /// Write every frame's G-buffer to `<out>/aovs/frame_NNNNN.<aov>.exr`:
    /// motion (backward, pixels), depth, normal, albedo, id.
    #[arg(long)]
    pub(crate) save_aovs: bool,
    /// Image width in pixels.
    #[arg(long, default_value_t = 512, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub(crate) width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 512, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub(crate) height: u32,
    /// Samples per pixel per frame.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub(crate) spp: u32,
    /// Frames to render.
    #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u32).range(1..))]
    pub(crate) frames: u32,
    /// How seeds change between frames: `white` (default with `--sampler
    /// screen-sobol` or `zsobol`, which draw every decision but Russian
    /// roulette themselves), `sort`, `permute` (the R2
    /// walk of Heitz & Belcour; default with `--tile 128`), `temporal` (the
    /// default: sort against slice `t mod 64` of the default spatiotemporal
    /// mask, retarget to the next slice: blue in time too; 64 tile; with
    /// `--features on` sorted in groups of one surface and cut at edges) or
    /// `hold` (default with `--sampler spatiotemporal` and with
    /// `--taa-clamp off`; takes it and
    /// `--sampler zsobol`: each pixel's sampler data, the spatiotemporal
    /// shift or ZSobol's point, stays with it, and follows the motion with
    /// reprojection).
    #[arg(long, value_enum)]
    pub(crate) mode: Option<ModeArg>,
    /// Block side of the sorting pass in pixels (2..=8).
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(2..=8))]
    pub(crate) block: u32,
    /// Side of the baked dither tile: 64 or 128 (default 64, the only side
    /// `--mode temporal` takes).
    #[arg(long, value_parser = parse_tile)]
    pub(crate) tile: Option<TileChoice>,
    /// Maximum path length in segments.
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=MAX_DEPTH_LIMIT as i64))]
    pub(crate) max_depth: u32,
    /// Path regularisation for glossy surfaces seen after rough ones, in
    /// [0, 1] (0: off, the default, unbiased): their roughness is raised to
    /// at least this times the roughest lobe earlier on the path, so that
    /// caustics on diffuse surfaces through glossy ones (wall -> metal ->
    /// light) are found often with small weights instead of rarely with large
    /// ones. Biased: blurs those caustics and loses some energy.
    #[arg(long, default_value_t = 0.0, value_parser = parse_strength, allow_hyphen_values = true)]
    pub(crate) glossy_regularization: f32,
    /// `fixed`: a seed alone defines its random stream (the paper's way);
    /// `advance`: the stream also advances with the frame index.
    #[arg(long, value_enum, default_value_t = SeedModeArg::Fixed)]
    pub(crate) seed_mode: SeedModeArg,
    /// Source of the path's 2D decisions (pixel jitter, light samples, BSDF
    /// directions): `seeds` (the seed stream, permuted per `--mode`),
    /// `screen-sobol` (screen-space Sobol with optimised keys, up to 16 spp),
    /// `zsobol` (Morton-ordered Sobol, up to 256 spp and 4096 pixels a
    /// side; its frames are digital shifts of one point set, so a pixel's
    /// frames converge faster than independent ones) or `spatiotemporal` (each pixel one progressive sequence across
    /// frames, shifted by blue noise: blue in time; takes every decision,
    /// Russian roulette included, and `--mode hold`; `spatiotemporal-kronecker`
    /// continues a Kronecker sequence instead of Sobol). With the others Russian
    /// roulette still reads the seeds.
    /// `screen-sobol-jitter` and `zsobol-jitter` take only the position inside
    /// the pixel from that sampler and everything else from the (permuted)
    /// seeds: with `--mode permute`, silhouettes get a stratified jitter too.
    /// Default: `zsobol-jitter` with the modes that permute seeds (`seeds`
    /// past 256 spp or 4096 pixels a side, with a note), `seeds` with
    /// `--mode white`, `spatiotemporal-kronecker` with `--mode hold` (so with
    /// `--taa-clamp off` too).
    #[arg(long, value_enum)]
    pub(crate) sampler: Option<SamplerArg>,
    /// Output directory (created if missing).
    #[arg(long, default_value = "out")]
    pub(crate) out: PathBuf,
    /// Where to render: `auto` uses a hardware GPU adapter if one exists,
    /// else the CPU renderer (also when the only adapter is a software
    /// rasteriser such as lavapipe, which is far slower than the native CPU
    /// renderer); `gpu` uses any adapter, software ones included.
    #[arg(long, value_enum, default_value_t = DeviceArg::Auto)]
    pub(crate) device: DeviceArg,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub(crate) enum ModeArg {
    /// Fresh white-noise seeds every frame.
    White,
    /// Sorting pass only.
    Sort,
    /// Sorting + retargeting.
    Permute,
    /// Nothing between frames; the spatiotemporal sampler's or ZSobol's homes
    /// follow the motion with reprojection.
    Hold,
    /// Sorting against the frame's slice of the default spatiotemporal mask
    /// + retargeting to the next slice (blue in time).
    Temporal,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub(crate) enum SeedModeArg {
    Fixed,
    Advance,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub(crate) enum SamplerArg {
    /// The pixel's seed stream.
    Seeds,
    /// Screen-space Owen-scrambled Sobol with optimised per-pixel keys.
    ScreenSobol,
    /// Morton-ordered Sobol with hashed digit permutations.
    Zsobol,
    /// The pixel jitter from `screen-sobol`, the rest from the seeds.
    ScreenSobolJitter,
    /// The pixel jitter from `zsobol`, the rest from the seeds.
    ZsobolJitter,
    /// Each pixel continues one progressive Owen-scrambled Sobol sequence
    /// across frames, rotated by a blue-noise shift (blue in time).
    Spatiotemporal,
    /// `spatiotemporal` with a Kronecker sequence in time instead of Sobol:
    /// every window of consecutive frames as well spread as the first.
    SpatiotemporalKronecker,
}

impl SamplerArg {
    /// The command-line spelling.
    pub(crate) fn name(self) -> String {
        self.to_possible_value()
            .map(|v| v.get_name().to_owned())
            .unwrap_or_default()
    }

    /// The trace's sampler flags ([`TraceSettings::sampler`]).
    pub(crate) fn flags(self) -> u32 {
        match self {
            SamplerArg::Seeds => SAMPLER_SEEDS,
            SamplerArg::ScreenSobol => SAMPLER_SCREEN_SOBOL,
            SamplerArg::Zsobol => SAMPLER_ZSOBOL,
            SamplerArg::ScreenSobolJitter => SAMPLER_SCREEN_SOBOL | SAMPLER_JITTER_ONLY,
            SamplerArg::ZsobolJitter => SAMPLER_ZSOBOL | SAMPLER_JITTER_ONLY,
            SamplerArg::Spatiotemporal => kernels::abi::SAMPLER_SPATIOTEMPORAL,
            SamplerArg::SpatiotemporalKronecker => {
                kernels::abi::SAMPLER_SPATIOTEMPORAL | kernels::abi::SAMPLER_KRONECKER
            }
        }
    }

    /// The sampler with these flags.
    pub(crate) fn from_flags(flags: u32) -> Option<SamplerArg> {
        SamplerArg::value_variants()
            .iter()
            .copied()
            .find(|s| s.flags() == flags)
    }
}

impl ModeArg {
    /// The mode it names.
    pub(crate) fn mode(self) -> PermuteMode {
        match self {
            ModeArg::White => PermuteMode::White,
            ModeArg::Sort => PermuteMode::Sort,
            ModeArg::Permute => PermuteMode::Permute,
            ModeArg::Hold => PermuteMode::Hold,
            ModeArg::Temporal => PermuteMode::Temporal,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum OnOff {
    On,
    Off,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum FeatureKeyArg {
    Demodulated,
    Raw,
    History,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum CameraPathArg {
    Orbit,
    Dolly,
    Pan,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum DeviceArg {
    Auto,
    Gpu,
    Cpu,
}

/// Parses `x,y,z`.
pub(crate) fn parse_vec3(s: &str) -> Result<glam::Vec3, String> {
    let parts: Vec<&str> = s.split(',').collect();
    let nums: Vec<f32> = parts
        .iter()
        .map(|p| p.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("'{s}' is not x,y,z: {e}"))?;
    match nums[..] {
        [x, y, z] if nums.iter().all(|v| v.is_finite()) => Ok(glam::Vec3::new(x, y, z)),
        _ => Err(format!("'{s}' is not three finite numbers x,y,z")),
    }
}

/// What `--env` names: a constant sky or an environment map file.
#[derive(Clone, Debug)]
pub(crate) enum EnvArg {
    /// A constant radiance, linear RGB.
    Constant(glam::Vec3),
    /// An `.exr` or `.hdr` file, read after parsing (so that a missing file
    /// is reported with the other input errors).
    Map(PathBuf),
}

/// Parses `--env`: a name ending in `.exr` or `.hdr` (any case) is a map
/// file; anything else must be `r,g,b`, each finite and `>= 0`.
pub(crate) fn parse_environment(s: &str) -> Result<EnvArg, String> {
    let lower = s.to_ascii_lowercase();
    if lower.ends_with(".exr") || lower.ends_with(".hdr") {
        return Ok(EnvArg::Map(PathBuf::from(s)));
    }
    let v =
        parse_vec3(s).map_err(|e| format!("{e} (a constant sky's radiance r,g,b, or a .exr/.hdr file)"))?;
    if v.min_element() < 0.0 {
        return Err(format!("'{s}': a radiance cannot be negative"));
    }
    Ok(EnvArg::Constant(v))
}

/// `--reproject-hold-below`: a finite number of pixels per frame, `>= 0`.
pub(crate) fn parse_pixels_per_frame(s: &str) -> Result<f32, String> {
    match s.trim().parse::<f32>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
        _ => Err(format!("'{s}' is not a finite speed >= 0 (pixels per frame)")),
    }
}

/// `--reproject-follow-share`: a share of the frame's pixels in `[0, 1]`.
pub(crate) fn parse_share(s: &str) -> Result<f32, String> {
    match s.trim().parse::<f32>() {
        Ok(v) if (0.0..=1.0).contains(&v) => Ok(v),
        _ => Err(format!("'{s}' is not a share of the frame in [0, 1] (0: off)")),
    }
}

/// `--glossy-regularization`: a strength in `[0, 1]`.
pub(crate) fn parse_strength(s: &str) -> Result<f32, String> {
    match s.trim().parse::<f32>() {
        Ok(v) if (0.0..=1.0).contains(&v) => Ok(v),
        _ => Err(format!("'{s}' is not a strength in [0, 1] (0: off)")),
    }
}

/// Parses `--tile`: the side of a baked dither tile, 64 or 128.
pub(crate) fn parse_tile(s: &str) -> Result<TileChoice, String> {
    match s {
        "64" => Ok(TileChoice::Tile64),
        "128" => Ok(TileChoice::Tile128),
        _ => Err(format!("{s} is not a baked tile size (64 or 128)")),
    }
}
