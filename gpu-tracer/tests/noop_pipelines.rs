//! Validates the committed SPIR-V, every pipeline and every bind group on
//! wgpu's no-op backend: runs on any machine, GPU or not, so a layout
//! mistake can never hide behind a skipped GPU test.

use gpu_tracer::cornell::cornell_box;
use gpu_tracer::gpu::{Gpu, PermuteMode, PermutePipelines, SeedPermuter, TracePipelines, Tracer};
use gpu_tracer::{SceneGpu, TraceSettings};
use sampler_core::FrameLayout;

#[test]
fn kernels_pipelines_and_bind_groups_validate() {
    let gpu = Gpu::noop().expect("no-op device with the kernels module");
    let tp = TracePipelines::new(&gpu).expect("trace pipelines");
    let pp = PermutePipelines::new(&gpu).expect("permute pipelines");
    let scene = SceneGpu::build(&cornell_box()).unwrap();
    let layout = FrameLayout::new(33, 17, 4, 64).unwrap();
    let mut settings = TraceSettings::new(33, 17);
    settings.padded_width = layout.padded_width();
    let params = scene.trace_params(&settings, 0).unwrap();
    let (tile, tables) = (
        sampler_core::defaults::tile_64(),
        sampler_core::defaults::tables_64(),
    );
    let color = Tracer::color_buffer(&gpu, 33, 17);
    let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let permuter = SeedPermuter::new(&gpu, &pp, layout, &tile, &tables, &color).unwrap();
    let mut tracer = Tracer::new(&gpu, &tp, &scene, &params, &permuter.seeds, color).expect("tracer");
    let mut e = gpu.device.create_command_encoder(&Default::default());
    tracer.encode_trace(&mut e, &tp, None);
    // Every trace kernel variant, through the one bind group.
    assert_eq!(tracer.variant(), gpu_tracer::TraceVariant::Basic);
    for variant in [
        gpu_tracer::TraceVariant::Untextured,
        gpu_tracer::TraceVariant::Full,
    ] {
        tracer.set_variant(&tp, &scene, variant).expect("trace variant");
        tracer.encode_trace(&mut e, &tp, None);
    }
    tracer.encode_accumulate(&mut e, &tp);
    // The trace bind group holds bindings 0..=7 (7 = screen-space Sobol keys):
    // auto layouts reject a group with a binding the shader lacks or without
    // one it declares. Every sampler runs through the same group.
    use kernels::abi::{SAMPLER_JITTER_ONLY, SAMPLER_SCREEN_SOBOL, SAMPLER_ZSOBOL};
    for sampler in [
        SAMPLER_SCREEN_SOBOL,
        SAMPLER_ZSOBOL,
        SAMPLER_SCREEN_SOBOL | SAMPLER_JITTER_ONLY,
        SAMPLER_ZSOBOL | SAMPLER_JITTER_ONLY,
    ] {
        settings.sampler = sampler;
        tracer.set_params(&gpu, &scene.trace_params(&settings, 1).unwrap());
        tracer.encode_trace(&mut e, &tp, None);
    }
    permuter.encode_intensity(&mut e, &pp);
    for mode in [PermuteMode::White, PermuteMode::Sort, PermuteMode::Permute] {
        permuter.encode_step(&mut e, &pp, 3, mode, None);
    }
    gpu.queue.submit([e.finish()]);
    let error = pollster::block_on(scope.pop());
    assert!(error.is_none(), "validation error: {error:?}");
}
