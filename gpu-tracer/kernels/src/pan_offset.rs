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
//! One `[u32]` of [`FRAME_MOTION_WORDS`] words, shared by the rigid-count,
//! pan-offset and motion passes ([`crate::entry::rigid_count_cs`],
//! [`crate::entry::pan_offset_cs`], [`crate::entry::motion_cs`]) and
//! mirrored by the CPU renderer:
//!
//! | word | contents | lifetime |
//! |---|---|---|
//! | [`FRAME_RIGID`] | pixels that move rigidly | cleared every frame |
//! | [`region_word`]`(r, k)`, `r < REGIONS`, `k < 3` | of those, the pixels on the [`SUM_GRID`] in screen region `r` ([`sum_region`]): their count (`k` = [`REGION_SAMPLED`]) and backward motion summed (`k` = [`REGION_SUM_X`], [`REGION_SUM_Y`]), [`OFFSET_UNITS`] per pixel ([`fixed_motion`]; `i32` bits, wrapping) | cleared every frame |
//! | [`FRAME_OFFSET_X`], [`FRAME_OFFSET_Y`] | the accumulated offset, [`OFFSET_UNITS`] per pixel (`i32` bits) | from the sequence's start |
//!
//! # Which frames move the offset
//! A frame moves the offset when it follows as a whole *and* its rigid
//! pixels move alike: the mean motion of each of the [`REGIONS`] screen
//! regions differs from the frame's by at most [`PAN_SPREAD_PERCENT`] of
//! the frame's speed on average ([`motion_spread`]). A camera that slides
//! moves every region alike, up to its parallax (at most 11.4% in any
//! frame of the Cornell box's pans); an orbit turns the picture, and its
//! walls move at different speeds in different parts of the screen (17% and
//! more in every frame of the 256x256 orbits),
//! where one offset would follow none of them and costs each raw frame
//! without a gain behind the history (QUALITY.md, "The pan offset leaves
//! orbits alone").
//!
//! Integer sums do not depend on the order of the atomic additions, so the
//! GPU's words equal the CPU's bit for bit.

use crate::abi::GBufferGpu;
use crate::motion::{frame_follows, moves_rigidly};

/// Word of the pixels that move rigidly ([`moves_rigidly`]).
pub const FRAME_RIGID: usize = 0;
/// Screen regions per axis whose sampled motion is summed apart
/// ([`sum_region`]): `REGIONS_PER_AXIS^2` regions.
pub const REGIONS_PER_AXIS: u32 = 4;
/// Screen regions whose sampled motion is summed apart (4 x 4).
pub const REGIONS: usize = (REGIONS_PER_AXIS * REGIONS_PER_AXIS) as usize;
/// Words of one region: sampled count, sum x, sum y.
pub const REGION_WORDS: usize = 3;
/// A region's word of the rigid pixels on the [`SUM_GRID`] ([`region_word`]).
pub const REGION_SAMPLED: usize = 0;
/// A region's word of the sampled pixels' summed x motion, [`OFFSET_UNITS`] per pixel.
pub const REGION_SUM_X: usize = 1;
/// A region's word of the sampled pixels' summed y motion, [`OFFSET_UNITS`] per pixel.
pub const REGION_SUM_Y: usize = 2;
/// Words `0..FRAME_CLEARED_WORDS` are cleared before every frame's count.
pub const FRAME_CLEARED_WORDS: usize = 1 + REGIONS * REGION_WORDS;
/// Word of the accumulated x offset, [`OFFSET_UNITS`] per pixel.
pub const FRAME_OFFSET_X: usize = FRAME_CLEARED_WORDS;
/// Word of the accumulated y offset, [`OFFSET_UNITS`] per pixel.
pub const FRAME_OFFSET_Y: usize = FRAME_CLEARED_WORDS + 1;
/// Length of the frame-motion buffer in `u32` words.
pub const FRAME_MOTION_WORDS: usize = FRAME_CLEARED_WORDS + 2;

/// Largest mean deviation of the regions' mean motions from the frame's,
/// in percent of the frame's speed (both in the L1 norm, `|x| + |y|`),
/// for which the offset moves ([`motion_spread`], module docs). Chosen
/// between the Cornell box's pans (at most 11.4% in any frame, 0.5-5
/// px/frame, 128x128 and 256x256) and the one orbit whose frames follow as
/// a whole (256x256, 2 px/frame: at least 16.9%).
pub const PAN_SPREAD_PERCENT: u32 = 14;

/// Index in the frame-motion buffer of word `k` ([`REGION_SAMPLED`],
/// [`REGION_SUM_X`], [`REGION_SUM_Y`]) of region `r` (`< REGIONS`).
#[inline]
pub const fn region_word(r: usize, k: usize) -> usize {
    1 + r * REGION_WORDS + k
}

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

/// The screen region (`0..REGIONS`, row-major, [`REGIONS_PER_AXIS`] per
/// axis) of pixel `(x, y)` in a `width x height` frame: region
/// `(x * 4 / width, y * 4 / height)`.
#[inline]
pub fn sum_region(x: u32, y: u32, width: u32, height: u32) -> usize {
    let rx = x.wrapping_mul(REGIONS_PER_AXIS) / width.max(1);
    let ry = y.wrapping_mul(REGIONS_PER_AXIS) / height.max(1);
    ry.wrapping_mul(REGIONS_PER_AXIS).wrapping_add(rx) as usize
}

/// What pixel `(x, y)` adds to the frame-motion buffer (module docs):
/// `[rigid, sampled, motion x, motion y]`, all 0 unless it moves rigidly
/// ([`moves_rigidly`] on `gbuffer`, `width x height`); `rigid` goes to
/// [`FRAME_RIGID`], the other three to the words of its region
/// ([`sum_region`], [`region_word`]). The GPU adds them atomically, the CPU
/// in a loop.
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

/// Fraction bits the spread of [`motion_spread`] has beyond
/// [`OFFSET_UNITS`]: it is in `1 / (OFFSET_UNITS * 2^SPREAD_BITS)` px
/// (1/256 px), fine enough for a fraction of a 1/16 px mean.
pub const SPREAD_BITS: u32 = 4;

/// The mean motion of a frame's sampled rigid pixels and how much its
/// regions' means spread around it, from the frame-motion buffer's words
/// `frame` (at least [`FRAME_CLEARED_WORDS`]): `[sampled, mean x, mean y,
/// spread]`. The means are in [`OFFSET_UNITS`] per pixel (`i32` bits, each
/// sum divided by its count, rounded toward zero); `spread` is the mean,
/// over the sampled pixels, of their region's mean's L1 distance `d_r` from
/// the frame's mean: `floor(2^SPREAD_BITS * sum_r n_r d_r / n)`, in
/// [`SPREAD_BITS`] finer units. All integer (the quotient and remainder of
/// each term kept apart, so nothing overflows for frames of up to 2^25
/// pixels, [`MOTION_CLAMP`]): the GPU's figures equal the CPU's.
#[inline]
pub fn motion_spread(frame: &[u32]) -> [u32; 4] {
    let (mut n, mut sx, mut sy) = (0u32, 0u32, 0u32);
    let mut r = 0;
    while r < REGIONS {
        n = n.wrapping_add(frame[region_word(r, REGION_SAMPLED)]);
        sx = sx.wrapping_add(frame[region_word(r, REGION_SUM_X)]);
        sy = sy.wrapping_add(frame[region_word(r, REGION_SUM_Y)]);
        r += 1;
    }
    if n == 0 {
        return [0; 4];
    }
    let dx = (sx as i32).wrapping_div(n as i32);
    let dy = (sy as i32).wrapping_div(n as i32);
    // sum_r n_r d_r = quotient * n + remainder, the remainder kept below n.
    let (mut quotient, mut remainder) = (0u32, 0u32);
    let mut r = 0;
    while r < REGIONS {
        let nr = frame[region_word(r, REGION_SAMPLED)];
        if nr > 0 {
            let mx = (frame[region_word(r, REGION_SUM_X)] as i32).wrapping_div(nr as i32);
            let my = (frame[region_word(r, REGION_SUM_Y)] as i32).wrapping_div(nr as i32);
            let d = mx
                .wrapping_sub(dx)
                .unsigned_abs()
                .wrapping_add(my.wrapping_sub(dy).unsigned_abs());
            // n_r is at most the region's grid pixels (2^17 and a row and a
            // column for 2^25 pixels), d <= 2 * 2 * 1024 = 2^12: no overflow.
            let term = nr.wrapping_mul(d);
            quotient = quotient.wrapping_add(term / n);
            remainder = remainder.wrapping_add(term % n);
            quotient = quotient.wrapping_add(remainder / n);
            remainder %= n;
        }
        r += 1;
    }
    let spread = (quotient << SPREAD_BITS).wrapping_add((remainder << SPREAD_BITS) / n);
    [n, dx as u32, dy as u32, spread]
}

/// The L1 length `|x| + |y|` of the mean motion of [`motion_spread`]'s
/// figures `spread`, in the spread's units (1/256 px): what the spread is
/// measured against.
#[inline]
pub fn spread_speed(spread: [u32; 4]) -> u32 {
    let speed = (spread[1] as i32)
        .unsigned_abs()
        .wrapping_add((spread[2] as i32).unsigned_abs());
    speed << SPREAD_BITS
}

/// Whether a frame with [`motion_spread`] figures `spread` moves alike
/// enough for the offset to follow it: some pixel sampled, and the spread
/// at most [`PAN_SPREAD_PERCENT`] of the mean's L1 length ([`spread_speed`]).
#[inline]
pub fn moves_alike(spread: [u32; 4]) -> bool {
    spread[0] > 0 && spread[3].wrapping_mul(100) <= PAN_SPREAD_PERCENT.wrapping_mul(spread_speed(spread))
}

/// The offset after a frame whose frame-motion words are `frame` (at least
/// [`FRAME_CLEARED_WORDS`]: the rigid count and the regions' sums over its
/// `pixels` pixels) when the offset was `offset` (`[x, y]`,
/// [`OFFSET_UNITS`] per pixel, `i32` bits): `offset` plus the sampled
/// pixels' mean motion ([`motion_spread`]) when the frame follows as a
/// whole ([`frame_follows`] of the rigid count with `share`) and its
/// rigid pixels move alike ([`moves_alike`]); `offset` otherwise.
#[inline]
pub fn advance_offset(offset: [u32; 2], frame: &[u32], pixels: u32, share: f32) -> [u32; 2] {
    if !frame_follows(frame[FRAME_RIGID], pixels, share) {
        return offset;
    }
    let spread = motion_spread(frame);
    if !moves_alike(spread) {
        return offset;
    }
    [
        (offset[0] as i32).wrapping_add(spread[1] as i32) as u32,
        (offset[1] as i32).wrapping_add(spread[2] as i32) as u32,
    ]
}

/// A fixed-point offset coordinate (`i32` bits, [`OFFSET_UNITS`] per pixel)
/// rounded to whole pixels (halves up), as `u32` bits of an `i32`: add it
/// to a pixel coordinate with `wrapping_add`.
#[inline]
pub fn offset_pixels(fixed: u32) -> u32 {
    ((fixed as i32).wrapping_add(1 << (OFFSET_BITS - 1)) >> OFFSET_BITS) as u32
}
