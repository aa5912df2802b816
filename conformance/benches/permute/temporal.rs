//! `TEMPORAL_ONLY=1`: the temporally blue permutation's step
//! (`permute_frame_temporal`, the default 128x128x64 target) beside today's
//! `permute_frame` with the default 64x64 tile and tables (and with the
//! 128x128 ones, the temporal step's tile side) and a one-core copy of the
//! 64-tile frame's bytes, at 1920x1080 with 4x4 blocks; every workload cold
//! (the eviction sweep before each), interleaved in every round.

use super::{evict, median, time, BLOCK, HEIGHT, WIDTH};
use sampler_core::{defaults, initial_seed, permute_frame, permute_frame_temporal, random_f32, FrameLayout};
use std::hint::black_box;
use std::time::Duration;

/// Random intensities and seeds for `layout`.
fn buffers(layout: &FrameLayout) -> (Vec<f32>, Vec<u32>) {
    let values = (0..layout.pixel_count() as u32)
        .map(|i| random_f32(i, 3))
        .collect();
    let seeds = (0..layout.seed_count() as u32)
        .map(|i| initial_seed(i, 0, 0, 3))
        .collect();
    (values, seeds)
}

/// Runs `rounds` interleaved rounds and prints each workload's median and
/// its ratios.
pub(super) fn run(rounds: usize, evict_buf: &mut [u64]) {
    let (l64, l128) = (
        FrameLayout::new(WIDTH, HEIGHT, BLOCK, 64).unwrap(),
        FrameLayout::new(WIDTH, HEIGHT, BLOCK, 128).unwrap(),
    );
    let (tile64, tables64) = (defaults::tile_64(), defaults::tables_64());
    let (tile128, tables128) = (defaults::tile_128(), defaults::tables_128());
    let target = defaults::stbn_128_slice_tables();
    let ((v64, s64), (v128, s128)) = (buffers(&l64), buffers(&l128));
    let (mut o64, mut o128, mut scratch) = (
        vec![0u32; s64.len()],
        vec![0u32; s128.len()],
        vec![0f32; v64.len()],
    );
    let mut t: [Vec<Duration>; 4] = Default::default();
    for r in 0..rounds as u32 {
        evict(evict_buf);
        t[0].push(time(&mut || {
            scratch.copy_from_slice(black_box(&v64));
            o64.copy_from_slice(&s64);
        }));
        evict(evict_buf);
        t[1].push(time(&mut || {
            permute_frame(&l64, r, black_box(&v64), &tile64, &tables64, &s64, &mut o64).unwrap()
        }));
        evict(evict_buf);
        t[2].push(time(&mut || {
            permute_frame(&l128, r, black_box(&v128), &tile128, &tables128, &s128, &mut o128).unwrap()
        }));
        evict(evict_buf);
        t[3].push(time(&mut || {
            permute_frame_temporal(&l128, r, black_box(&v128), &target, &s128, &mut o128).unwrap()
        }));
    }
    black_box((&o64, &o128));
    let ms: Vec<f64> = t.iter_mut().map(|v| median(v).as_secs_f64() * 1e3).collect();
    println!(
        "temporal permutation: {WIDTH}x{HEIGHT}, {BLOCK}x{BLOCK} blocks, median of {rounds} interleaved rounds, cold"
    );
    println!(
        "{:<52} {:>9} {:>8} {:>12}",
        "workload (one core)", "ms", "x copy", "x permute64"
    );
    let rows = [
        "copy of the 64-tile frame's bytes",
        "permute_frame, 64x64 tile (today's default)",
        "permute_frame, 128x128 tile",
        "permute_frame_temporal, 128x128x64 target",
    ];
    for (name, &m) in rows.iter().zip(&ms) {
        println!("{name:<52} {m:>9.3} {:>8.2} {:>12.2}", m / ms[0], m / ms[1]);
    }
    println!(
        "temporal / permute_frame at the same 128 tile: {:.2}x (the 128 tile pads 1080 rows to 1152, the 64 tile to 1088)",
        ms[3] / ms[2]
    );
}
