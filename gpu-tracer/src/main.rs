//! `gpu-tracer`: renders a scene with the blue-noise seed permutation on the
//! GPU (wgpu, kernels compiled by rust-gpu), falling back to the CPU renderer
//! where no GPU adapter exists.
//!
//! ```text
//! gpu-tracer render --scene cornell --width 512 --height 512 --frames 16 --out out
//! ```

use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand, ValueEnum};
use gpu_tracer::animation::Rig;
use gpu_tracer::aov::write_aovs;
use gpu_tracer::camera_path::{CameraPath, CameraPathKind};
use gpu_tracer::feature_keys::FeatureKey;
use gpu_tracer::filter::{FilterChain, FilterSettings, SequenceFilter};
use gpu_tracer::gpu::{Gpu, GpuError};
use gpu_tracer::image_out::{write_exr, write_png, ToneMap};
use gpu_tracer::method_choice::choose_method;
use gpu_tracer::scene::{Camera, Scene};
use gpu_tracer::timeline::{SceneSequence, Timeline};
use gpu_tracer::{
    cornell, gltf, obj, render_sequence_cpu, render_sequence_gpu, FrameView, PermuteMode, RenderJob,
    SequenceOptions, TileChoice, TraceSettings,
};
use indicatif::{ProgressBar, ProgressStyle};
use kernels::abi::{
    MAX_DEPTH_LIMIT, SAMPLER_JITTER_ONLY, SAMPLER_SCREEN_SOBOL, SAMPLER_SEEDS, SAMPLER_ZSOBOL,
    SEED_MODE_ADVANCE, SEED_MODE_FIXED,
};
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Parser, Debug)]
#[command(
    name = "gpu-tracer",
    version,
    about = "Path tracer with blue-noise error through seed permutation"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render frames and write the last frame and the accumulated mean.
    Render(RenderArgs),
}

#[derive(clap::Args, Debug)]
struct RenderArgs {
    /// `cornell` for the built-in Cornell box, `cornell-glossy` for the same
    /// room with three GGX spheres (roughness 0.1, 0.3, 0.6), `sun-sky` for
    /// objects on open ground under a sun with a disk and a sky (the sky is
    /// its default `--env`), the path of a glTF 2.0 file (`.gltf` or `.glb`:
    /// meshes, metallic-roughness materials, textures, cameras, node
    /// animation, KHR_lights_punctual lights), or of an OBJ file
    /// (materials from its MTL: Kd diffuse, Ke emission, Ks/Ns specular).
    #[arg(long, default_value = "cornell")]
    scene: String,
    /// glTF: which camera (0-based, in scene order); default the first.
    #[arg(long)]
    camera_index: Option<usize>,
    /// Camera position `x,y,z` (world units); replaces the scene's camera
    /// (needs `--camera-at`).
    #[arg(long, value_parser = parse_vec3, requires = "camera_at")]
    camera_from: Option<glam::Vec3>,
    /// Point the camera looks at, `x,y,z` (needs `--camera-from`).
    #[arg(long, value_parser = parse_vec3, requires = "camera_from")]
    camera_at: Option<glam::Vec3>,
    /// Vertical field of view in degrees for `--camera-from/--camera-at`.
    #[arg(long, default_value_t = 40.0)]
    fov: f32,
    /// Environment seen by rays that leave the scene: `r,g,b`, a constant sky
    /// of that linear radiance (each finite, >= 0), or an equirectangular
    /// environment map (`FILE.exr` or `FILE.hdr`, linear radiance, +Y up,
    /// the image's centre looking down -Z), importance-sampled.
    #[arg(long, value_parser = parse_environment, allow_hyphen_values = true)]
    env: Option<EnvArg>,
    /// Rotation of the `--env` map about +Y in degrees (a positive angle
    /// turns its content to the viewer's right).
    #[arg(long, allow_hyphen_values = true)]
    env_rotation: Option<f32>,
    /// Camera motion on top of the scene's: `orbit` (about the looked-at
    /// point, `--camera-speed` in degrees per frame), `dolly` (forward,
    /// scene units per frame) or `pan` (right, pixels per frame at the
    /// looked-at point's depth).
    #[arg(long, value_enum)]
    camera_path: Option<CameraPathArg>,
    /// Speed of `--camera-path`, in its unit per frame (any sign).
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    camera_speed: f32,
    /// Frames per second: frame `t` shows the glTF animation at
    /// `start-time + t / fps` seconds.
    #[arg(long, default_value_t = 30.0)]
    fps: f32,
    /// Animation time of the first frame, seconds.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    start_time: f32,
    /// Move the seeds along the motion vectors between frames (seeds follow
    /// the surfaces they sampled; no seed duplicated): `on` by default when
    /// the camera or objects move.
    #[arg(long, value_enum)]
    reproject: Option<OnOff>,
    /// Feature-aware permutation in `--mode permute` and `--mode temporal`: sort keys with the
    /// albedo divided out, each block sorted in groups of one surface, and
    /// no retarget move across an edge (object id, normal, depth from the
    /// G-buffer).
    #[arg(long, value_enum, default_value = "off")]
    features: OnOff,
    /// What the feature-aware sorting pass ranks (with `--features on`):
    /// `demodulated` (radiance luma / albedo luma; the default and the only
    /// key the GPU computes), `raw` (radiance luma), `history` (demodulated
    /// value minus its smoothed running mean; CPU only).
    #[arg(long, value_enum, default_value = "demodulated")]
    feature_key: FeatureKeyArg,
    /// Real-time filter after each frame, as a renderer shows it: `taa`
    /// (reprojected exponential history, 3x3 colour clamp), `gauss`
    /// (Gaussian, sigma 1 px), `atrous` (SVGF's edge-avoiding a-trous, 5
    /// iterations), `taa+atrous` (both, SVGF's order). Writes
    /// `last_filtered.png|exr`, and `frames/filtered_NNNNN.exr|png` beside
    /// the raw frames with `--save-frames`. Runs on the CPU from the
    /// read-back frame and G-buffer.
    #[arg(long, default_value = "none")]
    filter: FilterChain,
    /// Weight of the current frame in the `taa` history, in (0, 1].
    #[arg(long, default_value_t = 0.1)]
    taa_alpha: f32,
    /// Write every frame to `<out>/frames/frame_NNNNN.exr` (linear) and
    /// `.png` (tone-mapped).
    #[arg(long)]
    save_frames: bool,
    /// Write every frame's G-buffer to `<out>/aovs/frame_NNNNN.<aov>.exr`:
    /// motion (backward, pixels), depth, normal, albedo, id.
    #[arg(long)]
    save_aovs: bool,
    /// Image width in pixels.
    #[arg(long, default_value_t = 512, value_parser = clap::value_parser!(u32).range(1..=16384))]
    width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 512, value_parser = clap::value_parser!(u32).range(1..=16384))]
    height: u32,
    /// Samples per pixel per frame.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=4096))]
    spp: u32,
    /// Frames to render.
    #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u32).range(1..))]
    frames: u32,
    /// How seeds change between frames: `white`, `sort`, `permute` (the R2
    /// walk of Heitz & Belcour; default with `--tile 128`), `temporal` (the
    /// default: sort against slice `t mod 64` of the default spatiotemporal
    /// mask, retarget to the next slice: blue in time too; 64 tile; with
    /// `--features on` sorted in groups of one surface and cut at edges) or
    /// `hold` (default with `--sampler spatiotemporal`, the only sampler it
    /// takes: each pixel's shift stays with it, and follows the motion with
    /// reprojection).
    #[arg(long, value_enum)]
    mode: Option<ModeArg>,
    /// Block side of the sorting pass in pixels (2..=8).
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(2..=8))]
    block: u32,
    /// Side of the baked dither tile: 64 or 128 (default 64, the only side
    /// `--mode temporal` takes).
    #[arg(long, value_parser = parse_tile)]
    tile: Option<u32>,
    /// Maximum path length in segments.
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=MAX_DEPTH_LIMIT as i64))]
    max_depth: u32,
    /// `fixed`: a seed alone defines its random stream (the paper's way);
    /// `advance`: the stream also advances with the frame index.
    #[arg(long, value_enum, default_value_t = SeedModeArg::Fixed)]
    seed_mode: SeedModeArg,
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
    /// `--mode white`, `spatiotemporal-kronecker` with `--mode hold`.
    #[arg(long, value_enum)]
    sampler: Option<SamplerArg>,
    /// Output directory (created if missing).
    #[arg(long, default_value = "out")]
    out: PathBuf,
    /// Where to render: `auto` uses a hardware GPU adapter if one exists,
    /// else the CPU renderer (also when the only adapter is a software
    /// rasteriser such as lavapipe, which is far slower than the native CPU
    /// renderer); `gpu` uses any adapter, software ones included.
    #[arg(long, value_enum, default_value_t = DeviceArg::Auto)]
    device: DeviceArg,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum ModeArg {
    /// Fresh white-noise seeds every frame.
    White,
    /// Sorting pass only.
    Sort,
    /// Sorting + retargeting.
    Permute,
    /// Nothing between frames; the spatiotemporal sampler's homes follow the
    /// motion with reprojection.
    Hold,
    /// Sorting against the frame's slice of the default spatiotemporal mask
    /// + retargeting to the next slice (blue in time).
    Temporal,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum SeedModeArg {
    Fixed,
    Advance,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum SamplerArg {
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
    fn name(self) -> String {
        self.to_possible_value()
            .map(|v| v.get_name().to_owned())
            .unwrap_or_default()
    }

    /// The trace's sampler flags ([`TraceSettings::sampler`]).
    fn flags(self) -> u32 {
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
    fn from_flags(flags: u32) -> Option<SamplerArg> {
        SamplerArg::value_variants()
            .iter()
            .copied()
            .find(|s| s.flags() == flags)
    }
}

impl ModeArg {
    /// The mode it names.
    fn mode(self) -> PermuteMode {
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
enum OnOff {
    On,
    Off,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum FeatureKeyArg {
    Demodulated,
    Raw,
    History,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum CameraPathArg {
    Orbit,
    Dolly,
    Pan,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum DeviceArg {
    Auto,
    Gpu,
    Cpu,
}

fn main() -> Result<()> {
    // Before any thread: keeps Mesa's "XDG_RUNTIME_DIR is invalid" line away.
    gpu_tracer::gpu::prepare_headless_environment();
    let cli = Cli::parse();
    match cli.command {
        Command::Render(args) => render(args),
    }
}

fn render(args: RenderArgs) -> Result<()> {
    // Fail on bad input before any work: scene, motion, output directory.
    let (mut scene, mut rig) = load_scene(&args)?;
    let mut environment = if args.scene == "sun-sky" {
        gpu_tracer::outdoor::SKY
    } else {
        glam::Vec3::ZERO
    };
    match &args.env {
        Some(EnvArg::Constant(radiance)) => environment = *radiance,
        Some(EnvArg::Map(path)) => {
            let rotation = args.env_rotation.unwrap_or(0.0);
            scene.environment_map = Some(
                gpu_tracer::environment_file::load_environment_map(path, rotation)
                    .context("cannot use --env")?,
            );
            environment = glam::Vec3::ZERO;
        }
        None => {}
    }
    if args.env_rotation.is_some() && !matches!(args.env, Some(EnvArg::Map(_))) {
        bail!("--env-rotation applies to an environment map (--env FILE.exr|.hdr)");
    }
    if let (Some(from), Some(at)) = (args.camera_from, args.camera_at) {
        scene.camera = Camera {
            origin: from,
            target: at,
            up: glam::Vec3::Y,
            fov_y_degrees: args.fov,
        };
        scene
            .camera
            .basis()
            .context("--camera-from/--camera-at/--fov give a degenerate camera")?;
        if let Some(rig) = rig.as_mut() {
            rig.camera = None; // the command line's camera replaces the file's
        }
    }
    if !(args.fps.is_finite() && args.fps > 0.0 && args.start_time.is_finite()) {
        bail!("--fps must be a finite number > 0 and --start-time finite");
    }
    let timeline = Timeline {
        rig,
        camera_path: args.camera_path.map(|kind| CameraPath {
            kind: match kind {
                CameraPathArg::Orbit => CameraPathKind::Orbit,
                CameraPathArg::Dolly => CameraPathKind::Dolly,
                CameraPathArg::Pan => CameraPathKind::Pan,
            },
            speed: args.camera_speed,
        }),
        fps: args.fps,
        start_time: args.start_time,
    };
    // Every frame's camera is checked before rendering (a path can make the
    // camera degenerate later in the sequence).
    for t in 0..args.frames {
        timeline
            .camera(&scene.camera, t, args.height)
            .with_context(|| format!("frame {t} of the camera path or animation"))?;
    }
    let mut sequence =
        SceneSequence::new(&scene, timeline, args.height).context("cannot prepare the scene")?;
    if sequence.scene().emitter_count == 0 && environment == glam::Vec3::ZERO {
        eprintln!(
            "warning: scene {} has no emitter (no emissive material, no light) and no --env: the image will be black",
            args.scene
        );
    }

    let mut settings = TraceSettings::new(args.width, args.height);
    settings.spp = args.spp;
    settings.max_depth = args.max_depth;
    settings.environment = environment;
    settings.seed_mode = match args.seed_mode {
        SeedModeArg::Fixed => SEED_MODE_FIXED,
        SeedModeArg::Advance => SEED_MODE_ADVANCE,
    };
    let tile_arg = args
        .tile
        .map(|side| TileChoice::from_side(side).context("tile must be 64 or 128"))
        .transpose()?;
    let named_sampler = args.sampler.map(SamplerArg::flags);
    let spatiotemporal = matches!(
        args.sampler,
        Some(SamplerArg::Spatiotemporal | SamplerArg::SpatiotemporalKronecker)
    );
    match (args.mode, spatiotemporal) {
        (Some(ModeArg::Hold), false) if args.sampler.is_some() => bail!(
            "--mode hold keeps every pixel's numbers from frame to frame: only --sampler spatiotemporal, \
             which advances its own sequence every frame, can use it"
        ),
        (Some(m @ (ModeArg::Sort | ModeArg::Permute | ModeArg::Temporal)), true) => bail!(
            "--mode {} has nothing to permute with --sampler spatiotemporal, which draws every number \
             itself: use --mode hold (its default) or white",
            m.to_possible_value()
                .map(|v| v.get_name().to_owned())
                .unwrap_or_default()
        ),
        _ => {}
    }
    let choice = choose_method(args.mode.map(ModeArg::mode), named_sampler, tile_arg, &settings);
    settings.sampler = choice.sampler;
    let sampler_name = SamplerArg::from_flags(choice.sampler)
        .map(SamplerArg::name)
        .context("the chosen sampler has no command-line name")?;
    if let Some(why) = choice.fallback {
        eprintln!("note: {why}");
    }
    // Settings the chosen sampler does not support fail here, before any work.
    sequence
        .scene()
        .trace_params(&settings, 0)
        .with_context(|| format!("--sampler {sampler_name} cannot render these settings"))?;
    let filtering = args.filter != FilterChain::None;
    let mut filter = SequenceFilter::new(
        args.filter,
        FilterSettings {
            alpha: args.taa_alpha,
            ..FilterSettings::default()
        },
        args.width,
        args.height,
    )
    .context("--filter / --taa-alpha")?;
    if args.features == OnOff::Off && args.feature_key != FeatureKeyArg::Demodulated {
        bail!("--feature-key applies to the feature-aware permutation: add --features on");
    }
    prepare_out_dir(&args.out)?;
    let frames_dir = args.out.join("frames");
    let aovs_dir = args.out.join("aovs");
    for (wanted, dir) in [(args.save_frames, &frames_dir), (args.save_aovs, &aovs_dir)] {
        if wanted {
            prepare_out_dir(dir)?;
        }
    }
    let temporal = choice.mode == PermuteMode::Temporal;
    let tile = tile_arg.unwrap_or(TileChoice::TEMPORAL);
    if temporal && tile != TileChoice::TEMPORAL {
        bail!("--mode temporal sorts against the 64x64 slices of its default target: use --tile 64 (the default)");
    }
    let job = RenderJob {
        settings,
        frames: args.frames,
        mode: choice.mode,
        block: args.block,
        tile,
        salt: 0,
    };
    let want_gbuffer = args.save_aovs || filtering;
    let moves = sequence.timeline().moves();
    let reproject = match args.reproject {
        Some(OnOff::On) => true,
        Some(OnOff::Off) => false,
        None => moves,
    };
    let features = args.features == OnOff::On;
    let options = SequenceOptions {
        gbuffer: want_gbuffer,
        reproject,
        features,
        feature_key: match args.feature_key {
            FeatureKeyArg::Demodulated => FeatureKey::Demodulated,
            FeatureKeyArg::Raw => FeatureKey::Raw,
            FeatureKeyArg::History => FeatureKey::HistoryResidual,
        },
    };
    // Settings the mode cannot take fail here, before any work.
    job.validate()?;

    let gpu = match args.device {
        DeviceArg::Cpu => None,
        DeviceArg::Gpu => Some(Gpu::new().context("--device gpu was requested")?),
        DeviceArg::Auto => match Gpu::probe().and_then(|info| {
            if info.device_type == wgpu::DeviceType::Cpu {
                Ok(Err(info))
            } else {
                Gpu::new().map(Ok)
            }
        }) {
            Ok(Err(info)) => {
                eprintln!(
                    "notice: the only GPU adapter is a software rasteriser ({} ({:?}, {:?})); the \
                     native CPU renderer is much faster, so it renders (--device gpu forces the adapter)",
                    info.name, info.backend, info.device_type
                );
                None
            }
            Ok(Ok(gpu)) => Some(gpu),
            Err(GpuError::NoAdapter(reason)) => {
                eprintln!("notice: no GPU adapter ({reason}); rendering on the CPU");
                None
            }
            Err(e) => {
                eprintln!("warning: the GPU could not be used ({e}); rendering on the CPU");
                None
            }
        },
    };

    let bar = ProgressBar::new(args.frames as u64);
    bar.set_style(
        ProgressStyle::with_template("{prefix} [{bar:40}] {pos}/{len} frames {elapsed_precise} eta {eta}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    let start = Instant::now();
    let (w, h) = (args.width, args.height);
    let mut last_filtered: Vec<glam::Vec4> = Vec::new();
    let mut save_error: Option<anyhow::Error> = None;
    let mut on_frame = |f: &FrameView<'_>| {
        if save_error.is_some() {
            return;
        }
        let mut result = save_frame(&args, &frames_dir, &aovs_dir, w, h, f);
        if result.is_ok() && filtering {
            result = filter_frame(&args, &mut filter, &frames_dir, w, h, f).map(|out| last_filtered = out);
        }
        if let Err(e) = result {
            save_error = Some(e);
        }
    };
    let saving = args.save_frames || args.save_aovs || filtering;
    let output = match &gpu {
        Some(gpu) => {
            bar.set_prefix(format!("GPU {}", gpu.info.name));
            // Progress counts submitted frames (no read-back between frames
            // unless frames or AOVs are saved).
            let callback: Option<&mut gpu_tracer::render::SequenceCallback<'_>> =
                if saving { Some(&mut on_frame) } else { None };
            render_sequence_gpu(gpu, &mut sequence, &job, options, |_| bar.inc(1), callback)?
        }
        None => {
            bar.set_prefix("CPU");
            render_sequence_cpu(&mut sequence, &job, options, |f| {
                if saving {
                    on_frame(f);
                }
                bar.inc(1)
            })?
        }
    };
    if let Some(e) = save_error {
        return Err(e);
    }
    bar.finish();
    let secs = start.elapsed().as_secs_f64();

    let files = [
        (args.out.join("last.png"), Some(false), false),
        (args.out.join("mean.png"), Some(true), false),
        (args.out.join("last.exr"), Some(false), true),
        (args.out.join("mean.exr"), Some(true), true),
        (args.out.join("last_filtered.png"), None, false),
        (args.out.join("last_filtered.exr"), None, true),
    ];
    for (path, mean, exr) in &files {
        let pixels = match mean {
            Some(true) => &output.mean,
            Some(false) => &output.last,
            None if filtering => &last_filtered,
            None => continue,
        };
        if *exr {
            write_exr(path, w, h, pixels)
        } else {
            write_png(path, w, h, pixels, ToneMap::Reinhard)
        }
        .with_context(|| format!("cannot write {}", path.display()))?;
    }
    let mut saved = String::new();
    if args.save_frames {
        saved += &format!(", {}/frame_*.exr|png", frames_dir.display());
        if filtering {
            saved += &format!(", {}/filtered_*.exr|png", frames_dir.display());
        }
    }
    if args.save_aovs {
        saved += &format!(", {}/frame_*.<aov>.exr", aovs_dir.display());
    }
    println!(
        "rendered {} frame(s) of {}x{} at {} spp on {} in {:.2} s ({:?} mode, {} sampler, reprojection {}, features {}, filter {}); wrote {}{saved}",
        args.frames,
        w,
        h,
        args.spp,
        output.device,
        secs,
        job.mode,
        sampler_name,
        if reproject { "on" } else { "off" },
        if features {
            format!("on, {} key", options.feature_key.name())
        } else {
            "off".to_string()
        },
        args.filter,
        files
            .iter()
            .filter(|f| f.1.is_some() || filtering)
            .map(|f| f.0.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    Ok(())
}

/// Loads `--scene`: a built-in Cornell box, a glTF file (with its rig) or
/// an OBJ file. glTF notices (approximated features) go to stderr.
fn load_scene(args: &RenderArgs) -> Result<(Scene, Option<Rig>)> {
    let path = Path::new(&args.scene);
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if args.camera_index.is_some() && !matches!(ext.as_deref(), Some("gltf" | "glb")) {
        bail!("--camera-index applies to glTF scenes only");
    }
    if args.scene == "cornell" {
        return Ok((cornell::cornell_box(), None));
    }
    if args.scene == "cornell-glossy" {
        return Ok((cornell::cornell_glossy(), None));
    }
    if args.scene == "sun-sky" {
        return Ok((gpu_tracer::outdoor::sun_and_sky(), None));
    }
    match ext.as_deref() {
        Some("gltf" | "glb") => {
            let loaded = gltf::load_gltf(path, args.camera_index)
                .with_context(|| format!("cannot load scene {}", args.scene))?;
            for notice in &loaded.notices {
                eprintln!("notice: {}: {notice}", args.scene);
            }
            Ok((loaded.scene, Some(loaded.rig)))
        }
        _ => Ok((
            obj::load_obj(path).with_context(|| format!("cannot load scene {}", args.scene))?,
            None,
        )),
    }
}

/// Writes frame `f`'s colour and/or AOVs as `--save-frames` / `--save-aovs` ask.
fn save_frame(
    args: &RenderArgs,
    frames_dir: &Path,
    aovs_dir: &Path,
    w: u32,
    h: u32,
    f: &FrameView<'_>,
) -> Result<()> {
    let stem = format!("frame_{:05}", f.index);
    if args.save_frames {
        let exr = frames_dir.join(format!("{stem}.exr"));
        write_exr(&exr, w, h, f.color).with_context(|| format!("cannot write {}", exr.display()))?;
        let png = frames_dir.join(format!("{stem}.png"));
        write_png(&png, w, h, f.color, ToneMap::Reinhard)
            .with_context(|| format!("cannot write {}", png.display()))?;
    }
    if args.save_aovs {
        let gbuffer = f.gbuffer.context("the renderer returned no G-buffer")?;
        write_aovs(aovs_dir, &stem, w, h, gbuffer)
            .with_context(|| format!("cannot write the AOVs of frame {}", f.index))?;
    }
    Ok(())
}

/// Filters frame `f` (the filter keeps the history between calls) and, with
/// `--save-frames`, writes it as `filtered_NNNNN.exr|png`; returns it.
fn filter_frame(
    args: &RenderArgs,
    filter: &mut SequenceFilter,
    frames_dir: &Path,
    w: u32,
    h: u32,
    f: &FrameView<'_>,
) -> Result<Vec<glam::Vec4>> {
    let gbuffer = f.gbuffer.context("the renderer returned no G-buffer")?;
    let out = filter
        .next(f.color, gbuffer)
        .with_context(|| format!("filtering frame {}", f.index))?;
    if args.save_frames {
        let stem = format!("filtered_{:05}", f.index);
        let exr = frames_dir.join(format!("{stem}.exr"));
        write_exr(&exr, w, h, &out).with_context(|| format!("cannot write {}", exr.display()))?;
        let png = frames_dir.join(format!("{stem}.png"));
        write_png(&png, w, h, &out, ToneMap::Reinhard)
            .with_context(|| format!("cannot write {}", png.display()))?;
    }
    Ok(out)
}

/// Parses `x,y,z`.
fn parse_vec3(s: &str) -> Result<glam::Vec3, String> {
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
enum EnvArg {
    /// A constant radiance, linear RGB.
    Constant(glam::Vec3),
    /// An `.exr` or `.hdr` file, read after parsing (so that a missing file
    /// is reported with the other input errors).
    Map(PathBuf),
}

/// Parses `--env`: a name ending in `.exr` or `.hdr` (any case) is a map
/// file; anything else must be `r,g,b`, each finite and `>= 0`.
fn parse_environment(s: &str) -> Result<EnvArg, String> {
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

fn parse_tile(s: &str) -> Result<u32, String> {
    match s {
        "64" => Ok(64),
        "128" => Ok(128),
        _ => Err(format!("{s} is not a baked tile size (64 or 128)")),
    }
}

/// Creates `dir` and checks it is writable, so a bad path fails before rendering.
fn prepare_out_dir(dir: &Path) -> Result<()> {
    if dir.exists() && !dir.is_dir() {
        bail!("output path {} exists and is not a directory", dir.display());
    }
    std::fs::create_dir_all(dir)
        .with_context(|| format!("cannot create output directory {}", dir.display()))?;
    let probe = dir.join(".gpu-tracer-write-probe");
    std::fs::write(&probe, b"")
        .with_context(|| format!("output directory {} is not writable", dir.display()))?;
    std::fs::remove_file(&probe).ok();
    Ok(())
}
