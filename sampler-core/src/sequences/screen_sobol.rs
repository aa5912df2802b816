//! An a-priori screen-space blue-noise sampler: Owen-scrambled Sobol with
//! optimised per-pixel keys, in the style of Heitz, Belcour, Ostromoukhov,
//! Coeurjolly & Iehl (2019, "A low-discrepancy sampler that distributes
//! Monte Carlo errors as a blue noise in screen space"; our implementation,
//! keys and optimiser).
//!
//! # Sampling
//!
//! Dimensions come in pairs: dimension `d` is coordinate `d % 2` of pair
//! `d / 2`. A pixel's pair reads one `u32` **key** `k` from a key tile
//! (toroidally repeated over the screen) and takes its samples
//! ([`key_sample_u32`]):
//!
//! 1. **ranking key** `r = k >> 24` XORed into the sample index:
//!    `i' = i ^ r` (at `2^L` spp the first `2^L` indices map onto one aligned
//!    block of `2^L` indices, so the pixel still gets a whole net);
//! 2. the index is shuffled by a nested scramble seeded by the key
//!    ([`shuffle_index`], maps aligned blocks onto aligned blocks), which
//!    decorrelates the pairs of one pixel (padding);
//! 3. **scrambling key**: Sobol dimensions 0 and 1 at that index,
//!    Owen-scrambled with a seed derived from `k` ([`owen_sobol_u32`](crate::sequences::owen::owen_sobol_u32)).
//!
//! Each pixel alone therefore gets an Owen-scrambled (0, 2)-sequence: as good
//! per pixel as random per-pixel scrambling. Which key sits at which pixel is
//! what the offline optimiser (`bake::bake_sampler_keys`, feature `bake`)
//! decides: it swaps keys between pixels so that neighbouring pixels' errors
//! on random Heaviside integrands are anticorrelated (blue-noise error).
//!
//! # Key layout
//!
//! `levels x pairs x side x side` keys, level-major, then pair, then
//! row-major ([`ScreenSobolLayout::key_index`]). Level `j` was optimised for
//! exactly `2^j` samples per pixel; with `spp` samples the sampler reads
//! level `ceil(log2 spp)`, clamped to the last one. Pairs beyond
//! `layout.pairs` reuse the keys of pair `d / 2 % pairs` rehashed with the
//! pair number: valid, independent samples, but not optimised.
//!
//! Shader-callable: [`screen_sobol_sample_u32`] takes the keys as a `&[u32]`
//! (a storage buffer) and a `#[repr(C)]` [`ScreenSobolLayout`]; `u32`
//! arithmetic only. [`ScreenSobolKeys`] validates the pair on the host.

use crate::error::{Buffer, Error};
use crate::sequences::owen::{owen_sobol_pair_u32, shuffle_index};
use crate::sequences::seed::hash_u32;
use glam::UVec2;

pub use crate::limits::{MAX_KEY_LEVELS, MAX_KEY_TILE};

/// Layout of a key buffer (shared with shaders; 16 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ScreenSobolLayout {
    /// `log2` of the tile side in pixels.
    pub side_log2: u32,
    /// Number of optimised dimension pairs (at least 1).
    pub pairs: u32,
    /// Number of spp levels (level `j` for `2^j` spp), `1..=MAX_KEY_LEVELS`.
    pub levels: u32,
    /// Padding to 16 bytes; always 0.
    pub pad: u32,
}

const _: () = assert!(core::mem::size_of::<ScreenSobolLayout>() == 16);

impl ScreenSobolLayout {
    /// A layout of `levels x pairs` tiles of `side x side` keys.
    ///
    /// # Errors
    /// [`Error::KeyLayout`] if `side` is not a power of two in
    /// `1..=MAX_KEY_TILE`, `pairs` is 0, or `levels` is outside
    /// `1..=MAX_KEY_LEVELS`.
    pub fn new(side: u32, pairs: u32, levels: u32) -> Result<Self, Error> {
        if !side.is_power_of_two()
            || side > MAX_KEY_TILE
            || pairs == 0
            || pairs > 1 << 16
            || levels == 0
            || levels > MAX_KEY_LEVELS
        {
            return Err(Error::KeyLayout { side, pairs, levels });
        }
        Ok(ScreenSobolLayout {
            side_log2: side.trailing_zeros(),
            pairs,
            levels,
            pad: 0,
        })
    }

    /// Tile side in pixels.
    pub fn side(&self) -> u32 {
        1 << self.side_log2
    }

    /// Number of keys the layout addresses.
    pub fn key_count(&self) -> usize {
        self.levels as usize * self.pairs as usize * (1usize << (2 * self.side_log2))
    }

    /// The level read with `spp` samples per pixel: `ceil(log2 spp)`,
    /// clamped to `0..levels` (`spp = 0` reads level 0).
    #[inline]
    pub fn level_of_spp(&self, spp: u32) -> u32 {
        let mut level = 0u32;
        while level + 1 < self.levels && (1u32 << level) < spp {
            level += 1;
        }
        level
    }

    /// Index in the key buffer of the key of `pixel` (taken modulo the
    /// side), `level` and `pair` (both must be in range).
    #[inline]
    pub fn key_index(&self, pixel: UVec2, level: u32, pair: u32) -> u32 {
        let mask = (1u32 << self.side_log2).wrapping_sub(1);
        let texel = ((pixel.y & mask) << self.side_log2) | (pixel.x & mask);
        ((level * self.pairs + pair) << (2 * self.side_log2)) | texel
    }
}

/// Sample `index` of a pixel's dimension pair `pair` whose key is `key`:
/// both coordinates in 0.32 fixed point. The key's first `2^L` samples form
/// an Owen-scrambled (0, L, 2)-net.
#[inline]
pub fn key_sample_u32(key: u32, pair: u32, index: u32) -> [u32; 2] {
    let rank = key >> 24;
    let shuffled = shuffle_index(index ^ rank, hash_u32(key ^ hash_u32(pair ^ 0x7F4A_7C15)));
    owen_sobol_pair_u32(shuffled, key)
}

/// Pair `pair` (dimensions `2 pair` and `2 pair + 1`) of sample
/// `sample_index` of `pixel`, both in 0.32 fixed point, when rendering `spp`
/// samples per pixel. `keys` and `layout` must have been validated together
/// ([`ScreenSobolKeys::new`]); an index past the end of `keys` reads key 0
/// instead of panicking. Pairs `>= layout.pairs` rehash the key of pair
/// `pair % layout.pairs` with `pair` (valid, not optimised).
#[inline]
pub fn screen_sobol_pair_u32(
    keys: &[u32],
    layout: ScreenSobolLayout,
    spp: u32,
    pixel: UVec2,
    sample_index: u32,
    pair: u32,
) -> [u32; 2] {
    let level = layout.level_of_spp(spp);
    let stored_pair = pair % layout.pairs;
    let i = layout.key_index(pixel, level, stored_pair) as usize;
    let mut key = if i < keys.len() { keys[i] } else { 0 };
    if pair >= layout.pairs {
        key = hash_u32(key ^ hash_u32(pair));
    }
    key_sample_u32(key, pair, sample_index)
}

/// Dimension `dimension` of sample `sample_index` of `pixel`, in 0.32 fixed
/// point: coordinate `dimension % 2` of [`screen_sobol_pair_u32`]'s pair
/// `dimension / 2`.
#[inline]
pub fn screen_sobol_sample_u32(
    keys: &[u32],
    layout: ScreenSobolLayout,
    spp: u32,
    pixel: UVec2,
    sample_index: u32,
    dimension: u32,
) -> u32 {
    screen_sobol_pair_u32(keys, layout, spp, pixel, sample_index, dimension / 2)[(dimension & 1) as usize]
}

/// [`screen_sobol_sample_u32`] in `[0, 1)` (24 bits).
#[inline]
pub fn screen_sobol_sample(
    keys: &[u32],
    layout: ScreenSobolLayout,
    spp: u32,
    pixel: UVec2,
    sample_index: u32,
    dimension: u32,
) -> f32 {
    crate::sequences::r2::q32_to_f32(screen_sobol_sample_u32(
        keys,
        layout,
        spp,
        pixel,
        sample_index,
        dimension,
    ))
}

/// A validated key buffer and its layout (host side).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ScreenSobolKeys<'a> {
    layout: ScreenSobolLayout,
    keys: &'a [u32],
}

impl<'a> ScreenSobolKeys<'a> {
    /// Wraps `keys` laid out as `layout`.
    ///
    /// # Errors
    /// [`Error::BufferSize`] if `keys.len() != layout.key_count()`.
    pub fn new(layout: ScreenSobolLayout, keys: &'a [u32]) -> Result<Self, Error> {
        if keys.len() != layout.key_count() {
            return Err(Error::BufferSize {
                buffer: Buffer::SampleKeys,
                expected: layout.key_count(),
                actual: keys.len(),
            });
        }
        Ok(ScreenSobolKeys { layout, keys })
    }

    /// The layout.
    pub fn layout(&self) -> ScreenSobolLayout {
        self.layout
    }

    /// The keys.
    pub fn keys(&self) -> &'a [u32] {
        self.keys
    }

    /// Dimension `dimension` of sample `sample_index` of `pixel` at `spp`
    /// samples per pixel, in `[0, 1)`; identical to [`screen_sobol_sample`].
    ///
    /// # Example
    ///
    /// ```
    /// use sampler_core::defaults;
    /// use glam::UVec2;
    /// let keys = defaults::screen_sobol_keys();
    /// // Pair 0 (dimensions 0, 1: the position in the pixel) of sample 0 at 1 spp.
    /// let (x, y) = (keys.sample(UVec2::new(3, 4), 0, 0, 1), keys.sample(UVec2::new(3, 4), 0, 1, 1));
    /// assert!((0.0..1.0).contains(&x) && (0.0..1.0).contains(&y));
    /// // Across a 64x64 tile of pixels the values are evenly spread (blue noise).
    /// let mean: f32 = (0..64 * 64).map(|i| keys.sample(UVec2::new(i % 64, i / 64), 0, 0, 1)).sum::<f32>() / 4096.0;
    /// assert!((mean - 0.5).abs() < 0.01);
    /// ```
    #[inline]
    pub fn sample(&self, pixel: UVec2, sample_index: u32, dimension: u32, spp: u32) -> f32 {
        screen_sobol_sample(self.keys, self.layout, spp, pixel, sample_index, dimension)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sequences::sobol::tests::is_02_net;

    #[test]
    fn layouts_are_validated() {
        assert!(ScreenSobolLayout::new(64, 4, 5).is_ok());
        for (s, p, l) in [
            (0, 1, 1),
            (48, 1, 1),
            (2048, 1, 1),
            (4, 0, 1),
            (4, 1, 0),
            (4, 1, 10),
        ] {
            assert_eq!(
                ScreenSobolLayout::new(s, p, l),
                Err(Error::KeyLayout {
                    side: s,
                    pairs: p,
                    levels: l
                })
            );
        }
        let layout = ScreenSobolLayout::new(4, 2, 3).unwrap();
        assert_eq!(layout.key_count(), 96);
        let keys = [0u32; 95];
        assert!(matches!(
            ScreenSobolKeys::new(layout, &keys),
            Err(Error::BufferSize {
                expected: 96,
                actual: 95,
                ..
            })
        ));
    }

    #[test]
    fn levels_follow_ceil_log2_spp() {
        let layout = ScreenSobolLayout::new(4, 1, 5).unwrap();
        let got: [u32; 10] =
            core::array::from_fn(|i| layout.level_of_spp([0, 1, 2, 3, 4, 5, 8, 9, 16, 1000][i]));
        assert_eq!(got, [0, 0, 1, 2, 2, 3, 3, 4, 4, 4]);
    }

    #[test]
    fn key_index_is_a_bijection() {
        let layout = ScreenSobolLayout::new(8, 3, 2).unwrap();
        let mut seen = [false; 384];
        for level in 0..2 {
            for pair in 0..3 {
                for y in 0..8 {
                    for x in 0..8 {
                        let i = layout.key_index(UVec2::new(x + 16, y + 8), level, pair) as usize;
                        assert!(!core::mem::replace(&mut seen[i], true));
                    }
                }
            }
        }
    }

    #[test]
    fn every_key_gives_a_net_at_every_power_of_two() {
        for t in 0..200u32 {
            let key = hash_u32(t);
            for pair in [0u32, 1, 5] {
                for m in 0..=8u32 {
                    let pts: [[u32; 2]; 256] = core::array::from_fn(|i| key_sample_u32(key, pair, i as u32));
                    assert!(is_02_net(&pts[..1 << m]), "key {key:#x} pair {pair} m {m}");
                }
            }
        }
    }

    #[test]
    fn samples_are_in_unit_interval_and_pairs_beyond_the_table_work() {
        let layout = ScreenSobolLayout::new(4, 2, 2).unwrap();
        let keys: [u32; 64] = core::array::from_fn(|i| hash_u32(i as u32));
        let k = ScreenSobolKeys::new(layout, &keys).unwrap();
        for d in 0..12 {
            for s in 0..4 {
                let v = k.sample(UVec2::new(3, 9), s, d, 4);
                assert!((0.0..1.0).contains(&v));
            }
        }
        // Pair 2 is not pair 0 even though it reads pair 0's key.
        let a: [f32; 4] = core::array::from_fn(|s| k.sample(UVec2::new(1, 1), s as u32, 0, 4));
        let b: [f32; 4] = core::array::from_fn(|s| k.sample(UVec2::new(1, 1), s as u32, 4, 4));
        assert_ne!(a, b);
    }
}
