//! `conformance report --out DIR [--size N --frames N --ref-spp N]`: the rendered-quality
//! study of the seed permutation (issue 5) as an HTML page with images and plots.
//!
//! `conformance study [--size N --frames N --ref-spp N --methods a,b,... --scene S
//! --modulate-by S]`: the static study (`conformance::study`) for chosen rows only,
//! printed as markdown tables (whole image, per region, feature diagnostics; with
//! `--modulate-by`, the insets' LF with the error multiplied by another scene's albedo).
//!
//! `conformance motion [--size N --frames N --ref-spp N --methods a,b,... --speeds A,B --pan-speeds P,Q
//! --object-speed C --history-fetch nearest|bilinear]`: the study in motion (issue 13,
//! `conformance::motion`), printed as markdown tables.

use anyhow::Result;
use clap::{Parser, Subcommand};
use conformance::motion::{markdown, run_study, HistoryFetch, MotionCase, MotionConfig, MotionMethod};
use conformance::report::{write_report, ReportConfig};
use conformance::study::{default_cache_dir, Method, Study, StudyConfig, StudyScene};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::PathBuf;

#[derive(Parser, Debug)]
#[command(version, about = "Quality measurements of the blue-noise seed permutation")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render the Cornell box with every method and write DIR/index.html.
    Report {
        /// Output directory (created if missing).
        #[arg(long)]
        out: PathBuf,
        /// Image side in pixels (at least 32).
        #[arg(long, default_value_t = 256, value_parser = clap::value_parser!(u32).range(32..=2048))]
        size: u32,
        /// Frames for the single-frame figures (4 spp run); the 1-spp run renders twice
        /// as many for the accumulation figure.
        #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..=4096))]
        frames: u32,
        /// Samples per pixel of the reference.
        #[arg(long, default_value_t = 1024, value_parser = clap::value_parser!(u32).range(2..=1_000_000))]
        ref_spp: u32,
        /// Maximum path length in segments (2 = direct light only).
        #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=64))]
        max_depth: u32,
        /// Do not read or write the reference cache under target/quality-cache.
        #[arg(long)]
        no_cache: bool,
    },
    /// Render the still Cornell box with the chosen methods (1 spp) and print markdown
    /// tables: whole image, blurred RMSE per region, feature diagnostics.
    Study {
        /// Image side in pixels (at least 32).
        #[arg(long, default_value_t = 256, value_parser = clap::value_parser!(u32).range(32..=2048))]
        size: u32,
        /// Frames per method.
        #[arg(long, default_value_t = 128, value_parser = clap::value_parser!(u32).range(1..=4096))]
        frames: u32,
        /// Samples per pixel of the reference.
        #[arg(long, default_value_t = 1024, value_parser = clap::value_parser!(u32).range(2..=1_000_000))]
        ref_spp: u32,
        /// Maximum path length in segments.
        #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=64))]
        max_depth: u32,
        /// Rows, by name (white is always measured: every figure is relative to it).
        /// Default: white, permute, permute-jitter, feature-permute,
        /// feature-permute-jitter.
        #[arg(long, value_delimiter = ',')]
        methods: Vec<String>,
        /// The draw: salt of the initial white-noise seeds and of where the a-priori
        /// samplers' per-pixel data sits on the screen (1: as baked; the scatter
        /// between salts shows how far single runs can be trusted).
        #[arg(long, default_value_t = 1)]
        salt: u32,
        /// Run the study at this many consecutive salts from --salt (draws) and end
        /// with a table of each row's headline figures: mean and range over the
        /// draws. Single-draw differences of a few percent are not evidence.
        #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=16))]
        draws: u32,
        /// Scene: cornell, cornell-textured (the checker-textured glTF of the
        /// demodulation study), cornell-untextured (the same with each texture
        /// replaced by its mean colour), cornell-glossy (three GGX spheres,
        /// roughness 0.1, 0.3, 0.6) or sun-sky (objects on open ground under a
        /// sun with a disk and a constant sky; its own camera and insets).
        #[arg(long, default_value = "cornell")]
        scene: String,
        /// Path regularisation of every row, white and the reference, in [0, 1] (0:
        /// off): the tables then also give its bias against the unbiased reference and
        /// its effect on white's noise.
        #[arg(long, default_value_t = 0.0)]
        glossy_regularization: f32,
        /// Also measure the insets' LF with the error multiplied by this scene's albedo
        /// over the rendered scene's (same room and camera: cornell-textured over
        /// cornell-untextured tells what the texture's modulation alone does).
        #[arg(long)]
        modulate_by: Option<String>,
        /// TAA clamps its history to the current frame's 3x3 colour box (`on`, what a
        /// renderer runs); `off` measures what the clamp costs each row (a diagnostic:
        /// the filter's own bias and every ratio change with it).
        #[arg(long, default_value = "on", value_parser = ["on", "off"])]
        taa_clamp: String,
        /// Also write the tables to this file.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Do not read or write the reference cache under target/quality-cache.
        #[arg(long)]
        no_cache: bool,
    },
    /// Render the Cornell box in motion (camera orbit, moving block) and a still
    /// sequence with the motion study's rows; print markdown tables.
    Motion {
        /// Image side in pixels (at least 32).
        #[arg(long, default_value_t = 256, value_parser = clap::value_parser!(u32).range(32..=2048))]
        size: u32,
        /// Frames per sequence and method (1 spp).
        #[arg(long, default_value_t = 128, value_parser = clap::value_parser!(u32).range(1..=4096))]
        frames: u32,
        /// Samples per pixel of each pose's reference. 128 keeps a full run (84 distinct
        /// poses at 256x256) near half an hour on 2 cores; its noise is subtracted from
        /// the EMA figures.
        #[arg(long, default_value_t = 128, value_parser = clap::value_parser!(u32).range(2..=1_000_000))]
        ref_spp: u32,
        /// Maximum path length in segments.
        #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=64))]
        max_depth: u32,
        /// Rows, by key (white is always measured: every figure is relative to
        /// it). Default: every row. Keys: white, permute, permute-reproject,
        /// permute-jitter-reproject, feature-permute-reproject, screen-sobol,
        /// spatiotemporal, spatiotemporal-follow, spatiotemporal-kronecker-follow,
        /// zsobol, zsobol-follow, temporal-permute-jitter, temporal-permute-jitter-reproject,
        /// feature-temporal-permute-jitter-reproject,
        /// temporal-permute-jitter-reproject-fast.
        #[arg(long, value_delimiter = ',')]
        methods: Vec<String>,
        /// Orbit speeds at the image centre, pixels per frame.
        #[arg(long, value_delimiter = ',', default_values_t = [0.5f32, 2.0])]
        speeds: Vec<f32>,
        /// Camera pan speeds at the image centre, pixels per frame (none by default).
        #[arg(long, value_delimiter = ',')]
        pan_speeds: Vec<f32>,
        /// Speed of the moving block's centre, pixels per frame (0: no object sequence).
        #[arg(long, default_value_t = 1.0)]
        object_speed: f32,
        /// Sway period in frames, a multiple of 4 (default: size / 4; shorter periods
        /// keep fast orbits inside the room).
        #[arg(long)]
        sway_period: Option<u32>,
        /// How the EMA's history reads its previous value: `nearest` (the pixel
        /// that contains it) or `bilinear` (as TAA reads it; resamples at sub-pixel
        /// precision and blurs).
        #[arg(long, default_value = "nearest", value_parser = parse_history_fetch)]
        history_fetch: HistoryFetch,
        /// Also write the tables to this file.
        #[arg(long)]
        out: Option<PathBuf>,
        /// The draw: salt of the white-noise seeds every row starts from and of
        /// where the a-priori samplers' per-pixel data sits on the screen (1: as
        /// baked; the scatter between salts shows how far single runs can be
        /// trusted).
        #[arg(long, default_value_t = 1)]
        salt: u32,
        /// Run the study at this many consecutive salts from --salt (draws) and end
        /// with every figure's mean and range over the draws and the rows' paired
        /// differences against the first row.
        #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=16))]
        draws: u32,
        /// Do not read or write the reference cache under target/quality-cache.
        #[arg(long)]
        no_cache: bool,
    },
}

fn main() -> Result<()> {
    // Before any thread: keeps Mesa's "XDG_RUNTIME_DIR is invalid" line away.
    gpu_tracer::gpu::prepare_headless_environment();
    match Cli::parse().command {
        Command::Report {
            out,
            size,
            frames,
            ref_spp,
            max_depth,
            no_cache,
        } => {
            let cfg = ReportConfig {
                size,
                frames,
                ref_spp,
                max_depth,
            };
            let cache = default_cache_dir();
            let bar = ProgressBar::new(1);
            bar.set_style(
                ProgressStyle::with_template("{msg:>18} [{bar:40}] {pos}/{len} {elapsed}")
                    .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
            let start = std::time::Instant::now();
            let results = write_report(
                &cfg,
                &out,
                (!no_cache).then_some(cache.as_path()),
                |label, done, total| {
                    bar.set_message(label.to_string());
                    bar.set_length(total);
                    bar.set_position(done);
                },
            )?;
            bar.finish_and_clear();
            for r in &results {
                println!("{}", r.summary());
            }
            println!(
                "wrote {} in {:.1} s",
                out.join("index.html").display(),
                start.elapsed().as_secs_f64()
            );
            Ok(())
        }
        Command::Study {
            size,
            frames,
            ref_spp,
            max_depth,
            methods,
            salt,
            draws,
            scene,
            glossy_regularization,
            modulate_by,
            taa_clamp,
            out,
            no_cache,
        } => {
            let scene_named = |name: &str| {
                StudyScene::from_name(name).ok_or_else(|| {
                    let known: Vec<&str> = StudyScene::ALL.iter().map(|s| s.name()).collect();
                    anyhow::anyhow!("unknown scene {name:?} (known: {})", known.join(", "))
                })
            };
            let scene = scene_named(&scene)?;
            let modulate_by = modulate_by.as_deref().map(scene_named).transpose()?;
            let mut rows = vec![Method::White];
            if methods.is_empty() {
                rows = Method::FEATURE_ROWS.to_vec();
            }
            for name in &methods {
                let m = Method::from_name(name).ok_or_else(|| {
                    let known: Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
                    anyhow::anyhow!("unknown method {name:?} (known: {})", known.join(", "))
                })?;
                if !rows.contains(&m) {
                    rows.push(m);
                }
            }
            let cache = default_cache_dir();
            let start = std::time::Instant::now();
            let config = StudyConfig {
                max_depth,
                salt,
                scene,
                modulate_by,
                glossy_regularization,
                taa_clamp: taa_clamp == "on",
                ..StudyConfig::new(size, 1, frames, ref_spp)
            };
            // The scene, reference, insets and regions do not depend on the
            // salt: set up once, then render each draw.
            let mut study = Study::new(config, (!no_cache).then_some(cache.as_path()), |_, _| {})?;
            eprintln!("[{:7.1} s] reference ready", start.elapsed().as_secs_f64());
            let mut tables = String::new();
            let mut results = Vec::new();
            for draw in 0..draws {
                study.config.salt = salt.wrapping_add(draw);
                eprintln!(
                    "[{:7.1} s] salt {}",
                    start.elapsed().as_secs_f64(),
                    study.config.salt
                );
                let result = study.run(&rows, |m, t| {
                    if t + 1 == frames {
                        eprintln!("[{:7.1} s] {} done", start.elapsed().as_secs_f64(), m.name());
                    }
                })?;
                let draw_tables = result.markdown();
                println!("{}", result.summary());
                println!("{draw_tables}");
                tables += &draw_tables;
                results.push(result);
            }
            if draws > 1 {
                let table = conformance::study::draws_markdown(&results);
                println!("{table}");
                tables += "\n";
                tables += &table;
            }
            println!("total {:.1} s", start.elapsed().as_secs_f64());
            if let Some(path) = out {
                std::fs::write(&path, &tables)?;
            }
            Ok(())
        }
        Command::Motion {
            size,
            frames,
            ref_spp,
            max_depth,
            methods,
            speeds,
            pan_speeds,
            object_speed,
            sway_period,
            history_fetch,
            salt,
            draws,
            out,
            no_cache,
        } => {
            let rows = MotionMethod::rows_named(&methods)?;
            let config = MotionConfig {
                max_depth,
                sway_period,
                history_fetch,
                salt,
                ..MotionConfig::new(size, frames, ref_spp)
            };
            let mut cases: Vec<MotionCase> = speeds
                .iter()
                .map(|&px_per_frame| MotionCase::Orbit { px_per_frame })
                .chain(
                    pan_speeds
                        .iter()
                        .map(|&px_per_frame| MotionCase::Pan { px_per_frame }),
                )
                .collect();
            if object_speed != 0.0 {
                cases.push(MotionCase::Object {
                    px_per_frame: object_speed,
                });
            }
            let cache = default_cache_dir();
            let start = std::time::Instant::now();
            let mut tables = String::new();
            let mut per_draw = Vec::new();
            for draw in 0..draws {
                let config = MotionConfig {
                    salt: salt.wrapping_add(draw),
                    ..config
                };
                let results = run_study(
                    config,
                    &cases,
                    &rows,
                    (!no_cache).then_some(cache.as_path()),
                    |msg| {
                        eprintln!(
                            "[{:7.1} s] salt {}: {msg}",
                            start.elapsed().as_secs_f64(),
                            config.salt
                        )
                    },
                )?;
                let draw_tables = markdown(&results);
                println!("{draw_tables}");
                tables += &draw_tables;
                per_draw.push(results);
            }
            if draws > 1 {
                let table = conformance::motion::draws_markdown(&per_draw);
                println!("{table}");
                tables += "\n";
                tables += &table;
            }
            println!("total {:.1} s", start.elapsed().as_secs_f64());
            if let Some(path) = out {
                std::fs::write(&path, &tables)?;
            }
            Ok(())
        }
    }
}

/// `--history-fetch`: `nearest` or `bilinear`.
fn parse_history_fetch(s: &str) -> Result<HistoryFetch, String> {
    match s {
        "nearest" => Ok(HistoryFetch::Nearest),
        "bilinear" => Ok(HistoryFetch::Bilinear),
        other => Err(format!("unknown history fetch {other:?}: nearest or bilinear")),
    }
}
