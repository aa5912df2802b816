//! The spatiotemporal sampler without a renderer: every pixel of a 64x64
//! torus integrates the same held-out Heaviside steps, and `bake::field_quality`
//! reports each frame's blurred error, an exponential history's error and the
//! history blurred (white noise = 1), for the Sobol and Kronecker sequences in
//! time and for the scalar shift tile against a baked jointly blue one.
//!
//! ```text
//! cargo run --release -p sampler-core --features bake,defaults --example history_model
//! ```

use glam::UVec2;
use sampler_core::bake::{
    bake_shift_tile, field_quality, heaviside_integrands, no_progress, unpack_shift, FieldQuality,
    ShiftTileParams,
};
use sampler_core::sequences::seed::hash_u32;
use sampler_core::sequences::spatiotemporal::{
    spatiotemporal_sequence_point_u32, spatiotemporal_shift_u32, SEQUENCE_KRONECKER, SEQUENCE_SOBOL,
};
use sampler_core::walk_offset;

fn main() {
    let (side, frames, skip, alpha) = (64u32, 128u32, 16u32, 0.1);
    // Held out: the bake trains on other integrands and on pairs 0 and 1.
    let integrands = heaviside_integrands(24, 777);
    let pairs = 4..7u32;
    let run = |sample: &dyn Fn(UVec2, u32, u32) -> [u32; 2]| {
        field_quality(side, pairs.clone(), frames, skip, alpha, &integrands, sample)
    };
    let white = run(&|p, pair, t| {
        let key = hash_u32(p.x ^ hash_u32(p.y ^ hash_u32(pair ^ hash_u32(t))));
        [key, hash_u32(key)]
    });
    let tile = sampler_core::defaults::tile_64();
    let scalar = |sequence: u32| {
        move |p: UVec2, pair: u32, t: u32| {
            let s = spatiotemporal_shift_u32(tile.values(), 6, p, pair);
            let x = spatiotemporal_sequence_point_u32(sequence, t, pair);
            [x[0].wrapping_add(s[0]), x[1].wrapping_add(s[1])]
        }
    };
    let baked = bake_shift_tile(&ShiftTileParams::default(), &mut no_progress).expect("default parameters");
    let vector = |p: UVec2, pair: u32, t: u32| {
        let o = walk_offset(pair + 1, 6);
        let s = unpack_shift(baked.words[(((p.y + o.y) & 63) * 64 + ((p.x + o.x) & 63)) as usize]);
        let x = spatiotemporal_sequence_point_u32(SEQUENCE_SOBOL, t, pair);
        [x[0].wrapping_add(s[0]), x[1].wrapping_add(s[1])]
    };
    let show = |name: &str, q: FieldQuality| {
        let r = q.relative_to(&white);
        println!(
            "{name:<40} frame blur {:.3}  history {:.3}  history blur {:.3}",
            r.raw_blur, r.history, r.history_blur
        );
    };
    show("Sobol in time, scalar shift tile", run(&scalar(SEQUENCE_SOBOL)));
    show(
        "Kronecker in time, scalar shift tile",
        run(&scalar(SEQUENCE_KRONECKER)),
    );
    show("Sobol in time, baked jointly blue shifts", run(&vector));
}
