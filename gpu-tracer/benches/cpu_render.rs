//! CPU renderer throughput on the built-in Cornell box: paths (= pixel
//! samples) per second at 256 x 256, 1 spp, max depth 8, on one thread and
//! on all cores. A path is one camera sample including its bounces, shadow
//! rays and Russian roulette.
//!
//! `cargo bench -p gpu-tracer --bench cpu_render`; the bench prints
//! `rays/s` and `paths/s` per configuration after criterion's own report,
//! and the G-buffer pass (primary visibility + motion vectors) as a share of
//! the 1-spp frame, measured in interleaved rounds (goal: <= 10%), and the
//! render defaults' sampler (ZSobol's pixel jitter) against the seed stream.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::Vec4;
use gpu_tracer::cornell::cornell_box;
use gpu_tracer::cpu::{gbuffer_frame, render_frame, white_seeds};
use gpu_tracer::scene::{SceneGpu, TraceSettings};
use std::time::Instant;

const SIZE: u32 = 256;

fn bench_cpu_render(c: &mut Criterion) {
    let scene = SceneGpu::build(&cornell_box()).expect("scene");
    let settings = TraceSettings::new(SIZE, SIZE);
    let params = scene.trace_params(&settings, 0).expect("params");
    let seeds = white_seeds(SIZE, SIZE, 1);
    let pixels = (SIZE * SIZE) as usize;
    let mut color = vec![Vec4::ZERO; pixels];
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());

    let mut group = c.benchmark_group("cpu_render/cornell_256x256_1spp");
    group.throughput(Throughput::Elements(pixels as u64));
    group.sample_size(10);
    let mut report = Vec::new();
    for threads in [1, cores] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("thread pool");
        let name = format!("{threads}_threads");
        group.bench_function(&name, |b| {
            b.iter(|| pool.install(|| render_frame(&scene, &params, &seeds, &mut color).expect("render")))
        });
        // Own measurement for the printed figure: a few whole frames.
        let frames = 5;
        let start = Instant::now();
        let mut rays = 0u64;
        for _ in 0..frames {
            rays += pool.install(|| render_frame(&scene, &params, &seeds, &mut color).expect("render"));
        }
        let secs = start.elapsed().as_secs_f64();
        report.push((
            threads,
            frames as f64 * pixels as f64 / secs,
            rays as f64 / secs,
            secs / frames as f64,
        ));
    }
    group.finish();
    // G-buffer against the traced frame, interleaved, all cores.
    let mut gbuffer = vec![Default::default(); pixels];
    let (mut trace_ms, mut gbuffer_ms) = (Vec::new(), Vec::new());
    for _ in 0..9 {
        let start = Instant::now();
        render_frame(&scene, &params, &seeds, &mut color).expect("render");
        trace_ms.push(start.elapsed().as_secs_f64() * 1e3);
        let start = Instant::now();
        gbuffer_frame(&scene, &params, &mut gbuffer).expect("g-buffer");
        gbuffer_ms.push(start.elapsed().as_secs_f64() * 1e3);
    }
    trace_ms.sort_by(f64::total_cmp);
    gbuffer_ms.sort_by(f64::total_cmp);
    let (tr, gb) = (trace_ms[4], gbuffer_ms[4]);
    println!(
        "cpu_render cornell 256x256 {cores} thread(s): trace 1 spp {tr:.2} ms, g-buffer + motion {gb:.2} ms \
         = {:.1}% of the frame (median of 9 interleaved rounds)",
        100.0 * gb / tr
    );
    // The render defaults' sampler (ZSobol's pixel jitter, the rest from the
    // seeds) against the seed stream alone, interleaved, all cores.
    let jitter = TraceSettings {
        sampler: gpu_tracer::method_choice::DEFAULT_PERMUTE_SAMPLER,
        ..settings
    };
    let jitter_params = scene.trace_params(&jitter, 0).expect("params");
    let (mut seeds_ms, mut jitter_ms, mut rays) = (Vec::new(), Vec::new(), [0u64; 2]);
    for _ in 0..9 {
        let start = Instant::now();
        rays[0] += render_frame(&scene, &params, &seeds, &mut color).expect("render");
        seeds_ms.push(start.elapsed().as_secs_f64() * 1e3);
        let start = Instant::now();
        rays[1] += render_frame(&scene, &jitter_params, &seeds, &mut color).expect("render");
        jitter_ms.push(start.elapsed().as_secs_f64() * 1e3);
    }
    seeds_ms.sort_by(f64::total_cmp);
    jitter_ms.sort_by(f64::total_cmp);
    println!(
        "cpu_render cornell 256x256 {cores} thread(s): seed stream {:.2} ms, zsobol-jitter (the render defaults) \
         {:.2} ms = {:+.1}% (median of 9 interleaved rounds; rays {} / {})",
        seeds_ms[4],
        jitter_ms[4],
        100.0 * (jitter_ms[4] / seeds_ms[4] - 1.0),
        rays[0],
        rays[1]
    );
    for (threads, paths_per_s, rays_per_s, frame_s) in report {
        println!(
            "cpu_render cornell 256x256 1spp depth 8: {threads} thread(s): {rays_per_s:.0} rays/s, \
             {paths_per_s:.0} paths/s ({:.1} ms/frame)",
            frame_s * 1e3
        );
    }
}

criterion_group!(benches, bench_cpu_render);
criterion_main!(benches);
