//! The toroidal offset walk of the dither tile.
//!
//! # Convention (shared by every pass, the GPU kernels and the bakers)
//!
//! The tile is square, `W = 2^k` texels on a side. In frame `t` the dither
//! value of screen pixel `p` is read at tile texel `(p + o_t) mod W`:
//!
//! ```text
//! D_t(p) = tile[(p + o_t) mod W]
//! ```
//!
//! so as `o_t` grows the pattern appears to slide towards smaller screen
//! coordinates. The offset is the aperiodic R2 walk
//!
//! ```text
//! o_t = (floor(W * frac(t * a1)), floor(W * frac(t * a2)))   each in 0..W
//! ```
//!
//! computed in 0.32 fixed point: `o_t = ((t * A1) mod 2^32 >> (32 - k), ...)`
//! with [`R2_A1_Q32`], [`R2_A2_Q32`], so CPU and GPU agree bit for bit.
//!
//! A fixed integer step `t * (floor(W a1), floor(W a2))` must not be used:
//! for W = 64 it is `t * (48, 36)`, which repeats every 16 frames.
//!
//! # Steps
//!
//! The frame-to-frame step `(o_{t+1} - o_t) mod W` takes only
//! [`STEP_COUNT`] values: on each axis `floor(W a)` or `floor(W a) + 1`
//! (three-distance theorem). Each gets its own retarget table, numbered by
//! [`step_index`]: `index = sx + 2 * sy` where `s` is the `+1` carry per axis.

use crate::sequences::r2::{R2_A1_Q32, R2_A2_Q32};
use glam::UVec2;

pub use crate::limits::{MAX_TILE, MAX_TILE_LOG2};
/// Number of distinct steps of the walk, hence of retarget tables per tile.
pub const STEP_COUNT: usize = 4;

/// `log2` of a tile side, if it is a power of two in `2..=MAX_TILE`.
pub fn tile_log2(tile: u32) -> Option<u32> {
    if tile.is_power_of_two() && (2..=MAX_TILE).contains(&tile) {
        Some(tile.trailing_zeros())
    } else {
        None
    }
}

/// Tile offset `o_t` of frame `t` for a tile of side `2^tile_log2`; each
/// component in `0..2^tile_log2`. `o_0 = (0, 0)`.
///
/// `tile_log2` must be in `1..=MAX_TILE_LOG2` (callers validate with
/// [`tile_log2`]; out-of-range values give meaningless but in-range offsets).
///
/// # Example
///
/// ```
/// use sampler_core::walk_offset;
/// let o = walk_offset(5, 6); // frame 5, 64x64 tile
/// assert!(o.x < 64 && o.y < 64);
/// assert_ne!(walk_offset(5, 6), walk_offset(6, 6));
/// ```
#[inline]
pub fn walk_offset(frame: u32, tile_log2: u32) -> UVec2 {
    let shift = 32u32.wrapping_sub(tile_log2) & 31;
    UVec2::new(
        frame.wrapping_mul(R2_A1_Q32) >> shift,
        frame.wrapping_mul(R2_A2_Q32) >> shift,
    )
}

/// The smaller of the two step lengths per axis: `floor(W * a)` in fixed point.
#[inline]
pub fn base_step(tile_log2: u32) -> UVec2 {
    walk_offset(1, tile_log2)
}

/// Step `(o_{t+1} - o_t) mod W` taken after frame `t`.
#[inline]
pub fn walk_step(frame: u32, tile_log2: u32) -> UVec2 {
    let mask = (1u32 << tile_log2).wrapping_sub(1);
    let a = walk_offset(frame, tile_log2);
    let b = walk_offset(frame.wrapping_add(1), tile_log2);
    UVec2::new(b.x.wrapping_sub(a.x) & mask, b.y.wrapping_sub(a.y) & mask)
}

/// Index in `0..STEP_COUNT` of the step taken after frame `t`; selects the
/// retarget table.
///
/// # Example
///
/// ```
/// use sampler_core::{defaults, step_index, STEP_COUNT};
/// let tables = defaults::tables_64();
/// let t = 10;
/// let table = tables.table(step_index(t, 6)); // the table from frame t's tile to frame t + 1's
/// assert!(step_index(t, 6) < STEP_COUNT as u32);
/// assert_eq!(table.packed().len(), 64 * 64);
/// ```
#[inline]
pub fn step_index(frame: u32, tile_log2: u32) -> u32 {
    let mask = (1u32 << tile_log2).wrapping_sub(1);
    let s = walk_step(frame, tile_log2);
    let base = base_step(tile_log2);
    let cx = s.x.wrapping_sub(base.x) & mask & 1;
    let cy = s.y.wrapping_sub(base.y) & mask & 1;
    cx + 2 * cy
}

/// The step vector that table `index` (in `0..STEP_COUNT`) is baked for.
#[inline]
pub fn step_of_index(index: u32, tile_log2: u32) -> UVec2 {
    let mask = (1u32 << tile_log2).wrapping_sub(1);
    let base = base_step(tile_log2);
    UVec2::new(
        base.x.wrapping_add(index & 1) & mask,
        base.y.wrapping_add((index >> 1) & 1) & mask,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_match_the_real_r2_walk() {
        let want = [(0, 0), (48, 36), (32, 8), (16, 45), (1, 17), (49, 54)];
        for (t, w) in want.iter().enumerate() {
            assert_eq!(walk_offset(t as u32, 6), UVec2::new(w.0, w.1), "t = {t}");
        }
    }

    #[test]
    fn base_steps_are_floor_w_a() {
        for (k, w) in [(6, (48, 36)), (7, (96, 72)), (8, (193, 145)), (9, (386, 291))] {
            assert_eq!(base_step(k), UVec2::new(w.0, w.1));
        }
    }

    #[test]
    fn step_index_round_trips() {
        for k in 1..=MAX_TILE_LOG2 {
            for t in 0..2000 {
                let i = step_index(t, k);
                assert!(i < STEP_COUNT as u32);
                assert_eq!(step_of_index(i, k), walk_step(t, k), "k {k} t {t}");
            }
        }
    }
}
