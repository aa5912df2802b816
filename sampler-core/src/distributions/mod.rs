//! **Distributions**: importance sampling of tabulated functions, as
//! `no_std`, allocation-free math.
//!
//! - Piecewise-constant distributions on `[0, 1)` and `[0, 1)^2` (marginal
//!   over rows, conditional per row), built into caller-provided `f32`
//!   tables and sampled by inverse CDF: [`piecewise`]
//!   ([`Distribution1d`](crate::Distribution1d),
//!   [`Distribution2d`](crate::Distribution2d)).
//!
//! The builders are host code; sampling and pdf functions are `u32`/`f32`
//! arithmetic with bounded loops that compiles with rust-gpu and never
//! panics. Nothing here depends on the other capabilities.

pub mod piecewise;
