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
//!
//! # Rule
//!
//! For visible pixel `p = (x, y)` with backward motion `m` (pixels; its
//! point was at `(x + 0.5 + m.x, y + 0.5 + m.y)` in the previous frame), the
//! **source** is the visible pixel `q` containing that position. Every
//! pixel with a source **claims** it with the key
//! `(distance << index_bits) | index(p)`, where `distance` is the squared
//! distance from the previous position to `q`'s centre quantised to the
//! bits left above the pixel index (8 or more: [`MAX_REPROJECT_SEEDS`]).
//! Each source goes to its smallest key: the claimant whose point was
//! closest to the source's centre, ties to the smaller pixel index. A winner
//! takes its source's seed.
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
//! of prefix sums. [`reproject_frame`] runs the same three steps on the CPU.

use crate::error::{Buffer, Error};
use crate::layout::{FrameLayout, FrameParams};

/// A claims-buffer entry no pixel has claimed (and the source of a pixel
/// without one).
pub const CLAIM_NONE: u32 = u32::MAX;

/// Largest seed buffer (padded pixel count) [`reproject_frame`] accepts:
/// `2^24` (e.g. 4096 x 4096), so a claim key keeps at least 8 bits for the
/// distance above the pixel index.
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
/// outside the visible frame). Identical on the CPU and in shaders.
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
    // Squared distance in [0, 0.5], quantised to the bits above the index.
    let distance_bits = 32 - bits;
    let levels = ((1u32 << distance_bits) - 1) as f32;
    let d = ((dx * dx + dy * dy) * 2.0 * levels).min(levels) as u32;
    (qy.wrapping_mul(pw).wrapping_add(qx), (d << bits) | index)
}

/// The winners' step for seed-buffer index `index`: its source's seed if
/// its key won the claim (`claims[source] == key`), else [`CLAIM_NONE`]
/// (the pixel gets a recycled seed). `claims` holds the minimum key per
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
    let bits = index_bits(params.padded_width * params.padded_height);
    let (w, h) = (params.width as usize, params.height as usize);
    let pw = params.padded_width as usize;
    // Claim: visible pixels take the minimum key per source; padding claims itself.
    claims.fill(CLAIM_NONE);
    for (y, row) in claims.chunks_exact_mut(pw).enumerate() {
        if y >= h {
            for (x, c) in row.iter_mut().enumerate() {
                *c = (y * pw + x) as u32;
            }
        } else {
            for (x, c) in row.iter_mut().enumerate().skip(w) {
                *c = (y * pw + x) as u32;
            }
        }
    }
    for y in 0..h {
        for x in 0..w {
            let (source, key) = claim_at(&params, bits, x as u32, y as u32, motion[y * w + x]);
            if source != CLAIM_NONE && key < claims[source as usize] {
                claims[source as usize] = key;
            }
        }
    }
    // Winners take their source's seed; the k-th pixel without a seed (in
    // buffer order) takes the k-th unclaimed source's seed. There are exactly
    // as many of each (module docs).
    let mut stats = ReprojectStats::default();
    let mut free = claims
        .iter()
        .enumerate()
        .filter(|(_, &c)| c == CLAIM_NONE)
        .map(|(q, _)| q);
    for (y, row) in seeds_out.chunks_exact_mut(pw).enumerate() {
        for (x, out) in row.iter_mut().enumerate() {
            if x >= w || y >= h {
                *out = seeds_in[y * pw + x]; // padding always wins its own seed
                continue;
            }
            let (source, key) = claim_at(&params, bits, x as u32, y as u32, motion[y * w + x]);
            if let Some(seed) = take_if_won(claims, seeds_in, source, key) {
                *out = seed;
                stats.followed += 1;
            } else {
                let q = free
                    .next()
                    .expect("as many unclaimed sources as pixels without a seed");
                *out = seeds_in[q];
                stats.recycled += 1;
            }
        }
    }
    Ok(stats)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layout(w: u32, h: u32) -> FrameLayout {
        FrameLayout::new(w, h, 4, 16).unwrap()
    }

    fn run(l: &FrameLayout, motion: &[[f32; 2]]) -> alloc_free::Out {
        let n = l.seed_count();
        let mut out = alloc_free::Out::new(n);
        let seeds = alloc_free::Out::iota(n);
        let mut claims = alloc_free::Out::new(n);
        out.stats = reproject_frame(
            l,
            motion,
            seeds.as_slice(),
            claims.as_mut_slice(),
            out.as_mut_slice(),
        )
        .unwrap();
        out
    }

    /// Fixed-capacity buffers: this crate is `no_std` without `alloc` in tests too.
    mod alloc_free {
        pub const CAP: usize = 48 * 48;
        pub struct Out {
            pub data: [u32; CAP],
            pub len: usize,
            pub stats: super::ReprojectStats,
        }
        impl Out {
            pub fn new(len: usize) -> Self {
                assert!(len <= CAP);
                Out {
                    data: [0; CAP],
                    len,
                    stats: Default::default(),
                }
            }
            pub fn iota(len: usize) -> Self {
                let mut o = Self::new(len);
                for (i, v) in o.data[..len].iter_mut().enumerate() {
                    *v = i as u32 * 7 + 3;
                }
                o
            }
            pub fn as_slice(&self) -> &[u32] {
                &self.data[..self.len]
            }
            pub fn as_mut_slice(&mut self) -> &mut [u32] {
                &mut self.data[..self.len]
            }
        }
    }

    fn is_permutation(out: &[u32]) -> bool {
        let mut seen = [false; alloc_free::CAP];
        out.iter().all(|&s| {
            let i = ((s - 3) / 7) as usize;
            (s - 3) % 7 == 0 && i < out.len() && !core::mem::replace(&mut seen[i], true)
        })
    }

    #[test]
    fn zero_motion_is_the_identity() {
        let l = layout(20, 13);
        let motion = [[0.0f32; 2]; 20 * 13];
        let out = run(&l, &motion);
        assert_eq!(out.as_slice(), alloc_free::Out::iota(l.seed_count()).as_slice());
        assert_eq!(
            out.stats,
            ReprojectStats {
                followed: 260,
                recycled: 0
            }
        );
    }

    #[test]
    fn a_uniform_shift_moves_seeds_and_recycles_the_uncovered_edge() {
        let l = layout(20, 13);
        // The picture moved 2 px right: every pixel's point was 2 px to its left.
        let motion = [[-2.0f32, 0.0]; 20 * 13];
        let out = run(&l, &motion);
        let seeds = alloc_free::Out::iota(l.seed_count());
        let pw = l.padded_width() as usize;
        for y in 0..13 {
            for x in 2..20 {
                assert_eq!(out.as_slice()[y * pw + x], seeds.as_slice()[y * pw + x - 2]);
            }
        }
        assert_eq!(
            out.stats,
            ReprojectStats {
                followed: 18 * 13,
                recycled: 2 * 13
            }
        );
        assert!(is_permutation(out.as_slice()));
    }

    #[test]
    fn adversarial_fields_stay_permutations() {
        let l = layout(23, 17);
        let n = 23 * 17;
        let mut motion = [[0.0f32; 2]; 23 * 17];
        let fields: [fn(u32, u32) -> [f32; 2]; 6] = [
            |x, y| [11.0 - x as f32, 8.0 - y as f32], // all to one source
            |_, _| [f32::NAN, f32::NAN],              // nothing valid
            |x, y| [(y as f32 - 8.0) * 0.3, -(x as f32 - 11.0) * 0.3], // rotation
            |x, y| [(x as f32 - 11.0) * -0.5, (y as f32 - 8.0) * -0.5], // zoom
            |x, _| [if x % 3 == 0 { f32::INFINITY } else { 0.4 }, -0.6],
            |x, y| [1e30 * (x as f32 - y as f32), 0.0],
        ];
        for field in fields {
            for (i, m) in motion.iter_mut().enumerate().take(n) {
                *m = field(i as u32 % 23, i as u32 / 23);
            }
            let out = run(&l, &motion);
            assert!(is_permutation(out.as_slice()));
            assert_eq!(out.stats.followed + out.stats.recycled, n as u32);
        }
    }

    #[test]
    fn the_closest_claimant_wins_then_the_smaller_index() {
        let params = layout(8, 8).params(0);
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
    fn bad_buffers_are_errors() {
        let l = layout(8, 8);
        let n = l.seed_count();
        let seeds = alloc_free::Out::iota(n);
        let mut out = alloc_free::Out::new(n);
        let mut claims = alloc_free::Out::new(n);
        let motion = [[0.0f32; 2]; 63];
        assert!(matches!(
            reproject_frame(
                &l,
                &motion,
                seeds.as_slice(),
                claims.as_mut_slice(),
                out.as_mut_slice()
            ),
            Err(Error::BufferSize {
                buffer: Buffer::Motion,
                expected: 64,
                actual: 63
            })
        ));
    }
}
