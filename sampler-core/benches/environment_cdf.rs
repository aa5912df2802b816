//! Building the sampling table of a 2048x1024 environment map on one core
//! (issue 30's goal: <= 50 ms), measured beside a plain copy of the same
//! bytes in one run.
//!
//! ```text
//! cargo bench -p sampler-core --bench environment_cdf
//! cargo bench -p sampler-core --bench environment_cdf -- --test   # one quick round
//! ```
//!
//! Workloads, in interleaved rounds, each after a 64 MiB sweep that evicts
//! its buffers from the caches (what a build costs when the image comes from
//! memory):
//!
//! - `EnvironmentMap::build`: linear RGB `[f32; 3]` texels (24 MiB) to the
//!   table (`1 + 1024 + 2048 * 1024` f32, 8 MiB): luminance times
//!   `sin(theta)`, validation, `f64` prefix sums, two passes per row;
//! - `Distribution2d::build` of the same weights precomputed as `f32`
//!   (8 MiB in, 8 MiB out): the table alone;
//! - the copy: the texels into a scratch buffer and the table into another
//!   (every byte the environment build reads and writes, copied once).
//!
//! Prints the CPU (`/proc/cpuinfo`), each median in ms, and its ratio to
//! the copy.

use glam::Vec3;
use sampler_core::distributions::environment::texel_weight;
use sampler_core::{random_f32, Distribution2d, EnvironmentMap};
use std::hint::black_box;
use std::time::Instant;

const WIDTH: u32 = 2048;
const HEIGHT: u32 = 1024;
/// Issue 30's goal for the environment table build on one core.
const GOAL_MS: f64 = 50.0;

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// The CPU's model name (`/proc/cpuinfo`, Linux), or "unknown".
fn cpu_name() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| "unknown".into())
}

/// Touches 64 MiB so that the next workload's buffers come from memory.
fn evict(sweep: &mut [u64]) {
    for (i, v) in sweep.iter_mut().enumerate() {
        *v = v.wrapping_add(i as u64);
    }
    black_box(sweep);
}

/// A sky: a vertical gradient with noise, a sun of a few texels, a darker
/// ground with texture (so no row is uniform and no weight is zero).
fn sky() -> Vec<[f32; 3]> {
    let mut rgb = Vec::with_capacity((WIDTH * HEIGHT) as usize);
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let i = y * WIDTH + x;
            let v = (y as f32 + 0.5) / HEIGHT as f32;
            let n = random_f32(7, i);
            let (dx, dy) = (x as f32 - 1400.0, y as f32 - 300.0);
            rgb.push(if dx * dx + dy * dy < 36.0 {
                [5.0e4, 4.6e4, 4.0e4]
            } else if v < 0.5 {
                [0.3 + 0.4 * v + 0.05 * n, 0.5 + 0.3 * v, 1.2 - v]
            } else {
                [0.1 + 0.1 * n, 0.08 + 0.05 * n, 0.05]
            });
        }
    }
    rgb
}

fn main() {
    let quick = std::env::args().any(|a| a == "--test");
    let rounds = if quick { 1 } else { 15 };
    let rgb = sky();
    let weights: Vec<f32> = rgb
        .iter()
        .enumerate()
        .map(|(i, c)| texel_weight(Vec3::from_array(*c), i as u32 / WIDTH, HEIGHT))
        .collect();
    let len = EnvironmentMap::table_len(WIDTH, HEIGHT);
    let mut table = vec![0.0f32; len];
    let mut table_2d = vec![0.0f32; len];
    let mut rgb_copy = vec![[0.0f32; 3]; rgb.len()];
    let mut table_copy = vec![0.0f32; len];
    let mut sweep = vec![0u64; 8 << 20];
    // Fault every page in before timing (vec! of zeros maps pages lazily).
    for buffer in [&mut table, &mut table_2d, &mut table_copy] {
        buffer.fill(1.0);
    }
    rgb_copy.fill([1.0; 3]);
    sweep.fill(1);
    let (mut env_ms, mut dist_ms, mut copy_ms) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..rounds {
        evict(&mut sweep);
        let t = Instant::now();
        let map = EnvironmentMap::build(WIDTH, HEIGHT, black_box(&rgb), &mut table).expect("valid map");
        black_box(map);
        env_ms.push(t.elapsed().as_secs_f64() * 1e3);

        evict(&mut sweep);
        let t = Instant::now();
        let d =
            Distribution2d::build(WIDTH, HEIGHT, black_box(&weights), &mut table_2d).expect("valid weights");
        black_box(d);
        dist_ms.push(t.elapsed().as_secs_f64() * 1e3);

        evict(&mut sweep);
        let t = Instant::now();
        rgb_copy.copy_from_slice(black_box(&rgb));
        table_copy.copy_from_slice(black_box(&table));
        black_box((&rgb_copy, &table_copy));
        copy_ms.push(t.elapsed().as_secs_f64() * 1e3);
    }
    // Both builds made the same table (weights computed the same way).
    assert_eq!(
        table, table_2d,
        "EnvironmentMap::build and Distribution2d::build disagree"
    );
    let copied = (std::mem::size_of_val(rgb.as_slice()) + len * 4) as f64;
    let (env, dist, copy) = (median(&mut env_ms), median(&mut dist_ms), median(&mut copy_ms));
    println!("environment_cdf: {WIDTH}x{HEIGHT}, one core, {rounds} rounds, median, cold caches");
    println!("cpu: {}", cpu_name());
    println!(
        "copy (texels + table, {:.1} MiB)            {copy:8.2} ms  ({:.1} GB/s)",
        copied / (1 << 20) as f64,
        copied / copy / 1e6
    );
    println!(
        "EnvironmentMap::build (RGB -> table)          {env:8.2} ms  {:6.2}x copy   goal <= {GOAL_MS} ms: {}",
        env / copy,
        if env <= GOAL_MS { "met" } else { "NOT met" }
    );
    println!(
        "Distribution2d::build (f32 weights -> table)  {dist:8.2} ms  {:6.2}x copy",
        dist / copy
    );
}
