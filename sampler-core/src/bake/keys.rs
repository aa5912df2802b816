//! Offline optimisation of the screen-space sampler's per-pixel keys
//! ([`screen_sobol`](crate::screen_sobol)), and the swap optimiser it shares
//! with the vector spatiotemporal masks.
//!
//! # Energy
//!
//! A key fixes a pixel's samples. For a set of `M` training integrands
//! `f_m` (randomly oriented Heaviside steps over `[0, 1)^2`,
//! [`HeavisideIntegrand`]) the pixel's **error vector** is
//! `e_p[m] = (1/N) sum_k f_m(x_k) - integral(f_m)` at `N = 2^level` samples.
//! Keys are arranged on the `side x side` torus to minimise
//!
//! `E = sum over pixel pairs p != q of w(p - q) <e_p, e_q>`,
//! `w(d) = exp(-|d|^2 / (2 sigma^2))`,
//!
//! the correlation of close pixels' errors. Since a Gaussian blur of
//! standard deviation `s` turns the error energy into
//! `sum_{p,q} (g * g)(p - q) <e_p, e_q>` and `g * g` is a Gaussian of
//! `sigma = s sqrt 2`, the default `sigma = sqrt 2` minimises exactly the
//! (training) error energy after a blur of 1 pixel, minus the diagonal
//! `sum |e_p|^2`, which swaps cannot change.
//!
//! # Optimiser
//!
//! Moves swap the keys of two pixels, so the tile's multiset of keys stays
//! the i.i.d. random set it started from (every pixel's marginal
//! distribution over tile offsets is that of a random key: the sampler is
//! unbiased for any tile placement). The optimiser keeps the filtered field
//! `S_p = sum_q w(p - q) e_q`; a swap of `p` and `q` (vectors `a`, `b`)
//! changes the energy by `<b - a, S_p - S_q> - w(p - q) |a - b|^2`, an
//! `O(M)` test, and an accepted swap updates `S` over the kernel's support.
//! Greedy: a swap is kept if it lowers the energy. Partners are drawn
//! uniformly from the slice. Everything is `f64` in a fixed order, so a bake
//! is reproducible bit for bit.

use super::energy::axis_taps;
use super::{check_sigma, check_size, BakeError, Progress, SplitMix64, Throttle};
use crate::screen_sobol::{key_sample_u32, ScreenSobolLayout, MAX_KEY_LEVELS, MAX_KEY_TILE};
use alloc::vec;
use alloc::vec::Vec;

/// A step function over the unit square: 1 where `normal . x > offset`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeavisideIntegrand {
    /// Unit normal of the edge.
    pub normal: [f64; 2],
    /// Edge position: the step is at `normal . x = offset`.
    pub offset: f64,
}

impl HeavisideIntegrand {
    /// The step whose edge has direction angle `angle` (radians; normal
    /// `(cos, sin)`) and passes through `point`.
    pub fn through(angle: f64, point: [f64; 2]) -> Self {
        let normal = [libm::cos(angle), libm::sin(angle)];
        HeavisideIntegrand {
            normal,
            offset: normal[0] * point[0] + normal[1] * point[1],
        }
    }

    /// Value at `(x, y)`: 1 or 0.
    #[inline]
    pub fn eval(&self, x: f64, y: f64) -> f64 {
        if self.normal[0] * x + self.normal[1] * y > self.offset {
            1.0
        } else {
            0.0
        }
    }

    /// Exact integral over `[0, 1]^2`: the area of the unit square on the
    /// positive side, by clipping the square (Sutherland-Hodgman against one
    /// line) and the shoelace formula.
    pub fn integral(&self) -> f64 {
        let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let side = |p: [f64; 2]| self.normal[0] * p[0] + self.normal[1] * p[1] - self.offset;
        let mut poly: Vec<[f64; 2]> = Vec::with_capacity(8);
        for i in 0..4 {
            let (p, q) = (square[i], square[(i + 1) % 4]);
            let (sp, sq) = (side(p), side(q));
            if sp >= 0.0 {
                poly.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                let t = sp / (sp - sq);
                poly.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
            }
        }
        let n = poly.len();
        let mut area = 0.0;
        for i in 0..n {
            let (p, q) = (poly[i], poly[(i + 1) % n]);
            area += p[0] * q[1] - q[0] * p[1];
        }
        0.5 * libm::fabs(area)
    }
}

/// `count` random steps: uniform angle, edge through a uniform point of the
/// square (Heitz et al.'s test integrands), drawn from `seed`.
pub fn heaviside_integrands(count: u32, seed: u64) -> Vec<HeavisideIntegrand> {
    let mut rng = SplitMix64::new(seed ^ 0x4845_4156_4953_4944);
    (0..count)
        .map(|_| {
            let angle = rng.unit_f64() * core::f64::consts::TAU;
            let point = [rng.unit_f64(), rng.unit_f64()];
            HeavisideIntegrand::through(angle, point)
        })
        .collect()
}

/// The generic swap optimiser over a `width x height x depth` torus of
/// `channels`-dimensional vectors. Coupling: a 2D Gaussian within a slice
/// and (if `depth > 1`) a 1D Gaussian between the same pixel in other
/// slices (the STBN energy). Swaps stay within a slice.
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
    /// `S_i = sum_j w_ij x_j`, texel-major.
    field: Vec<f64>,
    /// Spatial taps `(dx, dy, w)` as residues, excluding `(0, 0)`.
    spatial: Vec<(u32, u32, f64)>,
    /// Spatial weight by residue offset `dy * width + dx` (for `w_ij`).
    spatial_map: Vec<f64>,
    /// Temporal taps `(dz, w)`, excluding 0.
    temporal: Vec<(u32, f64)>,
    /// Reused buffer for a swap's difference vector.
    scratch: Vec<f64>,
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

impl SwapOptimiser {
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
        let xs = axis_taps(width, sigma);
        let ys = axis_taps(height, sigma);
        let mut spatial = Vec::with_capacity(xs.len() * ys.len());
        let mut spatial_map = vec![0.0; width as usize * height as usize];
        for &(dy, wy) in &ys {
            for &(dx, wx) in &xs {
                if dx == 0 && dy == 0 {
                    continue;
                }
                spatial.push((dx, dy, wx * wy));
                spatial_map[(dy * width + dx) as usize] = wx * wy;
            }
        }
        let temporal = if depth > 1 {
            axis_taps(depth, temporal_sigma)
                .into_iter()
                .filter(|t| t.0 != 0)
                .collect()
        } else {
            Vec::new()
        };
        let n = width as usize * height as usize * depth as usize;
        let mut opt = SwapOptimiser {
            width,
            height,
            depth,
            channels,
            values,
            items: (0..n as u32).collect(),
            field: vec![0.0; n * channels],
            spatial,
            spatial_map,
            temporal,
            scratch: Vec::with_capacity(channels),
        };
        opt.field = opt.compute_field();
        opt
    }

    fn texels(&self) -> usize {
        self.width as usize * self.height as usize * self.depth as usize
    }

    /// Calls `f(neighbour, weight)` for every texel coupled to `i`.
    #[inline]
    fn for_neighbours(&self, i: usize, mut f: impl FnMut(usize, f64)) {
        let wh = self.width as usize * self.height as usize;
        let z = i / wh;
        let in_slice = i % wh;
        let x = (in_slice % self.width as usize) as u32;
        let y = (in_slice / self.width as usize) as u32;
        let (wm, hm) = (self.width - 1, self.height - 1);
        for &(dx, dy, w) in &self.spatial {
            let j = z * wh + (((y + dy) & hm) * self.width + ((x + dx) & wm)) as usize;
            f(j, w);
        }
        let dm = self.depth - 1;
        for &(dz, w) in &self.temporal {
            f((((z as u32 + dz) & dm) as usize) * wh + in_slice, w);
        }
    }

    fn compute_field(&self) -> Vec<f64> {
        let c = self.channels;
        let mut field = vec![0.0; self.texels() * c];
        for i in 0..self.texels() {
            // Scatter x_i into its neighbours' fields (weights are symmetric).
            let xi = &self.values[i * c..(i + 1) * c];
            self.for_neighbours(i, |j, w| {
                for (s, &v) in field[j * c..(j + 1) * c].iter_mut().zip(xi) {
                    *s += w * v;
                }
            });
        }
        field
    }

    /// `sum over unordered coupled pairs of w <x_i, x_j>`, from scratch.
    pub(crate) fn energy(&self) -> f64 {
        let field = self.compute_field();
        0.5 * self.values.iter().zip(&field).map(|(a, b)| a * b).sum::<f64>()
    }

    /// Tries to swap texels `i` and `j` of the same slice; keeps the swap if
    /// it lowers the energy.
    fn try_swap(&mut self, i: usize, j: usize) -> bool {
        let c = self.channels;
        let wh = self.width as usize * self.height as usize;
        let (pi, pj) = (i % wh, j % wh);
        let (xi, yi) = (pi as u32 % self.width, pi as u32 / self.width);
        let (xj, yj) = (pj as u32 % self.width, pj as u32 / self.width);
        let off = ((yj.wrapping_sub(yi) & (self.height - 1)) * self.width
            + (xj.wrapping_sub(xi) & (self.width - 1))) as usize;
        let w_ij = self.spatial_map[off];
        let (mut dot, mut dist) = (0.0, 0.0);
        for k in 0..c {
            let d = self.values[j * c + k] - self.values[i * c + k];
            dot += d * (self.field[i * c + k] - self.field[j * c + k]);
            dist += d * d;
        }
        let delta = dot - w_ij * dist;
        if delta >= -1e-12 * (1.0 + dist) {
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
        for (t, sign) in [(i, 1.0), (j, -1.0)] {
            self.for_neighbours(t, |u, w| {
                for (s, d) in field[u * c..(u + 1) * c].iter_mut().zip(&diff) {
                    *s += sign * w * d;
                }
            });
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
}

/// Parameters of a key bake.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KeyParams {
    /// Tile side in pixels: a power of two up to [`MAX_KEY_TILE`].
    pub side: u32,
    /// Number of dimension pairs (independent tiles per level).
    pub pairs: u32,
    /// Number of spp levels: level `j` is optimised for `2^j` spp.
    pub levels: u32,
    /// Number of training Heaviside integrands (`1..=1024`).
    pub integrands: u32,
    /// Energy sigma in pixels (`sqrt 2` targets a blur of 1 pixel).
    pub sigma: f64,
    /// Optimiser sweeps per tile (one trial per pixel each).
    pub sweeps: u32,
    /// Seed of the keys and integrands.
    pub seed: u64,
}

impl Default for KeyParams {
    /// 64x64 tiles, 4 pairs, 5 levels (1 to 16 spp), 128 integrands,
    /// sigma `sqrt 2`, 256 sweeps, seed 1.
    fn default() -> Self {
        KeyParams {
            side: 64,
            pairs: 4,
            levels: 5,
            integrands: 128,
            sigma: core::f64::consts::SQRT_2,
            sweeps: 256,
            seed: 1,
        }
    }
}

impl KeyParams {
    /// Checks the parameters and returns the layout they describe.
    ///
    /// # Errors
    /// [`BakeError::Size`] for a bad side, [`BakeError::Sigma`],
    /// [`BakeError::Core`] with [`Error::KeyLayout`](crate::Error::KeyLayout)
    /// for bad pairs or levels, [`BakeError::Size`] (depth = integrands) for
    /// an integrand count outside `1..=1024`.
    pub fn layout(&self) -> Result<ScreenSobolLayout, BakeError> {
        if self.side > MAX_KEY_TILE {
            return Err(BakeError::Size {
                width: self.side,
                height: self.side,
                depth: 1,
            });
        }
        check_size(self.side, self.side, 1)?;
        check_sigma(self.sigma)?;
        if self.integrands == 0 || self.integrands > 1024 {
            return Err(BakeError::Size {
                width: self.side,
                height: self.side,
                depth: self.integrands,
            });
        }
        let _ = MAX_KEY_LEVELS;
        Ok(ScreenSobolLayout::new(self.side, self.pairs, self.levels)?)
    }
}

/// Error vector of `key` for `pair` at `2^level` samples over `integrands`.
pub fn key_errors(key: u32, pair: u32, level: u32, integrands: &[HeavisideIntegrand], out: &mut [f64]) {
    let n = 1u32 << level;
    let scale = 1.0 / 4_294_967_296.0;
    out.iter_mut().for_each(|e| *e = 0.0);
    for k in 0..n {
        let [x, y] = key_sample_u32(key, pair, k);
        let (x, y) = (x as f64 * scale, y as f64 * scale);
        for (e, f) in out.iter_mut().zip(integrands) {
            *e += f.eval(x, y);
        }
    }
    for (e, f) in out.iter_mut().zip(integrands) {
        *e = *e / n as f64 - f.integral();
    }
}

/// Bakes the key tile of one `(level, pair)`: `side * side` keys,
/// row-major, and what the optimiser did. Tiles of different levels and
/// pairs are independent (bake them in parallel).
///
/// # Errors
/// As [`KeyParams::layout`]; [`BakeError::Core`] if `level` or `pair` is
/// outside the layout.
pub fn bake_key_tile(
    params: &KeyParams,
    level: u32,
    pair: u32,
    progress: Progress<'_>,
) -> Result<(Vec<u32>, SwapReport), BakeError> {
    let layout = params.layout()?;
    if level >= layout.levels || pair >= layout.pairs {
        return Err(BakeError::Core(crate::Error::KeyLayout {
            side: params.side,
            pairs: pair + 1,
            levels: level + 1,
        }));
    }
    let integrands = heaviside_integrands(params.integrands, params.seed);
    let tile_seed = params
        .seed
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(((level as u64) << 32) | pair as u64);
    let mut rng = SplitMix64::new(tile_seed);
    let n = (params.side * params.side) as usize;
    let keys: Vec<u32> = (0..n).map(|_| (rng.next_u64() >> 32) as u32).collect();
    let m = integrands.len();
    let mut values = vec![0.0; n * m];
    for (key, out) in keys.iter().zip(values.chunks_exact_mut(m)) {
        key_errors(*key, pair, level, &integrands, out);
    }
    let mut opt = SwapOptimiser::new(params.side, params.side, 1, m, values, params.sigma, params.sigma);
    let report = opt.run(params.sweeps, &mut rng, progress);
    Ok((opt.items().iter().map(|&i| keys[i as usize]).collect(), report))
}

/// Bakes every tile of `params` sequentially: the key buffer in
/// [`ScreenSobolLayout::key_index`] order and one report per tile (level
/// major, then pair).
///
/// # Errors
/// As [`bake_key_tile`].
pub fn bake_sampler_keys(
    params: &KeyParams,
    progress: Progress<'_>,
) -> Result<(ScreenSobolLayout, Vec<u32>, Vec<SwapReport>), BakeError> {
    let layout = params.layout()?;
    let mut keys = Vec::with_capacity(layout.key_count());
    let mut reports = Vec::new();
    let tiles = (layout.levels * layout.pairs) as u64;
    for level in 0..layout.levels {
        for pair in 0..layout.pairs {
            let done = (level * layout.pairs + pair) as u64;
            let (tile, report) =
                bake_key_tile(params, level, pair, &mut |d, t| progress(done * t + d, tiles * t))?;
            keys.extend(tile);
            reports.push(report);
        }
    }
    Ok((layout, keys, reports))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bake::no_progress;

    #[test]
    fn heaviside_integral_matches_a_fine_grid() {
        for f in heaviside_integrands(20, 5) {
            let g = 512;
            let mut sum = 0.0;
            for y in 0..g {
                for x in 0..g {
                    sum += f.eval((x as f64 + 0.5) / g as f64, (y as f64 + 0.5) / g as f64);
                }
            }
            let grid = sum / (g * g) as f64;
            assert!(
                (grid - f.integral()).abs() < 0.005,
                "{f:?}: {grid} vs {}",
                f.integral()
            );
        }
        let half = HeavisideIntegrand::through(0.0, [0.25, 0.9]);
        assert!((half.integral() - 0.75).abs() < 1e-12);
    }

    /// The incremental field and energy deltas agree with recomputation.
    #[test]
    fn incremental_energy_matches_recomputation() {
        let mut rng = SplitMix64::new(9);
        let (w, h, d, c) = (8u32, 8u32, 4u32, 3usize);
        let values: Vec<f64> = (0..(w * h * d) as usize * c)
            .map(|_| rng.unit_f64() - 0.5)
            .collect();
        let mut opt = SwapOptimiser::new(w, h, d, c, values, 1.2, 1.5);
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
            for (a, b) in fresh.iter().zip(&opt.field) {
                assert!((a - b).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn key_bake_lowers_energy_and_keeps_the_keys() {
        let params = KeyParams {
            side: 16,
            pairs: 1,
            levels: 2,
            integrands: 16,
            sweeps: 16,
            ..KeyParams::default()
        };
        let (layout, keys, reports) = bake_sampler_keys(&params, &mut no_progress).unwrap();
        assert_eq!(keys.len(), layout.key_count());
        for r in &reports {
            // Random keys: correlations cancel on average (energy near 0); optimised
            // keys anticorrelate neighbours (negative energy).
            assert!(r.energy_after < r.energy_before && r.energy_after < 0.0, "{r:?}");
            assert!(r.accepted > 0 && r.accepted < r.trials, "{r:?}");
        }
        // Swaps only: the multiset of a tile equals the random draw.
        let (tile, _) = bake_key_tile(&params, 1, 0, &mut no_progress).unwrap();
        let mut rng = SplitMix64::new(
            params
                .seed
                .wrapping_mul(0x9E37_79B9_7F4A_7C15)
                .wrapping_add(1 << 32),
        );
        let mut drawn: Vec<u32> = (0..256).map(|_| (rng.next_u64() >> 32) as u32).collect();
        let mut sorted = tile.clone();
        sorted.sort_unstable();
        drawn.sort_unstable();
        assert_eq!(sorted, drawn);
        assert_eq!(&keys[256..512], &tile[..]);
    }

    #[test]
    fn bad_parameters_are_errors() {
        let bad = |p: KeyParams| bake_sampler_keys(&p, &mut no_progress).is_err();
        let ok = KeyParams::default();
        assert!(bad(KeyParams { side: 48, ..ok }));
        assert!(bad(KeyParams { pairs: 0, ..ok }));
        assert!(bad(KeyParams { levels: 10, ..ok }));
        assert!(bad(KeyParams { integrands: 0, ..ok }));
        assert!(bad(KeyParams { sigma: -1.0, ..ok }));
    }
}
