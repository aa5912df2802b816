//! The CPU fast path of [`permute_frame`](crate::permute_frame), used when
//! the block side divides the tile side (`B` in {2, 4, 8}) and the tile has
//! 16 to 128 texels a side.
//!
//! Output is identical to the per-block reference ([`sort_block`](crate::sort_block)
//! followed by [`retarget_pixel`](crate::retarget_pixel)); the speed comes from:
//!
//! - **Dither order and retarget offsets cached per frame.** With `B | W`,
//!   screen block `(bx, by)` reads the tile window starting at
//!   `((bx mod W/B) B + o_t) mod W`, so there are only `(W/B)^2` distinct
//!   windows per frame. For each, the pixel of dither rank `k` and that
//!   pixel's retarget offset are resolved once per frame into a stack array
//!   of `W * W` offset pairs (32 KiB for W = 128).
//! - **Branch-free ranks.** Each full block ranks its intensity keys by
//!   all-pairs counting over a fixed-size array, which vectorises.
//! - **No division.** Positions come from shifts; the toroidal wrap
//!   (`|offset| <= B + 6 < W <= padded size`) is one conditional add.
//!
//! Blocks clipped by the frame edge take the reference path.

use crate::dither::tile_texel;
use crate::frame::permute_block;
use crate::layout::FrameParams;
use crate::retarget::{unpack_offset, RetargetTable};
use crate::sort::{intensity_key, Intensity};
use crate::walk::walk_offset;
use glam::UVec2;

/// Largest tile side the cached dither order supports.
const MAX_CACHED_TILE: u32 = 128;
/// Smallest tile side: offsets (|d| <= 6) must wrap at most once.
const MIN_CACHED_TILE: u32 = 16;

/// True when [`permute_blocks_cached`] applies to `params`.
pub(crate) fn applies(params: &FrameParams) -> bool {
    let w = 1u32 << params.tile_log2;
    params.block.is_power_of_two()
        && w % params.block == 0
        && (MIN_CACHED_TILE..=MAX_CACHED_TILE).contains(&w)
}

/// Sorting + retargeting of a whole frame; see the module docs.
pub(crate) fn permute_blocks_cached<T: Intensity>(
    params: &FrameParams,
    intensities: &[T],
    tile: &[u32],
    table: RetargetTable<'_>,
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) {
    match params.block {
        2 => permute_full_blocks::<T, 2, 4>(params, intensities, tile, table, seeds_in, seeds_out),
        4 => permute_full_blocks::<T, 4, 16>(params, intensities, tile, table, seeds_in, seeds_out),
        _ => permute_full_blocks::<T, 8, 64>(params, intensities, tile, table, seeds_in, seeds_out),
    }
}

/// [`permute_blocks_cached`] for block side `B` (`N = B * B` pixels).
fn permute_full_blocks<T: Intensity, const B: u32, const N: usize>(
    params: &FrameParams,
    intensities: &[T],
    tile: &[u32],
    table: RetargetTable<'_>,
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) {
    let log2 = params.tile_log2;
    let w = 1u32 << log2;
    let b_log2 = B.trailing_zeros();
    let classes = w / B;
    let offset = walk_offset(params.frame, log2);
    let (pw, ph) = (params.padded_width, params.padded_height);
    let packed = table.packed();

    // Per window class and dither rank k: where, relative to the block's
    // origin, the seed of intensity rank k ends up after the sort (the
    // pixel of dither rank k) and the retarget scatter (its table offset).
    let mut dest = [(0i8, 0i8); (MAX_CACHED_TILE * MAX_CACHED_TILE) as usize];
    let mut keys = [0u64; N];
    for cy in 0..classes {
        for cx in 0..classes {
            for i in 0..N as u32 {
                let p = UVec2::new(cx * B + (i & (B - 1)), cy * B + (i >> b_log2));
                keys[i as usize] = ((tile[tile_texel(p, offset, log2) as usize] as u64) << 6) | i as u64;
            }
            insertion_sort(&mut keys);
            let base = ((cy * classes + cx) as usize) * N;
            for k in 0..N {
                let j = (keys[k] & 63) as u32;
                let (jx, jy) = (j & (B - 1), j >> b_log2);
                let t = tile_texel(UVec2::new(cx * B + jx, cy * B + jy), offset, log2);
                let d = unpack_offset(packed[t as usize]);
                dest[base + k] = ((jx as i32 + d.x) as i8, (jy as i32 + d.y) as i8);
            }
        }
    }

    let full_x = params.width / B; // blocks fully inside the visible frame
    let full_y = params.height / B;
    let mut block_keys = [0u32; N];
    for by in 0..params.blocks_y() {
        for bx in 0..params.blocks_x() {
            if bx >= full_x || by >= full_y {
                permute_block(params, bx, by, intensities, tile, packed, seeds_in, seeds_out);
                continue;
            }
            let (x0, y0) = (bx * B, by * B);
            let mut seeds = [0u32; N];
            for r in 0..B as usize {
                // One bounds check per block row.
                let at = (y0 as usize + r) * params.width as usize + x0 as usize;
                let row = &intensities[at..at + B as usize];
                let s_at = (y0 as usize + r) * pw as usize + x0 as usize;
                let s_row = &seeds_in[s_at..s_at + B as usize];
                for c in 0..B as usize {
                    block_keys[r * B as usize + c] = intensity_key(row[c].intensity());
                    seeds[r * B as usize + c] = s_row[c];
                }
            }
            let ranks = block_ranks(&block_keys);
            let class = (((by & (classes - 1)) * classes + (bx & (classes - 1))) as usize) * N;
            for (i, &r) in ranks.iter().enumerate() {
                let (ox, oy) = dest[class + (r as usize & (N - 1))];
                let nx = wrap(x0 as i32 + ox as i32, pw);
                let ny = wrap(y0 as i32 + oy as i32, ph);
                seeds_out[(ny * pw + nx) as usize] = seeds[i];
            }
        }
    }
}

/// `v mod m` for `v` in `-m..2m` (one conditional add or subtract).
#[inline(always)]
fn wrap(v: i32, m: u32) -> u32 {
    let m = m as i32;
    (if v < 0 {
        v + m
    } else if v >= m {
        v - m
    } else {
        v
    }) as u32
}

/// Rank of each key in the block's total order (key, then index): branch-free
/// all-pairs counting, which the compiler vectorises for fixed `N`.
#[inline(always)]
fn block_ranks<const N: usize>(keys: &[u32; N]) -> [u8; N] {
    let mut ranks = [0u8; N];
    for i in 0..N {
        let ki = keys[i];
        let mut r = 0u32;
        for (j, &kj) in keys.iter().enumerate() {
            r += (kj < ki) as u32 + ((kj == ki) & (j < i)) as u32;
        }
        ranks[i] = r as u8;
    }
    ranks
}

/// Insertion sort, ascending.
#[inline]
fn insertion_sort(v: &mut [u64]) {
    for i in 1..v.len() {
        let x = v[i];
        let mut j = i;
        while j > 0 && v[j - 1] > x {
            v[j] = v[j - 1];
            j -= 1;
        }
        v[j] = x;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn block_ranks_follow_key_then_index() {
        let mut state = 12345u32;
        for _ in 0..500 {
            let mut keys = [0u32; 16];
            for k in keys.iter_mut() {
                state = crate::seed::hash_u32(state);
                *k = state % 5; // many ties
            }
            let ranks = block_ranks(&keys);
            let mut order: [usize; 16] = core::array::from_fn(|i| i);
            order.sort_by_key(|&i| (keys[i], i));
            for (r, &i) in order.iter().enumerate() {
                assert_eq!(ranks[i] as usize, r);
            }
        }
    }
}
