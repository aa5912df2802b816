//! A spatiotemporal a-priori sampler: every pixel continues **one
//! progressive** Owen-scrambled Sobol sequence across frames, rotated by a
//! per-pixel blue-noise shift (issue 29, "Blue in time").
//!
//! # Why
//!
//! A real-time renderer shows an exponential history of its frames. Samplers
//! that re-randomise every frame (the seed permutation's streams, the
//! screen-space samplers' per-frame keys) make each pixel's error white in
//! time, and a history of white-in-time error keeps `alpha / (2 - alpha)` of
//! the per-frame variance whatever the spatial arrangement. A pixel whose
//! samples over frames are the consecutive points of one low-discrepancy
//! sequence has an error that is anti-correlated from frame to frame (its
//! running mean converges faster than `1/sqrt(n)`), so the history keeps less.
//!
//! # Sampling
//!
//! Sample `s` of frame `t` at `spp` samples per pixel has the sequence index
//! `n = t * spp + s` (wrapping). Dimension pair `k` of pixel `p` is
//!
//! ```text
//! x_k(p, n) = frac( sobol_owen(shuffle(n, seed_k), dims 0 and 1, seed_k) + shift_k(p) )
//! ```
//!
//! - `sobol_owen(shuffle(n))` is the 2D Owen-scrambled Sobol (0, 2)-sequence
//!   with its index shuffled by a nested scramble ([`shuffle_index`]): every
//!   aligned block of `2^m` consecutive indices (so every prefix of `2^m`
//!   frames at 1 spp) is a (0, m, 2)-net, and the independent `seed_k` of
//!   each pair decorrelates the pairs ("padding"). It is the **same** for
//!   every pixel. With [`SEQUENCE_KRONECKER`] it is replaced by the
//!   Kronecker sequence `frac(n g_k)` of [`crate::sequences::kronecker`]
//!   (one searched generator per pair), whose every window of consecutive
//!   frames is as well spread as its first: what a history's sliding window
//!   wants ([`spatiotemporal_sequence_point_u32`]).
//! - `shift_k(p)` is a toroidal (Cranley-Patterson) rotation, constant over
//!   time, read from a blue-noise dither tile ([`spatiotemporal_shift_u32`]):
//!   coordinate `c` of pair `k` reads the tile at `p + o_(2k + c + 1)`, where
//!   `o_i` is the tile's R2 walk offset ([`walk_offset`]), so the coordinates
//!   read well-separated parts of the tile. In any one frame all pixels share
//!   the sequence point and differ only by their shift, so where neighbours
//!   integrate the same function their errors are the function of a
//!   blue-noise shift: blue in space, every frame.
//! - Pair [`NET_SHIFT_PAIR`] (pair 0, where a renderer puts the position
//!   inside the pixel) is shifted by a **2D net** instead ([`net_shift_u32`]):
//!   ZSobol's one-sample-per-pixel points, so that the shifts of every
//!   aligned square of `4^m` pixels are a (0, 2m, 2)-net: neighbours' jitters
//!   are stratified jointly, in both coordinates at once, where two scalar
//!   tile reads are blue one coordinate at a time. A common rotation by the
//!   frame's point moves the net off the aligned intervals but keeps most of
//!   its spread: at the lights' silhouettes, where the jitter decides the
//!   error, a frame's blurred error drops by about a tenth (`QUALITY.md`,
//!   "Blue in time"), and a pixel's sequence over frames is the same rotated
//!   sequence as before (any shift gives the same history and running means
//!   on average).
//!
//! Because a frame's sequence points are the same for every pixel, a renderer
//! can compute them once per frame ([`spatiotemporal_frame_points`]) and
//! leave each pixel only its shift and one add; the tracer does so.
//!
//! # Homes: shifts that follow the picture
//!
//! A pixel's **home** is where it reads its shift: by default its own
//! position. When the camera or objects move, a renderer can store each
//! pixel's home ([`home_of_pixel`]) in its seed buffer and move the homes
//! with the seed reprojection (`crate::reprojection`, a permutation, so the
//! field of shifts stays a rearrangement of the tile's: no shift duplicated),
//! so that the pixels that follow a surface keep its shift and its sequence;
//! the pixel then reads its shift at [`home_texel`]. Measured (`QUALITY.md`,
//! "Blue in time"): it keeps part of the interiors' gain at 2 px/frame, and
//! none of the whole image's, whose gain with a still camera is at the
//! light's silhouette, where the pixel footprint itself slides over the edge.
//!
//! # Both coordinates of a shift in one read
//!
//! The two coordinates of pair `k` read the tile at `p + o_(2k+1)` and `p +
//! o_(2k+2)`, and `o_(2k+2) - o_(2k+1)` is one of the walk's
//! [`STEP_COUNT`] steps ([`step_index`]). A renderer can therefore store,
//! per step `j`, a tile whose texel `q` holds `rank(q) | rank(q + step_j)
//! << 16` ([`write_shift_pair_tiles`], `STEP_COUNT` times the tile's words)
//! and read a pair's whole shift with one load
//! ([`spatiotemporal_shift_packed`]): the same shifts, bit for bit, for half
//! the scattered reads (what a shader's pixel spends most of the sampler's
//! time on: `BENCHMARKS.md`, "Spatiotemporal sampler"). Ranks must fit in
//! 16 bits: tiles up to 256x256.
//!
//! The net shifts of [`NET_SHIFT_PAIR`] are one more tile after those
//! ([`shift_pair_tiles_len`]): ZSobol's point of each texel, both
//! coordinates cut to 16 bits in one word, so that pair too is one load.
//!
//! So the sampler needs no per-frame data and no history, and its sequence
//! continues for 2^32 samples; nothing here is optimised for a filter yet
//! (the two coordinates of the other pairs' shifts are two scalar blue-noise
//! reads, not a jointly blue 2D vector): the measured figures are in
//! `QUALITY.md`, "Blue in time".
//!
//! All arithmetic is `u32` with `wrapping_*` (0.32 fixed point: `x_q32 / 2^32`);
//! identical on the CPU and in shaders.

use crate::error::{Buffer, Error};
use crate::sequences::kronecker::kronecker_point_u32;
use crate::sequences::owen::{owen_sobol_pair_u32, shuffle_index};
use crate::sequences::seed::hash_u32;
use crate::sequences::walk::{step_index, step_of_index, tile_log2, walk_offset, STEP_COUNT};
use crate::sequences::zsobol::zsobol_frame_pair_u32;
use glam::UVec2;

/// Seed of the shared sequence, so that a renderer's pairs match the
/// library's reference (any fixed value works; this one is `hash("st")`-like:
/// the ASCII bytes `"stsb"`).
pub const SPATIOTEMPORAL_SEED: u32 = 0x7374_7362;

/// The sequence index of sample `s` of `frame` at `spp` samples per pixel:
/// `frame * spp + s`, wrapping.
#[inline]
pub fn spatiotemporal_index(frame: u32, spp: u32, s: u32) -> u32 {
    frame.wrapping_mul(spp).wrapping_add(s)
}

/// The pair whose shifts are a 2D net ([`net_shift_u32`]) rather than two
/// tile reads: pair 0, where a renderer puts the position inside the pixel
/// (the tracer's pixel jitter), whose error at silhouettes is a 2D step.
pub const NET_SHIFT_PAIR: u32 = 0;

/// The shift of pair [`NET_SHIFT_PAIR`] at `pixel`, both coordinates in
/// 0.32 fixed point: ZSobol's one-sample-per-pixel point of frame 0
/// ([`zsobol_frame_pair_u32`]`(q, 0, 0, 0, 0)`) of the pixel `q = pixel mod
/// 2^side_log2` (the shift tile's period), each coordinate cut to its top
/// 16 bits plus half a step (the precision of the packed tile,
/// [`write_shift_pair_tiles`]). Over every aligned square of `4^m` pixels
/// inside the period the shifts are a (0, 2m, 2)-net: each elementary
/// interval of area `4^-m` holds one (module docs). `side_log2` must be in
/// `1..=15`.
#[inline]
pub fn net_shift_u32(side_log2: u32, pixel: UVec2) -> [u32; 2] {
    let mask = (1u32 << side_log2).wrapping_sub(1);
    let p = zsobol_frame_pair_u32(UVec2::new(pixel.x & mask, pixel.y & mask), 0, 0, 0, 0);
    [net_shift_word(p[0] >> 16), net_shift_word(p[1] >> 16)]
}

/// The 0.32 fixed-point shift of a 16-bit net coordinate: the centre of its
/// stratum.
#[inline]
fn net_shift_word(top16: u32) -> u32 {
    (top16 << 16) | (1u32 << 15)
}

/// The per-pixel shift of pair `pair`, both coordinates in 0.32 fixed point:
/// for pair [`NET_SHIFT_PAIR`] [`net_shift_u32`] (no read of `tile`); for
/// the others coordinate `c` is the rank `r` of the `2^side_log2`-sided
/// square `tile` (row-major, ranks `0..4^side_log2`) at texel `(pixel + o) mod
/// side`, `o = walk_offset(2 pair + c + 1, side_log2)`, as `(r + 0.5) /
/// 4^side_log2`. `side_log2` must be in `1..=15`; a texel past the end of
/// `tile` reads rank 0 (no panic in shaders).
#[inline]
pub fn spatiotemporal_shift_u32(tile: &[u32], side_log2: u32, pixel: UVec2, pair: u32) -> [u32; 2] {
    spatiotemporal_shift_at(tile, 0, side_log2, pixel, pair)
}

/// [`spatiotemporal_shift_u32`] with the tile stored in `buffer` from index
/// `start` on (shaders bind it after other data; no sub-slice needed).
#[inline]
pub fn spatiotemporal_shift_at(
    buffer: &[u32],
    start: usize,
    side_log2: u32,
    pixel: UVec2,
    pair: u32,
) -> [u32; 2] {
    if pair == NET_SHIFT_PAIR {
        return net_shift_u32(side_log2, pixel);
    }
    // Two calls, not a loop filling an array: shaders keep arrays indexed at
    // run time in scratch memory.
    [
        shift_coordinate(buffer, start, side_log2, pixel, pair, 0),
        shift_coordinate(buffer, start, side_log2, pixel, pair, 1),
    ]
}

/// Coordinate `c` (0 or 1) of [`spatiotemporal_shift_at`]: the tile read at
/// the walk's offset `2 pair + c + 1`, as a 0.32 fixed-point shift.
#[inline]
fn shift_coordinate(buffer: &[u32], start: usize, side_log2: u32, pixel: UVec2, pair: u32, c: u32) -> u32 {
    let walk = pair.wrapping_mul(2).wrapping_add(c + 1);
    let i = start.wrapping_add(shift_texel(side_log2, pixel, walk));
    shift_word(if i < buffer.len() { buffer[i] } else { 0 }, side_log2)
}

/// Row-major index of the texel of a `2^side_log2`-sided tile that `pixel`
/// reads at the walk's offset `o_walk` (toroidally).
#[inline]
fn shift_texel(side_log2: u32, pixel: UVec2, walk: u32) -> usize {
    let o = walk_offset(walk, side_log2);
    tile_texel(
        side_log2,
        UVec2::new(pixel.x.wrapping_add(o.x), pixel.y.wrapping_add(o.y)),
    )
}

/// Row-major index of the texel of a `2^side_log2`-sided tile at `pixel`
/// (toroidally).
#[inline]
fn tile_texel(side_log2: u32, pixel: UVec2) -> usize {
    let mask = (1u32 << side_log2).wrapping_sub(1);
    (((pixel.y & mask) << side_log2) | (pixel.x & mask)) as usize
}

/// The 0.32 fixed-point shift of `rank` in a tile of `4^side_log2` texels:
/// the centre of the rank's stratum.
#[inline]
fn shift_word(rank: u32, side_log2: u32) -> u32 {
    let bits = 2 * side_log2;
    (rank << (32 - bits)) | (1u32 << (31 - bits))
}

/// `log2` of the largest tile whose ranks [`write_shift_pair_tiles`] can
/// pack (two 16-bit ranks a word).
pub const MAX_SHIFT_PAIR_TILE_LOG2: u32 = 8;

/// Words [`write_shift_pair_tiles`] writes for a `2^side_log2`-sided tile:
/// `(STEP_COUNT + 1) * 4^side_log2` (the shift-pair tiles, then the net
/// shifts of [`NET_SHIFT_PAIR`]).
#[inline]
pub const fn shift_pair_tiles_len(side_log2: u32) -> usize {
    (STEP_COUNT + 1) << (2 * side_log2)
}

/// Writes the [`STEP_COUNT`] shift-pair tiles of the rank tile `ranks` (side
/// `2^side_log2`, row-major) into `out` (module docs, "Both coordinates of a
/// shift in one read"): `out[j * n + q] = ranks[q] | ranks[(q + step_j) mod
/// side] << 16`, `n = 4^side_log2`, where `step_j` is the walk's step of
/// index `j` ([`step_of_index`]); then the net shifts of [`NET_SHIFT_PAIR`]:
/// `out[STEP_COUNT * n + q]` holds the top 16 bits of [`net_shift_u32`]'s
/// coordinates at texel `q`, `x | y << 16`.
///
/// # Errors
/// [`Error::TileSize`] if the side is not a power of two in
/// `2..=2^`[`MAX_SHIFT_PAIR_TILE_LOG2`]; [`Error::BufferSize`] if `ranks` is
/// not `n` long ([`Buffer::DitherTile`]) or `out` not
/// [`shift_pair_tiles_len`] ([`Buffer::ShiftPairTiles`]). A rank of `2^16`
/// or more cannot occur in a tile of that size; one would be cut to 16 bits.
pub fn write_shift_pair_tiles(ranks: &[u32], side_log2: u32, out: &mut [u32]) -> Result<(), Error> {
    let side = 1u32 << side_log2.min(31);
    if side_log2 > MAX_SHIFT_PAIR_TILE_LOG2 || tile_log2(side).is_none() {
        return Err(Error::TileSize { tile: side });
    }
    let n = (side * side) as usize;
    if ranks.len() != n {
        return Err(Error::BufferSize {
            buffer: Buffer::DitherTile,
            expected: n,
            actual: ranks.len(),
        });
    }
    if out.len() != shift_pair_tiles_len(side_log2) {
        return Err(Error::BufferSize {
            buffer: Buffer::ShiftPairTiles,
            expected: shift_pair_tiles_len(side_log2),
            actual: out.len(),
        });
    }
    let mask = side - 1;
    let (pairs, nets) = out.split_at_mut(STEP_COUNT * n);
    for (q, word) in nets.iter_mut().enumerate() {
        let shift = net_shift_u32(side_log2, UVec2::new(q as u32 & mask, q as u32 >> side_log2));
        *word = (shift[0] >> 16) | (shift[1] >> 16 << 16);
    }
    for (j, tile) in pairs.chunks_exact_mut(n).enumerate() {
        let step = step_of_index(j as u32, side_log2);
        for (q, word) in tile.iter_mut().enumerate() {
            let (x, y) = (q as u32 & mask, q as u32 >> side_log2);
            let next = (((y + step.y) & mask) << side_log2) | ((x + step.x) & mask);
            *word = (ranks[q] & 0xFFFF) | (ranks[next as usize] << 16);
        }
    }
    Ok(())
}

/// [`spatiotemporal_shift_at`] from the shift-pair tiles of the rank tile
/// instead ([`write_shift_pair_tiles`], starting at `buffer[start]`): the same
/// two words, bit for bit, from one read (for [`NET_SHIFT_PAIR`] from the
/// net tile after the shift-pair tiles). A read past `buffer` gives rank 0
/// (or net coordinate 0) for both coordinates.
#[inline]
pub fn spatiotemporal_shift_packed(
    buffer: &[u32],
    start: usize,
    side_log2: u32,
    pixel: UVec2,
    pair: u32,
) -> [u32; 2] {
    if pair == NET_SHIFT_PAIR {
        let i = start
            .wrapping_add(STEP_COUNT << (2 * side_log2))
            .wrapping_add(tile_texel(side_log2, pixel));
        let word = if i < buffer.len() { buffer[i] } else { 0 };
        return [net_shift_word(word & 0xFFFF), net_shift_word(word >> 16)];
    }
    let first = pair.wrapping_mul(2).wrapping_add(1);
    let tile = (step_index(first, side_log2) as usize) << (2 * side_log2);
    let i = start
        .wrapping_add(tile)
        .wrapping_add(shift_texel(side_log2, pixel, first));
    let word = if i < buffer.len() { buffer[i] } else { 0 };
    [
        shift_word(word & 0xFFFF, side_log2),
        shift_word(word >> 16, side_log2),
    ]
}

/// Pair `pair` of sequence index `index` before the per-pixel shift: the 2D
/// Owen-scrambled Sobol point of the shuffled index, both coordinates in 0.32
/// fixed point. The same for every pixel.
#[inline]
pub fn spatiotemporal_point_u32(index: u32, pair: u32, seed: u32) -> [u32; 2] {
    let pair_seed = hash_u32(seed ^ hash_u32(pair ^ 0x2545_F491));
    owen_sobol_pair_u32(shuffle_index(index, pair_seed), pair_seed)
}

/// Selector of the sequence a pixel continues over frames: the Owen-scrambled Sobol points of
/// [`spatiotemporal_point_u32`] (seed [`SPATIOTEMPORAL_SEED`]).
pub const SEQUENCE_SOBOL: u32 = 0;
/// Selector of the sequence a pixel continues over frames: the Kronecker
/// sequence of [`kronecker_point_u32`] (every window of consecutive frames
/// as well spread as the first; see [`crate::sequences::kronecker`]).
pub const SEQUENCE_KRONECKER: u32 = 1;

/// Pair `pair` of sequence index `index` of `sequence` ([`SEQUENCE_SOBOL`],
/// [`SEQUENCE_KRONECKER`]; any other value reads as Sobol) before the
/// per-pixel shift, both coordinates in 0.32 fixed point.
#[inline]
pub fn spatiotemporal_sequence_point_u32(sequence: u32, index: u32, pair: u32) -> [u32; 2] {
    if sequence == SEQUENCE_KRONECKER {
        kronecker_point_u32(index, pair)
    } else {
        spatiotemporal_point_u32(index, pair, SPATIOTEMPORAL_SEED)
    }
}

/// Pair `pair` of sample `s` of `frame` (at `spp` samples per pixel) of the
/// pixel whose shift is `shift` ([`spatiotemporal_shift_u32`]) when its
/// samples continue `sequence`, both coordinates in 0.32 fixed point:
/// [`spatiotemporal_sequence_point_u32`] of [`spatiotemporal_index`] rotated
/// by `shift` (a wrapping add).
#[inline]
pub fn spatiotemporal_pair_u32(
    sequence: u32,
    shift: [u32; 2],
    frame: u32,
    spp: u32,
    s: u32,
    pair: u32,
) -> [u32; 2] {
    let p = spatiotemporal_sequence_point_u32(sequence, spatiotemporal_index(frame, spp, s), pair);
    [p[0].wrapping_add(shift[0]), p[1].wrapping_add(shift[1])]
}

/// The home of pixel `(x, y)` before anything moved: the pixel itself, `x` in
/// the low 16 bits and `y` in the high 16 bits (each taken modulo `2^16`; the
/// shift tile's period divides it).
#[inline]
pub fn home_of_pixel(x: u32, y: u32) -> u32 {
    (x & 0xFFFF) | (y << 16)
}

/// The position a home names ([`home_of_pixel`]'s inverse modulo `2^16`):
/// read the pixel's shift there ([`spatiotemporal_shift_u32`]).
#[inline]
pub fn home_texel(home: u32) -> UVec2 {
    UVec2::new(home & 0xFFFF, home >> 16)
}

/// [`home_of_pixel`] of every entry of a `padded_width x padded_height` seed
/// buffer (row-major): the homes of frame 0.
///
/// # Panics
/// If `out` is shorter than `padded_width * padded_height`.
pub fn write_initial_homes(padded_width: u32, padded_height: u32, out: &mut [u32]) {
    for y in 0..padded_height {
        for x in 0..padded_width {
            out[(y * padded_width + x) as usize] = home_of_pixel(x, y);
        }
    }
}

/// One frame's unshifted points, computed once for every pixel (they do not
/// depend on the pixel): for sample `s < samples` and `k < pairs.len()`,
/// `out[2 (s * pairs.len() + k) + c]` is coordinate `c` of
/// [`spatiotemporal_point_u32`]`(`[`spatiotemporal_index`]`(frame, spp, s),
/// pairs[k], SPATIOTEMPORAL_SEED)`, so a pixel's pair is that entry plus its
/// shift (wrapping), exactly [`spatiotemporal_pair_u32`].
///
/// # Errors
/// [`Error::BufferSize`] ([`Buffer::SamplePoints`]) unless `out` holds exactly
/// `2 * samples * pairs.len()` words; nothing is written then.
pub fn spatiotemporal_frame_points(
    sequence: u32,
    frame: u32,
    spp: u32,
    samples: u32,
    pairs: &[u32],
    out: &mut [u32],
) -> Result<(), Error> {
    let expected = 2 * samples as usize * pairs.len();
    if out.len() != expected {
        return Err(Error::BufferSize {
            buffer: Buffer::SamplePoints,
            expected,
            actual: out.len(),
        });
    }
    let mut i = 0;
    for s in 0..samples {
        let index = spatiotemporal_index(frame, spp, s);
        for &pair in pairs {
            let p = spatiotemporal_sequence_point_u32(sequence, index, pair);
            out[i] = p[0];
            out[i + 1] = p[1];
            i += 2;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;

    /// Every `2^m` consecutive frames of one pixel (1 spp), from frame 0 and
    /// from any aligned start, put exactly one point in each of the `2^m`
    /// elementary intervals of every shape, once the pixel's shift is undone.
    #[test]
    fn each_pixel_is_a_progressive_net_over_frames() {
        let tile: [u32; 16] = [5, 12, 0, 9, 14, 3, 10, 7, 1, 8, 15, 4, 11, 6, 13, 2];
        for (pixel, pair) in [
            (UVec2::new(0, 0), 0),
            (UVec2::new(3, 1), 1),
            (UVec2::new(77, 12), 5),
        ] {
            let shift = spatiotemporal_shift_u32(&tile, 2, pixel, pair);
            for m in [2u32, 4, 6] {
                let n = 1u32 << m;
                for start in [0, n, 5 * n] {
                    for xbits in 0..=m {
                        let ybits = m - xbits;
                        let mut seen = [false; 64];
                        for t in start..start + n {
                            let v = spatiotemporal_pair_u32(SEQUENCE_SOBOL, shift, t, 1, 0, pair);
                            let (x, y) = (v[0].wrapping_sub(shift[0]), v[1].wrapping_sub(shift[1]));
                            let cell =
                                ((x as u64 >> (32 - xbits)) << ybits | (y as u64 >> (32 - ybits))) as usize;
                            assert!(
                                !seen[cell],
                                "pixel {pixel} pair {pair} m {m} start {start} shape {xbits}x{ybits}"
                            );
                            seen[cell] = true;
                        }
                    }
                }
            }
        }
    }

    /// In one frame every pixel gets the same point rotated by its own shift,
    /// and the shifts over one tile period are the tile's ranks, each once.
    #[test]
    fn shifts_are_the_tiles_ranks_and_frames_share_one_point() {
        let side_log2 = 3;
        let n = 1u32 << (2 * side_log2);
        // A permutation of 0..64 as a stand-in tile.
        let tile: [u32; 64] = core::array::from_fn(|i| ((i as u32).wrapping_mul(37) + 11) % n);
        for pair in 1..4 {
            for c in 0..2 {
                let mut seen = [false; 64];
                for y in 0..8 {
                    for x in 0..8 {
                        let s = spatiotemporal_shift_u32(&tile, side_log2, UVec2::new(x, y), pair);
                        let rank = (s[c] >> (32 - 2 * side_log2)) as usize;
                        assert_eq!(
                            s[c] & ((1 << (32 - 2 * side_log2)) - 1),
                            1 << (31 - 2 * side_log2)
                        );
                        assert!(!seen[rank]);
                        seen[rank] = true;
                    }
                }
            }
        }
        let a = spatiotemporal_shift_u32(&tile, side_log2, UVec2::new(1, 2), 1);
        let b = spatiotemporal_shift_u32(&tile, side_log2, UVec2::new(6, 5), 1);
        assert_ne!(a, b);
        for frame in [0, 1, 17] {
            let pa = spatiotemporal_pair_u32(SEQUENCE_SOBOL, a, frame, 4, 3, 0);
            let pb = spatiotemporal_pair_u32(SEQUENCE_SOBOL, b, frame, 4, 3, 0);
            assert_eq!(pa[0].wrapping_sub(a[0]), pb[0].wrapping_sub(b[0]));
            assert_eq!(pa[1].wrapping_sub(a[1]), pb[1].wrapping_sub(b[1]));
        }
        // The same points as the table-driven Owen-scrambled Sobol.
        for index in [0u32, 1, 2, 1000, 0xDEAD_BEEF, u32::MAX] {
            let seed = hash_u32(SPATIOTEMPORAL_SEED ^ hash_u32(3 ^ 0x2545_F491));
            let shuffled = crate::sequences::owen::shuffle_index(index, seed);
            let want = [
                crate::sequences::owen::owen_sobol_u32(shuffled, 0, seed),
                crate::sequences::owen::owen_sobol_u32(shuffled, 1, seed),
            ];
            assert_eq!(spatiotemporal_point_u32(index, 3, SPATIOTEMPORAL_SEED), want);
        }
        // Different pairs are scrambled independently.
        assert_ne!(
            spatiotemporal_point_u32(5, 0, 1),
            spatiotemporal_point_u32(5, 1, 1)
        );
        // A short tile reads rank 0 instead of panicking.
        let short = spatiotemporal_shift_u32(&tile[..1], side_log2, UVec2::new(7, 7), 1);
        assert!(short
            .iter()
            .all(|&v| v >> (32 - 2 * side_log2) == 0 || v >> (32 - 2 * side_log2) == tile[0]));
    }

    /// Both coordinates from one word of the shift-pair tiles are the two
    /// reads of the rank tile, for every pair and pixel (wrapping included).
    #[test]
    fn packed_shift_pairs_are_the_two_reads() {
        for side_log2 in [1u32, 3, 6] {
            let n = 1usize << (2 * side_log2);
            // Ranks in 0..n as a stand-in tile.
            let ranks: std::vec::Vec<u32> = (0..n as u32)
                .map(|i| (i.wrapping_mul(2_654_435_761) >> 7) % n as u32)
                .collect();
            let mut packed = std::vec![0u32; shift_pair_tiles_len(side_log2)];
            write_shift_pair_tiles(&ranks, side_log2, &mut packed).expect("sizes");
            // Behind other data, as the tracer's buffer holds them.
            let mut buffer = std::vec![7u32; 5];
            buffer.extend_from_slice(&packed);
            let side = 1u32 << side_log2;
            for pair in 0..60 {
                for y in 0..side + 3 {
                    for x in 0..side + 2 {
                        let p = UVec2::new(x * 7, y);
                        assert_eq!(
                            spatiotemporal_shift_packed(&buffer, 5, side_log2, p, pair),
                            spatiotemporal_shift_u32(&ranks, side_log2, p, pair),
                            "side 2^{side_log2} pixel {p} pair {pair}"
                        );
                    }
                }
            }
            // Past the buffer: rank 0 for both, as the unpacked read.
            let [a, b] = spatiotemporal_shift_packed(&buffer[..6], 5, side_log2, UVec2::new(1, 1), 3);
            assert_eq!(a >> (32 - 2 * side_log2), 0);
            assert_eq!(b >> (32 - 2 * side_log2), 0);
            let net = spatiotemporal_shift_packed(&buffer[..6], 5, side_log2, UVec2::new(1, 1), 0);
            assert_eq!(net, [1 << 15, 1 << 15]);
        }
    }

    #[test]
    fn shift_pair_tiles_refuse_bad_sizes() {
        let ranks = [0u32; 16];
        let mut out = [0u32; 80];
        assert!(write_shift_pair_tiles(&ranks, 2, &mut out).is_ok());
        assert_eq!(
            write_shift_pair_tiles(&ranks[..15], 2, &mut out),
            Err(Error::BufferSize {
                buffer: Buffer::DitherTile,
                expected: 16,
                actual: 15
            })
        );
        assert_eq!(
            write_shift_pair_tiles(&ranks, 2, &mut out[..79]),
            Err(Error::BufferSize {
                buffer: Buffer::ShiftPairTiles,
                expected: 80,
                actual: 79
            })
        );
        assert_eq!(
            write_shift_pair_tiles(&ranks, 0, &mut out),
            Err(Error::TileSize { tile: 1 })
        );
        assert_eq!(
            write_shift_pair_tiles(&ranks, 9, &mut out),
            Err(Error::TileSize { tile: 512 })
        );
    }

    /// Pair 0's shifts are ZSobol's points of the pixel modulo the period,
    /// and over every aligned square of `4^m` pixels a (0, 2m, 2)-net at
    /// their 16 bits: each elementary interval of area `4^-m`, of every
    /// shape, holds exactly one.
    #[test]
    fn the_jitter_pairs_shifts_are_nets_over_aligned_squares() {
        let side_log2 = 6;
        let tile = [0u32; 1];
        for m in 0..=side_log2 {
            let side = 1u32 << m;
            for (bx, by) in [(0u32, 0u32), (1, 0), (0, 1), (3, 2)] {
                if (bx + 1) * side > 64 || (by + 1) * side > 64 {
                    continue;
                }
                for xbits in 0..=2 * m {
                    let ybits = 2 * m - xbits;
                    let mut seen = std::vec![false; 1 << (2 * m)];
                    for y in 0..side {
                        for x in 0..side {
                            let p = UVec2::new(bx * side + x, by * side + y);
                            let s = spatiotemporal_shift_u32(&tile, side_log2, p, NET_SHIFT_PAIR);
                            let cell = ((s[0] as u64 >> (32 - xbits)) << ybits
                                | (s[1] as u64 >> (32 - ybits)))
                                as usize;
                            assert!(
                                !seen[cell],
                                "square {bx},{by} of side {side}, shape {xbits}x{ybits}"
                            );
                            seen[cell] = true;
                        }
                    }
                }
            }
        }
        for p in [UVec2::new(0, 0), UVec2::new(5, 63), UVec2::new(64 + 5, 128 + 63)] {
            let q = UVec2::new(p.x % 64, p.y % 64);
            let z = zsobol_frame_pair_u32(q, 0, 0, 0, 0);
            let s = net_shift_u32(side_log2, p);
            assert_eq!(s, [(z[0] & 0xFFFF_0000) | 0x8000, (z[1] & 0xFFFF_0000) | 0x8000]);
        }
        // Not the tile's shifts: the other pairs keep theirs.
        assert_ne!(
            spatiotemporal_shift_u32(&[3u32; 4096], side_log2, UVec2::new(1, 1), 0),
            spatiotemporal_shift_u32(&[3u32; 4096], side_log2, UVec2::new(1, 1), 1)
        );
    }

    /// A pixel's first home reads the shift at the pixel (modulo the tile).
    #[test]
    fn a_first_home_is_the_pixel() {
        let mut homes = [0u32; 6 * 5];
        write_initial_homes(6, 5, &mut homes);
        for (i, &h) in homes.iter().enumerate() {
            assert_eq!(home_texel(h), UVec2::new(i as u32 % 6, i as u32 / 6));
        }
        assert_eq!(
            home_texel(home_of_pixel(70_000, 3)),
            UVec2::new(70_000 % 65_536, 3)
        );
        let tile: [u32; 16] = core::array::from_fn(|i| i as u32);
        for p in [UVec2::new(1, 2), UVec2::new(13, 7)] {
            assert_eq!(
                spatiotemporal_shift_u32(&tile, 2, home_texel(home_of_pixel(p.x, p.y)), 3),
                spatiotemporal_shift_u32(&tile, 2, p, 3)
            );
        }
    }

    /// The frame table plus a pixel's shift is the pixel's pair, and a table
    /// of the wrong size is refused untouched.
    #[test]
    fn the_frame_table_plus_the_shift_is_the_pair() {
        let tile: [u32; 16] = [5, 12, 0, 9, 14, 3, 10, 7, 1, 8, 15, 4, 11, 6, 13, 2];
        let pairs = [0u32, 1, 2, 7, 129];
        let (frame, spp, samples) = (37u32, 4u32, 3u32);
        let mut table = [0u32; 2 * 3 * 5];
        for sequence in [SEQUENCE_SOBOL, SEQUENCE_KRONECKER] {
            spatiotemporal_frame_points(sequence, frame, spp, samples, &pairs, &mut table).unwrap();
            for pixel in [UVec2::new(0, 0), UVec2::new(3, 9)] {
                for s in 0..samples {
                    for (k, &pair) in pairs.iter().enumerate() {
                        let shift = spatiotemporal_shift_u32(&tile, 2, pixel, pair);
                        let i = 2 * (s as usize * pairs.len() + k);
                        let from_table = [
                            table[i].wrapping_add(shift[0]),
                            table[i + 1].wrapping_add(shift[1]),
                        ];
                        let direct = spatiotemporal_pair_u32(sequence, shift, frame, spp, s, pair);
                        assert_eq!(from_table, direct);
                    }
                }
            }
        }
        // The two sequences differ.
        assert_ne!(
            spatiotemporal_sequence_point_u32(SEQUENCE_SOBOL, 5, 0),
            spatiotemporal_sequence_point_u32(SEQUENCE_KRONECKER, 5, 0)
        );
        let mut short = [7u32; 29];
        assert_eq!(
            spatiotemporal_frame_points(SEQUENCE_SOBOL, frame, spp, samples, &pairs, &mut short),
            Err(Error::BufferSize {
                buffer: Buffer::SamplePoints,
                expected: 30,
                actual: 29
            })
        );
        assert!(short.iter().all(|&w| w == 7));
    }
}
