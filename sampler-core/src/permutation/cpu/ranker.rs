//! The lane rankers' common part: the [`LaneRanker`] trait (a lane group
//! of blocks ranked at once, one block per vector lane, and its seeds
//! placed by rank), its portable form ([`PortableRanker`], [`quad_ranks`])
//! and the scalar placement. The instruction sets' 4x4 kernels live in
//! [`sse2`](super::sse2), [`avx2`](super::avx2) and [`avx512`](super::avx512).

#[cfg(test)]
use super::block_ranks;

/// Largest number of lanes (blocks ranked at once) of a ranker.
pub(super) const MAX_LANES: usize = 16;
/// Largest block side of the fast path.
pub(super) const MAX_FAST_BLOCK: usize = 8;
/// Keys of a lane group: `strips[r][l * B + c]` is the signed key
/// ([`signed_key`](super::signed_key)) of pixel `(c, r)` of block `l`; rows `r >= B` and
/// entries past `LANES * B` are unused.
pub(super) type Strips = [[i32; MAX_LANES * MAX_FAST_BLOCK]; MAX_FAST_BLOCK];

/// Sorts `LANES` side-by-side `B x B` blocks at once into their ring
/// lines. An instruction set supplies its 4x4 kernel
/// ([`sort_4x4`](Self::sort_4x4)); every other block size takes the
/// portable ranking and the scalar placement.
pub(super) trait LaneRanker {
    /// Blocks sorted at once (at most [`MAX_LANES`]).
    const LANES: usize;

    /// [`sort_group`](Self::sort_group) for 4x4 blocks.
    #[inline(always)]
    fn sort_4x4(
        strips: &Strips,
        ranks: &mut [[u32; MAX_LANES]; 16],
        group: GroupSeeds<'_>,
        lines: &mut [u32],
    ) {
        portable_rank_strips::<4, 16>(strips, ranks);
        place_seeds_scalar::<4, 16>(ranks, group, lines);
    }

    /// Sorts a lane group's seeds into their ring lines: block `l <
    /// LANES` (its keys in `strips`, its seeds in `group`) gets line
    /// `lines[l N..(l + 1) N]`, whose entry `k` is the seed of the block's
    /// pixel of rank `k` in its total order (key, then index;
    /// `lines.len() == LANES * N`). `ranks` is scratch: its content
    /// afterwards is unspecified.
    #[inline(always)]
    fn sort_group<const B: u32, const N: usize>(
        strips: &Strips,
        ranks: &mut [[u32; MAX_LANES]; N],
        group: GroupSeeds<'_>,
        lines: &mut [u32],
    ) {
        match <&mut [[u32; MAX_LANES]; 16]>::try_from(&mut ranks[..]) {
            Ok(ranks) if B == 4 => Self::sort_4x4(strips, ranks, group, lines),
            _ => {
                portable_rank_strips::<B, N>(strips, ranks);
                place_seeds_scalar::<B, N>(ranks, group, lines);
            }
        }
    }
}

/// Where a lane group's seeds are: pixel `(c, r)` of block `l` (blocks of
/// side `B`, side by side) holds `seeds[origin + l B + r pitch + c]`.
#[derive(Clone, Copy)]
pub(super) struct GroupSeeds<'a> {
    /// The frame's seeds (row-major, `pitch` seeds a row).
    pub seeds: &'a [u32],
    /// Index of the group's first seed: pixel `(0, 0)` of block 0.
    pub origin: usize,
    /// Seeds per row (the padded width).
    pub pitch: usize,
}

impl<'a> GroupSeeds<'a> {
    /// The seeds, origin and pitch of a group of `lanes` 4x4 blocks whose
    /// lines are `lines`, for the instruction sets' kernels, which read
    /// the blocks' rows and write the lines unchecked.
    ///
    /// # Panics
    /// Unless `lines` holds `lanes` lines of 16 seeds and the blocks lie
    /// inside the seeds ([`covers`](Self::covers)).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub fn checked_4x4(self, lanes: usize, lines: &[u32]) -> (&'a [u32], usize, usize) {
        assert!(lines.len() == lanes * 16 && self.covers(lanes, 4));
        (self.seeds, self.origin, self.pitch)
    }

    /// True when `lanes` blocks of side `block` lie inside `seeds`.
    #[inline(always)]
    pub fn covers(&self, lanes: usize, block: usize) -> bool {
        self.origin + (block - 1) * self.pitch + lanes * block <= self.seeds.len()
    }
}

/// Implements [`LaneRanker`] for `$ranker`, sorting `$lanes` blocks at
/// once, with the 4x4 kernel `$sort` ([`LaneRanker::sort_4x4`]): a
/// function compiled for an instruction set (`#[target_feature]`), which
/// makes calling it `unsafe`. Sound because a ranker built with this macro
/// is only used inside functions compiled for its instruction set,
/// themselves called only when the CPU has it ([`Isa`](super::Isa)).
#[cfg(target_arch = "x86_64")]
macro_rules! lane_ranker {
    ($ranker:ty, $lanes:expr, $sort:path) => {
        impl $crate::permutation::cpu::ranker::LaneRanker for $ranker {
            const LANES: usize = $lanes;
            #[inline(always)]
            fn sort_4x4(
                strips: &$crate::permutation::cpu::ranker::Strips,
                ranks: &mut [[u32; $crate::permutation::cpu::ranker::MAX_LANES]; 16],
                group: $crate::permutation::cpu::ranker::GroupSeeds<'_>,
                lines: &mut [u32],
            ) {
                // SAFETY: see `lane_ranker`.
                unsafe { $sort(strips, ranks, group, lines) }
            }
        }
    };
}
#[cfg(target_arch = "x86_64")]
pub(super) use lane_ranker;

/// The placement of [`LaneRanker::sort_group`] from each pixel's rank
/// (`ranks[i][l]`, a permutation of `0..N` for each block), one seed at a
/// time.
#[inline(always)]
pub(super) fn place_seeds_scalar<const B: u32, const N: usize>(
    ranks: &[[u32; MAX_LANES]; N],
    group: GroupSeeds<'_>,
    lines: &mut [u32],
) {
    let b = B as usize;
    debug_assert!(group.covers(lines.len() / N, b));
    let GroupSeeds {
        seeds,
        origin,
        pitch: pws,
    } = group;
    for (l, line) in lines.chunks_exact_mut(N).enumerate() {
        let src = &seeds[origin + l * b..origin + l * b + (b - 1) * pws + b];
        for r in 0..b {
            for c in 0..b {
                line[ranks[r * b + c][l] as usize & (N - 1)] = src[r * pws + c];
            }
        }
    }
}

/// Scalar transposition and [`quad_ranks`] over two groups of four lanes;
/// the compiler vectorises the lanes with whatever vector width the build
/// targets (one SSE2 register for four lanes on baseline x86_64).
// The baseline ranker off x86_64; there, the SSE2 ranker is.
#[cfg_attr(target_arch = "x86_64", allow(dead_code))]
pub(super) struct PortableRanker;

impl LaneRanker for PortableRanker {
    const LANES: usize = 8;
}

/// Each pixel's rank for eight lanes (`ranks[i][l]` for pixel `i = r B +
/// c` of block `l`), four at a time, one SSE2
/// register a pixel on x86_64, so a quad's keys and ranks stay in
/// registers ([`quad_ranks`]).
#[inline(always)]
pub(super) fn portable_rank_strips<const B: u32, const N: usize>(
    strips: &Strips,
    ranks: &mut [[u32; MAX_LANES]; N],
) {
    for half in 0..2 {
        let keys: [[i32; 4]; N] = core::array::from_fn(|i| {
            let (r, c) = (i / B as usize, i % B as usize);
            core::array::from_fn(|l| strips[r][(half * 4 + l) * B as usize + c])
        });
        for (out, lanes) in ranks.iter_mut().zip(quad_ranks(&keys)) {
            out[half * 4..half * 4 + 4].copy_from_slice(&lanes);
        }
    }
}

/// Ranks of four independent blocks at once: `keys[i][l]` is pixel `i` of
/// block `l` (`N` a multiple of 4); the result is each pixel's rank in its
/// block's total order (key, then index). Each unordered pair `i < j` costs
/// one comparison and two updates per lane: pixel `j` starts with rank `j`
/// (every `i < j` counted as smaller) and gives one back to `i` when
/// `key_i > key_j`, so ties rank by index with no extra work. Pixels are
/// taken four at a time: a quad's keys and rank accumulators stay in
/// registers while every later pixel is compared with them, so each later
/// pixel's rank is read and written once per quad, not once per pair (the
/// portable form of the AVX2 ranker's `rank_sixteen`).
#[inline(always)]
fn quad_ranks<const N: usize>(keys: &[[i32; 4]; N]) -> [[u32; 4]; N] {
    let mut ranks: [[u32; 4]; N] = core::array::from_fn(|j| [j as u32; 4]);
    let greater = |a: [i32; 4], b: [i32; 4]| -> [u32; 4] { core::array::from_fn(|l| (a[l] > b[l]) as u32) };
    let add = |a: [u32; 4], b: [u32; 4]| -> [u32; 4] { core::array::from_fn(|l| a[l].wrapping_add(b[l])) };
    let sub = |a: [u32; 4], b: [u32; 4]| -> [u32; 4] { core::array::from_fn(|l| a[l].wrapping_sub(b[l])) };
    for q in (0..N).step_by(4) {
        let k: [[i32; 4]; 4] = core::array::from_fn(|a| keys[q + a]);
        let mut acc: [[u32; 4]; 4] = core::array::from_fn(|a| ranks[q + a]);
        for a in 0..4 {
            for b in a + 1..4 {
                let g = greater(k[a], k[b]);
                acc[a] = add(acc[a], g);
                acc[b] = sub(acc[b], g);
            }
        }
        for j in q + 4..N {
            let kj = keys[j];
            let g: [[u32; 4]; 4] = core::array::from_fn(|a| greater(k[a], kj));
            for a in 0..4 {
                acc[a] = add(acc[a], g[a]);
            }
            let given = add(add(g[0], g[1]), add(g[2], g[3]));
            ranks[j] = sub(ranks[j], given);
        }
        ranks[q..q + 4].copy_from_slice(&acc);
    }
    ranks
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quad_ranks_equal_block_ranks() {
        let mut state = 99u32;
        for _ in 0..300 {
            let mut lanes = [[0i32; 4]; 16];
            for row in lanes.iter_mut() {
                for k in row.iter_mut() {
                    state = crate::sequences::seed::hash_u32(state);
                    *k = ((state % 7) as i32 - 3).wrapping_add(if state & 8 != 0 { i32::MIN } else { 0 });
                }
            }
            let ranks = quad_ranks(&lanes);
            for l in 0..4 {
                let keys: [u32; 16] = core::array::from_fn(|i| lanes[i][l] as u32 ^ 0x8000_0000);
                let want = block_ranks(&keys);
                let got: [u32; 16] = core::array::from_fn(|i| ranks[i][l]);
                assert_eq!(got, want, "lane {l}");
            }
        }
    }
}
