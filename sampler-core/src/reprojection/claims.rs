//! The claim each pixel makes on its source (the key, its sentinel
//! [`CLAIM_NONE`], the index width) and the winners' step, shared by the CPU
//! sweeps and the GPU passes; identical on the CPU and in shaders. The rule
//! is in the [module docs](super).

#[cfg(doc)]
use super::reproject_frame;
use crate::permutation::layout::FrameParams;

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
    // (`batch.rs`, above 128 seeds) take it in f32, where `levels`
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::permutation::layout::FrameLayout;

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
