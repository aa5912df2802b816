//! `gpu-tracer`: renders a scene with the blue-noise seed permutation on the
//! GPU (wgpu, kernels compiled by rust-gpu), falling back to the CPU renderer
//! where no GPU adapter exists.
//!
//! ```text
//! gpu-tracer render --scene cornell --width 512 --height 512 --frames 16 --out out
//! ```

use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand, ValueEnum};
use gpu_tracer::gpu::{Gpu, GpuError};
use gpu_tracer::image_out::{write_exr, write_png, ToneMap};
use gpu_tracer::{
    cornell, obj, render_cpu, render_gpu, PermuteMode, RenderJob, SceneGpu, TileChoice, TraceSettings,
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
    /// `cornell` for the built-in Cornell box, or the path of an OBJ file
    /// (materials from its MTL: Kd diffuse, Ke emission).
    #[arg(long, default_value = "cornell")]
    scene: String,
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
    /// How seeds change between frames.
    #[arg(long, value_enum, default_value_t = ModeArg::Permute)]
    mode: ModeArg,
    /// Block side of the sorting pass in pixels (2..=8).
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(2..=8))]
    block: u32,
    /// Side of the baked dither tile: 64 or 128.
    #[arg(long, default_value_t = 64, value_parser = parse_tile)]
    tile: u32,
    /// Maximum path length in segments.
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=MAX_DEPTH_LIMIT as i64))]
    max_depth: u32,
    /// `fixed`: a seed alone defines its random stream (the paper's way);
    /// `advance`: the stream also advances with the frame index.
    #[arg(long, value_enum, default_value_t = SeedModeArg::Fixed)]
    seed_mode: SeedModeArg,
    /// Source of the path's 2D decisions (pixel jitter, light samples, BSDF
    /// directions): `seeds` (the seed stream, permuted per `--mode`),
    /// `screen-sobol` (screen-space Sobol with optimised keys, up to 16 spp)
    /// or `zsobol` (Morton-ordered Sobol, up to 256 spp and 4096 pixels a
    /// side). Russian roulette still reads the seeds.
    /// `screen-sobol-jitter` and `zsobol-jitter` take only the position inside
    /// the pixel from that sampler and everything else from the (permuted)
    /// seeds: with `--mode permute`, silhouettes get a stratified jitter too.
    #[arg(long, value_enum, default_value_t = SamplerArg::Seeds)]
    sampler: SamplerArg,
    /// Output directory (created if missing).
    #[arg(long, default_value = "out")]
    out: PathBuf,
    /// Where to render: `auto` uses a GPU adapter if one exists, else the CPU.
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
}

impl SamplerArg {
    /// The command-line spelling.
    fn name(self) -> String {
        self.to_possible_value()
            .map(|v| v.get_name().to_owned())
            .unwrap_or_default()
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum DeviceArg {
    Auto,
    Gpu,
    Cpu,
}

fn main() -> Result<()> {
    let cli = Cli::parse();
    match cli.command {
        Command::Render(args) => render(args),
    }
}

fn render(args: RenderArgs) -> Result<()> {
    // Fail on bad input before any work: scene, output directory.
    let scene = if args.scene == "cornell" {
        cornell::cornell_box()
    } else {
        obj::load_obj(&args.scene).with_context(|| format!("cannot load scene {}", args.scene))?
    };
    let scene = SceneGpu::build(&scene).context("cannot prepare the scene")?;

    let mut settings = TraceSettings::new(args.width, args.height);
    settings.spp = args.spp;
    settings.max_depth = args.max_depth;
    settings.seed_mode = match args.seed_mode {
        SeedModeArg::Fixed => SEED_MODE_FIXED,
        SeedModeArg::Advance => SEED_MODE_ADVANCE,
    };
    settings.sampler = match args.sampler {
        SamplerArg::Seeds => SAMPLER_SEEDS,
        SamplerArg::ScreenSobol => SAMPLER_SCREEN_SOBOL,
        SamplerArg::Zsobol => SAMPLER_ZSOBOL,
        SamplerArg::ScreenSobolJitter => SAMPLER_SCREEN_SOBOL | SAMPLER_JITTER_ONLY,
        SamplerArg::ZsobolJitter => SAMPLER_ZSOBOL | SAMPLER_JITTER_ONLY,
    };
    // Settings the chosen sampler does not support fail here, before any work.
    scene
        .trace_params(&settings, 0)
        .with_context(|| format!("--sampler {} cannot render these settings", args.sampler.name()))?;
    prepare_out_dir(&args.out)?;
    let tile = TileChoice::from_side(args.tile).context("tile must be 64 or 128")?;
    let job = RenderJob {
        settings,
        frames: args.frames,
        mode: match args.mode {
            ModeArg::White => PermuteMode::White,
            ModeArg::Sort => PermuteMode::Sort,
            ModeArg::Permute => PermuteMode::Permute,
        },
        block: args.block,
        tile,
        salt: 0,
    };
    job.layout()?;

    let gpu = match args.device {
        DeviceArg::Cpu => None,
        DeviceArg::Gpu => Some(Gpu::new().context("--device gpu was requested")?),
        DeviceArg::Auto => match Gpu::new() {
            Ok(gpu) => Some(gpu),
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
    let output = match &gpu {
        Some(gpu) => {
            bar.set_prefix(format!("GPU {}", gpu.info.name));
            // Progress counts submitted frames (no read-back between frames).
            render_gpu(gpu, &scene, &job, |_| bar.inc(1), None)?
        }
        None => {
            bar.set_prefix("CPU");
            render_cpu(&scene, &job, |_, _| bar.inc(1))?
        }
    };
    bar.finish();
    let secs = start.elapsed().as_secs_f64();

    let (w, h) = (args.width, args.height);
    let files = [
        (args.out.join("last.png"), false, false),
        (args.out.join("mean.png"), true, false),
        (args.out.join("last.exr"), false, true),
        (args.out.join("mean.exr"), true, true),
    ];
    for (path, mean, exr) in &files {
        let pixels = if *mean { &output.mean } else { &output.last };
        if *exr {
            write_exr(path, w, h, pixels)
        } else {
            write_png(path, w, h, pixels, ToneMap::Reinhard)
        }
        .with_context(|| format!("cannot write {}", path.display()))?;
    }
    println!(
        "rendered {} frame(s) of {}x{} at {} spp on {} in {:.2} s ({:?} mode, {} sampler); wrote {}",
        args.frames,
        w,
        h,
        args.spp,
        output.device,
        secs,
        job.mode,
        args.sampler.name(),
        files
            .iter()
            .map(|f| f.0.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    Ok(())
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
