//! The CPU fast path of [`permute_frame`](crate::permute_frame), used when
//! the block side divides the tile side (`B` in {2, 4, 8}) and the tile has
//! 16 to 128 texels a side.
//!
//! Output is identical to the per-block reference ([`sort_block`](crate::sort_block)
//! followed by [`retarget_pixel`](crate::retarget_pixel)); the speed comes from:
//!
//! - **Dither order cached per frame.** With `B | W`, screen block `(bx, by)`
//!   reads the tile window starting at `((bx mod W/B) B + o_t) mod W`, so
//!   there are only `(W/B)^2` distinct windows per frame. Their in-block
//!   order by dither value is sorted once per frame into a stack array of
//!   `W * W` bytes (16 KiB for W = 128).
//! - **Branch-free intensity sort.** Each full block sorts `(key << 6) | index`
//!   `u64`s with a sorting network (`B * B` is a power of two).
//! - **No division.** Positions come from shifts; the toroidal wrap of a
//!   retarget offset (`|d| <= 6 < W <= padded size`) is one conditional add.
//!
//! Blocks clipped by the frame edge take the reference path.

use crate::dither::tile_texel;
use crate::layout::FrameParams;
use crate::retarget::{unpack_offset, RetargetTable};
use crate::sort::{intensity_key, sort_block, Intensity, MAX_BLOCK_PIXELS};
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
    let log2 = params.tile_log2;
    let w = 1u32 << log2;
    let mask = w - 1;
    let b = params.block;
    let b_log2 = b.trailing_zeros();
    let n = (b * b) as usize;
    let classes = w / b;
    let offset = walk_offset(params.frame, log2);
    let (pw, ph) = (params.padded_width, params.padded_height);
    let packed = table.packed();

    // order[(cy * classes + cx) * n + k] = in-block index with dither rank k.
    let mut order = [0u8; (MAX_CACHED_TILE * MAX_CACHED_TILE) as usize];
    let mut keys = [0u64; MAX_BLOCK_PIXELS];
    for cy in 0..classes {
        for cx in 0..classes {
            for i in 0..n as u32 {
                let p = UVec2::new(cx * b + (i & (b - 1)), cy * b + (i >> b_log2));
                keys[i as usize] = ((tile[tile_texel(p, offset, log2) as usize] as u64) << 6) | i as u64;
            }
            sort_keys(&mut keys[..n]);
            let base = ((cy * classes + cx) as usize) * n;
            for k in 0..n {
                order[base + k] = (keys[k] & 63) as u8;
            }
        }
    }

    let wrap = |v: i32, m: u32| -> u32 {
        let m = m as i32;
        (if v < 0 {
            v + m
        } else if v >= m {
            v - m
        } else {
            v
        }) as u32
    };
    let full_x = params.width / b; // blocks fully inside the visible frame
    let full_y = params.height / b;
    for by in 0..params.blocks_y() {
        for bx in 0..params.blocks_x() {
            let (x0, y0) = (bx * b, by * b);
            if bx >= full_x || by >= full_y {
                edge_block(params, bx, by, intensities, tile, packed, seeds_in, seeds_out);
                continue;
            }
            for i in 0..n as u32 {
                let (x, y) = (x0 + (i & (b - 1)), y0 + (i >> b_log2));
                let key = intensity_key(intensities[(y * params.width + x) as usize].intensity());
                keys[i as usize] = ((key as u64) << 6) | i as u64;
            }
            sort_keys(&mut keys[..n]);
            let class = (((by & (classes - 1)) * classes + (bx & (classes - 1))) as usize) * n;
            for k in 0..n {
                let src = (keys[k] & 63) as u32;
                let dst = order[class + k] as u32;
                let (sx, sy) = (x0 + (src & (b - 1)), y0 + (src >> b_log2));
                let (dx, dy) = (x0 + (dst & (b - 1)), y0 + (dst >> b_log2));
                let t = (((dy + offset.y) & mask) << log2) | ((dx + offset.x) & mask);
                let d = unpack_offset(packed[t as usize]);
                let nx = wrap(dx as i32 + d.x, pw);
                let ny = wrap(dy as i32 + d.y, ph);
                seeds_out[(ny * pw + nx) as usize] = seeds_in[(sy * pw + sx) as usize];
            }
        }
    }
}

/// A block clipped by the visible frame: the reference sort of its visible
/// pixels, then every seed of the block (padding included) is retargeted.
#[allow(clippy::too_many_arguments)]
fn edge_block<T: Intensity>(
    params: &FrameParams,
    bx: u32,
    by: u32,
    intensities: &[T],
    tile: &[u32],
    packed: &[u32],
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) {
    let offset = walk_offset(params.frame, params.tile_log2);
    let padded = UVec2::new(params.padded_width, params.padded_height);
    let mut keys = [0u32; MAX_BLOCK_PIXELS];
    let mut dither = [0u32; MAX_BLOCK_PIXELS];
    let mut seeds = [0u32; MAX_BLOCK_PIXELS];
    let mut pos = [UVec2::ZERO; MAX_BLOCK_PIXELS];
    let mut len = 0usize;
    let mut sorted = [0u32; MAX_BLOCK_PIXELS];
    let (x0, y0) = (bx * params.block, by * params.block);
    for y in y0..(y0 + params.block).min(params.padded_height) {
        for x in x0..(x0 + params.block).min(params.padded_width) {
            let p = UVec2::new(x, y);
            let s = seeds_in[(y * params.padded_width + x) as usize];
            if x < params.width && y < params.height {
                keys[len] = intensity_key(intensities[(y * params.width + x) as usize].intensity());
                dither[len] = tile[tile_texel(p, offset, params.tile_log2) as usize];
                seeds[len] = s;
                pos[len] = p;
                len += 1;
            } else {
                let d = crate::retarget_destination(p, offset, params.tile_log2, packed, padded);
                seeds_out[(d.y * params.padded_width + d.x) as usize] = s;
            }
        }
    }
    sort_block(len as u32, &keys, &dither, &seeds, &mut sorted);
    for i in 0..len {
        let d = crate::retarget_destination(pos[i], offset, params.tile_log2, packed, padded);
        seeds_out[(d.y * params.padded_width + d.x) as usize] = sorted[i];
    }
}

/// Sorts `v` ascending: Batcher's odd-even merge network for 4, 16 and 64
/// entries (no data-dependent branches), insertion sort otherwise.
#[inline]
fn sort_keys(v: &mut [u64]) {
    match v.len() {
        4 => run_network(v, &NETWORK_4.pairs[..NETWORK_4.len]),
        16 => run_network(v, &NETWORK_16.pairs[..NETWORK_16.len]),
        64 => run_network(v, &NETWORK_64.pairs[..NETWORK_64.len]),
        _ => insertion_sort(v),
    }
}

#[inline(always)]
fn run_network(v: &mut [u64], pairs: &[(u8, u8)]) {
    for &(a, b) in pairs {
        let (x, y) = (v[a as usize], v[b as usize]);
        v[a as usize] = x.min(y);
        v[b as usize] = x.max(y);
    }
}

/// Comparators of a sorting network: each puts the smaller value at `.0`.
struct Network {
    pairs: [(u8, u8); 544],
    len: usize,
}

const NETWORK_4: Network = odd_even_merge_network(4);
const NETWORK_16: Network = odd_even_merge_network(16);
const NETWORK_64: Network = odd_even_merge_network(64);

/// Batcher's odd-even merge sort for `n` (a power of two, `<= 64`) inputs,
/// in Knuth's iterative form: 5, 63 and 543 comparators for 4, 16, 64.
const fn odd_even_merge_network(n: usize) -> Network {
    let mut net = Network {
        pairs: [(0, 0); 544],
        len: 0,
    };
    let mut p = 1;
    while p < n {
        let mut k = p;
        while k >= 1 {
            let mut j = k % p;
            while j + k < n {
                let mut i = 0;
                while i < k && i < n - j - k {
                    if (i + j) / (2 * p) == (i + j + k) / (2 * p) {
                        net.pairs[net.len] = ((i + j) as u8, (i + j + k) as u8);
                        net.len += 1;
                    }
                    i += 1;
                }
                j += 2 * k;
            }
            k /= 2;
        }
        p *= 2;
    }
    net
}

/// Insertion sort, ascending.
#[inline]
pub(crate) fn insertion_sort(v: &mut [u64]) {
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
    fn networks_sort_like_insertion() {
        assert_eq!((NETWORK_4.len, NETWORK_16.len, NETWORK_64.len), (5, 63, 543));
        let mut state = 12345u32;
        for _ in 0..500 {
            for n in [4usize, 16, 64] {
                let mut a = [0u64; 64];
                for x in a[..n].iter_mut() {
                    state = crate::seed::hash_u32(state);
                    *x = (state % 7) as u64; // many ties
                }
                let mut b = a;
                sort_keys(&mut a[..n]);
                insertion_sort(&mut b[..n]);
                assert_eq!(a[..n], b[..n]);
                assert!(a[..n].windows(2).all(|w| w[0] <= w[1]));
            }
        }
    }
}
