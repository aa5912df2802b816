//! The retargeting pass (Heitz & Belcour 2019, Algorithm 2).
//!
//! After the sorting pass of frame `t`, seeds are ranked like the dither
//! values `D_t(p) = tile[(p + o_t) mod W]`. A **retarget table** moves them
//! so they are ranked like `D_{t+1}`: a precomputed permutation of the tile,
//! stored per texel as an offset `R(q) = (dx, dy)` with `|dx|, |dy| <=`
//! [`RETARGET_RADIUS`], applied as a scatter.
//!
//! # Convention
//!
//! The table for step `s = (o_{t+1} - o_t) mod W` is baked in tile space with
//! `o_t = 0`: the seed at texel `q` moves to `q + R(q)`, and the baker makes
//! `tile[q + R(q) + s] ~ tile[q]`. At run time the seed at screen pixel `p`
//! moves to `(p + R((p + o_t) mod W)) mod (padded_width, padded_height)`:
//! the table is read at the same texel the sorting pass read `D_t` from.
//! Because `q -> (q + R(q)) mod W` is a permutation of the tile and the
//! padded buffer is a multiple of `W`, the scatter is a permutation of the
//! whole seed buffer.
//!
//! # Packing (`_packed`)
//!
//! One `u32` per texel: bits 0..8 hold `dx + 128`, bits 8..16 `dy + 128`,
//! bits 16..32 are zero. The identity is `0x8080`.

use crate::error::{Buffer, Error};
use crate::permutation::dither::tile_texel;
use crate::sequences::walk::{tile_log2, STEP_COUNT};
use glam::{IVec2, UVec2};

pub use crate::limits::RETARGET_RADIUS;
/// Bias added to each offset component before packing.
pub const OFFSET_BIAS: i32 = 128;
/// The packed zero offset.
pub const IDENTITY_PACKED: u32 = 0x8080;

/// Packs an offset; components must be in `-128..128`.
#[inline]
pub fn pack_offset(offset: IVec2) -> u32 {
    let x = (offset.x + OFFSET_BIAS) as u32 & 0xFF;
    let y = (offset.y + OFFSET_BIAS) as u32 & 0xFF;
    x | (y << 8)
}

/// Unpacks an offset (bits 16..32 ignored).
#[inline]
pub fn unpack_offset(packed: u32) -> IVec2 {
    IVec2::new(
        (packed & 0xFF) as i32 - OFFSET_BIAS,
        ((packed >> 8) & 0xFF) as i32 - OFFSET_BIAS,
    )
}

/// `v mod m` in `0..m` for any `v` and `m > 0`.
#[inline]
fn wrap(v: i32, m: u32) -> u32 {
    let m = m as i32;
    let r = v % m;
    (if r < 0 { r + m } else { r }) as u32
}

/// Where the retargeting scatter sends the seed at padded-buffer pixel
/// `pixel` in a frame with tile offset `offset`. Shader-callable.
///
/// `table` is the packed table of the frame's step; `padded` the seed buffer
/// size. Identical on host and GPU.
#[inline]
pub fn retarget_destination(
    pixel: UVec2,
    offset: UVec2,
    tile_log2: u32,
    table: &[u32],
    padded: UVec2,
) -> UVec2 {
    let d = unpack_offset(table[tile_texel(pixel, offset, tile_log2) as usize]);
    UVec2::new(
        wrap(pixel.x as i32 + d.x, padded.x),
        wrap(pixel.y as i32 + d.y, padded.y),
    )
}

/// One validated retarget table: `tile * tile` packed offsets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RetargetTable<'a> {
    tile_log2: u32,
    packed: &'a [u32],
}

impl<'a> RetargetTable<'a> {
    /// Validates `packed` as a table for a `tile x tile` dither tile.
    ///
    /// # Errors
    /// [`Error::TileSize`], [`Error::BufferSize`] for a wrong length,
    /// [`Error::RetargetOffset`] for an entry with stray high bits or an
    /// offset beyond [`RETARGET_RADIUS`], [`Error::RetargetNotBijective`] if
    /// two texels move to the same place (the first texel receiving zero or
    /// several seeds is reported).
    pub fn new(tile: u32, packed: &'a [u32]) -> Result<Self, Error> {
        let table = Self::new_bounded(tile, packed)?;
        table.check_bijective()?;
        Ok(table)
    }

    /// [`new`](Self::new) without the bijection check (about 170 reads a
    /// texel): sizes and every offset's radius are checked, which is all
    /// the passes' memory safety rests on; that the table is a permutation
    /// is the caller's promise (compiled-in data whose tests check it). A
    /// table that is not would lose and duplicate seeds.
    ///
    /// # Errors
    /// As [`new`](Self::new), except [`Error::RetargetNotBijective`].
    pub(crate) fn new_bounded(tile: u32, packed: &'a [u32]) -> Result<Self, Error> {
        let log2 = tile_log2(tile).ok_or(Error::TileSize { tile })?;
        let n = (tile as usize) * (tile as usize);
        if packed.len() != n {
            return Err(Error::BufferSize {
                buffer: Buffer::RetargetTable,
                expected: n,
                actual: packed.len(),
            });
        }
        for (texel, &p) in packed.iter().enumerate() {
            let d = unpack_offset(p);
            if p >> 16 != 0 || d.x.abs() > RETARGET_RADIUS || d.y.abs() > RETARGET_RADIUS {
                return Err(Error::RetargetOffset {
                    texel: texel as u32,
                    packed: p,
                });
            }
        }
        Ok(RetargetTable {
            tile_log2: log2,
            packed,
        })
    }

    /// Rewraps a slice that [`new`](Self::new) or [`new_bounded`](Self::new_bounded)
    /// accepted before (for types that validate many tables once and hand
    /// them out per frame): no check but the length, in debug builds.
    pub(crate) fn from_checked(tile_log2: u32, packed: &'a [u32]) -> Self {
        debug_assert_eq!(packed.len(), 1usize << (2 * tile_log2));
        RetargetTable { tile_log2, packed }
    }

    /// Tile side in texels.
    pub fn tile(&self) -> u32 {
        1 << self.tile_log2
    }
    /// The packed offsets, row-major.
    pub fn packed(&self) -> &'a [u32] {
        self.packed
    }
    /// Offset of texel `(x, y)`.
    pub fn offset(&self, x: u32, y: u32) -> IVec2 {
        unpack_offset(self.packed[((y << self.tile_log2) | x) as usize])
    }
    /// Where texel `q` goes inside the tile: `(q + R(q)) mod W`.
    pub fn destination_in_tile(&self, q: UVec2) -> UVec2 {
        let w = self.tile();
        let d = self.offset(q.x, q.y);
        UVec2::new(wrap(q.x as i32 + d.x, w), wrap(q.y as i32 + d.y, w))
    }

    /// Counts, for each destination texel, the sources that land on it:
    /// every destination must receive exactly one. No allocation: sources
    /// of `d` lie within the radius, so each destination checks its
    /// `(2 r + 1)^2` candidates (all texels, deduplicated, on small tiles).
    fn check_bijective(&self) -> Result<(), Error> {
        let w = self.tile();
        let r = RETARGET_RADIUS;
        let small = w <= 2 * r as u32 + 1;
        for dy in 0..w {
            for dx in 0..w {
                let d = UVec2::new(dx, dy);
                let mut sources = 0u32;
                if small {
                    for qy in 0..w {
                        for qx in 0..w {
                            if self.destination_in_tile(UVec2::new(qx, qy)) == d {
                                sources += 1;
                            }
                        }
                    }
                } else {
                    for oy in -r..=r {
                        for ox in -r..=r {
                            let q = UVec2::new(wrap(dx as i32 - ox, w), wrap(dy as i32 - oy, w));
                            if self.offset(q.x, q.y) == IVec2::new(ox, oy) {
                                sources += 1;
                            }
                        }
                    }
                }
                if sources != 1 {
                    return Err(Error::RetargetNotBijective {
                        texel: (dy << self.tile_log2) | dx,
                        sources,
                    });
                }
            }
        }
        Ok(())
    }
}

/// The retarget tables of one dither tile, one per step of the offset walk:
/// `tables[i]` is baked for [`step_of_index`](crate::step_of_index)`(i)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RetargetTables<'a> {
    tables: [RetargetTable<'a>; STEP_COUNT],
}

impl<'a> RetargetTables<'a> {
    /// Validates four packed tables for a `tile x tile` tile.
    ///
    /// # Errors
    /// As [`RetargetTable::new`] for each table.
    pub fn new(tile: u32, packed: [&'a [u32]; STEP_COUNT]) -> Result<Self, Error> {
        Ok(RetargetTables {
            tables: [
                RetargetTable::new(tile, packed[0])?,
                RetargetTable::new(tile, packed[1])?,
                RetargetTable::new(tile, packed[2])?,
                RetargetTable::new(tile, packed[3])?,
            ],
        })
    }

    /// Tile side in texels.
    pub fn tile(&self) -> u32 {
        self.tables[0].tile()
    }
    /// Table of step index `index` (`0..STEP_COUNT`).
    ///
    /// # Panics
    /// If `index >= STEP_COUNT`.
    pub fn table(&self, index: u32) -> RetargetTable<'a> {
        self.tables[index as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packing_round_trips() {
        for y in -6..=6 {
            for x in -6..=6 {
                let v = IVec2::new(x, y);
                assert_eq!(unpack_offset(pack_offset(v)), v);
            }
        }
        assert_eq!(pack_offset(IVec2::ZERO), IDENTITY_PACKED);
    }

    #[test]
    fn validation_catches_collisions_and_radius() {
        let id = [IDENTITY_PACKED; 64 * 64];
        assert!(RetargetTable::new(64, &id).is_ok());
        let mut swap = id;
        // Swap texels 0 and 1 of row 0: a permutation.
        swap[0] = pack_offset(IVec2::new(1, 0));
        swap[1] = pack_offset(IVec2::new(-1, 0));
        assert!(RetargetTable::new(64, &swap).is_ok());
        let mut bad = id;
        bad[0] = pack_offset(IVec2::new(1, 0));
        assert_eq!(
            RetargetTable::new(64, &bad),
            Err(Error::RetargetNotBijective { texel: 0, sources: 0 })
        );
        bad[0] = pack_offset(IVec2::new(7, 0));
        assert!(matches!(
            RetargetTable::new(64, &bad),
            Err(Error::RetargetOffset { texel: 0, .. })
        ));
        bad[0] = IDENTITY_PACKED | 0x1_0000;
        assert!(matches!(
            RetargetTable::new(64, &bad),
            Err(Error::RetargetOffset { .. })
        ));
        // Wrapping: on a 4x4 tile, offset 4 returns to the same texel.
        let mut small = [IDENTITY_PACKED; 16];
        small[5] = pack_offset(IVec2::new(4, -4));
        assert!(RetargetTable::new(4, &small).is_ok());
        small[5] = pack_offset(IVec2::new(1, 0));
        assert!(RetargetTable::new(4, &small).is_err());
    }
}
