//! Conformance and quality measurement for the blue-noise seed permutation.
//!
//! The tests live in `tests/`; this library holds what they share.
