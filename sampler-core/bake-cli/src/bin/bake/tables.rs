//! Retarget tables: the exact (or annealed) assignment from each walk step's
//! sorted tile to the next, for a dither tile read from a file.

use anyhow::{Context, Result};
use bake::{bake_tables_parallel, create_dir, create_file, encode_tables, read_tile, write_all};
use sampler_core::bake::{anneal_retarget_table, mean_displacement, AnnealParams};
use sampler_core::{DitherTile, STEP_COUNT};
use std::path::Path;
use std::time::Instant;

use crate::progress::bar;

pub(crate) fn retarget(
    tile_path: &Path,
    out: &Path,
    anneal: Option<u32>,
    displacement_cost: u32,
) -> Result<()> {
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
