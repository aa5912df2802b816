//! The a-priori samplers' data, as the trace kernel reads it from one
//! buffer (binding 7 of `kernels::abi::TRACE_ENTRY`): the screen-space Sobol
//! keys (`sampler_core::defaults::screen_sobol_keys()`), then the
//! spatiotemporal sampler's 64x64 shift tile as its `STEP_COUNT` shift-pair
//! tiles and the jitter pair's net shifts
//! (`sampler_core::sequences::spatiotemporal::write_shift_pair_tiles`
//! of the ranks of `sampler_core::defaults::tile_64()`, at index
//! `key_count()` of the keys' layout: a pair's two shift coordinates in one
//! word), then the Kronecker generators of its `SAMPLER_KRONECKER`
//! sequence (`sampler_core::sequences::kronecker::KRONECKER_GENERATORS`),
//! then room for the spatiotemporal sampler's frame point table
//! ([`with_frame_points`]: the sequence points every pixel of a frame shares,
//! computed once per frame instead of once per pixel).

use kernels::abi::{TraceParams, MAX_DEPTH_LIMIT, SAMPLER_SPATIOTEMPORAL, SPATIOTEMPORAL_TILE_LOG2};
use kernels::numbers::{
    point_slot_pair, point_slots, point_table_start, sampler_kind, spatiotemporal_sequence,
};
use sampler_core::sequences::kronecker::KRONECKER_GENERATORS;
use sampler_core::sequences::spatiotemporal::{shift_pair_tiles_len, write_shift_pair_tiles};
use std::sync::OnceLock;

/// Words reserved for the frame point table after the shift tile: 64
/// samples of a path of [`MAX_DEPTH_LIMIT`] vertices (`2 * 64 *
/// point_slots(MAX_DEPTH_LIMIT)`, 99 KB); shallower paths fit more samples.
/// Samples past the table are computed by the kernel.
pub const POINT_TABLE_WORDS: usize = 2 * 64 * (1 + 3 * MAX_DEPTH_LIMIT as usize);

/// The buffer the CPU renderer passes and the GPU binds for every sampler.
///
/// # Panics
/// Never with the crate's baked defaults (the asserts check their sizes).
pub fn sampler_buffer() -> &'static [u32] {
    static BUFFER: OnceLock<Vec<u32>> = OnceLock::new();
    BUFFER.get_or_init(|| {
        let keys = sampler_core::defaults::screen_sobol_keys();
        let tile = sampler_core::defaults::tile_64();
        assert_eq!(
            tile.tile(),
            1 << SPATIOTEMPORAL_TILE_LOG2,
            "the shift tile's side"
        );
        assert_eq!(
            keys.keys().len(),
            keys.layout().key_count(),
            "keys fill their layout"
        );
        let mut buffer = keys.keys().to_vec();
        buffer.extend_from_slice(&shift_pair_tiles(tile.values()));
        buffer.extend_from_slice(&KRONECKER_GENERATORS);
        buffer.resize(buffer.len() + POINT_TABLE_WORDS, 0);
        buffer
    })
}

/// The shift-pair tiles of the spatiotemporal sampler's rank tile `ranks`
/// (side `2^SPATIOTEMPORAL_TILE_LOG2`), then its jitter pair's net shifts.
///
/// # Panics
/// If `ranks` is not that tile's size.
fn shift_pair_tiles(ranks: &[u32]) -> Vec<u32> {
    let mut out = vec![0u32; shift_pair_tiles_len(SPATIOTEMPORAL_TILE_LOG2)];
    write_shift_pair_tiles(ranks, SPATIOTEMPORAL_TILE_LOG2, &mut out).expect("the shift tile's size");
    out
}

/// Index in [`sampler_buffer`] of the frame point table.
pub fn point_table_offset() -> usize {
    point_table_start(sampler_core::defaults::screen_sobol_keys().layout().key_count())
}

/// `params` with [`TraceParams::point_samples`] set, and the frame point
/// table to store at [`point_table_offset`] of [`sampler_buffer`] before
/// tracing with them: with [`SAMPLER_SPATIOTEMPORAL`], the unshifted
/// sequence points of frame `params.frame` for as many of its samples as
/// [`POINT_TABLE_WORDS`] holds
/// (`sampler_core::sequences::spatiotemporal::spatiotemporal_frame_points`,
/// pairs in `kernels::numbers::point_slot` order); for every other sampler
/// `params` unchanged (`point_samples = 0`) and an empty table. Tracing with
/// the returned parameters gives the same numbers as with `point_samples =
/// 0`, only faster.
pub fn with_frame_points(params: &TraceParams) -> (TraceParams, Vec<u32>) {
    let mut out = *params;
    out.point_samples = 0;
    if sampler_kind(params) != SAMPLER_SPATIOTEMPORAL {
        return (out, Vec::new());
    }
    let slots = point_slots(params.max_depth);
    let samples = params
        .spp
        .max(1)
        .min((POINT_TABLE_WORDS / (2 * slots as usize)) as u32);
    let pairs: Vec<u32> = (0..slots).map(|k| point_slot_pair(k, params.max_depth)).collect();
    let mut table = vec![0u32; 2 * samples as usize * pairs.len()];
    sampler_core::sequences::spatiotemporal::spatiotemporal_frame_points(
        spatiotemporal_sequence(params),
        params.frame,
        params.spp.max(1),
        samples,
        &pairs,
        &mut table,
    )
    .expect("the table is sized for its samples and pairs");
    out.point_samples = samples;
    (out, table)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tile_follows_the_keys() {
        use kernels::numbers::generators_start;
        let b = sampler_buffer();
        let keys = sampler_core::defaults::screen_sobol_keys();
        let n = keys.layout().key_count();
        assert_eq!(&b[..n], keys.keys());
        let tile = shift_pair_tiles_len(SPATIOTEMPORAL_TILE_LOG2);
        let ranks = sampler_core::defaults::tile_64();
        let packed = &b[n..n + tile];
        let texels = 1 << (2 * SPATIOTEMPORAL_TILE_LOG2);
        for j in 0..sampler_core::STEP_COUNT {
            let part = &packed[j * texels..(j + 1) * texels];
            // Every shift-pair tile holds the ranks in its low halves.
            assert!(part.iter().zip(ranks.values()).all(|(w, r)| w & 0xFFFF == *r));
        }
        // Then the net shifts, one tile more.
        assert_eq!(tile, (sampler_core::STEP_COUNT + 1) * texels);
        assert_eq!(packed, shift_pair_tiles(ranks.values()).as_slice());
        assert_eq!(generators_start(n), n + tile);
        let g = KRONECKER_GENERATORS.len();
        assert_eq!(&b[n + tile..n + tile + g], KRONECKER_GENERATORS.as_slice());
        assert_eq!(point_table_offset(), n + tile + g);
        assert_eq!(b.len() - point_table_offset(), POINT_TABLE_WORDS);
    }

    /// Every pair a path draws reads the same numbers from the frame table as
    /// the kernel computes without it, at several depths and spp, including
    /// samples past the table.
    #[test]
    fn the_frame_table_gives_the_computed_numbers() {
        use glam::UVec2;
        use kernels::abi::SAMPLER_KRONECKER;
        use kernels::numbers::{apriori_pair, pair_bsdf, pair_light, pair_roulette, point_slot};
        let keys = sampler_core::defaults::screen_sobol_keys();
        let l = keys.layout();
        let cases = [
            (1u32, 8u32, 0u32, 0u32),
            (1, 8, 77, SAMPLER_KRONECKER),
            (4, 3, 5, 0),
            (200, 64, 9, SAMPLER_KRONECKER),
        ];
        for (spp, max_depth, frame, flag) in cases {
            let params = TraceParams {
                spp,
                max_depth,
                frame,
                sampler: SAMPLER_SPATIOTEMPORAL | flag,
                key_side_log2: l.side_log2,
                key_pairs: l.pairs,
                key_levels: l.levels,
                ..Default::default()
            };
            let (with, table) = with_frame_points(&params);
            assert!(with.point_samples >= 1 && with.point_samples <= spp);
            assert_eq!(
                with.point_samples == spp,
                spp < 200,
                "{spp} spp at depth {max_depth}"
            );
            let mut buffer = sampler_buffer().to_vec();
            buffer[point_table_offset()..point_table_offset() + table.len()].copy_from_slice(&table);
            let mut pairs = vec![0u32];
            for d in 0..max_depth {
                pairs.extend([pair_light(d), pair_bsdf(d), pair_roulette(d)]);
            }
            for &pair in &pairs {
                assert_ne!(point_slot(pair, max_depth), u32::MAX);
                for s in [0, spp / 2, spp - 1] {
                    for pixel in [UVec2::new(0, 0), UVec2::new(1279, 3), UVec2::new(65, 700)] {
                        assert_eq!(
                            apriori_pair(&with, &buffer, pixel, s, pair),
                            apriori_pair(&params, sampler_buffer(), pixel, s, pair),
                            "pair {pair} sample {s} pixel {pixel} ({spp} spp, depth {max_depth})"
                        );
                    }
                }
            }
        }
        // The table is read, not recomputed: a zeroed one changes the numbers.
        let params = TraceParams {
            spp: 1,
            max_depth: 8,
            frame: 3,
            sampler: SAMPLER_SPATIOTEMPORAL,
            key_side_log2: l.side_log2,
            key_pairs: l.pairs,
            key_levels: l.levels,
            ..Default::default()
        };
        let (with, _) = with_frame_points(&params);
        let pixel = UVec2::new(9, 9);
        assert_ne!(
            apriori_pair(&with, sampler_buffer(), pixel, 0, pair_bsdf(2)),
            apriori_pair(&params, sampler_buffer(), pixel, 0, pair_bsdf(2))
        );
        // Other samplers: no table.
        let (p, t) = with_frame_points(&TraceParams::default());
        assert_eq!((p.point_samples, t.len()), (0, 0));
    }

    /// The kernel's pair is the sampler's definition on the plain rank tile:
    /// the sequence point plus the two separate tile reads of the shift.
    #[test]
    fn the_kernel_reads_the_shifts_of_the_rank_tile() {
        use glam::{UVec2, Vec2};
        use kernels::numbers::apriori_pair;
        use sampler_core::sequences::r2::q32_to_f32;
        use sampler_core::sequences::spatiotemporal::{
            spatiotemporal_pair_u32, spatiotemporal_shift_u32, SEQUENCE_SOBOL,
        };
        let l = sampler_core::defaults::screen_sobol_keys().layout();
        let params = TraceParams {
            spp: 2,
            max_depth: 8,
            frame: 41,
            sampler: SAMPLER_SPATIOTEMPORAL,
            key_side_log2: l.side_log2,
            key_pairs: l.pairs,
            key_levels: l.levels,
            ..Default::default()
        };
        let ranks = sampler_core::defaults::tile_64();
        for pair in 0..25 {
            for pixel in [
                UVec2::new(0, 0),
                UVec2::new(63, 1),
                UVec2::new(1279, 719),
                UVec2::new(200, 77),
            ] {
                let shift = spatiotemporal_shift_u32(ranks.values(), SPATIOTEMPORAL_TILE_LOG2, pixel, pair);
                let want = spatiotemporal_pair_u32(SEQUENCE_SOBOL, shift, params.frame, params.spp, 1, pair);
                assert_eq!(
                    apriori_pair(&params, sampler_buffer(), pixel, 1, pair),
                    Vec2::new(q32_to_f32(want[0]), q32_to_f32(want[1])),
                    "pair {pair} pixel {pixel}"
                );
            }
        }
    }
}
