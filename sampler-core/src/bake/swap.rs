//! The swap optimiser shared by the screen-space sampler keys and the vector
//! spatiotemporal masks: vectors on a `width x height x depth` torus
//! (powers of two) are rearranged, by swaps within a slice, to minimise
//!
//! `E = sum over couplings c, unordered texel pairs (i, j) of w_c(i - j) <x_i, x_j>_c`,
//!
//! where each [`Coupling`] owns a range of the vectors' channels and a
//! kernel `w_c`: a 2D Gaussian within a slice plus a 1D Gaussian between the
//! same pixel in other slices (the STBN energy), or a 1D Gaussian along
//! rows or along columns only (for integrands whose error lives on a line
//! of pixels, such as an edge crossing the screen).
//!
//! The optimiser keeps each coupling's filtered field
//! `S_i = sum_j w(i - j) x_j` over its channels; a swap of `i` and `j`
//! (vectors `a`, `b`) changes the energy by
//! `sum_c <b - a, S_i - S_j>_c - w_c(i - j) |a - b|_c^2`, an `O(channels)`
//! test, and an accepted swap updates the fields over the kernels' support.
//! Greedy: a swap is kept if it lowers the energy. Partners are drawn
//! uniformly from the slice. Everything is `f64` in a fixed order, so a run
//! is reproducible bit for bit.

use super::energy::axis_taps;
use super::{Progress, SplitMix64, Throttle};
use alloc::vec;
use alloc::vec::Vec;
use core::ops::Range;

/// A range of channels and the kernel that couples them between texels.
#[derive(Clone, Debug)]
pub(crate) struct Coupling {
    channels: Range<usize>,
    /// Taps `(dx, dy, dz, w)` as residues on the torus, excluding `(0, 0, 0)`.
    taps: Vec<(u32, u32, u32, f64)>,
    /// Weight by in-slice residue offset `dy * width + dx` (for `w(i - j)`
    /// of a swap, which stays in a slice).
    in_slice: Vec<f64>,
}

impl Coupling {
    /// A 2D Gaussian of `sigma` pixels within each slice and, for
    /// `depth > 1`, a 1D Gaussian of `temporal_sigma` slices between the
    /// same pixel in other slices.
    pub(crate) fn gaussian(
        width: u32,
        height: u32,
        depth: u32,
        channels: Range<usize>,
        sigma: f64,
        temporal_sigma: f64,
    ) -> Self {
        let mut c = Coupling::empty(width, height, channels);
        for &(dy, wy) in &axis_taps(height, sigma) {
            for &(dx, wx) in &axis_taps(width, sigma) {
                c.push(width, dx, dy, 0, wx * wy);
            }
        }
        if depth > 1 {
            for (dz, w) in axis_taps(depth, temporal_sigma) {
                c.push(width, 0, 0, dz, w);
            }
        }
        c
    }

    /// A 1D Gaussian of `sigma` pixels between pixels on the same line of
    /// direction `step` (e.g. `(1, 0)` rows, `(0, 1)` columns, `(1, 1)`
    /// diagonals): pixel `p` is coupled to `p + k step` with the weight of
    /// the distance `|k step|`.
    pub(crate) fn along_line(
        width: u32,
        height: u32,
        channels: Range<usize>,
        step: (i32, i32),
        sigma: f64,
    ) -> Self {
        let mut c = Coupling::empty(width, height, channels);
        let length = libm::sqrt((step.0 * step.0 + step.1 * step.1) as f64);
        let reach = libm::ceil(4.0 * sigma / length) as i32;
        for k in -reach..=reach {
            let d = k as f64 * length;
            let w = libm::exp(-(d * d) / (2.0 * sigma * sigma));
            let dx = (k * step.0).rem_euclid(width as i32) as u32;
            let dy = (k * step.1).rem_euclid(height as i32) as u32;
            c.push(width, dx, dy, 0, w);
        }
        c
    }

    fn empty(width: u32, height: u32, channels: Range<usize>) -> Self {
        Coupling {
            channels,
            taps: Vec::new(),
            in_slice: vec![0.0; width as usize * height as usize],
        }
    }

    /// Adds a tap; taps landing on the same residue (a kernel longer than
    /// the torus) add up.
    fn push(&mut self, width: u32, dx: u32, dy: u32, dz: u32, w: f64) {
        if (dx, dy, dz) == (0, 0, 0) {
            return;
        }
        match self.taps.iter_mut().find(|t| (t.0, t.1, t.2) == (dx, dy, dz)) {
            Some(t) => t.3 += w,
            None => self.taps.push((dx, dy, dz, w)),
        }
        if dz == 0 {
            self.in_slice[(dy * width + dx) as usize] += w;
        }
    }
}

/// What a run of the optimiser did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SwapReport {
    /// Energy of the initial arrangement.
    pub energy_before: f64,
    /// Energy after optimisation (recomputed from scratch).
    pub energy_after: f64,
    /// Swaps tried.
    pub trials: u64,
    /// Swaps accepted.
    pub accepted: u64,
}

/// See the module docs.
#[derive(Clone, Debug)]
pub(crate) struct SwapOptimiser {
    width: u32,
    height: u32,
    depth: u32,
    channels: usize,
    /// Current vectors, texel-major.
    values: Vec<f64>,
    /// Which original item sits at each texel.
    items: Vec<u32>,
    /// Each coupling's field over its own channels (the others stay 0),
    /// texel-major: `S_i = sum_j w(i - j) x_j`.
    field: Vec<f64>,
    couplings: Vec<Coupling>,
    /// Reused buffer for a swap's difference vector.
    scratch: Vec<f64>,
}

impl SwapOptimiser {
    /// One Gaussian coupling over all channels (see [`Coupling::gaussian`]).
    /// Sizes and sigmas must already be validated; `values.len()` must be
    /// `width * height * depth * channels`.
    pub(crate) fn new(
        width: u32,
        height: u32,
        depth: u32,
        channels: usize,
        values: Vec<f64>,
        sigma: f64,
        temporal_sigma: f64,
    ) -> Self {
        let all = Coupling::gaussian(width, height, depth, 0..channels, sigma, temporal_sigma);
        SwapOptimiser::with_couplings(width, height, depth, channels, values, vec![all])
    }

    /// Any set of couplings; their channel ranges must not overlap and must
    /// lie in `0..channels`.
    pub(crate) fn with_couplings(
        width: u32,
        height: u32,
        depth: u32,
        channels: usize,
        values: Vec<f64>,
        couplings: Vec<Coupling>,
    ) -> Self {
        debug_assert!(couplings.iter().all(|c| c.channels.end <= channels));
        let n = width as usize * height as usize * depth as usize;
        let mut opt = SwapOptimiser {
            width,
            height,
            depth,
            channels,
            values,
            items: (0..n as u32).collect(),
            field: vec![0.0; n * channels],
            couplings,
            scratch: Vec::with_capacity(channels),
        };
        opt.field = opt.compute_field();
        opt
    }

    fn texels(&self) -> usize {
        self.width as usize * self.height as usize * self.depth as usize
    }

    /// Calls `f(neighbour, weight)` for every texel `coupling` couples to `i`.
    #[inline]
    fn for_neighbours(&self, coupling: &Coupling, i: usize, mut f: impl FnMut(usize, f64)) {
        let wh = self.width as usize * self.height as usize;
        let z = (i / wh) as u32;
        let in_slice = i % wh;
        let x = (in_slice % self.width as usize) as u32;
        let y = (in_slice / self.width as usize) as u32;
        let (wm, hm, dm) = (self.width - 1, self.height - 1, self.depth - 1);
        for &(dx, dy, dz, w) in &coupling.taps {
            let j =
                (((z + dz) & dm) as usize) * wh + (((y + dy) & hm) * self.width + ((x + dx) & wm)) as usize;
            f(j, w);
        }
    }

    fn compute_field(&self) -> Vec<f64> {
        let c = self.channels;
        let mut field = vec![0.0; self.texels() * c];
        for coupling in &self.couplings {
            let r = coupling.channels.clone();
            for i in 0..self.texels() {
                // Scatter x_i into its neighbours' fields (weights are symmetric).
                let xi = &self.values[i * c + r.start..i * c + r.end];
                self.for_neighbours(coupling, i, |j, w| {
                    for (s, &v) in field[j * c + r.start..j * c + r.end].iter_mut().zip(xi) {
                        *s += w * v;
                    }
                });
            }
        }
        field
    }

    /// `sum over couplings and unordered coupled pairs of w <x_i, x_j>`,
    /// from scratch.
    pub(crate) fn energy(&self) -> f64 {
        let field = self.compute_field();
        0.5 * self.values.iter().zip(&field).map(|(a, b)| a * b).sum::<f64>()
    }

    /// Tries to swap texels `i` and `j` of the same slice; keeps the swap if
    /// it lowers the energy.
    pub(crate) fn try_swap(&mut self, i: usize, j: usize) -> bool {
        let c = self.channels;
        let wh = self.width as usize * self.height as usize;
        let (pi, pj) = (i % wh, j % wh);
        let (xi, yi) = (pi as u32 % self.width, pi as u32 / self.width);
        let (xj, yj) = (pj as u32 % self.width, pj as u32 / self.width);
        let off = ((yj.wrapping_sub(yi) & (self.height - 1)) * self.width
            + (xj.wrapping_sub(xi) & (self.width - 1))) as usize;
        let (mut delta, mut scale) = (0.0, 1.0);
        for coupling in &self.couplings {
            let (mut dot, mut dist) = (0.0, 0.0);
            for k in coupling.channels.clone() {
                let d = self.values[j * c + k] - self.values[i * c + k];
                dot += d * (self.field[i * c + k] - self.field[j * c + k]);
                dist += d * d;
            }
            delta += dot - coupling.in_slice[off] * dist;
            scale += dist;
        }
        if delta >= -1e-12 * scale {
            return false;
        }
        let mut diff = core::mem::take(&mut self.scratch);
        diff.clear();
        diff.extend((0..c).map(|k| self.values[j * c + k] - self.values[i * c + k]));
        for k in 0..c {
            self.values.swap(i * c + k, j * c + k);
        }
        self.items.swap(i, j);
        // x_i grew by diff, x_j shrank by diff.
        let mut field = core::mem::take(&mut self.field);
        for coupling in &self.couplings {
            let r = coupling.channels.clone();
            for (t, sign) in [(i, 1.0), (j, -1.0)] {
                self.for_neighbours(coupling, t, |u, w| {
                    for (s, d) in field[u * c + r.start..u * c + r.end]
                        .iter_mut()
                        .zip(&diff[r.clone()])
                    {
                        *s += sign * w * d;
                    }
                });
            }
        }
        self.field = field;
        self.scratch = diff;
        true
    }

    /// Runs `sweeps` sweeps (one sweep = one trial per texel, each with a
    /// uniformly drawn partner in the same slice).
    pub(crate) fn run(&mut self, sweeps: u32, rng: &mut SplitMix64, progress: Progress<'_>) -> SwapReport {
        let energy_before = self.energy();
        let n = self.texels();
        let wh = self.width as u64 * self.height as u64;
        let total = sweeps as u64 * n as u64;
        let mut throttle = Throttle::new(total);
        let (mut trials, mut accepted) = (0u64, 0u64);
        for _ in 0..sweeps {
            for i in 0..n {
                let slice = i / wh as usize;
                let j = slice * wh as usize + rng.below(wh) as usize;
                trials += 1;
                if j != i && self.try_swap(i, j) {
                    accepted += 1;
                }
                throttle.tick(trials, total, progress);
            }
        }
        progress(total, total);
        SwapReport {
            energy_before,
            energy_after: self.energy(),
            trials,
            accepted,
        }
    }

    /// The original item index now at each texel.
    pub(crate) fn items(&self) -> &[u32] {
        &self.items
    }

    /// The current vectors, texel-major.
    #[cfg(test)]
    pub(crate) fn values(&self) -> &[f64] {
        &self.values
    }

    /// The maintained field (for tests against [`Self::compute_field`]).
    #[cfg(test)]
    fn field(&self) -> &[f64] {
        &self.field
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The incremental fields and energy deltas agree with recomputation,
    /// for the STBN coupling alone and for a mix of couplings.
    #[test]
    fn incremental_energy_matches_recomputation() {
        let mut rng = SplitMix64::new(9);
        let (w, h, d, c) = (8u32, 8u32, 4u32, 5usize);
        for mixed in [false, true] {
            let values: Vec<f64> = (0..(w * h * d) as usize * c)
                .map(|_| rng.unit_f64() - 0.5)
                .collect();
            let mut opt = if mixed {
                let couplings = vec![
                    Coupling::gaussian(w, h, d, 0..2, 1.2, 1.5),
                    Coupling::along_line(w, h, 2..4, (1, 0), 1.0),
                    Coupling::along_line(w, h, 4..5, (1, -1), 2.5),
                ];
                SwapOptimiser::with_couplings(w, h, d, c, values, couplings)
            } else {
                SwapOptimiser::new(w, h, d, c, values, 1.2, 1.5)
            };
            let mut e = opt.energy();
            for _ in 0..300 {
                let i = rng.below((w * h * d) as u64) as usize;
                let slice = i / 64;
                let j = slice * 64 + rng.below(64) as usize;
                if i == j {
                    continue;
                }
                let before = opt.values().to_vec();
                if opt.try_swap(i, j) {
                    let now = opt.energy();
                    assert!(now < e + 1e-9, "accepted swap raised energy {e} -> {now}");
                    e = now;
                } else {
                    assert_eq!(before, opt.values());
                }
                let fresh = opt.compute_field();
                for (a, b) in fresh.iter().zip(opt.field()) {
                    assert!((a - b).abs() < 1e-9);
                }
            }
        }
    }

    /// A row coupling only sees pixels of the same row: the energy of a
    /// pattern constant along columns and alternating along rows is negative,
    /// and a column coupling sees none of it.
    #[test]
    fn line_couplings_see_only_their_line() {
        let (w, h) = (8u32, 8u32);
        let values: Vec<f64> = (0..w * h).map(|i| if i % 2 == 0 { 1.0 } else { -1.0 }).collect();
        let line = |step| vec![Coupling::along_line(w, h, 0..1, step, 1.0)];
        let rows = SwapOptimiser::with_couplings(w, h, 1, 1, values.clone(), line((1, 0)));
        let cols = SwapOptimiser::with_couplings(w, h, 1, 1, values, line((0, 1)));
        assert!(rows.energy() < -1.0, "{}", rows.energy());
        assert!(cols.energy() > 1.0, "{}", cols.energy());
    }
}
