//! Offline optimisation of the spatiotemporal sampler's per-pixel shifts
//! ([`spatiotemporal`](crate::sequences::spatiotemporal)): a tile of
//! **jointly** blue 2D shifts, arranged for the error a history filter keeps
//! (the idea of FAST, Donnelly et al. 2024, optimising for the filter, applied
//! to a sampler's shifts instead of a dither mask).
//!
//! # Values
//!
//! The tile's `side * side` shifts are the points of an Owen-scrambled 2D
//! Sobol (0, m, 2)-net of that size, quantised to 16 bits per coordinate
//! ([`pack_shift`]; the sampler adds half a step back, [`unpack_shift`]).
//! Swaps only rearrange them, so in every frame the whole tile's samples,
//! one shared sequence point plus every shift, form a rotated net.
//!
//! # Energy
//!
//! A shift `s` fixes a pixel's samples over frames: pair `k`'s frame `t`
//! point is `p_k(t) + s` (toroidal), `p_k` the shared progressive sequence
//! ([`spatiotemporal_point_u32`]). For training Heaviside integrands `f_m`
//! ([`heaviside_integrands`]) the pixel's **error vector** holds, for each
//! training pair `k < training_pairs` and integrand:
//! - the raw errors `f_m(p_k(t) + s) - I_m` of frames `t < raw_frames`
//!   (what one frame shows), and
//! - the errors of the exponential history (`h_0 = e_0`,
//!   `h_t = (1 - alpha) h_(t-1) + alpha e_t`) at frames `stride`,
//!   `2 stride`, ..., `history_samples * stride`, scaled by
//!   `sqrt(history_weight * (2 - alpha) / alpha)` so that white noise's
//!   history would weigh as much as one raw frame.
//!
//! Shifts are arranged on the torus to minimise `sum w(p - q) <e_p, e_q>`
//! with a Gaussian `w` of `sigma` pixels (`sqrt 2`: the error energy after a
//! blur of one pixel, as for the screen-space keys,
//! [`bake_key_tile`](super::bake_key_tile)), plus the same vectors on
//! [`line_integrands`] edges coupled along rows, columns and diagonals with
//! weight `line_weight` (the error of a silhouette lives on a line of
//! pixels). The swap optimiser is the one of the keys and vector masks.
//!
//! The per-pixel history error itself (without the blur) depends on a
//! pixel's own shift only, which swaps do not change: what the arrangement
//! buys is the spatial part, every frame and after the history.
//!
//! **Measured, and not shipped**: on held-out integrands and pairs
//! (`examples/history_model.rs`) the baked tile lowers the blurred history's
//! error from 0.562 to 0.541 of white noise's but raises each frame's blurred
//! error from 0.663 to 0.676 against the sampler's two scalar reads of the
//! void-and-cluster tile, and the Kronecker sequence in time alone buys far
//! more (0.492). The sampler keeps the scalar tile; this baker stays as the
//! tool of that measurement (`QUALITY.md`, "Tried and dropped").

use super::keys::{heaviside_integrands, line_integrands, HeavisideIntegrand, LINE_STEPS};
use super::swap::{Coupling, SwapOptimiser, SwapReport};
use super::{check_sigma, check_size, BakeError, Progress, SplitMix64};
use crate::sequences::owen::owen_sobol_u32;
use crate::sequences::spatiotemporal::{spatiotemporal_point_u32, SPATIOTEMPORAL_SEED};
use alloc::vec;
use alloc::vec::Vec;

/// `2^-32`: 0.32 fixed point to `f64`.
const Q32: f64 = 1.0 / 4_294_967_296.0;

/// Packs a shift (both coordinates in 0.32 fixed point) into one word: the
/// top 16 bits of `x` in bits 16..32, of `y` in bits 0..16.
#[inline]
pub fn pack_shift(shift: [u32; 2]) -> u32 {
    (shift[0] & 0xFFFF_0000) | (shift[1] >> 16)
}

/// The shift a packed word holds, in 0.32 fixed point, each coordinate at
/// the centre of its `2^-16` step (the inverse of [`pack_shift`] up to that
/// step; what the sampler reads).
#[inline]
pub fn unpack_shift(word: u32) -> [u32; 2] {
    [(word & 0xFFFF_0000) | 0x8000, (word << 16) | 0x8000]
}

/// Parameters of a shift-tile bake.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShiftTileParams {
    /// Tile side in pixels: a power of two, `2..=256` (the 16-bit packing
    /// keeps a net of up to `2^16` points exact).
    pub side: u32,
    /// Training Heaviside integrands (`1..=1024`).
    pub integrands: u32,
    /// Sequence pairs whose points the errors are computed for (`1..=16`):
    /// the tile serves every pair (each reads it at its own offset), so it
    /// is trained on several pairs' sequences rather than one.
    pub training_pairs: u32,
    /// Raw frames per pair in the error vector (`0..=64`).
    pub raw_frames: u32,
    /// History samples per pair (`0..=64`), at frames `stride * (i + 1)`.
    pub history_samples: u32,
    /// Frames between history samples (`1..=64`).
    pub stride: u32,
    /// The history's blend factor, in `(0, 1]` (0.1: a common TAA setting).
    pub alpha: f64,
    /// Weight of the history samples against the raw frames, `>= 0`.
    pub history_weight: f64,
    /// Energy sigma in pixels.
    pub sigma: f64,
    /// Weight of the line terms, `>= 0`.
    pub line_weight: f64,
    /// Optimiser sweeps (one trial swap per pixel each).
    pub sweeps: u32,
    /// Seed of the net's scramble, the integrands and the swaps.
    pub seed: u64,
}

impl Default for ShiftTileParams {
    /// 64x64, 32 integrands, 2 training pairs, 4 raw frames, 4 history
    /// samples every 16 frames, alpha 0.1, history weight 1, sigma `sqrt 2`,
    /// no line terms, 256 sweeps, seed 1 (the best of a few settings on
    /// held-out integrands, `examples/history_model.rs`).
    fn default() -> Self {
        ShiftTileParams {
            side: 64,
            integrands: 32,
            training_pairs: 2,
            raw_frames: 4,
            history_samples: 4,
            stride: 16,
            alpha: 0.1,
            history_weight: 1.0,
            sigma: core::f64::consts::SQRT_2,
            line_weight: 0.0,
            sweeps: 256,
            seed: 1,
        }
    }
}

impl ShiftTileParams {
    fn check(&self) -> Result<(), BakeError> {
        let size = BakeError::Size {
            width: self.side,
            height: self.side,
            depth: 1,
        };
        if !(2..=256).contains(&self.side) {
            return Err(size);
        }
        check_size(self.side, self.side, 1)?;
        check_sigma(self.sigma)?;
        let counts_ok = (1..=1024).contains(&self.integrands)
            && (1..=16).contains(&self.training_pairs)
            && self.raw_frames <= 64
            && self.history_samples <= 64
            && (1..=64).contains(&self.stride)
            && self.raw_frames + self.history_samples > 0;
        if !counts_ok {
            return Err(size);
        }
        if !(self.alpha > 0.0 && self.alpha <= 1.0) {
            return Err(BakeError::Filter {
                parameter: "alpha",
                value: self.alpha,
            });
        }
        for weight in [self.history_weight, self.line_weight] {
            if !(weight >= 0.0 && weight.is_finite()) {
                return Err(BakeError::Weight { weight });
            }
        }
        Ok(())
    }

    /// Entries of one pixel's error vector per integrand: `training_pairs *
    /// (raw_frames + history_samples)`.
    fn per_integrand(&self) -> usize {
        (self.training_pairs * (self.raw_frames + self.history_samples)) as usize
    }
}

/// A baked shift tile.
#[derive(Clone, Debug, PartialEq)]
pub struct ShiftTile {
    /// The parameters it was baked with.
    pub params: ShiftTileParams,
    /// `side * side` packed shifts ([`pack_shift`]), row-major.
    pub words: Vec<u32>,
    /// What the optimiser did.
    pub report: SwapReport,
}

/// The error vector of the packed shift `word` (module docs) for one set of
/// integrands with their integrals, written to `out` (`integrands.len() *
/// params.per_integrand()` entries, integrand-major).
fn shift_errors(
    word: u32,
    params: &ShiftTileParams,
    points: &[Vec<[u32; 2]>],
    integrands: &[HeavisideIntegrand],
    integrals: &[f64],
    out: &mut [f64],
) {
    let s = unpack_shift(word);
    let history_scale = libm::sqrt(params.history_weight * (2.0 - params.alpha) / params.alpha);
    let mut i = 0;
    for (f, integral) in integrands.iter().zip(integrals) {
        for pair_points in points {
            let mut h = 0.0;
            for (t, p) in pair_points.iter().enumerate() {
                let x = p[0].wrapping_add(s[0]) as f64 * Q32;
                let y = p[1].wrapping_add(s[1]) as f64 * Q32;
                let e = f.eval(x, y) - integral;
                h = if t == 0 { e } else { h + params.alpha * (e - h) };
                let t = t as u32;
                if t < params.raw_frames {
                    out[i] = e;
                    i += 1;
                }
                if t > 0 && t.is_multiple_of(params.stride) && t / params.stride <= params.history_samples {
                    out[i] = h * history_scale;
                    i += 1;
                }
            }
        }
    }
}

/// Bakes a shift tile.
///
/// # Errors
/// [`BakeError::Size`] for a side that is not a power of two in `2..=256`
/// or counts out of range, [`BakeError::Sigma`], [`BakeError::Filter`] for
/// alpha, [`BakeError::Weight`] for a negative or non-finite weight.
pub fn bake_shift_tile(params: &ShiftTileParams, progress: Progress<'_>) -> Result<ShiftTile, BakeError> {
    params.check()?;
    let mut rng = SplitMix64::new(params.seed ^ 0x5348_4946_5453_0000);
    let n = (params.side * params.side) as usize;
    let scramble = (rng.next_u64() >> 32) as u32;
    let words: Vec<u32> = (0..n as u32)
        .map(|i| pack_shift([owen_sobol_u32(i, 0, scramble), owen_sobol_u32(i, 1, scramble)]))
        .collect();
    refine_shift_tile(params, words, &mut rng, progress)
}

/// Rearranges the packed shifts `words` (`side * side`, row-major; e.g. an
/// existing tile) to lower the energy of [`bake_shift_tile`].
///
/// # Errors
/// As [`bake_shift_tile`]; [`BakeError::Size`] if `words` does not hold
/// `side * side` shifts.
pub fn refine_shift_tile_words(
    params: &ShiftTileParams,
    words: Vec<u32>,
    progress: Progress<'_>,
) -> Result<ShiftTile, BakeError> {
    params.check()?;
    if words.len() != (params.side * params.side) as usize {
        return Err(BakeError::Size {
            width: params.side,
            height: params.side,
            depth: 1,
        });
    }
    let mut rng = SplitMix64::new(params.seed ^ 0x5348_4946_5453_0001);
    refine_shift_tile(params, words, &mut rng, progress)
}

fn refine_shift_tile(
    params: &ShiftTileParams,
    words: Vec<u32>,
    rng: &mut SplitMix64,
    progress: Progress<'_>,
) -> Result<ShiftTile, BakeError> {
    let n = words.len();
    let frames = params.raw_frames.max(params.history_samples * params.stride + 1);
    let points: Vec<Vec<[u32; 2]>> = (0..params.training_pairs)
        .map(|k| {
            (0..frames)
                .map(|t| spatiotemporal_point_u32(t, k, SPATIOTEMPORAL_SEED))
                .collect()
        })
        .collect();
    let planar = heaviside_integrands(params.integrands, params.seed);
    let integrals =
        |set: &[HeavisideIntegrand]| set.iter().map(HeavisideIntegrand::integral).collect::<Vec<_>>();
    let mut sets = vec![(planar.clone(), integrals(&planar), 1.0)];
    if params.line_weight > 0.0 {
        for &step in &LINE_STEPS {
            let set = line_integrands(step);
            let ints = integrals(&set);
            sets.push((set, ints, libm::sqrt(params.line_weight)));
        }
    }
    let per = params.per_integrand();
    let widths: Vec<usize> = sets.iter().map(|(set, _, _)| set.len() * per).collect();
    let c: usize = widths.iter().sum();
    let mut values = vec![0.0; n * c];
    for (&word, out) in words.iter().zip(values.chunks_exact_mut(c)) {
        let mut start = 0;
        for ((set, ints, scale), width) in sets.iter().zip(&widths) {
            let part = &mut out[start..start + width];
            shift_errors(word, params, &points, set, ints, part);
            part.iter_mut().for_each(|v| *v *= scale);
            start += width;
        }
    }
    let side = params.side;
    let mut couplings = vec![Coupling::gaussian(
        side,
        side,
        1,
        0..widths[0],
        params.sigma,
        params.sigma,
    )];
    let mut start = widths[0];
    for (step, width) in LINE_STEPS.iter().zip(&widths[1..]) {
        couplings.push(Coupling::along_line(
            side,
            side,
            start..start + width,
            *step,
            params.sigma,
        ));
        start += width;
    }
    let mut opt = SwapOptimiser::with_couplings(side, side, 1, c, values, couplings);
    let report = opt.run(params.sweeps, rng, progress);
    Ok(ShiftTile {
        params: *params,
        words: opt.items().iter().map(|&i| words[i as usize]).collect(),
        report,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bake::no_progress;

    #[test]
    fn packing_keeps_sixteen_bits_and_centres_the_step() {
        let s = [0x1234_5678, 0x9ABC_DEF0];
        assert_eq!(pack_shift(s), 0x1234_9ABC);
        assert_eq!(unpack_shift(pack_shift(s)), [0x1234_8000, 0x9ABC_8000]);
    }

    #[test]
    fn the_tile_is_a_net_and_the_energy_drops() {
        let p = ShiftTileParams {
            side: 16,
            integrands: 8,
            sweeps: 8,
            ..ShiftTileParams::default()
        };
        let t = bake_shift_tile(&p, &mut no_progress).unwrap();
        assert_eq!(t.words.len(), 256);
        assert!(t.report.energy_after < t.report.energy_before, "{:?}", t.report);
        // A (0, 8, 2)-net: one shift per 1/16 x 1/16 cell.
        let mut seen = [false; 256];
        for &w in &t.words {
            let [x, y] = unpack_shift(w);
            let cell = (x >> 28) as usize * 16 + (y >> 28) as usize;
            assert!(!core::mem::replace(&mut seen[cell], true), "cell {cell} twice");
        }
        // Reproducible bit for bit.
        assert_eq!(bake_shift_tile(&p, &mut no_progress).unwrap(), t);
    }

    #[test]
    fn bad_parameters_are_errors() {
        let ok = ShiftTileParams::default();
        for bad in [
            ShiftTileParams { side: 48, ..ok },
            ShiftTileParams { side: 512, ..ok },
            ShiftTileParams { integrands: 0, ..ok },
            ShiftTileParams { stride: 0, ..ok },
            ShiftTileParams {
                raw_frames: 0,
                history_samples: 0,
                ..ok
            },
        ] {
            assert!(matches!(
                bake_shift_tile(&bad, &mut no_progress),
                Err(BakeError::Size { .. })
            ));
        }
        let alpha = ShiftTileParams { alpha: 0.0, ..ok };
        assert!(matches!(
            bake_shift_tile(&alpha, &mut no_progress),
            Err(BakeError::Filter { .. })
        ));
        let nan = ShiftTileParams {
            history_weight: f64::NAN,
            ..ok
        };
        assert!(matches!(
            bake_shift_tile(&nan, &mut no_progress),
            Err(BakeError::Weight { .. })
        ));
    }
}
