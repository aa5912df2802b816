//! `conformance report --out DIR [--size N --frames N --ref-spp N]`: the rendered-quality
//! study of the seed permutation (issue 5) as an HTML page with images and plots.

use anyhow::Result;
use clap::{Parser, Subcommand};
use conformance::render_study::default_cache_dir;
use conformance::report::{write_report, ReportConfig};
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
}

fn main() -> Result<()> {
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
    }
}
