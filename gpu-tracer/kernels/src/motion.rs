//! Motion vectors for the seed reprojection: the G-buffer's backward motion
//! with disoccluded pixels marked [`DISOCCLUDED`], per pixel, in the form
//! `sampler_core::reproject_frame` and the GPU reprojection passes take.
//! The CPU renderer (`gpu_tracer::motion`) and the motion entry point
//! ([`crate::entry::motion_cs`]) both call [`reprojection_motion_pixel`] and
//! [`seed_motion`], and count the pixels that move rigidly
//! ([`moves_rigidly`], [`crate::entry::rigid_count_cs`]) for
//! [`frame_follows`].

use crate::abi::{GBufferGpu, GBUFFER_HIT, GBUFFER_NO_HIT, GBUFFER_PREV_IN_FRONT};
use glam::{UVec2, Vec2};

/// Largest relative difference between a point's depth in the previous
/// camera and the previous frame's G-buffer depth at its previous pixel for
/// the point to count as visible there (the usual TAA depth test). 5%:
/// generous for the depth slopes of one pixel at grazing angles, far below
/// the jump at an occluding edge of a room-scale scene.
pub const DISOCCLUSION_DEPTH_TOLERANCE: f32 = 0.05;

/// The motion written for a pixel whose point was not visible in the
/// previous frame: `-f32::MAX` on both axes, a previous position far
/// outside any frame, which the reprojection treats as "no source" exactly
/// as it treats NaN. Not NaN itself: naga (wgpu's SPIR-V front end) rejects
/// NaN constants in a shader module.
pub const DISOCCLUDED: Vec2 = Vec2::splat(-f32::MAX);

/// What the next frame needs of this frame's G-buffer texel to test
/// visibility, 8 bytes: `x` the object id ([`GBUFFER_NO_HIT`] without a
/// hit), `y` the bits of the linear depth (`f32`, world units; 0 without a
/// hit).
#[inline]
pub fn visibility(g: &GBufferGpu) -> UVec2 {
    if g.ids.w & GBUFFER_HIT == 0 {
        UVec2::new(GBUFFER_NO_HIT, 0)
    } else {
        UVec2::new(g.ids.x, g.normal_depth.w.to_bits())
    }
}

/// Backward motion of pixel `(x, y)` of a `width x height` frame with
/// G-buffer texel `g`, in pixels (raster `y` down), or [`DISOCCLUDED`] where its point
/// was not visible in the previous frame: behind the previous camera,
/// outside the previous frame, hidden by something nearer (depth test
/// against `previous`, the previous frame's [`visibility`] buffer,
/// `width * height` row-major, with [`DISOCCLUSION_DEPTH_TOLERANCE`]), or on
/// another object than the previous pixel showed. Background pixels keep
/// their (camera-rotation) motion.
#[inline]
pub fn reprojection_motion_pixel(
    g: &GBufferGpu,
    x: u32,
    y: u32,
    width: u32,
    height: u32,
    previous: &[UVec2],
) -> Vec2 {
    let m = Vec2::new(g.motion.x, g.motion.y);
    if g.ids.w & GBUFFER_HIT == 0 {
        return m;
    }
    if g.ids.w & GBUFFER_PREV_IN_FRONT == 0 {
        return DISOCCLUDED;
    }
    let px = x as f32 + 0.5 + m.x;
    let py = y as f32 + 0.5 + m.y;
    // Comparisons are false for NaN (a G-buffer without a previous position).
    if !(px >= 0.0 && py >= 0.0 && px < width as f32 && py < height as f32) {
        return DISOCCLUDED;
    }
    let p = previous[(py as u32).wrapping_mul(width).wrapping_add(px as u32) as usize];
    let depth = f32::from_bits(p.y);
    let prev_depth = g.motion.z;
    if p.x == g.ids.x && libm::fabsf(depth - prev_depth) <= DISOCCLUSION_DEPTH_TOLERANCE * prev_depth {
        m
    } else {
        DISOCCLUDED
    }
}

/// Largest difference, in pixels per frame, between a pixel's G-buffer
/// motion and each of its four neighbours' for the pixel to move
/// *rigidly* ([`moves_rigidly`]), whatever its speed: the floor of the
/// tolerance, which grows with the speed above 2 px/frame
/// ([`RIGID_WITHIN_PER_SPEED`]). 0.05: a seam where neighbours' rounded
/// motions part (the seams that cost followed seeds their order, QUALITY.md
/// "Why followed points lose their blue noise") then crosses a pixel at
/// most once in 20 frames. A camera pan moves a wall facing it by exactly
/// the same amount everywhere; an orbit's perspective bends the field.
pub const RIGID_WITHIN: f32 = 0.05;

/// Tolerance of [`moves_rigidly`] per pixel per frame of the pixel's own
/// speed: neighbours move rigidly with a pixel moving at `v` px/frame when
/// their motions differ from its by at most `max(RIGID_WITHIN,
/// RIGID_WITHIN_PER_SPEED * v)` (0.05 px/frame up to 2 px/frame, 0.1 at 4).
/// A camera's motion scales every pixel's motion alike (a pan's motion is
/// its speed over the depth), so a tolerance that scales with the speed
/// classifies the same picture's motion the same at every speed: a pan
/// whose floor and walls recede counts as rigid at 4 px/frame as at 2,
/// where an absolute 0.05 counted the back wall alone and held every seed
/// (QUALITY.md, "Pans follow at every speed"). 0.025 keeps the rule
/// measured at 2 px/frame unchanged there.
pub const RIGID_WITHIN_PER_SPEED: f32 = 0.025;

/// Slowest G-buffer motion, in pixels per frame, that counts as moving
/// rigidly ([`moves_rigidly`]). Below a pixel a frame a followed seed jumps
/// a whole pixel where the drift crosses a rounding boundary and stays put
/// elsewhere, which costs the sorting pass's prediction more than holding
/// it (QUALITY.md, "Which default for reprojection").
pub const RIGID_MIN_SPEED: f32 = 1.0;

/// Whether pixel `(x, y)` of a `width x height` frame whose G-buffer is
/// `gbuffer` (`width * height`, row-major) moves rigidly: its surface moved
/// at least [`RIGID_MIN_SPEED`] pixels since the previous frame, and its
/// four neighbours are inside the frame, show a surface, and moved within
/// `max(RIGID_WITHIN, RIGID_WITHIN_PER_SPEED * speed)` pixels of it
/// ([`RIGID_WITHIN_PER_SPEED`]; G-buffer motion `motion.xy`, disoccluded or
/// not). Pixels without a hit, at the frame's border, or with a NaN
/// motion do not. [`seed_motion`]'s frame-wide rule counts these pixels.
#[inline]
pub fn moves_rigidly(gbuffer: &[GBufferGpu], x: u32, y: u32, width: u32, height: u32) -> bool {
    if x == 0 || y == 0 || x.wrapping_add(1) >= width || y.wrapping_add(1) >= height {
        return false;
    }
    // Plain functions, not closures: a closure that captures the slice
    // becomes a struct holding a pointer, which naga rejects.
    let g = texel_at(gbuffer, x, y, width);
    let m = Vec2::new(g.motion.x, g.motion.y);
    // False for a NaN motion.
    let fast = m.length_squared() >= RIGID_MIN_SPEED * RIGID_MIN_SPEED;
    if g.ids.w & GBUFFER_HIT == 0 || !fast {
        return false;
    }
    // Squared tolerance: the larger of the floor and the share of the speed.
    let within = (RIGID_WITHIN * RIGID_WITHIN)
        .max(RIGID_WITHIN_PER_SPEED * RIGID_WITHIN_PER_SPEED * m.length_squared());
    let (l, r, u, d) = (
        x.wrapping_sub(1),
        x.wrapping_add(1),
        y.wrapping_sub(1),
        y.wrapping_add(1),
    );
    moves_with(texel_at(gbuffer, l, y, width), m, within)
        && moves_with(texel_at(gbuffer, r, y, width), m, within)
        && moves_with(texel_at(gbuffer, x, u, width), m, within)
        && moves_with(texel_at(gbuffer, x, d, width), m, within)
}

/// The texel of pixel `(x, y)` of a row-major G-buffer `width` wide.
#[inline]
fn texel_at(gbuffer: &[GBufferGpu], x: u32, y: u32, width: u32) -> GBufferGpu {
    gbuffer[y.wrapping_mul(width).wrapping_add(x) as usize]
}

/// Whether texel `q` shows a surface whose motion is within
/// `sqrt(within_squared)` px/frame of `m` (false for NaN).
#[inline]
fn moves_with(q: GBufferGpu, m: Vec2, within_squared: f32) -> bool {
    let d = Vec2::new(q.motion.x, q.motion.y) - m;
    q.ids.w & GBUFFER_HIT != 0 && d.length_squared() <= within_squared
}

/// Whether every seed of a frame follows its surface whatever its speed:
/// when `rigid` pixels ([`moves_rigidly`]) make at least `share` of the
/// frame's `pixels`. `share` in `[0, 1]`; 0: never (the rule is off).
/// A camera pan moves most of the picture rigidly and there following
/// every seed measures better; an orbit's or a moving object's seams make
/// holding slow surfaces' seeds better (QUALITY.md, "Pans follow").
#[inline]
pub fn frame_follows(rigid: u32, pixels: u32, share: f32) -> bool {
    share > 0.0 && rigid as f32 >= share * pixels as f32
}

/// The motion the seed reprojection takes for a pixel with G-buffer texel
/// `g` and reprojection motion `motion` ([`reprojection_motion_pixel`]):
/// zero, so that the pixel keeps the seed it had, when its surface moved
/// less than `hold_below` pixels since the previous frame (the length of the
/// G-buffer's backward motion `g.motion.xy`, disoccluded or not; the
/// background's is the camera's rotation) and the frame does not follow as
/// a whole (`follows_all`, from [`frame_follows`]); `motion` otherwise.
///
/// `hold_below` is in pixels per frame, finite and `>= 0`; 0 gives `motion`
/// unchanged for every pixel (every seed follows its surface). A NaN
/// G-buffer motion (no previous position) never holds. Slow surfaces are
/// where a seed is better left at its pixel: the sorting pass's prediction
/// (this pixel's next value from its last) survives a sub-pixel drift, and
/// moving seeds by rounded whole pixels scrambles the ranks it set
/// (`QUALITY.md`, "Which default for reprojection").
#[inline]
pub fn seed_motion(g: &GBufferGpu, motion: Vec2, hold_below: f32, follows_all: bool) -> Vec2 {
    let raw = Vec2::new(g.motion.x, g.motion.y);
    if !follows_all && raw.length_squared() < hold_below * hold_below {
        Vec2::ZERO
    } else {
        motion
    }
}
