//! The command line: `bake`'s subcommands and their options, parsed by clap.

use bake::DefaultSet;
use clap::{Parser, Subcommand};
use sampler_core::bake::{Distribution, FilterValue, VectorKind};
use std::path::PathBuf;

#[derive(Parser, Debug)]
#[command(
    name = "bake",
    version,
    about = "Bake blue-noise masks, spatiotemporal masks and retarget tables"
)]
pub(crate) struct Cli {
    #[command(subcommand)]
    pub(crate) command: Command,
}

#[derive(Subcommand, Debug)]
pub(crate) enum Command {
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
pub(crate) enum ValueArg {
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
pub(crate) enum DistributionArg {
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
    pub(crate) fn value(self, d: DistributionArg) -> FilterValue {
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
pub(crate) enum KindArg {
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
    pub(crate) fn kind(self) -> VectorKind {
        match self {
            KindArg::Vec2 => VectorKind::Vec2,
            KindArg::Vec3 => VectorKind::Vec3,
            KindArg::Sphere => VectorKind::UnitSphere,
            KindArg::Cosine => VectorKind::CosineHemisphere,
        }
    }
}
