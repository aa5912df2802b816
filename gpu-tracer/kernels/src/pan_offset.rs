//! ZSobol's screen offset that follows a frame moving as a whole (the *pan
//! offset*).
//!
//! In a frame that follows as a whole ([`crate::motion::frame_follows`]:
//! a camera pan) every seed moves with its surface, but the a-priori
//! sampler's points are read at the pixel, so a surface point crossing the
//! screen reads a different pixel's sequence every frame and a history that
//! follows it sees white noise in time. The pan offset moves where ZSobol is
//! read instead: pixel `p` reads ZSobol's point of `p + offset`, where
//! `offset` accumulates, over the frames that follow as a whole, the mean
//! backward motion of the frame's rigid pixels ([`crate::motion::moves_rigidly`]).
//! A surface point then keeps reading one ZSobol pixel's sequence while the
//! picture slides, and the frame stays a translated ZSobol frame: a single
//! offset for the whole frame has no seams (QUALITY.md, "ZSobol follows a
//! pan"). Frames that do not follow leave the offset where it is.
//!
//! # The frame-motion buffer
//! One `[u32]` of [`FRAME_MOTION_WORDS`] words, shared by the rigid-count
//! and motion passes ([`crate::entry::rigid_count_cs`],
//! [`crate::entry::motion_cs`]) and mirrored by the CPU renderer:
//!
//! | word | contents | lifetime |
//! |---|---|---|
//! | [`FRAME_RIGID`] | pixels that move rigidly | cleared every frame |
//! | [`FRAME_SAMPLED`] | of those, the pixels on the [`SUM_GRID`] | cleared every frame |
//! | [`FRAME_SUM_X`], [`FRAME_SUM_Y`] | their backward motion summed, [`OFFSET_UNITS`] per pixel ([`fixed_motion`]; `i32` bits, wrapping) | cleared every frame |
//! | [`FRAME_OFFSET_X`], [`FRAME_OFFSET_Y`] | the accumulated offset, [`OFFSET_UNITS`] per pixel (`i32` bits) | from the sequence's start |
//!
//! Integer sums do not depend on the order of the atomic additions, so the
//! GPU's words equal the CPU's bit for bit.

use crate::abi::GBufferGpu;
use crate::motion::{frame_follows, moves_rigidly};

/// Word of the pixels that move rigidly ([`moves_rigidly`]).
pub const FRAME_RIGID: usize = 0;
/// Word of the rigid pixels on the [`SUM_GRID`], whose motion is summed.
pub const FRAME_SAMPLED: usize = 1;
/// Word of the summed x motion of the sampled pixels, [`OFFSET_UNITS`] per pixel.
pub const FRAME_SUM_X: usize = 2;
/// Word of the summed y motion of the sampled pixels, [`OFFSET_UNITS`] per pixel.
pub const FRAME_SUM_Y: usize = 3;
/// Words `0..FRAME_CLEARED_WORDS` are cleared before every frame's count.
pub const FRAME_CLEARED_WORDS: usize = 4;
/// Word of the accumulated x offset, [`OFFSET_UNITS`] per pixel.
pub const FRAME_OFFSET_X: usize = 4;
/// Word of the accumulated y offset, [`OFFSET_UNITS`] per pixel.
pub const FRAME_OFFSET_Y: usize = 5;
/// Length of the frame-motion buffer in `u32` words.
pub const FRAME_MOTION_WORDS: usize = 6;

/// Fraction bits of the fixed-point sums and offset: [`OFFSET_UNITS`] `= 2^OFFSET_BITS`.
pub const OFFSET_BITS: u32 = 4;

/// Fixed-point units per pixel of the sums and the offset: 1/16 px. The
/// offset accumulates a rounded mean every frame; at 1/16 px its drift from
/// the picture stays under a pixel for 32 frames even if every mean rounds
/// the same way, and a pixel's error is what the rounding to whole pixels
/// ([`offset_pixels`]) allows anyway.
pub const OFFSET_UNITS: f32 = (1u32 << OFFSET_BITS) as f32;

/// Only pixels whose `x` and `y` are multiples of `SUM_GRID` add their
/// motion to the sums (every rigid pixel counts in [`FRAME_RIGID`]): one in
/// 16 is plenty for a mean, and keeps the sums far from overflowing
/// ([`MOTION_CLAMP`]).
pub const SUM_GRID: u32 = 4;
const _: () = assert!(SUM_GRID.is_power_of_two());

/// Largest motion, in pixels per frame on either axis, a sampled pixel adds
/// to the sums: larger ones are clamped. With [`OFFSET_UNITS`] and
/// [`SUM_GRID`] the sums stay exact (inside `i32`) for frames of up to
/// `2^31 / (64 * 16) * 16 = 2^25` pixels (33.5 Mpx, beyond 8K UHD).
pub const MOTION_CLAMP: f32 = 64.0;

/// `m` pixels per frame as a fixed-point count of [`OFFSET_UNITS`],
/// rounded to nearest (halves up), clamped to `+-MOTION_CLAMP`; `i32` bits.
/// A NaN motion gives 0 (never reached: such pixels are not rigid).
#[inline]
pub fn fixed_motion(m: f32) -> u32 {
    let c = if m > MOTION_CLAMP {
        MOTION_CLAMP
    } else if m < -MOTION_CLAMP {
        -MOTION_CLAMP
    } else if !m.is_nan() {
        m
    } else {
        0.0
    };
    libm::floorf(c * OFFSET_UNITS + 0.5) as i32 as u32
}

/// Whether pixel `(x, y)` adds its motion to the sums: on the [`SUM_GRID`].
#[inline]
pub fn on_sum_grid(x: u32, y: u32) -> bool {
    // SUM_GRID is a power of two.
    (x | y) & (SUM_GRID - 1) == 0
}

/// What pixel `(x, y)` adds to the cleared words of the frame-motion buffer
/// (module docs): `[rigid, sampled, sum x, sum y]`, all 0 unless it moves
/// rigidly ([`moves_rigidly`] on `gbuffer`, `width x height`). The GPU adds
/// them atomically, the CPU in a loop.
#[inline]
pub fn pixel_contribution(gbuffer: &[GBufferGpu], x: u32, y: u32, width: u32, height: u32) -> [u32; 4] {
    if !moves_rigidly(gbuffer, x, y, width, height) {
        return [0; 4];
    }
    if !on_sum_grid(x, y) {
        return [1, 0, 0, 0];
    }
    let g = gbuffer[y.wrapping_mul(width).wrapping_add(x) as usize];
    [1, 1, fixed_motion(g.motion.x), fixed_motion(g.motion.y)]
}

/// The offset after a frame whose cleared words are `frame`
/// (`frame[..FRAME_CLEARED_WORDS]` summed over its `pixels` pixels) when the
/// offset was `offset` (`[x, y]`, [`OFFSET_UNITS`] per pixel, `i32` bits):
/// `offset` plus the sampled pixels' mean motion (each sum divided by the
/// sampled count, rounded toward zero) when the frame follows as a whole
/// ([`frame_follows`] of the rigid count with `share`) and some rigid pixel
/// was sampled; `offset` otherwise.
#[inline]
pub fn advance_offset(offset: [u32; 2], frame: [u32; 4], pixels: u32, share: f32) -> [u32; 2] {
    let sampled = frame[FRAME_SAMPLED] as i32;
    if sampled <= 0 || !frame_follows(frame[FRAME_RIGID], pixels, share) {
        return offset;
    }
    let dx = (frame[FRAME_SUM_X] as i32).wrapping_div(sampled);
    let dy = (frame[FRAME_SUM_Y] as i32).wrapping_div(sampled);
    [
        (offset[0] as i32).wrapping_add(dx) as u32,
        (offset[1] as i32).wrapping_add(dy) as u32,
    ]
}

/// A fixed-point offset coordinate (`i32` bits, [`OFFSET_UNITS`] per pixel)
/// rounded to whole pixels (halves up), as `u32` bits of an `i32`: add it
/// to a pixel coordinate with `wrapping_add`.
#[inline]
pub fn offset_pixels(fixed: u32) -> u32 {
    ((fixed as i32).wrapping_add(1 << (OFFSET_BITS - 1)) >> OFFSET_BITS) as u32
}
