//! What the GPU benches share: their round count, one timed trace pass,
//! and the median.

use gpu_tracer::gpu::{Gpu, PassTimer, TracePipelines, Tracer};
use std::time::Instant;

/// Rounds to run: 1 with `--test` (what `cargo test --benches` passes),
/// else `ROUNDS` from the environment, else `default`; at least 1.
pub fn rounds(default: usize) -> usize {
    if std::env::args().any(|a| a == "--test") {
        return 1;
    }
    std::env::var("ROUNDS")
        .ok()
        .and_then(|r| r.parse().ok())
        .unwrap_or(default)
        .max(1)
}

/// Milliseconds of one trace pass of `tracer`: the device's timestamps
/// when `timer` exists, else the wall clock of the submission.
pub fn time_trace(gpu: &Gpu, tracer: &Tracer, pipelines: &TracePipelines, timer: Option<&PassTimer>) -> f64 {
    let mut e = gpu.device.create_command_encoder(&Default::default());
    tracer.encode_trace(&mut e, pipelines, timer.map(|t| (t, 0)));
    if let Some(t) = timer {
        t.resolve(&mut e);
    }
    let start = Instant::now();
    gpu.queue.submit([e.finish()]);
    gpu.wait().expect("wait");
    let wall = start.elapsed().as_secs_f64() * 1e3;
    match timer {
        Some(t) => t.read_ms(gpu).expect("timestamps")[0],
        None => wall,
    }
}

/// How [`time_trace`] timed: for the printed header.
pub fn timing_name(timer: Option<&PassTimer>) -> &'static str {
    if timer.is_some() {
        "timestamp queries"
    } else {
        "wall clock per submission"
    }
}

/// The median of `v` (sorted in place); `v` must not be empty.
pub fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}
