//! One CPU frame of the seed permutation at 1920x1080 (sort + retarget, 4x4
//! blocks, 64x64 tile), measured side by side with a plain copy of the same
//! bytes and with a naive version, on one core, in one run.
//!
//! ```text
//! cargo bench -p conformance --bench permute
//! ```
//!
//! Each workload runs in interleaved rounds; the median of each is reported
//! with its ratio to the copy. The seed reprojection (`reproject_frame`,
//! issue 13) is measured beside its own copy: the motion vectors and seeds
//! it reads and the seeds it writes (its claims buffer is scratch on top).
//! `REPROJECT_ONLY=1` runs only those two, to iterate on the reprojection:
//!
//! ```text
//! REPROJECT_ONLY=1 cargo bench -p conformance --bench permute
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

const WIDTH: u32 = 1920;
const HEIGHT: u32 = 1080;
const BLOCK: u32 = 4;
const TILE: u32 = 64;
const ROUNDS: usize = 41;

/// The bytes a frame pass must touch: read intensities and seeds, write seeds.
fn copy_baseline(intensities: &[f32], seeds_in: &[u32], scratch: &mut [f32], seeds_out: &mut [u32]) {
    scratch.copy_from_slice(intensities);
    seeds_out.copy_from_slice(seeds_in);
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
    let bits = reproject::index_bits(p.padded_width * p.padded_height);
    let (w, h, pw) = (p.width as usize, p.height as usize, p.padded_width as usize);
    claims.fill(CLAIM_NONE);
    for (i, c) in claims.iter_mut().enumerate() {
        if i % pw >= w || i / pw >= h {
            *c = i as u32;
        }
    }
    for y in 0..h {
        for x in 0..w {
            let (s, k) = reproject::claim_at(&p, bits, x as u32, y as u32, motion[y * w + x]);
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
        let (s, k) = reproject::claim_at(&p, bits, x as u32, y as u32, motion[y * w + x]);
        *o = match reproject::take_if_won(claims, seeds_in, s, k) {
            Some(seed) => seed,
            None => seeds_in[free.next().unwrap()],
        };
    }
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
    let mut out = vec![0u32; seeds.len()];
    let mut scratch = vec![0f32; intensities.len()];

    let (mut t_copy, mut t_fast, mut t_naive, mut t_shader) = (vec![], vec![], vec![], vec![]);
    let mut t_baseline = vec![];
    let (mut t_features, mut t_features_one) = (vec![], vec![]);
    let features = banded_features(WIDTH, HEIGHT, 6, true, 0);
    let one_surface = vec![SurfaceFeature::new(1, 2.0, glam::Vec3::Z); features.len()];
    let (mut sorted_scratch, mut sources) =
        (vec![0u32; layout.seed_count()], vec![0u32; layout.seed_count()]);
    // A camera pan of 0.7 px/frame with a disoccluded band: typical motion.
    let motion: Vec<[f32; 2]> = (0..layout.pixel_count() as u32)
        .map(|i| if i % WIDTH < 8 { [f32::NAN; 2] } else { [-0.7, 0.1] })
        .collect();
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
        t_copy.push(time(&mut || {
            copy_baseline(black_box(&intensities), &seeds, &mut scratch, &mut out)
        }));
        t_fast.push(time(&mut || {
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
        t_baseline.push(time(&mut || {
            permute_frame_baseline_isa(
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
    println!(
        "permute_frame_1080p: {WIDTH}x{HEIGHT}, {BLOCK}x{BLOCK} blocks, {TILE}x{TILE} tile, one core, median of {rounds}"
    );
    println!("{:<34} {:>10} {:>12}", "workload", "ms", "x copy");
    for (name, t) in [
        ("copy of the same bytes", copy),
        ("permute_frame (fused, fast path)", median(&mut t_fast)),
        ("  same, baseline ISA (no AVX2)", median(&mut t_baseline)),
        ("sort_frame + retarget_frame (GPU path)", median(&mut t_shader)),
        ("naive (alloc + std sort per block)", median(&mut t_naive)),
        ("permute_frame_features (7 surfaces)", median(&mut t_features)),
        ("  same, one surface", median(&mut t_features_one)),
    ] {
        println!(
            "{name:<34} {:>10.3} {:>12.2}",
            t.as_secs_f64() * 1e3,
            t.as_secs_f64() / copy.as_secs_f64()
        );
    }
    println!(
        "copy bandwidth: {:.2} GB/s",
        bytes as f64 / copy.as_secs_f64() / 1e9
    );
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
/// group (`sampler_core::feature_permute::block_groups`).
fn mixed_blocks(layout: &FrameLayout, features: &[SurfaceFeature]) -> f64 {
    use sampler_core::feature_permute::block_groups;
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
