//! What each sampler's numbers cost on the GPU: the 1-spp path-traced frame
//! (Cornell box, 1280x720, max depth 8) drawn from the seed stream, from
//! screen-space Sobol, from ZSobol (every number, or the pixel jitter only,
//! as `--mode temporal --sampler zsobol-jitter` uses it) and from the spatiotemporal sampler
//! (the basic trace kernel, which the Cornell box fits), and the seed
//! stream's frame from the full trace kernel (`kernels::trace_variant`),
//! measured on one device in one run, the samplers alternated round by
//! round so that clock and thermal drift fall on all of them alike.
//!
//! ```text
//! cargo bench -p gpu-tracer --bench gpu_samplers
//! ```
//!
//! Prints each sampler's median trace time and its excess over the seed
//! stream's, as a share of the seed stream's frame (issue 29's goal for the
//! spatiotemporal sampler: <= 3%), and the same per traced ray: a sampler's
//! numbers also choose the paths (how far Russian roulette lets them go,
//! what the light samples hit), so each row's rays are counted by the CPU
//! renderer on the same frame (white seeds, salt 1) and the per-ray excess
//! is what the numbers themselves cost. `ROUNDS=N` sets the number of rounds
//! (default 9; a lavapipe frame takes seconds); `--test` runs one;
//! `SAMPLERS=seed stream,spatiotemporal` keeps only the named rows (the seed
//! stream always runs: it is the baseline).

use gpu_tracer::cornell::cornell_box;
use gpu_tracer::gpu::{Gpu, PassTimer, PermutePipelines, SeedPermuter, TracePipelines, Tracer};
use gpu_tracer::{cpu, SceneGpu, TraceSettings, TraceVariant};
use kernels::abi::{
    SAMPLER_JITTER_ONLY, SAMPLER_KRONECKER, SAMPLER_SCREEN_SOBOL, SAMPLER_SEEDS, SAMPLER_SPATIOTEMPORAL,
    SAMPLER_ZSOBOL,
};
use sampler_core::FrameLayout;

const WIDTH: u32 = 1280;
const HEIGHT: u32 = 720;

/// The rows: name, `TraceParams::sampler` and the trace kernel variant
/// (the Cornell box fits the basic one, `kernels::trace_variant`; the last
/// row runs the full kernel on the same frame, for its cost).
const SAMPLERS: [(&str, u32, TraceVariant); 7] = [
    ("seed stream", SAMPLER_SEEDS, TraceVariant::Basic),
    ("screen-sobol", SAMPLER_SCREEN_SOBOL, TraceVariant::Basic),
    ("zsobol", SAMPLER_ZSOBOL, TraceVariant::Basic),
    (
        "zsobol-jitter",
        SAMPLER_ZSOBOL | SAMPLER_JITTER_ONLY,
        TraceVariant::Basic,
    ),
    ("spatiotemporal", SAMPLER_SPATIOTEMPORAL, TraceVariant::Basic),
    (
        "spatiotemporal-kronecker",
        SAMPLER_SPATIOTEMPORAL | SAMPLER_KRONECKER,
        TraceVariant::Basic,
    ),
    ("seed stream (full kernel)", SAMPLER_SEEDS, TraceVariant::Full),
];

mod common;

fn main() {
    let rounds = common::rounds(9);
    let gpu = match Gpu::new() {
        Ok(g) => g,
        Err(e) => {
            println!("gpu_samplers: SKIPPED, {e}");
            return;
        }
    };
    let scene = SceneGpu::build(&cornell_box()).expect("scene");
    let layout = FrameLayout::new(WIDTH, HEIGHT, 4, 64).expect("layout");
    let mut settings = TraceSettings::new(WIDTH, HEIGHT);
    settings.padded_width = layout.padded_width();
    let params = |sampler: u32| {
        let mut s = settings;
        s.sampler = sampler;
        scene.trace_params(&s, 1).expect("params")
    };
    let tp = TracePipelines::new(&gpu).expect("trace pipelines");
    let pp = PermutePipelines::new(&gpu).expect("permute pipelines");
    let color = Tracer::color_buffer(&gpu, WIDTH, HEIGHT);
    let (tile, tables) = (
        sampler_core::defaults::tile_64(),
        sampler_core::defaults::tables_64(),
    );
    let permuter = SeedPermuter::new(&gpu, &pp, layout, &tile, &tables, &color).expect("permuter");
    let mut tracer =
        Tracer::new(&gpu, &tp, &scene, &params(SAMPLER_SEEDS), &permuter.seeds, color).expect("tracer");
    permuter.set_frame(&gpu, 1);
    let mut e = gpu.device.create_command_encoder(&Default::default());
    permuter.encode_seed_init(&mut e, &pp);
    gpu.queue.submit([e.finish()]);

    let wanted = std::env::var("SAMPLERS").ok();
    let samplers: Vec<(&str, u32, TraceVariant)> = SAMPLERS
        .iter()
        .copied()
        .filter(|&(name, s, v)| {
            (s == SAMPLER_SEEDS && v == TraceVariant::Basic)
                || wanted.as_deref().is_none_or(|w| w.split(',').any(|x| x == name))
        })
        .collect();
    // Rays of each row's frame, counted on the CPU.
    let seeds = cpu::white_seeds(settings.padded_width, HEIGHT, 1);
    let mut cpu_color = vec![glam::Vec4::ZERO; (WIDTH * HEIGHT) as usize];
    let rays: Vec<u64> = samplers
        .iter()
        .map(|&(_, sampler, _)| {
            cpu::render_frame(&scene, &params(sampler), &seeds, &mut cpu_color).expect("cpu frame")
        })
        .collect();
    let timer = PassTimer::new(&gpu, 1);
    let mut ms = vec![Vec::new(); samplers.len()];
    // Round 0 warms every pipeline up and is not counted.
    for round in 0..=rounds {
        for (k, &(_, sampler, variant)) in samplers.iter().enumerate() {
            tracer.set_variant(&tp, &scene, variant).expect("variant");
            tracer.set_params(&gpu, &params(sampler));
            let t = common::time_trace(&gpu, &tracer, &tp, timer.as_ref());
            if round > 0 {
                ms[k].push(t);
            }
        }
    }
    println!(
        "gpu_samplers: {WIDTH}x{HEIGHT}, Cornell box 1 spp, depth 8, {rounds} rounds, on {}",
        gpu.describe()
    );
    println!("timing: {}", common::timing_name(timer.as_ref()));
    println!(
        "{:<26} {:>10} {:>10} {:>10} {:>22} {:>12} {:>22}",
        "sampler",
        "median ms",
        "min ms",
        "max ms",
        "excess, % of seed frame",
        "rays/frame",
        "excess per ray, %"
    );
    let medians: Vec<f64> = ms.iter_mut().map(|v| common::median(v)).collect();
    let per_ray: Vec<f64> = medians.iter().zip(&rays).map(|(m, r)| m / *r as f64).collect();
    for (k, (name, _, _)) in samplers.iter().enumerate() {
        let (v, m) = (&ms[k], medians[k]);
        let (lo, hi) = (v[0], v[v.len() - 1]);
        println!(
            "{name:<26} {m:>10.3} {lo:>10.3} {hi:>10.3} {:>21.2}% {:>12} {:>21.2}%",
            100.0 * (m - medians[0]) / medians[0],
            rays[k],
            100.0 * (per_ray[k] - per_ray[0]) / per_ray[0]
        );
    }
}
