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
//! (outside the visible frame, [`crate::layout`]) claim their own position
//! with distance 0 and no visible pixel claims them, so they stay put.
//!
//! # GPU form
//!
//! The claim step is one `atomicMin` per pixel on a claims buffer cleared to
//! [`CLAIM_NONE`] ([`claim`] computes the source and key); the winners' step
//! is a per-pixel comparison ([`take_if_won`]); the recycling step is a pair
//! of prefix sums ([`crate::reproject_passes`]).
//!
//! # CPU form
//!
//! [`reproject_frame`] runs the same three steps, the same output bit for
//! bit, in one sweep over the motion vectors while no claim reaches more
//! than 16 rows (`reproject_sweep.rs`, which documents the traffic floor),
//! else in two (`reproject_two_sweeps.rs`); both compute the keys of 16
//! pixels side by side (`reproject_batch.rs`), with AVX2 where the CPU has
//! it. `reproject_tests.rs` checks every path against the first version.
//! The figures are in `BENCHMARKS.md`.

use crate::error::{Buffer, Error};
use crate::layout::{FrameLayout, FrameParams};
use crate::reproject_sweep::reproject_one_sweep;
use crate::reproject_two_sweeps::reproject_two_sweeps;

/// A claims-buffer entry no pixel has claimed (and the source of a pixel
/// without one). No claim key equals it (module docs, "Rule").
pub const CLAIM_NONE: u32 = u32::MAX;

/// Largest seed buffer (padded pixel count) [`reproject_frame`] accepts:
/// `2^24` (e.g. 4096 x 4096), so a claim key keeps 8 bits for the distance
/// above the pixel index (levels 0 to 254, module docs).
pub const MAX_REPROJECT_SEEDS: usize = 1 << 24;

/// Number of bits of a pixel index in a claim key of a buffer of
/// `seed_count` seeds: `ceil(log2(seed_count))`, at least 1.
#[inline]
pub fn index_bits(seed_count: u32) -> u32 {
    let n = if seed_count < 2 { 2 } else { seed_count };
    32 - (n - 1).leading_zeros()
}

/// The source and claim key of seed-buffer index `index` (row-major in the
/// padded buffer of `params`) with backward motion `motion` (pixels; any
/// value for padding indices). Returns `(CLAIM_NONE, CLAIM_NONE)` for a
/// visible pixel without a source (non-finite motion, previous position
/// outside the visible frame); any other key is below [`CLAIM_NONE`].
/// Identical on the CPU and in shaders.
#[inline]
pub fn claim(params: &FrameParams, index: u32, motion: [f32; 2]) -> (u32, u32) {
    let pw = params.padded_width;
    let bits = index_bits(pw.wrapping_mul(params.padded_height));
    claim_at(params, bits, index % pw, index / pw, motion)
}

/// [`claim`] for pixel `(x, y)` with the index width `bits` =
/// [`index_bits`]`(padded_width * padded_height)` precomputed.
#[inline]
pub fn claim_at(params: &FrameParams, bits: u32, x: u32, y: u32, motion: [f32; 2]) -> (u32, u32) {
    let pw = params.padded_width;
    let index = y.wrapping_mul(pw).wrapping_add(x);
    if x >= params.width || y >= params.height {
        // Padding: stays, distance 0.
        return (index, index);
    }
    let px = x as f32 + 0.5 + motion[0];
    let py = y as f32 + 0.5 + motion[1];
    // Comparisons are false for NaN, so NaN and infinities fail.
    let inside = px >= 0.0 && py >= 0.0 && px < params.width as f32 && py < params.height as f32;
    if !inside {
        return (CLAIM_NONE, CLAIM_NONE);
    }
    let qx = (px as u32).min(params.width - 1);
    let qy = (py as u32).min(params.height - 1);
    let dx = px - (qx as f32 + 0.5);
    let dy = py - (qy as f32 + 0.5);
    // Squared distance in [0, 0.5] scaled to [0, levels], one level below
    // the largest the bits above the index hold, so that no key equals
    // `CLAIM_NONE`. The minimum is taken on the integer: with at most 64
    // seeds `levels` (2^26 - 2 or more) is not exact in f32 and rounds up
    // to 2^(32 - bits), which would shift out of the key. The batched keys
    // (`reproject_batch.rs`, above 128 seeds) take it in f32, where `levels`
    // is exact and both minima agree.
    let levels = (1u32 << (32 - bits)) - 2;
    let d = (((dx * dx + dy * dy) * 2.0 * levels as f32) as u32).min(levels);
    (qy.wrapping_mul(pw).wrapping_add(qx), (d << bits) | index)
}

/// The winners' step for seed-buffer index `index`: its source's seed if
/// its key won the claim (`claims[source] == key`), else `None` (the
/// pixel gets a recycled seed). `claims` holds the minimum key per
/// source after every pixel's claim.
#[inline]
pub fn take_if_won(claims: &[u32], seeds_in: &[u32], source: u32, key: u32) -> Option<u32> {
    if source != CLAIM_NONE && claims[source as usize] == key {
        Some(seeds_in[source as usize])
    } else {
        None
    }
}

/// What one [`reproject_frame`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReprojectStats {
    /// Visible pixels that took their source's seed.
    pub followed: u32,
    /// Visible pixels that took a recycled seed (no source, or lost the claim).
    pub recycled: u32,
}

/// Reprojects `seeds_in` (laid out for the previous frame's screen) along
/// frame `t + 1`'s backward motion vectors into `seeds_out` (see the module
/// docs for the rule); `claims` is scratch. The output is a permutation of
/// the input.
///
/// `motion` holds one `[dx, dy]` per visible pixel, row-major,
/// `width * height` entries, in pixels (raster `y` down): where the pixel's
/// point was in the previous frame minus the pixel's centre. NaN marks a
/// pixel whose point was not visible (disocclusion).
///
/// # Panics
/// Never for valid input: the recycling step relies on the invariant that
/// unclaimed sources and pixels without a seed are equally many (module
/// docs); a panic there is a bug.
///
/// # Errors
/// [`Error::BufferSize`] when a buffer's length does not match the layout
/// (`seeds_in`, `seeds_out`, `claims`: `seed_count`; `motion`:
/// `pixel_count`); [`Error::FrameSize`] when the padded frame has more than
/// [`MAX_REPROJECT_SEEDS`] seeds.
///
/// # Example
///
/// The camera panned 3 pixels to the left: every pixel's surface was 3 pixels
/// to its right in the previous frame (backward motion `+3`), so seeds follow.
///
/// ```
/// use sampler_core::{reproject_frame, FrameLayout};
/// let layout = FrameLayout::new(32, 16, 4, 16)?;
/// let n = layout.seed_count();
/// let motion = vec![[3.0f32, 0.0]; 32 * 16];
/// let seeds: Vec<u32> = (0..n as u32).collect();
/// let (mut claims, mut next) = (vec![0; n], vec![0; n]);
/// let stats = reproject_frame(&layout, &motion, &seeds, &mut claims, &mut next)?;
/// assert_eq!(next[5], seeds[8]); // pixel (5, 0) takes the seed of (8, 0)
/// assert!(stats.recycled > 0);  // the right edge had no source: recycled seeds
/// let mut check = next.clone();
/// check.sort();
/// assert_eq!(check, seeds); // never a duplicated seed
/// # Ok::<(), sampler_core::Error>(())
/// ```
pub fn reproject_frame(
    layout: &FrameLayout,
    motion: &[[f32; 2]],
    seeds_in: &[u32],
    claims: &mut [u32],
    seeds_out: &mut [u32],
) -> Result<ReprojectStats, Error> {
    let n = layout.seed_count();
    if n > MAX_REPROJECT_SEEDS {
        return Err(Error::FrameSize {
            width: layout.width(),
            height: layout.height(),
        });
    }
    layout.check_seed_buffer(Buffer::SeedsIn, seeds_in.len())?;
    layout.check_seed_buffer(Buffer::SeedsOut, seeds_out.len())?;
    layout.check_seed_buffer(Buffer::Claims, claims.len())?;
    if motion.len() != layout.pixel_count() {
        return Err(Error::BufferSize {
            buffer: Buffer::Motion,
            expected: layout.pixel_count(),
            actual: motion.len(),
        });
    }
    let params = layout.params(0);
    Ok(reproject_one_sweep(&params, motion, seeds_in, claims, seeds_out)
        .unwrap_or_else(|| reproject_two_sweeps(&params, motion, seeds_in, claims, seeds_out)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params(w: u32, h: u32, tile: u32) -> FrameParams {
        FrameLayout::new(w, h, 2, tile).unwrap().params(0)
    }

    #[test]
    fn the_closest_claimant_wins_then_the_smaller_index() {
        let params = params(8, 8, 16);
        // Pixel 1 lands 0.1 px from source 0's centre, pixel 2 0.3 px: pixel 1 wins.
        let (s1, k1) = claim(&params, 1, [-1.1, 0.0]);
        let (s2, k2) = claim(&params, 2, [-2.3, 0.0]);
        assert_eq!((s1, s2), (0, 0));
        assert!(k1 < k2);
        // Equal distances: the smaller index.
        let (_, a) = claim(&params, 3, [-3.0, 0.0]);
        let (_, b) = claim(&params, 4, [-4.0, 0.0]);
        assert!(a < b);
        // Outside the visible frame, or NaN: no source.
        assert_eq!(claim(&params, 0, [-0.6, 0.0]), (CLAIM_NONE, CLAIM_NONE));
        assert_eq!(claim(&params, 0, [f32::NAN, 0.0]), (CLAIM_NONE, CLAIM_NONE));
        assert_eq!(index_bits(1), 1);
        assert_eq!(index_bits(256), 8);
        assert_eq!(index_bits(257), 9);
    }

    #[test]
    fn the_largest_key_is_below_claim_none_and_the_largest_distance() {
        // Buffers of exactly 2^k seeds without padding (the last index is
        // all ones), from 2 seeds to MAX_REPROJECT_SEEDS, and padded ones.
        let sizes = [
            (1, 2, 2),
            (2, 2, 2),
            (4, 4, 4),
            (8, 8, 8),
            (8, 16, 16),
            (16, 16, 16),
            (64, 64, 64),
            (256, 256, 64),
            (4096, 4096, 64),
            (5, 3, 2),
            (1920, 1080, 64),
        ];
        for (w, h, tile) in sizes {
            let p = params(w, h, tile);
            let bits = index_bits(p.seed_count());
            let levels = (1u32 << (32 - bits)) - 2;
            // The last visible pixel, its point exactly on the corner of its
            // own square: squared distance 0.5, the largest.
            let (s, k) = claim_at(&p, bits, w - 1, h - 1, [-0.5, -0.5]);
            let last = (h - 1) * p.padded_width + w - 1;
            assert_eq!((s, k), (last, (levels << bits) | last), "{w}x{h}");
            assert!(k < CLAIM_NONE, "{w}x{h}");
            // ...which loses to any closer point, and beats no point closer.
            let (_, centre) = claim_at(&p, bits, w - 1, h - 1, [0.0, 0.0]);
            assert!(centre < k, "{w}x{h}");
            if w > 1 {
                let (s2, k2) = claim_at(&p, bits, w - 2, h - 1, [0.6, -0.4]);
                assert_eq!(s2, last, "{w}x{h}");
                assert!(k2 < k, "{w}x{h}");
            }
            // Every corner of every pixel of a 2^k buffer, at most 2^16 pixels.
            if p.seed_count() <= 1 << 16 {
                for y in 0..h {
                    for x in 0..w {
                        for m in [[-0.5, -0.5], [0.5, 0.5], [-0.5, 0.5], [0.5, -0.5]] {
                            let (s, k) = claim_at(&p, bits, x, y, m);
                            assert!(s == CLAIM_NONE || k >> bits == levels, "{w}x{h} ({x}, {y})");
                        }
                    }
                }
            }
        }
        // 8 bits of distance with the most seeds: levels 0 to 254.
        assert_eq!((1u32 << (32 - index_bits(MAX_REPROJECT_SEEDS as u32))) - 2, 254);
    }
}
