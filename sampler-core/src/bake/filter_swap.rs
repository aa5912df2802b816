//! The swap optimiser of the filter-adapted masks: vectors on a
//! `width x height x depth` torus are rearranged, by swaps within a slice,
//! to minimise
//!
//! `E = 1/2 sum over texels i, j of W(i - j) <x_i, x_j>`,
//!
//! the energy of the field after a spatiotemporal filter (`W` is the
//! filter's autocorrelation, see `filters.rs`), with
//!
//! - product: `W(dx, dy, dz) = S(dx, dy) T(dz)`,
//! - separate: `W = w S(dx, dy) [dz = 0] + (1 - w) T(dz) [dx = dy = 0]`,
//!
//! `S` the spatial autocorrelation (separable, offsets whose weight is below
//! [`SPATIAL_CUTOFF`] of the peak dropped) and `T` the temporal one.
//!
//! Unlike the generic `swap.rs` (explicit 3D taps), the product kernel is
//! never expanded: the optimiser keeps only the spatially filtered field
//! `P = S * x` (per slice), stored pixel-major (a pixel's slices together),
//! and a swap's test computes the full field at the two texels as the
//! temporal sum `sum_dz T(dz) P(p, z + dz)`: `O(depth)` contiguous reads per
//! test, `O(spatial taps)` writes per accepted swap, instead of
//! `O(spatial taps x depth)`. Swapping `i` and `j` (vectors `a`, `b`,
//! `d = b - a`) changes the energy by
//! `<d, F_i - F_j> + |d|^2 (W(0) - W(i - j))` with `F = W * x`.
//!
//! Greedy, partners drawn uniformly from the slice, everything `f64` in a
//! fixed order: a run is reproducible bit for bit.

use super::{Progress, SplitMix64, Throttle};
use alloc::vec;
use alloc::vec::Vec;

/// Spatial autocorrelation weights below this fraction of the peak are
/// dropped (for a Gaussian filter of sigma 1.3435 this keeps the disc of
/// radius 7, 149 offsets); temporal weights are all kept.
pub(crate) const SPATIAL_CUTOFF: f64 = 1e-3;

/// How the spatial and temporal autocorrelations combine.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Mix {
    /// `S(dx, dy) T(dz)`.
    Product,
    /// `w S [dz = 0] + (1 - w) T [dx = dy = 0]`, `w` the spatial weight.
    Separate(f64),
}

/// See the module docs.
#[derive(Clone, Debug)]
pub(crate) struct FilterSwap {
    width: u32,
    height: u32,
    depth: u32,
    channels: usize,
    mix: Mix,
    /// Spatial taps `(dx, dy, weight)` as residues (including `(0, 0)`).
    spatial: Vec<(u32, u32, f64)>,
    /// Spatial weight by residue offset `dy * width + dx` (0 when dropped).
    spatial_table: Vec<f64>,
    /// Temporal autocorrelation by slice offset, `depth` entries.
    temporal: Vec<f64>,
    /// Vectors, pixel-major: `((pixel * depth) + z) * channels + k`.
    values: Vec<f64>,
    /// Spatially filtered field `S * x`, same layout.
    filtered: Vec<f64>,
    /// Original item (slice-major texel index) now at each pixel-major texel.
    items: Vec<u32>,
}

impl FilterSwap {
    /// `values` slice-major (`(z * height + y) * width + x`), `channels` per
    /// texel; `spatial_x`/`spatial_y` are the per-axis spatial
    /// autocorrelations (`width` and `height` entries), `temporal` the
    /// temporal one (`depth` entries). Sides must be validated powers of two.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        width: u32,
        height: u32,
        depth: u32,
        channels: usize,
        values: &[f64],
        spatial_x: &[f64],
        spatial_y: &[f64],
        temporal: Vec<f64>,
        mix: Mix,
    ) -> Self {
        let peak = spatial_x[0] * spatial_y[0];
        let mut spatial = Vec::new();
        let mut spatial_table = vec![0.0; width as usize * height as usize];
        for (dy, &wy) in spatial_y.iter().enumerate() {
            for (dx, &wx) in spatial_x.iter().enumerate() {
                let w = wx * wy;
                if w >= SPATIAL_CUTOFF * peak {
                    spatial.push((dx as u32, dy as u32, w));
                    spatial_table[dy * width as usize + dx] = w;
                }
            }
        }
        let wh = width as usize * height as usize;
        let d = depth as usize;
        let mut pixel_major = vec![0.0; values.len()];
        let mut items = vec![0u32; wh * d];
        for z in 0..d {
            for p in 0..wh {
                let src = z * wh + p;
                let dst = p * d + z;
                items[dst] = src as u32;
                pixel_major[dst * channels..(dst + 1) * channels]
                    .copy_from_slice(&values[src * channels..(src + 1) * channels]);
            }
        }
        let mut opt = FilterSwap {
            width,
            height,
            depth,
            channels,
            mix,
            spatial,
            spatial_table,
            temporal,
            values: pixel_major,
            filtered: Vec::new(),
            items,
        };
        opt.filtered = opt.compute_filtered();
        opt
    }

    fn texels(&self) -> usize {
        self.width as usize * self.height as usize * self.depth as usize
    }

    /// `S * x` from scratch.
    fn compute_filtered(&self) -> Vec<f64> {
        let mut out = vec![0.0; self.values.len()];
        let wh = self.width as usize * self.height as usize;
        for p in 0..wh {
            for z in 0..self.depth as usize {
                let src = (p * self.depth as usize + z) * self.channels;
                let v: Vec<f64> = self.values[src..src + self.channels].to_vec();
                self.scatter(p, z, &v, 1.0, &mut out);
            }
        }
        out
    }

    /// Adds `sign * S(q - p) v` to `field` at every pixel `q` of slice `z`.
    #[inline]
    fn scatter(&self, p: usize, z: usize, v: &[f64], sign: f64, field: &mut [f64]) {
        let (w, d, c) = (self.width, self.depth as usize, self.channels);
        let (x, y) = (p as u32 % w, p as u32 / w);
        let (wm, hm) = (w - 1, self.height - 1);
        for &(dx, dy, s) in &self.spatial {
            let q = (((y + dy) & hm) * w + ((x + dx) & wm)) as usize;
            let o = (q * d + z) * c;
            for (f, &vk) in field[o..o + c].iter_mut().zip(v) {
                *f += sign * s * vk;
            }
        }
    }

    /// The full field `W * x` at pixel `p`, slice `z`, channel `k`.
    #[inline]
    fn field(&self, p: usize, z: usize, k: usize) -> f64 {
        let (d, c) = (self.depth as usize, self.channels);
        let base = p * d * c + k;
        let dm = d - 1;
        match self.mix {
            Mix::Product => {
                let mut acc = 0.0;
                for (dz, &t) in self.temporal.iter().enumerate() {
                    acc += t * self.filtered[base + ((z + dz) & dm) * c];
                }
                acc
            }
            Mix::Separate(w) => {
                let mut acc = 0.0;
                for (dz, &t) in self.temporal.iter().enumerate() {
                    acc += t * self.values[base + ((z + dz) & dm) * c];
                }
                w * self.filtered[base + z * c] + (1.0 - w) * acc
            }
        }
    }

    /// `W(0)` and `W` between two pixels of a slice at residue offset `off`.
    fn weights(&self, off: usize) -> (f64, f64) {
        let (s0, t0) = (self.spatial_table[0], self.temporal[0]);
        match self.mix {
            Mix::Product => (s0 * t0, self.spatial_table[off] * t0),
            Mix::Separate(w) => (w * s0 + (1.0 - w) * t0, w * self.spatial_table[off]),
        }
    }

    /// `E = 1/2 sum x . (W * x)`, from scratch.
    pub(crate) fn energy(&self) -> f64 {
        let filtered = self.compute_filtered();
        let probe = FilterSwap {
            filtered,
            ..self.clone()
        };
        let wh = self.width as usize * self.height as usize;
        let mut e = 0.0;
        for p in 0..wh {
            for z in 0..self.depth as usize {
                for k in 0..self.channels {
                    let x = self.values[(p * self.depth as usize + z) * self.channels + k];
                    e += x * probe.field(p, z, k);
                }
            }
        }
        0.5 * e
    }

    /// Tries to swap pixels `p` and `q` of slice `z`; keeps the swap if it
    /// lowers the energy.
    pub(crate) fn try_swap(&mut self, p: usize, q: usize, z: usize) -> bool {
        let (d, c, w) = (self.depth as usize, self.channels, self.width);
        let (i, j) = ((p * d + z) * c, (q * d + z) * c);
        let (xp, yp) = (p as u32 % w, p as u32 / w);
        let (xq, yq) = (q as u32 % w, q as u32 / w);
        let off = ((yq.wrapping_sub(yp) & (self.height - 1)) * w + (xq.wrapping_sub(xp) & (w - 1))) as usize;
        let (w0, wij) = self.weights(off);
        let (mut dot, mut dist) = (0.0, 0.0);
        for k in 0..c {
            let diff = self.values[j + k] - self.values[i + k];
            dot += diff * (self.field(p, z, k) - self.field(q, z, k));
            dist += diff * diff;
        }
        let delta = dot + dist * (w0 - wij);
        if delta >= -1e-12 * (1.0 + dist) {
            return false;
        }
        let mut diff = [0.0f64; 4];
        for (k, dk) in diff.iter_mut().enumerate().take(c) {
            *dk = self.values[j + k] - self.values[i + k];
            self.values.swap(i + k, j + k);
        }
        self.items.swap(p * d + z, q * d + z);
        let mut filtered = core::mem::take(&mut self.filtered);
        self.scatter(p, z, &diff[..c], 1.0, &mut filtered);
        self.scatter(q, z, &diff[..c], -1.0, &mut filtered);
        self.filtered = filtered;
        true
    }

    /// Runs `sweeps` sweeps (one trial per texel each, partner uniform in
    /// the slice); returns `(energy before, energy after, trials, accepted)`.
    pub(crate) fn run(
        &mut self,
        sweeps: u32,
        rng: &mut SplitMix64,
        progress: Progress<'_>,
    ) -> (f64, f64, u64, u64) {
        let before = self.energy();
        let wh = self.width as usize * self.height as usize;
        let total = sweeps as u64 * self.texels() as u64;
        let mut throttle = Throttle::new(total);
        let (mut trials, mut accepted) = (0u64, 0u64);
        for _ in 0..sweeps {
            for z in 0..self.depth as usize {
                for p in 0..wh {
                    let q = rng.below(wh as u64) as usize;
                    trials += 1;
                    if q != p && self.try_swap(p, q, z) {
                        accepted += 1;
                    }
                    throttle.tick(trials, total, progress);
                }
            }
        }
        progress(total, total);
        (before, self.energy(), trials, accepted)
    }

    /// The original item (slice-major texel index) now at each texel, in
    /// slice-major order.
    pub(crate) fn items_slice_major(&self) -> Vec<u32> {
        let wh = self.width as usize * self.height as usize;
        super::slice_major(&self.items, wh, self.depth as usize)
    }

    /// The maintained spatially filtered field (for tests).
    #[cfg(test)]
    fn filtered(&self) -> &[f64] {
        &self.filtered
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bake::filters::{spatial_autocorrelation, SpatialFilter, TemporalFilter};

    /// Direct `1/2 sum_ij W(i - j) <x_i, x_j>` with the 3D kernel expanded.
    fn naive_energy(opt: &FilterSwap) -> f64 {
        let (w, h, d, c) = (
            opt.width as usize,
            opt.height as usize,
            opt.depth as usize,
            opt.channels,
        );
        let kernel = |p: usize, q: usize, dz: usize| {
            let (dx, dy) = ((q % w + w - p % w) % w, (q / w + h - p / w) % h);
            let s = opt.spatial_table[dy * w + dx];
            match opt.mix {
                Mix::Product => s * opt.temporal[dz],
                Mix::Separate(sw) => {
                    let mut k = 0.0;
                    if dz == 0 {
                        k += sw * s;
                    }
                    if p == q {
                        k += (1.0 - sw) * opt.temporal[dz];
                    }
                    k
                }
            }
        };
        let mut e = 0.0;
        for p in 0..w * h {
            for zp in 0..d {
                for q in 0..w * h {
                    for zq in 0..d {
                        let dz = (zq + d - zp) % d;
                        let (a, b) = ((p * d + zp) * c, (q * d + zq) * c);
                        let dot: f64 = (0..c).map(|k| opt.values[a + k] * opt.values[b + k]).sum();
                        e += kernel(p, q, dz) * dot;
                    }
                }
            }
        }
        0.5 * e
    }

    #[test]
    fn incremental_energy_matches_recomputation() {
        let (w, h, d) = (8u32, 4u32, 4u32);
        let mut rng = SplitMix64::new(3);
        for (c, mix) in [(1usize, Mix::Product), (2, Mix::Separate(0.4)), (3, Mix::Product)] {
            let values: Vec<f64> = (0..(w * h * d) as usize * c)
                .map(|_| rng.unit_f64() - 0.5)
                .collect();
            let sx = spatial_autocorrelation(&SpatialFilter::Gaussian { sigma: 1.0 }, w);
            let sy = spatial_autocorrelation(&SpatialFilter::Box { size: 3 }, h);
            let t = TemporalFilter::Exponential { alpha: 0.3 }.autocorrelation(d);
            let mut opt = FilterSwap::new(w, h, d, c, &values, &sx, &sy, t, mix);
            assert!((opt.energy() - naive_energy(&opt)).abs() < 1e-9);
            let mut e = opt.energy();
            for _ in 0..200 {
                let (p, q) = (rng.below(32) as usize, rng.below(32) as usize);
                let z = rng.below(4) as usize;
                if p == q {
                    continue;
                }
                if opt.try_swap(p, q, z) {
                    let now = naive_energy(&opt);
                    assert!(now < e + 1e-12, "accepted swap raised energy {e} -> {now}");
                    e = now;
                }
                let fresh = opt.compute_filtered();
                for (a, b) in fresh.iter().zip(opt.filtered()) {
                    assert!((a - b).abs() < 1e-9);
                }
            }
            // The items still form a per-slice permutation of the original texels.
            let items = opt.items_slice_major();
            for (t, &item) in items.iter().enumerate() {
                assert_eq!(t / 32, item as usize / 32);
            }
        }
    }
}
