//! The trace kernel's smaller variants (`kernels::trace_variant`) on the
//! GPU against the CPU renderer's full kernel (the CPU's own test shows each
//! variant equal to the full kernel bit for bit; the full kernel's GPU
//! build is exercised by the textured scenes of [`super::trace`], and is
//! not compiled here: it takes lavapipe 13 s).

use glam::Vec4;
use gpu_tracer::cornell::{cornell_box, cornell_glossy};
use gpu_tracer::gpu::{Gpu, PermutePipelines, SeedPermuter, TracePipelines, Tracer};
use gpu_tracer::{cpu, SceneGpu, TraceSettings, TraceVariant};
use kernels::abi::{SAMPLER_SEEDS, SAMPLER_SPATIOTEMPORAL};
use sampler_core::FrameLayout;

/// The Cornell box through `trace_basic_cs` and the glossy box through
/// `trace_untextured_cs` (the kernels `Tracer::new` picks for them), from
/// the seeds the GPU initialised: the CPU's full kernel on the same seeds
/// agrees within float rounding on at least 99% of pixels (1e-3
/// relative); the basic kernel is refused for the glossy box.
#[test]
fn the_smaller_trace_kernels_match_the_cpu() {
    let Some(gpu) = Gpu::for_test("the_smaller_trace_kernels_match_the_cpu") else {
        return;
    };
    let (w, h) = (40u32, 32u32);
    let layout = FrameLayout::new(w, h, 4, 64).unwrap();
    let tp = TracePipelines::new(&gpu).unwrap();
    let pp = PermutePipelines::new(&gpu).unwrap();
    let color = Tracer::color_buffer(&gpu, w, h);
    let (tile, tables) = (
        sampler_core::defaults::tile_64(),
        sampler_core::defaults::tables_64(),
    );
    let permuter = SeedPermuter::new(&gpu, &pp, layout, &tile, &tables, &color).unwrap();
    permuter.set_frame(&gpu, 1);
    let mut e = gpu.device.create_command_encoder(&Default::default());
    permuter.encode_seed_init(&mut e, &pp);
    gpu.queue.submit([e.finish()]);
    let seeds: Vec<u32> = gpu.read(&permuter.seeds, layout.seed_count()).unwrap();

    let cases = [
        ("cornell", cornell_box(), TraceVariant::Basic, SAMPLER_SEEDS),
        (
            "cornell",
            cornell_box(),
            TraceVariant::Basic,
            SAMPLER_SPATIOTEMPORAL,
        ),
        (
            "cornell-glossy",
            cornell_glossy(),
            TraceVariant::Untextured,
            SAMPLER_SEEDS,
        ),
    ];
    for (name, scene, variant, sampler) in cases {
        let scene = SceneGpu::build(&scene).unwrap();
        let mut settings = TraceSettings::new(w, h);
        settings.padded_width = layout.padded_width();
        settings.spp = 2;
        settings.sampler = sampler;
        let params = scene.trace_params(&settings, 3).unwrap();
        let mut tracer =
            Tracer::new(&gpu, &tp, &scene, &params, &permuter.seeds, color.clone()).expect("tracer");
        assert_eq!(tracer.variant(), variant, "{name}");
        if variant != TraceVariant::Basic {
            assert!(tracer.set_variant(&tp, &scene, TraceVariant::Basic).is_err());
        }
        tracer.set_params(&gpu, &params);
        let mut e = gpu.device.create_command_encoder(&Default::default());
        tracer.encode_trace(&mut e, &tp, None);
        gpu.queue.submit([e.finish()]);
        let on_gpu: Vec<Vec4> = gpu.read(&tracer.color, (w * h) as usize).unwrap();
        let mut on_cpu = vec![Vec4::ZERO; (w * h) as usize];
        cpu::render_frame_variant(&scene, &params, &seeds, &mut on_cpu, TraceVariant::Full).unwrap();
        assert!(on_cpu.iter().any(|c| c.x > 0.0), "a black frame proves nothing");
        let close = on_cpu
            .iter()
            .zip(&on_gpu)
            .filter(|(p, q)| (**p - **q).abs().max_element() <= 1e-3 * (1.0 + p.abs().max_element()))
            .count() as f64
            / on_cpu.len() as f64;
        eprintln!(
            "{name}, sampler {sampler:#x}: the {} kernel on the GPU against the CPU's full kernel: {:.2}% within 1e-3",
            variant.name(),
            100.0 * close
        );
        assert!(close >= 0.99, "{name}: {:.2}% close", 100.0 * close);
    }
}
