//! **Sequences**: where every random or quasi-random number comes from.
//!
//! - Low-discrepancy recurrences R1 / R2 / R_d (plastic constant), in 0.32
//!   fixed point: [`r2`] ([`r1`](crate::r1), [`r2()`](crate::r2), [`Rd`](crate::Rd)).
//! - The aperiodic toroidal offset walk of the dither tile and its steps:
//!   [`walk`] ([`walk_offset`](crate::walk_offset), [`step_index`](crate::step_index)).
//! - Pixel seeds and the counter-based random streams they define (the
//!   a-posteriori permutation moves seeds, never changes them): [`seed`]
//!   ([`initial_seed`](crate::initial_seed), [`RandomStream`](crate::RandomStream)).
//! - Sobol points ([`sobol`]), Owen scrambling by hashing ([`owen`]), and the
//!   two a-priori screen-space samplers built on them: Owen-scrambled Sobol
//!   with optimised per-pixel keys ([`screen_sobol`],
//!   [`ScreenSobolKeys::sample`](crate::ScreenSobolKeys::sample)) and
//!   Morton-ordered ZSobol ([`zsobol`], [`zsobol_sample`](crate::zsobol_sample)).
//! - A spatiotemporal a-priori sampler whose pixels each continue one
//!   progressive sequence across frames, rotated by a blue-noise shift
//!   ([`spatiotemporal`], [`spatiotemporal_pair_u32`](crate::spatiotemporal_pair_u32)),
//!   the sequence Owen-scrambled Sobol or a Kronecker sequence ([`kronecker`]).
//!
//! Everything here is `u32`/`f32` arithmetic that compiles with rust-gpu and
//! gives the same bits on the CPU and in shaders. Nothing here depends on the
//! other capabilities.

pub mod kronecker;
pub mod owen;
pub mod r2;
pub mod screen_sobol;
pub mod seed;
pub mod sobol;
pub mod spatiotemporal;
pub mod walk;
pub mod zsobol;
