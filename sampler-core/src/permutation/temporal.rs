//! The temporally blue permutation (issue 29): the sorting target of frame
//! `t` is slice `z = t mod D` of a spatiotemporal mask (blue in space and
//! along time at every pixel), and the retarget table after it moves seeds
//! from slice `z` to slice `z + 1` (slice `D - 1` to slice 0 at the wrap),
//! both read at tile offset 0 every frame (the walk's offset `o_0`).
//!
//! ```text
//! loop t:  image_t = render(seeds)
//!          z       = t mod D
//!          seeds   = permute_frame_temporal(t, image_t, seeds)  // sort with slice z, retarget z -> z+1
//! ```
//!
//! With fixed seed streams a block's values then repeat every frame and only
//! their arrangement changes: each pixel takes, over frames, values in the
//! order the mask's ranks give it, blue in time; the retarget tables still
//! carry seeds across block borders. The arrangement repeats every `D`
//! frames.
//!
//! The table of slice `z` is what `bake::bake_retarget_between(slice z,
//! slice z + 1 mod D, 0)` returns (feature `bake`): exact, radius-bounded,
//! in the packing of [`retarget`](crate::permutation::retarget). The
//! default target, a 64x64x64 mask and its tables, is compiled in
//! (`defaults::temporal_target`, feature `defaults`).

use crate::error::{Buffer, Error};
use crate::permutation::dither::DitherTile;
use crate::permutation::frame::{check_common, permute_checked};
use crate::permutation::layout::FrameLayout;
use crate::permutation::retarget::RetargetTable;
use crate::permutation::sort::Intensity;
use crate::sequences::walk::tile_log2;

/// The slices of a spatiotemporal mask as rank tiles and the retarget
/// tables between consecutive slices: the sorting target of
/// [`permute_frame_temporal`].
///
/// Slice `z` (`0..depth`) holds `tile * tile` `u32` values, row-major
/// (baked masks: ranks `0..tile * tile`, each once); table `z` holds
/// `tile * tile` packed offsets that move seeds ranked like slice `z` so
/// they rank like slice `(z + 1) mod depth`, read at tile offset 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SliceTables<'a> {
    tile_log2: u32,
    depth: u32,
    slices: &'a [u32],
    tables: &'a [u32],
}

impl<'a> SliceTables<'a> {
    /// Validates `depth` slices and `depth` tables for a `tile x tile`
    /// target, each array slice-major then row-major
    /// (`depth * tile * tile` entries). Every table is checked as
    /// [`RetargetTable::new`] does (about 170 reads a texel: call once and
    /// keep the result).
    ///
    /// # Errors
    /// [`Error::TileSize`] for a tile that is not a power of two in
    /// `2..=MAX_TILE`; [`Error::MaskSize`] for `depth == 0`;
    /// [`Error::BufferSize`] ([`Buffer::TemporalSlices`],
    /// [`Buffer::TemporalTables`]) for a wrong length; as
    /// [`RetargetTable::new`] for a table that is not a radius-bounded
    /// permutation.
    pub fn new(tile: u32, depth: u32, slices: &'a [u32], tables: &'a [u32]) -> Result<Self, Error> {
        let target = Self::new_bounded(tile, depth, slices, tables)?;
        for z in 0..depth {
            RetargetTable::new(tile, target.table(z).packed())?;
        }
        Ok(target)
    }

    /// [`new`](Self::new) without the tables' bijection check (sizes and
    /// offsets' radius are checked): for compiled-in data whose tests
    /// check the rest.
    ///
    /// # Errors
    /// As [`new`](Self::new), except [`Error::RetargetNotBijective`].
    pub(crate) fn new_bounded(
        tile: u32,
        depth: u32,
        slices: &'a [u32],
        tables: &'a [u32],
    ) -> Result<Self, Error> {
        let log2 = tile_log2(tile).ok_or(Error::TileSize { tile })?;
        if depth == 0 {
            return Err(Error::MaskSize {
                width: tile,
                height: tile,
                depth,
            });
        }
        let expected = depth as usize * (tile as usize * tile as usize);
        for (buffer, actual) in [
            (Buffer::TemporalSlices, slices.len()),
            (Buffer::TemporalTables, tables.len()),
        ] {
            if actual != expected {
                return Err(Error::BufferSize {
                    buffer,
                    expected,
                    actual,
                });
            }
        }
        let n = expected / depth as usize;
        for packed in tables.chunks_exact(n) {
            RetargetTable::new_bounded(tile, packed)?;
        }
        Ok(SliceTables {
            tile_log2: log2,
            depth,
            slices,
            tables,
        })
    }

    /// Tile (slice) side in texels.
    pub fn tile(&self) -> u32 {
        1 << self.tile_log2
    }
    /// Number of slices (and of tables), `>= 1`.
    pub fn depth(&self) -> u32 {
        self.depth
    }
    /// The slice frame `frame` sorts against (and whose table it
    /// retargets with): `frame mod depth`.
    pub fn slice_index(&self, frame: u32) -> u32 {
        frame % self.depth
    }
    /// Texels per slice, `tile * tile`.
    fn texels(&self) -> usize {
        1usize << (2 * self.tile_log2)
    }
    /// Slice `z` as a dither tile.
    ///
    /// # Panics
    /// If `z >= depth`.
    pub fn slice(&self, z: u32) -> DitherTile<'a> {
        assert!(z < self.depth, "slice {z} of {}", self.depth);
        let n = self.texels();
        DitherTile::from_checked(self.tile_log2, &self.slices[z as usize * n..][..n])
    }
    /// The table from slice `z` to slice `(z + 1) mod depth`.
    ///
    /// # Panics
    /// If `z >= depth`.
    pub fn table(&self, z: u32) -> RetargetTable<'a> {
        assert!(z < self.depth, "table {z} of {}", self.depth);
        let n = self.texels();
        RetargetTable::from_checked(self.tile_log2, &self.tables[z as usize * n..][..n])
    }
    /// Every slice, slice-major then row-major (`depth * tile * tile`
    /// values): what a GPU uploads once.
    pub fn slices_packed(&self) -> &'a [u32] {
        self.slices
    }
    /// Every table, table-major then row-major (`depth * tile * tile`
    /// packed offsets).
    pub fn tables_packed(&self) -> &'a [u32] {
        self.tables
    }
}

/// The temporally blue permutation's step after frame `frame`: every block
/// of `seeds_in` sorted so that `intensities` rank like slice
/// `z = frame mod depth` of `target` at tile offset 0, then scattered with
/// table `z` (to slice `z + 1`), into `seeds_out`, fused in one pass with no
/// allocation (the fast path of [`permute_frame`](crate::permute_frame)).
/// Identical to [`sort_block_at_offset`](crate::sort_block_at_offset) on
/// every block with offset 0 and slice `z`, then
/// [`retarget_pixel_at_offset`](crate::retarget_pixel_at_offset) on every
/// seed with offset 0 and table `z`; and to what the GPU's sort and
/// retarget kernels compute with frame parameters of frame 0 and slice and
/// table `z` bound. A permutation of the seeds.
///
/// # Errors
/// [`Error::BufferSize`] for a buffer of the wrong length,
/// [`Error::TileSize`] if the target's tile differs from the layout's.
///
/// ```
/// use sampler_core::{permute_frame_temporal, FrameLayout, SliceTables, IDENTITY_PACKED};
/// let layout = FrameLayout::new(6, 5, 2, 4)?; // 6x5 frame, 2x2 blocks, 4x4 slices
/// let slices: Vec<u32> = (0..2 * 16).map(|i| (i * 7 + i / 16) % 16).collect();
/// let tables = [IDENTITY_PACKED; 2 * 16];
/// let target = SliceTables::new(4, 2, &slices, &tables)?;
/// let seeds: Vec<u32> = (0..layout.seed_count() as u32).collect();
/// let image: Vec<f32> = (0..30).map(|i| (i % 5) as f32).collect();
/// let mut next = vec![0; seeds.len()];
/// permute_frame_temporal(&layout, 3, &image, &target, &seeds, &mut next)?; // slice 1
/// let mut sorted = next.clone();
/// sorted.sort();
/// assert_eq!(sorted, seeds);
/// # Ok::<(), sampler_core::Error>(())
/// ```
pub fn permute_frame_temporal<T: Intensity>(
    layout: &FrameLayout,
    frame: u32,
    intensities: &[T],
    target: &SliceTables<'_>,
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) -> Result<(), Error> {
    let z = target.slice_index(frame);
    let slice = target.slice(z);
    check_common(layout, &slice, intensities, seeds_in, seeds_out)?;
    // Frame 0's parameters: the walk's offset `o_0` is (0, 0).
    let params = layout.params(0);
    permute_checked(
        &params,
        intensities,
        slice.values(),
        target.table(z),
        seeds_in,
        seeds_out,
        true,
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::permutation::frame::{retarget_pixel_at_offset, sort_block_at_offset};
    use crate::permutation::retarget::{pack_offset, IDENTITY_PACKED};
    use crate::sequences::seed::{hash_u32, random_f32};
    use glam::{IVec2, UVec2};
    use std::vec;
    use std::vec::Vec;

    const TILE: u32 = 16;
    const DEPTH: u32 = 3;
    const N: usize = (TILE * TILE) as usize;

    /// Three 16x16 slices of distinct ranks, and three tables: pairs of
    /// texels swapped along rows, columns and diagonals (radius 1..3).
    fn target_data() -> (Vec<u32>, Vec<u32>) {
        let mut slices = Vec::new();
        for z in 0..DEPTH {
            slices.extend((0..N as u32).map(|i| (i * 97 + 31 * z) % N as u32));
        }
        let mut tables = vec![IDENTITY_PACKED; DEPTH as usize * N];
        for (z, table) in tables.chunks_exact_mut(N).enumerate() {
            let d = IVec2::new(1 + z as i32 % 2, (z as i32 + 1) / 2);
            for y in (0..TILE as i32).step_by(4) {
                for x in (0..TILE as i32).step_by(4) {
                    table[(y * TILE as i32 + x) as usize] = pack_offset(d);
                    table[((y + d.y) * TILE as i32 + x + d.x) as usize] = pack_offset(-d);
                }
            }
        }
        (slices, tables)
    }

    /// The reference: sort every block at offset 0, then retarget every seed.
    fn reference(
        layout: &FrameLayout,
        values: &[f32],
        slice: &[u32],
        table: &[u32],
        seeds: &[u32],
    ) -> Vec<u32> {
        let params = layout.params(0);
        let mut sorted = seeds.to_vec();
        for by in 0..params.blocks_y() {
            for bx in 0..params.blocks_x() {
                sort_block_at_offset(&params, UVec2::ZERO, bx, by, values, slice, seeds, &mut sorted);
            }
        }
        let mut next = vec![u32::MAX; seeds.len()];
        for i in 0..params.seed_count() {
            retarget_pixel_at_offset(&params, UVec2::ZERO, i, table, &sorted, &mut next);
        }
        next
    }

    /// The fused pass equals sort then retarget at offset 0 with the
    /// frame's slice and table, on odd sizes, every block side the fast
    /// path takes and one it does not, across the wrap of the slices.
    #[test]
    fn the_fused_step_equals_sort_then_retarget() {
        let (slices, tables) = target_data();
        let target = SliceTables::new(TILE, DEPTH, &slices, &tables).unwrap();
        for (width, height, block) in [(37, 21, 4), (16, 16, 2), (45, 19, 8), (23, 29, 3)] {
            let layout = FrameLayout::new(width, height, block, TILE).unwrap();
            let values: Vec<f32> = (0..layout.pixel_count() as u32)
                .map(|i| random_f32(i, block))
                .collect();
            let seeds: Vec<u32> = (0..layout.seed_count() as u32).map(hash_u32).collect();
            for frame in [0, 1, 2, 3, 5, u32::MAX] {
                let z = (frame % DEPTH) as usize;
                let want = reference(
                    &layout,
                    &values,
                    &slices[z * N..][..N],
                    &tables[z * N..][..N],
                    &seeds,
                );
                let mut got = vec![0; seeds.len()];
                permute_frame_temporal(&layout, frame, &values, &target, &seeds, &mut got).unwrap();
                assert_eq!(got, want, "{width}x{height}, block {block}, frame {frame}");
                let mut check = got.clone();
                check.sort_unstable();
                let mut all = seeds.clone();
                all.sort_unstable();
                assert_eq!(check, all, "seeds lost or repeated");
            }
        }
    }

    #[test]
    fn bad_targets_are_errors() {
        let (slices, mut tables) = target_data();
        assert!(matches!(
            SliceTables::new(TILE, DEPTH, &slices[1..], &tables),
            Err(Error::BufferSize {
                buffer: Buffer::TemporalSlices,
                ..
            })
        ));
        assert!(matches!(
            SliceTables::new(TILE, 0, &[], &[]),
            Err(Error::MaskSize { depth: 0, .. })
        ));
        assert!(matches!(
            SliceTables::new(12, 1, &slices[..144], &tables[..144]),
            Err(Error::TileSize { tile: 12 })
        ));
        // Table 2 loses a seed: caught by `new`, not by the bounded check.
        tables[2 * N] = pack_offset(IVec2::new(1, 0));
        assert!(matches!(
            SliceTables::new(TILE, DEPTH, &slices, &tables),
            Err(Error::RetargetNotBijective { .. })
        ));
        assert!(SliceTables::new_bounded(TILE, DEPTH, &slices, &tables).is_ok());
        tables[2 * N] = pack_offset(IVec2::new(7, 0));
        assert!(matches!(
            SliceTables::new_bounded(TILE, DEPTH, &slices, &tables),
            Err(Error::RetargetOffset { .. })
        ));
        let layout = FrameLayout::new(10, 10, 2, 32).unwrap();
        let good = target_data().1;
        let target = SliceTables::new(TILE, DEPTH, &slices, &good).unwrap();
        let seeds = vec![0; layout.seed_count()];
        let mut out = seeds.clone();
        assert_eq!(
            permute_frame_temporal(&layout, 0, &[0.0f32; 100], &target, &seeds, &mut out),
            Err(Error::TileSize { tile: TILE })
        );
    }
}
