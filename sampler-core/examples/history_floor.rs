//! How low can a history's error go with one sequence in time? The
//! spatiotemporal sampler gives every pixel the same sequence of 2D points
//! over frames, rotated by the pixel's shift. This example optimises a free
//! periodic sequence of 128 points for exactly the figure a history keeps
//! (`bake::bake_history_sequence`: the steady-state EMA of alpha 0.1 over
//! every window of the period, with or without the running means), from the
//! shipped Kronecker sequence of pair 0 and from random points, on 256
//! training Heaviside steps x 24 shifts, and scores the result on 64
//! held-out steps x 64 shifts (white noise = 1).
//!
//! ```text
//! cargo run --release -p sampler-core --features bake,defaults --example history_floor
//! ```

use sampler_core::bake::{
    bake_history_sequence, heaviside_integrands, history_sequence_figures, HistorySequenceParams, MEAN_WEIGHT,
};
use sampler_core::sequences::kronecker::kronecker_point_u32;
use sampler_core::sequences::seed::hash_u32;

fn main() {
    let base = HistorySequenceParams::default();
    let train = heaviside_integrands(256, 4242);
    let held = heaviside_integrands(64, 777);
    let period = 128u32;
    let kronecker: Vec<[u32; 2]> = (0..period).map(|n| kronecker_point_u32(n, 0)).collect();
    let random: Vec<[u32; 2]> = (0..period)
        .map(|n| {
            let a = hash_u32(2 * n + 99);
            [a, hash_u32(a)]
        })
        .collect();
    let show = |name: &str, points: &[[u32; 2]]| {
        let f = history_sequence_figures(points, &held, 64, base.alpha, 9);
        println!(
            "{name:<52} history {:.3}  mean 8 / 32 / 128 {:.3} / {:.3} / {:.3}",
            f[0], f[1], f[2], f[3]
        );
    };
    println!("held-out steps, white noise = 1");
    show("random points (start)", &random);
    show("Kronecker, pair 0 (shipped)", &kronecker);
    for alpha in [0.05, 0.2] {
        let f = history_sequence_figures(&kronecker, &held, 64, alpha, 9);
        let name = format!("Kronecker, pair 0, a history of alpha {alpha}");
        println!("{name:<52} history {:.3}", f[0]);
    }
    for (name, start, mean_weight) in [
        ("optimised for the history, from random points", &random, 0.0),
        ("optimised for the history, from Kronecker", &kronecker, 0.0),
        (
            "optimised for history + means, from Kronecker",
            &kronecker,
            MEAN_WEIGHT,
        ),
    ] {
        let params = HistorySequenceParams { mean_weight, ..base };
        let (points, _) = bake_history_sequence(&params, &train, start).expect("valid parameters");
        show(name, &points);
    }
}
