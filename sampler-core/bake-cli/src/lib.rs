//! The `bake` tool's library: file formats, the recipe of sampler-core's
//! default data, and the bake jobs the CLI and its tests share.
//!
//! # File formats (all little-endian, no header)
//!
//! - mask / dither tile `.bin`: one `u32` rank per texel, row-major.
//! - retarget tables `.bin`: the [`STEP_COUNT`] tables of one tile back to
//!   back, table `i` (baked for `step_of_index(i)`) first at byte
//!   `i * 4 * W * W`; one packed `u32` offset per texel, row-major.
//! - spatiotemporal `.bin`: one `u16` per-slice rank per texel, slice-major
//!   then row-major.
//! - slice tables `.bin`: the tables from each slice of a spatiotemporal
//!   mask to the next (the last to the first), table `z` first at byte
//!   `z * 2 * W * W`; one packed offset per texel as a `u16` (the packing's
//!   bits 16..32 are zero), row-major.
//! - screen-space sampler keys `.bin`: one `u32` key per texel, in
//!   `ScreenSobolLayout::key_index` order (spp level, then dimension pair, then
//!   row-major).
//! - vector spatiotemporal `.bin`: `f32` components, slice-major then
//!   row-major, the 2 or 3 components of a texel together.
//! - filter-adapted `.bin`: scalars as spatiotemporal `.bin` (`u16` ranks);
//!   with a non-uniform distribution or vectors also `f32` values as the
//!   vector `.bin` (`values_*.bin`) and one EXR per slice.
//!
//! PNG output maps rank `r` of `n` to `floor(r * 2^bits / n)` (8 or 16 bits
//! per texel, grey), so every level is used equally often.

use anyhow::{bail, ensure, Context, Result};
use rayon::prelude::*;
use sampler_core::bake::{
    bake_filter_adapted, bake_key_tile, bake_mask, bake_retarget_table_with, bake_slice_table, bake_stbn,
    no_progress, FilterAdaptedParams, FilterCombine, KeyParams, MaskParams, RetargetBake, SpatialFilter,
    StbnParams, SwapReport, TemporalFilter, DISPLACEMENT_COST, MAX_MASK_SIDE,
};
use sampler_core::{DitherTile, ScreenSobolLayout, SpatiotemporalMask, STEP_COUNT};
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Sigma of the default dither tiles (Wolfe et al.'s 1.9; see BENCHMARKS.md
/// for the retargeting energy it gives).
pub const DEFAULT_TILE_SIGMA: f64 = 1.9;
/// Recorded seed of the default 64x64 dither tile.
pub const DEFAULT_TILE_64_SEED: u64 = 64;
/// Recorded seed of the default 128x128 dither tile.
pub const DEFAULT_TILE_128_SEED: u64 = 128;
/// Size of the default spatiotemporal mask.
pub const DEFAULT_STBN_SIZE: (u32, u32, u32) = (128, 128, 64);
/// Size of the temporally blue permutation's default target, a smaller
/// spatiotemporal mask (same sigma and seed) whose 64x64 slices keep the
/// permutation's per-frame cost at the walk's 64x64 tile's
/// (BENCHMARKS.md, "Temporal permutation").
pub const DEFAULT_TEMPORAL_SIZE: (u32, u32, u32) = (64, 64, 64);
/// Spatial and temporal sigma of the default spatiotemporal mask.
pub const DEFAULT_STBN_SIGMA: f64 = 1.9;
/// Recorded seed of the default spatiotemporal mask.
pub const DEFAULT_STBN_SEED: u64 = 3;
/// Sweeps of the default filter-adapted mask: 8 (about 18 s with the STBN
/// start on 2 busy cores; QUALITY.md, "Filter-adapted masks").
pub const DEFAULT_FILTER_ADAPTED_SWEEPS: u32 = 8;

/// Parameters of the default filter-adapted mask: 128x128x64 uniform scalars
/// adapted to an exponential history (alpha 0.1) times a Gaussian of sigma
/// 1.3435 (product), [`DEFAULT_FILTER_ADAPTED_SWEEPS`] sweeps, seed
/// [`DEFAULT_STBN_SEED`], so it starts from the default STBN mask itself.
pub fn default_filter_adapted_params() -> FilterAdaptedParams {
    let (width, height, depth) = DEFAULT_STBN_SIZE;
    FilterAdaptedParams {
        width,
        height,
        depth,
        sweeps: DEFAULT_FILTER_ADAPTED_SWEEPS,
        seed: DEFAULT_STBN_SEED,
        ..FilterAdaptedParams::default()
    }
}

/// Recorded seed of the default screen-space sampler keys (and of their training
/// integrands).
pub const DEFAULT_KEYS_SEED: u64 = 6;

/// Weight of the line (edge) terms of the default keys (`KeyParams::line_weight`):
/// 16 gave the lowest blurred error of 4, 16, 64, 256 and 1024 on the rendered
/// Cornell box at 1 spp (QUALITY.md).
pub const DEFAULT_KEYS_LINE_WEIGHT: f64 = 16.0;

/// Parameters of the default screen-space sampler keys: 64x64 tiles, 4 dimension pairs,
/// 5 spp levels (1, 2, 4, 8, 16 spp), 128 training integrands, energy sigma `sqrt 2` (a
/// blur of 1 pixel), 256 sweeps, line terms of weight [`DEFAULT_KEYS_LINE_WEIGHT`], seed
/// [`DEFAULT_KEYS_SEED`] (the defaults of `bake keys`).
pub fn default_key_params() -> KeyParams {
    KeyParams {
        side: 64,
        pairs: 4,
        levels: 5,
        integrands: 128,
        sigma: std::f64::consts::SQRT_2,
        sweeps: 256,
        line_weight: DEFAULT_KEYS_LINE_WEIGHT,
        seed: DEFAULT_KEYS_SEED,
    }
}

/// One group of files of sampler-core's `data/` directory.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum DefaultSet {
    /// `tile_64.bin` and `tables_64.bin`.
    Tile64,
    /// `tile_128.bin` and `tables_128.bin`.
    Tile128,
    /// `stbn_128x128x64.bin`.
    Stbn,
    /// `screen_sobol_keys_64.bin`.
    Keys,
    /// `filter_adapted_128x128x64.bin`.
    FilterAdapted,
    /// `stbn_64x64x64.bin` and `stbn_64x64x64_tables.bin`: the temporally
    /// blue permutation's target ([`DEFAULT_TEMPORAL_SIZE`]) and the
    /// retarget tables between its consecutive slices.
    Temporal64,
}

impl DefaultSet {
    /// Every set, in the order `defaults` writes them.
    pub const ALL: [DefaultSet; 6] = [
        DefaultSet::Tile64,
        DefaultSet::Tile128,
        DefaultSet::Stbn,
        DefaultSet::Keys,
        DefaultSet::FilterAdapted,
        DefaultSet::Temporal64,
    ];

    /// File names this set writes.
    pub fn files(self) -> &'static [&'static str] {
        match self {
            DefaultSet::Tile64 => &["tile_64.bin", "tables_64.bin"],
            DefaultSet::Tile128 => &["tile_128.bin", "tables_128.bin"],
            DefaultSet::Stbn => &["stbn_128x128x64.bin"],
            DefaultSet::Keys => &["screen_sobol_keys_64.bin"],
            DefaultSet::FilterAdapted => &["filter_adapted_128x128x64.bin"],
            DefaultSet::Temporal64 => &["stbn_64x64x64.bin", "stbn_64x64x64_tables.bin"],
        }
    }
}

/// Files to write: `(file name, bytes)`.
pub type NamedFiles = Vec<(&'static str, Vec<u8>)>;

/// Reports progress: `(done, total)`.
pub type Report<'a> = &'a mut dyn FnMut(u64, u64);

/// `u32`s as little-endian bytes.
pub fn encode_u32(values: &[u32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// Ranks as little-endian `u16` bytes.
///
/// # Errors
/// If a rank does not fit in 16 bits.
pub fn encode_u16(values: &[u32]) -> Result<Vec<u8>> {
    let mut out = Vec::with_capacity(values.len() * 2);
    for &v in values {
        let v = u16::try_from(v).with_context(|| format!("rank {v} does not fit in 16 bits"))?;
        out.extend_from_slice(&v.to_le_bytes());
    }
    Ok(out)
}

/// Little-endian `u32`s from bytes.
///
/// # Errors
/// If the length is not a multiple of 4.
pub fn decode_u32(bytes: &[u8]) -> Result<Vec<u32>> {
    ensure!(
        bytes.len().is_multiple_of(4),
        "{} bytes is not a whole number of u32 values",
        bytes.len()
    );
    Ok(bytes
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect())
}

/// Reads a square dither tile `.bin` (the side is inferred from the length).
///
/// # Errors
/// Unreadable file, or a texel count that is not the square of a power of two.
pub fn read_tile(path: &Path) -> Result<(u32, Vec<u32>)> {
    let bytes = fs::read(path).with_context(|| format!("cannot read tile {}", path.display()))?;
    let values = decode_u32(&bytes)?;
    let side = (values.len() as f64).sqrt() as u32;
    ensure!(
        side as usize * side as usize == values.len() && side.is_power_of_two() && side >= 2,
        "tile {} holds {} texels: not a square tile with a power-of-two side",
        path.display(),
        values.len()
    );
    Ok((side, values))
}

/// Creates (truncates) a file for writing, with the path in the error.
///
/// # Errors
/// If the file cannot be created.
pub fn create_file(path: &Path) -> Result<fs::File> {
    fs::File::create(path).with_context(|| format!("cannot write {}", path.display()))
}

/// Creates a directory (and parents), with the path in the error.
///
/// # Errors
/// If it cannot be created.
pub fn create_dir(path: &Path) -> Result<()> {
    fs::create_dir_all(path).with_context(|| format!("cannot create directory {}", path.display()))
}

/// Writes `bytes` to an already created file.
///
/// # Errors
/// On I/O failure.
pub fn write_all(mut file: fs::File, path: &Path, bytes: &[u8]) -> Result<()> {
    file.write_all(bytes)
        .with_context(|| format!("cannot write {}", path.display()))
}

/// Encodes ranks `0..n` (`n = width * height`) as a grey PNG of `bits`
/// (8 or 16) per texel into `file`.
///
/// # Errors
/// Bad `bits`, or an encoding/I/O failure.
pub fn write_png(
    file: fs::File,
    path: &Path,
    width: u32,
    height: u32,
    ranks: &[u32],
    bits: u32,
) -> Result<()> {
    let n = ranks.len() as u64;
    let level = |r: u32, b: u32| ((r as u64) << b) / n;
    let encoder = image::codecs::png::PngEncoder::new(std::io::BufWriter::new(file));
    let result = match bits {
        8 => image::GrayImage::from_fn(width, height, |x, y| {
            image::Luma([level(ranks[(y * width + x) as usize], 8) as u8])
        })
        .write_with_encoder(encoder),
        16 => image::ImageBuffer::<image::Luma<u16>, Vec<u16>>::from_fn(width, height, |x, y| {
            image::Luma([level(ranks[(y * width + x) as usize], 16) as u16])
        })
        .write_with_encoder(encoder),
        _ => bail!("PNG bit depth must be 8 or 16, not {bits}"),
    };
    result.with_context(|| format!("cannot write PNG {}", path.display()))
}

/// Encodes one slice of a vector mask (`channels` = 2 or 3 components per texel) as an
/// 8-bit RGB PNG into `file`: component `v` maps to `floor(256 v)` (values in `[0, 1)`) or,
/// with `signed`, to `floor(128 (v + 1))` (unit-vector components in `[-1, 1]`), clamped
/// to 255; a missing third component is 0.
///
/// # Errors
/// Bad `channels` or length, or an encoding/I/O failure.
pub fn write_vector_png(
    file: fs::File,
    path: &Path,
    width: u32,
    height: u32,
    channels: usize,
    values: &[f32],
    signed: bool,
) -> Result<()> {
    ensure!(
        (channels == 2 || channels == 3) && values.len() == (width * height) as usize * channels,
        "vector slice {} has {} components, expected {width}x{height}x{channels}",
        path.display(),
        values.len()
    );
    let level = |v: f32| {
        let x = if signed { 128.0 * (v + 1.0) } else { 256.0 * v };
        x.clamp(0.0, 255.0) as u8
    };
    let img = image::RgbImage::from_fn(width, height, |x, y| {
        let t = &values[(y * width + x) as usize * channels..][..channels];
        image::Rgb([
            level(t[0]),
            level(t[1]),
            if channels == 3 { level(t[2]) } else { 0 },
        ])
    });
    let encoder = image::codecs::png::PngEncoder::new(std::io::BufWriter::new(file));
    img.write_with_encoder(encoder)
        .with_context(|| format!("cannot write PNG {}", path.display()))
}

/// Writes one slice of `channels` (1, 2 or 3) `f32` components per texel as
/// an RGB `f32` OpenEXR image into `file`: a scalar fills all three
/// channels (grey), a 2D vector leaves blue 0.
///
/// # Errors
/// Bad `channels` or length, or an encoding/I/O failure.
pub fn write_exr(
    file: fs::File,
    path: &Path,
    width: u32,
    height: u32,
    channels: usize,
    values: &[f32],
) -> Result<()> {
    ensure!(
        (1..=3).contains(&channels) && values.len() == (width * height) as usize * channels,
        "slice {} has {} components, expected {width}x{height}x{channels}",
        path.display(),
        values.len()
    );
    let img = image::Rgb32FImage::from_fn(width, height, |x, y| {
        let t = &values[(y * width + x) as usize * channels..][..channels];
        match channels {
            1 => image::Rgb([t[0], t[0], t[0]]),
            2 => image::Rgb([t[0], t[1], 0.0]),
            _ => image::Rgb([t[0], t[1], t[2]]),
        }
    });
    img.write_to(&mut std::io::BufWriter::new(file), image::ImageFormat::OpenExr)
        .with_context(|| format!("cannot write EXR {}", path.display()))
}

/// `f32`s as little-endian bytes.
pub fn encode_f32(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// Parses `W`, `WxH` (2D) or `WxHxD` sizes; every side a power of two in
/// `1..=MAX_MASK_SIDE`.
///
/// # Errors
/// A message naming the problem (zero, not a power of two, too many parts).
pub fn parse_size(text: &str, max_parts: usize) -> Result<Vec<u32>> {
    let parts: Vec<&str> = text.split(['x', 'X']).collect();
    ensure!(
        parts.len() <= max_parts,
        "size {text:?} has more than {max_parts} parts"
    );
    let mut sides = Vec::new();
    for p in parts {
        let v: u32 = p
            .trim()
            .parse()
            .with_context(|| format!("size {text:?}: {p:?} is not a number"))?;
        ensure!(
            v.is_power_of_two() && v <= MAX_MASK_SIDE,
            "size {text:?}: {v} is not a power of two in 1..={MAX_MASK_SIDE}"
        );
        sides.push(v);
    }
    Ok(sides)
}

/// Splits `name:a:b` into the name and its numbers.
fn parse_spec(text: &str, what: &str) -> Result<(String, Vec<f64>)> {
    let mut parts = text.split(':');
    let name = parts.next().unwrap_or("").trim().to_lowercase();
    let numbers = parts
        .map(|p| {
            p.trim()
                .parse::<f64>()
                .with_context(|| format!("{what} {text:?}: {p:?} is not a number"))
        })
        .collect::<Result<Vec<f64>>>()?;
    Ok((name, numbers))
}

/// The one integer parameter of a box or binomial filter.
fn count(text: &str, numbers: &[f64]) -> Result<u32> {
    ensure!(
        numbers.len() == 1 && numbers[0].fract() == 0.0 && numbers[0] >= 0.0,
        "filter {text:?} needs one whole number"
    );
    Ok(numbers[0] as u32)
}

/// Parses a spatial filter: `gauss:SIGMA`, `box:SIZE` or `binomial:N`
/// (ranges are checked by the bake).
///
/// # Errors
/// An unknown name or a wrong number of parameters.
pub fn parse_spatial(text: &str) -> Result<SpatialFilter> {
    let (name, v) = parse_spec(text, "spatial filter")?;
    Ok(match name.as_str() {
        "gauss" | "gaussian" if v.len() == 1 => SpatialFilter::Gaussian { sigma: v[0] },
        "box" => SpatialFilter::Box {
            size: count(text, &v)?,
        },
        "binomial" => SpatialFilter::Binomial { n: count(text, &v)? },
        _ => bail!("spatial filter {text:?} is not gauss:SIGMA, box:SIZE or binomial:N"),
    })
}

/// Parses a temporal filter: `gauss:SIGMA`, `box:SIZE`, `binomial:N`,
/// `exp:ALPHA` (the whole history) or `exp:ALPHA:BETA` (FAST's random
/// history length).
///
/// # Errors
/// An unknown name or a wrong number of parameters.
pub fn parse_temporal(text: &str) -> Result<TemporalFilter> {
    let (name, v) = parse_spec(text, "temporal filter")?;
    Ok(match (name.as_str(), v.len()) {
        ("gauss" | "gaussian", 1) => TemporalFilter::Gaussian { sigma: v[0] },
        ("box", _) => TemporalFilter::Box {
            size: count(text, &v)?,
        },
        ("binomial", _) => TemporalFilter::Binomial { n: count(text, &v)? },
        ("exp" | "exponential", 1) => TemporalFilter::Exponential { alpha: v[0] },
        ("exp" | "exponential", 2) => TemporalFilter::WeightedExponential {
            alpha: v[0],
            beta: v[1],
        },
        _ => bail!(
            "temporal filter {text:?} is not gauss:SIGMA, box:SIZE, binomial:N, exp:ALPHA or exp:ALPHA:BETA"
        ),
    })
}

/// Parses `product` or `separate:SPATIAL_WEIGHT`.
///
/// # Errors
/// Anything else.
pub fn parse_combine(text: &str) -> Result<FilterCombine> {
    let (name, v) = parse_spec(text, "combination")?;
    Ok(match (name.as_str(), v.len()) {
        ("product", 0) => FilterCombine::Product,
        ("separate", 1) => FilterCombine::Separate { spatial_weight: v[0] },
        _ => bail!("combination {text:?} is not product or separate:WEIGHT"),
    })
}

/// Bakes the tables of every step for `tile`, in parallel (one rayon task
/// per table), in index order, with `displacement_cost` per texel of
/// `|dx| + |dy|` (`sampler_core::bake::DISPLACEMENT_COST` for the defaults).
/// `done` is called once per finished table.
///
/// # Errors
/// As [`bake_retarget_table_with`].
pub fn bake_tables_parallel(
    tile: &DitherTile<'_>,
    displacement_cost: u32,
    done: &(dyn Fn() + Sync),
) -> Result<Vec<RetargetBake>> {
    (0..STEP_COUNT as u32)
        .into_par_iter()
        .map(|i| {
            let b = bake_retarget_table_with(tile, i, displacement_cost);
            done();
            b.map_err(anyhow::Error::from)
        })
        .collect()
}

/// Bakes every key tile of `params` in parallel (one rayon task per level and pair):
/// the key buffer in `ScreenSobolLayout::key_index` order and one report per tile (level
/// major, then pair). `done` is called once per finished tile. Identical to the
/// sequential `sampler_core::bake::bake_sampler_keys`.
///
/// # Errors
/// As `sampler_core::bake::bake_key_tile`.
pub fn bake_keys_parallel(
    params: &KeyParams,
    done: &(dyn Fn() + Sync),
) -> Result<(ScreenSobolLayout, Vec<u32>, Vec<SwapReport>)> {
    let layout = params.layout()?;
    let tiles: Vec<(u32, u32)> = (0..layout.levels)
        .flat_map(|l| (0..layout.pairs).map(move |p| (l, p)))
        .collect();
    let baked = tiles
        .into_par_iter()
        .map(|(level, pair)| {
            let b = bake_key_tile(params, level, pair, &mut no_progress);
            done();
            b.map_err(anyhow::Error::from)
        })
        .collect::<Result<Vec<_>>>()?;
    let mut keys = Vec::with_capacity(layout.key_count());
    let mut reports = Vec::with_capacity(baked.len());
    for (tile, report) in baked {
        keys.extend(tile);
        reports.push(report);
    }
    Ok((layout, keys, reports))
}

/// The bytes of a tables file: tables in index order, back to back.
pub fn encode_tables(tables: &[RetargetBake]) -> Vec<u8> {
    tables.iter().flat_map(|t| encode_u32(&t.packed)).collect()
}

/// Bakes a default dither tile and its tables: `(tile bytes, tables bytes, bakes)`.
///
/// # Errors
/// Propagated bake errors (none for the recorded parameters).
pub fn bake_default_tile(
    side: u32,
    seed: u64,
    report: Report<'_>,
) -> Result<(Vec<u8>, Vec<u8>, Vec<RetargetBake>)> {
    let params = MaskParams {
        width: side,
        height: side,
        sigma: DEFAULT_TILE_SIGMA,
        seed,
    };
    let ranks = bake_mask(&params, report)?;
    let tile = DitherTile::new(side, &ranks)?;
    let tables = bake_tables_parallel(&tile, DISPLACEMENT_COST, &|| {})?;
    Ok((encode_u32(&ranks), encode_tables(&tables), tables))
}

/// Bakes the default spatiotemporal mask: its `u16` bytes.
///
/// # Errors
/// Propagated bake errors (none for the recorded parameters).
pub fn bake_default_stbn(report: Report<'_>) -> Result<Vec<u8>> {
    bake_stbn_of_size(DEFAULT_STBN_SIZE, report)
}

/// A spatiotemporal mask of `size` with the default sigma and seed: its
/// `u16` bytes.
fn bake_stbn_of_size((width, height, depth): (u32, u32, u32), report: Report<'_>) -> Result<Vec<u8>> {
    let params = StbnParams {
        width,
        height,
        depth,
        sigma: DEFAULT_STBN_SIGMA,
        temporal_sigma: DEFAULT_STBN_SIGMA,
        seed: DEFAULT_STBN_SEED,
    };
    encode_u16(&bake_stbn(&params, report)?)
}

/// Bakes the temporally blue permutation's default target
/// ([`DEFAULT_TEMPORAL_SIZE`], default sigma and seed) and the retarget
/// tables between its consecutive slices: `(mask bytes, table bytes)`,
/// both `u16`, table `z` at byte `z * 2 * 64 * 64`.
///
/// # Errors
/// Propagated bake errors (none for the recorded parameters).
pub fn bake_default_temporal_target(report: Report<'_>) -> Result<(Vec<u8>, Vec<u8>)> {
    let bytes = bake_stbn_of_size(DEFAULT_TEMPORAL_SIZE, report)?;
    let tables = slice_tables_of(&bytes, DEFAULT_TEMPORAL_SIZE)?;
    Ok((bytes, tables))
}

/// The slice tables of a mask's `u16` bytes, one rayon task per slice.
fn slice_tables_of(bytes: &[u8], (width, height, depth): (u32, u32, u32)) -> Result<Vec<u8>> {
    let mask = SpatiotemporalMask::new(width, height, depth, bytes)?;
    let tables = (0..depth)
        .into_par_iter()
        .map(|z| bake_slice_table(&mask, z).map_err(anyhow::Error::from))
        .collect::<Result<Vec<_>>>()?;
    encode_u16(&tables.concat())
}

/// Bakes one default set: `(file name, bytes)` pairs, plus the retarget
/// bakes (for reporting energies; empty for the STBN set).
///
/// # Errors
/// Propagated bake errors.
pub fn bake_default_set(set: DefaultSet, report: Report<'_>) -> Result<(NamedFiles, Vec<RetargetBake>)> {
    let files = set.files();
    Ok(match set {
        DefaultSet::Tile64 | DefaultSet::Tile128 => {
            let (side, seed) = if set == DefaultSet::Tile64 {
                (64, DEFAULT_TILE_64_SEED)
            } else {
                (128, DEFAULT_TILE_128_SEED)
            };
            let (tile, tables, bakes) = bake_default_tile(side, seed, report)?;
            (vec![(files[0], tile), (files[1], tables)], bakes)
        }
        DefaultSet::Stbn => (vec![(files[0], bake_default_stbn(report)?)], Vec::new()),
        DefaultSet::Keys => {
            let (_, keys, _) = bake_keys_parallel(&default_key_params(), &|| {})?;
            (vec![(files[0], encode_u32(&keys))], Vec::new())
        }
        DefaultSet::FilterAdapted => {
            let mask = bake_filter_adapted(&default_filter_adapted_params(), report)?;
            (vec![(files[0], encode_u16(&mask.ranks)?)], Vec::new())
        }
        DefaultSet::Temporal64 => {
            let (mask, tables) = bake_default_temporal_target(report)?;
            (vec![(files[0], mask), (files[1], tables)], Vec::new())
        }
    })
}

/// The committed data directory of sampler-core (next to this crate).
pub fn committed_data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join("data")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_or_explain() {
        assert_eq!(parse_size("64", 2).unwrap(), vec![64]);
        assert_eq!(parse_size("64x32", 2).unwrap(), vec![64, 32]);
        assert_eq!(parse_size("128x128x64", 3).unwrap(), vec![128, 128, 64]);
        for bad in ["0", "48", "64x0", "x", "abc", "8192", "4x4x4"] {
            assert!(parse_size(bad, 2).is_err(), "{bad}");
        }
        assert!(parse_size("48", 2)
            .unwrap_err()
            .to_string()
            .contains("power of two"));
    }

    #[test]
    fn filter_specs_parse_or_explain() {
        assert_eq!(
            parse_spatial("gauss:1.5").unwrap(),
            SpatialFilter::Gaussian { sigma: 1.5 }
        );
        assert_eq!(parse_spatial("Box:3").unwrap(), SpatialFilter::Box { size: 3 });
        assert_eq!(
            parse_spatial("binomial:2").unwrap(),
            SpatialFilter::Binomial { n: 2 }
        );
        assert_eq!(
            parse_temporal("exp:0.1").unwrap(),
            TemporalFilter::Exponential { alpha: 0.1 }
        );
        assert_eq!(
            parse_temporal("exp:0.2:0.3").unwrap(),
            TemporalFilter::WeightedExponential {
                alpha: 0.2,
                beta: 0.3
            }
        );
        assert_eq!(parse_temporal("box:8").unwrap(), TemporalFilter::Box { size: 8 });
        assert_eq!(parse_combine("product").unwrap(), FilterCombine::Product);
        assert_eq!(
            parse_combine("separate:0.5").unwrap(),
            FilterCombine::Separate { spatial_weight: 0.5 }
        );
        for bad in ["gauss", "box:2.5", "tent:1", "box:x"] {
            assert!(parse_spatial(bad).is_err(), "{bad}");
        }
        assert!(parse_temporal("exp:0.1:0.2:0.3").is_err());
        assert!(parse_combine("separate").is_err());
    }

    #[test]
    fn encodings_round_trip() {
        let v = vec![0, 1, 0xDEAD_BEEF, u32::MAX];
        assert_eq!(decode_u32(&encode_u32(&v)).unwrap(), v);
        assert!(decode_u32(&[1, 2, 3]).is_err());
        assert_eq!(encode_u16(&[0x1234, 1]).unwrap(), vec![0x34, 0x12, 1, 0]);
        assert!(encode_u16(&[70000]).is_err());
    }
}
