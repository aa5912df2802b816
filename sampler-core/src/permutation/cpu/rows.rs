//! [`permute_frame`](crate::permute_frame) for a band of block rows: the
//! entry point for renderers that split the pass over their own threads.

use super::edge::permute_block_in_band;
use super::{applies, permute_band_cached, Band, Isa};
use crate::error::{Buffer, Error};
use crate::permutation::dither::DitherTile;
use crate::permutation::layout::FrameLayout;
use crate::permutation::retarget::{RetargetTables, RETARGET_RADIUS};
use crate::permutation::sort::Intensity;
use crate::sequences::walk::step_index;
use core::ops::Range;

/// The rows `block_rows` of what [`permute_frame`](crate::permute_frame)
/// writes, computed alone: `seeds_out_rows` receives, bit for bit, the
/// padded seed rows `block_rows.start * B .. min(block_rows.end * B,
/// padded_height)` of `permute_frame`'s `seeds_out` (`B` the block side),
/// i.e. `seeds_out[band_seed_range(layout, block_rows)]`.
///
/// Bands that do not overlap write disjoint slices and read only shared
/// inputs, so a frame split into bands can be permuted on any thread pool
/// (see the example; with `rayon`, `par_chunks_mut` over `seeds_out` in
/// chunks of `rows_per_band * B * padded_width` seeds).
///
/// What a band reads: its own block rows of `intensities` and `seeds_in`,
/// plus the block rows within [`RETARGET_RADIUS`] (6) seed rows above and
/// below it, toroidally (the retarget step moves a seed at most that far,
/// so their seeds may land in the band); those neighbouring blocks are
/// ranked again by each band that needs them (at 1920x1080 with 4x4 blocks,
/// 4 extra block rows per band, 1.5% of the frame). It writes every seed
/// of `seeds_out_rows` and nothing else. The instruction set is the one
/// [`Isa::best`] names.
///
/// # Errors
/// As [`permute_frame`](crate::permute_frame) ([`Error::BufferSize`] with
/// [`Buffer::SeedsOut`] when `seeds_out_rows` is not the band's length);
/// [`Error::BlockRows`] when `block_rows` is not `start <= end <=` the
/// number of block rows (`ceil(padded_height / B)`).
///
/// ```
/// use sampler_core::*;
/// let layout = FrameLayout::new(100, 60, 4, 16)?; // 100x60 frame, 4x4 blocks, 16x16 tile
/// let tile: Vec<u32> = (0..256).map(|i| (i * 7) % 256).collect();
/// let tile = DitherTile::new(16, &tile)?;
/// let identity = [IDENTITY_PACKED; 256];
/// let tables = RetargetTables::new(16, [&identity; 4])?;
/// let image: Vec<f32> = (0..layout.pixel_count()).map(|i| ((i * 37) % 101) as f32).collect();
/// let seeds: Vec<u32> = (0..layout.seed_count() as u32).collect();
///
/// // Two bands on two threads, each writing its own rows of `next`.
/// let blocks_y = layout.params(0).blocks_y();
/// let (top, bottom) = (0..blocks_y / 2, blocks_y / 2..blocks_y);
/// let mut next = vec![0; layout.seed_count()];
/// let (next_top, next_bottom) = next.split_at_mut(band_seed_range(&layout, top.clone()).end);
/// std::thread::scope(|s| {
///     let other = s.spawn(|| permute_frame_rows(&layout, 0, &image, &tile, &tables, &seeds, top, next_top));
///     permute_frame_rows(&layout, 0, &image, &tile, &tables, &seeds, bottom, next_bottom)?;
///     other.join().expect("band thread panicked")
/// })?;
///
/// let mut whole = vec![0; layout.seed_count()];
/// permute_frame(&layout, 0, &image, &tile, &tables, &seeds, &mut whole)?;
/// assert_eq!(next, whole);
/// # Ok::<(), sampler_core::Error>(())
/// ```
#[allow(clippy::too_many_arguments)]
pub fn permute_frame_rows<T: Intensity>(
    layout: &FrameLayout,
    frame: u32,
    intensities: &[T],
    tile: &DitherTile<'_>,
    tables: &RetargetTables<'_>,
    seeds_in: &[u32],
    block_rows: Range<u32>,
    seeds_out_rows: &mut [u32],
) -> Result<(), Error> {
    permute_frame_rows_isa(
        Isa::best(),
        layout,
        frame,
        intensities,
        tile,
        tables,
        seeds_in,
        block_rows,
        seeds_out_rows,
    )
}

/// [`permute_frame_rows`] with the ranker of `isa`, or of the best
/// instruction set below it that the CPU has: identical output, for
/// benchmarks and tests that compare instruction sets on one machine.
/// The whole frame is the band `0..layout.params(frame).blocks_y()`.
///
/// # Errors
/// As [`permute_frame_rows`].
#[doc(hidden)]
#[allow(clippy::too_many_arguments)]
pub fn permute_frame_rows_isa<T: Intensity>(
    isa: Isa,
    layout: &FrameLayout,
    frame: u32,
    intensities: &[T],
    tile: &DitherTile<'_>,
    tables: &RetargetTables<'_>,
    seeds_in: &[u32],
    block_rows: Range<u32>,
    seeds_out_rows: &mut [u32],
) -> Result<(), Error> {
    for side in [tile.tile(), tables.tile()] {
        if side != layout.tile() {
            return Err(Error::TileSize { tile: side });
        }
    }
    layout.check_intensity_buffer(intensities.len())?;
    layout.check_seed_buffer(Buffer::SeedsIn, seeds_in.len())?;
    let params = layout.params(frame);
    let blocks = params.blocks_y();
    if block_rows.start > block_rows.end || block_rows.end > blocks {
        return Err(Error::BlockRows {
            start: block_rows.start,
            end: block_rows.end,
            blocks,
        });
    }
    let expected = band_seed_range(layout, block_rows.clone()).len();
    if seeds_out_rows.len() != expected {
        return Err(Error::BufferSize {
            buffer: Buffer::SeedsOut,
            expected,
            actual: seeds_out_rows.len(),
        });
    }
    if block_rows.is_empty() {
        return Ok(());
    }
    let band = Band::of_block_rows(&params, block_rows);
    let table = tables.table(step_index(frame, params.tile_log2));
    let (values, packed) = (tile.values(), table.packed());
    if applies(&params) {
        permute_band_cached(
            isa,
            &params,
            intensities,
            values,
            table,
            seeds_in,
            band,
            seeds_out_rows,
        );
    } else {
        for rows in band.source_block_rows(&params, RETARGET_RADIUS) {
            for by in rows {
                for bx in 0..params.blocks_x() {
                    permute_block_in_band(
                        &params,
                        bx,
                        by,
                        intensities,
                        values,
                        packed,
                        seeds_in,
                        band,
                        seeds_out_rows,
                    );
                }
            }
        }
    }
    Ok(())
}

/// The seeds that [`permute_frame_rows`] writes for `block_rows`, as a range
/// of indices into the padded seed buffer: rows `block_rows.start * B ..
/// min(block_rows.end * B, padded_height)`, all `padded_width` seeds of
/// each. Ranges of consecutive bands are adjacent (`split_at_mut` or
/// `chunks_mut` cut the output into them).
pub fn band_seed_range(layout: &FrameLayout, block_rows: Range<u32>) -> Range<usize> {
    let band = Band::of_block_rows(&layout.params(0), block_rows);
    let pw = layout.padded_width() as usize;
    band.row0 as usize * pw..band.row_end as usize * pw
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::defaults::{tables_64, tile_64};
    use crate::sequences::seed::hash_u32;
    use std::vec::Vec;

    /// Every instruction set this CPU has, and bands of several sizes, give
    /// the portable whole-frame output (NaN, infinities, ties, odd sizes).
    #[test]
    fn every_isa_and_band_split_equals_the_portable_frame() {
        let tile = tile_64();
        let tables = tables_64();
        let mut state = 7u32;
        for (width, height) in [(64, 64), (200, 77), (480, 270), (37, 128)] {
            let layout = FrameLayout::new(width, height, 4, 64).unwrap();
            for frame in [0u32, 5, 1000] {
                let intensities: Vec<f32> = (0..layout.pixel_count())
                    .map(|_| {
                        state = hash_u32(state);
                        match state % 11 {
                            0 => f32::NAN,
                            1 => f32::INFINITY,
                            2 => f32::NEG_INFINITY,
                            3 => -0.0,
                            4 => (state >> 28) as f32,
                            _ => f32::from_bits(state >> 2) - 1.0,
                        }
                    })
                    .collect();
                let seeds: Vec<u32> = (0..layout.seed_count() as u32).map(hash_u32).collect();
                let blocks = layout.params(frame).blocks_y();
                let mut want = std::vec![0u32; seeds.len()];
                let whole = 0..blocks;
                permute_frame_rows_isa(
                    Isa::Baseline,
                    &layout,
                    frame,
                    &intensities,
                    &tile,
                    &tables,
                    &seeds,
                    whole,
                    &mut want,
                )
                .unwrap();
                for isa in Isa::ALL {
                    if !isa.is_available() {
                        std::println!("skipped {isa:?}: not on this CPU");
                        continue;
                    }
                    for bands in [1u32, 2, 3, 7] {
                        let mut got = std::vec![u32::MAX; seeds.len()];
                        for k in 0..bands {
                            let rows = blocks * k / bands..blocks * (k + 1) / bands;
                            let out = &mut got[band_seed_range(&layout, rows.clone())];
                            permute_frame_rows_isa(
                                isa,
                                &layout,
                                frame,
                                &intensities,
                                &tile,
                                &tables,
                                &seeds,
                                rows,
                                out,
                            )
                            .unwrap();
                        }
                        assert!(
                            got == want,
                            "{isa:?}, {bands} bands, {width}x{height} frame {frame}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn bad_bands_are_errors() {
        let layout = FrameLayout::new(64, 64, 4, 64).unwrap();
        let (tile, tables) = (tile_64(), tables_64());
        let image = std::vec![0f32; layout.pixel_count()];
        let seeds = std::vec![0u32; layout.seed_count()];
        let mut out = std::vec![0u32; layout.seed_count()];
        let run = |rows: Range<u32>, out: &mut [u32]| {
            permute_frame_rows(&layout, 0, &image, &tile, &tables, &seeds, rows, out)
        };
        assert_eq!(
            run(0..17, &mut out),
            Err(Error::BlockRows {
                start: 0,
                end: 17,
                blocks: 16
            })
        );
        assert!(matches!(
            run(0..8, &mut out),
            Err(Error::BufferSize {
                buffer: Buffer::SeedsOut,
                ..
            })
        ));
        assert_eq!(run(0..8, &mut out[..32 * 64]), Ok(()));
        assert_eq!(run(3..3, &mut []), Ok(()));
    }
}
