//! Low-discrepancy additive recurrences: R1 (golden ratio), R2 (plastic
//! constant) and their `d`-dimensional generalisation R_d (Roberts 2018).
//!
//! The n-th point is `frac(s0 + n * alpha)` per dimension. Everything is
//! computed in **0.32 fixed point** (suffix `_q32`): a value `x_q32: u32`
//! stands for `x_q32 / 2^32` in `[0, 1)`, and `frac(a + b)` is a wrapping
//! add. That makes CPU and GPU agree bit for bit and nothing drifts with `n`
//! (the fixed-point generator differs from the real one by at most
//! `2^-33`, so point `n` is off by at most `n * 2^-33`).

/// Plastic constant: the real root of `x^3 = x + 1`.
pub const PLASTIC: f64 = 1.324_717_957_244_746;
/// Golden ratio: the positive root of `x^2 = x + 1`.
pub const GOLDEN: f64 = 1.618_033_988_749_895;

/// R1 generator `1 / golden ratio` = 0.6180339887...
pub const R1_A: f64 = 0.618_033_988_749_894_9;
/// R2 generator, first axis: `1 / plastic` = 0.7548776662...
pub const R2_A1: f64 = 0.754_877_666_246_692_7;
/// R2 generator, second axis: `1 / plastic^2` = 0.5698402909... (= `R2_A1^2`).
pub const R2_A2: f64 = 0.569_840_290_998_053_3;

/// `round(R1_A * 2^32)`.
pub const R1_A_Q32: u32 = 0x9E37_79B9;
/// `round(R2_A1 * 2^32)`.
pub const R2_A1_Q32: u32 = 0xC13F_A9A9;
/// `round(R2_A2 * 2^32)`.
pub const R2_A2_Q32: u32 = 0x91E1_0DA6;

/// Converts 0.32 fixed point to `f32` in `[0, 1)`, exactly (keeps the top 24
/// bits, so the result is never rounded up to 1.0).
#[inline]
pub fn q32_to_f32(x_q32: u32) -> f32 {
    (x_q32 >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// Converts `x` in `[0, 1)` to 0.32 fixed point (`x` outside wraps; NaN gives 0).
#[inline]
pub fn f32_to_q32(x: f32) -> u32 {
    let f = x - libm::floorf(x);
    // f in [0, 1]; 1.0 can appear through rounding of tiny negative x.
    let scaled = f * 16_777_216.0;
    if scaled >= 16_777_216.0 || scaled.is_nan() {
        0
    } else {
        (scaled as u32) << 8
    }
}

/// n-th point of R1 in 0.32 fixed point with start `s0_q32`.
#[inline]
pub fn r1_q32(n: u32, s0_q32: u32) -> u32 {
    s0_q32.wrapping_add(n.wrapping_mul(R1_A_Q32))
}

/// n-th point of R2 in 0.32 fixed point with start `s0_q32` on both axes.
#[inline]
pub fn r2_q32(n: u32, s0_q32: u32) -> [u32; 2] {
    [
        s0_q32.wrapping_add(n.wrapping_mul(R2_A1_Q32)),
        s0_q32.wrapping_add(n.wrapping_mul(R2_A2_Q32)),
    ]
}

/// n-th point of R1 in `[0, 1)`, start `s0` in `[0, 1)`.
#[inline]
pub fn r1(n: u32, s0: f32) -> f32 {
    q32_to_f32(r1_q32(n, f32_to_q32(s0)))
}

/// n-th point of R2 in `[0, 1)^2`, start `s0` in `[0, 1)` on both axes.
///
/// ```
/// let p = sampler_core::r2(1, 0.5);
/// assert!((p.x - 0.254_877_67).abs() < 1e-6 && (p.y - 0.069_840_29).abs() < 1e-6);
/// ```
#[inline]
pub fn r2(n: u32, s0: f32) -> glam::Vec2 {
    let [x, y] = r2_q32(n, f32_to_q32(s0));
    glam::Vec2::new(q32_to_f32(x), q32_to_f32(y))
}

/// The generalised golden ratio `phi_d`: the positive root of
/// `x^(d+1) = x + 1` (`d = 1` golden ratio, `d = 2` plastic constant).
/// Host-side helper (f64); `d` in `1..=64`.
pub fn rd_phi(d: u32) -> f64 {
    // Fixed-point iteration x <- (1 + x)^(1/(d+1)) contracts with factor
    // < 1/(d+1); 64 steps reach f64 precision for every d >= 1.
    let mut x = 2.0f64;
    let e = 1.0 / (d as f64 + 1.0);
    for _ in 0..64 {
        x = libm::pow(1.0 + x, e);
    }
    x
}

/// The R_d sequence in `D` dimensions: generators `alpha_j = phi_D^-(j+1)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rd<const D: usize> {
    /// Generators in 0.32 fixed point, `round(alpha_j * 2^32)`.
    pub alpha_q32: [u32; D],
}

impl<const D: usize> Rd<D> {
    /// Builds the generators (f64 maths; call once, not per sample).
    pub fn new() -> Self {
        let phi = rd_phi(D as u32);
        let mut alpha_q32 = [0u32; D];
        let mut a = 1.0f64;
        for slot in alpha_q32.iter_mut() {
            a /= phi;
            *slot = libm::round(a * 4_294_967_296.0) as u64 as u32;
        }
        Rd { alpha_q32 }
    }

    /// n-th point in 0.32 fixed point, start `s0_q32` on every axis.
    #[inline]
    pub fn point_q32(&self, n: u32, s0_q32: u32) -> [u32; D] {
        let mut out = [0u32; D];
        for (o, a) in out.iter_mut().zip(self.alpha_q32.iter()) {
            *o = s0_q32.wrapping_add(n.wrapping_mul(*a));
        }
        out
    }

    /// n-th point in `[0, 1)^D`, start `s0` on every axis.
    #[inline]
    pub fn point(&self, n: u32, s0: f32) -> [f32; D] {
        self.point_q32(n, f32_to_q32(s0)).map(q32_to_f32)
    }
}

impl<const D: usize> Default for Rd<D> {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_point_generators_round_the_real_ones() {
        let s = 4_294_967_296.0f64;
        assert_eq!(libm::round(R1_A * s) as u32, R1_A_Q32);
        assert_eq!(libm::round(R2_A1 * s) as u32, R2_A1_Q32);
        assert_eq!(libm::round(R2_A2 * s) as u32, R2_A2_Q32);
        assert!((1.0 / PLASTIC - R2_A1).abs() < 1e-15);
        assert!((R2_A1 * R2_A1 - R2_A2).abs() < 1e-15);
        assert!((PLASTIC * PLASTIC * PLASTIC - PLASTIC - 1.0).abs() < 1e-14);
    }

    #[test]
    fn rd_generalises_r1_and_r2() {
        assert!((rd_phi(1) - GOLDEN).abs() < 1e-14);
        assert!((rd_phi(2) - PLASTIC).abs() < 1e-14);
        assert_eq!(Rd::<1>::new().alpha_q32, [R1_A_Q32]);
        assert_eq!(Rd::<2>::new().alpha_q32, [R2_A1_Q32, R2_A2_Q32]);
        let rd = Rd::<2>::new();
        for n in [0u32, 1, 7, 1000, u32::MAX] {
            assert_eq!(rd.point_q32(n, 123), r2_q32(n, 123));
        }
    }

    #[test]
    fn q32_conversion_stays_below_one() {
        assert_eq!(q32_to_f32(u32::MAX), 1.0 - 1.0 / 16_777_216.0);
        assert_eq!(f32_to_q32(0.5), 0x8000_0000);
        assert_eq!(f32_to_q32(-0.25), 0xC000_0000);
        assert_eq!(f32_to_q32(f32::NAN), 0);
    }
}
