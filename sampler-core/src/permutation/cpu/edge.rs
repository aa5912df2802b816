//! The reference form of one block's sort + retarget, writing only the
//! seeds that land in a band: every block of a band whose layout the fast
//! path does not cover (the fast path's own clipped and padding blocks take
//! `sort_edge_block` in [`gather`](super::gather), into its ring).

use super::{wrap, Band};
use crate::permutation::dither::tile_texel;
use crate::permutation::layout::FrameParams;
use crate::permutation::retarget::{unpack_offset, RETARGET_RADIUS};
use crate::permutation::sort::{intensity_key, sort_block, Intensity, MAX_BLOCK_PIXELS};
use crate::sequences::walk::walk_offset;
use glam::UVec2;

/// Sorting + retargeting of block `(bx, by)`: the reference sort
/// ([`sort_block`]) of its visible pixels, then every seed of the block
/// (padding included) goes to its retargeted place if that lies in `band`.
/// With the whole frame as the band this is `frame::permute_block`; a block
/// with no visible pixel (the padding) skips the sort.
#[allow(clippy::too_many_arguments)]
pub(super) fn permute_block_in_band<T: Intensity>(
    params: &FrameParams,
    bx: u32,
    by: u32,
    intensities: &[T],
    tile: &[u32],
    packed: &[u32],
    seeds_in: &[u32],
    band: Band,
    seeds_out: &mut [u32],
) {
    let offset = walk_offset(params.frame, params.tile_log2);
    let (pw, ph) = (params.padded_width, params.padded_height);
    let mut keys = [0u32; MAX_BLOCK_PIXELS];
    let mut dither = [0u32; MAX_BLOCK_PIXELS];
    let mut seeds = [0u32; MAX_BLOCK_PIXELS];
    let mut pos = [UVec2::ZERO; MAX_BLOCK_PIXELS];
    let mut len = 0usize;
    let (x0, y0) = (bx * params.block, by * params.block);
    // `retarget_destination` without its divisions: offsets are at most
    // RETARGET_RADIUS, so beyond that size the wrap is one add or subtract.
    let wrap_any = |v: i32, m: u32| {
        if m as i32 > RETARGET_RADIUS {
            wrap(v, m)
        } else {
            v.rem_euclid(m as i32) as u32
        }
    };
    let mut put = |p: UVec2, seed: u32| {
        let d = unpack_offset(packed[tile_texel(p, offset, params.tile_log2) as usize]);
        let (x, y) = (wrap_any(p.x as i32 + d.x, pw), wrap_any(p.y as i32 + d.y, ph));
        if let Some(at) = band.index(pw, x, y) {
            seeds_out[at] = seed;
        }
    };
    if x0 >= params.width || y0 >= params.height {
        for y in y0..(y0 + params.block).min(ph) {
            for x in x0..(x0 + params.block).min(pw) {
                put(UVec2::new(x, y), seeds_in[(y * pw + x) as usize]);
            }
        }
        return;
    }
    for y in y0..(y0 + params.block).min(ph) {
        for x in x0..(x0 + params.block).min(pw) {
            let p = UVec2::new(x, y);
            let s = seeds_in[(y * pw + x) as usize];
            if x < params.width && y < params.height {
                keys[len] = intensity_key(intensities[(y * params.width + x) as usize].intensity());
                dither[len] = tile[tile_texel(p, offset, params.tile_log2) as usize];
                seeds[len] = s;
                pos[len] = p;
                len += 1;
            } else {
                put(p, s);
            }
        }
    }
    let mut sorted = [0u32; MAX_BLOCK_PIXELS];
    sort_block(len as u32, &keys, &dither, &seeds, &mut sorted);
    for i in 0..len {
        put(pos[i], sorted[i]);
    }
}
