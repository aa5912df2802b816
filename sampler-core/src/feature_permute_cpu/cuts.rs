//! The cut bits of a frame: bit `i` of block `k` (in the order the blocks
//! are visited, row of blocks by row of blocks) is set when the retarget
//! edge out of that block's pixel `i` (row-major inside the block) is cut
//! ([`edge_is_cut`](crate::feature_permute::edge_is_cut)). `N = B * B` bits
//! a block, packed little-endian into `u32` words: `N` divides 32 (B = 2,
//! 4) or 32 divides `N` (B = 8).

/// Index of the cut bit of seed `(x, y)` for block side `B` (`N = B * B`)
/// and `blocks_x` blocks a row.
#[inline(always)]
pub(super) fn bit_index<const B: u32, const N: usize>(blocks_x: u32, x: u32, y: u32) -> usize {
    let b_log2 = B.trailing_zeros();
    let block = (y >> b_log2) as usize * blocks_x as usize + (x >> b_log2) as usize;
    block * N + (((y & (B - 1)) << b_log2) | (x & (B - 1))) as usize
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
