//! The real-time filters on the CPU at 1920x1080 (`gpu_tracer::filter`, the
//! kernels' per-pixel functions over rayon's pool): each chain's time per
//! frame on the Cornell box's G-buffer with a noisy 1-spp-like frame, beside
//! a copy of the frame's bytes on the same threads, in one run.
//!
//! ```text
//! cargo bench -p gpu-tracer --bench cpu_filters
//! ```

use glam::{Vec2, Vec4};
use gpu_tracer::cornell::cornell_box;
use gpu_tracer::cpu::gbuffer_frame;
use gpu_tracer::filter::{FilterChain, FilterSettings, FrameFilter};
use gpu_tracer::{SceneGpu, TraceSettings};
use kernels::abi::GBufferGpu;
use std::time::Instant;

const WIDTH: u32 = 1920;
const HEIGHT: u32 = 1080;

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

fn main() {
    let quick = std::env::args().any(|a| a == "--test");
    let rounds = if quick { 1 } else { 9 };
    let (w, h) = if quick { (64, 36) } else { (WIDTH, HEIGHT) };
    let scene = SceneGpu::build(&cornell_box()).expect("scene");
    let params = scene.trace_params(&TraceSettings::new(w, h), 0).expect("params");
    let mut gbuffer = vec![GBufferGpu::default(); (w * h) as usize];
    gbuffer_frame(&scene, &params, &mut gbuffer).expect("g-buffer");
    let frame = |t: u32| -> Vec<Vec4> {
        gbuffer
            .iter()
            .enumerate()
            .map(|(i, g)| {
                let r = sampler_core::sequences::seed::hash_u32(i as u32 ^ t.wrapping_mul(0x9e37_79b9));
                let noise = 2.0 * (r >> 8) as f32 / (1u32 << 24) as f32;
                (g.albedo.truncate() * noise).extend(1.0)
            })
            .collect()
    };
    let frames: Vec<Vec<Vec4>> = (0..2).map(frame).collect();
    let still = vec![Vec2::ZERO; (w * h) as usize];
    let threads = rayon::current_num_threads();
    println!("cpu_filters: {w}x{h}, {threads} rayon thread(s), median of {rounds} frames");
    let mut copy_ms = Vec::new();
    let mut sink = vec![Vec4::ZERO; frames[0].len()];
    for k in 0..rounds {
        let start = Instant::now();
        sink.copy_from_slice(&frames[k % 2]);
        copy_ms.push(start.elapsed().as_secs_f64() * 1e3);
        std::hint::black_box(&sink);
    }
    let copy = median(&mut copy_ms);
    println!("{:<14} {:>9.3} ms (16 B/px)", "copy", copy);
    for chain in [
        FilterChain::Taa,
        FilterChain::Gauss,
        FilterChain::Atrous,
        FilterChain::TaaAtrous,
    ] {
        let mut filter = FrameFilter::new(chain, FilterSettings::default(), w, h).expect("filter");
        let mut ms = Vec::new();
        for k in 0..rounds + 1 {
            let start = Instant::now();
            let out = filter.apply(&frames[k % 2], &gbuffer, &still).expect("filter");
            std::hint::black_box(out);
            if k > 0 {
                ms.push(start.elapsed().as_secs_f64() * 1e3);
            }
        }
        let ms = median(&mut ms);
        println!("{:<14} {ms:>9.3} ms ({:.0}x the copy)", chain.name(), ms / copy);
    }
}
