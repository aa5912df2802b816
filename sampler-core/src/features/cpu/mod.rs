//! The CPU fast path of
//! [`permute_frame_features`](crate::permute_frame_features), used where the
//! plain fast path applies (`B` in {2, 4, 8} dividing a tile of 16 to 128
//! texels a side). Output is identical, bit for bit, to the reference
//! ([`permute_frame_features_reference`](crate::features::permute::permute_frame_features_reference)),
//! for every input.
//!
//! Three passes over the frame:
//!
//! 1. **The plain permutation** ([`permute_frame`](crate::permute_frame)'s
//!    fused fast path, unchanged): right for every block of one group and
//!    every uncut edge, the usual case.
//! 2. **Repair, block by block** ([`blocks`]): reads each pixel's feature
//!    once (the pass's main cost: 16 bytes a pixel, more than the seeds and
//!    intensities together), tests whether the block is one group (every
//!    pixel the same surface as its first, as `block_groups` does) and
//!    which of its seeds' edges are cut (the destination's feature is a
//!    few pixels away, in cache). A block of one group with no cut edge is
//!    done. Split blocks are sorted in groups again ([`groups`]); the cut
//!    edges are recorded as bits (`N` a block, [`cuts`]) and their seeds
//!    listed for pass 3.
//! 3. **Chain starts** ([`walks`]): each listed seed walks `π⁻¹` back along
//!    uncut edges to its chain's start and is stored there. `π⁻¹` comes
//!    from the tile's inverse table ([`steps`]), exact by construction, so
//!    the inverse is never scattered into a frame-sized buffer, and the
//!    walk reads cut bits, not features.
//!
//! The caller's scratch buffers hold the cut bits (`sources`, two bits a
//! seed: [`cuts`]) and the listed seeds (`sorted`, one `u32` a cut edge); their
//! contents afterwards are unspecified.

mod blocks;
mod cuts;
mod groups;
mod steps;
mod walks;

use crate::features::step::FeatureStep;
use crate::permutation::layout::FrameParams;
use crate::permutation::sort::Intensity;
use blocks::{repair_blocks, Inputs};
use steps::{Steps, MAX_TILE};

/// True when the fast path applies to `params` (the plain fast path's
/// condition: `B` a power of two dividing the tile side, `16 <= W <= 128`).
pub(crate) fn applies(params: &FrameParams) -> bool {
    let w = 1u32 << params.tile_log2;
    crate::permutation::cpu::applies(params) && w <= MAX_TILE
}

/// The feature-aware permutation of a frame on the CPU (see the module
/// docs). Buffers are those of `permute_frame_features`, already checked;
/// `applies(params)` must hold. `sources` needs `seed_count / 16` words,
/// `sorted` one word per cut edge (at most `seed_count`).
pub(crate) fn permute_features_fast<T: Intensity>(
    step: &FeatureStep<'_, T>,
    seeds_in: &[u32],
    sorted: &mut [u32],
    sources: &mut [u32],
    seeds_out: &mut [u32],
) {
    let FeatureStep {
        ref params,
        intensities,
        features,
        thresholds,
        tile,
        table,
    } = *step;
    debug_assert!(applies(params));
    crate::permutation::cpu::permute_blocks_cached(params, intensities, tile, table, seeds_in, seeds_out);
    let steps = Steps::new(params, table);
    let inputs = Inputs {
        params,
        steps: &steps,
        intensities,
        features,
        thresholds,
        tile,
        seeds_in,
    };
    let count = cuts::word_count(params.seed_count() as usize);
    let (words, rest) = sources.split_at_mut(count);
    let raster = &mut rest[..count];
    let (pw, blocks_x) = (params.padded_width, params.blocks_x());
    match params.block {
        2 => {
            let listed = repair_blocks::<T, 2, 4>(&inputs, words, raster, sorted, seeds_out);
            walks::walk_chains::<2, 4>(&steps, pw, blocks_x, words, raster, &sorted[..listed], seeds_out);
        }
        4 => {
            let listed = repair_blocks::<T, 4, 16>(&inputs, words, raster, sorted, seeds_out);
            walks::walk_chains::<4, 16>(&steps, pw, blocks_x, words, raster, &sorted[..listed], seeds_out);
        }
        _ => {
            let listed = repair_blocks::<T, 8, 64>(&inputs, words, raster, sorted, seeds_out);
            walks::walk_chains::<8, 64>(&steps, pw, blocks_x, words, raster, &sorted[..listed], seeds_out);
        }
    }
}
