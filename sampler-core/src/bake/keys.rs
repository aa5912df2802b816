//! Offline optimisation of the screen-space sampler's per-pixel keys
//! ([`screen_sobol`](crate::sequences::screen_sobol)).
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
//! **Edges along rows and columns.** That energy assumes every pixel sees
//! the same integrand. Along a geometric edge crossing the screen (a
//! light's or an object's silhouette, a shadow boundary) the error lives
//! on a line one pixel wide, and there only the pairs on that line count.
//! With [`KeyParams::line_weight`] `> 0`, one more term per line family of
//! [`LINE_STEPS`] (rows, columns, both diagonals) is added: the error
//! vectors on [`LINE_INTEGRANDS`] edges parallel to the line
//! ([`line_integrands`]; for rows `f = [y > c]`), coupled only between
//! pixels on the same line by a 1D Gaussian of the same sigma, weighted by
//! `line_weight`. At one sample per pixel the row term asks the `y`
//! coordinates along a row to be blue noise in 1D, the column term the `x`
//! coordinates along a column, and so on.
//!
//! # Optimiser
//!
//! The swap optimiser of [`swap`](super::swap): moves swap the keys of two
//! pixels, so the tile's multiset of keys stays the i.i.d. random set it
//! started from (every pixel's marginal distribution over tile offsets is
//! that of a random key: the sampler is unbiased for any tile placement).
//! A bake is reproducible bit for bit.

use super::swap::{Coupling, SwapOptimiser, SwapReport};
use super::{check_sigma, check_size, BakeError, Progress, SplitMix64};
use crate::sequences::screen_sobol::{key_sample_u32, ScreenSobolLayout, MAX_KEY_LEVELS, MAX_KEY_TILE};
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
    /// Weight of the line terms (edges along rows, columns and diagonals;
    /// module docs), `>= 0`; 0 leaves them out.
    pub line_weight: f64,
    /// Seed of the keys and integrands.
    pub seed: u64,
}

impl Default for KeyParams {
    /// 64x64 tiles, 4 pairs, 5 levels (1 to 16 spp), 128 integrands,
    /// sigma `sqrt 2`, 256 sweeps, line weight 16, seed 1.
    fn default() -> Self {
        KeyParams {
            side: 64,
            pairs: 4,
            levels: 5,
            integrands: 128,
            sigma: core::f64::consts::SQRT_2,
            sweeps: 256,
            line_weight: 16.0,
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
        if !(self.line_weight >= 0.0 && self.line_weight.is_finite()) {
            return Err(BakeError::Weight {
                weight: self.line_weight,
            });
        }
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
    let integrals: Vec<f64> = integrands.iter().map(HeavisideIntegrand::integral).collect();
    errors_with_integrals(key, pair, level, integrands, &integrals, out);
}

/// [`key_errors`] with the integrands' integrals computed once by the caller
/// (a tile evaluates the same integrands for every key).
fn errors_with_integrals(
    key: u32,
    pair: u32,
    level: u32,
    integrands: &[HeavisideIntegrand],
    integrals: &[f64],
    out: &mut [f64],
) {
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
    for (e, integral) in out.iter_mut().zip(integrals) {
        *e = *e / n as f64 - integral;
    }
}

/// Edges per line family of the line terms (offsets evenly spread across
/// the unit square).
pub const LINE_INTEGRANDS: u32 = 32;

/// The line families of the line terms: the screen direction of the line
/// of pixels an edge covers (`y` down). Rows, columns and both diagonals.
pub const LINE_STEPS: [(i32, i32); 4] = [(1, 0), (0, 1), (1, 1), (1, -1)];

/// The [`LINE_INTEGRANDS`] steps of the family whose edges run along
/// `step`: normal perpendicular to `step`, offsets at `(k + 1/2) / L` of the
/// way across the square.
pub fn line_integrands(step: (i32, i32)) -> Vec<HeavisideIntegrand> {
    let length = libm::sqrt((step.0 * step.0 + step.1 * step.1) as f64);
    let normal = [-step.1 as f64 / length, step.0 as f64 / length];
    let project = |x: f64, y: f64| normal[0] * x + normal[1] * y;
    let corners = [
        project(0.0, 0.0),
        project(1.0, 0.0),
        project(0.0, 1.0),
        project(1.0, 1.0),
    ];
    let lo = corners.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = corners.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (0..LINE_INTEGRANDS)
        .map(|k| HeavisideIntegrand {
            normal,
            offset: lo + (hi - lo) * (k as f64 + 0.5) / LINE_INTEGRANDS as f64,
        })
        .collect()
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
    let integrals =
        |set: &[HeavisideIntegrand]| set.iter().map(HeavisideIntegrand::integral).collect::<Vec<_>>();
    let planar_integrals = integrals(&integrands);
    // Per line family (LINE_STEPS order, none without line terms): its
    // integrands and their integrals.
    let families = if params.line_weight > 0.0 {
        LINE_STEPS.len()
    } else {
        0
    };
    let line_sets: Vec<(Vec<HeavisideIntegrand>, Vec<f64>)> = LINE_STEPS[..families]
        .iter()
        .map(|&step| {
            let set = line_integrands(step);
            let ints = integrals(&set);
            (set, ints)
        })
        .collect();
    let l = LINE_INTEGRANDS as usize;
    let c = m + families * l;
    let scale = libm::sqrt(params.line_weight);
    let mut values = vec![0.0; n * c];
    for (key, out) in keys.iter().zip(values.chunks_exact_mut(c)) {
        let (planar, edges) = out.split_at_mut(m);
        errors_with_integrals(*key, pair, level, &integrands, &planar_integrals, planar);
        for ((family, ints), e) in line_sets.iter().zip(edges.chunks_exact_mut(l)) {
            errors_with_integrals(*key, pair, level, family, ints, e);
            e.iter_mut().for_each(|v| *v *= scale);
        }
    }
    let side = params.side;
    let mut couplings = vec![Coupling::gaussian(
        side,
        side,
        1,
        0..m,
        params.sigma,
        params.sigma,
    )];
    for (f, step) in LINE_STEPS[..families].iter().enumerate() {
        let channels = m + f * l..m + (f + 1) * l;
        couplings.push(Coupling::along_line(side, side, channels, *step, params.sigma));
    }
    let mut opt = SwapOptimiser::with_couplings(side, side, 1, c, values, couplings);
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
        assert!(bad(KeyParams {
            line_weight: -1.0,
            ..ok
        }));
        assert!(bad(KeyParams {
            line_weight: f64::NAN,
            ..ok
        }));
    }
}
