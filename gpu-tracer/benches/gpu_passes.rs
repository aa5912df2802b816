//! Per-pass GPU times at 1280x720, measured on one device in one run: the
//! 1-spp path-traced frame (Cornell box) against the G-buffer pass
//! (primary visibility and motion vectors), the sorting and retargeting
//! passes (4x4 blocks, 64x64 tile), and the seed reprojection (its motion
//! pass and its six passes) under a camera panning 2 units a frame (about
//! 1.5 px at the back wall; the motion pass with the render defaults'
//! reprojection settings, so its rigid count, frame-wide rule and pan
//! offset included), and the feature-aware permutation (the
//! tracer's feature pass, the grouped sort, the inverse + cut retarget),
//! and the real-time filters (`taa`, `gauss`, `atrous`, `taa+atrous`) on the
//! traced frame and its G-buffer; and the temporally blue permutation
//! (`--mode temporal`: the same sorting and retargeting kernels bound on the
//! frame's slice and table of the default 64x64x64 target) beside the
//! walk's sort + retarget on a second permuter of the same 64x64 tile, the
//! two in alternating order, all in each frame's submission. The sort runs
//! in the form the tracer picks for the device (`PassForm::for_device`); both
//! forms (per block, per seed: the same seeds) are timed beside it, as are
//! the reprojection's and the feature-aware step's, and (with timestamp
//! queries) the reprojection's passes one by one. `GPU_PASSES_ROUNDS=N`
//! measures `N` frames instead of 15; `GPU_PASSES_FOLLOW_SHARE=0` times the
//! motion pass without the defaults' rigid count.
//!
//! ```text
//! cargo bench -p gpu-tracer --bench gpu_passes
//! ```
//!
//! Uses timestamp queries where the device has them, else wall-clock time of
//! each pass in its own submission. Prints each pass's median and its share
//! of a traced frame (goals: permutation <= 5%, G-buffer <= 10%,
//! reprojection <= 1%, feature-aware permutation <= 5%; the filters are
//! reported, with no goal).

use gpu_tracer::cornell::cornell_box;
use gpu_tracer::filter::{FilterChain, FilterSettings};
use gpu_tracer::gpu::{
    FilterPipelines, FrameFilterGpu, Gpu, PassForm, PassTimer, PermuteMode, PermutePipelines,
    ReprojectPipelines, SeedPermuter, SeedReprojector, TracePipelines, Tracer,
};
use gpu_tracer::{SceneGpu, TraceSettings};
use sampler_core::FrameLayout;
use std::time::Instant;

const WIDTH: u32 = 1280;
const HEIGHT: u32 = 720;

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

fn main() {
    let quick = std::env::args().any(|a| a == "--test");
    let rounds = match std::env::var("GPU_PASSES_ROUNDS")
        .ok()
        .and_then(|r| r.parse().ok())
    {
        Some(r) if !quick => r,
        _ if quick => 1,
        _ => 15,
    };
    let gpu = match Gpu::new() {
        Ok(g) => g,
        Err(e) => {
            println!("gpu_passes: SKIPPED, {e}");
            return;
        }
    };
    let base = cornell_box();
    let mut scene = SceneGpu::build(&base).expect("scene");
    let camera = |t: u32| {
        let mut c = base.camera;
        let shift = glam::Vec3::new(2.0 * t as f32, 0.0, 0.0);
        c.origin += shift;
        c.target += shift;
        c
    };
    let layout = FrameLayout::new(WIDTH, HEIGHT, 4, 64).expect("layout");
    let mut settings = TraceSettings::new(WIDTH, HEIGHT);
    settings.padded_width = layout.padded_width();
    let params = scene.trace_params(&settings, 0).expect("params");
    let (tile, tables) = (
        sampler_core::defaults::tile_64(),
        sampler_core::defaults::tables_64(),
    );
    let tp = TracePipelines::new(&gpu).expect("trace pipelines");
    let pp = PermutePipelines::new(&gpu).expect("permute pipelines");
    let color = Tracer::color_buffer(&gpu, WIDTH, HEIGHT);
    let permuter = SeedPermuter::new(&gpu, &pp, layout, &tile, &tables, &color).expect("permuter");
    let mut tracer = Tracer::new(&gpu, &tp, &scene, &params, &permuter.seeds, color).expect("tracer");
    let rp = ReprojectPipelines::new(&gpu).expect("reproject pipelines");
    let mut reprojector = SeedReprojector::new(&gpu, &rp, layout, &permuter.seeds).expect("reprojector");
    tracer.enable_motion(&gpu, &tp, &reprojector.motion);
    // A second permuter, feature-aware, fed by the tracer's feature pass.
    let mut featured = SeedPermuter::new(&gpu, &pp, layout, &tile, &tables, &tracer.color).expect("permuter");
    featured.enable_features(&gpu, &pp, &sampler_core::FeatureThresholds::DEFAULT);
    tracer.enable_features(
        &gpu,
        &tp,
        featured.features().expect("enabled"),
        &featured.intensity,
    );
    // The temporal permutation and the walk's, side by side on the same tile.
    let pair_permuter =
        |gpu: &Gpu| SeedPermuter::new(gpu, &pp, layout, &tile, &tables, &tracer.color).expect("permuter");
    let (mut temporal, walk) = (pair_permuter(&gpu), pair_permuter(&gpu));
    let target = sampler_core::defaults::temporal_target();
    temporal
        .enable_temporal(&gpu, &pp, &target)
        .expect("temporal target");
    for p in [&permuter, &featured, &temporal, &walk] {
        p.set_frame(&gpu, 0);
        let mut e = gpu.device.create_command_encoder(&Default::default());
        p.encode_seed_init(&mut e, &pp);
        gpu.queue.submit([e.finish()]);
    }

    let timer = PassTimer::new(&gpu, 18);
    let (mut trace_ms, mut sort_ms, mut retarget_ms, mut gbuffer_ms) = (vec![], vec![], vec![], vec![]);
    let (mut motion_ms, mut reproject_ms, mut reproject_seed_ms) = (vec![], vec![], vec![]);
    let (mut features_ms, mut fsort_ms, mut fretarget_ms) = (vec![], vec![], vec![]);
    let (mut fsort_seed_ms, mut fretarget_seed_ms) = (vec![], vec![]);
    let (mut tsort_ms, mut tretarget_ms, mut wsort_ms, mut wretarget_ms) = (vec![], vec![], vec![], vec![]);
    let (mut block_sort_ms, mut seed_sort_ms) = (vec![], vec![]);
    for t in 0..rounds + 1 {
        scene
            .set_cameras(&camera(t), &camera(t.saturating_sub(1)))
            .expect("camera");
        tracer.set_params(&gpu, &defaults_params(&scene, &settings, t));
        permuter.set_frame(&gpu, t);
        featured.set_frame(&gpu, t);
        walk.set_frame(&gpu, t);
        let times = match &timer {
            Some(timer) => {
                let mut e = gpu.device.create_command_encoder(&Default::default());
                tracer.encode_gbuffer(&mut e, &tp, Some((timer, 3)));
                tracer.encode_motion(&mut e, &tp, Some((timer, 4)));
                // The reprojection in both forms, one after the other (the seeds move twice).
                reprojector.set_form(PassForm::PerGroup);
                reprojector.encode(&mut e, &rp, Some((timer, 5)));
                reprojector.set_form(PassForm::PerSeed);
                reprojector.encode(&mut e, &rp, Some((timer, 15)));
                tracer.encode_trace(&mut e, &tp, Some((timer, 0)));
                permuter.encode_intensity(&mut e, &pp);
                permuter.encode_step(&mut e, &pp, t, PermuteMode::Permute, Some((timer, 1)));
                tracer.encode_features(&mut e, &tp, Some((timer, 6)));
                // The feature-aware step with each sort form (the seeds move twice).
                featured.set_sort_form(PassForm::PerGroup);
                featured.encode_step(&mut e, &pp, t, PermuteMode::Permute, Some((timer, 7)));
                featured.set_sort_form(PassForm::PerSeed);
                featured.encode_step(&mut e, &pp, t, PermuteMode::Permute, Some((timer, 16)));
                // The temporal permutation and the walk's, in alternating order from frame to frame.
                let (first, second) = if t % 2 == 0 { (9, 11) } else { (11, 9) };
                temporal.encode_intensity(&mut e, &pp);
                walk.encode_intensity(&mut e, &pp);
                for span in [first, second] {
                    match span {
                        9 => temporal.encode_step(&mut e, &pp, t, PermuteMode::Temporal, Some((timer, 9))),
                        _ => walk.encode_step(&mut e, &pp, t, PermuteMode::Permute, Some((timer, 11))),
                    }
                }
                // Both sort forms on the same seeds (their output is overwritten next frame).
                permuter.encode_walk_sort(&mut e, &pp, PassForm::PerGroup, Some((timer, 13)));
                permuter.encode_walk_sort(&mut e, &pp, PassForm::PerSeed, Some((timer, 14)));
                timer.resolve(&mut e);
                gpu.queue.submit([e.finish()]);
                timer.read_ms(&gpu).expect("timestamps")
            }
            None => {
                let mut ms = vec![];
                let mut run = |f: &dyn Fn(&mut wgpu::CommandEncoder)| {
                    let mut e = gpu.device.create_command_encoder(&Default::default());
                    f(&mut e);
                    let start = Instant::now();
                    gpu.queue.submit([e.finish()]);
                    gpu.wait().expect("wait");
                    ms.push(start.elapsed().as_secs_f64() * 1e3);
                };
                run(&|e| tracer.encode_trace(e, &tp, None));
                run(&|e| permuter.encode_intensity(e, &pp));
                // Sort and retarget together, then sort alone: retarget = difference.
                run(&|e| permuter.encode_step(e, &pp, t, PermuteMode::Permute, None));
                run(&|e| tracer.encode_gbuffer(e, &tp, None));
                reprojector.set_form(PassForm::PerGroup);
                run(&|e| reprojector.encode(e, &rp, None));
                reprojector.set_form(PassForm::PerSeed);
                run(&|e| reprojector.encode(e, &rp, None));
                run(&|e| tracer.encode_features(e, &tp, None));
                featured.set_sort_form(PassForm::PerGroup);
                run(&|e| featured.encode_step(e, &pp, t, PermuteMode::Permute, None));
                featured.set_sort_form(PassForm::PerSeed);
                run(&|e| featured.encode_step(e, &pp, t, PermuteMode::Permute, None));
                run(&|e| temporal.encode_step(e, &pp, t, PermuteMode::Temporal, None));
                run(&|e| walk.encode_step(e, &pp, t, PermuteMode::Permute, None));
                run(&|e| permuter.encode_walk_sort(e, &pp, PassForm::PerGroup, None));
                run(&|e| permuter.encode_walk_sort(e, &pp, PassForm::PerSeed, None));
                let mut e = gpu.device.create_command_encoder(&Default::default());
                tracer.encode_motion(&mut e, &tp, None);
                let start = Instant::now();
                gpu.queue.submit([e.finish()]);
                gpu.wait().expect("wait");
                ms.push(start.elapsed().as_secs_f64() * 1e3);
                vec![
                    ms[0], ms[2], 0.0, ms[3], ms[13], ms[4], ms[6], ms[7], 0.0, ms[9], 0.0, ms[10], 0.0,
                    ms[11], ms[12], ms[5], ms[8], 0.0,
                ]
            }
        };
        if t > 0 {
            trace_ms.push(times[0]);
            sort_ms.push(times[1]);
            retarget_ms.push(times[2]);
            gbuffer_ms.push(times[3]);
            motion_ms.push(times[4]);
            reproject_ms.push(times[5]);
            features_ms.push(times[6]);
            fsort_ms.push(times[7]);
            fretarget_ms.push(times[8]);
            fsort_seed_ms.push(times[16]);
            fretarget_seed_ms.push(times[17]);
            tsort_ms.push(times[9]);
            tretarget_ms.push(times[10]);
            wsort_ms.push(times[11]);
            wretarget_ms.push(times[12]);
            block_sort_ms.push(times[13]);
            seed_sort_ms.push(times[14]);
            reproject_seed_ms.push(times[15]);
        }
    }
    // The reprojection's passes one by one, both forms (each in its own timed
    // pass, after the frames above; the camera keeps panning).
    let mut split_rows: Vec<(String, Vec<f64>)> = Vec::new();
    if let Some(split_timer) = PassTimer::new(&gpu, 8) {
        for form in [PassForm::PerGroup, PassForm::PerSeed] {
            reprojector.set_form(form);
            let mut per_pass: Vec<Vec<f64>> = Vec::new();
            let mut names = Vec::new();
            for t in 0..rounds {
                let t = rounds + 1 + t;
                scene
                    .set_cameras(&camera(t), &camera(t.saturating_sub(1)))
                    .expect("camera");
                tracer.set_params(&gpu, &defaults_params(&scene, &settings, t));
                let mut e = gpu.device.create_command_encoder(&Default::default());
                tracer.encode_motion(&mut e, &tp, None);
                names = reprojector.encode_each_timed(&mut e, &rp, &split_timer, 0);
                split_timer.resolve(&mut e);
                gpu.queue.submit([e.finish()]);
                let ms = split_timer.read_ms(&gpu).expect("timestamps");
                per_pass.resize(names.len(), Vec::new());
                for (k, v) in per_pass.iter_mut().enumerate() {
                    v.push(ms[k]);
                }
            }
            for (name, v) in names.iter().zip(per_pass) {
                let form = if form == PassForm::PerSeed {
                    "seed"
                } else {
                    "chunk"
                };
                split_rows.push((format!("  per {form}: {name}"), v));
            }
        }
    }
    // The filters, each chain on the traced frame and G-buffer (copied into
    // its inputs, untimed), timed per chain.
    let chains = [
        FilterChain::Taa,
        FilterChain::Gauss,
        FilterChain::Atrous,
        FilterChain::TaaAtrous,
    ];
    let fp = FilterPipelines::new(&gpu).expect("filter pipelines");
    let mut filters: Vec<FrameFilterGpu> = chains
        .iter()
        .map(|&c| {
            FrameFilterGpu::new(&gpu, &fp, c, FilterSettings::default(), WIDTH, HEIGHT).expect("filter")
        })
        .collect();
    let filter_timer = PassTimer::new(&gpu, chains.len() as u32);
    let mut filter_ms = vec![Vec::new(); chains.len()];
    let pixels = (WIDTH * HEIGHT) as u64;
    for _ in 0..rounds {
        let mut e = gpu.device.create_command_encoder(&Default::default());
        for f in &filters {
            e.copy_buffer_to_buffer(&tracer.color, 0, &f.color, 0, pixels * 16);
            e.copy_buffer_to_buffer(&tracer.gbuffer, 0, &f.gbuffer, 0, f.gbuffer.size());
        }
        gpu.queue.submit([e.finish()]);
        for (k, f) in filters.iter_mut().enumerate() {
            let mut e = gpu.device.create_command_encoder(&Default::default());
            let start = Instant::now();
            f.encode(&gpu, &mut e, &fp, filter_timer.as_ref().map(|t| (t, k as u32)));
            if let Some(t) = &filter_timer {
                t.resolve(&mut e);
            }
            gpu.queue.submit([e.finish()]);
            gpu.wait().expect("wait");
            let wall = start.elapsed().as_secs_f64() * 1e3;
            filter_ms[k].push(match &filter_timer {
                Some(t) => t.read_ms(&gpu).expect("timestamps")[k],
                None => wall,
            });
        }
    }
    let (tr, so, re, gb) = (
        median(&mut trace_ms),
        median(&mut sort_ms),
        median(&mut retarget_ms),
        median(&mut gbuffer_ms),
    );
    println!(
        "gpu_passes: {WIDTH}x{HEIGHT}, Cornell box 1 spp, 4x4 blocks, 64x64 tile, on {}; sort form {:?}",
        gpu.describe(),
        permuter.sort_form()
    );
    println!(
        "timing: {}",
        if timer.is_some() {
            "timestamp queries"
        } else {
            "wall clock per submission (sort+retarget together)"
        }
    );
    println!("{:<28} {:>10} {:>14}", "pass", "ms", "% of trace");
    for (name, ms) in [
        ("trace (1 spp)", tr),
        ("sort", so),
        ("sort, per-block form", median(&mut block_sort_ms)),
        ("sort, per-seed form", median(&mut seed_sort_ms)),
        ("retarget", re),
        ("sort + retarget", so + re),
        ("g-buffer + motion", gb),
        ("reprojection motion pass", median(&mut motion_ms)),
        ("reprojection, per chunk", median(&mut reproject_ms)),
        ("reprojection, per seed", median(&mut reproject_seed_ms)),
        ("feature pass", median(&mut features_ms)),
        ("feature-aware sort, per block", median(&mut fsort_ms)),
        ("feature-aware sort, per seed", median(&mut fsort_seed_ms)),
        ("feature-aware retarget", median(&mut fretarget_ms)),
        ("  (after the per-seed sort)", median(&mut fretarget_seed_ms)),
        ("walk beside it: sort", median(&mut wsort_ms)),
        ("walk beside it: retarget", median(&mut wretarget_ms)),
        (
            "walk beside it: sort+retarget",
            median(&mut wsort_ms) + median(&mut wretarget_ms),
        ),
        ("temporal: sort", median(&mut tsort_ms)),
        ("temporal: retarget", median(&mut tretarget_ms)),
        (
            "temporal: sort + retarget",
            median(&mut tsort_ms) + median(&mut tretarget_ms),
        ),
    ] {
        println!("{name:<28} {ms:>10.3} {:>13.2}%", 100.0 * ms / tr);
    }
    for (c, ms) in chains.iter().zip(&mut filter_ms) {
        let ms = median(ms);
        let name = format!("filter {c}");
        println!("{name:<28} {ms:>10.3} {:>13.2}%", 100.0 * ms / tr);
    }
    if !split_rows.is_empty() {
        println!("reprojection pass by pass (each in its own timed pass):");
    }
    for (name, mut ms) in split_rows {
        let ms = median(&mut ms);
        println!("{name:<28} {ms:>10.3} {:>13.2}%", 100.0 * ms / tr);
    }
}

/// Frame `t`'s parameters with the render defaults' reprojection settings
/// (`--mode temporal`): seeds held below 6 px/frame, every seed following in
/// frames half rigid, so that the motion pass runs its rigid count.
/// `GPU_PASSES_FOLLOW_SHARE=S` sets another share (0: no rigid count, to
/// time the motion pass without it).
fn defaults_params(scene: &SceneGpu, settings: &TraceSettings, t: u32) -> kernels::abi::TraceParams {
    let mut p = scene.trace_params(settings, t).expect("params");
    p.seed_hold_below = gpu_tracer::method_choice::DEFAULT_REPROJECT_HOLD_BELOW;
    p.seed_follow_share = std::env::var("GPU_PASSES_FOLLOW_SHARE")
        .ok()
        .map(|s| s.parse().expect("GPU_PASSES_FOLLOW_SHARE: a share in [0, 1]"))
        .unwrap_or(gpu_tracer::method_choice::DEFAULT_REPROJECT_FOLLOW_SHARE);
    p
}
