//! A sorting network for the sixteen pixels of a 4x4 block: Batcher's
//! odd-even merge sort, 63 compare-exchanges in 10 layers. Applied to
//! 64-bit lanes that hold a pixel's key above its index, it sorts by key
//! then index (the block's total order) with two instructions (min, max)
//! per comparator and leaves each rank's pixel index in the low bits
//! ([`avx512`](super::avx512)).

/// Inputs of [`NETWORK`]: the pixels of a 4x4 block.
pub(super) const INPUTS: usize = 16;

/// The comparators `(a, b)`, `a < b`, in order: after each, wire `a` holds
/// the smaller value and wire `b` the larger. Batcher's odd-even merge
/// sort: merges of sorted runs of 1, 2, 4 and 8 wires. The kernels apply
/// it through [`for_each_comparator`], its written-out form; the tests
/// check that one against this one.
#[cfg_attr(not(test), allow(dead_code))]
pub(super) const NETWORK: [(u8, u8); 63] = odd_even_merge_sort();

/// Calls `$exchange(a, b)` for every comparator of [`NETWORK`], in order,
/// written out: with constant wire numbers the compiler keeps the wires in
/// registers (a loop over `NETWORK` stays a loop, its wires in memory).
/// The test `unrolled_network_is_network` holds the two lists equal.
#[rustfmt::skip]
macro_rules! for_each_comparator {
    ($exchange:expr) => {{
        let mut exchange = $exchange;
        // Merges of sorted runs of 1 into runs of 2.
        exchange(0, 1); exchange(2, 3); exchange(4, 5); exchange(6, 7); exchange(8, 9); exchange(10, 11); exchange(12, 13); exchange(14, 15);
        // Merges of sorted runs of 2 into runs of 4.
        exchange(0, 2); exchange(1, 3); exchange(4, 6); exchange(5, 7); exchange(8, 10); exchange(9, 11); exchange(12, 14); exchange(13, 15);
        exchange(1, 2); exchange(5, 6); exchange(9, 10); exchange(13, 14);
        // Merges of sorted runs of 4 into runs of 8.
        exchange(0, 4); exchange(1, 5); exchange(2, 6); exchange(3, 7); exchange(8, 12); exchange(9, 13); exchange(10, 14); exchange(11, 15);
        exchange(2, 4); exchange(3, 5); exchange(10, 12); exchange(11, 13); exchange(1, 2); exchange(3, 4); exchange(5, 6); exchange(9, 10);
        exchange(11, 12); exchange(13, 14);
        // Merges of sorted runs of 8 into runs of 16.
        exchange(0, 8); exchange(1, 9); exchange(2, 10); exchange(3, 11); exchange(4, 12); exchange(5, 13); exchange(6, 14); exchange(7, 15);
        exchange(4, 8); exchange(5, 9); exchange(6, 10); exchange(7, 11); exchange(2, 4); exchange(3, 5); exchange(6, 8); exchange(7, 9);
        exchange(10, 12); exchange(11, 13); exchange(1, 2); exchange(3, 4); exchange(5, 6); exchange(7, 8); exchange(9, 10); exchange(11, 12);
        exchange(13, 14);
    }};
}
pub(super) use for_each_comparator;

/// Batcher's odd-even merge sort on [`INPUTS`] wires (Knuth, TAOCP vol. 3,
/// 5.2.2, algorithm M, in its iterative form): for each run length `p`
/// (1, 2, 4, 8) and each distance `k` (`p`, `p / 2`, ..., 1), compare
/// wires `i` and `i + k` where both lie in the same pair of runs being
/// merged (`i / 2p == (i + k) / 2p`) and `i` is at an offset `k mod p`
/// from a multiple of `2k`.
#[cfg_attr(not(test), allow(dead_code))]
const fn odd_even_merge_sort() -> [(u8, u8); 63] {
    let mut out = [(0u8, 0u8); 63];
    let mut len = 0;
    let mut p = 1;
    while p < INPUTS {
        let mut k = p;
        while k >= 1 {
            let mut j = k % p;
            while j + k < INPUTS {
                let mut i = 0;
                while i < k && i + j + k < INPUTS {
                    if (i + j) / (2 * p) == (i + j + k) / (2 * p) {
                        out[len] = ((i + j) as u8, (i + j + k) as u8);
                        len += 1;
                    }
                    i += 1;
                }
                j += 2 * k;
            }
            k /= 2;
        }
        p *= 2;
    }
    assert!(len == out.len());
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The zero-one principle: a comparator network sorts every input if
    /// it sorts every sequence of zeros and ones (all 2^16 of them here).
    #[test]
    fn network_sorts_every_zero_one_input() {
        for bits in 0u32..1 << INPUTS {
            let mut wires: [u32; INPUTS] = core::array::from_fn(|i| bits >> i & 1);
            for &(a, b) in NETWORK.iter() {
                let (a, b) = (a as usize, b as usize);
                assert!(a < b);
                let (x, y) = (wires[a], wires[b]);
                wires[a] = x.min(y);
                wires[b] = x.max(y);
            }
            assert!(wires.windows(2).all(|w| w[0] <= w[1]), "{bits:016b}");
        }
    }

    #[test]
    fn unrolled_network_is_network() {
        extern crate std;
        let mut pairs = std::vec::Vec::new();
        for_each_comparator!(|a: usize, b: usize| pairs.push((a as u8, b as u8)));
        assert_eq!(pairs, NETWORK);
    }

    #[test]
    fn network_has_ten_layers() {
        let mut depth = [0u32; INPUTS];
        for &(a, b) in NETWORK.iter() {
            let d = depth[a as usize].max(depth[b as usize]) + 1;
            depth[a as usize] = d;
            depth[b as usize] = d;
        }
        assert_eq!(depth.iter().max(), Some(&10));
    }
}
