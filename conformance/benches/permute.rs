//! One CPU frame of the seed permutation at 1920x1080 (sort + retarget, 4x4
//! blocks, 64x64 tile), measured side by side with a plain copy of the same
//! bytes and with a naive version, in one run.
//!
//! ```text
//! cargo bench -p conformance --bench permute
//! ```
//!
//! Each workload runs in interleaved rounds; the median of each is reported
//! with its ratio to the copy. The permutation's workloads and their copies
//! each start with cold caches (a 64 MiB sweep before each): what a frame
//! costs when its buffers come from memory, and the same for every line
//! whatever else the round runs. The first lines name the CPU (`/proc/cpuinfo`)
//! and the instruction set `permute_frame` chose (`sampler_core::Isa::best`);
//! then `permute_frame` with that choice, with AVX2 and AVX-512 forced (where
//! the CPU has them) and with the baseline instruction set, all on one core
//! against the one-core copy; then the same four run again at once, their
//! inputs now in the cache: each one's floor on this core, which no memory
//! makes faster, and so the copy bandwidth above which its ratio must
//! exceed its goal (issue 18: 2.0x, 3.0x for the baseline) on this core
//! whatever the memory does; then `permute_frame_rows` on two bands of
//! block rows, one thread each, against a copy of the same bytes split in
//! two halves, one thread each (the calling thread and one spawned for
//! each call, the spawn timed in both); then `permute_frame` on a
//! 3840x2160 frame (wider than one ring: two column strips) against its
//! own one-core copy.
//! `PERMUTE_ONLY=1` runs only those lines (a few seconds), to iterate on the
//! CPU permutation:
//!
//! ```text
//! PERMUTE_ONLY=1 cargo bench -p conformance --bench permute
//! ```
//!
//! The seed reprojection (`reproject_frame`,
//! issue 13) is measured beside its own copy: the motion vectors and seeds
//! it reads and the seeds it writes (its claims buffer is scratch on top).
//! `REPROJECT_ONLY=1` runs only those two, to iterate on the reprojection:
//!
//! ```text
//! REPROJECT_ONLY=1 cargo bench -p conformance --bench permute
//! ```
//!
//! `TEMPORAL_ONLY=1` runs only the temporally blue permutation's step beside
//! `permute_frame` (module `temporal`, issue 29):
//!
//! ```text
//! TEMPORAL_ONLY=1 cargo bench -p conformance --bench permute
//! ```
//!
//! The feature-aware permutation (`permute_frame_features`, issue 14) runs
//! on a frame of seven surfaces (vertical bands, a disc, creases; the bench
//! prints how many of its blocks hold more than one group) and on a frame
//! of one surface, and is reported against the same copy
//! as the plain permutation (its feature buffer, 16 B a pixel, is read on
//! top).

use conformance::fixtures::{banded_features, random_table, random_tile};
use sampler_core::*;
use std::hint::black_box;
use std::time::{Duration, Instant};

#[path = "permute/temporal.rs"]
mod temporal;

const WIDTH: u32 = 1920;
const HEIGHT: u32 = 1080;
const WIDTH_4K: u32 = 3840;
const HEIGHT_4K: u32 = 2160;
const BLOCK: u32 = 4;
const TILE: u32 = 64;
const ROUNDS: usize = 41;
/// Bytes swept between timed permutation workloads so that each starts
/// with its buffers out of the caches (twice this VM's 32 MiB L3).
const EVICT_BYTES: usize = 64 << 20;
/// Threads of the parallel lines (the permutation's bands and the copy's halves).
const THREADS: usize = 2;

/// The one-core workloads: `None` is `permute_frame` (its instruction set
/// chosen at run time), `Some(isa)` that instruction set forced.
const ONE_CORE: [Option<Isa>; 4] = [None, Some(Isa::Avx2), Some(Isa::Avx512), Some(Isa::Baseline)];

/// True where the CPU can run a one-core workload.
fn one_core_available(isa: Option<Isa>) -> bool {
    isa.is_none_or(|isa| isa.is_available())
}

/// A one-core workload's line label.
fn one_core_label(isa: Option<Isa>) -> String {
    match isa {
        None => format!("permute_frame ({:?}, chosen at run time)", Isa::best()),
        Some(Isa::Baseline) => "  same, baseline ISA (SSE2 ranker on x86_64)".to_string(),
        Some(isa) => format!("  same, {isa:?} forced"),
    }
}

/// Issue 18's goal for a one-core workload's ratio to the copy: 2.0 for
/// the vector instruction sets, 3.0 for the baseline.
fn one_core_goal(isa: Option<Isa>) -> f64 {
    if isa == Some(Isa::Baseline) {
        3.0
    } else {
        2.0
    }
}

/// The bytes a frame pass must touch: read intensities and seeds, write seeds.
fn copy_baseline(intensities: &[f32], seeds_in: &[u32], scratch: &mut [f32], seeds_out: &mut [u32]) {
    scratch.copy_from_slice(intensities);
    seeds_out.copy_from_slice(seeds_in);
}

/// Runs `work(k)` for `k` in `0..THREADS`: `k = 0` on the calling thread,
/// the others on threads spawned for the call (so that no more threads are
/// runnable than there are parts).
fn on_threads<W: FnOnce() + Send>(parts: impl IntoIterator<Item = W>) {
    std::thread::scope(|s| {
        let mut parts = parts.into_iter();
        let first = parts.next();
        for part in parts {
            s.spawn(part);
        }
        if let Some(first) = first {
            first();
        }
    });
}

/// [`copy_baseline`] split in `THREADS` equal parts, one per thread.
fn copy_baseline_par(intensities: &[f32], seeds_in: &[u32], scratch: &mut [f32], seeds_out: &mut [u32]) {
    let (ci, cs) = (
        intensities.len().div_ceil(THREADS),
        seeds_in.len().div_ceil(THREADS),
    );
    let parts = scratch
        .chunks_mut(ci)
        .zip(intensities.chunks(ci))
        .zip(seeds_out.chunks_mut(cs).zip(seeds_in.chunks(cs)));
    on_threads(parts.map(|((d, src), (d2, src2))| {
        move || {
            d.copy_from_slice(src);
            d2.copy_from_slice(src2);
        }
    }));
}

/// `permute_frame` as `THREADS` bands of block rows (`permute_frame_rows`),
/// one per thread.
fn permute_frame_threads(
    layout: &FrameLayout,
    frame: u32,
    intensities: &[f32],
    tile: &DitherTile<'_>,
    tables: &RetargetTables<'_>,
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) {
    let blocks = layout.params(frame).blocks_y();
    let mut rest = seeds_out;
    let mut parts = Vec::with_capacity(THREADS);
    for k in 0..THREADS as u32 {
        let rows = blocks * k / THREADS as u32..blocks * (k + 1) / THREADS as u32;
        let (band, tail) =
            std::mem::take(&mut rest).split_at_mut(band_seed_range(layout, rows.clone()).len());
        rest = tail;
        parts.push(move || {
            permute_frame_rows(layout, frame, intensities, tile, tables, seeds_in, rows, band).unwrap()
        });
    }
    on_threads(parts);
}

/// Reads and writes every cache line of `buf`, pushing other data out of
/// the caches.
fn evict(buf: &mut [u64]) {
    for line in buf.chunks_mut(8) {
        line[0] = line[0].wrapping_add(1);
    }
    black_box(buf);
}

/// Logical CPUs the OS reports.
fn num_cpus() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
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

/// The obvious implementation: per block, collect pixels into fresh vectors,
/// sort them with the standard library, then scatter through the table.
fn naive_permute(
    layout: &FrameLayout,
    frame: u32,
    intensities: &[f32],
    tile: &[u32],
    table: &[u32],
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) {
    let p = layout.params(frame);
    let offset = walk_offset(frame, p.tile_log2);
    let mut mid = seeds_in.to_vec();
    for by in 0..p.blocks_y() {
        for bx in 0..p.blocks_x() {
            let mut px: Vec<(u32, u32)> = Vec::new();
            for y in by * p.block..((by + 1) * p.block).min(p.height) {
                for x in bx * p.block..((bx + 1) * p.block).min(p.width) {
                    px.push((x, y));
                }
            }
            let mut a: Vec<usize> = (0..px.len()).collect();
            a.sort_by_key(|&i| {
                (
                    intensity_key(intensities[(px[i].1 * p.width + px[i].0) as usize]),
                    i,
                )
            });
            let mut d: Vec<usize> = (0..px.len()).collect();
            d.sort_by_key(|&i| {
                (
                    tile[tile_texel(glam::UVec2::new(px[i].0, px[i].1), offset, p.tile_log2) as usize],
                    i,
                )
            });
            for k in 0..px.len() {
                let (sx, sy) = px[a[k]];
                let (dx, dy) = px[d[k]];
                mid[(dy * p.padded_width + dx) as usize] = seeds_in[(sy * p.padded_width + sx) as usize];
            }
        }
    }
    for i in 0..p.seed_count() {
        retarget_pixel(&p, i, table, &mid, seeds_out);
    }
}

/// The reprojection's first version (two sweeps: a clearing fill and every
/// pixel's claim, then every pixel's claim again for the winners and the
/// recycling): the baseline the fused CPU pass is measured against.
fn reproject_two_sweeps(
    layout: &FrameLayout,
    motion: &[[f32; 2]],
    seeds_in: &[u32],
    claims: &mut [u32],
    out: &mut [u32],
) {
    let p = layout.params(0);
    let bits = reprojection::index_bits(p.padded_width * p.padded_height);
    let (w, h, pw) = (p.width as usize, p.height as usize, p.padded_width as usize);
    claims.fill(CLAIM_NONE);
    for (i, c) in claims.iter_mut().enumerate() {
        if i % pw >= w || i / pw >= h {
            *c = i as u32;
        }
    }
    for y in 0..h {
        for x in 0..w {
            let (s, k) = reprojection::claim_at(&p, bits, x as u32, y as u32, motion[y * w + x]);
            if s != CLAIM_NONE && k < claims[s as usize] {
                claims[s as usize] = k;
            }
        }
    }
    let mut free = claims
        .iter()
        .enumerate()
        .filter(|(_, &c)| c == CLAIM_NONE)
        .map(|(q, _)| q);
    for (i, o) in out.iter_mut().enumerate() {
        let (x, y) = (i % pw, i / pw);
        if x >= w || y >= h {
            *o = seeds_in[i];
            continue;
        }
        let (s, k) = reprojection::claim_at(&p, bits, x as u32, y as u32, motion[y * w + x]);
        *o = match reprojection::take_if_won(claims, seeds_in, s, k) {
            Some(seed) => seed,
            None => seeds_in[free.next().unwrap()],
        };
    }
}

/// A frame's random intensities and initial seeds (`salt` tells frames
/// apart).
fn frame_buffers(layout: &FrameLayout, salt: u32) -> (Vec<f32>, Vec<u32>) {
    let intensities = (0..layout.pixel_count() as u32)
        .map(|i| random_f32(i, salt))
        .collect();
    let seeds = (0..layout.seed_count() as u32)
        .map(|i| initial_seed(i, 0, 0, salt))
        .collect();
    (intensities, seeds)
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

fn main() {
    // `cargo test --benches` runs bench targets with `--test`: keep that quick.
    let quick = std::env::args().any(|a| a == "--test");
    let rounds = if quick { 1 } else { ROUNDS };
    let reproject_only = std::env::var_os("REPROJECT_ONLY").is_some_and(|v| v == "1");
    if std::env::var_os("TEMPORAL_ONLY").is_some_and(|v| v == "1") {
        return temporal::run(rounds, &mut vec![0u64; EVICT_BYTES / 8]);
    }
    let layout = FrameLayout::new(WIDTH, HEIGHT, BLOCK, TILE).unwrap();
    let tile_values = random_tile(TILE, 1, false);
    let tile = DitherTile::new(TILE, &tile_values).unwrap();
    let packed: Vec<Vec<u32>> = (0..4).map(|i| random_table(TILE, i, 20_000)).collect();
    let tables = RetargetTables::new(TILE, [&packed[0], &packed[1], &packed[2], &packed[3]]).unwrap();
    let (intensities, seeds) = frame_buffers(&layout, 0);
    let mut out = vec![0u32; seeds.len()];
    let mut scratch = vec![0f32; intensities.len()];

    let (mut t_copy, mut t_naive, mut t_shader) = (vec![], vec![], vec![]);
    // The one-core workloads of `ONE_CORE`, cold and with inputs in cache.
    let (mut t_cold, mut t_warm) = (vec![vec![]; ONE_CORE.len()], vec![vec![]; ONE_CORE.len()]);
    let (mut t_par, mut t_copy_par) = (vec![], vec![]);
    let permute_only = std::env::var_os("PERMUTE_ONLY").is_some_and(|v| v == "1");
    let mut evict_buf = vec![0u64; EVICT_BYTES / 8];
    let (mut t_features, mut t_features_one) = (vec![], vec![]);
    let features = banded_features(WIDTH, HEIGHT, 6, true, 0);
    let one_surface = vec![SurfaceFeature::new(1, 2.0, glam::Vec3::Z); features.len()];
    let (mut sorted_scratch, mut sources) =
        (vec![0u32; layout.seed_count()], vec![0u32; layout.seed_count()]);
    // A camera pan of 0.7 px/frame with a disoccluded band: typical motion.
    let motion: Vec<[f32; 2]> = (0..layout.pixel_count() as u32)
        .map(|i| if i % WIDTH < 8 { [f32::NAN; 2] } else { [-0.7, 0.1] })
        .collect();
    // A 3840x2160 frame: past one ring (two column strips), and four
    // times the bytes.
    let layout_4k = FrameLayout::new(WIDTH_4K, HEIGHT_4K, BLOCK, TILE).unwrap();
    let (intensities_4k, seeds_4k) = frame_buffers(&layout_4k, 1);
    let (mut out_4k, mut scratch_4k) = (vec![0u32; seeds_4k.len()], vec![0f32; intensities_4k.len()]);
    let (mut t_copy_4k, mut t_fast_4k) = (vec![], vec![]);
    let mut claims = vec![0u32; seeds.len()];
    let mut motion_scratch = vec![[0f32; 2]; motion.len()];
    let (mut t_reproject, mut t_reproject_copy, mut t_reproject_old) = (vec![], vec![], vec![]);
    for r in 0..rounds {
        let frame = r as u32;
        if reproject_only {
            t_reproject_copy.push(time(&mut || {
                motion_scratch.copy_from_slice(black_box(&motion));
                out.copy_from_slice(&seeds);
            }));
            t_reproject.push(time(&mut || {
                reproject_frame(&layout, black_box(&motion), &seeds, &mut claims, &mut out).unwrap();
            }));
            t_reproject_old.push(time(&mut || {
                reproject_two_sweeps(&layout, black_box(&motion), &seeds, &mut claims, &mut out)
            }));
            continue;
        }
        evict(&mut evict_buf);
        t_copy.push(time(&mut || {
            copy_baseline(black_box(&intensities), &seeds, &mut scratch, &mut out)
        }));
        // Each one-core workload runs cold, then at once again with its
        // inputs in the cache (the same frame: the same work).
        for (slot, isa) in ONE_CORE.into_iter().enumerate() {
            if one_core_available(isa) {
                evict(&mut evict_buf);
                for t in [&mut t_cold[slot], &mut t_warm[slot]] {
                    let i = black_box(&intensities);
                    t.push(time(&mut || {
                        match isa {
                            None => permute_frame(&layout, frame, i, &tile, &tables, &seeds, &mut out),
                            Some(Isa::Baseline) => permute_frame_baseline_isa(
                                &layout, frame, i, &tile, &tables, &seeds, &mut out,
                            ),
                            Some(isa) => {
                                let whole = 0..layout.params(frame).blocks_y();
                                permute_frame_rows_isa(
                                    isa, &layout, frame, i, &tile, &tables, &seeds, whole, &mut out,
                                )
                            }
                        }
                        .unwrap()
                    }));
                }
            }
        }
        // The parallel workloads run on threads spawned for the call (the
        // spawn is timed too, for both): a rayon pool woken for a few
        // milliseconds may find its threads on one core (the scheduler
        // places a woken thread near its waker; a renderer whose pool was
        // busy rendering does not see that), new threads go to idle cores.
        evict(&mut evict_buf);
        t_copy_par.push(time(&mut || {
            copy_baseline_par(black_box(&intensities), &seeds, &mut scratch, &mut out)
        }));
        evict(&mut evict_buf);
        t_par.push(time(&mut || {
            permute_frame_threads(
                &layout,
                frame,
                black_box(&intensities),
                &tile,
                &tables,
                &seeds,
                &mut out,
            )
        }));
        evict(&mut evict_buf);
        t_copy_4k.push(time(&mut || {
            copy_baseline(
                black_box(&intensities_4k),
                &seeds_4k,
                &mut scratch_4k,
                &mut out_4k,
            )
        }));
        evict(&mut evict_buf);
        t_fast_4k.push(time(&mut || {
            permute_frame(
                &layout_4k,
                frame,
                black_box(&intensities_4k),
                &tile,
                &tables,
                &seeds_4k,
                &mut out_4k,
            )
            .unwrap()
        }));
        if permute_only {
            continue;
        }
        t_reproject_copy.push(time(&mut || {
            motion_scratch.copy_from_slice(black_box(&motion));
            out.copy_from_slice(&seeds);
        }));
        t_reproject.push(time(&mut || {
            reproject_frame(&layout, black_box(&motion), &seeds, &mut claims, &mut out).unwrap();
        }));
        t_reproject_old.push(time(&mut || {
            reproject_two_sweeps(&layout, black_box(&motion), &seeds, &mut claims, &mut out)
        }));
        let table = tables.table(step_index(frame, 6)).packed();
        t_naive.push(time(&mut || {
            naive_permute(
                &layout,
                frame,
                black_box(&intensities),
                &tile_values,
                table,
                &seeds,
                &mut out,
            )
        }));
        for (f, t) in [(&features, &mut t_features), (&one_surface, &mut t_features_one)] {
            t.push(time(&mut || {
                permute_frame_features(
                    &layout,
                    frame,
                    black_box(&intensities),
                    f,
                    &FeatureThresholds::DEFAULT,
                    &tile,
                    &tables,
                    &seeds,
                    &mut sorted_scratch,
                    &mut sources,
                    &mut out,
                )
                .unwrap()
            }));
        }
        // The per-block rank-counting path the GPU kernels run, on the CPU.
        let mut mid = vec![0u32; seeds.len()];
        t_shader.push(time(&mut || {
            sort_frame(&layout, frame, black_box(&intensities), &tile, &seeds, &mut mid).unwrap();
            retarget_frame(&layout, frame, &tables, &mid, &mut out).unwrap();
        }));
    }
    black_box(&out);
    if reproject_only {
        return print_reproject(
            [&mut t_reproject, &mut t_reproject_old, &mut t_reproject_copy],
            motion.len(),
            seeds.len(),
        );
    }
    let copy = median(&mut t_copy);
    let bytes = intensities.len() * 4 + seeds.len() * 8;
    let gbs = |t: Duration| bytes as f64 / t.as_secs_f64() / 1e9;
    println!(
        "CPU: {} ({} cores); permute_frame chose {:?}",
        cpu_model(),
        num_cpus(),
        Isa::best()
    );
    println!(
        "permute_frame_1080p: {WIDTH}x{HEIGHT}, {BLOCK}x{BLOCK} blocks, {TILE}x{TILE} tile, median of {rounds} interleaved rounds"
    );
    println!(
        "copy of the same bytes ({:.1} MB: intensities and seeds in, seeds out): {:.3} ms, {:.2} GB/s",
        bytes as f64 / 1e6,
        copy.as_secs_f64() * 1e3,
        gbs(copy)
    );
    println!("{:<44} {:>10} {:>12}", "workload (one core)", "ms", "x copy");
    let mut rows = vec![("copy of the same bytes".to_string(), Some(copy))];
    for (slot, isa) in ONE_CORE.into_iter().enumerate() {
        let t = one_core_available(isa).then(|| median(&mut t_cold[slot]));
        rows.push((one_core_label(isa), t));
    }
    if !permute_only {
        rows.extend([
            (
                "sort_frame + retarget_frame (GPU path)".to_string(),
                Some(median(&mut t_shader)),
            ),
            (
                "naive (alloc + std sort per block)".to_string(),
                Some(median(&mut t_naive)),
            ),
            (
                "permute_frame_features (7 surfaces)".to_string(),
                Some(median(&mut t_features)),
            ),
            (
                "  same, one surface".to_string(),
                Some(median(&mut t_features_one)),
            ),
        ]);
    }
    for (name, t) in rows {
        match t {
            Some(t) => println!(
                "{name:<44} {:>10.3} {:>12.2}",
                t.as_secs_f64() * 1e3,
                t.as_secs_f64() / copy.as_secs_f64()
            ),
            None => println!("{name:<44} {:>10} {:>12}", "n/a", "(CPU lacks it)"),
        }
    }
    println!(
        "{:<44} {:>10} {:>12}   goal: out of reach where the copy beats",
        "the same, inputs in cache (each one's floor)", "ms", "x copy"
    );
    for (slot, isa) in ONE_CORE.into_iter().enumerate() {
        if !one_core_available(isa) {
            continue;
        }
        // A frame from memory takes at least its time with the inputs in
        // cache: wherever the copy is faster than `floor / goal`, the
        // ratio exceeds the goal whatever else the memory does.
        let (floor, goal) = (median(&mut t_warm[slot]), one_core_goal(isa));
        println!(
            "{:<44} {:>10.3} {:>12.2}   {goal:.1}x: {:.1} GB/s",
            one_core_label(isa),
            floor.as_secs_f64() * 1e3,
            floor.as_secs_f64() / copy.as_secs_f64(),
            gbs(floor) * goal
        );
    }
    let (copy_par, par) = (median(&mut t_copy_par), median(&mut t_par));
    println!(
        "{:<44} {:>10} {:>12}",
        format!("workload ({THREADS} threads)"),
        "ms",
        "x copy"
    );
    println!(
        "{:<44} {:>10.3} {:>12.2}   ({:.2} GB/s)",
        format!("copy of the same bytes, {THREADS} halves"),
        copy_par.as_secs_f64() * 1e3,
        1.0,
        gbs(copy_par)
    );
    println!(
        "{:<44} {:>10.3} {:>12.2}",
        format!("permute_frame_rows, {THREADS} bands ({:?})", Isa::best()),
        par.as_secs_f64() * 1e3,
        par.as_secs_f64() / copy_par.as_secs_f64()
    );
    let (copy_4k, fast_4k) = (median(&mut t_copy_4k), median(&mut t_fast_4k));
    let bytes_4k = intensities_4k.len() * 4 + seeds_4k.len() * 8;
    println!(
        "{:<44} {:>10} {:>12}",
        format!("workload ({WIDTH_4K}x{HEIGHT_4K}, one core)"),
        "ms",
        "x copy"
    );
    println!(
        "{:<44} {:>10.3} {:>12.2}   ({:.2} GB/s)",
        format!("copy of the same bytes ({:.1} MB)", bytes_4k as f64 / 1e6),
        copy_4k.as_secs_f64() * 1e3,
        1.0,
        bytes_4k as f64 / copy_4k.as_secs_f64() / 1e9
    );
    println!(
        "{:<44} {:>10.3} {:>12.2}",
        format!("permute_frame ({:?}, column strips)", Isa::best()),
        fast_4k.as_secs_f64() * 1e3,
        fast_4k.as_secs_f64() / copy_4k.as_secs_f64()
    );
    if permute_only {
        return;
    }
    println!(
        "feature frame: {:.1}% of blocks hold more than one group",
        100.0 * mixed_blocks(&layout, &features)
    );
    print_reproject(
        [&mut t_reproject, &mut t_reproject_old, &mut t_reproject_copy],
        motion.len(),
        seeds.len(),
    );
}

/// Fraction of the frame's blocks whose visible pixels form more than one
/// group (`sampler_core::features::permute::block_groups`).
fn mixed_blocks(layout: &FrameLayout, features: &[SurfaceFeature]) -> f64 {
    use sampler_core::features::permute::block_groups;
    let p = layout.params(0);
    let (mut mixed, mut total) = (0, 0);
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
            if len == 0 {
                continue;
            }
            let mut g = [0u32; MAX_BLOCK_PIXELS];
            block_groups(len as u32, &f, &FeatureThresholds::DEFAULT, &mut g);
            total += 1;
            mixed += usize::from(g[..len].iter().any(|&v| v != 0));
        }
    }
    mixed as f64 / total as f64
}

/// The reprojection's line: its median against its copy's, and the copy's
/// bandwidth over the bytes the pass must touch (motion and seeds in, seeds
/// out; the copy also writes the motion vectors back, which is not counted).
fn print_reproject([t, t_old, t_copy]: [&mut [Duration]; 3], pixels: usize, seeds: usize) {
    let (reproject, old, copy) = (median(t), median(t_old), median(t_copy));
    println!(
        "reproject_frame (pan 0.7 px): {:.3} ms, copy of motion + seeds {:.3} ms: {:.2} x copy",
        reproject.as_secs_f64() * 1e3,
        copy.as_secs_f64() * 1e3,
        reproject.as_secs_f64() / copy.as_secs_f64()
    );
    println!(
        "  same, first version (two sweeps): {:.3} ms: {:.2} x copy",
        old.as_secs_f64() * 1e3,
        old.as_secs_f64() / copy.as_secs_f64()
    );
    let bytes = pixels * 8 + seeds * 8;
    println!(
        "reprojection copy bandwidth: {:.2} GB/s ({:.1} MB of motion and seeds in, seeds out)",
        bytes as f64 / copy.as_secs_f64() / 1e9,
        bytes as f64 / 1e6
    );
}
