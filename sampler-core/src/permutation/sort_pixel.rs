//! The sorting pass one seed at a time, in two passes: the form for GPUs.
//!
//! [`sort_block_at_offset`](crate::sort_block_at_offset) sorts a whole block
//! in one call: on a GPU that is one invocation per block (a sixteenth of the
//! pixels at the default 4x4 block) walking `O(n^2)` comparisons over local
//! arrays, which hardware GPUs keep in slow scratch memory. The same
//! permutation, bit for bit, splits into two passes of one invocation per
//! seed, each `O(n)` with no local array:
//!
//! 1. [`sort_rank_pixel`]: a visible pixel counts the block's pixels whose
//!    [`intensity_key`] ranks below its own (ties by in-block index, as
//!    [`sort_block`](crate::sort_block)), and writes its seed to the block's
//!    *slot* of that rank in a scratch buffer `ranked`.
//! 2. [`sort_gather_pixel`]: a visible position counts the block's positions
//!    whose dither value ranks below its own, and takes the seed in the slot of
//!    that rank.
//!
//! So the seed of the pixel whose intensity has rank `k` moves to the position
//! whose dither value has rank `k`: the sorting pass's definition
//! ([`sort`](super::sort)). A block's visible pixels are a rectangle `w x h`
//! (the frame's edge may cut it); in-block index `i` is row-major inside it,
//! and the slot of rank `r` is the visible position of in-block index `r`
//! (`x0 + r mod w`, `y0 + r / w`). Seeds in the padding are not sorted: the
//! first pass copies them into `ranked` at their own index, the second copies
//! them on. Both passes write every index of their output exactly once.
//!
//! The rank pass does not read the tile: one `ranked` buffer serves any tile
//! and offset (the walk's tile or a temporal slice).
//!
//! # Groups
//!
//! The feature-aware sort ([`crate::features::sort_pixel`]) sorts each group
//! of one surface inside a block on its own: ranks ordered by `(group, key,
//! index)` and `(group, dither, index)`, as
//! [`sort_block_grouped`](crate::features::permute::sort_block_grouped). Both
//! passes take the groups as a [`PixelGroups`]; a plain `u32` (every pixel in
//! that one group) is the plain sort.

use super::dither::tile_texel;
use super::layout::FrameParams;
use super::sort::{intensity_key, Intensity};
use glam::UVec2;

/// Each visible pixel's group inside its block, by padded-buffer index.
/// Groups order the ranks: a lower group's pixels rank first.
pub trait PixelGroups {
    /// The group of the visible pixel at padded-buffer index `seed_index`.
    fn group(&self, seed_index: u32) -> u32;
}

/// Every pixel in this one group: the plain sorting pass. (A `u32`, not a
/// unit struct: naga rejects the empty struct rust-gpu would emit.)
impl PixelGroups for u32 {
    #[inline]
    fn group(&self, _seed_index: u32) -> u32 {
        *self
    }
}

/// A buffer of groups indexed by padded-buffer index (`seed_count` long;
/// entries of padding positions are not read).
impl PixelGroups for [u32] {
    #[inline]
    fn group(&self, seed_index: u32) -> u32 {
        self[seed_index as usize]
    }
}

/// The visible rectangle of the block holding padded position `(x, y)`:
/// its corner `(x0, y0)` and size `(w, h)`, both `>= 1` for a visible pixel.
#[inline]
pub(crate) fn visible_block(params: &FrameParams, x: u32, y: u32) -> (u32, u32, u32, u32) {
    let x0 = x - x % params.block;
    let y0 = y - y % params.block;
    let w = if params.width - x0 < params.block {
        params.width - x0
    } else {
        params.block
    };
    let h = if params.height - y0 < params.block {
        params.height - y0
    } else {
        params.block
    };
    (x0, y0, w, h)
}

/// Padded-buffer index of the slot of rank `rank` in the block at `(x0, y0)`
/// whose visible rectangle is `w` wide.
#[inline]
fn slot(params: &FrameParams, x0: u32, y0: u32, w: u32, rank: u32) -> usize {
    ((y0 + rank / w) * params.padded_width + x0 + rank % w) as usize
}

/// Pass 1 of the two-pass sort, for padded-buffer index `seed_index`
/// (`< params.seed_count()`): writes `seeds_in[seed_index]` into `ranked` at
/// the slot of its pixel's intensity rank inside its block (module docs), or
/// at `seed_index` itself for a seed in the padding. `intensities` is
/// `width * height` row-major; `seeds_in` and `ranked` are
/// `params.seed_count()` long. Over all indices, `ranked` is written once
/// each.
#[inline]
pub fn sort_rank_pixel<T: Intensity>(
    params: &FrameParams,
    seed_index: u32,
    intensities: &[T],
    seeds_in: &[u32],
    ranked: &mut [u32],
) {
    sort_rank_pixel_in_groups(params, seed_index, intensities, &0u32, seeds_in, ranked);
}

/// [`sort_rank_pixel`] within `groups`: ranks ordered by `(group, key,
/// index)`, so each group's seeds land on the slots its positions' ranks
/// take in [`sort_gather_pixel_in_groups`] with the same groups.
#[inline]
pub fn sort_rank_pixel_in_groups<T: Intensity, G: PixelGroups + ?Sized>(
    params: &FrameParams,
    seed_index: u32,
    intensities: &[T],
    groups: &G,
    seeds_in: &[u32],
    ranked: &mut [u32],
) {
    let x = seed_index % params.padded_width;
    let y = seed_index / params.padded_width;
    if x >= params.width || y >= params.height {
        ranked[seed_index as usize] = seeds_in[seed_index as usize];
        return;
    }
    let (x0, y0, w, h) = visible_block(params, x, y);
    let own = intensity_key(intensities[(y * params.width + x) as usize].intensity());
    let own_group = groups.group(seed_index);
    let own_index = (y - y0) * w + (x - x0);
    let mut rank = 0u32;
    for dy in 0..h {
        let row = (y0 + dy) * params.width + x0;
        let seed_row = (y0 + dy) * params.padded_width + x0;
        for dx in 0..w {
            let key = intensity_key(intensities[(row + dx) as usize].intensity());
            let group = groups.group(seed_row + dx);
            let index = dy * w + dx;
            let below = key < own || (key == own && index < own_index);
            if group < own_group || (group == own_group && below) {
                rank += 1;
            }
        }
    }
    ranked[slot(params, x0, y0, w, rank)] = seeds_in[seed_index as usize];
}

/// Pass 2 of the two-pass sort, for padded-buffer index `seed_index`:
/// `seeds_out[seed_index]` = the seed in the slot of this position's dither
/// rank inside its block, the dither tile (`W x W`, row-major) read at tile
/// offset `offset` (each component in `0..W`) as
/// [`sort_block_at_offset`](crate::sort_block_at_offset) reads it; a seed in
/// the padding is copied from `ranked[seed_index]`. After
/// [`sort_rank_pixel`] over every index, this over every index writes what
/// `sort_block_at_offset` over every block writes.
#[inline]
pub fn sort_gather_pixel(
    params: &FrameParams,
    offset: UVec2,
    seed_index: u32,
    tile: &[u32],
    ranked: &[u32],
    seeds_out: &mut [u32],
) {
    sort_gather_pixel_in_groups(params, offset, seed_index, tile, &0u32, ranked, seeds_out);
}

/// [`sort_gather_pixel`] within `groups`: ranks ordered by `(group, dither,
/// index)` (after [`sort_rank_pixel_in_groups`] with the same groups).
#[inline]
pub fn sort_gather_pixel_in_groups<G: PixelGroups + ?Sized>(
    params: &FrameParams,
    offset: UVec2,
    seed_index: u32,
    tile: &[u32],
    groups: &G,
    ranked: &[u32],
    seeds_out: &mut [u32],
) {
    let x = seed_index % params.padded_width;
    let y = seed_index / params.padded_width;
    if x >= params.width || y >= params.height {
        seeds_out[seed_index as usize] = ranked[seed_index as usize];
        return;
    }
    let (x0, y0, w, h) = visible_block(params, x, y);
    let own = tile[tile_texel(UVec2::new(x, y), offset, params.tile_log2) as usize];
    let own_group = groups.group(seed_index);
    let own_index = (y - y0) * w + (x - x0);
    let mut rank = 0u32;
    for dy in 0..h {
        let seed_row = (y0 + dy) * params.padded_width + x0;
        for dx in 0..w {
            let value = tile[tile_texel(UVec2::new(x0 + dx, y0 + dy), offset, params.tile_log2) as usize];
            let group = groups.group(seed_row + dx);
            let index = dy * w + dx;
            let below = value < own || (value == own && index < own_index);
            if group < own_group || (group == own_group && below) {
                rank += 1;
            }
        }
    }
    seeds_out[seed_index as usize] = ranked[slot(params, x0, y0, w, rank)];
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::{sort_block_at_offset, DitherTile, FrameLayout};
    use std::vec;
    use std::vec::Vec;

    /// Both passes over every index against the per-block sort over every
    /// block, on a frame whose edges cut blocks, with tied and NaN keys.
    #[test]
    fn two_passes_equal_the_block_sort() {
        for (width, height, block) in [
            (21u32, 13u32, 4u32),
            (16, 16, 2),
            (9, 30, 8),
            (64, 3, 4),
            (17, 13, 3),
            (50, 20, 5),
            (7, 7, 7),
        ] {
            let layout = FrameLayout::new(width, height, block, 16).unwrap();
            let params = layout.params(0);
            let tile_values: Vec<u32> = (0..256u32).map(|i| i.wrapping_mul(2_654_435_761) >> 24).collect();
            let tile = DitherTile::new(16, &tile_values).unwrap();
            let intensities: Vec<f32> = (0..width * height)
                .map(|i| match i % 11 {
                    0 => f32::NAN,
                    1 | 2 => 0.5,
                    _ => (i.wrapping_mul(747_796_405) >> 9) as f32 * 1e-6,
                })
                .collect();
            let seeds: Vec<u32> = (0..params.seed_count()).map(|i| i ^ 0x9e37_79b9).collect();
            for offset in [UVec2::new(0, 0), UVec2::new(5, 11)] {
                let mut expected = vec![0u32; seeds.len()];
                for by in 0..params.blocks_y() {
                    for bx in 0..params.blocks_x() {
                        sort_block_at_offset(
                            &params,
                            offset,
                            bx,
                            by,
                            &intensities,
                            tile.values(),
                            &seeds,
                            &mut expected,
                        );
                    }
                }
                let mut ranked = vec![u32::MAX; seeds.len()];
                for s in 0..params.seed_count() {
                    sort_rank_pixel(&params, s, &intensities, &seeds, &mut ranked);
                }
                let mut out = vec![u32::MAX; seeds.len()];
                for s in 0..params.seed_count() {
                    sort_gather_pixel(&params, offset, s, tile.values(), &ranked, &mut out);
                }
                assert_eq!(out, expected, "{width}x{height}, block {block}, offset {offset}");
            }
        }
    }
}
