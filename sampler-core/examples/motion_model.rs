//! Why the spatiotemporal sampler's gain behind a history is lost in motion, without a
//! renderer: a 64x64 torus of pixels watches a picture of sharp stripes (edges in every
//! direction, like silhouettes) slide by a constant sub-pixel or whole-pixel motion,
//! each pixel estimates its box integral from one jittered sample a frame, and a
//! reprojecting exponential history (alpha 0.1) runs over each frame's error (the "EMA
//! noise part" of the motion study). It prints that history's RMS error over frames
//! 16.. against white noise's (white = 1) for:
//!
//! - **screen**: the spatiotemporal sampler's Kronecker sequence with each pixel's
//!   blue-noise shift read at the pixel (`--mode white`);
//! - **follow**: the shift read where the picture's pixel came from, rounded to whole
//!   pixels (what the seed reprojection's homes do at best);
//! - **compensated**: the same, and the jitter offset by the sub-pixel part of the
//!   accumulated motion, so that a picture cell's samples are the consecutive points of
//!   its own sequence (wrapped into the pixel box, which keeps every frame unbiased);
//!
//! each with the history read at the nearest pixel and bilinearly (sub-pixel).
//!
//! ```text
//! cargo run --release -p sampler-core --features defaults --example motion_model
//! ```

use glam::{UVec2, Vec2};
use sampler_core::sequences::seed::hash_u32;
use sampler_core::sequences::spatiotemporal::{
    spatiotemporal_sequence_point_u32, spatiotemporal_shift_u32, SEQUENCE_KRONECKER,
};

const SIDE: usize = 64;
const FRAMES: u32 = 96;
const SKIP: u32 = 16;
const ALPHA: f64 = 0.1;
/// Supersampling of the reference box integrals, per axis.
const REFERENCE_GRID: usize = 16;

/// A picture periodic on the torus: 1 where `frac(k . x / SIDE + phase) < 0.5`.
struct Stripes {
    k: Vec2,
    phase: f32,
}

impl Stripes {
    fn eval(&self, x: Vec2) -> f64 {
        let s = self.k.dot(x) / SIDE as f32 + self.phase;
        f64::from(u8::from(s - s.floor() < 0.5))
    }
}

#[derive(Clone, Copy, PartialEq)]
enum Sampler {
    White,
    Screen,
    Follow,
    Compensated,
}

#[derive(Clone, Copy, PartialEq)]
enum Fetch {
    Nearest,
    Bilinear,
}

const Q: f32 = 1.0 / 4_294_967_296.0;

/// Pixel `p`'s jitter in frame `t` (each coordinate in `[0, 1)`) when the picture has
/// moved by `moved` pixels since frame 0.
fn jitter(sampler: Sampler, tile: &[u32], p: UVec2, t: u32, moved: Vec2) -> Vec2 {
    let wrap = |v: f32| v.rem_euclid(SIDE as f32) as u32;
    let sequence = |home: UVec2| {
        let shift = spatiotemporal_shift_u32(tile, 6, home, 0);
        let x = spatiotemporal_sequence_point_u32(SEQUENCE_KRONECKER, t, 0);
        Vec2::new(
            x[0].wrapping_add(shift[0]) as f32 * Q,
            x[1].wrapping_add(shift[1]) as f32 * Q,
        )
    };
    match sampler {
        Sampler::White => {
            let a = hash_u32(p.x ^ hash_u32(p.y ^ hash_u32(t ^ 0x5bd1_e995)));
            Vec2::new(a as f32 * Q, hash_u32(a) as f32 * Q)
        }
        Sampler::Screen => sequence(p),
        Sampler::Follow => {
            let home = p.as_vec2() - moved.round();
            sequence(UVec2::new(wrap(home.x), wrap(home.y)))
        }
        Sampler::Compensated => {
            // The picture cell whose origin is `p - floor(moved)`; the pixel box
            // starts `frac(moved)` before it, so the cell's point `y` sits at
            // `frac(y + frac(moved))` in the box.
            let home = p.as_vec2() - moved.floor();
            let y = sequence(UVec2::new(wrap(home.x), wrap(home.y)));
            let f = moved - moved.floor();
            Vec2::new((y.x + f.x).fract(), (y.y + f.y).fract())
        }
    }
}

/// The history `h` (toroidal) at position `x` in pixels.
fn fetch(h: &[f64], fetch: Fetch, x: Vec2) -> f64 {
    let at =
        |x: i64, y: i64| h[y.rem_euclid(SIDE as i64) as usize * SIDE + x.rem_euclid(SIDE as i64) as usize];
    match fetch {
        Fetch::Nearest => at(x.x.floor() as i64, x.y.floor() as i64),
        Fetch::Bilinear => {
            let c = x - Vec2::splat(0.5);
            let (x0, y0) = (c.x.floor(), c.y.floor());
            let (fx, fy) = (f64::from(c.x - x0), f64::from(c.y - y0));
            let (x0, y0) = (x0 as i64, y0 as i64);
            let top = at(x0, y0) * (1.0 - fx) + at(x0 + 1, y0) * fx;
            let bottom = at(x0, y0 + 1) * (1.0 - fx) + at(x0 + 1, y0 + 1) * fx;
            top * (1.0 - fy) + bottom * fy
        }
    }
}

/// Sum of the squared history error over frames `SKIP..` and pixels, over every
/// picture.
fn history_error(pictures: &[Stripes], tile: &[u32], velocity: Vec2, sampler: Sampler, how: Fetch) -> f64 {
    let mut total = 0.0;
    let n = SIDE * SIDE;
    let (mut h, mut next) = (vec![0.0f64; n], vec![0.0f64; n]);
    for picture in pictures {
        for t in 0..FRAMES {
            let moved = velocity * t as f32;
            for (i, out) in next.iter_mut().enumerate() {
                let p = UVec2::new((i % SIDE) as u32, (i / SIDE) as u32);
                // The picture point under screen position x is x - moved.
                let origin = p.as_vec2() - moved;
                let mut reference = 0.0;
                for j in 0..REFERENCE_GRID * REFERENCE_GRID {
                    let u = Vec2::new(
                        (j % REFERENCE_GRID) as f32 + 0.5,
                        (j / REFERENCE_GRID) as f32 + 0.5,
                    ) / REFERENCE_GRID as f32;
                    reference += picture.eval(origin + u);
                }
                reference /= (REFERENCE_GRID * REFERENCE_GRID) as f64;
                let e = picture.eval(origin + jitter(sampler, tile, p, t, moved)) - reference;
                *out = if t == 0 {
                    e
                } else {
                    // The pixel centre was at p + 0.5 - velocity in the previous frame.
                    let previous = fetch(&h, how, p.as_vec2() + Vec2::splat(0.5) - velocity);
                    ALPHA * e + (1.0 - ALPHA) * previous
                };
            }
            std::mem::swap(&mut h, &mut next);
            if t >= SKIP {
                total += h.iter().map(|v| v * v).sum::<f64>();
            }
        }
    }
    total
}

fn main() {
    let tile = sampler_core::defaults::tile_64();
    let tile = tile.values();
    // Held-out pictures: stripes of 5-16 px period in every direction.
    let pictures: Vec<Stripes> = (0..8u32)
        .map(|i| {
            let a = hash_u32(i ^ 0x1234_5678);
            let b = hash_u32(a);
            let angle = a as f32 * Q * core::f32::consts::TAU;
            let frequency = 4.0 + 8.0 * (b as f32 * Q);
            let k = (Vec2::new(angle.cos(), angle.sin()) * frequency).round();
            Stripes {
                k,
                phase: hash_u32(b) as f32 * Q,
            }
        })
        .collect();
    println!(
        "EMA (alpha {ALPHA}) of each frame's error over frames {SKIP}..{FRAMES}, 64x64 torus, white = 1"
    );
    println!("| motion, px/frame | history fetch | screen | follow | compensated |");
    println!("|---|---|---|---|---|");
    for velocity in [
        Vec2::ZERO,
        Vec2::new(0.5, 0.0),
        Vec2::new(0.25, 0.1),
        Vec2::new(0.37, -0.61),
        Vec2::new(2.0, 0.0),
        Vec2::new(2.3, 0.7),
    ] {
        for how in [Fetch::Nearest, Fetch::Bilinear] {
            let white = history_error(&pictures, tile, velocity, Sampler::White, how);
            let row: Vec<String> = [Sampler::Screen, Sampler::Follow, Sampler::Compensated]
                .iter()
                .map(|&s| {
                    format!(
                        "{:.3}",
                        (history_error(&pictures, tile, velocity, s, how) / white).sqrt()
                    )
                })
                .collect();
            let name = if how == Fetch::Nearest {
                "nearest"
            } else {
                "bilinear"
            };
            println!(
                "| ({}, {}) | {name} | {} |",
                velocity.x,
                velocity.y,
                row.join(" | ")
            );
        }
    }
}
