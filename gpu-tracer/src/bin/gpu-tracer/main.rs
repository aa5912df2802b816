//! `gpu-tracer`: renders a scene with the blue-noise seed permutation on the
//! GPU (wgpu, kernels compiled by rust-gpu), falling back to the CPU renderer
//! where no GPU adapter exists.
//!
//! ```text
//! gpu-tracer render --scene cornell --width 512 --height 512 --frames 16 --out out
//! ```

mod args;
mod device;
mod output;
mod scene_setup;

use anyhow::{bail, Context, Result};
use args::{Cli, Command, FeatureKeyArg, ModeArg, OnOff, RenderArgs, SamplerArg, SeedModeArg};
use clap::{Parser, ValueEnum};
use device::open_device;
use gpu_tracer::feature_keys::FeatureKey;
use gpu_tracer::filter::{FilterChain, FilterSettings, SequenceFilter};
use gpu_tracer::method_choice::{
    choose_method, default_reproject_follow_share, default_reproject_hold_below, History,
};
use gpu_tracer::{
    render_sequence_cpu, render_sequence_gpu, FrameView, PermuteMode, RenderJob, SequenceOptions, TileChoice,
    TraceSettings,
};
use indicatif::{ProgressBar, ProgressStyle};
use kernels::abi::{SAMPLER_KIND_MASK, SAMPLER_ZSOBOL, SEED_MODE_ADVANCE, SEED_MODE_FIXED};
use output::{filter_frame, prepare_out_dir, save_frame, write_results};
use scene_setup::prepare_scene;
use std::time::Instant;

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
    let (mut sequence, environment) = prepare_scene(&args)?;
    let mut settings = TraceSettings::new(args.width, args.height);
    settings.spp = args.spp;
    settings.max_depth = args.max_depth;
    settings.environment = environment;
    settings.glossy_regularization = args.glossy_regularization;
    settings.seed_mode = match args.seed_mode {
        SeedModeArg::Fixed => SEED_MODE_FIXED,
        SeedModeArg::Advance => SEED_MODE_ADVANCE,
    };
    let tile_arg = args.tile;
    let named_sampler = args.sampler.map(SamplerArg::flags);
    let spatiotemporal = matches!(
        args.sampler,
        Some(SamplerArg::Spatiotemporal | SamplerArg::SpatiotemporalKronecker)
    );
    match (args.mode, spatiotemporal) {
        (Some(ModeArg::Hold), _) if named_sampler.is_some_and(|s| !gpu_tracer::render::hold_takes(s)) => {
            bail!(
                "--mode hold keeps every pixel's numbers from frame to frame: only --sampler spatiotemporal \
             (or spatiotemporal-kronecker) and --sampler zsobol, which advance their own sequence every \
             frame, can use it"
            )
        }
        (Some(m @ (ModeArg::Sort | ModeArg::Permute | ModeArg::Temporal)), true) => bail!(
            "--mode {} has nothing to permute with --sampler spatiotemporal, which draws every number \
             itself: use --mode hold (its default) or white",
            m.to_possible_value()
                .map(|v| v.get_name().to_owned())
                .unwrap_or_default()
        ),
        _ => {}
    }
    let history = match args.taa_clamp {
        OnOff::On => History::Clamped,
        OnOff::Off => History::Unclamped,
    };
    let choice = choose_method(
        args.mode.map(ModeArg::mode),
        named_sampler,
        tile_arg,
        history,
        &settings,
    );
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
    if args.taa_clamp == OnOff::Off && !matches!(args.filter, FilterChain::Taa | FilterChain::TaaAtrous) {
        bail!("--taa-clamp applies to the history: add --filter taa or --filter taa+atrous");
    }
    let mut filter = SequenceFilter::new(
        args.filter,
        FilterSettings {
            alpha: args.taa_alpha,
            clamp: args.taa_clamp == OnOff::On,
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
        reproject_hold_below: args
            .reproject_hold_below
            .unwrap_or_else(|| default_reproject_hold_below(job.mode)),
        reproject_follow_share: args
            .reproject_follow_share
            .unwrap_or_else(|| default_reproject_follow_share(job.mode)),
        pan_offset: args.pan_offset == OnOff::On,
        features,
        feature_key: match args.feature_key {
            FeatureKeyArg::Demodulated => FeatureKey::Demodulated,
            FeatureKeyArg::Raw => FeatureKey::Raw,
            FeatureKeyArg::History => FeatureKey::HistoryResidual,
        },
    };
    // Settings the mode cannot take fail here, before any work.
    job.validate()?;

    let gpu = open_device(args.device)?;

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

    let last_filtered = filtering.then_some(last_filtered.as_slice());
    let files = write_results(&args, &output, last_filtered)?;
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
        "rendered {} frame(s) of {}x{} at {} spp on {} in {:.2} s ({:?} mode, {} sampler, reprojection {}, features {}, filter {}{}); wrote {}{saved}",
        args.frames,
        w,
        h,
        args.spp,
        output.device,
        secs,
        job.mode,
        sampler_name,
        if !reproject {
            "off".to_string()
        } else if options.reproject_hold_below > 0.0 && options.reproject_follow_share > 0.0 {
            format!(
                "on from {} px/frame, everywhere in frames {} rigid{}",
                options.reproject_hold_below,
                options.reproject_follow_share,
                if options.pan_offset && job.settings.sampler & SAMPLER_KIND_MASK == SAMPLER_ZSOBOL {
                    ", ZSobol following them"
                } else {
                    ""
                }
            )
        } else if options.reproject_hold_below > 0.0 {
            format!("on from {} px/frame", options.reproject_hold_below)
        } else {
            "on".to_string()
        },
        if features {
            format!("on, {} key", options.feature_key.name())
        } else {
            "off".to_string()
        },
        args.filter,
        if args.glossy_regularization > 0.0 {
            format!(", glossy regularization {}", args.glossy_regularization)
        } else {
            String::new()
        },
        files
            .iter()
            .map(|f| f.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    Ok(())
}
