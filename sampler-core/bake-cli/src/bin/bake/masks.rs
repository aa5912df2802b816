//! Blue-noise masks: 2D void-and-cluster masks, spatiotemporal (STBN) masks,
//! vector-valued STBN and filter-adapted masks, written as PNG, EXR or raw
//! little-endian words.

use anyhow::{ensure, Context, Result};
use bake::{
    create_dir, create_file, encode_f32, encode_u16, encode_u32, parse_size, write_all, write_exr, write_png,
    write_vector_png,
};
use sampler_core::bake::{
    bake_filter_adapted, bake_mask, bake_stbn, bake_vector_stbn, refine_filter_adapted, Distribution,
    FilterAdaptedParams, FilterValue, MaskParams, StbnParams, VectorKind, VectorStbnParams,
};
use std::path::Path;
use std::time::Instant;

use crate::args::KindArg;
use crate::progress::bar;

pub(crate) fn check_bits(bits: u32) -> Result<()> {
    ensure!(bits == 8 || bits == 16, "--bits must be 8 or 16, not {bits}");
    Ok(())
}

pub(crate) fn mask(size: &str, sigma: f64, seed: u64, out: &Path, bits: u32) -> Result<()> {
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

pub(crate) fn stbn(
    size: &str,
    sigma: f64,
    temporal_sigma: f64,
    seed: u64,
    out: &Path,
    bits: u32,
) -> Result<()> {
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

pub(crate) fn vector_stbn(
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

pub(crate) fn filter_adapted(
    params: &FilterAdaptedParams,
    start: Option<&Path>,
    out: &Path,
    bits: u32,
) -> Result<()> {
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
