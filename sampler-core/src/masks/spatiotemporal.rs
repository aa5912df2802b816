//! Read-only access to a scalar spatiotemporal blue-noise mask (STBN-style
//! `W x H x D` volume, see `bake::bake_stbn` behind the `bake` feature).
//!
//! Storage: one little-endian `u16` rank per texel, slice-major then
//! row-major (`index = (z * height + y) * width + x`), read byte-wise so any
//! byte slice works (no alignment assumption; `include_bytes!` data
//! included). In a baked mask every slice holds each rank of
//! `0..width * height` exactly once.

use crate::error::{Buffer, Error};

/// Largest number of texels per slice: ranks must fit a `u16`.
pub const MAX_SLICE_TEXELS: u32 = 1 << 16;

/// A `width x height x depth` volume of per-slice ranks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SpatiotemporalMask<'a> {
    width: u32,
    height: u32,
    depth: u32,
    bytes: &'a [u8],
}

impl<'a> SpatiotemporalMask<'a> {
    /// Wraps `bytes`: `2 * width * height * depth` bytes of little-endian
    /// `u16` ranks. The rank values themselves are not checked (that would
    /// cost a pass over the volume); baked masks hold exact per-slice
    /// histograms.
    ///
    /// # Errors
    /// [`Error::MaskSize`] if a side is zero or `width * height` exceeds
    /// [`MAX_SLICE_TEXELS`]; [`Error::BufferSize`] if `bytes` has the wrong
    /// length (in bytes).
    pub fn new(width: u32, height: u32, depth: u32, bytes: &'a [u8]) -> Result<Self, Error> {
        let slice = width as u64 * height as u64;
        if width == 0 || height == 0 || depth == 0 || slice > MAX_SLICE_TEXELS as u64 {
            return Err(Error::MaskSize { width, height, depth });
        }
        let expected = (2 * slice * depth as u64) as usize;
        if bytes.len() != expected {
            return Err(Error::BufferSize {
                buffer: Buffer::SpatiotemporalMask,
                expected,
                actual: bytes.len(),
            });
        }
        Ok(SpatiotemporalMask {
            width,
            height,
            depth,
            bytes,
        })
    }

    /// Width in texels.
    pub fn width(&self) -> u32 {
        self.width
    }
    /// Height in texels.
    pub fn height(&self) -> u32 {
        self.height
    }
    /// Depth in slices (frames).
    pub fn depth(&self) -> u32 {
        self.depth
    }
    /// The raw little-endian `u16` ranks.
    pub fn bytes(&self) -> &'a [u8] {
        self.bytes
    }

    /// Rank of texel `(x, y)` in slice `z`, in `0..width * height` for a
    /// baked mask. Coordinates wrap toroidally (`x mod width`, ...), as the
    /// mask tiles the screen and repeats in time.
    #[inline]
    pub fn rank(&self, x: u32, y: u32, z: u32) -> u32 {
        let (x, y, z) = (x % self.width, y % self.height, z % self.depth);
        let i = 2 * (((z as usize * self.height as usize) + y as usize) * self.width as usize + x as usize);
        u16::from_le_bytes([self.bytes[i], self.bytes[i + 1]]) as u32
    }

    /// Dither value of texel `(x, y)` in slice `z`:
    /// `(rank + 0.5) / (width * height)`, in `(0, 1)` for a baked mask.
    #[inline]
    pub fn value(&self, x: u32, y: u32, z: u32) -> f32 {
        (self.rank(x, y, z) as f32 + 0.5) / (self.width * self.height) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_little_endian_ranks_and_wraps() {
        // 2x1x2 volume: slice 0 ranks [1, 0], slice 1 ranks [0, 1].
        let bytes = [1, 0, 0, 0, 0, 0, 1, 0];
        let m = SpatiotemporalMask::new(2, 1, 2, &bytes).unwrap();
        assert_eq!(
            (m.rank(0, 0, 0), m.rank(1, 0, 0), m.rank(0, 0, 1), m.rank(1, 0, 1)),
            (1, 0, 0, 1)
        );
        assert_eq!(m.rank(2, 5, 2), m.rank(0, 0, 0));
        assert_eq!(m.value(0, 0, 0), 0.75);
        assert_eq!(m.value(1, 0, 0), 0.25);
        // High byte.
        let bytes = [0x34, 0x12];
        assert_eq!(
            SpatiotemporalMask::new(1, 1, 1, &bytes).unwrap().rank(0, 0, 0),
            0x1234
        );
    }

    #[test]
    fn sizes_are_validated() {
        let bytes = [0u8; 8];
        assert_eq!(
            SpatiotemporalMask::new(0, 1, 1, &bytes),
            Err(Error::MaskSize {
                width: 0,
                height: 1,
                depth: 1
            })
        );
        assert!(matches!(
            SpatiotemporalMask::new(512, 256, 1, &bytes),
            Err(Error::MaskSize { .. })
        ));
        assert_eq!(
            SpatiotemporalMask::new(2, 2, 2, &bytes),
            Err(Error::BufferSize {
                buffer: Buffer::SpatiotemporalMask,
                expected: 16,
                actual: 8
            })
        );
    }
}
