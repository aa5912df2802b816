//! **Distributions**: importance sampling of tabulated functions, as
//! `no_std`, allocation-free math.
//!
//! - Piecewise-constant distributions on `[0, 1)` and `[0, 1)^2` (marginal
//!   over rows, conditional per row), built into caller-provided `f32`
//!   tables and sampled by inverse CDF: [`piecewise`]
//!   ([`Distribution1d`](crate::Distribution1d),
//!   [`Distribution2d`](crate::Distribution2d)).
//! - Importance sampling of an equirectangular environment map by
//!   luminance times `sin(theta)`, with directions and pdfs per steradian
//!   (+Y up, rotation about +Y in turns): [`environment`]
//!   ([`EnvironmentMap`](crate::EnvironmentMap),
//!   [`sample_environment`](environment::sample_environment),
//!   [`pdf_environment`](environment::pdf_environment)).
//!
//! The builders are host code; sampling and pdf functions are `u32`/`f32`
//! arithmetic with bounded loops that compiles with rust-gpu and never
//! panics. Nothing here depends on the other capabilities; `environment`
//! builds on `piecewise`, never the reverse.

pub mod environment;
pub mod piecewise;
