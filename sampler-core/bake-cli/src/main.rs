//! `bake`: bakes blue-noise masks, spatiotemporal masks and retarget tables,
//! and regenerates sampler-core's committed defaults.
//!
//! ```text
//! bake mask --size 128 --sigma 1.5 --seed 1 --out mask.png
//! bake stbn --size 128x128x64 --out stbn/
//! bake retarget --tile tile.bin --out tables/
//! bake keys --side 64 --out keys.bin
//! bake vector-stbn --kind vec2 --size 64x64x32 --out vstbn/
//! bake filter-adapted --size 128x128x64 --spatial gauss:1.3435 --temporal exp:0.1 --out fa/
//! bake defaults --out sampler-core/data
//! ```

use anyhow::{ensure, Context, Result};
use bake::{
    bake_default_set, bake_keys_parallel, bake_tables_parallel, create_dir, create_file, default_key_params,
    encode_f32, encode_tables, encode_u16, encode_u32, parse_combine, parse_size, parse_spatial,
    parse_temporal, read_tile, write_all, write_exr, write_png, write_vector_png, DefaultSet,
};
use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use sampler_core::bake::{
    anneal_retarget_table, bake_filter_adapted, bake_mask, bake_stbn, bake_vector_stbn, mean_displacement,
    refine_filter_adapted, AnnealParams, Distribution, FilterAdaptedParams, FilterValue, KeyParams,
    MaskParams, StbnParams, VectorKind, VectorStbnParams,
};
use sampler_core::{DitherTile, STEP_COUNT};
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Parser, Debug)]
#[command(
    name = "bake",
    version,
    about = "Bake blue-noise masks, spatiotemporal masks and retarget tables"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// A 2D toroidal void-and-cluster mask (exact histogram).
    Mask {
        /// `W` or `WxH`, powers of two.
        #[arg(long)]
        size: String,
        /// Gaussian energy sigma in texels.
        #[arg(long, default_value_t = 1.9, allow_negative_numbers = true)]
        sigma: f64,
        /// Seed of the initial pattern.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Output: `.png` (grey) or `.bin` (little-endian u32 ranks).
        #[arg(long)]
        out: PathBuf,
        /// PNG bits per texel: 8 or 16.
        #[arg(long, default_value_t = 16)]
        bits: u32,
    },
    /// A scalar spatiotemporal mask: per-slice PNGs and one binary file.
    Stbn {
        /// `WxHxD`, powers of two, `W * H <= 65536`.
        #[arg(long)]
        size: String,
        /// Spatial sigma in texels.
        #[arg(long, default_value_t = 1.9, allow_negative_numbers = true)]
        sigma: f64,
        /// Temporal sigma in slices.
        #[arg(long, default_value_t = 1.9, allow_negative_numbers = true)]
        temporal_sigma: f64,
        /// Seed of the initial pattern.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Output directory: `slice_NNN.png` and `stbn_WxHxD.bin` (u16 ranks).
        #[arg(long)]
        out: PathBuf,
        /// PNG bits per texel: 8 or 16.
        #[arg(long, default_value_t = 16)]
        bits: u32,
    },
    /// The retarget tables of every walk step for a dither tile.
    Retarget {
        /// Square tile of little-endian u32 values (`mask --out X.bin`).
        #[arg(long)]
        tile: PathBuf,
        /// Output directory: `tables_W.bin`.
        #[arg(long)]
        out: PathBuf,
        /// Also run the simulated-annealing baseline with this many sweeps and print its energy.
        #[arg(long)]
        anneal: Option<u32>,
        /// Cost per texel of displacement |dx| + |dy|, in dither-rank units, added to the
        /// dither energy: larger values move seeds less (closer to where their estimate was
        /// measured) at the price of a worse fit to the next frame's tile.
        #[arg(long, default_value_t = sampler_core::bake::DISPLACEMENT_COST)]
        displacement_cost: u32,
    },
    /// Per-pixel keys of the screen-space Sobol sampler, optimised for blue-noise error.
    Keys {
        /// Tile side, a power of two.
        #[arg(long, default_value_t = 64)]
        side: u32,
        /// Dimension pairs (independent tiles per spp level).
        #[arg(long, default_value_t = 4)]
        pairs: u32,
        /// spp levels: level j is optimised for 2^j samples per pixel.
        #[arg(long, default_value_t = 5)]
        levels: u32,
        /// Training Heaviside integrands.
        #[arg(long, default_value_t = 128)]
        integrands: u32,
        /// Energy sigma in pixels (sqrt 2 targets a blur of 1 pixel).
        #[arg(long, default_value_t = std::f64::consts::SQRT_2, allow_negative_numbers = true)]
        sigma: f64,
        /// Optimiser sweeps per tile.
        #[arg(long, default_value_t = 256)]
        sweeps: u32,
        /// Weight of the line terms: edges along rows, columns and diagonals (0 leaves them out).
        #[arg(long, default_value_t = bake::DEFAULT_KEYS_LINE_WEIGHT, allow_negative_numbers = true)]
        line_weight: f64,
        /// Seed of the keys and training integrands.
        #[arg(long, default_value_t = bake::DEFAULT_KEYS_SEED)]
        seed: u64,
        /// Output `.bin`: little-endian u32 keys, level, pair, then row-major.
        #[arg(long)]
        out: PathBuf,
    },
    /// A vector spatiotemporal mask: per-slice RGB PNGs and one binary file of f32s.
    VectorStbn {
        /// What the texels hold.
        #[arg(long, value_enum)]
        kind: KindArg,
        /// `WxHxD`, powers of two.
        #[arg(long)]
        size: String,
        /// Spatial sigma in texels.
        #[arg(long, default_value_t = 1.9, allow_negative_numbers = true)]
        sigma: f64,
        /// Temporal sigma in slices.
        #[arg(long, default_value_t = 1.9, allow_negative_numbers = true)]
        temporal_sigma: f64,
        /// Optimiser sweeps.
        #[arg(long, default_value_t = 1024)]
        sweeps: u32,
        /// Seed.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Output directory: `slice_NNN.png` and `vector_stbn_KIND_WxHxD.bin`.
        #[arg(long)]
        out: PathBuf,
    },
    /// A mask adapted to a spatial and a temporal filter (FAST-style): a `.bin`
    /// of u16 ranks (scalars) and/or f32 values, PNG slices, and EXR slices
    /// for float values.
    FilterAdapted {
        /// `WxHxD`, powers of two.
        #[arg(long)]
        size: String,
        /// What the texels hold.
        #[arg(long, value_enum, default_value = "scalar")]
        value: ValueArg,
        /// Distribution of scalar values.
        #[arg(long, value_enum, default_value = "uniform")]
        distribution: DistributionArg,
        /// Spatial filter: gauss:SIGMA, box:SIZE or binomial:N.
        #[arg(long, default_value = "gauss:1.3435")]
        spatial: String,
        /// Temporal filter: gauss:SIGMA, box:SIZE, binomial:N, exp:ALPHA or exp:ALPHA:BETA.
        #[arg(long, default_value = "exp:0.1")]
        temporal: String,
        /// product, or separate:SPATIAL_WEIGHT.
        #[arg(long, default_value = "product")]
        combine: String,
        /// Optimiser sweeps.
        #[arg(long, default_value_t = 8)]
        sweeps: u32,
        /// Seed (scalars start from the STBN mask of this seed).
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Scalars: start from this u16 rank file (`stbn --out`) instead of baking STBN.
        #[arg(long)]
        start: Option<PathBuf>,
        /// Output directory.
        #[arg(long)]
        out: PathBuf,
        /// PNG bits per texel for scalar slices: 8 or 16.
        #[arg(long, default_value_t = 16)]
        bits: u32,
    },
    /// Searches ZSobol's one-sample-per-pixel placement map (prints it; the
    /// defaults reproduce `sampler_core::sequences::zsobol::ZSOBOL_PLACEMENT`).
    ZsobolPlacement {
        /// Random maps to draw (about 1 in 2000 is valid).
        #[arg(long, default_value_t = sampler_core::bake::DEFAULT_PLACEMENT_DRAWS)]
        draws: u64,
        /// Seed of the draws.
        #[arg(long, default_value_t = sampler_core::bake::DEFAULT_PLACEMENT_SEED)]
        seed: u32,
    },
    /// Regenerates sampler-core's data files from the recorded seeds.
    Defaults {
        /// Output directory (sampler-core/data to refresh the committed files).
        #[arg(long)]
        out: PathBuf,
        /// Only these sets (default: all).
        #[arg(long, value_enum)]
        only: Vec<DefaultSet>,
    },
}

/// `--value` of `filter-adapted`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum ValueArg {
    /// One value per texel (`--distribution`).
    Scalar,
    /// Points of [0, 1)^2.
    Vec2,
    /// Points of [0, 1)^3.
    Vec3,
    /// Unit vectors of the circle.
    Circle,
    /// Unit vectors of the sphere.
    Sphere,
    /// Cosine-weighted hemisphere directions (z up).
    Cosine,
}

/// `--distribution` of `filter-adapted`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum DistributionArg {
    /// Uniform on [0, 1).
    Uniform,
    /// Triangular on [-1, 1].
    Tent,
    /// Standard normal.
    Gaussian,
    /// Density (pi/4) cos(pi x / 2) on [-1, 1].
    Cosine,
}

impl ValueArg {
    fn value(self, d: DistributionArg) -> FilterValue {
        match self {
            ValueArg::Scalar => FilterValue::Scalar(match d {
                DistributionArg::Uniform => Distribution::Uniform,
                DistributionArg::Tent => Distribution::Tent,
                DistributionArg::Gaussian => Distribution::Gaussian,
                DistributionArg::Cosine => Distribution::Cosine,
            }),
            ValueArg::Vec2 => FilterValue::Vec2,
            ValueArg::Vec3 => FilterValue::Vec3,
            ValueArg::Circle => FilterValue::UnitCircle,
            ValueArg::Sphere => FilterValue::UnitSphere,
            ValueArg::Cosine => FilterValue::CosineHemisphere,
        }
    }
}

/// `--kind` of `vector-stbn`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum KindArg {
    /// Points of [0, 1)^2.
    Vec2,
    /// Points of [0, 1)^3.
    Vec3,
    /// Uniform unit vectors.
    Sphere,
    /// Cosine-weighted hemisphere directions (z up).
    Cosine,
}

impl KindArg {
    fn kind(self) -> VectorKind {
        match self {
            KindArg::Vec2 => VectorKind::Vec2,
            KindArg::Vec3 => VectorKind::Vec3,
            KindArg::Sphere => VectorKind::UnitSphere,
            KindArg::Cosine => VectorKind::CosineHemisphere,
        }
    }
}

fn bar(total: u64, what: &str) -> ProgressBar {
    let pb = ProgressBar::new(total);
    pb.set_style(
        ProgressStyle::with_template("{msg:>12} [{elapsed_precise}] {wide_bar} {pos}/{len} ({eta})")
            .expect("static template is valid"),
    );
    pb.set_message(what.to_string());
    pb
}

fn main() -> Result<()> {
    match Cli::parse().command {
        Command::Mask {
            size,
            sigma,
            seed,
            out,
            bits,
        } => mask(&size, sigma, seed, &out, bits),
        Command::Stbn {
            size,
            sigma,
            temporal_sigma,
            seed,
            out,
            bits,
        } => stbn(&size, sigma, temporal_sigma, seed, &out, bits),
        Command::Retarget {
            tile,
            out,
            anneal,
            displacement_cost,
        } => retarget(&tile, &out, anneal, displacement_cost),
        Command::Keys {
            side,
            pairs,
            levels,
            integrands,
            sigma,
            sweeps,
            line_weight,
            seed,
            out,
        } => keys(
            &KeyParams {
                side,
                pairs,
                levels,
                integrands,
                sigma,
                sweeps,
                line_weight,
                seed,
            },
            &out,
        ),
        Command::VectorStbn {
            kind,
            size,
            sigma,
            temporal_sigma,
            sweeps,
            seed,
            out,
        } => vector_stbn(kind, &size, sigma, temporal_sigma, sweeps, seed, &out),
        Command::FilterAdapted {
            size,
            value,
            distribution,
            spatial,
            temporal,
            combine,
            sweeps,
            seed,
            start,
            out,
            bits,
        } => {
            let sides = parse_size(&size, 3)?;
            ensure!(
                sides.len() == 3,
                "filter-adapted size must be WxHxD, got {size:?}"
            );
            let params = FilterAdaptedParams {
                width: sides[0],
                height: sides[1],
                depth: sides[2],
                value: value.value(distribution),
                spatial: parse_spatial(&spatial)?,
                temporal: parse_temporal(&temporal)?,
                combine: parse_combine(&combine)?,
                sweeps,
                seed,
            };
            filter_adapted(&params, start.as_deref(), &out, bits)
        }
        Command::ZsobolPlacement { draws, seed } => zsobol_placement(draws, seed),
        Command::Defaults { out, only } => defaults(&out, &only),
    }
}

fn zsobol_placement(draws: u64, seed: u32) -> Result<()> {
    let start = std::time::Instant::now();
    let found = sampler_core::bake::search_placement(draws, seed)
        .with_context(|| format!("none of the {draws} maps drawn with seed {seed} is valid"))?;
    let masks: Vec<String> = found.map.iter().map(|m| format!("{m:#x}")).collect();
    println!("[{}]", masks.join(", "));
    println!(
        "edge scores (white = 1, {} trials): rows {:.3}, columns {:.3}; {} valid of {draws} drawn; {:.1} s; committed map: {}",
        sampler_core::bake::FINAL_TRIALS,
        found.scores.0,
        found.scores.1,
        found.valid,
        start.elapsed().as_secs_f64(),
        if found.map == sampler_core::sequences::zsobol::ZSOBOL_PLACEMENT { "same" } else { "different" }
    );
    Ok(())
}

fn check_bits(bits: u32) -> Result<()> {
    ensure!(bits == 8 || bits == 16, "--bits must be 8 or 16, not {bits}");
    Ok(())
}

fn mask(size: &str, sigma: f64, seed: u64, out: &Path, bits: u32) -> Result<()> {
    let sides = parse_size(size, 2)?;
    let (width, height) = (sides[0], *sides.get(1).unwrap_or(&sides[0]));
    let ext = out.extension().and_then(|e| e.to_str()).unwrap_or("");
    ensure!(
        ext == "png" || ext == "bin",
        "output {} must end in .png or .bin",
        out.display()
    );
    check_bits(bits)?;
    let file = create_file(out)?; // fail before a long bake
    let pb = bar((width * height) as u64, "mask");
    let start = Instant::now();
    let ranks = bake_mask(
        &MaskParams {
            width,
            height,
            sigma,
            seed,
        },
        &mut |d, _| pb.set_position(d),
    )?;
    pb.finish_and_clear();
    eprintln!(
        "baked {width}x{height} sigma {sigma} seed {seed} in {:.3} s",
        start.elapsed().as_secs_f64()
    );
    if ext == "png" {
        write_png(file, out, width, height, &ranks, bits)
    } else {
        write_all(file, out, &encode_u32(&ranks))
    }
}

fn stbn(size: &str, sigma: f64, temporal_sigma: f64, seed: u64, out: &Path, bits: u32) -> Result<()> {
    let sides = parse_size(size, 3)?;
    ensure!(
        sides.len() == 3,
        "spatiotemporal size must be WxHxD, got {size:?}"
    );
    let (width, height, depth) = (sides[0], sides[1], sides[2]);
    ensure!(
        width as u64 * height as u64 <= 1 << 16,
        "a {width}x{height} slice has more than 65536 texels: its ranks do not fit the u16 file format"
    );
    check_bits(bits)?;
    create_dir(out)?;
    let bin_path = out.join(format!("stbn_{width}x{height}x{depth}.bin"));
    let bin = create_file(&bin_path)?;
    let total = width as u64 * height as u64 * depth as u64;
    let pb = bar(total, "stbn");
    let start = Instant::now();
    let params = StbnParams {
        width,
        height,
        depth,
        sigma,
        temporal_sigma,
        seed,
    };
    let ranks = bake_stbn(&params, &mut |d, _| pb.set_position(d))?;
    pb.finish_and_clear();
    eprintln!(
        "baked {width}x{height}x{depth} in {:.3} s",
        start.elapsed().as_secs_f64()
    );
    write_all(bin, &bin_path, &encode_u16(&ranks)?)?;
    let n = (width * height) as usize;
    for (z, slice) in ranks.chunks(n).enumerate() {
        let path = out.join(format!("slice_{z:03}.png"));
        write_png(create_file(&path)?, &path, width, height, slice, bits)?;
    }
    Ok(())
}

fn retarget(tile_path: &Path, out: &Path, anneal: Option<u32>, displacement_cost: u32) -> Result<()> {
    let (side, values) = read_tile(tile_path)?;
    let tile = DitherTile::new(side, &values).context("invalid dither tile")?;
    create_dir(out)?;
    let path = out.join(format!("tables_{side}.bin"));
    let file = create_file(&path)?;
    let pb = bar(STEP_COUNT as u64, "tables");
    let start = Instant::now();
    let tables = bake_tables_parallel(&tile, displacement_cost, &|| pb.inc(1))?;
    pb.finish_and_clear();
    println!(
        "{side}x{side} tile: {STEP_COUNT} tables in {:.3} s",
        start.elapsed().as_secs_f64()
    );
    for t in &tables {
        println!(
            "table {} step ({}, {}): energy identity {} -> exact {} (ratio {:.5}, {} bids), mean displacement {:.2}",
            t.index,
            t.step.x,
            t.step.y,
            t.energy_identity,
            t.energy,
            t.energy_ratio(),
            t.bids,
            mean_displacement(&t.packed)
        );
    }
    if let Some(sweeps) = anneal {
        for i in 0..STEP_COUNT as u32 {
            let start = Instant::now();
            let a = anneal_retarget_table(
                &tile,
                i,
                &AnnealParams {
                    sweeps,
                    ..AnnealParams::default()
                },
            )?;
            println!(
                "table {i}: annealing ({sweeps} sweeps, {:.2} s): energy {} (ratio {:.5})",
                start.elapsed().as_secs_f64(),
                a.energy,
                a.energy_ratio()
            );
        }
    }
    write_all(file, &path, &encode_tables(&tables))
}

fn keys(params: &KeyParams, out: &Path) -> Result<()> {
    let layout = params.layout()?;
    let file = create_file(out)?; // fail before a long bake
    let pb = bar((layout.levels * layout.pairs) as u64, "keys");
    let start = Instant::now();
    let (_, keys, reports) = bake_keys_parallel(params, &|| pb.inc(1))?;
    pb.finish_and_clear();
    println!(
        "{}x{} keys, {} pairs, {} levels, {} integrands, sigma {}, {} sweeps, seed {}: {:.3} s",
        params.side,
        params.side,
        params.pairs,
        params.levels,
        params.integrands,
        params.sigma,
        params.sweeps,
        params.seed,
        start.elapsed().as_secs_f64()
    );
    for (t, r) in reports.iter().enumerate() {
        println!(
            "level {} pair {}: energy {:.5} -> {:.5}, {} of {} swaps accepted",
            t as u32 / layout.pairs,
            t as u32 % layout.pairs,
            r.energy_before,
            r.energy_after,
            r.accepted,
            r.trials
        );
    }
    if params == &default_key_params() {
        println!("(these are the parameters of the committed defaults)");
    }
    write_all(file, out, &encode_u32(&keys))
}

fn vector_stbn(
    kind: KindArg,
    size: &str,
    sigma: f64,
    temporal_sigma: f64,
    sweeps: u32,
    seed: u64,
    out: &Path,
) -> Result<()> {
    let sides = parse_size(size, 3)?;
    ensure!(sides.len() == 3, "vector mask size must be WxHxD, got {size:?}");
    let (width, height, depth) = (sides[0], sides[1], sides[2]);
    create_dir(out)?;
    let name = format!("{kind:?}").to_lowercase();
    let bin_path = out.join(format!("vector_stbn_{name}_{width}x{height}x{depth}.bin"));
    let bin = create_file(&bin_path)?;
    let params = VectorStbnParams {
        width,
        height,
        depth,
        kind: kind.kind(),
        sigma,
        temporal_sigma,
        sweeps,
        seed,
    };
    let pb = bar(0, "vector-stbn");
    let start = Instant::now();
    let mask = bake_vector_stbn(&params, &mut |d, t| {
        pb.set_length(t);
        pb.set_position(d)
    })?;
    pb.finish_and_clear();
    println!(
        "{name} {width}x{height}x{depth}: baked in {:.3} s, energy {:.5} -> {:.5}, {} of {} swaps accepted",
        start.elapsed().as_secs_f64(),
        mask.report.energy_before,
        mask.report.energy_after,
        mask.report.accepted,
        mask.report.trials
    );
    write_all(bin, &bin_path, &encode_f32(&mask.values))?;
    let c = params.kind.channels() as usize;
    let signed = matches!(params.kind, VectorKind::UnitSphere | VectorKind::CosineHemisphere);
    for (z, slice) in mask.values.chunks((width * height) as usize * c).enumerate() {
        let path = out.join(format!("slice_{z:03}.png"));
        write_vector_png(create_file(&path)?, &path, width, height, c, slice, signed)?;
    }
    Ok(())
}

fn filter_adapted(params: &FilterAdaptedParams, start: Option<&Path>, out: &Path, bits: u32) -> Result<()> {
    let (width, height, depth) = (params.width, params.height, params.depth);
    let scalar = matches!(params.value, FilterValue::Scalar(_));
    ensure!(
        !scalar || width as u64 * height as u64 <= 1 << 16,
        "a {width}x{height} slice has more than 65536 texels: its ranks do not fit the u16 file format"
    );
    check_bits(bits)?;
    let start_ranks = match start {
        Some(path) => {
            ensure!(scalar, "--start only applies to scalar masks");
            let bytes = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
            ensure!(
                bytes.len() == 2 * (width * height * depth) as usize,
                "{} has {} bytes, not the 2 x {width}x{height}x{depth} of u16 ranks",
                path.display(),
                bytes.len()
            );
            Some(
                bytes
                    .chunks_exact(2)
                    .map(|c| u16::from_le_bytes([c[0], c[1]]) as u32)
                    .collect::<Vec<u32>>(),
            )
        }
        None => None,
    };
    create_dir(out)?;
    let pb = bar(0, "filter-adapted");
    let start_time = Instant::now();
    let mut report = |d, t| {
        pb.set_length(t);
        pb.set_position(d)
    };
    let mask = match &start_ranks {
        Some(r) => refine_filter_adapted(params, r, &mut report)?,
        None => bake_filter_adapted(params, &mut report)?,
    };
    pb.finish_and_clear();
    println!(
        "{width}x{height}x{depth} {:?}, {:?} x {:?} ({:?}), {} sweeps: baked in {:.3} s, energy {:.5} -> {:.5}, {} of {} swaps accepted",
        params.value,
        params.spatial,
        params.temporal,
        params.combine,
        params.sweeps,
        start_time.elapsed().as_secs_f64(),
        mask.report.energy_before,
        mask.report.energy_after,
        mask.report.accepted,
        mask.report.trials
    );
    let n = (width * height) as usize;
    let c = params.value.channels() as usize;
    let floats = !matches!(params.value, FilterValue::Scalar(Distribution::Uniform));
    if scalar {
        let path = out.join(format!("filter_adapted_{width}x{height}x{depth}.bin"));
        write_all(create_file(&path)?, &path, &encode_u16(&mask.ranks)?)?;
        for (z, slice) in mask.ranks.chunks(n).enumerate() {
            let path = out.join(format!("slice_{z:03}.png"));
            write_png(create_file(&path)?, &path, width, height, slice, bits)?;
        }
    } else {
        let signed = !matches!(params.value, FilterValue::Vec2 | FilterValue::Vec3);
        for (z, slice) in mask.values.chunks(n * c).enumerate() {
            let path = out.join(format!("slice_{z:03}.png"));
            write_vector_png(create_file(&path)?, &path, width, height, c, slice, signed)?;
        }
    }
    if floats {
        let path = out.join(format!("values_{width}x{height}x{depth}.bin"));
        write_all(create_file(&path)?, &path, &encode_f32(&mask.values))?;
        for (z, slice) in mask.values.chunks(n * c).enumerate() {
            let path = out.join(format!("slice_{z:03}.exr"));
            write_exr(create_file(&path)?, &path, width, height, c, slice)?;
        }
    }
    Ok(())
}

fn defaults(out: &Path, only: &[DefaultSet]) -> Result<()> {
    create_dir(out)?;
    let sets = if only.is_empty() {
        DefaultSet::ALL.to_vec()
    } else {
        only.to_vec()
    };
    for set in sets {
        // Check writability before baking.
        let files = set
            .files()
            .iter()
            .map(|name| Ok((out.join(name), create_file(&out.join(name))?)))
            .collect::<Result<Vec<_>>>()?;
        let pb = bar(0, &format!("{set:?}"));
        let start = Instant::now();
        let (outputs, bakes) = bake_default_set(set, &mut |d, t| {
            pb.set_length(t);
            pb.set_position(d)
        })?;
        pb.finish_and_clear();
        println!("{set:?}: baked in {:.3} s", start.elapsed().as_secs_f64());
        for t in &bakes {
            println!(
                "  table {}: energy identity {} -> {} (ratio {:.5})",
                t.index,
                t.energy_identity,
                t.energy,
                t.energy_ratio()
            );
        }
        for ((path, file), (_, bytes)) in files.into_iter().zip(outputs) {
            write_all(file, &path, &bytes)?;
            println!("  wrote {} ({} bytes)", path.display(), bytes.len());
        }
    }
    Ok(())
}
