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

mod args;
mod defaults;
mod masks;
mod progress;
mod sampler_keys;
mod tables;

use anyhow::{ensure, Result};
use args::{Cli, Command};
use bake::{parse_combine, parse_size, parse_spatial, parse_temporal};
use clap::Parser;
use defaults::defaults;
use masks::{filter_adapted, mask, stbn, vector_stbn};
use sampler_core::bake::{FilterAdaptedParams, KeyParams};
use sampler_keys::{keys, zsobol_placement};
use tables::retarget;

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
