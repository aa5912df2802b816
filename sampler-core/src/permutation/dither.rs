//! The dither tile the sorting pass ranks seeds against.

use crate::error::{Buffer, Error};
use crate::sequences::walk::tile_log2;
use glam::UVec2;

/// A square blue-noise dither tile of side `W = 2^k`, row-major, one `u32`
/// per texel.
///
/// Only the order of the values matters: the sorting pass ranks them, with
/// ties broken by in-block index. Baked tiles store exact ranks
/// `0..W*W` (each once); the dither value in `[0, 1)` of rank `r` is
/// `(r + 0.5) / (W*W)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DitherTile<'a> {
    tile_log2: u32,
    values: &'a [u32],
}

impl<'a> DitherTile<'a> {
    /// Wraps `values` (row-major, `tile * tile` entries).
    ///
    /// # Errors
    /// [`Error::TileSize`] if `tile` is not a power of two in `2..=MAX_TILE`,
    /// [`Error::BufferSize`] if `values.len() != tile * tile`.
    pub fn new(tile: u32, values: &'a [u32]) -> Result<Self, Error> {
        let tile_log2 = tile_log2(tile).ok_or(Error::TileSize { tile })?;
        let expected = (tile as usize) * (tile as usize);
        if values.len() != expected {
            return Err(Error::BufferSize {
                buffer: Buffer::DitherTile,
                expected,
                actual: values.len(),
            });
        }
        Ok(DitherTile { tile_log2, values })
    }

    /// Rewraps values that [`new`](Self::new)'s checks hold for (a slice of
    /// an already validated volume): no check but the length, in debug builds.
    pub(crate) fn from_checked(tile_log2: u32, values: &'a [u32]) -> Self {
        debug_assert_eq!(values.len(), 1usize << (2 * tile_log2));
        DitherTile { tile_log2, values }
    }

    /// Tile side in texels.
    pub fn tile(&self) -> u32 {
        1 << self.tile_log2
    }
    /// `log2` of the tile side.
    pub fn tile_log2(&self) -> u32 {
        self.tile_log2
    }
    /// The texel values, row-major.
    pub fn values(&self) -> &'a [u32] {
        self.values
    }
}

/// Row-major index of the tile texel that screen pixel `pixel` reads in a
/// frame whose tile offset is `offset`: `(pixel + offset) mod W` (see the
/// convention in [`walk`](crate::sequences::walk)).
#[inline]
pub fn tile_texel(pixel: UVec2, offset: UVec2, tile_log2: u32) -> u32 {
    let mask = (1u32 << tile_log2).wrapping_sub(1);
    let x = pixel.x.wrapping_add(offset.x) & mask;
    let y = pixel.y.wrapping_add(offset.y) & mask;
    (y << tile_log2) | x
}
