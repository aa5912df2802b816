//! The trace kernel's smaller variants (`kernels::trace_variant`) against
//! the full one on the GPU, and against the CPU renderer's same variant.

use glam::Vec4;
use gpu_tracer::cornell::cornell_box;
use gpu_tracer::gpu::{Gpu, PermutePipelines, SeedPermuter, TracePipelines, Tracer};
use gpu_tracer::{cpu, SceneGpu, TraceSettings, TraceVariant};
use kernels::abi::{SAMPLER_SEEDS, SAMPLER_SPATIOTEMPORAL};
use sampler_core::FrameLayout;

/// The Cornell box traced by `trace_basic_cs` and by `trace_cs` from the
/// same seeds: the same colours (float rounding of two compiled shaders
/// aside: at least 99% of pixels within 1e-4 relative), and the basic
/// variant's frame close to the CPU's; likewise the glossy box through
/// `trace_untextured_cs`, which refuses the basic variant.
#[test]
fn the_smaller_trace_kernels_match_the_full_one() {
    let Some(gpu) = Gpu::for_test("the_smaller_trace_kernels_match_the_full_one") else {
        return;
    };
    let scene = SceneGpu::build(&cornell_box()).unwrap();
    assert_eq!(scene.trace_variant(), TraceVariant::Basic);
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
    let close = |a: &[Vec4], b: &[Vec4], tol: f32| {
        a.iter()
            .zip(b)
            .filter(|(p, q)| (**p - **q).abs().max_element() <= tol * (1.0 + p.abs().max_element()))
            .count() as f64
            / a.len() as f64
    };

    for sampler in [SAMPLER_SEEDS, SAMPLER_SPATIOTEMPORAL] {
        let mut settings = TraceSettings::new(w, h);
        settings.padded_width = layout.padded_width();
        settings.spp = 2;
        settings.sampler = sampler;
        let params = scene.trace_params(&settings, 3).unwrap();
        let mut tracer =
            Tracer::new(&gpu, &tp, &scene, &params, &permuter.seeds, color.clone()).expect("tracer");
        tracer.set_params(&gpu, &params);
        let mut frame = |variant: TraceVariant| -> Vec<Vec4> {
            tracer.set_variant(&tp, &scene, variant).unwrap();
            let mut e = gpu.device.create_command_encoder(&Default::default());
            tracer.encode_trace(&mut e, &tp, None);
            gpu.queue.submit([e.finish()]);
            gpu.read(&tracer.color, (w * h) as usize).unwrap()
        };
        let basic = frame(TraceVariant::Basic);
        let full = frame(TraceVariant::Full);
        let mut on_cpu = vec![Vec4::ZERO; (w * h) as usize];
        cpu::render_frame_variant(&scene, &params, &seeds, &mut on_cpu, TraceVariant::Basic).unwrap();
        assert!(basic.iter().any(|c| c.x > 0.0), "a black frame proves nothing");
        let same = close(&full, &basic, 1e-4);
        let cpu_gpu = close(&on_cpu, &basic, 1e-3);
        eprintln!(
            "sampler {sampler:#x}: basic vs full on the GPU {:.2}% within 1e-4, basic GPU vs CPU {:.2}% within 1e-3",
            100.0 * same,
            100.0 * cpu_gpu
        );
        assert!(
            same >= 0.99,
            "basic and full kernels differ: {:.2}% close",
            100.0 * same
        );
        assert!(
            cpu_gpu >= 0.95,
            "basic kernel against the CPU: {:.2}% close",
            100.0 * cpu_gpu
        );
    }

    // The glossy box: the untextured kernel against the full one and the
    // CPU; the basic kernel refused.
    let glossy = SceneGpu::build(&gpu_tracer::cornell::cornell_glossy()).unwrap();
    let mut settings = TraceSettings::new(w, h);
    settings.padded_width = layout.padded_width();
    settings.spp = 2;
    let params = glossy.trace_params(&settings, 0).unwrap();
    let mut tracer =
        Tracer::new(&gpu, &tp, &glossy, &params, &permuter.seeds, color.clone()).expect("tracer");
    assert_eq!(tracer.variant(), TraceVariant::Untextured);
    assert!(tracer.set_variant(&tp, &glossy, TraceVariant::Basic).is_err());
    tracer.set_params(&gpu, &params);
    let mut frame = |variant: TraceVariant| -> Vec<Vec4> {
        tracer.set_variant(&tp, &glossy, variant).unwrap();
        let mut e = gpu.device.create_command_encoder(&Default::default());
        tracer.encode_trace(&mut e, &tp, None);
        gpu.queue.submit([e.finish()]);
        gpu.read(&tracer.color, (w * h) as usize).unwrap()
    };
    let untextured = frame(TraceVariant::Untextured);
    let full = frame(TraceVariant::Full);
    let mut on_cpu = vec![Vec4::ZERO; (w * h) as usize];
    cpu::render_frame_variant(&glossy, &params, &seeds, &mut on_cpu, TraceVariant::Untextured).unwrap();
    let same = close(&full, &untextured, 1e-4);
    let cpu_gpu = close(&on_cpu, &untextured, 1e-3);
    eprintln!(
        "glossy: untextured vs full on the GPU {:.2}% within 1e-4, untextured GPU vs CPU {:.2}% within 1e-3",
        100.0 * same,
        100.0 * cpu_gpu
    );
    assert!(
        same >= 0.99,
        "untextured and full kernels differ: {:.2}% close",
        100.0 * same
    );
    assert!(
        cpu_gpu >= 0.95,
        "untextured kernel against the CPU: {:.2}% close",
        100.0 * cpu_gpu
    );
}
