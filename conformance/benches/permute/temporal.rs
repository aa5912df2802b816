//! `TEMPORAL_ONLY=1`: the temporally blue permutation's step
//! (`permute_frame_temporal`, the default 64x64x64 target,
//! `defaults::temporal_target`) beside today's `permute_frame` with the
//! default 64x64 tile and tables and a one-core copy of the frame's bytes,
//! at 1920x1080 with 4x4 blocks; every workload cold (the eviction sweep
//! before each), interleaved in every round.

use super::{evict, median, time, BLOCK, HEIGHT, WIDTH};
use sampler_core::{defaults, initial_seed, permute_frame, permute_frame_temporal, random_f32, FrameLayout};
use std::hint::black_box;
use std::time::Duration;

/// Runs `rounds` interleaved rounds and prints each workload's median and
/// its ratios.
pub(super) fn run(rounds: usize, evict_buf: &mut [u64]) {
    let layout = FrameLayout::new(WIDTH, HEIGHT, BLOCK, 64).unwrap();
    let (tile, tables) = (defaults::tile_64(), defaults::tables_64());
    let target = defaults::temporal_target();
    let values: Vec<f32> = (0..layout.pixel_count() as u32)
        .map(|i| random_f32(i, 3))
        .collect();
    let seeds: Vec<u32> = (0..layout.seed_count() as u32)
        .map(|i| initial_seed(i, 0, 0, 3))
        .collect();
    let (mut out, mut scratch) = (vec![0u32; seeds.len()], vec![0f32; values.len()]);
    let mut t: [Vec<Duration>; 3] = Default::default();
    for r in 0..rounds as u32 {
        evict(evict_buf);
        t[0].push(time(&mut || {
            scratch.copy_from_slice(black_box(&values));
            out.copy_from_slice(&seeds);
        }));
        // The two permutations in alternating order from round to round.
        for k in [1 + r as usize % 2, 2 - r as usize % 2] {
            evict(evict_buf);
            t[k].push(time(&mut || match k {
                1 => permute_frame(&layout, r, black_box(&values), &tile, &tables, &seeds, &mut out).unwrap(),
                _ => {
                    permute_frame_temporal(&layout, r, black_box(&values), &target, &seeds, &mut out).unwrap()
                }
            }));
        }
    }
    black_box(&out);
    let ms: Vec<f64> = t.iter_mut().map(|v| median(v).as_secs_f64() * 1e3).collect();
    println!(
        "temporal permutation: {WIDTH}x{HEIGHT}, {BLOCK}x{BLOCK} blocks, median of {rounds} interleaved rounds, cold"
    );
    println!(
        "{:<52} {:>9} {:>8} {:>12}",
        "workload (one core)", "ms", "x copy", "x permute"
    );
    let rows = [
        "copy of the frame's bytes",
        "permute_frame, 64x64 tile (the walk)",
        "permute_frame_temporal, 64x64x64 target",
    ];
    for (name, &m) in rows.iter().zip(&ms) {
        println!("{name:<52} {m:>9.3} {:>8.2} {:>12.2}", m / ms[0], m / ms[1]);
    }
    let bytes = 4 * (values.len() + 2 * seeds.len());
    println!(
        "the copy's bandwidth: {:.1} GB/s over the {:.1} MB the pass touches",
        bytes as f64 / (ms[0] * 1e-3) / 1e9,
        bytes as f64 / 1e6
    );
}
