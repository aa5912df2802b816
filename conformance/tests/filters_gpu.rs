//! The real-time filters on the GPU (`kernels::filter_entry` through
//! `gpu_tracer::gpu::FrameFilterGpu`) against the same kernel functions on
//! the CPU (`gpu_tracer::filter::FrameFilter`): every chain, a Cornell box
//! frame sequence with motion and disocclusion, within 1e-5 relative.
//!
//! Needs a GPU adapter (Mesa's lavapipe counts); without one the test prints
//! `SKIPPED` with the reason, and `BLUENOISE_REQUIRE_GPU=1` (set in CI)
//! turns that into a failure.

use glam::{Vec2, Vec4};
use gpu_tracer::cornell::cornell_box;
use gpu_tracer::cpu::{gbuffer_frame, render_frame, white_seeds};
use gpu_tracer::filter::{FilterChain, FilterSettings, FrameFilter};
use gpu_tracer::gpu::{FilterPipelines, FrameFilterGpu, Gpu};
use gpu_tracer::{SceneGpu, TraceSettings};
use kernels::abi::GBufferGpu;
use kernels::motion::DISOCCLUDED;

const W: u32 = 48;
const H: u32 = 40;

/// Frame `t`'s motion: still for frame 0, then a sub-pixel pan with a
/// disoccluded band and a few pixels pointing off screen.
fn motion(t: u32) -> Vec<Vec2> {
    (0..W * H)
        .map(|i| {
            let (x, y) = (i % W, i / W);
            match (t, x) {
                (0, _) => Vec2::ZERO,
                (_, 0..=2) => DISOCCLUDED,
                _ if y == 5 => Vec2::new(-100.0, 0.0),
                _ => Vec2::new(0.37 * t as f32, -0.21),
            }
        })
        .collect()
}

#[test]
fn every_filter_chain_matches_the_cpu() {
    let Some(gpu) = Gpu::for_test("every_filter_chain_matches_the_cpu") else {
        return;
    };
    let scene = SceneGpu::build(&cornell_box()).unwrap();
    let settings = TraceSettings::new(W, H);
    let params = scene.trace_params(&settings, 0).unwrap();
    let mut gbuffer = vec![GBufferGpu::default(); (W * H) as usize];
    gbuffer_frame(&scene, &params, &mut gbuffer).unwrap();
    let frames: Vec<Vec<Vec4>> = (0..4)
        .map(|t| {
            let p = scene.trace_params(&settings, t).unwrap();
            let seeds = white_seeds(W, H, 17 + t);
            let mut color = vec![Vec4::ZERO; (W * H) as usize];
            render_frame(&scene, &p, &seeds, &mut color).unwrap();
            color
        })
        .collect();
    let pipelines = FilterPipelines::new(&gpu).unwrap();
    let mut worst = 0.0f32;
    for chain in FilterChain::ALL {
        let s = FilterSettings::default();
        let mut cpu = FrameFilter::new(chain, s, W, H).unwrap();
        let mut dev = FrameFilterGpu::new(&gpu, &pipelines, chain, s, W, H).unwrap();
        for (t, color) in frames.iter().enumerate() {
            let m = motion(t as u32);
            let want = cpu.apply(color, &gbuffer, &m).unwrap();
            dev.upload(&gpu, color, &gbuffer, &m).unwrap();
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            dev.encode(&gpu, &mut encoder, &pipelines, None);
            gpu.queue.submit([encoder.finish()]);
            let got = dev.read_output(&gpu).unwrap();
            for (i, (a, b)) in want.iter().zip(&got).enumerate() {
                let (a, b) = (a.truncate(), b.truncate());
                let scale = a.abs().max(b.abs()).max_element().max(1e-3);
                let rel = (a - b).abs().max_element() / scale;
                worst = worst.max(rel);
                assert!(
                    rel <= 1e-5,
                    "{chain}, frame {t}, pixel {i}: CPU {a} GPU {b} (relative {rel:e})"
                );
            }
        }
    }
    println!("largest relative difference over every chain and frame: {worst:e}");
    // Bad input is refused on the device side too.
    let bad = FilterSettings {
        alpha: 0.0,
        ..Default::default()
    };
    assert!(FrameFilterGpu::new(&gpu, &pipelines, FilterChain::Taa, bad, W, H).is_err());
    let dev = FrameFilterGpu::new(
        &gpu,
        &pipelines,
        FilterChain::Taa,
        FilterSettings::default(),
        W,
        H,
    )
    .unwrap();
    assert!(dev.upload(&gpu, &frames[0][1..], &gbuffer, &motion(0)).is_err());
}
