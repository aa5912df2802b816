//! Owen scrambling (nested uniform scrambling in base 2) by hashing, and
//! Owen-scrambled Sobol points.
//!
//! # Owen scrambling
//!
//! Write `x` in `[0, 1)` as binary digits `0.x_1 x_2 x_3 ...`. An Owen
//! scramble flips digit `x_k` by a random bit that depends on the seed and on
//! the digits before it, `x_1..x_(k-1)`, and on nothing else: it swaps the
//! two halves of `[0, 1)`, then independently the halves of each half, and
//! so on (a random permutation of the binary tree of intervals). It maps
//! every elementary interval `[j / 2^k, (j + 1) / 2^k)` onto another one of
//! the same size, so it keeps every (t, m, s)-net a net, while each scrambled
//! point is uniform on `[0, 1)`.
//!
//! # The hash (suffix `_rev`)
//!
//! In 0.32 fixed point `x_1` is bit 31. After [`u32::reverse_bits`] it is
//! bit 0, and "depends only on earlier digits" becomes "bit `k` of the result
//! depends only on bits `0..=k` of the input": exactly the functions built
//! from integer addition, multiplication, and `x ^ (x * even)`, whose carries
//! only travel upwards. [`nested_scramble_rev`] composes such steps
//! (the idea of Laine & Karras 2011, "Stratified sampling for stochastic
//! transparency", refined by Burley 2020, "Practical hash-based Owen
//! scrambling"; our steps and constants are our own):
//!
//! 1. `x += s0`: flips bit 0 by `s0`'s bit 0 (the first digit's coin), and
//!    every higher bit by a seed bit plus the carry from below;
//! 2. `x ^= x * K`, `K` even: bit `k` is flipped by a function of bits `< k`;
//! 3. `x *= s1 | 1`: an odd, seed-dependent multiplier mixes lower bits
//!    upwards again (a bijection, bit 0 unchanged);
//! 4. two more `x ^= x * K` rounds, and a final seed add.
//!
//! Every step is a bijection on `u32`, so the whole map is one, and with the
//! reversal it is a permutation of the binary tree. `s0`, `s1` come from the
//! caller's seed through [`hash_u32`]. The even constants are the first
//! fractional bits of `sqrt(2)`, `sqrt(3)`, `sqrt(5)`, `sqrt(7)` (the SHA-2
//! initial values) with bit 0 cleared: arbitrary "nothing up my sleeve"
//! numbers; tests check the flip probabilities they give are close to 1/2.
//!
//! The same function scrambles a sample **index** ([`shuffle_index`]): there
//! bit `k` of the index is flipped depending only on the bits above it, so
//! every aligned block `[b 2^m, (b + 1) 2^m)` of indices maps onto an
//! aligned block of the same size. A Sobol sequence whose index is shuffled
//! this way still delivers a net in every such block (Burley 2020), and
//! independently shuffled dimension pairs decorrelate ("padding").
//!
//! Shader-callable: `u32` arithmetic with `wrapping_*`, no tables.

use crate::sequences::seed::hash_u32;
use crate::sequences::sobol::{sobol_pair_u32, sobol_u32};

/// `floor(frac(sqrt(2)) * 2^32)` with bit 0 cleared.
const K0: u32 = 0x6A09_E666;
/// `floor(frac(sqrt(3)) * 2^32)` with bit 0 cleared.
const K1: u32 = 0xBB67_AE84;
/// `floor(frac(sqrt(5)) * 2^32)` (already even).
const K2: u32 = 0x3C6E_F372;
/// `floor(frac(sqrt(7)) * 2^32)` (already even).
const K3: u32 = 0xA54F_F53A;

/// The nested scramble on **bit-reversed** input: bit `k` of the result
/// depends on bits `0..=k` of `x_rev` and on `seed` only; a bijection of
/// `u32` for every seed.
#[inline]
pub fn nested_scramble_rev(x_rev: u32, seed: u32) -> u32 {
    let s0 = hash_u32(seed);
    let s1 = hash_u32(s0 ^ K0);
    let mut x = x_rev.wrapping_add(s0);
    x ^= x.wrapping_mul(K0);
    x = x.wrapping_mul(s1 | 1);
    x ^= x.wrapping_mul(K1);
    x = x.wrapping_add(s1);
    x ^= x.wrapping_mul(K2);
    x ^= x.wrapping_mul(K3);
    x
}

/// Owen-scrambles `x_q32` (0.32 fixed point): digit `k` flips by a hash of
/// `seed` and digits `1..k`. Bijective; maps elementary intervals onto
/// elementary intervals of the same size.
#[inline]
pub fn owen_scramble(x_q32: u32, seed: u32) -> u32 {
    nested_scramble_rev(x_q32.reverse_bits(), seed).reverse_bits()
}

/// Shuffles a sample index: a bijection of `u32` that maps every aligned
/// block of `2^m` indices onto an aligned block of `2^m` indices (bit `k`
/// flips depending only on the bits above it). `seed` selects the shuffle.
#[inline]
pub fn shuffle_index(index: u32, seed: u32) -> u32 {
    owen_scramble(index, seed)
}

/// Seed of dimension `dimension` derived from a caller's `seed`, so every
/// dimension is scrambled independently.
#[inline]
pub fn dimension_seed(seed: u32, dimension: u32) -> u32 {
    hash_u32(seed ^ hash_u32(dimension.wrapping_add(0x5851_F42D)))
}

/// Owen-scrambled Sobol point `index` of `dimension` (taken modulo
/// [`SOBOL_DIMENSIONS`](crate::sequences::sobol::SOBOL_DIMENSIONS)), in 0.32 fixed
/// point; each dimension gets its own scramble derived from `seed`.
#[inline]
pub fn owen_sobol_u32(index: u32, dimension: u32, seed: u32) -> u32 {
    owen_scramble(sobol_u32(index, dimension), dimension_seed(seed, dimension))
}

/// Dimensions 0 and 1 of [`owen_sobol_u32`] together (`[owen_sobol_u32(index,
/// 0, seed), owen_sobol_u32(index, 1, seed)]`, tested), without the direction
/// table ([`sobol_pair_u32`]): the 2D Owen-scrambled Sobol (0, 2)-sequence.
#[inline]
pub fn owen_sobol_pair_u32(index: u32, seed: u32) -> [u32; 2] {
    let [x, y] = sobol_pair_u32(index);
    [
        owen_scramble(x, dimension_seed(seed, 0)),
        owen_scramble(y, dimension_seed(seed, 1)),
    ]
}

/// [`owen_sobol_u32`] in `[0, 1)` (24 bits).
#[inline]
pub fn owen_sobol(index: u32, dimension: u32, seed: u32) -> f32 {
    crate::sequences::r2::q32_to_f32(owen_sobol_u32(index, dimension, seed))
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_pair_form_equals_two_single_dimensions() {
        for (index, seed) in [
            (0u32, 0u32),
            (1, 7),
            (1000, 3),
            (0xDEAD_BEEF, 0x1234_5678),
            (u32::MAX, 9),
        ] {
            assert_eq!(
                owen_sobol_pair_u32(index, seed),
                [owen_sobol_u32(index, 0, seed), owen_sobol_u32(index, 1, seed)]
            );
        }
    }

    use super::*;
    use crate::sequences::sobol::tests::is_02_net;

    #[test]
    fn scramble_is_nested_bit_k_depends_on_lower_bits_only() {
        // Changing bit j of the reversed input never changes bits below j.
        for seed in 0..64u32 {
            for t in 0..64u32 {
                let x = hash_u32(t ^ (seed << 8));
                for j in 0..32 {
                    let a = nested_scramble_rev(x, seed);
                    let b = nested_scramble_rev(x ^ (1 << j), seed);
                    let low = if j == 0 { 0 } else { u32::MAX >> (32 - j) };
                    assert_eq!(a & low, b & low, "seed {seed} bit {j}");
                    assert_ne!(a, b);
                }
            }
        }
    }

    #[test]
    fn scramble_is_a_bijection_on_a_range() {
        let mut v: [u32; 1 << 16] = [0; 1 << 16];
        for (i, slot) in v.iter_mut().enumerate() {
            // Varying the top 16 bits of the value = the low 16 of the reversed value.
            *slot = owen_scramble((i as u32) << 16, 12345) >> 16;
        }
        v.sort_unstable();
        assert!(v.iter().enumerate().all(|(i, &x)| x == i as u32));
    }

    /// Owen's randomisation: over seeds, each digit of a scrambled point is a
    /// fair coin, and for two points whose first differing digit is `j`,
    /// the digits after `j` are independent coins (agree half the time).
    #[test]
    fn flips_are_fair_coins() {
        let seeds = 20_000u32;
        let x = 0x1234_5678u32;
        let mut ones = [0u32; 24];
        let mut agree = [0u32; 24];
        let y = x ^ (1 << 27); // first differs at digit 5 (bit 27)
        for s in 0..seeds {
            let a = owen_scramble(x, s);
            let b = owen_scramble(y, s);
            for k in 0..24 {
                let bit = 31 - k;
                ones[k] += (a >> bit) & 1;
                agree[k] += (((a ^ b) >> bit) & 1 == 0) as u32;
            }
        }
        for k in 0..24 {
            let p = ones[k] as f64 / seeds as f64;
            assert!((p - 0.5).abs() < 0.02, "digit {k}: P(1) = {p}");
            let q = agree[k] as f64 / seeds as f64;
            if k < 4 {
                assert_eq!(agree[k], seeds, "shared digit {k} must agree");
            } else if k == 4 {
                assert_eq!(agree[k], 0, "the differing digit stays different");
            } else {
                assert!((q - 0.5).abs() < 0.02, "digit {k}: P(agree) = {q}");
            }
        }
    }

    #[test]
    fn scrambled_points_are_stratified_in_1d() {
        for seed in [0u32, 1, 99, 0xDEAD_BEEF] {
            for d in 0..4 {
                for m in 0..=12u32 {
                    let n = 1u32 << m;
                    let mut seen = [false; 4096];
                    for i in 0..n {
                        let v = owen_sobol_u32(i, d, seed);
                        let f = crate::sequences::r2::q32_to_f32(v);
                        assert!((0.0..1.0).contains(&f));
                        let cell = if m == 0 { 0 } else { v >> (32 - m) };
                        assert!(!core::mem::replace(&mut seen[cell as usize], true));
                    }
                }
            }
        }
    }

    #[test]
    fn scrambled_and_shuffled_sobol_is_a_02_net_in_every_block() {
        for seed in [0u32, 7, 0x8000_0001] {
            for m in 0..=8u32 {
                let n = 1u32 << m;
                for block in [0u32, 1, 2, 77] {
                    let pts: [[u32; 2]; 256] = core::array::from_fn(|i| {
                        let i = shuffle_index(block * n + (i as u32 % n), seed ^ 0xABC);
                        [owen_sobol_u32(i, 0, seed), owen_sobol_u32(i, 1, seed)]
                    });
                    assert!(is_02_net(&pts[..n as usize]), "seed {seed} m {m} block {block}");
                }
            }
        }
    }

    #[test]
    fn shuffle_keeps_aligned_blocks() {
        for seed in [1u32, 2, 3] {
            for m in [1u32, 4, 8] {
                for i in 0..1024u32 {
                    let j = shuffle_index(i, seed);
                    let k = shuffle_index(i ^ ((1 << m) - 1), seed); // same block of 2^m
                    assert_eq!(j >> m, k >> m);
                }
            }
        }
    }
}
