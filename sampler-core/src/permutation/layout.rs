//! Frame geometry: visible size, padded seed buffer, blocks.
//!
//! # Padding rule
//!
//! The **seed buffer** covers the frame padded up to a multiple of the tile
//! side `W` on both axes (`padded_width = ceil(width / W) * W`), row-major,
//! `padded_width * padded_height` seeds. Seeds in the padding are never
//! rendered and never take part in sorting (a block sorts only its visible
//! pixels), but the retargeting scatter moves them like any other, toroidally
//! over the padded buffer. Both passes are therefore bijections of the whole
//! seed buffer for any frame size: no seed is lost or duplicated.
//!
//! The **intensity buffer** covers only the visible frame, row-major,
//! `width * height` values.
//!
//! Blocks are `B x B` pixels on a fixed grid anchored at pixel (0, 0); the
//! last row and column of blocks may be clipped by the frame edge.

use crate::error::Error;
use crate::permutation::sort::{MAX_BLOCK, MIN_BLOCK};
use crate::sequences::walk::tile_log2;

/// Frame geometry as plain `u32`s, the form shaders receive
/// (Vulkan block layout: 8 scalars, 32 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct FrameParams {
    /// Visible width in pixels, `>= 1`.
    pub width: u32,
    /// Visible height in pixels, `>= 1`.
    pub height: u32,
    /// Seed-buffer width: `width` rounded up to a multiple of the tile side.
    pub padded_width: u32,
    /// Seed-buffer height: `height` rounded up to a multiple of the tile side.
    pub padded_height: u32,
    /// Block side `B` in pixels, in `MIN_BLOCK..=MAX_BLOCK`.
    pub block: u32,
    /// `log2` of the tile side `W`.
    pub tile_log2: u32,
    /// Frame index `t` of the intensities being sorted (selects the tile
    /// offset `o_t` and the retarget table of step `t -> t + 1`).
    pub frame: u32,
    /// Unused; keeps the struct 32 bytes. Zero.
    pub reserved: u32,
}

impl FrameParams {
    /// Blocks per row: `ceil(padded_width / block)`.
    #[inline]
    pub fn blocks_x(&self) -> u32 {
        self.padded_width.div_ceil(self.block)
    }
    /// Blocks per column: `ceil(padded_height / block)`.
    #[inline]
    pub fn blocks_y(&self) -> u32 {
        self.padded_height.div_ceil(self.block)
    }
    /// Number of seeds in the padded buffer.
    #[inline]
    pub fn seed_count(&self) -> u32 {
        self.padded_width * self.padded_height
    }
    /// Number of visible pixels.
    #[inline]
    pub fn pixel_count(&self) -> u32 {
        self.width * self.height
    }
    /// The same geometry for frame `frame`.
    #[inline]
    pub fn with_frame(mut self, frame: u32) -> Self {
        self.frame = frame;
        self
    }
}

/// Validated frame geometry. Build with [`FrameLayout::new`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameLayout {
    params: FrameParams,
}

impl FrameLayout {
    /// Geometry of a `width x height` frame sorted in `block x block` blocks
    /// against a `tile x tile` dither tile.
    ///
    /// # Errors
    /// [`Error::FrameSize`] for a zero side or a padded buffer of more than
    /// `2^31` seeds, [`Error::BlockSize`] for a block outside
    /// `MIN_BLOCK..=MAX_BLOCK`, [`Error::TileSize`] for a tile side that is
    /// not a power of two in `2..=MAX_TILE`.
    ///
    /// # Example
    ///
    /// ```
    /// use sampler_core::{Error, FrameLayout};
    /// let layout = FrameLayout::new(1920, 1080, 4, 64)?;
    /// assert_eq!((layout.padded_width(), layout.padded_height()), (1920, 1088)); // whole tiles
    /// assert_eq!(layout.seed_count(), 1920 * 1088);
    /// assert!(matches!(FrameLayout::new(1920, 1080, 4, 48), Err(Error::TileSize { .. }))); // not a power of two
    /// # Ok::<(), sampler_core::Error>(())
    /// ```
    pub fn new(width: u32, height: u32, block: u32, tile: u32) -> Result<Self, Error> {
        if !(MIN_BLOCK..=MAX_BLOCK).contains(&block) {
            return Err(Error::BlockSize { block });
        }
        let log2 = tile_log2(tile).ok_or(Error::TileSize { tile })?;
        let too_big = Error::FrameSize { width, height };
        if width == 0 || height == 0 {
            return Err(too_big);
        }
        let pw = width.checked_next_multiple_of(tile).ok_or(too_big)?;
        let ph = height.checked_next_multiple_of(tile).ok_or(too_big)?;
        match pw.checked_mul(ph) {
            Some(n) if n <= 1 << 31 => {}
            _ => return Err(too_big),
        }
        Ok(FrameLayout {
            params: FrameParams {
                width,
                height,
                padded_width: pw,
                padded_height: ph,
                block,
                tile_log2: log2,
                frame: 0,
                reserved: 0,
            },
        })
    }

    /// The plain form, for frame `frame`.
    #[inline]
    pub fn params(&self, frame: u32) -> FrameParams {
        self.params.with_frame(frame)
    }
    /// Visible width in pixels.
    pub fn width(&self) -> u32 {
        self.params.width
    }
    /// Visible height in pixels.
    pub fn height(&self) -> u32 {
        self.params.height
    }
    /// Seed-buffer width (multiple of the tile side).
    pub fn padded_width(&self) -> u32 {
        self.params.padded_width
    }
    /// Seed-buffer height (multiple of the tile side).
    pub fn padded_height(&self) -> u32 {
        self.params.padded_height
    }
    /// Block side in pixels.
    pub fn block(&self) -> u32 {
        self.params.block
    }
    /// Tile side in texels.
    pub fn tile(&self) -> u32 {
        1 << self.params.tile_log2
    }
    /// Length the seed buffers must have.
    pub fn seed_count(&self) -> usize {
        self.params.seed_count() as usize
    }
    /// Length the intensity buffer must have.
    pub fn pixel_count(&self) -> usize {
        self.params.pixel_count() as usize
    }

    /// Checks that a seed buffer (`buffer` names which, for the error) has
    /// [`seed_count`](Self::seed_count) elements.
    ///
    /// # Errors
    /// [`Error::BufferSize`] otherwise.
    pub fn check_seed_buffer(&self, buffer: crate::Buffer, len: usize) -> Result<(), Error> {
        check_len(buffer, self.seed_count(), len)
    }

    /// Checks that an intensity buffer has [`pixel_count`](Self::pixel_count)
    /// elements.
    ///
    /// # Errors
    /// [`Error::BufferSize`] otherwise.
    pub fn check_intensity_buffer(&self, len: usize) -> Result<(), Error> {
        check_len(crate::Buffer::Intensities, self.pixel_count(), len)
    }
}

fn check_len(buffer: crate::Buffer, expected: usize, actual: usize) -> Result<(), Error> {
    if expected == actual {
        Ok(())
    } else {
        Err(Error::BufferSize {
            buffer,
            expected,
            actual,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pads_to_tile_multiples() {
        let l = FrameLayout::new(1920, 1080, 4, 64).unwrap();
        assert_eq!((l.padded_width(), l.padded_height()), (1920, 1088));
        assert_eq!(l.params(3).frame, 3);
        let l = FrameLayout::new(1, 1, 3, 64).unwrap();
        assert_eq!((l.padded_width(), l.padded_height()), (64, 64));
        assert_eq!(l.params(0).blocks_x(), 22);
    }

    #[test]
    fn rejects_bad_geometry() {
        assert_eq!(
            FrameLayout::new(0, 5, 4, 64),
            Err(Error::FrameSize { width: 0, height: 5 })
        );
        assert_eq!(FrameLayout::new(5, 5, 1, 64), Err(Error::BlockSize { block: 1 }));
        assert_eq!(FrameLayout::new(5, 5, 9, 64), Err(Error::BlockSize { block: 9 }));
        assert_eq!(FrameLayout::new(5, 5, 4, 48), Err(Error::TileSize { tile: 48 }));
        assert_eq!(
            FrameLayout::new(5, 5, 4, 2048),
            Err(Error::TileSize { tile: 2048 })
        );
        assert!(matches!(
            FrameLayout::new(u32::MAX, 5, 4, 64),
            Err(Error::FrameSize { .. })
        ));
        assert!(matches!(
            FrameLayout::new(65536, 65536, 4, 64),
            Err(Error::FrameSize { .. })
        ));
    }
}
