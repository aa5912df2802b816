//! The one error type of the measurement library.

use std::fmt;

/// Everything that can be wrong with the input of a measurement. Carries the numbers.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// A sample buffer does not hold `width * height` (or `width * height * depth`) values.
    DataLength {
        /// Required number of samples.
        expected: usize,
        /// Number of samples passed.
        actual: usize,
    },
    /// A width, height or depth is zero (or their product overflows `usize`).
    ZeroSize {
        /// Requested width in samples.
        width: usize,
        /// Requested height in samples.
        height: usize,
        /// Requested depth in slices (1 for a 2D grid).
        depth: usize,
    },
    /// Two inputs that must have the same shape do not, e.g. a frame appended to a
    /// volume. Shapes are `[width, height, depth]`.
    ShapeMismatch {
        /// Shape the operation requires.
        expected: [usize; 3],
        /// Shape passed.
        actual: [usize; 3],
    },
    /// A numeric parameter is outside its documented range (a non-positive blur sigma,
    /// an EMA factor outside `(0, 1]`, zero thresholds, a NaN).
    Parameter {
        /// Name of the parameter as spelled in the API.
        name: &'static str,
        /// The value passed.
        value: f64,
    },
    /// A frame index is not below the depth of the volume it indexes.
    FrameIndex {
        /// Requested frame (slice) index.
        frame: usize,
        /// Number of frames (slices) available.
        depth: usize,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Error::DataLength { expected, actual } => {
                write!(f, "sample buffer holds {actual} values, expected {expected}")
            }
            Error::ZeroSize { width, height, depth } => {
                write!(
                    f,
                    "invalid size {width}x{height}x{depth}: every side must be positive"
                )
            }
            Error::ShapeMismatch { expected, actual } => write!(
                f,
                "shape mismatch: expected {}x{}x{}, got {}x{}x{}",
                expected[0], expected[1], expected[2], actual[0], actual[1], actual[2]
            ),
            Error::Parameter { name, value } => write!(f, "parameter `{name}` out of range: {value}"),
            Error::FrameIndex { frame, depth } => {
                write!(f, "frame {frame} out of range for a volume of {depth} frames")
            }
        }
    }
}

impl std::error::Error for Error {}
