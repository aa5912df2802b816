//! Baking speed (issue 3 goals: 128x128 mask <= 0.1 s; 128x128x64
//! spatiotemporal volume <= 20 s; all retarget tables of a 64x64 tile
//! <= 10 s, of a 128x128 tile <= 60 s).
//!
//! `cargo bench -p bake --bench bake` runs the criterion groups and then
//! times one 128x128x64 spatiotemporal bake (too slow for criterion's ten
//! samples); `cargo bench -p bake --bench bake -- mask` (any filter not
//! matching `stbn`) skips the one-shot run.

use criterion::{BenchmarkId, Criterion};
use sampler_core::bake::{
    anneal_retarget_table, bake_mask, bake_retarget_tables, bake_stbn, no_progress, AnnealParams, MaskParams,
    StbnParams,
};
use sampler_core::DitherTile;
use std::hint::black_box;
use std::time::{Duration, Instant};

fn mask(side: u32) -> Vec<u32> {
    bake_mask(
        &MaskParams {
            width: side,
            height: side,
            sigma: 1.9,
            seed: 1,
        },
        &mut no_progress,
    )
    .unwrap()
}

fn masks(c: &mut Criterion) {
    let mut g = c.benchmark_group("mask");
    g.sample_size(10).measurement_time(Duration::from_secs(5));
    for side in [64u32, 128, 256] {
        g.bench_with_input(
            BenchmarkId::new("void_and_cluster_sigma1.9", side),
            &side,
            |b, &s| b.iter(|| mask(black_box(s))),
        );
    }
    g.finish();
}

fn tables(c: &mut Criterion) {
    let mut g = c.benchmark_group("retarget_tables");
    g.sample_size(10).measurement_time(Duration::from_secs(10));
    for side in [64u32, 128] {
        let ranks = mask(side);
        let tile = DitherTile::new(side, &ranks).unwrap();
        g.bench_with_input(BenchmarkId::new("exact_all4_sequential", side), &tile, |b, t| {
            b.iter(|| bake_retarget_tables(black_box(t)).unwrap())
        });
        g.bench_with_input(BenchmarkId::new("exact_all4_rayon", side), &tile, |b, t| {
            b.iter(|| {
                bake::bake_tables_parallel(black_box(t), sampler_core::bake::DISPLACEMENT_COST, &|| {})
                    .unwrap()
            })
        });
    }
    // Baseline: the paper's simulated annealing, one table, 200 sweeps.
    let ranks = mask(64);
    let tile = DitherTile::new(64, &ranks).unwrap();
    g.bench_function("anneal_one_table_200_sweeps/64", |b| {
        b.iter(|| anneal_retarget_table(black_box(&tile), 0, &AnnealParams::default()).unwrap())
    });
    g.finish();
}

fn stbn_once() {
    let params = StbnParams {
        width: 128,
        height: 128,
        depth: 64,
        sigma: 1.9,
        temporal_sigma: 1.9,
        seed: 3,
    };
    let start = Instant::now();
    let ranks = bake_stbn(&params, &mut no_progress).unwrap();
    black_box(ranks);
    println!(
        "stbn/128x128x64 (one run): {:.2} s",
        start.elapsed().as_secs_f64()
    );
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    masks(&mut c);
    tables(&mut c);
    let filter = std::env::args().skip(1).find(|a| !a.starts_with('-'));
    if filter.is_none_or(|f| "stbn".contains(f.as_str()) || f.contains("stbn")) {
        stbn_once();
    }
    c.final_summary();
}
