//! The cut bits of a frame, in two orders, each packed little-endian into
//! `u32` words: bit `p` of the **raster** bits is set when the retarget
//! edge out of seed `p` (padded index `y * padded_width + x`) is cut
//! ([`edge_is_cut`](crate::features::surface::edge_is_cut)); the walks test
//! these. The **block-order** bits hold the same bits block by block (in
//! the order the blocks are visited, row of blocks by row of blocks;
//! `N = B * B` bits a block, pixels row-major inside it): the order in
//! which the second pass lists the cut seeds. `N` divides 32 (B = 2, 4) or
//! 32 divides `N` (B = 8); a block's row of `B` bits never straddles two
//! raster words (`B` divides `x`, and 16 divides `padded_width`).

/// Writes block `(x0, y0)`'s cut bits (`mask`, bit `r * B + c` for pixel
/// `(c, r)`) into the raster bits.
#[inline(always)]
pub(super) fn store_raster<const B: u32>(words: &mut [u32], padded_width: u32, x0: u32, y0: u32, mask: u64) {
    let ones = (1u32 << B) - 1;
    for r in 0..B {
        let bit = ((y0 + r) * padded_width + x0) as usize;
        let (w, shift) = (bit >> 5, bit & 31);
        let row = (mask >> (r * B)) as u32 & ones;
        words[w] = (words[w] & !(ones << shift)) | (row << shift);
    }
}

/// Whether bit `bit` is set.
#[inline(always)]
pub(super) fn is_set(words: &[u32], bit: usize) -> bool {
    words[bit >> 5] >> (bit & 31) & 1 != 0
}

/// Writes block `block`'s `N` cut bits (`mask`, bit `i` for pixel `i`).
#[inline(always)]
pub(super) fn store_block<const N: usize>(words: &mut [u32], block: usize, mask: u64) {
    if N >= 32 {
        for k in 0..N / 32 {
            words[block * (N / 32) + k] = (mask >> (32 * k)) as u32;
        }
    } else {
        let per_word = 32 / N;
        let (w, shift) = (block / per_word, (block % per_word) * N);
        let field = ((u64::MAX >> (64 - N)) as u32) << shift;
        words[w] = (words[w] & !field) | ((mask as u32) << shift);
    }
}

/// Words needed for `seeds` cut bits.
#[inline(always)]
pub(super) fn word_count(seeds: usize) -> usize {
    seeds.div_ceil(32)
}
