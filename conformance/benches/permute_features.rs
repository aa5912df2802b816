//! One CPU frame of the feature-aware permutation (`permute_frame_features`,
//! issue 14) at 1920x1080 (4x4 blocks, 64x64 tile), its fast path and its
//! reference form (`permute_frame_features_reference`), measured side by
//! side with a plain copy of the same bytes in one run, on one core.
//!
//! ```text
//! cargo bench -p conformance --bench permute_features
//! ```
//!
//! The copy is the one `benches/permute.rs` measures the plain permutation
//! against (intensities and seeds in, seeds out); the feature buffer (16 B a
//! pixel, more than those three together) is read on top, so a line reading
//! just the features is printed for scale, as is the plain permutation. Two
//! frames: seven surfaces (vertical bands, a disc, creases; as
//! `benches/permute.rs`) and one surface. Every workload starts with cold
//! caches (a 64 MiB sweep before each) and runs in interleaved rounds; the
//! median of each is reported with its ratio to the copy's. The fast path is
//! checked against the reference once before timing. The last lines give
//! the frame's statistics that set the fast path's cost: blocks of several
//! groups, cut edges, and the chain walk's steps per seed. `FAST_ONLY=1`
//! leaves out the reference form (about 200 times the copy) and the
//! statistics, to iterate on the fast path:
//!
//! ```text
//! FAST_ONLY=1 cargo bench -p conformance --bench permute_features
//! ```

use conformance::fixtures::{banded_features, random_table, random_tile};
use sampler_core::features::permute::{
    block_groups, permute_frame_features_reference, record_source, retarget_index,
};
use sampler_core::features::surface::edge_is_cut;
use sampler_core::*;
use std::hint::black_box;
use std::time::{Duration, Instant};

const WIDTH: u32 = 1920;
const HEIGHT: u32 = 1080;
const BLOCK: u32 = 4;
const TILE: u32 = 64;
const ROUNDS: usize = 21;
/// Bytes swept before each timed workload so that it starts with its
/// buffers out of the caches (twice this VM's 32 MiB L3).
const EVICT_BYTES: usize = 64 << 20;

/// Reads and writes every cache line of `buf`.
fn evict(buf: &mut [u64]) {
    for line in buf.chunks_mut(8) {
        line[0] = line[0].wrapping_add(1);
    }
    black_box(buf);
}

/// The CPU's model name (`/proc/cpuinfo`, Linux), or "unknown".
fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| "unknown".into())
}

fn time(f: &mut dyn FnMut()) -> Duration {
    let t = Instant::now();
    f();
    t.elapsed()
}

fn median(v: &mut [Duration]) -> Duration {
    v.sort();
    v[v.len() / 2]
}

/// Sum of the feature ids: reads every feature once (the features' share
/// of the traffic, for scale).
fn read_features(features: &[SurfaceFeature]) -> u32 {
    features.iter().fold(0u32, |a, f| a.wrapping_add(f.id ^ f.normal))
}

fn main() {
    // `cargo test --benches` runs bench targets with `--test`: keep that quick.
    let quick = std::env::args().any(|a| a == "--test");
    // `FAST_ONLY=1`: skip the (slow) reference form's lines, to iterate.
    let fast_only = std::env::var_os("FAST_ONLY").is_some_and(|v| v == "1");
    let rounds = if quick { 1 } else { ROUNDS };
    let layout = FrameLayout::new(WIDTH, HEIGHT, BLOCK, TILE).unwrap();
    let tile_values = random_tile(TILE, 1, false);
    let tile = DitherTile::new(TILE, &tile_values).unwrap();
    let packed: Vec<Vec<u32>> = (0..4).map(|i| random_table(TILE, i, 20_000)).collect();
    let tables = RetargetTables::new(TILE, [&packed[0], &packed[1], &packed[2], &packed[3]]).unwrap();
    let intensities: Vec<f32> = (0..layout.pixel_count() as u32)
        .map(|i| random_f32(i, 0))
        .collect();
    let seeds: Vec<u32> = (0..layout.seed_count() as u32)
        .map(|i| initial_seed(i, 0, 0, 0))
        .collect();
    let n = layout.seed_count();
    let seven = banded_features(WIDTH, HEIGHT, 6, true, 0);
    let one = vec![SurfaceFeature::new(1, 2.0, glam::Vec3::Z); seven.len()];
    let t = FeatureThresholds::DEFAULT;
    let (mut out, mut sorted, mut sources) = (vec![0u32; n], vec![0u32; n], vec![0u32; n]);
    let mut scratch = vec![0f32; intensities.len()];
    let mut evict_buf = vec![0u64; EVICT_BYTES / 8];

    let frames = [("7 surfaces", &seven), ("one surface", &one)];
    for (name, f) in frames {
        let mut want = vec![0u32; n];
        permute_frame_features_reference(
            &layout,
            3,
            &intensities,
            f,
            &t,
            &tile,
            &tables,
            &seeds,
            &mut sorted,
            &mut sources,
            &mut want,
        )
        .unwrap();
        permute_frame_features(
            &layout,
            3,
            &intensities,
            f,
            &t,
            &tile,
            &tables,
            &seeds,
            &mut sorted,
            &mut sources,
            &mut out,
        )
        .unwrap();
        assert!(out == want, "fast path differs from the reference ({name})");
    }

    let mut t_copy = vec![];
    let mut t_read = vec![];
    let mut t_plain = vec![];
    let mut t_fast = [vec![], vec![]];
    let mut t_ref = [vec![], vec![]];
    for r in 0..rounds {
        let frame = r as u32;
        evict(&mut evict_buf);
        t_copy.push(time(&mut || {
            scratch.copy_from_slice(black_box(&intensities));
            out.copy_from_slice(&seeds);
        }));
        evict(&mut evict_buf);
        t_read.push(time(&mut || {
            black_box(read_features(black_box(&seven)));
        }));
        evict(&mut evict_buf);
        t_plain.push(time(&mut || {
            permute_frame(
                &layout,
                frame,
                black_box(&intensities),
                &tile,
                &tables,
                &seeds,
                &mut out,
            )
            .unwrap()
        }));
        for (k, (_, f)) in frames.iter().enumerate() {
            evict(&mut evict_buf);
            t_fast[k].push(time(&mut || {
                permute_frame_features(
                    &layout,
                    frame,
                    black_box(&intensities),
                    f,
                    &t,
                    &tile,
                    &tables,
                    &seeds,
                    &mut sorted,
                    &mut sources,
                    &mut out,
                )
                .unwrap()
            }));
            if fast_only {
                continue;
            }
            evict(&mut evict_buf);
            t_ref[k].push(time(&mut || {
                permute_frame_features_reference(
                    &layout,
                    frame,
                    black_box(&intensities),
                    f,
                    &t,
                    &tile,
                    &tables,
                    &seeds,
                    &mut sorted,
                    &mut sources,
                    &mut out,
                )
                .unwrap()
            }));
        }
    }
    black_box(&out);
    let copy = median(&mut t_copy);
    let bytes = intensities.len() * 4 + seeds.len() * 8;
    println!(
        "CPU: {} (one core used); permute_frame chose {:?}",
        cpu_model(),
        Isa::best()
    );
    println!(
        "permute_frame_features_1080p: {WIDTH}x{HEIGHT}, {BLOCK}x{BLOCK} blocks, {TILE}x{TILE} tile, median of {rounds} interleaved rounds, cold caches"
    );
    println!(
        "copy of the same bytes ({:.1} MB: intensities and seeds in, seeds out): {:.3} ms, {:.2} GB/s",
        bytes as f64 / 1e6,
        copy.as_secs_f64() * 1e3,
        bytes as f64 / copy.as_secs_f64() / 1e9
    );
    println!("{:<52} {:>10} {:>10}", "workload (one core)", "ms", "x copy");
    let mut rows = vec![
        ("copy of the same bytes".to_string(), copy),
        (
            format!(
                "read of the features only ({:.1} MB)",
                seven.len() as f64 * 16.0 / 1e6
            ),
            median(&mut t_read),
        ),
        (
            "permute_frame (plain, for scale)".to_string(),
            median(&mut t_plain),
        ),
    ];
    for (k, (name, _)) in frames.iter().enumerate() {
        rows.push((
            format!("permute_frame_features, fast path ({name})"),
            median(&mut t_fast[k]),
        ));
        if !fast_only {
            rows.push((format!("  reference form ({name})"), median(&mut t_ref[k])));
        }
    }
    for (name, d) in rows {
        println!(
            "{name:<52} {:>10.3} {:>10.2}",
            d.as_secs_f64() * 1e3,
            d.as_secs_f64() / copy.as_secs_f64()
        );
    }
    if !fast_only {
        print_statistics(&layout, &tables, &seven, &t);
    }
}

/// The 7-surface frame's blocks of several groups, cut edges, and walk
/// steps per seed (frame 0's table).
fn print_statistics(
    layout: &FrameLayout,
    tables: &RetargetTables<'_>,
    features: &[SurfaceFeature],
    t: &FeatureThresholds,
) {
    let p = layout.params(0);
    let offset = walk_offset(0, p.tile_log2);
    let table = tables.table(step_index(0, p.tile_log2)).packed();
    let (mut split, mut blocks) = (0usize, 0usize);
    for by in 0..p.blocks_y() {
        for bx in 0..p.blocks_x() {
            let mut f = [SurfaceFeature::default(); MAX_BLOCK_PIXELS];
            let mut len = 0;
            for y in by * p.block..((by + 1) * p.block).min(p.height) {
                for x in bx * p.block..((bx + 1) * p.block).min(p.width) {
                    f[len] = features[(y * p.width + x) as usize];
                    len += 1;
                }
            }
            if len > 0 {
                let mut g = [0u32; MAX_BLOCK_PIXELS];
                block_groups(len as u32, &f, t, &mut g);
                blocks += 1;
                split += usize::from(g[..len].iter().any(|&v| v != 0));
            }
        }
    }
    let seeds = p.seed_count();
    let mut sources = vec![0u32; seeds as usize];
    for q in 0..seeds {
        record_source(&p, offset, table, q, &mut sources);
    }
    let (mut cut, mut steps) = (0u64, 0u64);
    for q in 0..seeds {
        if edge_is_cut(&p, features, t, q, retarget_index(&p, offset, table, q)) {
            cut += 1;
            let mut s = q;
            loop {
                steps += 1;
                let r = sources[s as usize];
                if edge_is_cut(&p, features, t, r, s) {
                    break;
                }
                s = r;
            }
        }
    }
    println!(
        "7-surface frame: {:.1}% of blocks hold more than one group, {:.1}% of edges are cut, chain walks take {:.2} steps per seed",
        100.0 * split as f64 / blocks as f64,
        100.0 * cut as f64 / seeds as f64,
        steps as f64 / seeds as f64
    );
}
