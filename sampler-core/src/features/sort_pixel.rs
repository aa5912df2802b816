//! The feature-aware sorting pass one seed at a time, in three passes: the
//! form for GPUs.
//!
//! [`sort_block_features_at_offset`](crate::features::permute::sort_block_features_at_offset)
//! groups a block's pixels by surface (union-find over [`same_surface`]
//! pairs) and sorts each group in one call per block. The same seeds, bit for
//! bit, come from three passes of one invocation per seed:
//!
//! 1. [`surface_group_pixel`]: a visible pixel finds its group, the smallest
//!    in-block index connected to it by a chain of [`same_surface`] pairs (a
//!    search over the block's pixels, `O(n)` tests when the block is one
//!    surface, at most `O(n^2)`), and writes it to `groups`;
//! 2. [`sort_rank_pixel_in_groups`](crate::sort_rank_pixel_in_groups) with
//!    those groups;
//! 3. [`sort_gather_pixel_in_groups`](crate::sort_gather_pixel_in_groups) with
//!    the same groups.
//!
//! A pair's test reads its two features in the order the union-find reads
//! them (the larger in-block index first), so the groups are the union-find's
//! whatever [`same_surface`] does with its arguments' order.

use crate::features::surface::{same_surface, FeatureThresholds, SurfaceFeature};
use crate::permutation::layout::FrameParams;
use crate::permutation::sort_pixel::visible_block;

/// Whether bit `i` (`< 64`) of the two-word set `(lo, hi)` is set.
#[inline]
fn has(lo: u32, hi: u32, i: u32) -> bool {
    if i < 32 {
        lo & (1 << i) != 0
    } else {
        hi & (1 << (i - 32)) != 0
    }
}

/// `(lo, hi)` with bit `i` (`< 64`) set.
#[inline]
fn with(lo: u32, hi: u32, i: u32) -> (u32, u32) {
    if i < 32 {
        (lo | 1 << i, hi)
    } else {
        (lo, hi | 1 << (i - 32))
    }
}

/// `(lo, hi)` with bit `i` (`< 64`) cleared.
#[inline]
fn without(lo: u32, hi: u32, i: u32) -> (u32, u32) {
    if i < 32 {
        (lo & !(1 << i), hi)
    } else {
        (lo, hi & !(1 << (i - 32)))
    }
}

/// Pass 1 of the feature-aware per-seed sort, for padded-buffer index
/// `seed_index`: for a visible pixel, `groups[seed_index]` = the smallest
/// in-block index (row-major inside the block's visible rectangle) of a
/// pixel connected to it by [`same_surface`] pairs under `thresholds`, as
/// [`block_groups`](crate::features::permute::block_groups) computes it.
/// `features` is `width * height` row-major; `groups` is `seed_count` long;
/// padding entries are left as they are.
#[inline]
pub fn surface_group_pixel(
    params: &FrameParams,
    seed_index: u32,
    features: &[SurfaceFeature],
    thresholds: &FeatureThresholds,
    groups: &mut [u32],
) {
    let x = seed_index % params.padded_width;
    let y = seed_index / params.padded_width;
    if x >= params.width || y >= params.height {
        return;
    }
    let (x0, y0, w, h) = visible_block(params, x, y);
    let n = w * h;
    // The feature index of in-block index `i`.
    let at = |i: u32| ((y0 + i / w) * params.width + x0 + i % w) as usize;
    let own = (y - y0) * w + (x - x0);
    // Depth-first search: `reached` holds the pixels found, `todo` those whose
    // neighbours are still to be tested.
    let (mut reached_lo, mut reached_hi) = with(0, 0, own);
    let (mut todo_lo, mut todo_hi) = (reached_lo, reached_hi);
    let mut found = 1u32;
    while (todo_lo | todo_hi) != 0 && found < n {
        let mut j = 0u32;
        while !has(todo_lo, todo_hi, j) {
            j += 1;
        }
        (todo_lo, todo_hi) = without(todo_lo, todo_hi, j);
        let fj = features[at(j)];
        for k in 0..n {
            if !has(reached_lo, reached_hi, k) {
                let fk = features[at(k)];
                let same = if j > k {
                    same_surface(&fj, &fk, thresholds)
                } else {
                    same_surface(&fk, &fj, thresholds)
                };
                if same {
                    (reached_lo, reached_hi) = with(reached_lo, reached_hi, k);
                    (todo_lo, todo_hi) = with(todo_lo, todo_hi, k);
                    found += 1;
                }
            }
        }
    }
    let mut smallest = 0u32;
    while !has(reached_lo, reached_hi, smallest) {
        smallest += 1;
    }
    groups[seed_index as usize] = smallest;
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::features::permute::sort_block_features_at_offset;
    use crate::{sort_gather_pixel_in_groups, sort_rank_pixel_in_groups, DitherTile, FrameLayout};
    use glam::UVec2;
    use std::vec;
    use std::vec::Vec;

    /// Features with several surfaces per block: ids in bands, depth jumps,
    /// creases, background, and chains whose pixels connect only through
    /// others.
    fn features(width: u32, height: u32, salt: u32) -> Vec<SurfaceFeature> {
        (0..width * height)
            .map(|i| {
                let (x, y) = (i % width, i / width);
                let h = (i ^ salt).wrapping_mul(0x9e37_79b9).rotate_left(7);
                let id = match h % 9 {
                    0 => crate::NO_SURFACE,
                    1 | 2 => 2,
                    _ => 1 + (x / 3 + y / 5) % 2,
                };
                // Depth ramps along x by 4% a pixel: neighbours join, pixels
                // two apart need the one between (a chain).
                let depth = 1.0 + 0.04 * (x % 7) as f32 + if h.is_multiple_of(13) { 5.0 } else { 0.0 };
                let normal =
                    glam::Vec3::new(if h.is_multiple_of(11) { 1.0 } else { 0.0 }, 1.0, 0.0).normalize();
                SurfaceFeature::new(id, depth, normal)
            })
            .collect()
    }

    /// The three passes over every index against the per-block feature-aware
    /// sort over every block: frames cut by their edges, blocks 2 to 8.
    #[test]
    fn three_passes_equal_the_block_sort() {
        let thresholds = FeatureThresholds {
            depth_relative: 0.05,
            normal_cos: 0.9,
        };
        for (width, height, block) in [
            (21u32, 13u32, 4u32),
            (16, 16, 2),
            (19, 30, 8),
            (50, 20, 5),
            (17, 13, 3),
        ] {
            let layout = FrameLayout::new(width, height, block, 16).unwrap();
            let params = layout.params(0);
            let tile_values: Vec<u32> = (0..256u32).map(|i| i.wrapping_mul(2_654_435_761) >> 24).collect();
            let tile = DitherTile::new(16, &tile_values).unwrap();
            let f = features(width, height, block);
            let intensities: Vec<f32> = (0..width * height)
                .map(|i| {
                    if i % 7 == 0 {
                        0.5
                    } else {
                        (i.wrapping_mul(747_796_405) >> 9) as f32 * 1e-6
                    }
                })
                .collect();
            let seeds: Vec<u32> = (0..params.seed_count()).map(|i| i ^ 0x9e37_79b9).collect();
            let offset = UVec2::new(5, 11);
            let mut expected = vec![0u32; seeds.len()];
            for by in 0..params.blocks_y() {
                for bx in 0..params.blocks_x() {
                    sort_block_features_at_offset(
                        &params,
                        offset,
                        bx,
                        by,
                        &intensities,
                        &f,
                        &thresholds,
                        tile.values(),
                        &seeds,
                        &mut expected,
                    );
                }
            }
            let mut groups = vec![0u32; seeds.len()];
            for s in 0..params.seed_count() {
                surface_group_pixel(&params, s, &f, &thresholds, &mut groups);
            }
            let several = (0..params.seed_count()).any(|s| groups[s as usize] != 0);
            assert!(several, "{width}x{height}: the features must split some block");
            let mut ranked = vec![u32::MAX; seeds.len()];
            for s in 0..params.seed_count() {
                sort_rank_pixel_in_groups(&params, s, &intensities, &groups[..], &seeds, &mut ranked);
            }
            let mut out = vec![u32::MAX; seeds.len()];
            for s in 0..params.seed_count() {
                sort_gather_pixel_in_groups(
                    &params,
                    offset,
                    s,
                    tile.values(),
                    &groups[..],
                    &ranked,
                    &mut out,
                );
            }
            assert_eq!(out, expected, "{width}x{height}, block {block}");
        }
    }
}
