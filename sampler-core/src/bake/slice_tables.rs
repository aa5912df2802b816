//! The retarget tables between consecutive slices of a spatiotemporal mask:
//! the tables of the temporally blue permutation
//! ([`temporal`](crate::permutation::temporal)).

use super::retarget_bake::bake_retarget_between;
use super::BakeError;
use crate::masks::spatiotemporal::SpatiotemporalMask;
use crate::permutation::dither::DitherTile;
use alloc::vec::Vec;

/// The ranks of slice `z` of `mask` as a row-major `u32` tile
/// (`width * height` values; every rank once in a baked mask).
///
/// # Panics
/// If `z >= mask.depth()`.
pub fn slice_ranks(mask: &SpatiotemporalMask<'_>, z: u32) -> Vec<u32> {
    assert!(z < mask.depth(), "slice {z} of {}", mask.depth());
    let w = mask.width();
    (0..w * mask.height())
        .map(|i| mask.rank(i % w, i / w, z))
        .collect()
}

/// Every slice of `mask`, slice-major then row-major: the slices of a
/// [`SliceTables`](crate::SliceTables).
pub fn slices_packed(mask: &SpatiotemporalMask<'_>) -> Vec<u32> {
    (0..mask.depth()).flat_map(|z| slice_ranks(mask, z)).collect()
}

/// The exact retarget table from slice `z` of `mask` to slice
/// `(z + 1) mod depth` (slice `depth - 1` wraps to slice 0):
/// [`bake_retarget_between`] with no displacement cost, as the temporal
/// permutation reads it (tile offset 0). `width * height` packed offsets.
///
/// # Errors
/// [`BakeError::Size`] if the slices are not square with a power-of-two
/// side (a tile); as [`bake_retarget_between`].
///
/// # Panics
/// If `z >= mask.depth()`.
pub fn bake_slice_table(mask: &SpatiotemporalMask<'_>, z: u32) -> Result<Vec<u32>, BakeError> {
    let side = mask.width();
    if side != mask.height() || !side.is_power_of_two() || side < 2 {
        return Err(BakeError::Size {
            width: mask.width(),
            height: mask.height(),
            depth: mask.depth(),
        });
    }
    let (a, b) = (slice_ranks(mask, z), slice_ranks(mask, (z + 1) % mask.depth()));
    bake_retarget_between(&DitherTile::new(side, &a)?, &DitherTile::new(side, &b)?, 0)
}

/// Every slice's table ([`bake_slice_table`] for `z` in `0..depth`), one
/// after another, table-major: the tables of a
/// [`SliceTables`](crate::SliceTables). A caller with threads can call
/// [`bake_slice_table`] per slice instead.
///
/// # Errors
/// As [`bake_slice_table`].
pub fn bake_slice_tables(mask: &SpatiotemporalMask<'_>) -> Result<Vec<u32>, BakeError> {
    let mut out = Vec::new();
    for z in 0..mask.depth() {
        out.extend(bake_slice_table(mask, z)?);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SliceTables;

    /// On a small mask the tables make a valid target, the last one leads
    /// back to slice 0, and a non-square mask is refused.
    #[test]
    fn slice_tables_of_a_small_mask_are_a_valid_target() {
        let (w, d) = (8u32, 3u32);
        let bytes: Vec<u8> = (0..w * w * d)
            .flat_map(|i| {
                let (z, t) = (i / (w * w), i % (w * w));
                (((t * 37 + 11 * z + z * z) % (w * w)) as u16).to_le_bytes()
            })
            .collect();
        let mask = SpatiotemporalMask::new(w, w, d, &bytes).unwrap();
        let tables = bake_slice_tables(&mask).unwrap();
        let slices = slices_packed(&mask);
        let target = SliceTables::new(w, d, &slices, &tables).unwrap();
        assert_eq!(target.table(2).packed(), &bake_slice_table(&mask, 2).unwrap()[..]);
        let (last, first) = (slice_ranks(&mask, 2), slice_ranks(&mask, 0));
        let wrap = bake_retarget_between(
            &DitherTile::new(w, &last).unwrap(),
            &DitherTile::new(w, &first).unwrap(),
            0,
        )
        .unwrap();
        assert_eq!(target.table(2).packed(), &wrap[..]);
        let flat = SpatiotemporalMask::new(8, 4, 1, &bytes[..64]).unwrap();
        assert!(matches!(bake_slice_table(&flat, 0), Err(BakeError::Size { .. })));
    }
}
