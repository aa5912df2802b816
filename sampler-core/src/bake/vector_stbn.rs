//! Vector spatiotemporal blue noise: `W x H x D` volumes of 2D or 3D values,
//! unit vectors or cosine-weighted hemisphere directions, blue in every
//! slice and along time at every pixel.
//!
//! # Values
//!
//! Each slice holds `W * H` vectors made from an Owen-scrambled Sobol point
//! set of that size (a fresh scramble per slice, [`owen_sobol_u32`]), so
//! every slice's histogram is stratified (a (0, m, 2)-net for the 2D kinds),
//! mapped by [`VectorKind`]. The optimiser only swaps vectors within a slice,
//! so those histograms are kept exactly.
//!
//! # Energy
//!
//! The correlation energy of the key optimiser (see `keys.rs`):
//! `E = sum over coupled pairs w_ij <x_i - m, x_j - m>` where `m` is the
//! slice mean, each channel is first divided by its standard deviation over
//! the volume (so the small-spread `z` of the cosine hemisphere counts as
//! much as `x` and `y`), and two texels are coupled only if they are in the same slice
//! (`w = exp(-d^2 / (2 sigma^2))`, toroidal distance `d`) or at the same
//! pixel in different slices (`w = exp(-dt^2 / (2 sigma_t^2))`), the STBN
//! coupling of Wolfe et al. For any direction `u`, the projection `u . x`
//! has `sum w_ij (u . x_i)(u . x_j)` of low-pass power, and `E` is its sum
//! over an orthonormal basis: minimising `E` removes low-frequency power
//! from every channel and every linear projection at once, in space and
//! in time.
//!
//! Swaps are greedy (see [`SwapReport`]): fast and reproducible.

use super::swap::{SwapOptimiser, SwapReport};
use super::{check_sigma, check_size, BakeError, Progress, SplitMix64};
use crate::sequences::owen::owen_sobol_u32;
use alloc::vec::Vec;

/// What a vector mask holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VectorKind {
    /// Points of `[0, 1)^2`.
    Vec2,
    /// Points of `[0, 1)^3`.
    Vec3,
    /// Unit vectors, uniform on the sphere (`z = 1 - 2u`, `phi = 2 pi v`:
    /// Archimedes' area-preserving map).
    UnitSphere,
    /// Unit vectors of the `z >= 0` hemisphere with density `cos(theta) / pi`
    /// (`r = sqrt u`, `phi = 2 pi v`, lifted to `z = sqrt(1 - u)`: Malley's
    /// method with the polar disk map).
    CosineHemisphere,
}

impl VectorKind {
    /// Components per texel: 2 for [`VectorKind::Vec2`], else 3.
    pub fn channels(self) -> u32 {
        match self {
            VectorKind::Vec2 => 2,
            _ => 3,
        }
    }

    /// Maps a Sobol point (0.32 fixed point, 3 coordinates; the third is
    /// used by [`VectorKind::Vec3`] only) to the kind's value.
    pub(crate) fn map(self, p: [u32; 3]) -> [f64; 3] {
        let u = |x: u32| crate::sequences::r2::q32_to_f32(x) as f64;
        let (a, b, c) = (u(p[0]), u(p[1]), u(p[2]));
        let tau = core::f64::consts::TAU;
        match self {
            VectorKind::Vec2 => [a, b, 0.0],
            VectorKind::Vec3 => [a, b, c],
            VectorKind::UnitSphere => {
                let z = 1.0 - 2.0 * a;
                let r = libm::sqrt((1.0 - z * z).max(0.0));
                [r * libm::cos(tau * b), r * libm::sin(tau * b), z]
            }
            VectorKind::CosineHemisphere => {
                let r = libm::sqrt(a);
                [
                    r * libm::cos(tau * b),
                    r * libm::sin(tau * b),
                    libm::sqrt(1.0 - a),
                ]
            }
        }
    }
}

/// Parameters of a vector mask.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VectorStbnParams {
    /// Width in texels: a power of two.
    pub width: u32,
    /// Height in texels: a power of two.
    pub height: u32,
    /// Number of slices (frames): a power of two.
    pub depth: u32,
    /// What the texels hold.
    pub kind: VectorKind,
    /// Spatial energy sigma in texels (1.9 as in STBN).
    pub sigma: f64,
    /// Temporal energy sigma in slices (1.9 as in STBN).
    pub temporal_sigma: f64,
    /// Optimiser sweeps (one trial swap per texel each).
    pub sweeps: u32,
    /// Seed of the point sets, the initial arrangement and the swaps.
    pub seed: u64,
}

impl Default for VectorStbnParams {
    /// 64x64x32 [`VectorKind::Vec2`], sigma 1.9 in space and time, 1024 sweeps, seed 1.
    fn default() -> Self {
        VectorStbnParams {
            width: 64,
            height: 64,
            depth: 32,
            kind: VectorKind::Vec2,
            sigma: 1.9,
            temporal_sigma: 1.9,
            sweeps: 1024,
            seed: 1,
        }
    }
}

/// A baked vector mask.
#[derive(Clone, Debug, PartialEq)]
pub struct VectorStbn {
    /// The parameters it was baked with.
    pub params: VectorStbnParams,
    /// `width * height * depth * channels` components, slice-major, then
    /// row-major, components of a texel together.
    pub values: Vec<f32>,
    /// What the optimiser did.
    pub report: SwapReport,
}

/// Bakes a vector spatiotemporal mask.
///
/// # Errors
/// [`BakeError::Size`] (sides must be powers of two, slices of at least 4
/// texels), [`BakeError::Sigma`] (either sigma).
pub fn bake_vector_stbn(params: &VectorStbnParams, progress: Progress<'_>) -> Result<VectorStbn, BakeError> {
    check_size(params.width, params.height, params.depth)?;
    if params.width * params.height < 4 {
        return Err(BakeError::Size {
            width: params.width,
            height: params.height,
            depth: params.depth,
        });
    }
    check_sigma(params.sigma)?;
    check_sigma(params.temporal_sigma)?;
    let c = params.kind.channels() as usize;
    let n = (params.width * params.height) as usize;
    let mut rng = SplitMix64::new(params.seed ^ 0x5653_5442_4E00_0000);
    let mut raw: Vec<f64> = Vec::with_capacity(n * params.depth as usize * c);
    let mut centred: Vec<f64> = Vec::with_capacity(raw.capacity());
    let mut order: Vec<u32> = Vec::with_capacity(n);
    for _ in 0..params.depth {
        let scramble = (rng.next_u64() >> 32) as u32;
        // Random initial arrangement (Fisher-Yates).
        order.clear();
        order.extend(0..n as u32);
        for i in (1..n).rev() {
            let j = rng.below(i as u64 + 1) as usize;
            order.swap(i, j);
        }
        let start = raw.len();
        for &i in &order {
            let p = [0, 1, 2].map(|d| owen_sobol_u32(i, d, scramble));
            raw.extend_from_slice(&params.kind.map(p)[..c]);
        }
        let slice = &raw[start..];
        let mut mean = [0.0f64; 3];
        for v in slice.chunks_exact(c) {
            for k in 0..c {
                mean[k] += v[k] / n as f64;
            }
        }
        for v in slice.chunks_exact(c) {
            for k in 0..c {
                centred.push(v[k] - mean[k]);
            }
        }
    }
    // Standardise each channel (unit variance over the volume) so a channel of small
    // spread (z of the cosine hemisphere) weighs as much as the others.
    let mut var = [0.0f64; 3];
    for v in centred.chunks_exact(c) {
        for k in 0..c {
            var[k] += v[k] * v[k];
        }
    }
    let texels = (centred.len() / c) as f64;
    let inv_sd = var.map(|v| {
        if v > 0.0 {
            1.0 / libm::sqrt(v / texels)
        } else {
            1.0
        }
    });
    for v in centred.chunks_exact_mut(c) {
        for k in 0..c {
            v[k] *= inv_sd[k];
        }
    }
    let mut opt = SwapOptimiser::new(
        params.width,
        params.height,
        params.depth,
        c,
        centred,
        params.sigma,
        params.temporal_sigma,
    );
    let report = opt.run(params.sweeps, &mut rng, progress);
    let mut values = Vec::with_capacity(raw.len());
    for &item in opt.items() {
        let i = item as usize;
        values.extend(raw[i * c..(i + 1) * c].iter().map(|&v| v as f32));
    }
    Ok(VectorStbn {
        params: *params,
        values,
        report,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bake::no_progress;

    #[test]
    fn slices_keep_their_point_sets_and_energy_drops() {
        for kind in [VectorKind::Vec2, VectorKind::CosineHemisphere] {
            let p = VectorStbnParams {
                width: 8,
                height: 8,
                depth: 4,
                kind,
                sweeps: 8,
                ..VectorStbnParams::default()
            };
            let m = bake_vector_stbn(&p, &mut no_progress).unwrap();
            let c = kind.channels() as usize;
            assert_eq!(m.values.len(), 8 * 8 * 4 * c);
            assert!(m.report.energy_after < m.report.energy_before, "{:?}", m.report);
            if kind == VectorKind::Vec2 {
                // Each slice is still a (0, 6, 2)-net: one point per 1/8 x 1/8 cell.
                for slice in m.values.chunks(64 * c) {
                    let mut seen = [false; 64];
                    for v in slice.chunks(c) {
                        let cell = (v[0] * 8.0) as usize * 8 + (v[1] * 8.0) as usize;
                        assert!(!core::mem::replace(&mut seen[cell], true));
                    }
                }
            }
        }
    }

    #[test]
    fn mappings_land_where_documented() {
        for i in 0..256u32 {
            let p = [0, 1, 2].map(|d| owen_sobol_u32(i, d, 7));
            let s = VectorKind::UnitSphere.map(p);
            let h = VectorKind::CosineHemisphere.map(p);
            for v in [s, h] {
                assert!((v[0] * v[0] + v[1] * v[1] + v[2] * v[2] - 1.0).abs() < 1e-12);
            }
            assert!(h[2] >= 0.0);
        }
        assert!(bake_vector_stbn(
            &VectorStbnParams {
                width: 6,
                ..VectorStbnParams::default()
            },
            &mut no_progress
        )
        .is_err());
    }
}
