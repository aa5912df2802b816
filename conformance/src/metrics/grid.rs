//! A 2D field of samples: the input of every spatial measurement.

use crate::metrics::error::Error;

/// Number of samples of a `width x height x depth` block.
///
/// # Errors
/// [`Error::ZeroSize`] if a side is zero or the product overflows `usize`.
pub(crate) fn sample_count(width: usize, height: usize, depth: usize) -> Result<usize, Error> {
    width
        .checked_mul(height)
        .and_then(|n| n.checked_mul(depth))
        .filter(|&n| n > 0)
        .ok_or(Error::ZeroSize { width, height, depth })
}

/// A `width x height` field of `f32` samples, row-major (`x` fastest), treated as one
/// period of a toroidal (wrap-around) signal by every measurement.
///
/// Invariant: `data.len() == width * height` and both sides are positive. Values are
/// unitless; masks use `[0, 1)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    width: usize,
    height: usize,
    data: Vec<f32>,
}

impl Grid {
    /// Wraps `data` (row-major, `width * height` samples).
    ///
    /// # Errors
    /// [`Error::ZeroSize`] if a side is zero, [`Error::DataLength`] if
    /// `data.len() != width * height`.
    pub fn new(width: usize, height: usize, data: Vec<f32>) -> Result<Self, Error> {
        let expected = sample_count(width, height, 1)?;
        if data.len() != expected {
            return Err(Error::DataLength {
                expected,
                actual: data.len(),
            });
        }
        Ok(Grid { width, height, data })
    }

    /// A grid of zeros.
    ///
    /// # Errors
    /// [`Error::ZeroSize`] if a side is zero.
    pub fn zeros(width: usize, height: usize) -> Result<Self, Error> {
        let n = sample_count(width, height, 1)?;
        Ok(Grid {
            width,
            height,
            data: vec![0.0; n],
        })
    }

    /// A grid whose sample at `(x, y)` is `f(x, y)`, evaluated in row-major order.
    ///
    /// # Errors
    /// [`Error::ZeroSize`] if a side is zero.
    pub fn from_fn(
        width: usize,
        height: usize,
        mut f: impl FnMut(usize, usize) -> f32,
    ) -> Result<Self, Error> {
        sample_count(width, height, 1)?;
        let data = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .map(|(x, y)| f(x, y))
            .collect();
        Ok(Grid { width, height, data })
    }

    /// A mask from exact ranks (`0..width*height`, row-major): rank `r` becomes the
    /// value `(r + 0.5) / (width * height)` in `(0, 1)`, the convention of
    /// `sampler_core::DitherTile`. Ranks need not be a permutation.
    ///
    /// # Errors
    /// As [`Grid::new`], with `ranks` as the data.
    pub fn from_ranks(width: usize, height: usize, ranks: &[u32]) -> Result<Self, Error> {
        let n = sample_count(width, height, 1)?;
        if ranks.len() != n {
            return Err(Error::DataLength {
                expected: n,
                actual: ranks.len(),
            });
        }
        let scale = 1.0 / n as f64;
        let data = ranks.iter().map(|&r| ((r as f64 + 0.5) * scale) as f32).collect();
        Ok(Grid { width, height, data })
    }

    /// Width in samples (positive).
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in samples (positive).
    pub fn height(&self) -> usize {
        self.height
    }

    /// The samples, row-major: `(x, y)` is at `y * width + x`.
    pub fn data(&self) -> &[f32] {
        &self.data
    }

    /// Mutable samples, row-major (the length cannot change).
    pub fn data_mut(&mut self) -> &mut [f32] {
        &mut self.data
    }

    /// Gives back the row-major samples.
    pub fn into_data(self) -> Vec<f32> {
        self.data
    }

    /// Sample at `(x, y)`.
    ///
    /// # Panics
    /// If `x >= width` or `y >= height`.
    pub fn get(&self, x: usize, y: usize) -> f32 {
        assert!(
            x < self.width && y < self.height,
            "({x}, {y}) outside {}x{}",
            self.width,
            self.height
        );
        self.data[y * self.width + x]
    }

    /// Arithmetic mean of the samples, accumulated in `f64`.
    pub fn mean(&self) -> f64 {
        self.data.iter().map(|&v| v as f64).sum::<f64>() / self.data.len() as f64
    }

    /// Population variance of the samples (divisor `width * height`), in `f64`.
    pub fn variance(&self) -> f64 {
        let m = self.mean();
        self.data.iter().map(|&v| (v as f64 - m).powi(2)).sum::<f64>() / self.data.len() as f64
    }

    /// Root mean square of the samples (not mean-removed), in `f64`.
    pub fn rms(&self) -> f64 {
        (self.data.iter().map(|&v| (v as f64).powi(2)).sum::<f64>() / self.data.len() as f64).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_sizes() {
        assert_eq!(
            Grid::new(0, 4, vec![]),
            Err(Error::ZeroSize {
                width: 0,
                height: 4,
                depth: 1
            })
        );
        assert_eq!(
            Grid::new(3, 2, vec![0.0; 5]),
            Err(Error::DataLength {
                expected: 6,
                actual: 5
            })
        );
        assert!(Grid::from_ranks(2, 2, &[0, 1, 2]).is_err());
    }

    #[test]
    fn from_fn_is_row_major() {
        let g = Grid::from_fn(3, 2, |x, y| (10 * y + x) as f32).unwrap();
        assert_eq!(g.data(), &[0.0, 1.0, 2.0, 10.0, 11.0, 12.0]);
        assert_eq!(g.get(2, 1), 12.0);
    }

    #[test]
    fn ranks_map_to_cell_centres() {
        let g = Grid::from_ranks(2, 2, &[3, 0, 2, 1]).unwrap();
        assert_eq!(g.data(), &[0.875, 0.125, 0.625, 0.375]);
        assert!((g.mean() - 0.5).abs() < 1e-12);
        // Variance of {1,3,5,7}/8 = 20/64 - 1/4... computed directly:
        let v: f64 = [0.875f64, 0.125, 0.625, 0.375]
            .iter()
            .map(|x| (x - 0.5).powi(2))
            .sum::<f64>()
            / 4.0;
        assert!((g.variance() - v).abs() < 1e-12);
    }
}
