//! The third pass: every seed whose edge is cut goes to the start of its
//! chain, found by walking `π⁻¹` back along uncut edges, refreshed when the
//! chain is its own position alone
//! ([`retarget_features_pixel`](crate::features::permute::retarget_features_pixel)).
//!
//! A walk reads only the frame's inverse table and the cut bits (an
//! eighth of a byte a seed: 256 KiB at 1080p, cache-resident), never the
//! features. Walks are long (on a typical frame their lengths add up to
//! about one step per seed, since the table's cycles are long and nearly
//! all are cut somewhere) and each step depends on the last, so
//! [`WALKS`] of them advance side by side: the steps of different walks
//! overlap in the pipeline instead of waiting on each other.

use super::cuts::is_set;
use super::steps::Steps;
use crate::features::isolated::refresh_isolated_seed;

/// Walks in flight at once (12 and 24 measured alike at 1080p).
const WALKS: usize = 12;

/// One walk in flight: its current position, the seed it carries, and
/// whether it has left its first position (a walk that has not ends at a
/// chain of one position, whose seed is refreshed).
#[derive(Clone, Copy)]
struct Walk {
    x: u32,
    y: u32,
    seed: u32,
    live: bool,
    moved: bool,
}

/// The cut seeds, in cut-bit order, with their positions.
struct CutSeeds<'a> {
    words: &'a [u32],
    seeds: &'a [u32],
    /// Index of the current word and its bits not yet taken.
    word: usize,
    bits: u32,
    /// Seeds taken so far.
    taken: usize,
}

impl CutSeeds<'_> {
    /// The next cut seed as `(bit index, seed)`.
    #[inline(always)]
    fn next(&mut self) -> Option<(usize, u32)> {
        while self.bits == 0 {
            self.word += 1;
            if self.word >= self.words.len() {
                return None;
            }
            self.bits = self.words[self.word];
        }
        let bit = self.word * 32 + self.bits.trailing_zeros() as usize;
        self.bits &= self.bits - 1;
        let seed = self.seeds[self.taken];
        self.taken += 1;
        Some((bit, seed))
    }
}

/// Sends each of the `cut_seeds` (listed in cut-bit order by the second
/// pass in the order of the block-order bits `cut_words`) to its chain's
/// start in `seeds_out`, testing the raster bits `raster_words`; `B` is the
/// block side, `N = B * B`, `blocks_x` the blocks a row.
pub(super) fn walk_chains<const B: u32, const N: usize>(
    steps: &Steps<'_>,
    padded_width: u32,
    blocks_x: u32,
    cut_words: &[u32],
    raster_words: &[u32],
    cut_seeds: &[u32],
    seeds_out: &mut [u32],
) {
    let (n_log2, b_log2) = (N.trailing_zeros(), B.trailing_zeros());
    let mut source = CutSeeds {
        words: cut_words,
        seeds: cut_seeds,
        word: 0,
        bits: cut_words.first().copied().unwrap_or(0),
        taken: 0,
    };
    let position = |bit: usize| {
        let (block, i) = ((bit >> n_log2) as u32, bit as u32 & (N as u32 - 1));
        let (bx, by) = (block % blocks_x, block / blocks_x);
        ((bx << b_log2) | (i & (B - 1)), (by << b_log2) | (i >> b_log2))
    };
    let mut walks = [Walk {
        x: 0,
        y: 0,
        seed: 0,
        live: false,
        moved: false,
    }; WALKS];
    let mut exhausted = false;
    loop {
        let mut any = false;
        for walk in walks.iter_mut() {
            if !walk.live {
                if exhausted {
                    continue;
                }
                match source.next() {
                    Some((bit, seed)) => {
                        let (x, y) = position(bit);
                        *walk = Walk {
                            x,
                            y,
                            seed,
                            live: true,
                            moved: false,
                        };
                    }
                    None => {
                        exhausted = true;
                        continue;
                    }
                }
            }
            any = true;
            let (rx, ry) = steps.inverse(walk.x, walk.y);
            if is_set(raster_words, (ry * padded_width + rx) as usize) {
                seeds_out[(walk.y * padded_width + walk.x) as usize] = if walk.moved {
                    walk.seed
                } else {
                    refresh_isolated_seed(walk.seed)
                };
                walk.live = false;
            } else {
                walk.x = rx;
                walk.y = ry;
                walk.moved = true;
            }
        }
        if !any {
            break;
        }
    }
}
