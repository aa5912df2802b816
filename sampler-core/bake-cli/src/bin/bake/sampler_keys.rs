//! The a-priori samplers' baked data: the screen-space Sobol keys, and the
//! search for ZSobol's placement map.

use anyhow::{Context, Result};
use bake::{bake_keys_parallel, create_file, default_key_params, encode_u32, write_all};
use sampler_core::bake::KeyParams;
use std::path::Path;
use std::time::Instant;

use crate::progress::bar;

pub(crate) fn keys(params: &KeyParams, out: &Path) -> Result<()> {
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

pub(crate) fn zsobol_placement(draws: u64, seed: u32) -> Result<()> {
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
