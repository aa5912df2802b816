//! Piecewise-constant distributions on `[0, 1)` and `[0, 1)^2`, sampled by
//! inverting their CDF tables, with no allocation: the builders write the
//! tables into caller-provided `&mut [f32]` slices, and sampling and pdf
//! read `&[f32]` slices (a storage buffer in a shader).
//!
//! # Tables
//!
//! A 1D distribution of `n` cells with weights `w_i >= 0` is a table of
//! [`Distribution1d::table_len`]`(n) = 1 + n` entries:
//!
//! | index | entry |
//! |---|---|
//! | `0` | the **integral** of the step function over `[0, 1)`: `sum(w) / n` (0 for an all-zero function) |
//! | `1 + i` | the **CDF at the right edge of cell `i`**: `(w_0 + ... + w_i) / sum(w)`, non-decreasing; entry `n` is exactly `1.0` |
//!
//! A 2D distribution of `width x height` cells (row-major weights `w(x, y)`)
//! is a table of [`Distribution2d::table_len`]`(width, height) =
//! 1 + height + width * height` entries:
//!
//! | index | entry |
//! |---|---|
//! | `0` | the integral over `[0, 1)^2`: `sum(w) / (width * height)` |
//! | `1 + y` | the **marginal** CDF over rows at the bottom edge of row `y` (row weights: the row means, proportional to the row sums) |
//! | `1 + height + y * width + x` | row `y`'s **conditional** CDF at the right edge of cell `x` |
//!
//! The first `1 + height` entries are thus the 1D table of the row means.
//! Sums and prefix sums are accumulated in `f64` and rounded once to `f32`.
//!
//! # Sampling and pdf
//!
//! [`sample_1d`] finds the first cell whose CDF entry exceeds `u` (a binary
//! search, at most 32 steps) and places the sample linearly inside it, so
//! the map `u -> x` is non-decreasing, and continuous except where it skips
//! cells of zero weight. [`sample_2d`] picks the row
//! with `u.y` from the marginal, then the column with `u.x` from that row's
//! conditional, so the point is monotone in each coordinate of `u`
//! (stratification of `u` carries over).
//!
//! Densities are with respect to the unit interval / unit square. A cell's
//! **mass** is the difference of its two stored CDF entries, which is exactly
//! the probability that the sampler picks it; the density inside the cell is
//! `mass * n` (`mass_row * height * mass_column * width` in 2D). So the pdf
//! returned with a sample and the pdf recomputed at the sample's point agree
//! exactly (up to points within rounding of a cell edge, which may be
//! assigned to the neighbouring cell), and a cell whose stored mass is 0 is
//! never sampled. A cell whose weight is below about `2^-24` of its row's
//! sum can round to mass 0 (never sampled, pdf 0), as in any `f32` CDF.
//!
//! # Zero weights
//!
//! A row whose weights are all 0 gets a uniform conditional CDF; if every
//! weight is 0 the marginal is uniform too. An all-zero function therefore
//! samples uniformly (`x = u` and pdf 1, each up to the `f32` rounding of
//! `i / n`) and has integral 0: never NaN.
//!
//! # Shader rules
//!
//! [`sample_1d`], [`pdf_1d`], [`sample_2d`] and [`pdf_2d`] use `u32`/`f32`
//! arithmetic (`wrapping_*` for indices), bounded loops, no allocation and
//! no `clamp` or checked arithmetic, following rust-gpu's rules (their
//! SPIR-V build comes with the tracer's integration). They never panic: `u` is clamped to
//! `[0, ONE_MINUS_EPSILON]` (NaN reads as 0), points outside `[0, 1]` are
//! clamped to the edge cells (NaN to cell 0), a size of 0 reads as 1, and a
//! CDF entry past the end of a too-short table reads as `1.0` (the missing
//! cells get no mass; the integral reads as 0). Tables are validated by the
//! host-side builders and by [`Distribution1d::new`] /
//! [`Distribution2d::new`].

use crate::error::{Buffer, Error};
use crate::limits::MAX_DISTRIBUTION_SIDE;
use glam::{UVec2, Vec2};

/// The largest `f32` below 1 (`1 - 2^-24`): sample coordinates are clamped
/// to `[0, ONE_MINUS_EPSILON]` so they stay inside `[0, 1)`.
pub const ONE_MINUS_EPSILON: f32 = 0.999_999_94;

/// A sample of a 1D distribution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample1d {
    /// The sample, in `[0, 1)`.
    pub x: f32,
    /// Its density with respect to `[0, 1)`: `mass * n`, `> 0` for a valid table.
    pub pdf: f32,
    /// The cell it lies in, `0..n`.
    pub index: u32,
}

/// A sample of a 2D distribution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample2d {
    /// The sample, in `[0, 1)^2` (`x` along a row, `y` across rows).
    pub point: Vec2,
    /// Its density with respect to `[0, 1)^2`, `> 0` for a valid table.
    pub pdf: f32,
    /// The cell (column, row) it lies in.
    pub cell: UVec2,
}

/// Entry `i` of `table`, or `default` past its end (no panic in shaders).
#[inline]
fn read(table: &[f32], i: u32, default: f32) -> f32 {
    let i = i as usize;
    if i < table.len() {
        table[i]
    } else {
        default
    }
}

/// `u` clamped to `[0, ONE_MINUS_EPSILON]`; NaN reads as 0.
#[inline]
fn clamp_unit(u: f32) -> f32 {
    if u >= 0.0 {
        u.min(ONE_MINUS_EPSILON)
    } else {
        0.0
    }
}

/// The cell of `[0, 1)` split in `n` that contains `x`, clamped to `0..n`
/// (NaN and negative `x` give cell 0).
#[inline]
fn cell_of(x: f32, n: u32) -> u32 {
    if x > 0.0 {
        let i = (x * n as f32) as u32;
        i.min(n.wrapping_sub(1))
    } else {
        0
    }
}

/// Mass of cell `i` of the CDF stored from `start` (entries `start..start + n`).
#[inline]
fn cell_mass(table: &[f32], start: u32, i: u32) -> f32 {
    let below = if i == 0 {
        0.0
    } else {
        read(table, start.wrapping_add(i).wrapping_sub(1), 1.0)
    };
    read(table, start.wrapping_add(i), 1.0) - below
}

/// Inverts the CDF of `n` cells stored from `start`: the first cell whose
/// entry exceeds `u`, the position `t` in `[0, 1)` of `u` inside it, and its
/// mass.
#[inline]
fn invert_cdf(table: &[f32], start: u32, n: u32, u: f32) -> (u32, f32, f32) {
    let u = clamp_unit(u);
    // Binary search for the first entry > u; `len` halves each step, so 32
    // steps cover any u32 size (a side is at most 2^15).
    let mut first = 0u32;
    let mut len = n;
    let mut step = 0u32;
    while len > 0 && step < 32 {
        let half = len / 2;
        let mid = first.wrapping_add(half);
        if read(table, start.wrapping_add(mid), 1.0) <= u {
            first = mid.wrapping_add(1);
            len = len.wrapping_sub(half).wrapping_sub(1);
        } else {
            len = half;
        }
        step = step.wrapping_add(1);
    }
    // Only a corrupt table (last entry <= u) leaves `first == n`.
    let i = if first >= n { n.wrapping_sub(1) } else { first };
    let below = if i == 0 {
        0.0
    } else {
        read(table, start.wrapping_add(i).wrapping_sub(1), 1.0)
    };
    let mass = read(table, start.wrapping_add(i), 1.0) - below;
    let t = if mass > 0.0 {
        clamp_unit((u - below) / mass)
    } else {
        0.0
    };
    (i, t, mass)
}

/// `(i + t) / n`, kept below 1.
#[inline]
fn place(i: u32, t: f32, n: u32) -> f32 {
    ((i as f32 + t) / n as f32).min(ONE_MINUS_EPSILON)
}

/// Draws from the 1D distribution of `n` cells whose table is `table`
/// ([`Distribution1d`]'s layout) with the uniform number `u` in `[0, 1)`.
///
/// `n` must be the table's cell count (`table.len() - 1`); a zero `n` reads
/// as 1. Shader-ready; see the module doc for out-of-range input.
#[inline]
pub fn sample_1d(table: &[f32], n: u32, u: f32) -> Sample1d {
    let n = n.max(1);
    let (index, t, mass) = invert_cdf(table, 1, n, u);
    Sample1d {
        x: place(index, t, n),
        pdf: mass * n as f32,
        index,
    }
}

/// Density at `x` in `[0, 1)` of the 1D distribution of `n` cells whose
/// table is `table`: `mass * n` of the cell containing `x`. Identical to the
/// pdf [`sample_1d`] returns with a sample in that cell. `x` outside
/// `[0, 1)` is clamped to the edge cells (NaN to cell 0).
#[inline]
pub fn pdf_1d(table: &[f32], n: u32, x: f32) -> f32 {
    let n = n.max(1);
    cell_mass(table, 1, cell_of(x, n)) * n as f32
}

/// Draws from the 2D distribution of `width x height` cells whose table is
/// `table` ([`Distribution2d`]'s layout): `u.y` picks the row from the
/// marginal, `u.x` the column from that row's conditional, both by inverse
/// CDF with linear interpolation inside the cell.
///
/// `u` in `[0, 1)^2`; zero sides read as 1. Shader-ready; see the module doc
/// for out-of-range input.
#[inline]
pub fn sample_2d(table: &[f32], width: u32, height: u32, u: Vec2) -> Sample2d {
    let (width, height) = (width.max(1), height.max(1));
    let (row, ty, row_mass) = invert_cdf(table, 1, height, u.y);
    let start = 1u32.wrapping_add(height).wrapping_add(row.wrapping_mul(width));
    let (column, tx, column_mass) = invert_cdf(table, start, width, u.x);
    Sample2d {
        point: Vec2::new(place(column, tx, width), place(row, ty, height)),
        pdf: row_mass * height as f32 * (column_mass * width as f32),
        cell: UVec2::new(column, row),
    }
}

/// Density at `p` in `[0, 1)^2` of the 2D distribution of `width x height`
/// cells whose table is `table`. Identical to the pdf [`sample_2d`] returns
/// with a sample in that cell. Coordinates outside `[0, 1)` are clamped to
/// the edge cells (NaN to cell 0).
#[inline]
pub fn pdf_2d(table: &[f32], width: u32, height: u32, p: Vec2) -> f32 {
    let (width, height) = (width.max(1), height.max(1));
    let (column, row) = (cell_of(p.x, width), cell_of(p.y, height));
    let start = 1u32.wrapping_add(height).wrapping_add(row.wrapping_mul(width));
    cell_mass(table, 1, row) * height as f32 * (cell_mass(table, start, column) * width as f32)
}

/// Writes the normalised CDF of one row of weights into `row` (host only).
/// Returns the row's sum in `f64`.
///
/// Pass 1 stores each validated weight in `row` and sums; pass 2 replaces
/// them by their normalised prefix sums (uniform if the sum is 0). The last
/// entry is set to exactly 1.
fn write_cdf(row: &mut [f32], y: u32, mut weight: impl FnMut(u32) -> f32) -> Result<f64, Error> {
    let mut sum = 0.0f64;
    for (x, slot) in row.iter_mut().enumerate() {
        let w = weight(x as u32);
        if !(w >= 0.0 && w.is_finite()) {
            return Err(Error::Weight {
                x: x as u32,
                y,
                bits: w.to_bits(),
            });
        }
        *slot = w;
        sum += w as f64;
    }
    normalise_cdf(row, sum);
    Ok(sum)
}

/// Replaces the weights in `row` (summing to `sum`) by their normalised
/// prefix sums; a uniform CDF if `sum` is 0.
fn normalise_cdf(row: &mut [f32], sum: f64) {
    let n = row.len();
    if sum > 0.0 {
        let inv = 1.0 / sum;
        let mut prefix = 0.0f64;
        for slot in row.iter_mut() {
            prefix += *slot as f64;
            *slot = (prefix * inv).min(1.0) as f32;
        }
    } else {
        for (i, slot) in row.iter_mut().enumerate() {
            *slot = ((i + 1) as f64 / n as f64) as f32;
        }
    }
    if let Some(last) = row.last_mut() {
        *last = 1.0;
    }
}

/// Checks a distribution size (each side in `1..=MAX_DISTRIBUTION_SIDE`).
pub(crate) fn check_size(width: u32, height: u32) -> Result<(), Error> {
    if width == 0 || height == 0 || width > MAX_DISTRIBUTION_SIDE || height > MAX_DISTRIBUTION_SIDE {
        return Err(Error::DistributionSize { width, height });
    }
    Ok(())
}

/// Checks that `actual` entries are the `expected` of `buffer`.
pub(crate) fn check_len(buffer: Buffer, expected: usize, actual: usize) -> Result<(), Error> {
    if actual != expected {
        return Err(Error::BufferSize {
            buffer,
            expected,
            actual,
        });
    }
    Ok(())
}

/// A validated 1D piecewise-constant distribution: `n` cells and a table of
/// `1 + n` entries (layout in the [module doc](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Distribution1d<'a> {
    n: u32,
    table: &'a [f32],
}

impl<'a> Distribution1d<'a> {
    /// Table entries for `n` cells: `1 + n`.
    pub fn table_len(n: u32) -> usize {
        1 + n as usize
    }

    /// Builds the table of `weights` (one per cell, each finite and `>= 0`)
    /// into `table` and returns the distribution reading it.
    ///
    /// # Errors
    /// [`Error::DistributionSize`] (with `height` 1) if `weights` is empty or
    /// longer than [`MAX_DISTRIBUTION_SIDE`]; [`Error::BufferSize`] if
    /// `table.len()` is not [`Self::table_len`]`(weights.len())`;
    /// [`Error::Weight`] (with `y` 0) for the first NaN, infinite or negative
    /// weight. On error `table` may be partly written.
    pub fn build(weights: &[f32], table: &'a mut [f32]) -> Result<Self, Error> {
        let n = u32::try_from(weights.len()).unwrap_or(u32::MAX);
        check_size(n, 1)?;
        check_len(Buffer::DistributionTable, Self::table_len(n), table.len())?;
        let (head, cdf) = table.split_at_mut(1);
        let sum = write_cdf(cdf, 0, |x| weights[x as usize])?;
        head[0] = (sum / n as f64) as f32;
        Ok(Distribution1d { n, table })
    }

    /// Wraps a table built earlier (by [`Self::build`], possibly read back
    /// from a file or buffer). The entries are not checked.
    ///
    /// # Errors
    /// [`Error::DistributionSize`] if `n` is 0 or over
    /// [`MAX_DISTRIBUTION_SIDE`]; [`Error::BufferSize`] if `table.len()` is
    /// not [`Self::table_len`]`(n)`.
    pub fn new(n: u32, table: &'a [f32]) -> Result<Self, Error> {
        check_size(n, 1)?;
        check_len(Buffer::DistributionTable, Self::table_len(n), table.len())?;
        Ok(Distribution1d { n, table })
    }

    /// Number of cells.
    pub fn len(&self) -> u32 {
        self.n
    }

    /// Always false: a distribution has at least one cell.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// The table (layout in the [module doc](self)).
    pub fn table(&self) -> &'a [f32] {
        self.table
    }

    /// Integral of the step function over `[0, 1)`: the mean weight, `>= 0`.
    pub fn integral(&self) -> f32 {
        read(self.table, 0, 0.0)
    }

    /// [`sample_1d`] of this distribution.
    #[inline]
    pub fn sample(&self, u: f32) -> Sample1d {
        sample_1d(self.table, self.n, u)
    }

    /// [`pdf_1d`] of this distribution.
    #[inline]
    pub fn pdf(&self, x: f32) -> f32 {
        pdf_1d(self.table, self.n, x)
    }
}

/// A validated 2D piecewise-constant distribution: `width x height` cells
/// and a table of `1 + height + width * height` entries (layout in the
/// [module doc](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Distribution2d<'a> {
    width: u32,
    height: u32,
    table: &'a [f32],
}

impl<'a> Distribution2d<'a> {
    /// Table entries for `width x height` cells: `1 + height + width *
    /// height` (saturating; sizes over [`MAX_DISTRIBUTION_SIDE`] are rejected
    /// by the builders anyway).
    pub fn table_len(width: u32, height: u32) -> usize {
        let (w, h) = (width as usize, height as usize);
        1usize.saturating_add(h).saturating_add(w.saturating_mul(h))
    }

    /// Builds the table of the row-major `weights` (`width * height`, each
    /// finite and `>= 0`) into `table` and returns the distribution reading
    /// it.
    ///
    /// # Errors
    /// [`Error::DistributionSize`] if a side is 0 or over
    /// [`MAX_DISTRIBUTION_SIDE`]; [`Error::BufferSize`] if `weights` does
    /// not have `width * height` entries or `table` not
    /// [`Self::table_len`]`(width, height)`; [`Error::Weight`] for the first
    /// NaN, infinite or negative weight (row by row). On error `table` may be
    /// partly written.
    pub fn build(width: u32, height: u32, weights: &[f32], table: &'a mut [f32]) -> Result<Self, Error> {
        check_size(width, height)?;
        check_len(Buffer::Weights, width as usize * height as usize, weights.len())?;
        Self::build_with(width, height, table, |x, y| {
            weights[y as usize * width as usize + x as usize]
        })
    }

    /// [`Self::build`] with the weight of cell `(x, y)` given by
    /// `weight(x, y)`, called once per cell, row by row (so no weight buffer
    /// is needed).
    ///
    /// # Errors
    /// As [`Self::build`], less the weight buffer's length.
    pub fn build_with(
        width: u32,
        height: u32,
        table: &'a mut [f32],
        mut weight: impl FnMut(u32, u32) -> f32,
    ) -> Result<Self, Error> {
        check_size(width, height)?;
        check_len(
            Buffer::DistributionTable,
            Self::table_len(width, height),
            table.len(),
        )?;
        let (head, rows) = table.split_at_mut(1 + height as usize);
        let mut total = 0.0f64;
        for (y, row) in rows.chunks_exact_mut(width as usize).enumerate() {
            let y = y as u32;
            let sum = write_cdf(row, y, |x| weight(x, y))?;
            // The marginal's weight: the row's mean (proportional to its sum,
            // and finite in f32 where the sum of huge weights would not be).
            let mean = sum / width as f64;
            head[1 + y as usize] = mean as f32;
            total += mean;
        }
        head[0] = (total / height as f64) as f32;
        // Normalised by the sum of the rounded means, so the rounding of the
        // means moves the marginal's masses by at most 2^-24 relative.
        let marginal = &mut head[1..];
        let sum: f64 = marginal.iter().map(|&m| m as f64).sum();
        normalise_cdf(marginal, sum);
        Ok(Distribution2d { width, height, table })
    }

    /// Wraps a table built earlier (by [`Self::build`], possibly read back
    /// from a file or buffer). The entries are not checked.
    ///
    /// # Errors
    /// [`Error::DistributionSize`] if a side is 0 or over
    /// [`MAX_DISTRIBUTION_SIDE`]; [`Error::BufferSize`] if `table.len()` is
    /// not [`Self::table_len`]`(width, height)`.
    pub fn new(width: u32, height: u32, table: &'a [f32]) -> Result<Self, Error> {
        check_size(width, height)?;
        check_len(
            Buffer::DistributionTable,
            Self::table_len(width, height),
            table.len(),
        )?;
        Ok(Distribution2d { width, height, table })
    }

    /// Cells per row.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Rows.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The table (layout in the [module doc](self)).
    pub fn table(&self) -> &'a [f32] {
        self.table
    }

    /// Integral of the step function over `[0, 1)^2`: the mean weight, `>= 0`.
    pub fn integral(&self) -> f32 {
        read(self.table, 0, 0.0)
    }

    /// [`sample_2d`] of this distribution.
    #[inline]
    pub fn sample(&self, u: Vec2) -> Sample2d {
        sample_2d(self.table, self.width, self.height, u)
    }

    /// [`pdf_2d`] of this distribution.
    #[inline]
    pub fn pdf(&self, p: Vec2) -> f32 {
        pdf_2d(self.table, self.width, self.height, p)
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::sequences::seed::random_f32;
    use std::string::ToString;
    use std::vec::Vec;
    use std::{format, vec};

    /// Random weights in `[0, 1)`, about a quarter of them 0.
    fn random_weights(n: usize, seed: u32) -> Vec<f32> {
        (0..n as u32)
            .map(|i| {
                let w = random_f32(seed, 2 * i);
                if random_f32(seed, 2 * i + 1) < 0.25 {
                    0.0
                } else {
                    w
                }
            })
            .collect()
    }

    fn build_2d(width: u32, height: u32, weights: &[f32]) -> Vec<f32> {
        let mut table = vec![0.0; Distribution2d::table_len(width, height)];
        Distribution2d::build(width, height, weights, &mut table).unwrap();
        table
    }

    /// Distance from `x` in `[0, 1)` to the nearest edge of a grid of `n` cells.
    fn edge_distance(x: f32, n: u32) -> f32 {
        let s = x * n as f32;
        (s - libm::roundf(s)).abs() / n as f32
    }

    #[test]
    fn one_d_table_layout_samples_and_pdf() {
        let mut table = [0.0; 5];
        let d = Distribution1d::build(&[1.0, 3.0, 0.0, 4.0], &mut table).unwrap();
        assert_eq!(d.table(), &[2.0, 0.125, 0.5, 0.5, 1.0]);
        assert_eq!(d.integral(), 2.0);
        assert_eq!(
            d.sample(0.0),
            Sample1d {
                x: 0.0,
                pdf: 0.5,
                index: 0
            }
        );
        assert_eq!(
            d.sample(0.0625),
            Sample1d {
                x: 0.125,
                pdf: 0.5,
                index: 0
            }
        );
        // Cell 1 covers u in [0.125, 0.5): linear inside it.
        assert_eq!(
            d.sample(0.3125),
            Sample1d {
                x: 0.375,
                pdf: 1.5,
                index: 1
            }
        );
        // u = 0.5 skips the empty cell 2.
        assert_eq!(
            d.sample(0.5),
            Sample1d {
                x: 0.75,
                pdf: 2.0,
                index: 3
            }
        );
        assert_eq!(d.sample(0.75).x, 0.875);
        assert_eq!(
            (d.pdf(0.1), d.pdf(0.3), d.pdf(0.6), d.pdf(0.9)),
            (0.5, 1.5, 0.0, 2.0)
        );
    }

    /// The pdf returned with a sample is the pdf at its point, in 1D and 2D,
    /// on odd sizes, except within rounding of a cell edge.
    #[test]
    fn sample_and_pdf_agree() {
        let mut table = vec![0.0; 12];
        let d = Distribution1d::build(&random_weights(11, 1), &mut table).unwrap();
        let (width, height) = (7, 5);
        let weights = random_weights(35, 2);
        let table2 = build_2d(width, height, &weights);
        let d2 = Distribution2d::new(width, height, &table2).unwrap();
        let mut at_edges = 0;
        for i in 0..20_000 {
            let s = d.sample(random_f32(3, i));
            assert!(s.pdf > 0.0);
            assert_eq!(s.index, cell_of(s.x, 11));
            assert_eq!(d.pdf(s.x), s.pdf);
            let s = d2.sample(Vec2::new(random_f32(4, 2 * i), random_f32(4, 2 * i + 1)));
            assert!(s.pdf > 0.0);
            assert!(weights[(s.cell.y * width + s.cell.x) as usize] > 0.0);
            if s.cell == UVec2::new(cell_of(s.point.x, width), cell_of(s.point.y, height)) {
                assert_eq!(d2.pdf(s.point), s.pdf);
            } else {
                at_edges += 1;
                assert!(edge_distance(s.point.x, width).min(edge_distance(s.point.y, height)) < 1e-6);
            }
        }
        assert!(at_edges < 20, "{at_edges} samples moved cell");
    }

    #[test]
    fn bad_input_is_an_error() {
        let mut table = vec![0.0; Distribution2d::table_len(3, 2)];
        for (bad, x, y) in [
            (f32::NAN, 2, 0),
            (f32::INFINITY, 0, 1),
            (f32::NEG_INFINITY, 1, 1),
            (-1e-30, 2, 1),
        ] {
            let mut weights = [1.0f32; 6];
            weights[(y * 3 + x) as usize] = bad;
            let e = Distribution2d::build(3, 2, &weights, &mut table).unwrap_err();
            assert_eq!(
                e,
                Error::Weight {
                    x,
                    y,
                    bits: bad.to_bits()
                }
            );
            let message = e.to_string();
            assert!(
                message.contains(&format!("{bad}")) && message.contains(">= 0"),
                "{message}"
            );
            let mut t1 = [0.0; 4];
            let row = (y * 3) as usize..(y * 3 + 3) as usize;
            let e = Distribution1d::build(&weights[row], &mut t1).unwrap_err();
            assert_eq!(
                e,
                Error::Weight {
                    x,
                    y: 0,
                    bits: bad.to_bits()
                },
                "{bad} at row {y}"
            );
        }
        let weights = [1.0f32; 6];
        for (width, height) in [
            (0, 2),
            (3, 0),
            (MAX_DISTRIBUTION_SIDE + 1, 1),
            (1, MAX_DISTRIBUTION_SIDE + 1),
        ] {
            let e = Distribution2d::build(width, height, &weights, &mut table).unwrap_err();
            assert_eq!(e, Error::DistributionSize { width, height });
            assert!(e.to_string().contains(&format!("{width}x{height}")));
            assert!(e.to_string().contains("1..=32768"));
            assert_eq!(Distribution2d::new(width, height, &table).unwrap_err(), e);
        }
        assert_eq!(
            Distribution1d::build(&[], &mut []).unwrap_err(),
            Error::DistributionSize { width: 0, height: 1 }
        );
        assert_eq!(
            Distribution2d::build(3, 2, &weights[..5], &mut table).unwrap_err(),
            Error::BufferSize {
                buffer: Buffer::Weights,
                expected: 6,
                actual: 5
            }
        );
        let mut short = vec![0.0; 8];
        assert_eq!(
            Distribution2d::build(3, 2, &weights, &mut short).unwrap_err(),
            Error::BufferSize {
                buffer: Buffer::DistributionTable,
                expected: 9,
                actual: 8
            }
        );
        assert_eq!(
            Distribution1d::new(3, &table[..3]).unwrap_err(),
            Error::BufferSize {
                buffer: Buffer::DistributionTable,
                expected: 4,
                actual: 3
            }
        );
    }

    /// Out-of-range `u`, points, sizes and too-short tables give the
    /// documented values, never a panic or NaN.
    #[test]
    fn out_of_range_input_is_clamped() {
        let mut table = [0.0; 5];
        let d = Distribution1d::build(&[1.0, 3.0, 0.0, 4.0], &mut table).unwrap();
        assert_eq!(d.sample(f32::NAN), d.sample(0.0));
        assert_eq!(d.sample(-3.0), d.sample(0.0));
        assert_eq!(d.sample(1.0), d.sample(ONE_MINUS_EPSILON));
        assert_eq!(d.sample(f32::INFINITY).x, ONE_MINUS_EPSILON);
        assert_eq!(
            (d.pdf(-1.0), d.pdf(f32::NAN), d.pdf(1.0), d.pdf(7.0)),
            (0.5, 0.5, 2.0, 2.0)
        );
        // A zero size reads as 1; a too-short or empty table reads 1.0 past its end.
        assert_eq!(sample_1d(&table, 0, 0.3).index, 0);
        assert_eq!(
            sample_1d(&[], 4, 0.3),
            Sample1d {
                x: 0.075,
                pdf: 4.0,
                index: 0
            }
        );
        assert_eq!(pdf_1d(&[], 4, 0.9), 0.0);
        assert_eq!(pdf_1d(&table[..3], 4, 0.9), 0.0);
        let s = sample_2d(&[], 3, 2, Vec2::new(0.5, 0.5));
        assert_eq!((s.cell, s.pdf), (UVec2::ZERO, 6.0));
        let s = sample_2d(&table, 0, 0, Vec2::splat(f32::NAN));
        assert!(s.pdf.is_finite() && s.point.is_finite());
        // A corrupt table whose last entry is below u: the last cell.
        assert_eq!(sample_1d(&[0.0, 0.25, 0.5], 2, 0.75).index, 1);
        for p in [
            Vec2::NAN,
            Vec2::INFINITY,
            Vec2::NEG_INFINITY,
            Vec2::new(2.0, -1.0),
        ] {
            assert!(pdf_2d(&table, 2, 2, p).is_finite());
        }
    }
}
