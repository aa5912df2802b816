//! Quantised toroidal Gaussian energy kernels for void-and-cluster.
//!
//! The energy of texel `p` is the sum over the "ones" `q` of the binary
//! pattern of a Gaussian of their toroidal distance, truncated at
//! `ceil(4 sigma)` per axis. Weights are `exp(-d^2 / (2 sigma^2))` (peak 1),
//! scaled so that the energy of any texel stays below about `2^29` and rounded to
//! integers: incremental updates are then exact (no drift), and ties are
//! broken by texel index, so bakes are bit-for-bit reproducible.
//!
//! On an axis shorter than the kernel (`size < 2 ceil(4 sigma) + 1`) the
//! kernel is periodised: the weights of all offsets congruent modulo `size`
//! are summed, so every residue appears once.

use super::extrema::Extrema;
use alloc::vec;
use alloc::vec::Vec;

/// Energy bound the weights are scaled to: `2^29`, so that an energy plus
/// the membership bias [`ONE_BIAS`](super::extrema::ONE_BIAS) (rounding adds
/// at most half a unit per tap) stays below `i32::MAX`.
const ENERGY_BOUND: f64 = (1u64 << 29) as f64;

/// One axis of a kernel: residues `0..size` and unscaled weights.
pub(crate) fn axis_taps(size: u32, sigma: f64) -> Vec<(u32, f64)> {
    let r = libm::ceil(4.0 * sigma) as i64;
    let g = |d: i64| libm::exp(-((d * d) as f64) / (2.0 * sigma * sigma));
    let n = size as i64;
    if n > 2 * r {
        (-r..=r).map(|d| (d.rem_euclid(n) as u32, g(d))).collect()
    } else {
        let mut acc = vec![0.0f64; size as usize];
        for d in -r..=r {
            acc[d.rem_euclid(n) as usize] += g(d);
        }
        acc.into_iter().enumerate().map(|(i, w)| (i as u32, w)).collect()
    }
}

/// Sum of the unscaled weights of a separable 2D kernel.
fn sum_2d(xs: &[(u32, f64)], ys: &[(u32, f64)]) -> f64 {
    let sx: f64 = xs.iter().map(|t| t.1).sum();
    let sy: f64 = ys.iter().map(|t| t.1).sum();
    sx * sy
}

/// A quantised spatial kernel on a `width x height` torus (powers of two),
/// optionally with a temporal 1D kernel across `depth` slices that couples
/// only the same pixel in other slices (the STBN energy).
#[derive(Clone, Debug)]
pub(crate) struct Kernel {
    width: u32,
    height: u32,
    depth: u32,
    xs: Vec<u32>,
    /// The columns a splat at x = 0 reaches: `x_first..x_first + x_len`
    /// (mod width), a contiguous run.
    x_first: u32,
    x_len: u32,
    ys: Vec<u32>,
    /// `ys.len() x xs.len()` weights, row-major.
    weights: Vec<i32>,
    /// Temporal taps: (slice residue != 0, weight).
    zs: Vec<(u32, i32)>,
}

impl Kernel {
    /// Builds the kernel. `temporal_sigma` is ignored when `depth == 1`.
    /// Sizes and sigmas must already be validated.
    pub(crate) fn new(width: u32, height: u32, depth: u32, sigma: f64, temporal_sigma: f64) -> Self {
        let xs = axis_taps(width, sigma);
        let ys = axis_taps(height, sigma);
        let zs: Vec<(u32, f64)> = if depth > 1 {
            axis_taps(depth, temporal_sigma)
                .into_iter()
                .filter(|t| t.0 != 0)
                .collect()
        } else {
            Vec::new()
        };
        let total = sum_2d(&xs, &ys) + zs.iter().map(|t| t.1).sum::<f64>();
        let scale = libm::floor(ENERGY_BOUND / total);
        let q = |w: f64| libm::round(scale * w) as i32;
        let mut weights = Vec::with_capacity(xs.len() * ys.len());
        for &(_, wy) in &ys {
            for &(_, wx) in &xs {
                weights.push(q(wy * wx));
            }
        }
        // Taps come in order -r..=r (or 0..width when periodised).
        let (x_first, x_len) = (xs[0].0, xs.len() as u32);
        Kernel {
            width,
            height,
            depth,
            x_first,
            x_len,
            xs: xs.iter().map(|t| t.0).collect(),
            ys: ys.iter().map(|t| t.0).collect(),
            weights,
            zs: zs.iter().map(|&(z, w)| (z, q(w))).collect(),
        }
    }

    /// Number of texels of the volume.
    pub(crate) fn len(&self) -> usize {
        self.width as usize * self.height as usize * self.depth as usize
    }

    /// Adds (`sign = 1`) or removes (`sign = -1`) the contribution of a one
    /// at texel `index` to every energy it reaches, and marks them in `extrema`.
    #[inline]
    pub(crate) fn splat(&self, index: usize, sign: i32, energy: &mut [i32], extrema: &mut Extrema) {
        let wh = self.width as usize * self.height as usize;
        let z = index / wh;
        let in_slice = index % wh;
        let x = (in_slice % self.width as usize) as u32;
        let y = (in_slice / self.width as usize) as u32;
        let base = z * wh;
        let (wm, hm) = (self.width - 1, self.height - 1);
        let nx = self.xs.len();
        for (j, &oy) in self.ys.iter().enumerate() {
            let row = base + (((y + oy) & hm) * self.width) as usize;
            let weights = &self.weights[j * nx..(j + 1) * nx];
            for (&ox, &w) in self.xs.iter().zip(weights) {
                energy[row + ((x + ox) & wm) as usize] += sign * w;
            }
            let first = (x + self.x_first) & wm;
            let end = first + self.x_len;
            if end <= self.width {
                extrema.touch_range(row + first as usize, row + end as usize);
            } else {
                extrema.touch_range(row + first as usize, row + self.width as usize);
                extrema.touch_range(row, row + (end - self.width) as usize);
            }
        }
        let dm = self.depth - 1;
        for &(oz, w) in &self.zs {
            let i = (((z as u32 + oz) & dm) as usize) * wh + in_slice;
            energy[i] += sign * w;
            extrema.touch(i);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn periodised_taps_cover_each_residue_once() {
        for size in [1u32, 2, 4, 8, 16, 32, 64] {
            let taps = axis_taps(size, 1.9);
            let mut seen: Vec<u32> = taps.iter().map(|t| t.0).collect();
            seen.sort_unstable();
            seen.dedup();
            assert_eq!(seen.len(), taps.len(), "size {size}");
            assert!(taps.iter().all(|t| t.0 < size));
            // Periodisation keeps the total weight of the truncated kernel.
            let total: f64 = taps.iter().map(|t| t.1).sum();
            let reference: f64 = axis_taps(1024, 1.9).iter().map(|t| t.1).sum();
            assert!((total - reference).abs() < 1e-12, "size {size}");
        }
    }

    #[test]
    fn splat_is_symmetric_and_reversible() {
        // Energy at a from a one at b equals energy at b from a one at a.
        let k = Kernel::new(16, 8, 4, 1.5, 1.9);
        let n = k.len();
        let mut ex = Extrema::new(n);
        let (a, b) = (3 + 16 * 2 + 128, 5 + 16 * 7 + 128);
        let mut ea = vec![0; n];
        k.splat(a, 1, &mut ea, &mut ex);
        let mut eb = vec![0; n];
        k.splat(b, 1, &mut eb, &mut ex);
        assert_eq!(ea[b], eb[a]);
        assert!(ea[b] > 0);
        // Same pixel, other slice: coupled; other pixel, other slice: not.
        assert!(ea[a + 2 * 128] > 0);
        assert_eq!(ea[b + 128], 0);
        k.splat(a, -1, &mut ea, &mut ex);
        assert!(ea.iter().all(|&e| e == 0));
    }
}
