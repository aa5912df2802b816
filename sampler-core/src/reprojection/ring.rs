//! The on-stack ring of "this pixel has its seed" marks that both CPU forms
//! of the reprojection ([`super::sweep`], [`super::two_sweeps`]) hand seeds
//! out with: its size, whether a frame's rows fit it, and the walk over the
//! unmarked pixels of a row.

use crate::permutation::layout::FrameParams;

/// Words of the on-stack ring of "this pixel has its seed" marks used by
/// `reproject_fused` and by `assign_by_sources` in two sweeps: 16 KiB,
/// 2^17 pixels, so 68 rows of 1920 pixels (claims up to 33 rows away from
/// their pixel) or 32 rows of 4096.
pub(crate) const RING_WORDS: usize = 2048;

/// Whether a ring of `ring_words` words gives distinct marks to the pixels
/// of `2 * span + 1` rows (`reproject_fused`, `assign_by_sources`).
pub(crate) fn fits_ring(params: &FrameParams, span: usize, ring_words: usize) -> bool {
    (2 * span + 1) * params.padded_width as usize <= ring_words * 64
}

/// Calls `f(p)` for every visible pixel `p` of seed-buffer row `row`
/// (`row_start = row * padded_width`, `w` visible pixels) whose bit in the
/// ring of taken pixels is clear (it has no seed yet), in buffer order, and
/// clears the row's bits for the ring's next lap.
#[inline(always)]
pub(crate) fn for_each_unseeded(
    ring: &mut [u64],
    ring_mask: usize,
    row_start: usize,
    w: usize,
    mut f: impl FnMut(usize),
) {
    let mut x = 0;
    while x < w {
        let b = (row_start + x) & ring_mask;
        let off = b & 63;
        let lanes = (64 - off).min(w - x);
        let mask = (u64::MAX >> (64 - lanes)) << off;
        let mut empty = !ring[b >> 6] & mask;
        ring[b >> 6] &= !mask;
        while empty != 0 {
            f(row_start + x + empty.trailing_zeros() as usize - off);
            empty &= empty - 1;
        }
        x += lanes;
    }
}
