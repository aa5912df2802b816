//! Why ZSobol's frames lose their blue noise when its points follow the picture
//! (`--mode hold --sampler zsobol`), without a renderer: a 128x128 frame whose
//! pixels read the jitter pair of ZSobol's frame `t` at their *home* (the seed the
//! seed reprojection moves, [`reproject_frame`]), under synthetic backward motion
//! fields, and the blurred error of one jittered sample a pixel against a set of
//! Heaviside steps shared by every pixel (the a-priori samplers' test: an error
//! pattern that is blue where the points are). It prints, over frames 16..64,
//! the blurred (Gaussian sigma 1) RMS error against white noise's (white = 1),
//! the share of pixels recycled a frame, and the share of neighbours whose homes
//! are still neighbours (`home(x + 1, y) = home(x, y) + (1, 0)`, and the same
//! vertically: what ZSobol's Morton order needs), for:
//!
//! - **screen**: home = pixel (the point stays on the screen);
//! - **follow**: homes moved by [`reproject_frame`] (what the hold mode does);
//! - **repair**: the same, and each recycled pixel's home replaced by its left
//!   (else upper) neighbour's home plus the one-pixel step, when no pixel holds
//!   that home yet (homes stay unique; a candidate rule, not shipped).
//!
//! Motion fields (backward, pixels a frame, about 2 px/frame at the frame's edge
//! unless named): a uniform pan, a pan with parallax (speed 0.6-1.4x across rows,
//! as a floor receding), a pan with a stretch (speed 0.9-1.1x across columns), a
//! rotation about the centre and a zoom.
//!
//! ```text
//! cargo run --release -p sampler-core --example home_order
//! ```

use glam::{UVec2, Vec2};
use sampler_core::reprojection::claim;
use sampler_core::sequences::seed::hash_u32;
use sampler_core::sequences::spatiotemporal::{home_of_pixel, home_texel};
use sampler_core::sequences::zsobol::zsobol_frame_pair_u32;
use sampler_core::{reproject_frame, FrameLayout, CLAIM_NONE};

const SIDE: u32 = 128;
const FRAMES: u32 = 64;
const SKIP: u32 = 16;
const STEPS: u32 = 24;
/// Pixels this far from the frame's edge are left out of the error (the blur's reach).
const MARGIN: u32 = 4;
const Q: f32 = 1.0 / 4_294_967_296.0;

#[derive(Clone, Copy, PartialEq)]
enum Homes {
    White,
    Screen,
    Follow,
    Repair,
}

#[derive(Clone, Copy)]
enum Motion {
    Pan(f32),
    Parallax(f32),
    Stretch(f32),
    Rotate(f32),
    Zoom(f32),
}

impl Motion {
    /// Backward motion of pixel `p`'s centre (where it was in the previous frame, minus where it is).
    fn at(self, p: UVec2) -> Vec2 {
        let c = Vec2::splat(SIDE as f32 * 0.5);
        let x = p.as_vec2() + Vec2::splat(0.5);
        match self {
            Motion::Pan(v) => Vec2::new(v, 0.0),
            Motion::Parallax(v) => Vec2::new(v * (0.6 + 0.8 * x.y / SIDE as f32), 0.0),
            Motion::Stretch(v) => Vec2::new(v * (1.0 + 0.2 * (x.x - c.x) / SIDE as f32), 0.0),
            Motion::Rotate(edge_speed) => {
                let a = edge_speed / (SIDE as f32 * 0.5);
                let d = x - c;
                let (s, co) = a.sin_cos();
                Vec2::new(co * d.x - s * d.y, s * d.x + co * d.y) - d
            }
            Motion::Zoom(edge_speed) => (x - c) * (edge_speed / (SIDE as f32 * 0.5)),
        }
    }

    fn name(self) -> String {
        match self {
            Motion::Pan(v) => format!("pan {v}"),
            Motion::Parallax(v) => format!("pan {v}, parallax"),
            Motion::Stretch(v) => format!("pan {v}, stretch"),
            Motion::Rotate(v) => format!("rotation, edge {v}"),
            Motion::Zoom(v) => format!("zoom, edge {v}"),
        }
    }
}

/// A Heaviside step in the pixel box: 1 where `n . (u - 0.5) < offset`.
struct Step {
    n: Vec2,
    offset: f32,
    area: f64,
}

fn steps() -> Vec<Step> {
    (0..STEPS)
        .map(|i| {
            let a = hash_u32(i ^ 0x9e37_79b9);
            let b = hash_u32(a);
            let angle = a as f32 * Q * core::f32::consts::TAU;
            let n = Vec2::new(angle.cos(), angle.sin());
            let offset = (b as f32 * Q - 0.5) * 0.8;
            // Area by a fine grid (the reference of the pixel's integral).
            let g = 256;
            let inside = (0..g * g)
                .filter(|j| {
                    let u = Vec2::new((j % g) as f32 + 0.5, (j / g) as f32 + 0.5) / g as f32;
                    n.dot(u - Vec2::splat(0.5)) < offset
                })
                .count();
            Step {
                n,
                offset,
                area: inside as f64 / (g * g) as f64,
            }
        })
        .collect()
}

/// Toroidal-free Gaussian blur (sigma 1, radius 3, edges clamped) of a `SIDE`-square field.
fn blur(field: &[f64]) -> Vec<f64> {
    let w: Vec<f64> = (-3i32..=3).map(|d| (-(d * d) as f64 / 2.0).exp()).collect();
    let norm: f64 = w.iter().sum();
    let n = SIDE as i32;
    let pass = |src: &[f64], horizontal: bool| -> Vec<f64> {
        let mut out = vec![0.0; src.len()];
        for y in 0..n {
            for x in 0..n {
                let mut s = 0.0;
                for (k, wk) in w.iter().enumerate() {
                    let d = k as i32 - 3;
                    let (sx, sy) = if horizontal {
                        ((x + d).clamp(0, n - 1), y)
                    } else {
                        (x, (y + d).clamp(0, n - 1))
                    };
                    s += wk * src[(sy * n + sx) as usize];
                }
                out[(y * n + x) as usize] = s / norm;
            }
        }
        out
    };
    pass(&pass(field, true), false)
}

struct Figures {
    /// Sum over measured frames, steps and pixels of the blurred squared error.
    blurred: f64,
    recycled: f64,
    ordered: f64,
}

fn run(motion: Motion, homes_rule: Homes, steps: &[Step]) -> Figures {
    let layout = FrameLayout::new(SIDE, SIDE, 4, 16).expect("layout");
    let n = layout.seed_count();
    assert_eq!(n, (SIDE * SIDE) as usize, "no padding at this size");
    let mut homes: Vec<u32> = (0..n as u32).map(|i| home_of_pixel(i % SIDE, i / SIDE)).collect();
    let (mut claims, mut next) = (vec![0u32; n], vec![0u32; n]);
    let motion_field: Vec<[f32; 2]> = (0..n as u32)
        .map(|i| motion.at(UVec2::new(i % SIDE, i / SIDE)).to_array())
        .collect();
    let mut figures = Figures {
        blurred: 0.0,
        recycled: 0.0,
        ordered: 0.0,
    };
    for t in 0..FRAMES {
        if t > 0 && matches!(homes_rule, Homes::Follow | Homes::Repair) {
            let stats =
                reproject_frame(&layout, &motion_field, &homes, &mut claims, &mut next).expect("reproject");
            if homes_rule == Homes::Repair {
                repair(&layout, t, &motion_field, &claims, &mut next);
            }
            std::mem::swap(&mut homes, &mut next);
            if t >= SKIP {
                figures.recycled += f64::from(stats.recycled) / n as f64;
            }
        }
        if t < SKIP {
            continue;
        }
        let points: Vec<Vec2> = (0..n as u32)
            .map(|i| match homes_rule {
                Homes::White => {
                    let a = hash_u32(i ^ hash_u32(t ^ 0x5bd1_e995));
                    Vec2::new(a as f32 * Q, hash_u32(a) as f32 * Q)
                }
                Homes::Screen => point(UVec2::new(i % SIDE, i / SIDE), t),
                Homes::Follow | Homes::Repair => point(home_texel(homes[i as usize]), t),
            })
            .collect();
        for step in steps {
            let error: Vec<f64> = points
                .iter()
                .map(|&u| f64::from(u8::from(step.n.dot(u - Vec2::splat(0.5)) < step.offset)) - step.area)
                .collect();
            let b = blur(&error);
            for y in MARGIN..SIDE - MARGIN {
                for x in MARGIN..SIDE - MARGIN {
                    let v = b[(y * SIDE + x) as usize];
                    figures.blurred += v * v;
                }
            }
        }
        let mut kept = 0u32;
        for y in 0..SIDE {
            for x in 0..SIDE - 1 {
                let i = (y * SIDE + x) as usize;
                kept += u32::from(homes[i + 1] == homes[i].wrapping_add(1));
                let j = (x * SIDE + y) as usize;
                kept += u32::from(homes[j + SIDE as usize] == homes[j].wrapping_add(1 << 16));
            }
        }
        figures.ordered += f64::from(kept) / f64::from(2 * SIDE * (SIDE - 1));
    }
    let frames = f64::from(FRAMES - SKIP);
    figures.recycled /= frames;
    figures.ordered /= frames;
    figures
}

/// The jitter pair of ZSobol's frame `t` at home `home`, one sample a pixel.
fn point(home: UVec2, t: u32) -> Vec2 {
    let p = zsobol_frame_pair_u32(home, 0, 0, 0, t);
    Vec2::new(p[0] as f32 * Q, p[1] as f32 * Q)
}

/// The candidate rule: each pixel that took a recycled home takes its left (else
/// upper) neighbour's home plus the one-pixel step instead, when that neighbour kept
/// its own and no pixel holds the new home yet (homes stay unique).
fn repair(layout: &FrameLayout, t: u32, motion: &[[f32; 2]], claims: &[u32], homes: &mut [u32]) {
    let params = layout.params(t);
    let n = homes.len();
    let recycled: Vec<bool> = (0..n as u32)
        .map(|i| {
            let (source, key) = claim(&params, i, motion[i as usize]);
            source == CLAIM_NONE || claims[source as usize] != key
        })
        .collect();
    let mut used = std::collections::HashSet::with_capacity(n);
    for &h in homes.iter() {
        used.insert(h);
    }
    for i in 0..n {
        if !recycled[i] {
            continue;
        }
        let (x, y) = (i as u32 % SIDE, i as u32 / SIDE);
        let candidate = if x > 0 && !recycled[i - 1] {
            Some(homes[i - 1].wrapping_add(1))
        } else if y > 0 && !recycled[i - SIDE as usize] {
            Some(homes[i - SIDE as usize].wrapping_add(1 << 16))
        } else {
            None
        };
        if let Some(h) = candidate {
            if !used.contains(&h) {
                used.remove(&homes[i]);
                used.insert(h);
                homes[i] = h;
            }
        }
    }
}

fn main() {
    let steps = steps();
    println!(
        "ZSobol's jitter pair at the homes, {SIDE}x{SIDE}, frames {SKIP}..{FRAMES}, {STEPS} Heaviside steps, \
         blurred sigma 1, white = 1"
    );
    println!("| motion (px/frame) | screen | follow | follow, recycled % / neighbours kept % | repair | repair: neighbours kept % |");
    println!("|---|---|---|---|---|---|");
    // Neither white noise nor points on the screen depend on the motion: measured once.
    let white = run(Motion::Pan(0.0), Homes::White, &steps).blurred;
    let screen = run(Motion::Pan(0.0), Homes::Screen, &steps).blurred;
    for motion in [
        Motion::Pan(2.0),
        Motion::Pan(0.5),
        Motion::Parallax(2.0),
        Motion::Parallax(0.5),
        Motion::Stretch(2.0),
        Motion::Stretch(0.5),
        Motion::Rotate(2.0),
        Motion::Rotate(0.5),
        Motion::Zoom(2.0),
    ] {
        let follow = run(motion, Homes::Follow, &steps);
        let repaired = run(motion, Homes::Repair, &steps);
        println!(
            "| {} | {:.3} | {:.3} | {:.1} / {:.1} | {:.3} | {:.1} |",
            motion.name(),
            (screen / white).sqrt(),
            (follow.blurred / white).sqrt(),
            100.0 * follow.recycled,
            100.0 * follow.ordered,
            (repaired.blurred / white).sqrt(),
            100.0 * repaired.ordered,
        );
    }
}
