//! The first dimensions of the Sobol sequence, in 0.32 fixed point.
//!
//! Point `i` of dimension `d` is the carry-less (XOR) product of the bits of
//! `i` with the dimension's **generator matrix**, whose columns are the
//! direction numbers `v_k = m_k / 2^k` (`k = 1..=32`). We store each column
//! as the `u32` `m_k << (32 - k)`, so a point is a plain `u32` in 0.32 fixed
//! point (`x_q32 / 2^32`, see [`crate::sequences::r2`](mod@crate::sequences::r2)): bit 31 is the first binary
//! digit of the coordinate.
//!
//! # Where the direction numbers come from
//!
//! Dimension `d >= 1` has a primitive polynomial over GF(2)
//! `x^s + a_1 x^(s-1) + ... + a_(s-1) x + 1` and initial odd integers
//! `m_1..m_s` with `m_k < 2^k`; later ones follow Bratley & Fox's
//! recurrence (1988, Algorithm 659), with `a = a_1 a_2 ... a_(s-1)` read
//! as binary digits:
//!
//! `m_k = 2 a_1 m_(k-1) ^ 4 a_2 m_(k-2) ^ ... ^ 2^(s-1) a_(s-1) m_(k-s+1) ^ 2^s m_(k-s) ^ m_(k-s)`.
//!
//! [`directions`] evaluates it at compile time; nothing is tabulated by hand.
//!
//! | dimension | polynomial | `s` | `a` | `m_1..m_s` | note |
//! |---|---|---|---|---|---|
//! | 0 | none | | | | van der Corput: `v_k = 2^-k`, the identity matrix, so the point is `reverse_bits(i)` |
//! | 1 | `x + 1` | 1 | 0 | 1 | the only primitive polynomial of degree 1; `m_k = 3 m_(k-1)` carry-less, so `m_k` is row `k-1` of Pascal's triangle mod 2 |
//! | 2 | `x^2 + x + 1` | 2 | 1 | 1, 3 | the only primitive polynomial of degree 2 |
//! | 3 | `x^3 + x + 1` | 3 | 1 | 1, 3, 1 | first primitive polynomial of degree 3 |
//!
//! Polynomials are taken in the standard order (by degree, then value); the
//! initial numbers of dimensions 2 and 3 are those Joe & Kuo (2008,
//! "Constructing Sobol sequences with better two-dimensional projections",
//! file `new-joe-kuo-6.21201`, its dimensions 3 and 4) chose to optimise
//! two-dimensional projections. Dimensions 0 and 1 form a (0, 2)-sequence in
//! base 2: every aligned block of `2^m` points is a (0, m, 2)-net (each
//! elementary interval of area `2^-m` holds exactly one point); a test below
//! checks it. We keep four dimensions: the samplers of this crate use only
//! dimensions 0 and 1 (higher dimensions are padded pairs with independent
//! scrambles), and more dimensions are only worth adding with a measured
//! use for them.
//!
//! Shader-callable: `u32` arithmetic, a constant table, no allocation.

/// Number of dimensions of [`SOBOL_DIRECTIONS`].
pub const SOBOL_DIMENSIONS: usize = 4;

/// Evaluates the direction numbers of a primitive polynomial of degree
/// `degree` (1..=3) with inner coefficients `a` and initial numbers `m_init`
/// (the first `degree` entries are used), as `m_k << (32 - k)` for
/// `k = 1..=32` (entry `k - 1`).
pub const fn directions(degree: u32, a: u32, m_init: [u32; 3]) -> [u32; 32] {
    let s = degree as usize;
    let mut m = [0u32; 32];
    let mut k = 0;
    while k < 32 {
        if k < s {
            m[k] = m_init[k];
        } else {
            // 2^s m_(k-s) ^ m_(k-s): m_(k-s) < 2^(k-s+1), so the shift stays within 32 bits.
            let mut v = m[k - s] ^ (m[k - s] << s);
            let mut j = 1;
            while j < s {
                if (a >> (s - 1 - j)) & 1 == 1 {
                    v ^= m[k - j] << j;
                }
                j += 1;
            }
            m[k] = v;
        }
        k += 1;
    }
    let mut out = [0u32; 32];
    let mut k = 0;
    while k < 32 {
        out[k] = m[k] << (31 - k);
        k += 1;
    }
    out
}

/// The van der Corput generator matrix: `v_k = 2^-k` (the identity).
const fn van_der_corput() -> [u32; 32] {
    let mut out = [0u32; 32];
    let mut k = 0;
    while k < 32 {
        out[k] = 1 << (31 - k);
        k += 1;
    }
    out
}

/// Generator-matrix columns of the first [`SOBOL_DIMENSIONS`] dimensions:
/// entry `[d][k]` is `v_(k+1)` of dimension `d` in 0.32 fixed point (see the
/// module documentation for their derivation).
pub const SOBOL_DIRECTIONS: [[u32; 32]; SOBOL_DIMENSIONS] = [
    van_der_corput(),
    directions(1, 0, [1, 0, 0]),
    directions(2, 1, [1, 3, 0]),
    directions(3, 1, [1, 3, 1]),
];

/// Point `index` of Sobol dimension `dimension`, in 0.32 fixed point.
///
/// `dimension` is taken modulo [`SOBOL_DIMENSIONS`] (no panic on the GPU).
#[inline]
pub fn sobol_u32(index: u32, dimension: u32) -> u32 {
    let d = (dimension % SOBOL_DIMENSIONS as u32) as usize;
    let mut result = 0u32;
    let mut i = index;
    let mut k = 0usize;
    while i != 0 {
        if i & 1 != 0 {
            result ^= SOBOL_DIRECTIONS[d][k];
        }
        i >>= 1;
        k += 1;
    }
    result
}

/// Point `index` of Sobol dimensions 0 and 1 together, in 0.32 fixed point;
/// identical to `[sobol_u32(index, 0), sobol_u32(index, 1)]`, without the
/// table or a loop over the index's bits. Dimension 0 is the bit reversal
/// `r` of `index` (van der Corput). Dimension 1's columns follow `v_(k+1) =
/// v_k ^ (v_k >> 1)` (its primitive polynomial is `x + 1`), so its generator
/// matrix is Pascal's triangle mod 2: by Lucas's theorem, output bit `31 - m`
/// is the XOR of the index bits `k` whose binary digits include `m`'s. In
/// terms of `r` (index bit `k` sits at position `31 - k`), position `q` of
/// the output is the XOR of `r`'s bits at the positions `p` whose binary
/// digits are a subset of `q`'s: a subset-sum transform over the five bits
/// of a position, five shift-and-mask steps.
#[inline]
pub fn sobol_pair_u32(index: u32) -> [u32; 2] {
    let r = index.reverse_bits();
    let mut y = r;
    // Step b adds position q - 2^b into every position q that has bit b.
    y ^= (y << 1) & 0xAAAA_AAAA;
    y ^= (y << 2) & 0xCCCC_CCCC;
    y ^= (y << 4) & 0xF0F0_F0F0;
    y ^= (y << 8) & 0xFF00_FF00;
    y ^= (y << 16) & 0xFFFF_0000;
    [r, y]
}

/// Point `index` of Sobol dimension `dimension`, in `[0, 1)` (24 bits).
#[inline]
pub fn sobol(index: u32, dimension: u32) -> f32 {
    crate::sequences::r2::q32_to_f32(sobol_u32(index, dimension))
}

#[cfg(test)]
pub(crate) mod tests {
    #[test]
    fn the_pair_equals_the_table_for_dimensions_0_and_1() {
        let mut state = 7u32;
        for k in 0..20_000u32 {
            let index = if k < 4096 {
                k
            } else {
                crate::sequences::seed::hash_u32(state)
            };
            state = state.wrapping_add(1);
            assert_eq!(
                sobol_pair_u32(index),
                [sobol_u32(index, 0), sobol_u32(index, 1)],
                "index {index}"
            );
        }
        assert_eq!(
            sobol_pair_u32(u32::MAX),
            [sobol_u32(u32::MAX, 0), sobol_u32(u32::MAX, 1)]
        );
    }

    use super::*;

    /// Whether `points` (0.32 fixed point pairs, `2^m` of them) form a
    /// (0, m, 2)-net: for every split `m = a + b`, each box of
    /// `2^-a x 2^-b` holds exactly one point.
    pub(crate) fn is_02_net(points: &[[u32; 2]]) -> bool {
        let n = points.len();
        assert!(n.is_power_of_two());
        let m = n.trailing_zeros();
        (0..=m).all(|a| {
            let b = m - a;
            let mut seen = [false; 256];
            points.iter().all(|p| {
                let cx = if a == 0 { 0 } else { p[0] >> (32 - a) };
                let cy = if b == 0 { 0 } else { p[1] >> (32 - b) };
                !core::mem::replace(&mut seen[((cx << b) | cy) as usize], true)
            })
        })
    }

    #[test]
    fn direction_numbers_are_valid() {
        // m_k odd and below 2^k: bit (32 - k) set, nothing below it.
        for (d, dirs) in SOBOL_DIRECTIONS.iter().enumerate() {
            for (k, &v) in dirs.iter().enumerate() {
                assert_eq!(v.trailing_zeros(), 31 - k as u32, "dimension {d} column {k}");
            }
        }
    }

    #[test]
    fn dimension_zero_is_van_der_corput_and_one_is_pascal() {
        for i in [0u32, 1, 2, 3, 77, 1 << 20, u32::MAX] {
            assert_eq!(sobol_u32(i, 0), i.reverse_bits());
        }
        // m_k of x + 1: binomial coefficients C(k-1, j) mod 2 as bits.
        for (k, &v) in SOBOL_DIRECTIONS[1].iter().enumerate() {
            let m = v >> (31 - k);
            for j in 0..=k {
                // Lucas: C(k, j) is odd iff j & !k == 0.
                let odd = j & !k == 0;
                assert_eq!((m >> j) & 1 == 1, odd, "k {k} j {j}");
            }
        }
        // v_1 = 1/2, v_2 = 3/4, v_3 = 5/8 (m = 1, 3, 5), so the first eight points are
        // the XOR combinations in index order.
        let first: [f32; 8] = core::array::from_fn(|i| sobol(i as u32, 1));
        assert_eq!(first, [0.0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875]);
    }

    #[test]
    fn each_dimension_is_stratified_in_1d() {
        for d in 0..SOBOL_DIMENSIONS as u32 {
            for m in 0..=10u32 {
                let n = 1u32 << m;
                for block in [0u32, 1, 5] {
                    let mut seen = [false; 1024];
                    for i in block * n..(block + 1) * n {
                        let cell = if m == 0 { 0 } else { sobol_u32(i, d) >> (32 - m) };
                        assert!(!core::mem::replace(&mut seen[cell as usize], true), "d {d} m {m}");
                    }
                }
            }
        }
    }

    #[test]
    fn dimensions_zero_and_one_are_a_02_sequence() {
        for m in 0..=8u32 {
            let n = 1u32 << m;
            for block in [0u32, 1, 3, 1000] {
                let pts: [[u32; 2]; 256] = core::array::from_fn(|i| {
                    let i = block * n + (i as u32 % n);
                    [sobol_u32(i, 0), sobol_u32(i, 1)]
                });
                assert!(is_02_net(&pts[..n as usize]), "m {m} block {block}");
            }
        }
    }
}
