//! The swap optimiser of filter-adapted scalar masks: the energy is the
//! thresholded error of `shared/notes/quality.md` itself, not an energy of
//! the values.
//!
//! Dithering the constant `t` with a mask of per-slice ranks `r` leaves the
//! error `b_t(i) = [v_i < t] - t`, `v_i = (r_i + 0.5) / n`. After a linear
//! filter `g` its squared norm is `sum_ij W(i - j) b_t(i) b_t(j)` with `W`
//! the autocorrelation of `g` (`filters.rs`); the optimiser minimises
//!
//! `E = 1/2 sum over thresholds t of sum_ij W(i - j) b_t(i) b_t(j)`
//!
//! over up to [`THRESHOLDS`] evenly spaced thresholds at a time, whose
//! positions change during the run (below), every end frame alike (the
//! temporal filter wraps around the torus). `W` is the product
//! `S(dx, dy) T(dz)` or the separate sum `w S [dz = 0] + (1 - w) T [dx = dy
//! = 0]`; as in `filter_swap.rs` the product is never expanded: the fields
//! are filtered in space only, and a test sums them over time.
//!
//! The fields hold the filtered indicators `S * [rank < c_k]` (the level
//! `t_k` is a constant per slice, which swaps cannot change). The cuts
//! `c_k = k B + o` (`B = n / levels` ranks apart) move together: a sweep
//! has `B / m` steps, each giving every slice and cut `2m` trials (`m =
//! B / 4`) and then moving the offset `o` by a random step in `-m..=m`
//! (reflected at 0 and `B`; only the fields of the ranks the cuts pass are
//! updated), so every level of the mask is optimised and no lattice of
//! levels is favoured.
//!
//! Moves: a rank `a` drawn in `[c - m, c)` and a rank `b` in `[c, c + m)`
//! trade texels (`p` holds `a`, `q` holds `b`). Only the levels between `a`
//! and `b`, all within `m` ranks of the cut, change, and the energy change
//! of the continuum of levels is approximated by that at the cut:
//! `F_k(q) - F_k(p) + W(0) - W(p - q)` with `F_k = W * [rank < c_k]` (after
//! the trade `p` is above the cut and `q` below). A sweep makes about two
//! trials per texel.
//!
//! Greedy, deterministic: the fields are `f32` updated in a fixed order and
//! decisions are taken in `f64`.

use super::{Progress, SplitMix64, Throttle};
use alloc::vec;
use alloc::vec::Vec;

/// Most cuts kept at once (fields of `4 * texels * THRESHOLDS` bytes: 128 MiB
/// for 128x128x64). Slices of fewer than `16 * THRESHOLDS` texels use
/// `n / 16` cuts.
pub(crate) const THRESHOLDS: usize = 32;

/// Spatial autocorrelation weights below this fraction of the peak, per
/// axis, are dropped (a square of taps: the Gaussian filter of sigma 1.3435
/// keeps 15 x 15).
const AXIS_CUTOFF: f64 = 1e-3;

/// See the module docs.
pub(crate) struct ThresholdSwap {
    width: u32,
    height: u32,
    depth: u32,
    /// `None`: product; `Some(w)`: separate with spatial weight `w`.
    separate: Option<f64>,
    /// Spatial taps `(dx, dy, weight)` (residues, including `(0, 0)`).
    spatial: Vec<(u32, u32, f64)>,
    /// The kept per-axis taps `(offset residue, weight)`.
    axis_x: Vec<(u32, f64)>,
    axis_y: Vec<(u32, f64)>,
    /// Spatial weight by residue offset `dy * width + dx`.
    spatial_table: Vec<f64>,
    /// Temporal autocorrelation, `depth` entries.
    temporal: Vec<f64>,
    /// Number of cuts and their spacing `B` in ranks.
    levels: usize,
    spacing: u32,
    /// Current offset `o` of the cuts `c_k = k B + o`.
    offset: u32,
    /// Ranks, pixel-major: `pixel * depth + z`.
    ranks: Vec<u32>,
    /// Pixel of each rank in each slice: `z * n + rank`.
    pixel_of: Vec<u32>,
    /// `S * [rank < c_k]`: `(k * n + pixel) * depth + z` (a level's fields
    /// together, a pixel's slices together: a level fits the caches).
    filtered: Vec<f32>,
}

impl ThresholdSwap {
    /// `ranks` slice-major, per-slice permutations of `0..width*height`
    /// (`width * height >= 16`); `spatial_x`/`spatial_y`/`temporal`
    /// autocorrelations as in `filter_swap.rs`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        width: u32,
        height: u32,
        depth: u32,
        ranks: &[u32],
        spatial_x: &[f64],
        spatial_y: &[f64],
        temporal: Vec<f64>,
        separate: Option<f64>,
    ) -> Self {
        let axis = |a: &[f64]| -> Vec<(u32, f64)> {
            a.iter()
                .enumerate()
                .filter(|(_, &w)| w >= AXIS_CUTOFF * a[0])
                .map(|(d, &w)| (d as u32, w))
                .collect()
        };
        let (ax, ay) = (axis(spatial_x), axis(spatial_y));
        let mut spatial = Vec::with_capacity(ax.len() * ay.len());
        let mut spatial_table = vec![0.0; width as usize * height as usize];
        for &(dy, wy) in &ay {
            for &(dx, wx) in &ax {
                spatial.push((dx, dy, wx * wy));
                spatial_table[(dy * width + dx) as usize] = wx * wy;
            }
        }
        let n = width as usize * height as usize;
        let d = depth as usize;
        let levels = THRESHOLDS.min(n / 16).max(1);
        let mut pm = vec![0u32; n * d];
        let mut pixel_of = vec![0u32; n * d];
        for z in 0..d {
            for p in 0..n {
                let r = ranks[z * n + p];
                pm[p * d + z] = r;
                pixel_of[z * n + r as usize] = p as u32;
            }
        }
        let mut opt = ThresholdSwap {
            width,
            height,
            depth,
            separate,
            spatial,
            axis_x: ax,
            axis_y: ay,
            spatial_table,
            temporal,
            levels,
            spacing: (n / levels) as u32,
            offset: 0,
            ranks: pm,
            pixel_of,
            filtered: Vec::new(),
        };
        opt.set_offset((n / levels / 2) as u32);
        opt
    }

    fn texel_count(&self) -> usize {
        self.width as usize * self.height as usize
    }

    #[inline]
    fn cut(&self, k: usize) -> u32 {
        k as u32 * self.spacing + self.offset
    }

    /// Moves the cuts to offset `o` (in `0..=spacing`) and recomputes the
    /// fields from scratch (separably: rows, then columns).
    fn set_offset(&mut self, o: u32) {
        self.offset = o;
        let (w, h, d) = (self.width as usize, self.height as usize, self.depth as usize);
        let n = w * h;
        let levels = self.levels;
        let mut out = vec![0.0f32; n * levels * d];
        let mut plane = vec![0.0f64; n];
        let mut rows = vec![0.0f64; n];
        let xs: Vec<(usize, f64)> = self.axis_x.iter().map(|&(o, v)| (o as usize, v)).collect();
        let ys: Vec<(usize, f64)> = self.axis_y.iter().map(|&(o, v)| (o as usize, v)).collect();
        for z in 0..d {
            for k in 0..levels {
                let c = self.cut(k);
                for (p, v) in plane.iter_mut().enumerate() {
                    *v = if self.ranks[p * d + z] < c { 1.0 } else { 0.0 };
                }
                // A tap at offset dx carries b(p) to p + dx: out(q) = sum S(dx) b(q - dx).
                for y in 0..h {
                    let row = &plane[y * w..(y + 1) * w];
                    for x in 0..w {
                        let mut acc = 0.0;
                        for &(dx, wx) in &xs {
                            acc += wx * row[(x + w - dx) & (w - 1)];
                        }
                        rows[y * w + x] = acc;
                    }
                }
                for y in 0..h {
                    for x in 0..w {
                        let mut acc = 0.0;
                        for &(dy, wy) in &ys {
                            acc += wy * rows[((y + h - dy) & (h - 1)) * w + x];
                        }
                        out[(k * n + y * w + x) * d + z] = acc as f32;
                    }
                }
            }
        }
        self.filtered = out;
    }

    /// Moves every cut by `step` ranks (up if positive), updating the
    /// fields of the ranks it passes.
    fn shift_cuts(&mut self, step: i64) {
        let (n, d) = (self.texel_count(), self.depth as usize);
        for k in 0..self.levels {
            let c = self.cut(k) as i64;
            let (lo, hi, sign) = if step > 0 {
                (c, (c + step).min(n as i64), 1.0)
            } else {
                ((c + step).max(0), c, -1.0)
            };
            for z in 0..d {
                for r in lo..hi {
                    let p = self.pixel_of[z * n + r as usize] as usize;
                    self.scatter(p, z, k, sign);
                }
            }
        }
        self.offset = (self.offset as i64 + step) as u32;
    }

    /// The field `F_k = W * [rank < c_k]` at pixel `p`, slice `z`.
    #[inline]
    fn field(&self, p: usize, z: usize, k: usize) -> f64 {
        let d = self.depth as usize;
        match self.separate {
            None => {
                let row = &self.filtered[(k * self.texel_count() + p) * d..][..d];
                // sum_dz T(dz) row[(z + dz) mod d], as two contiguous runs.
                let (near, far) = self.temporal.split_at(d - z);
                dot4(near, &row[z..]) + dot4(far, &row[..z])
            }
            Some(w) => {
                let dm = d - 1;
                let ranks = &self.ranks[p * d..(p + 1) * d];
                let c = self.cut(k);
                let mut acc = 0.0f64;
                for (dz, &t) in self.temporal.iter().enumerate() {
                    if ranks[(z + dz) & dm] < c {
                        acc += t;
                    }
                }
                w * self.filtered[(k * self.texel_count() + p) * d + z] as f64 + (1.0 - w) * acc
            }
        }
    }

    fn weights(&self, off: usize) -> (f64, f64) {
        let (s0, t0) = (self.spatial_table[0], self.temporal[0]);
        match self.separate {
            None => (s0 * t0, self.spatial_table[off] * t0),
            Some(w) => (w * s0 + (1.0 - w) * t0, w * self.spatial_table[off]),
        }
    }

    /// Sum of all weights of `W` (for the energy's constant terms).
    fn weight_sum(&self) -> f64 {
        let s: f64 = self.spatial.iter().map(|t| t.2).sum();
        let t: f64 = self.temporal.iter().sum();
        match self.separate {
            None => s * t,
            Some(w) => w * s + (1.0 - w) * t,
        }
    }

    /// `E = 1/2 sum_k sum_ij W(i - j) b_k(i) b_k(j)` with the zero-mean
    /// patterns `b_k = [rank < c_k] - c_k / n`, at the current cuts.
    pub(crate) fn energy(&self) -> f64 {
        let (n, d) = (self.texel_count(), self.depth as usize);
        let sigma = self.weight_sum();
        let mut e = 0.0;
        for k in 0..self.levels {
            let c = self.cut(k);
            let mut dot = 0.0;
            for z in 0..d {
                for r in 0..c {
                    let p = self.pixel_of[z * n + r as usize] as usize;
                    dot += self.field(p, z, k);
                }
            }
            // sum (i - t)(W i - t sigma) = i.Wi - sigma c^2 d / n, t = c / n.
            e += dot - sigma * (c as f64) * (c as f64) * d as f64 / n as f64;
        }
        0.5 * e
    }

    /// Adds `delta * S(. - p)` to field `k` in slice `z`.
    #[inline]
    fn scatter(&mut self, p: usize, z: usize, k: usize, delta: f64) {
        let (w, d) = (self.width, self.depth as usize);
        let base = k * self.texel_count();
        let (x, y) = (p as u32 % w, p as u32 / w);
        let (wm, hm) = (w - 1, self.height - 1);
        for &(dx, dy, s) in &self.spatial {
            let q = (((y + dy) & hm) * w + ((x + dx) & wm)) as usize;
            self.filtered[(base + q) * d + z] += (delta * s) as f32;
        }
    }

    /// Tries the trade of ranks `a < c_k <= b` in slice `z`; keeps it if it
    /// lowers the energy at cut `k`.
    fn try_trade(&mut self, z: usize, a: u32, b: u32, k: usize) -> bool {
        let (n, d, w) = (self.texel_count(), self.depth as usize, self.width);
        let p = self.pixel_of[z * n + a as usize] as usize;
        let q = self.pixel_of[z * n + b as usize] as usize;
        let (xp, yp) = (p as u32 % w, p as u32 / w);
        let (xq, yq) = (q as u32 % w, q as u32 / w);
        let off = ((yq.wrapping_sub(yp) & (self.height - 1)) * w + (xq.wrapping_sub(xp) & (w - 1))) as usize;
        let (w0, wpq) = self.weights(off);
        // The indicator drops by one at p and grows by one at q.
        let delta = self.field(q, z, k) - self.field(p, z, k) + w0 - wpq;
        if delta >= -1e-9 {
            return false;
        }
        self.ranks[p * d + z] = b;
        self.ranks[q * d + z] = a;
        self.pixel_of[z * n + a as usize] = q as u32;
        self.pixel_of[z * n + b as usize] = p as u32;
        self.scatter(p, z, k, -1.0);
        self.scatter(q, z, k, 1.0);
        true
    }

    /// Runs `sweeps` sweeps (see the module docs); returns `(energy before,
    /// energy after, trials, accepted)`, both energies at the cuts of the
    /// start (offset `B / 2`).
    pub(crate) fn run(
        &mut self,
        sweeps: u32,
        rng: &mut SplitMix64,
        progress: Progress<'_>,
    ) -> (f64, f64, u64, u64) {
        let before = self.energy();
        let (n, d) = (self.texel_count(), self.depth as usize);
        let spacing = self.spacing;
        let half = (spacing / 4).max(1);
        let steps = (spacing / half).max(1);
        let total = sweeps as u64 * steps as u64 * (d * self.levels) as u64 * 2 * half as u64;
        let mut throttle = Throttle::new(total);
        let (mut trials, mut accepted) = (0u64, 0u64);
        for _ in 0..sweeps {
            for _ in 0..steps {
                for k in 0..self.levels {
                    for z in 0..d {
                        let c = self.cut(k);
                        let lo = c.saturating_sub(half);
                        let hi = (c + half).min(n as u32);
                        if lo >= c || hi <= c {
                            trials += 2 * half as u64;
                            continue;
                        }
                        for _ in 0..2 * half {
                            trials += 1;
                            let a = lo + rng.below((c - lo) as u64) as u32;
                            let b = c + rng.below((hi - c) as u64) as u32;
                            if self.try_trade(z, a, b, k) {
                                accepted += 1;
                            }
                        }
                        throttle.tick(trials, total, progress);
                    }
                }
                // A random walk of the offset (steps up to m, reflected at 0
                // and B), so no lattice of levels is favoured and a step only
                // updates the fields of the few ranks the cuts pass.
                let step = rng.below(2 * half as u64 + 1) as i64 - half as i64;
                let mut next = self.offset as i64 + step;
                if next < 0 {
                    next = -next;
                }
                if next > spacing as i64 {
                    next = 2 * spacing as i64 - next;
                }
                self.shift_cuts(next - self.offset as i64);
            }
        }
        progress(total, total);
        let start = spacing / 2;
        self.shift_cuts(start as i64 - self.offset as i64);
        (before, self.energy(), trials, accepted)
    }

    /// The ranks, slice-major.
    pub(crate) fn ranks_slice_major(&self) -> Vec<u32> {
        super::slice_major(&self.ranks, self.texel_count(), self.depth as usize)
    }

    #[cfg(test)]
    fn filtered(&self) -> &[f32] {
        &self.filtered
    }
}

/// `sum a[i] b[i]` with four running sums (a fixed order: reproducible,
/// and fast without reassociation by the compiler).
#[inline]
fn dot4(a: &[f64], b: &[f32]) -> f64 {
    let mut acc = [0.0f64; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        for i in 0..4 {
            acc[i] += x[i] * y[i] as f64;
        }
    }
    let mut tail = 0.0;
    for (x, y) in ra.iter().zip(rb) {
        tail += x * *y as f64;
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bake::filters::{spatial_autocorrelation, SpatialFilter, TemporalFilter};

    /// Direct `1/2 sum_k sum_ij W(i - j) b_k(i) b_k(j)`, `b_k` zero-mean.
    fn naive_energy(opt: &ThresholdSwap) -> f64 {
        let (w, h, d) = (opt.width as usize, opt.height as usize, opt.depth as usize);
        let n = w * h;
        let mut e = 0.0;
        for k in 0..opt.levels {
            let c = opt.cut(k);
            let b = |r: u32| (if r < c { 1.0 } else { 0.0 }) - c as f64 / n as f64;
            for p in 0..n {
                for zp in 0..d {
                    for q in 0..n {
                        for zq in 0..d {
                            let dz = (zq + d - zp) % d;
                            let (dx, dy) = ((q % w + w - p % w) % w, (q / w + h - p / w) % h);
                            let s = opt.spatial_table[dy * w + dx];
                            let kern = match opt.separate {
                                None => s * opt.temporal[dz],
                                Some(sw) => {
                                    (if dz == 0 { sw * s } else { 0.0 })
                                        + (if p == q {
                                            (1.0 - sw) * opt.temporal[dz]
                                        } else {
                                            0.0
                                        })
                                }
                            };
                            e += kern * b(opt.ranks[p * d + zp]) * b(opt.ranks[q * d + zq]);
                        }
                    }
                }
            }
        }
        0.5 * e
    }

    #[test]
    fn incremental_fields_and_energy_match_recomputation() {
        let (w, h, d) = (8u32, 8u32, 4u32);
        let mut rng = SplitMix64::new(5);
        let mut ranks = Vec::new();
        for _ in 0..d {
            let mut perm: Vec<u32> = (0..64).collect();
            for i in (1..64).rev() {
                perm.swap(i, rng.below(i as u64 + 1) as usize);
            }
            ranks.extend(perm);
        }
        for separate in [None, Some(0.3)] {
            let sx = spatial_autocorrelation(&SpatialFilter::Binomial { n: 2 }, w);
            let sy = spatial_autocorrelation(&SpatialFilter::Gaussian { sigma: 0.8 }, h);
            let t = TemporalFilter::Exponential { alpha: 0.3 }.autocorrelation(d);
            let mut opt = ThresholdSwap::new(w, h, d, &ranks, &sx, &sy, t, separate);
            let e0 = naive_energy(&opt);
            assert!((opt.energy() - e0).abs() < 1e-5, "{} vs {e0}", opt.energy());
            let (before, after, _, accepted) = opt.run(3, &mut rng, &mut crate::bake::no_progress);
            assert!(accepted > 0);
            assert!((before - e0).abs() < 1e-5);
            let e1 = naive_energy(&opt);
            assert!((after - e1).abs() < 1e-4, "{after} vs {e1}");
            assert!(e1 < e0, "{e1} vs {e0}");
            let maintained = opt.filtered().to_vec();
            opt.set_offset(opt.offset);
            for (a, b) in maintained.iter().zip(opt.filtered()) {
                assert!((a - b).abs() < 1e-5);
            }
            // Still per-slice permutations.
            let out = opt.ranks_slice_major();
            for slice in out.chunks(64) {
                let mut s = slice.to_vec();
                s.sort_unstable();
                assert!(s.iter().enumerate().all(|(i, &r)| r == i as u32));
            }
        }
    }
}
