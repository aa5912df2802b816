//! A table-free screen-space sampler: Morton-ordered pixels sharing one
//! Owen-scrambled Sobol sequence, with hashed base-4 digit permutations
//! (the idea of Ahmed & Wonka 2020, "Screen-space blue-noise diffusion of
//! Monte Carlo sampling error via hierarchical ordering of pixels", used by
//! pbrt-v4's `ZSobolSampler`; our own implementation).
//!
//! # Idea
//!
//! Number the pixels along the Morton (Z) curve and give pixel `p` with
//! `2^L` samples per pixel the global sample indices
//! `morton(p) * 2^L + s`, `s < 2^L`. All pixels draw from **one**
//! Owen-scrambled Sobol sequence, so the `4^j` pixels of any aligned
//! `2^j x 2^j` square of the Morton curve together own an aligned block of
//! `4^j * 2^L` consecutive indices: a (0, m, 2)-net. Their samples are
//! jointly stratified, so neighbouring pixels' errors cancel (anticorrelate)
//! and the error image is blue noise.
//!
//! Plain Morton order would give every square the same structure (which
//! quadrant gets which sub-block), a visible pattern. So each base-4 digit
//! of the index (two bits: which quadrant, from the coarsest level down) is
//! passed through one of the 24 permutations of `{0, 1, 2, 3}`, chosen by a
//! hash of the digits above it, the dimension pair and the seed. A digit's
//! permutation depends only on higher digits, so the map is a bijection that
//! keeps aligned blocks (a nested base-4 scramble of the index) and the joint
//! stratification survives. When `2 * 12 + L` is odd the last digit is a
//! single bit, flipped by a hashed coin.
//!
//! **One sample per pixel.** There an edge crossing the screen (a
//! silhouette, a shadow boundary) puts its error on a line of pixels one
//! pixel wide, and a 2D net seen through a line is barely stratified. So at
//! `L = 0` the low [`PLACED_LEVELS`] digits are placed by a fixed linear map
//! (`placed_digits`) instead of hashed: in every aligned `2^K x 2^K`
//! square, `K <= 6`, each row has its `2^K` `y` coordinates in `2^K`
//! different intervals of length `2^-K`, and each column its `x`
//! coordinates (1D stratification along rows and columns, at every scale up
//! to 64 pixels). Aligned squares are still nets, the map is still a
//! bijection, and a hashed constant per 64x64 square and seed varies the
//! pattern.
//!
//! # Frames
//!
//! A renderer calls [`zsobol_frame_sample_u32`] with the frame number: each
//! frame is the same ZSobol point set XORed with point `frame` of a 2D
//! (0, 2)-sequence (a digital shift), so each frame keeps the properties
//! above and a pixel's points over frames continue a progressive sequence
//! (blue in time: its running mean converges faster than independent
//! frames'). [`zsobol_sample_u32`] with a seed per frame gives independent
//! frames instead (white in time).
//!
//! # Sizes
//!
//! The index is a `u32` (shader rule: no `u64`): pixels are taken modulo a
//! [`ZSOBOL_TILE`] x [`ZSOBOL_TILE`] tile (12 Morton levels, 24 bits) and at
//! most `2^8` samples per pixel ([`ZSOBOL_MAX_LOG2_SPP`]); `sample_index` is
//! taken modulo `2^log2_spp`. Dimension `d` reads Sobol dimension `d % 2`
//! of pair `d / 2`; each pair has its own digit permutations and Owen
//! scramble (padding), so pairs are independent.
//!
//! Shader-callable: `u32` arithmetic, fixed-size arrays, no tables.

use crate::sequences::owen::{owen_sobol_pair_u32, owen_sobol_u32, shuffle_index};
use crate::sequences::seed::hash_u32;

/// Morton levels of the pixel part of the index: pixels wrap every
/// `2^ZSOBOL_LEVELS` in x and y.
pub const ZSOBOL_LEVELS: u32 = 12;
/// Side of the pixel tile: 4096 (`2^ZSOBOL_LEVELS`).
pub const ZSOBOL_TILE: u32 = 1 << ZSOBOL_LEVELS;
/// Largest supported `log2(samples per pixel)`: 8 (256 spp), so the index
/// `2 * 12 + 8 = 32` bits fits a `u32`. Larger values are clamped.
pub const ZSOBOL_MAX_LOG2_SPP: u32 = 8;

/// Interleaves the low 16 bits of `x` (even bits) and `y` (odd bits).
#[inline]
pub fn morton_encode(x: u32, y: u32) -> u32 {
    spread_bits(x) | (spread_bits(y) << 1)
}

/// Moves bit `i` of the low 16 bits of `v` to bit `2 i`.
#[inline]
fn spread_bits(v: u32) -> u32 {
    let mut v = v & 0xFFFF;
    v = (v | (v << 8)) & 0x00FF_00FF;
    v = (v | (v << 4)) & 0x0F0F_0F0F;
    v = (v | (v << 2)) & 0x3333_3333;
    (v | (v << 1)) & 0x5555_5555
}

/// Applies permutation number `p` (`0..24`, Lehmer code) of `{0, 1, 2, 3}`
/// to `digit` (`0..4`).
///
/// The remaining items live packed in one `u32`, two bits each, not in an
/// array: GPUs keep small arrays indexed at run time in scratch memory, and
/// this runs once per index digit of every ZSobol pair.
#[inline]
pub fn permute_digit(digit: u32, p: u32) -> u32 {
    // Lehmer code: position 0 takes the (p / 6)-th remaining item, position 1
    // the ((p % 6) / 2)-th, position 2 the (p % 2)-th, position 3 the last.
    let mut items = 0b11_10_01_00u32; // item k at bits 2k..2k+2
    let mut out = 0u32;
    let mut j = 0u32;
    while j <= digit && j < 4 {
        let c = match j {
            0 => p / 6,
            1 => (p % 6) / 2,
            2 => p % 2,
            _ => 0,
        };
        out = (items >> (2 * c)) & 3;
        // Remove item c: keep the items below it, shift those above it down.
        let below = items & ((1u32 << (2 * c)) - 1);
        items = below | ((items >> (2 * c + 2)) << (2 * c));
        j += 1;
    }
    out
}

/// Pixel levels whose index digits are placed rather than hashed at one
/// sample per pixel: aligned 64x64 squares (module docs).
pub const PLACED_LEVELS: u32 = 6;

/// Rows of the placement map: index bit `k` (`k < 2 PLACED_LEVELS`) is the
/// parity of `ZSOBOL_PLACEMENT[k] & v`, where `v` is the pixel's Morton code inside
/// its aligned 64x64 square (bit `2i` is `x_i`, bit `2i + 1` is `y_i`).
///
/// Found by a search over GF(2): digit `j` depends only on pixel levels
/// `>= j` and its own level enters invertibly (so aligned squares still own
/// aligned index blocks: nets, and the map is a bijection); and for every
/// `K <= 6` the first `K` bits of the Sobol point's `x` coordinate (index
/// bits `0..K`, dimension 0 reverses them) are a bijective function of the
/// `K` low bits of `y` (every aligned column segment of `2^K` pixels has its
/// `x` coordinates in `2^K` different intervals of `2^-K`), and the first
/// `K` bits of `y` (bit `k` of dimension 1 is the parity of the index bits
/// `j` with `binomial(j, k)` odd) a bijective function of the `K` low bits
/// of `x` (the same along rows). Owen scrambling is a bijection on every
/// prefix, so the property survives it.
///
/// Among the maps with these properties (about 1 in 2000 random
/// block-triangular ones), this one gives the smallest blurred error on
/// straight edges: a step `1[u < c]` along a row (`y`) or column (`x`) of
/// 64 pixels, `c` uniform, Owen-scrambled, blurred by a Gaussian of sigma 1
/// pixel reaches 0.568 of white noise's both ways (a golden-ratio sequence
/// along the line: 0.571); the first map found reached 0.621 along rows.
/// Consecutive pixels of a line then fall in far-apart intervals, not only
/// different ones. `bake zsobol-placement` (`bake::search_placement`,
/// feature `bake`) repeats the search.
pub const ZSOBOL_PLACEMENT: [u32; 12] = [
    0x553, 0x45e, 0x5f4, 0x188, 0xe60, 0x330, 0x5c0, 0x140, 0x700, 0x500, 0xc00, 0x800,
];

/// The low `2 PLACED_LEVELS` bits of the index at one sample per pixel:
/// [`ZSOBOL_PLACEMENT`] applied to the pixel's Morton code (`index`'s low bits),
/// XORed with a hash of the already permuted higher bits (`high`), which
/// changes the pattern from square to square and from seed to seed without
/// touching the stratification (a constant per square).
#[inline]
fn placed_digits(index: u32, high: u32, salt: u32) -> u32 {
    let bits = 2 * PLACED_LEVELS;
    let mask = (1u32 << bits) - 1;
    apply_placement(&ZSOBOL_PLACEMENT, index & mask)
        ^ (hash_u32((high >> bits) ^ hash_u32(salt ^ 0x5EED_1E55)) & mask)
}

/// A placement map applied to the Morton code `v` of a pixel inside its
/// aligned 64x64 square: bit `k` of the result is the parity of
/// `map[k] & v` (see [`ZSOBOL_PLACEMENT`]).
///
/// Written out bit by bit (no loop over the map): with constant indices the
/// map's rows fold into the shader's code instead of an array read at run time.
#[inline]
pub fn apply_placement(map: &[u32; 12], v: u32) -> u32 {
    let bit = |k: usize| ((map[k] & v).count_ones() & 1) << k;
    bit(0)
        | bit(1)
        | bit(2)
        | bit(3)
        | bit(4)
        | bit(5)
        | bit(6)
        | bit(7)
        | bit(8)
        | bit(9)
        | bit(10)
        | bit(11)
}

/// The permuted global Sobol index of sample `sample_index` of `pixel` for
/// dimension pair `pair`, with `2^log2_spp` samples per pixel. A bijection
/// from (pixel in the tile, sample) onto `0..2^(24 + log2_spp)`.
#[inline]
pub fn zsobol_index(pixel: glam::UVec2, sample_index: u32, log2_spp: u32, pair: u32, seed: u32) -> u32 {
    let l = if log2_spp > ZSOBOL_MAX_LOG2_SPP {
        ZSOBOL_MAX_LOG2_SPP
    } else {
        log2_spp
    };
    let mask = ZSOBOL_TILE - 1;
    let morton = morton_encode(pixel.x & mask, pixel.y & mask);
    let s = if l == 0 {
        0
    } else {
        sample_index & ((1u32 << l) - 1)
    };
    let index = if l == 0 { morton } else { (morton << l) | s };
    let bits = 2 * ZSOBOL_LEVELS + l;
    let salt = hash_u32(seed ^ hash_u32(pair.wrapping_mul(0x9E37_79B9).wrapping_add(0x632B_E5AB)));
    let odd = bits & 1;
    let digits = bits / 2;
    // One sample per pixel: the low digits are placed below, not hashed.
    let hashed = if l == 0 { digits - PLACED_LEVELS } else { digits };
    let mut out = 0u32;
    let mut i = 0u32;
    while i < hashed {
        // Digit i from the top sits at bit `shift`.
        let shift = bits - 2 * (i + 1);
        let digit = (index >> shift) & 3;
        let higher = if shift + 2 >= 32 { 0 } else { index >> (shift + 2) };
        let h = hash_u32(higher ^ hash_u32(salt.wrapping_add(shift)));
        let p = ((h >> 16) * 24) >> 16;
        out |= permute_digit(digit, p) << shift;
        i += 1;
    }
    if l == 0 {
        out |= placed_digits(index, out, salt);
    }
    if odd == 1 {
        let h = hash_u32((index >> 1) ^ hash_u32(salt.wrapping_add(0xFFFF)));
        out |= (index & 1) ^ (h & 1);
    }
    out
}

/// Dimension `dimension` of sample `sample_index` of `pixel`, in 0.32 fixed
/// point, with `2^log2_spp` samples per pixel; `seed` selects an independent
/// randomisation (e.g. per frame).
#[inline]
pub fn zsobol_sample_u32(
    pixel: glam::UVec2,
    sample_index: u32,
    dimension: u32,
    log2_spp: u32,
    seed: u32,
) -> u32 {
    let pair = dimension / 2;
    let index = zsobol_index(pixel, sample_index, log2_spp, pair, seed);
    owen_sobol_u32(index, dimension & 1, pair_scramble_seed(seed, pair))
}

/// The seed of pair `pair`'s Owen scramble under `seed`: one global scramble
/// per pair, shared by all pixels.
#[inline]
fn pair_scramble_seed(seed: u32, pair: u32) -> u32 {
    hash_u32(seed ^ hash_u32(pair.wrapping_add(0x2545_F491)))
}

/// [`zsobol_sample_u32`] in `[0, 1)` (24 bits).
///
/// # Example
///
/// Four samples per pixel, dimension pair 0 (e.g. the position in the pixel):
///
/// ```
/// use sampler_core::zsobol_sample;
/// use glam::UVec2;
/// let pixel = UVec2::new(10, 7);
/// let xs: Vec<f32> = (0..4).map(|s| zsobol_sample(pixel, s, 0, 2, 1234)).collect();
/// // Stratified: one sample in each quarter of [0, 1).
/// let mut quarters: Vec<u32> = xs.iter().map(|x| (x * 4.0) as u32).collect();
/// quarters.sort();
/// assert_eq!(quarters, [0, 1, 2, 3]);
/// ```
#[inline]
pub fn zsobol_sample(pixel: glam::UVec2, sample_index: u32, dimension: u32, log2_spp: u32, seed: u32) -> f32 {
    crate::sequences::r2::q32_to_f32(zsobol_sample_u32(pixel, sample_index, dimension, log2_spp, seed))
}

/// Seed of the fixed randomisation of [`zsobol_frame_sample_u32`] (any
/// constant; the frames differ by their digital shifts, not their seeds).
pub const ZSOBOL_FRAME_SEED: u32 = 0x2F0B_5E7D;

/// The digital shift of frame `frame` for dimension pair `pair`: point
/// `frame` of a 2D Owen-scrambled Sobol (0, 2)-sequence, each pair with its
/// own index shuffle and scramble (so pairs are independent), shared by
/// every pixel; both coordinates in 0.32 fixed point.
#[inline]
pub fn zsobol_frame_shift_u32(frame: u32, pair: u32) -> [u32; 2] {
    let seed = hash_u32(ZSOBOL_FRAME_SEED ^ hash_u32(pair.wrapping_add(0x7F4A_7C15)));
    owen_sobol_pair_u32(shuffle_index(frame, seed), seed)
}

/// Dimension `dimension` of sample `sample_index` of `pixel` in frame
/// `frame`, progressive across frames; 0.32 fixed point, `2^log2_spp`
/// samples per pixel.
///
/// Every frame is the same ZSobol point set ([`zsobol_sample_u32`] with seed
/// [`ZSOBOL_FRAME_SEED`]) XORed with the frame's shift
/// ([`zsobol_frame_shift_u32`]). A digital shift maps every elementary
/// interval onto an elementary interval of the same shape, so:
/// - **in space** each frame keeps everything ZSobol guarantees (aligned
///   squares are nets, rows and columns stratified at one sample per pixel);
/// - **in time** a pixel's points over frames `0..2^m` are its fixed point
///   XORed with the first `2^m` points of a (0, 2)-sequence: a (0, m, 2)-net
///   (at one sample per pixel), so its running mean converges like the
///   sequence, not like independent frames.
///
/// Independent randomisations per frame (seed = frame, the sampler's first
/// form) make every frame as good in space but a pixel's frames independent
/// (white in time), and every pixel shares each frame's randomisation, so a
/// region's accumulated error is one draw of how lucky the frames were.
#[inline]
pub fn zsobol_frame_sample_u32(
    pixel: glam::UVec2,
    sample_index: u32,
    dimension: u32,
    log2_spp: u32,
    frame: u32,
) -> u32 {
    let point = zsobol_sample_u32(pixel, sample_index, dimension, log2_spp, ZSOBOL_FRAME_SEED);
    let shift = zsobol_frame_shift_u32(frame, dimension / 2);
    point ^ shift[(dimension & 1) as usize]
}

/// Dimensions `2 pair` and `2 pair + 1` of [`zsobol_frame_sample_u32`]
/// together, computing the pixel's index and the frame's shift once (what a
/// renderer wants: its decisions are 2D pairs).
#[inline]
pub fn zsobol_frame_pair_u32(
    pixel: glam::UVec2,
    sample_index: u32,
    pair: u32,
    log2_spp: u32,
    frame: u32,
) -> [u32; 2] {
    let index = zsobol_index(pixel, sample_index, log2_spp, pair, ZSOBOL_FRAME_SEED);
    let point = owen_sobol_pair_u32(index, pair_scramble_seed(ZSOBOL_FRAME_SEED, pair));
    let shift = zsobol_frame_shift_u32(frame, pair);
    [point[0] ^ shift[0], point[1] ^ shift[1]]
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::sequences::sobol::tests::is_02_net;
    use glam::UVec2;

    #[test]
    fn packed_digit_permutation_equals_the_array_form() {
        // The first form, with the items in an array (Lehmer code).
        fn array_form(digit: u32, p: u32) -> u32 {
            let codes = [p / 6, (p % 6) / 2, p % 2, 0];
            let mut items = std::vec![0u32, 1, 2, 3];
            let mut out = 0;
            for &c in codes.iter().take(digit as usize + 1) {
                out = items.remove(c as usize);
            }
            out
        }
        for p in 0..24 {
            for digit in 0..4 {
                assert_eq!(
                    permute_digit(digit, p),
                    array_form(digit, p),
                    "digit {digit}, permutation {p}"
                );
            }
        }
    }

    #[test]
    fn digit_permutations_are_the_24_permutations() {
        let mut all = [[0u32; 4]; 24];
        for (p, perm) in all.iter_mut().enumerate() {
            for (d, slot) in perm.iter_mut().enumerate() {
                *slot = permute_digit(d as u32, p as u32);
            }
            let mut sorted = *perm;
            sorted.sort_unstable();
            assert_eq!(sorted, [0, 1, 2, 3], "permutation {p}");
        }
        let mut distinct = all;
        distinct.sort_unstable();
        assert!(distinct.windows(2).all(|w| w[0] != w[1]));
    }

    #[test]
    fn morton_interleaves() {
        assert_eq!(morton_encode(0, 0), 0);
        assert_eq!(morton_encode(1, 0), 1);
        assert_eq!(morton_encode(0, 1), 2);
        assert_eq!(morton_encode(3, 3), 15);
        assert_eq!(morton_encode(0xFFFF, 0), 0x5555_5555);
    }

    /// Every (pixel, sample) of an odd-sized 16x9 image gets its own index,
    /// for even and odd log2 spp (pbrt tests ZSobol on 16x9 too).
    #[test]
    fn index_is_injective_on_odd_sizes() {
        for l in [0u32, 1, 2, 3, 8] {
            let spp = 1u32 << l;
            let mut v = std::vec::Vec::new();
            for y in 0..9 {
                for x in 0..16 {
                    for s in 0..spp {
                        v.push(zsobol_index(UVec2::new(x, y), s, l, 3, 42));
                    }
                }
            }
            let n = v.len();
            v.sort_unstable();
            v.dedup();
            assert_eq!(v.len(), n, "log2 spp {l}");
        }
    }

    /// An aligned 2^j x 2^j square of pixels with 2^l samples each owns an
    /// aligned block of indices, so its samples form a (0, m, 2)-net.
    #[test]
    fn aligned_squares_form_nets() {
        for (l, j) in [(0u32, 1u32), (0, 2), (1, 1), (2, 1), (2, 2), (3, 2), (0, 4)] {
            let side = 1u32 << j;
            for (ox, oy) in [(0u32, 0u32), (side * 3, side * 5)] {
                let mut pts = std::vec::Vec::new();
                for y in 0..side {
                    for x in 0..side {
                        for s in 0..(1u32 << l) {
                            let p = UVec2::new(ox + x, oy + y);
                            pts.push([zsobol_sample_u32(p, s, 0, l, 9), zsobol_sample_u32(p, s, 1, l, 9)]);
                        }
                    }
                }
                assert!(pts.len() <= 256);
                assert!(is_02_net(&pts), "l {l} j {j}");
            }
        }
    }

    /// At one sample per pixel, in every aligned `2^K x 2^K` square
    /// (`K <= PLACED_LEVELS`), the `y` coordinates of a row fall in `2^K`
    /// different intervals of length `2^-K`, and so do the `x` coordinates
    /// of a column.
    #[test]
    fn one_spp_rows_and_columns_are_stratified_at_every_scale() {
        for seed in [1u32, 77] {
            for pair in [0u32, 3] {
                for k in 1..=PLACED_LEVELS {
                    let side = 1u32 << k;
                    let prefix = |x: u32, y: u32, dim: u32| {
                        zsobol_sample_u32(UVec2::new(x, y), 0, 2 * pair + dim, 0, seed) >> (32 - k)
                    };
                    for (sx, sy) in [(0u32, 0u32), (1, 2), (5, 3)] {
                        for t in (0..side).step_by(((side / 8).max(1)) as usize) {
                            let (x0, y0) = (sx * side, sy * side);
                            let mut row: std::vec::Vec<u32> =
                                (0..side).map(|i| prefix(x0 + i, y0 + t, 1)).collect();
                            let mut col: std::vec::Vec<u32> =
                                (0..side).map(|i| prefix(x0 + t, y0 + i, 0)).collect();
                            row.sort_unstable();
                            row.dedup();
                            col.sort_unstable();
                            col.dedup();
                            assert_eq!(
                                row.len() as u32,
                                side,
                                "row {t} of {side}-square ({sx}, {sy}), pair {pair}"
                            );
                            assert_eq!(
                                col.len() as u32,
                                side,
                                "column {t} of {side}-square ({sx}, {sy}), pair {pair}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn values_are_in_unit_interval() {
        for i in 0..2000u32 {
            let p = UVec2::new(hash_u32(i), hash_u32(i + 7));
            let v = zsobol_sample(p, i, i % 9, i % 10, i);
            assert!((0.0..1.0).contains(&v));
        }
    }

    /// Progressive frames: at one sample per pixel a pixel's points over
    /// frames `0..2^m` form a (0, m, 2)-net for every pair, and every frame's
    /// aligned squares are still nets.
    #[test]
    fn frames_are_nets_over_time_and_in_space() {
        for pair in [0u32, 1, 5] {
            for p in [UVec2::new(0, 0), UVec2::new(37, 211), UVec2::new(4095, 9)] {
                for m in [4u32, 6, 8] {
                    let pts: std::vec::Vec<[u32; 2]> = (0..1u32 << m)
                        .map(|t| {
                            [
                                zsobol_frame_sample_u32(p, 0, 2 * pair, 0, t),
                                zsobol_frame_sample_u32(p, 0, 2 * pair + 1, 0, t),
                            ]
                        })
                        .collect();
                    assert!(is_02_net(&pts), "pixel {p}, pair {pair}, 2^{m} frames");
                }
            }
            for frame in [0u32, 1, 77] {
                let mut pts = std::vec::Vec::new();
                for y in 0..16 {
                    for x in 0..16 {
                        let p = UVec2::new(32 + x, 48 + y);
                        pts.push([
                            zsobol_frame_sample_u32(p, 0, 2 * pair, 0, frame),
                            zsobol_frame_sample_u32(p, 0, 2 * pair + 1, 0, frame),
                        ]);
                    }
                }
                assert!(is_02_net(&pts), "frame {frame}, pair {pair}");
            }
        }
    }

    /// The pair form computes the same words as the per-dimension one.
    #[test]
    fn frame_pairs_equal_their_dimensions() {
        for i in 0..500u32 {
            let p = UVec2::new(hash_u32(i) % 5000, hash_u32(i + 3) % 5000);
            let (s, pair, l, frame) = (i % 7, i % 13, i % 10, hash_u32(i + 11) % 1000);
            assert_eq!(
                zsobol_frame_pair_u32(p, s, pair, l, frame),
                [
                    zsobol_frame_sample_u32(p, s, 2 * pair, l, frame),
                    zsobol_frame_sample_u32(p, s, 2 * pair + 1, l, frame)
                ]
            );
        }
    }

    /// Frame 0's shift is not zero for every pair (the sequence is
    /// scrambled), and pairs get different shifts.
    #[test]
    fn frame_shifts_differ_between_pairs() {
        let shifts: std::vec::Vec<[u32; 2]> = (0..8).map(|pair| zsobol_frame_shift_u32(3, pair)).collect();
        for (i, a) in shifts.iter().enumerate() {
            for b in &shifts[i + 1..] {
                assert_ne!(a, b);
            }
        }
    }
}
