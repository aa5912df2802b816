//! The retarget step of one frame as the fast path reads it: the table's
//! destination of a seed (`π`) and its exact inverse (`π⁻¹`), both from a
//! tile texel, without division.

use crate::permutation::dither::tile_texel;
use crate::permutation::layout::FrameParams;
use crate::permutation::retarget::{unpack_offset, RetargetTable};
use crate::sequences::walk::walk_offset;
use glam::UVec2;

/// Largest tile side of the fast path (as the plain fast path's cache).
pub(super) const MAX_TILE: u32 = 128;

/// `π` and `π⁻¹` of one frame on the padded seed buffer.
///
/// Positions are `(x, y)` in the padded frame, `x < padded_width`,
/// `y < padded_height`. Offsets are at most `RETARGET_RADIUS` (6) on each
/// axis and the padded sides are at least the tile side (`>= 16`), so a
/// wrap is one conditional add or subtract.
pub(super) struct Steps<'a> {
    /// The frame's packed table (`tile * tile`, row-major by texel).
    packed: &'a [u32],
    /// `inverse[tq]`: the offset `(dx, dy)` from a seed
    /// whose texel is `tq` back to the seed that `π` sends there
    /// (`-R(tp)` where `(tp + R(tp)) mod W = tq`).
    inverse: [(i8, i8); (MAX_TILE * MAX_TILE) as usize],
    /// The frame's tile offset `o_t`.
    offset: UVec2,
    /// `log2` of the tile side.
    log2: u32,
    /// Padded frame size in seeds.
    padded_width: u32,
    padded_height: u32,
}

/// Unpacked `(dx, dy)` of a table entry or an [`Steps::inverse`] entry.
#[inline(always)]
fn offset_of(packed: u32) -> (i32, i32) {
    let d = unpack_offset(packed);
    (d.x, d.y)
}

/// `v mod m` for `v` in `-m..2m`.
#[inline(always)]
pub(super) fn wrap(v: i32, m: u32) -> u32 {
    let m = m as i32;
    (if v < 0 {
        v + m
    } else if v >= m {
        v - m
    } else {
        v
    }) as u32
}

impl<'a> Steps<'a> {
    /// The step of frame `params.frame` with `table` (a valid, bijective
    /// table of the layout's tile, side `16..=MAX_TILE`).
    pub fn new(params: &FrameParams, table: RetargetTable<'a>) -> Self {
        let log2 = params.tile_log2;
        let w = 1u32 << log2;
        let mask = w - 1;
        let packed = table.packed();
        let mut inverse = [(0i8, 0i8); (MAX_TILE * MAX_TILE) as usize];
        for (tp, &entry) in packed.iter().enumerate() {
            let (dx, dy) = offset_of(entry);
            let tx = (tp as u32 & mask).wrapping_add(dx as u32) & mask;
            let ty = ((tp as u32) >> log2).wrapping_add(dy as u32) & mask;
            inverse[((ty << log2) | tx) as usize] = (-dx as i8, -dy as i8);
        }
        Steps {
            packed,
            inverse,
            offset: walk_offset(params.frame, log2),
            log2,
            padded_width: params.padded_width,
            padded_height: params.padded_height,
        }
    }

    /// The table's offset `R` at seed `(x, y)` (the texel the sort read).
    #[inline(always)]
    pub fn forward_offset(&self, x: u32, y: u32) -> (i32, i32) {
        offset_of(self.packed[tile_texel(UVec2::new(x, y), self.offset, self.log2) as usize])
    }

    /// `π(x, y)`: where the table sends the seed at `(x, y)`.
    #[inline(always)]
    pub fn forward(&self, x: u32, y: u32) -> (u32, u32) {
        let (dx, dy) = self.forward_offset(x, y);
        (
            wrap(x as i32 + dx, self.padded_width),
            wrap(y as i32 + dy, self.padded_height),
        )
    }

    /// `π⁻¹(x, y)`: the seed the table sends to `(x, y)`. Exact:
    /// `forward(inverse(x, y)) == (x, y)` for every position.
    #[inline(always)]
    pub fn inverse(&self, x: u32, y: u32) -> (u32, u32) {
        let t = tile_texel(UVec2::new(x, y), self.offset, self.log2);
        let (dx, dy) = self.inverse[t as usize];
        let (dx, dy) = (dx as i32, dy as i32);
        (
            wrap(x as i32 + dx, self.padded_width),
            wrap(y as i32 + dy, self.padded_height),
        )
    }
}
