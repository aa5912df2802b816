//! What each built-in scene's paths cost on the GPU per ray: the 1-spp
//! path-traced frame (1280x720, max depth 8, seed stream) of the Lambertian
//! Cornell box, the glossy Cornell box (GGX spheres: NEE with MIS at
//! glossy vertices) and the outdoor `sun-sky` scene (a sun disk sampled in
//! its cone, a constant sky, open space) and the textured box
//! (`tests/data/gltf/cornell_textured.gltf`: filtered textures), alternated
//! round by round on one device in one run.
//!
//! ```text
//! cargo bench -p gpu-tracer --bench gpu_scenes
//! ```
//!
//! Prints each scene's median trace time, the rays its frame traces
//! (camera, continuation and shadow rays: every BVH query, counted by the
//! CPU renderer on the same frame with white seeds, `kernels::trace_pixel_counted_variant`),
//! the time per ray and its ratio to the Cornell box's first row. Each
//! scene runs on the smallest trace kernel that renders it exactly
//! (`kernels::trace_variant`), and again on the full kernel. Issue 30's goal is
//! <= 1.5x per path vertex for the glossy and the outdoor scene on
//! lavapipe. The glossy box runs once more with path regularisation
//! (`--glossy-regularization 1`: the same kernel, its paths found by other
//! rays), for what it costs per ray. `ROUNDS=N` sets the rounds (default 5;
//! a lavapipe frame takes seconds); `--test` runs one; `SCENES=cornell,
//! cornell-glossy` keeps only the named scenes (the Cornell box always runs:
//! it is the baseline); `SMALLEST=1` skips the full-kernel rows;
//! `JITTER=zsobol` takes the pixel jitter (and, at sharp first hits, vertex
//! 0's pairs) from ZSobol, as the render defaults do, instead of the seeds.

use glam::Vec4;
use gpu_tracer::cornell::{cornell_box, cornell_glossy};
use gpu_tracer::gpu::{Gpu, PassTimer, PermutePipelines, SeedPermuter, TracePipelines, Tracer};
use gpu_tracer::outdoor::{sun_and_sky, SKY};
use gpu_tracer::{cpu, SceneGpu, TraceSettings, TraceVariant};
use sampler_core::FrameLayout;

const WIDTH: u32 = 1280;
const HEIGHT: u32 = 720;

mod common;

fn main() {
    let rounds = common::rounds(5);
    let gpu = match Gpu::new() {
        Ok(g) => g,
        Err(e) => {
            println!("gpu_scenes: SKIPPED, {e}");
            return;
        }
    };
    let layout = FrameLayout::new(WIDTH, HEIGHT, 4, 64).expect("layout");
    // (name, scene, constant sky, path regularisation strength)
    let scenes = [
        ("cornell", cornell_box(), glam::Vec3::ZERO, 0.0),
        ("cornell-glossy", cornell_glossy(), glam::Vec3::ZERO, 0.0),
        ("glossy-reg-1", cornell_glossy(), glam::Vec3::ZERO, 1.0),
        ("sun-sky", sun_and_sky(), SKY, 0.0),
        // The textured box (filtered textures, the full kernel), as the
        // study's held-out scene.
        (
            "cornell-textured",
            gpu_tracer::gltf::load_gltf(
                concat!(
                    env!("CARGO_MANIFEST_DIR"),
                    "/tests/data/gltf/cornell_textured.gltf"
                ),
                None,
            )
            .expect("the textured fixture")
            .scene,
            glam::Vec3::ZERO,
            0.0,
        ),
    ];
    let wanted = std::env::var("SCENES").ok();
    let smallest_only = std::env::var("SMALLEST").is_ok_and(|v| v == "1");
    let sampler = if std::env::var("JITTER").is_ok_and(|v| v == "zsobol") {
        kernels::abi::SAMPLER_ZSOBOL | kernels::abi::SAMPLER_JITTER_ONLY
    } else {
        kernels::abi::SAMPLER_SEEDS
    };
    let tp = TracePipelines::new(&gpu).expect("trace pipelines");
    let pp = PermutePipelines::new(&gpu).expect("permute pipelines");
    let (tile, tables) = (
        sampler_core::defaults::tile_64(),
        sampler_core::defaults::tables_64(),
    );
    let mut rows = Vec::new();
    let mut tracers = Vec::new();
    for (name, scene, sky, regularization) in scenes {
        if name != "cornell"
            && wanted
                .as_deref()
                .is_some_and(|w| !w.split(',').any(|x| x == name))
        {
            continue;
        }
        let scene = SceneGpu::build(&scene).expect("scene");
        let mut settings = TraceSettings::new(WIDTH, HEIGHT);
        settings.padded_width = layout.padded_width();
        settings.environment = sky;
        settings.glossy_regularization = regularization;
        settings.sampler = sampler;
        let params = scene.trace_params(&settings, 1).expect("params");
        // Rays of one frame, counted on the CPU.
        let seeds = cpu::white_seeds(settings.padded_width, HEIGHT, 1);
        let mut color = vec![Vec4::ZERO; (WIDTH * HEIGHT) as usize];
        let rays = cpu::render_frame(&scene, &params, &seeds, &mut color).expect("cpu frame");
        let gpu_color = Tracer::color_buffer(&gpu, WIDTH, HEIGHT);
        let permuter = SeedPermuter::new(&gpu, &pp, layout, &tile, &tables, &gpu_color).expect("permuter");
        let tracer = Tracer::new(&gpu, &tp, &scene, &params, &permuter.seeds, gpu_color).expect("tracer");
        let smallest = tracer.variant();
        permuter.set_frame(&gpu, 1);
        let mut e = gpu.device.create_command_encoder(&Default::default());
        permuter.encode_seed_init(&mut e, &pp);
        gpu.queue.submit([e.finish()]);
        tracers.push((scene, tracer));
        let t = tracers.len() - 1;
        rows.push((name, rays, t, smallest, Vec::new()));
        if smallest != TraceVariant::Full && !smallest_only {
            rows.push((name, rays, t, TraceVariant::Full, Vec::new()));
        }
    }
    let timer = PassTimer::new(&gpu, 1);
    // Round 0 warms every pipeline up and is not counted.
    for round in 0..=rounds {
        for (_, _, k, variant, ms) in rows.iter_mut() {
            let (scene, tracer) = &mut tracers[*k];
            tracer.set_variant(&tp, scene, *variant).expect("variant");
            let t = common::time_trace(&gpu, tracer, &tp, timer.as_ref());
            if round > 0 {
                ms.push(t);
            }
        }
    }
    println!(
        "gpu_scenes: {WIDTH}x{HEIGHT}, 1 spp, depth 8, {}, {rounds} rounds, on {}",
        if sampler == kernels::abi::SAMPLER_SEEDS {
            "seed stream"
        } else {
            "zsobol jitter"
        },
        gpu.describe()
    );
    println!("timing: {}", common::timing_name(timer.as_ref()));
    println!(
        "{:<16} {:<11} {:>10} {:>12} {:>10} {:>22}",
        "scene", "kernel", "median ms", "rays/frame", "ns/ray", "per ray, x cornell"
    );
    let per_ray: Vec<f64> = rows
        .iter_mut()
        .map(|(_, rays, _, _, ms)| common::median(ms) * 1e6 / *rays as f64)
        .collect();
    for ((name, rays, _, variant, ms), ns) in rows.iter_mut().zip(&per_ray) {
        println!(
            "{name:<16} {:<11} {:>10.3} {rays:>12} {ns:>10.3} {:>21.3}x",
            variant.name(),
            common::median(ms),
            ns / per_ray[0]
        );
    }
}
