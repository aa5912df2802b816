//! The second pass of the fast path, over every block once: each block's
//! groups and cut edges, and the repair of what the plain permutation
//! (the first pass) got wrong for it.
//!
//! After the first pass, `seeds_out[π(p)]` holds `plain(p)`, the seed the
//! plain sort put at `p`. For a block of one group, `plain(p)` is the
//! feature-aware sort's seed too, so only its cut edges need work: the
//! seed at `p` must go to its chain's start instead of `π(p)` (the third
//! pass, [`walks`](super::walks)), and it is read back from `π(p)` now,
//! before anything overwrites it. For a block of several groups, the
//! grouped sort is computed and its seeds stored again at `π(p)` (uncut
//! edges) or kept for the third pass (cut edges).
//!
//! Nothing here overwrites a position another block reads back: a block
//! stores only at `π(p)` for its own uncut `p`, and reads back only at
//! `π(p)` for its own cut `p` (`π` is a bijection).

use super::cuts::{store_block, store_raster};
use super::groups::{groups_of, sort_grouped, SurfaceTest};
use super::steps::Steps;
use crate::features::surface::edge_is_cut;
use crate::features::surface::{FeatureThresholds, SurfaceFeature, NO_SURFACE};
use crate::permutation::cpu::prefetch;
use crate::permutation::dither::tile_texel;
use crate::permutation::layout::FrameParams;
use crate::permutation::retarget::RETARGET_RADIUS;
use crate::permutation::sort::{intensity_key, Intensity, MAX_BLOCK_PIXELS};
use crate::sequences::walk::walk_offset;
use glam::UVec2;

/// How far ahead of the current block, in pixels, the features of the
/// destination rows are prefetched.
const PREFETCH_AHEAD: usize = 64;

/// The inputs the second pass reads.
pub(super) struct Inputs<'a, T> {
    /// Frame geometry.
    pub params: &'a FrameParams,
    /// The frame's `π` and `π⁻¹`.
    pub steps: &'a Steps<'a>,
    /// Sort keys, `width * height`.
    pub intensities: &'a [T],
    /// Surface features, `width * height`.
    pub features: &'a [SurfaceFeature],
    /// The same-surface rule.
    pub thresholds: &'a FeatureThresholds,
    /// Dither tile values, `W * W`.
    pub tile: &'a [u32],
    /// Seeds before the permutation (padded).
    pub seeds_in: &'a [u32],
}

/// Runs the second pass for block side `B` (`N = B * B`): writes every
/// block's cut bits to `cut_words` (block order) and `raster_words`
/// (raster order), repairs `seeds_out` for blocks of
/// several groups, and lists the seeds of cut edges, in cut-bit order, in
/// `cut_seeds`. Returns how many were listed (`<= seed_count`).
#[allow(clippy::needless_range_loop)]
pub(super) fn repair_blocks<T: Intensity, const B: u32, const N: usize>(
    inputs: &Inputs<'_, T>,
    cut_words: &mut [u32],
    raster_words: &mut [u32],
    cut_seeds: &mut [u32],
    seeds_out: &mut [u32],
) -> usize {
    let params = inputs.params;
    let (w, h, pw) = (params.width, params.height, params.padded_width);
    let (wu, pwu) = (w as usize, pw as usize);
    let radius = RETARGET_RADIUS as u32;
    let thresholds = inputs.thresholds;
    let mut test = SurfaceTest::new(thresholds);
    let features = inputs.features;
    let steps = inputs.steps;
    let mut listed = 0usize;
    let blocks_x = params.blocks_x();
    for by in 0..params.blocks_y() {
        let y0 = by * B;
        let rows_interior = y0 >= radius && y0 + B + radius <= h;
        for bx in 0..blocks_x {
            let x0 = bx * B;
            let block = (by * blocks_x + bx) as usize;
            let mut dest = [0u32; N];
            if rows_interior {
                // The feature rows this block row's destinations reach first
                // (`y0 + B + radius - B ..= y0 + B - 1 + radius`) are read at
                // scattered columns, which the hardware prefetchers do not
                // follow: ask for them some blocks ahead.
                for r in y0 + radius..(y0 + B + radius).min(h) {
                    let at = r as usize * wu + x0 as usize + PREFETCH_AHEAD;
                    prefetch(features, at, false);
                }
            }
            // The cut bits, and whether the block is known to be one group.
            let (cut, one) = if rows_interior && x0 >= radius && x0 + B + radius <= w {
                // Every pixel and every destination is visible and none
                // wraps: features are read at the pixel plus its offset.
                let base = y0 as usize * wu + x0 as usize;
                // Each pixel's feature index and its destination's.
                let mut own_at = [0usize; N];
                let mut dest_at = [0usize; N];
                for r in 0..B as usize {
                    for c in 0..B as usize {
                        let i = r * B as usize + c;
                        let (x, y) = (x0 + c as u32, y0 + r as u32);
                        let (dx, dy) = steps.forward_offset(x, y);
                        own_at[i] = base + r * wu + c;
                        dest_at[i] = (y as i32 + dy) as usize * wu + (x as i32 + dx) as usize;
                        dest[i] = ((y as i32 + dy) as usize * pwu + (x as i32 + dx) as usize) as u32;
                    }
                }
                let (cut, one) = block_tests::<N>(features, &own_at, &dest_at, &mut test);
                if one && cut == 0 {
                    store_block::<N>(cut_words, block, 0);
                    store_raster::<B>(raster_words, pw, x0, y0, 0);
                    continue;
                }
                (cut, one)
            } else {
                let mut cut = 0u64;
                for i in 0..N {
                    let (x, y) = (x0 + i as u32 % B, y0 + i as u32 / B);
                    let (qx, qy) = steps.forward(x, y);
                    let (p, q) = (y * pw + x, qy * pw + qx);
                    cut |= (edge_is_cut(params, features, thresholds, p, q) as u64) << i;
                    dest[i] = q;
                }
                (cut, false)
            };
            // A split block is sorted in groups again; a block of one group
            // (known here, or found by `split_block`) keeps the plain pass's
            // order and only its cut seeds are read back.
            if one
                || !split_block::<T, B, N>(
                    inputs,
                    &mut test,
                    x0,
                    y0,
                    cut,
                    &dest,
                    cut_seeds,
                    &mut listed,
                    seeds_out,
                )
            {
                read_back::<N>(cut, &dest, cut_seeds, &mut listed, seeds_out);
            }
            store_block::<N>(cut_words, block, cut);
            store_raster::<B>(raster_words, pw, x0, y0, cut);
        }
    }
    listed
}

/// The cut bits of an interior block's edges (`features[own_at[i]]` to
/// `features[dest_at[i]]`) and whether every pixel is the same surface as
/// the first (`block_groups`' one-group test), as [`SurfaceTest::same`]
/// decides them. The usual block, whose pixels and destinations all share
/// the first pixel's id and normal encoding, needs only the depth tests
/// (or none, for `NO_SURFACE`), done branch-free over the block; any other
/// block is tested pixel by pixel.
#[inline(always)]
fn block_tests<const N: usize>(
    features: &[SurfaceFeature],
    own_at: &[usize; N],
    dest_at: &[usize; N],
    test: &mut SurfaceTest<'_>,
) -> (u64, bool) {
    let own: [SurfaceFeature; N] = core::array::from_fn(|i| features[own_at[i]]);
    let dst: [SurfaceFeature; N] = core::array::from_fn(|i| features[dest_at[i]]);
    let (id, normal) = (own[0].id, own[0].normal);
    let mut flat = true;
    for i in 0..N {
        flat &= (own[i].id == id) & (own[i].normal == normal) & (dst[i].id == id) & (dst[i].normal == normal);
    }
    if flat {
        if id == NO_SURFACE {
            return (0, true);
        }
        // `same_surface`'s depth test for equal ids and normals, in its
        // argument order (the pixel first).
        let relative = test.depth_relative();
        let close = |a: f32, b: f32| {
            let larger = if a > b { a } else { b };
            f32::from_bits((a - b).to_bits() & 0x7FFF_FFFF) <= relative * larger
        };
        let mut cut = 0u64;
        let mut one = true;
        for i in 0..N {
            cut |= (!close(own[i].depth, dst[i].depth) as u64) << i;
            one &= (i == 0) | close(own[i].depth, own[0].depth);
        }
        return (cut, one);
    }
    let mut cut = 0u64;
    let mut one = true;
    for i in 0..N {
        cut |= (!test.same(&own[i], &dst[i]) as u64) << i;
        if i > 0 {
            one &= test.same(&own[i], &own[0]);
        }
    }
    (cut, one)
}

/// A block of one group: lists the seeds of its cut edges, read back from
/// where the plain permutation put them.
#[inline(always)]
fn read_back<const N: usize>(
    cut: u64,
    dest: &[u32; N],
    cut_seeds: &mut [u32],
    listed: &mut usize,
    seeds_out: &[u32],
) {
    let mut bits = cut;
    while bits != 0 {
        let i = bits.trailing_zeros() as usize;
        bits &= bits - 1;
        cut_seeds[*listed] = seeds_out[dest[i] as usize];
        *listed += 1;
    }
}

/// The block at `(x0, y0)` if its visible pixels form several groups: its
/// grouped sort, each seed stored at `dest` (uncut) or listed (cut), and
/// `true`. `false` (nothing done) for a block of one group.
#[allow(clippy::too_many_arguments, clippy::needless_range_loop)]
#[inline(never)]
fn split_block<T: Intensity, const B: u32, const N: usize>(
    inputs: &Inputs<'_, T>,
    test: &mut SurfaceTest<'_>,
    x0: u32,
    y0: u32,
    cut: u64,
    dest: &[u32; N],
    cut_seeds: &mut [u32],
    listed: &mut usize,
    seeds_out: &mut [u32],
) -> bool {
    let params = inputs.params;
    let (w, h, pw) = (params.width, params.height, params.padded_width);
    let offset = walk_offset(params.frame, params.tile_log2);
    let mut feats = [SurfaceFeature::default(); MAX_BLOCK_PIXELS];
    let mut keys = [0u32; MAX_BLOCK_PIXELS];
    let mut dither = [0u32; MAX_BLOCK_PIXELS];
    let mut seeds = [0u32; MAX_BLOCK_PIXELS];
    let mut pixel = [0u32; MAX_BLOCK_PIXELS];
    // Seed sent from each block pixel: unsorted for padding pixels.
    let mut value = [0u32; N];
    let mut n = 0usize;
    for i in 0..N {
        let (x, y) = (x0 + i as u32 % B, y0 + i as u32 / B);
        let s = inputs.seeds_in[(y * pw + x) as usize];
        value[i] = s;
        if x < w && y < h {
            let v = (y * w + x) as usize;
            feats[n] = inputs.features[v];
            keys[n] = intensity_key(inputs.intensities[v].intensity());
            dither[n] = inputs.tile[tile_texel(UVec2::new(x, y), offset, params.tile_log2) as usize];
            seeds[n] = s;
            pixel[n] = i as u32;
            n += 1;
        }
    }
    let mut groups = [0u32; MAX_BLOCK_PIXELS];
    if groups_of(n, &feats, test, &mut groups) {
        return false;
    }
    let mut sorted = [0u32; MAX_BLOCK_PIXELS];
    if n == N {
        // A whole block: the rank loops with a constant count unroll.
        sort_grouped(N, &groups, &keys, &dither, &seeds, &mut sorted);
    } else {
        sort_grouped(n, &groups, &keys, &dither, &seeds, &mut sorted);
    }
    for j in 0..n {
        value[pixel[j] as usize] = sorted[j];
    }
    for i in 0..N {
        if cut >> i & 1 != 0 {
            cut_seeds[*listed] = value[i];
            *listed += 1;
        } else {
            seeds_out[dest[i] as usize] = value[i];
        }
    }
    true
}
