//! A stack of equally sized 2D slices: a spatiotemporal mask or a sequence of frames.

use crate::metrics::error::Error;
use crate::metrics::grid::{sample_count, Grid};

/// A `width x height x depth` block of `f32` samples: `depth` slices (frames) of
/// `width x height`, each row-major, stored one after another. Sample `(x, y, z)` is at
/// `(z * height + y) * width + x`.
///
/// Invariant: all three sides are positive and `data.len() == width * height * depth`.
#[derive(Clone, Debug, PartialEq)]
pub struct Volume {
    width: usize,
    height: usize,
    depth: usize,
    data: Vec<f32>,
}

impl Volume {
    /// Wraps `data` (`depth` row-major slices, `width * height * depth` samples).
    ///
    /// # Errors
    /// [`Error::ZeroSize`] if a side is zero, [`Error::DataLength`] if the length is wrong.
    pub fn new(width: usize, height: usize, depth: usize, data: Vec<f32>) -> Result<Self, Error> {
        let expected = sample_count(width, height, depth)?;
        if data.len() != expected {
            return Err(Error::DataLength {
                expected,
                actual: data.len(),
            });
        }
        Ok(Volume {
            width,
            height,
            depth,
            data,
        })
    }

    /// A volume whose sample at `(x, y, z)` is `f(x, y, z)`, evaluated in storage order.
    ///
    /// # Errors
    /// [`Error::ZeroSize`] if a side is zero.
    pub fn from_fn(
        width: usize,
        height: usize,
        depth: usize,
        mut f: impl FnMut(usize, usize, usize) -> f32,
    ) -> Result<Self, Error> {
        let n = sample_count(width, height, depth)?;
        let mut data = Vec::with_capacity(n);
        for z in 0..depth {
            for y in 0..height {
                for x in 0..width {
                    data.push(f(x, y, z));
                }
            }
        }
        Ok(Volume {
            width,
            height,
            depth,
            data,
        })
    }

    /// Stacks `slices` in order (slice `z` of the result is `slices[z]`).
    ///
    /// # Errors
    /// [`Error::ZeroSize`] if `slices` is empty, [`Error::ShapeMismatch`] if a slice
    /// differs in size from the first.
    pub fn from_slices(slices: &[Grid]) -> Result<Self, Error> {
        let first = slices.first().ok_or(Error::ZeroSize {
            width: 0,
            height: 0,
            depth: 0,
        })?;
        let (width, height) = (first.width(), first.height());
        let mut data = Vec::with_capacity(width * height * slices.len());
        for s in slices {
            if (s.width(), s.height()) != (width, height) {
                return Err(Error::ShapeMismatch {
                    expected: [width, height, 1],
                    actual: [s.width(), s.height(), 1],
                });
            }
            data.extend_from_slice(s.data());
        }
        Ok(Volume {
            width,
            height,
            depth: slices.len(),
            data,
        })
    }

    /// Width of a slice in samples (positive).
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height of a slice in samples (positive).
    pub fn height(&self) -> usize {
        self.height
    }

    /// Number of slices (frames), positive.
    pub fn depth(&self) -> usize {
        self.depth
    }

    /// All samples in storage order (see [`Volume`]).
    pub fn data(&self) -> &[f32] {
        &self.data
    }

    /// The samples of slice `z`, row-major.
    ///
    /// # Errors
    /// [`Error::FrameIndex`] if `z >= depth`.
    pub fn slice_data(&self, z: usize) -> Result<&[f32], Error> {
        if z >= self.depth {
            return Err(Error::FrameIndex {
                frame: z,
                depth: self.depth,
            });
        }
        let n = self.width * self.height;
        Ok(&self.data[z * n..(z + 1) * n])
    }

    /// A copy of slice `z` as a [`Grid`].
    ///
    /// # Errors
    /// [`Error::FrameIndex`] if `z >= depth`.
    pub fn slice(&self, z: usize) -> Result<Grid, Error> {
        Grid::new(self.width, self.height, self.slice_data(z)?.to_vec())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slices_round_trip() {
        let v = Volume::from_fn(3, 2, 4, |x, y, z| (100 * z + 10 * y + x) as f32).unwrap();
        assert_eq!(v.slice(2).unwrap().get(1, 1), 211.0);
        let slices: Vec<Grid> = (0..4).map(|z| v.slice(z).unwrap()).collect();
        assert_eq!(Volume::from_slices(&slices).unwrap(), v);
        assert_eq!(v.slice(4), Err(Error::FrameIndex { frame: 4, depth: 4 }));
    }

    #[test]
    fn rejects_mismatched_slices() {
        let a = Grid::zeros(2, 2).unwrap();
        let b = Grid::zeros(2, 3).unwrap();
        assert_eq!(
            Volume::from_slices(&[a, b]),
            Err(Error::ShapeMismatch {
                expected: [2, 2, 1],
                actual: [2, 3, 1]
            })
        );
        assert!(Volume::new(2, 2, 2, vec![0.0; 7]).is_err());
    }
}
