//! Seeds that follow the picture: a bijective reprojection of the seed
//! buffer along backward motion vectors.
//!
//! The permutation leaves seeds laid out for frame `t`'s screen. When the
//! camera or objects move, a seed left at its pixel samples another surface
//! next frame; reprojection moves each seed to where its surface went, so
//! it keeps sampling the surface it was sorted on. Run it between the
//! permutation of frame `t` and the trace of frame `t + 1`, with frame
//! `t + 1`'s backward motion vectors (from a primary-visibility pass).
//!
//! # Invariant
//!
//! The output is a **permutation** of the input seed buffer: every seed of
//! the input appears exactly once in the output, so no seed is duplicated
//! (duplicates make correlated, visible error) and every pixel has one.
//! It rests on every claim key being below [`CLAIM_NONE`] (see the
//! quantisation below), so that a claims entry equal to [`CLAIM_NONE`]
//! means "unclaimed" and nothing else.
//!
//! # Rule
//!
//! For visible pixel `p = (x, y)` with backward motion `m` (pixels; its
//! point was at `(x + 0.5 + m.x, y + 0.5 + m.y)` in the previous frame), the
//! **source** is the visible pixel `q` containing that position. Every
//! pixel with a source **claims** it with the key
//! `(distance << index_bits) | index(p)` ([`index_bits`] bits of pixel
//! index), where `distance` is the squared distance from the previous
//! position to `q`'s centre, in `[0, 0.5]`, scaled to `[0, levels]` and
//! truncated, with `levels = 2^(32 - index_bits) - 2`: one level below the
//! largest the bits above the index hold, so the largest key (distance
//! 0.5 at the last index of a buffer of exactly `2^k` seeds, a point on a
//! pixel corner) is `2^32 - 2^index_bits - 1`, below [`CLAIM_NONE`]. With
//! [`MAX_REPROJECT_SEEDS`] seeds 8 bits of distance remain: levels 0 to
//! 254. Each source goes to its smallest key: the claimant whose point was
//! closest to the source's centre (to the quantisation), ties to the
//! smaller pixel index. A winner takes its source's seed.
//!
//! Pixels without a seed then: losers of a claim, pixels whose motion is
//! not finite (mark disoccluded pixels with NaN motion: the caller's depth
//! test decides), and pixels whose previous position lies outside the
//! visible frame. Seeds without a pixel: sources nobody claimed. There are
//! exactly as many of each (`N` pixels, `N` seeds, winners and claimed
//! sources in one-to-one correspondence), and the `k`-th pixel without a
//! seed (in buffer order) takes the seed of the `k`-th unclaimed source (in
//! buffer order): recycled seeds, which appear nowhere else. Padding seeds
//! (outside the visible frame, [`crate::permutation::layout`]) claim their own position
//! with distance 0 and no visible pixel claims them, so they stay put.
//!
//! # GPU form
//!
//! The claim step is one `atomicMin` per pixel on a claims buffer cleared to
//! [`CLAIM_NONE`] ([`claim`] computes the source and key); the winners' step
//! is a per-pixel comparison ([`take_if_won`]); the recycling step is a pair
//! of prefix sums ([`crate::reprojection::passes`], or per seed for hardware
//! GPUs: [`crate::reprojection::seed_passes`]).
//!
//! # CPU form
//!
//! [`reproject_frame`] runs the same three steps, the same output bit for
//! bit, in one sweep over the motion vectors while no claim reaches more
//! than 16 rows (`sweep.rs`, which documents the traffic floor),
//! else in two (`two_sweeps.rs`); both compute the keys of 16
//! pixels side by side (`batch.rs`), with AVX2 where the CPU has
//! it. `tests.rs` checks every path against the first version.
//! The figures are in `BENCHMARKS.md`.
//!
//! The seeds moved need not be seeds: the spatiotemporal sampler's homes
//! (`crate::sequences::spatiotemporal::home_of_pixel`) travel the same way.

mod batch;
mod claims;
mod frame;
pub mod passes;
mod ring;
pub mod seed_passes;
mod sweep;
#[cfg(test)]
mod tests;
mod two_sweeps;

pub use claims::{claim, claim_at, index_bits, take_if_won, ReprojectStats, CLAIM_NONE, MAX_REPROJECT_SEEDS};
pub use frame::reproject_frame;
