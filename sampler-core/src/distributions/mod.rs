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
//! arithmetic with bounded loops and no allocation, written to rust-gpu's
//! rules (compiled to SPIR-V when the tracer integrates them), and never
//! panic. Nothing here depends on the other capabilities; `environment`
//! builds on `piecewise`, never the reverse.
//!
//! ```
//! use glam::Vec2;
//! use sampler_core::EnvironmentMap;
//! // A black 4x2 sky with one bright texel, (2, 1): u in [0.5, 0.75), below the horizon...
//! let mut rgb = [[0.0f32; 3]; 8];
//! rgb[6] = [10.0, 10.0, 10.0];
//! let mut table = vec![0.0; EnvironmentMap::table_len(4, 2)];
//! let map = EnvironmentMap::build(4, 2, &rgb, &mut table)?;
//! // ...draws every direction there, between -Z (u = 0.5) and +X (u = 0.75),
//! // with the pdf per steradian that `pdf` gives the direction.
//! let (dir, pdf) = map.sample_direction(Vec2::new(0.3, 0.7));
//! assert!(dir.y < 0.0 && dir.x >= 0.0 && dir.z <= 0.0);
//! assert!((map.pdf(dir) - pdf).abs() <= 1e-5 * pdf);
//! # Ok::<(), sampler_core::Error>(())
//! ```

pub mod environment;
pub mod piecewise;
