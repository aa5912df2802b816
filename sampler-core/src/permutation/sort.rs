//! The sorting pass (Heitz & Belcour 2019, Algorithm 1).
//!
//! Inside each `B x B` block, the seed of the pixel whose last-frame
//! intensity has rank `k` moves to the pixel whose dither value has rank `k`.
//! A block only permutes its own visible pixels, so the pass is a bijection.
//!
//! # Order
//!
//! Intensities are ranked by [`intensity_key`], a total order on every `f32`
//! bit pattern:
//! `-NaN < -inf < ... < -0.0 < +0.0 < ... < +inf < +NaN`
//! (a NaN ranks by its sign bit and payload beyond the infinities; `-0.0`
//! ranks just below `+0.0`). Equal keys, and equal dither values, are
//! ordered by in-block index (row-major inside the block, visible pixels
//! only). The result is therefore unique: every implementation (the
//! shader-callable [`sort_block`], the CPU frame functions, the GPU kernel)
//! must produce exactly the same permutation.
//!
//! # Intensity
//!
//! RGB values are reduced to Rec. 709 luma `0.2126 r + 0.7152 g + 0.0722 b`
//! ([`Intensity`]).

use glam::{Vec3, Vec4};

pub use crate::limits::{MAX_BLOCK, MIN_BLOCK};
/// Block side the paper and both public implementations use.
pub const DEFAULT_BLOCK: u32 = 4;
/// Pixels in the largest block: the length of the per-block arrays.
pub const MAX_BLOCK_PIXELS: usize = (MAX_BLOCK * MAX_BLOCK) as usize;

/// Maps an `f32` to a `u32` whose unsigned order is the total order
/// described in the [module docs](self). Identical on host and GPU.
#[inline]
pub fn intensity_key(value: f32) -> u32 {
    let bits = value.to_bits();
    if bits & 0x8000_0000 != 0 {
        !bits
    } else {
        bits | 0x8000_0000
    }
}

/// A pixel value the sorting pass can rank.
pub trait Intensity: Copy {
    /// The scalar that is ranked.
    fn intensity(self) -> f32;
}

impl Intensity for f32 {
    #[inline]
    fn intensity(self) -> f32 {
        self
    }
}

impl Intensity for Vec3 {
    #[inline]
    fn intensity(self) -> f32 {
        luma(self)
    }
}

impl Intensity for Vec4 {
    /// Luma of `xyz`; `w` is ignored.
    #[inline]
    fn intensity(self) -> f32 {
        luma(self.truncate())
    }
}

impl Intensity for [f32; 3] {
    #[inline]
    fn intensity(self) -> f32 {
        luma(Vec3::from_array(self))
    }
}

impl Intensity for [f32; 4] {
    /// Luma of the first three channels.
    #[inline]
    fn intensity(self) -> f32 {
        luma(Vec3::new(self[0], self[1], self[2]))
    }
}

/// Rec. 709 luma of linear RGB.
#[inline]
pub fn luma(rgb: Vec3) -> f32 {
    0.2126 * rgb.x + 0.7152 * rgb.y + 0.0722 * rgb.z
}

/// Sorts one block: shader-callable, no allocation, `O(len^2)` rank counting.
///
/// `len` pixels (`<= MAX_BLOCK_PIXELS`) in in-block order; `keys[i]` is the
/// [`intensity_key`] of pixel `i`, `dither[i]` its dither value, `seeds[i]`
/// its seed. Writes `out[j]` = the seed that moves to pixel `j`. Entries at
/// or beyond `len` are ignored and `out` is left untouched there.
// Index loops on purpose: shader code avoids slice iterators.
#[allow(clippy::needless_range_loop)]
#[inline]
pub fn sort_block(
    len: u32,
    keys: &[u32; MAX_BLOCK_PIXELS],
    dither: &[u32; MAX_BLOCK_PIXELS],
    seeds: &[u32; MAX_BLOCK_PIXELS],
    out: &mut [u32; MAX_BLOCK_PIXELS],
) {
    let n = if len as usize > MAX_BLOCK_PIXELS {
        MAX_BLOCK_PIXELS
    } else {
        len as usize
    };
    // position_of_rank[r] = in-block pixel whose dither value has rank r.
    let mut position_of_rank = [0u32; MAX_BLOCK_PIXELS];
    for j in 0..n {
        let dj = dither[j];
        let mut rank = 0usize;
        for i in 0..n {
            let di = dither[i];
            if di < dj || (di == dj && i < j) {
                rank += 1;
            }
        }
        position_of_rank[rank] = j as u32;
    }
    for i in 0..n {
        let ki = keys[i];
        let mut rank = 0usize;
        for j in 0..n {
            let kj = keys[j];
            if kj < ki || (kj == ki && j < i) {
                rank += 1;
            }
        }
        out[position_of_rank[rank] as usize] = seeds[i];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn key_order_is_total_and_documented() {
        let ordered = [
            f32::from_bits(0xFFC0_0000), // -NaN
            f32::NEG_INFINITY,
            -1.0,
            -f32::MIN_POSITIVE,
            -0.0,
            0.0,
            f32::MIN_POSITIVE,
            1.0,
            f32::INFINITY,
            f32::NAN,
        ];
        for w in ordered.windows(2) {
            assert!(intensity_key(w[0]) < intensity_key(w[1]), "{:?}", w);
        }
    }

    #[test]
    fn paper_oracle_2x2() {
        let mut keys = [0; MAX_BLOCK_PIXELS];
        let mut dither = [0; MAX_BLOCK_PIXELS];
        let mut seeds = [0; MAX_BLOCK_PIXELS];
        for (i, (v, d)) in [(0.9f32, 0.2f32), (0.1, 0.8), (0.5, 0.6), (0.3, 0.4)]
            .iter()
            .enumerate()
        {
            keys[i] = intensity_key(*v);
            dither[i] = intensity_key(*d);
            seeds[i] = 100 + i as u32;
        }
        let mut out = [0; MAX_BLOCK_PIXELS];
        sort_block(4, &keys, &dither, &seeds, &mut out);
        assert_eq!(out[..4], [101, 100, 102, 103]);
    }
}
