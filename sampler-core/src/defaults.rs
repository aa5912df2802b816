//! Baked defaults compiled into the crate (cargo feature `defaults`, on by
//! default; the workspace dependency turns it off so shader crates never
//! carry its 5.6 MiB of data and 2 MiB of zero-initialised statics).
//!
//! The data are the files of `sampler-core/data/` (see its README), produced
//! by the `bake` CLI from recorded seeds: void-and-cluster dither tiles with
//! sigma 1.9, the exact retarget tables of every step of their offset walk
//! (energy about 0.011 of the identity's), and a 128x128x64 spatiotemporal
//! mask with sigma 1.9 in space and time, a 128x128x64 mask adapted to an
//! exponential history (alpha 0.1) times a Gaussian blur (sigma 1.3435), and
//! the optimised keys of the screen-space Sobol sampler, and the temporally
//! blue permutation's target: a 64x64x64 spatiotemporal mask and the exact
//! retarget tables between its consecutive slices. Tiles, tables and keys
//! are decoded at compile time into `u32` statics; the masks are read
//! byte-wise; the target's slices and tables, a quarter of a million words
//! each, are decoded into zero-initialised `u32` statics on first use
//! (module `decoded`).

use crate::masks::spatiotemporal::SpatiotemporalMask;
use crate::permutation::dither::DitherTile;
use crate::permutation::retarget::RetargetTables;
use crate::permutation::temporal::SliceTables;
use crate::sequences::screen_sobol::{ScreenSobolKeys, ScreenSobolLayout};
use crate::sequences::walk::STEP_COUNT;
use decoded::DecodedU16;

mod decoded;

/// Decodes little-endian `u32`s at compile time (no alignment assumption);
/// a length mismatch is a compile error.
const fn decode_u32<const N: usize>(bytes: &[u8]) -> [u32; N] {
    assert!(bytes.len() == 4 * N, "data file has the wrong length");
    let mut out = [0u32; N];
    let mut i = 0;
    while i < N {
        out[i] = u32::from_le_bytes([bytes[4 * i], bytes[4 * i + 1], bytes[4 * i + 2], bytes[4 * i + 3]]);
        i += 1;
    }
    out
}

static TILE_64: [u32; 64 * 64] = decode_u32(include_bytes!("../data/tile_64.bin"));
static TABLES_64: [u32; STEP_COUNT * 64 * 64] = decode_u32(include_bytes!("../data/tables_64.bin"));
static TILE_128: [u32; 128 * 128] = decode_u32(include_bytes!("../data/tile_128.bin"));
static TABLES_128: [u32; STEP_COUNT * 128 * 128] = decode_u32(include_bytes!("../data/tables_128.bin"));
static STBN_128: &[u8; 2 * 128 * 128 * 64] = include_bytes!("../data/stbn_128x128x64.bin");
static FILTER_ADAPTED_128: &[u8; 2 * 128 * 128 * 64] =
    include_bytes!("../data/filter_adapted_128x128x64.bin");
static STBN_64: &[u8; 2 * 64 * 64 * 64] = include_bytes!("../data/stbn_64x64x64.bin");
/// The slices of [`STBN_64`] as `u32` ranks, slice-major, decoded on first use.
static STBN_64_SLICES: DecodedU16<{ 64 * 64 * 64 }> = DecodedU16::new(STBN_64);
/// The retarget tables between its consecutive slices, decoded on first use.
static STBN_64_TABLES: DecodedU16<{ 64 * 64 * 64 }> =
    DecodedU16::new(include_bytes!("../data/stbn_64x64x64_tables.bin"));
/// Side, dimension pairs and spp levels of the default screen-space sampler keys.
const KEYS_LAYOUT: (u32, u32, u32) = (64, 4, 5);
static SCREEN_SOBOL_KEYS: [u32; 5 * 4 * 64 * 64] =
    decode_u32(include_bytes!("../data/screen_sobol_keys_64.bin"));

fn tile(side: u32, values: &'static [u32]) -> DitherTile<'static> {
    match DitherTile::new(side, values) {
        Ok(t) => t,
        // Unreachable: the static's length is fixed by its type above.
        Err(e) => panic!("default {side}x{side} tile is malformed: {e}"),
    }
}

fn tables(side: u32, packed: &'static [u32]) -> RetargetTables<'static> {
    let n = (side * side) as usize;
    let t = |i: usize| &packed[i * n..(i + 1) * n];
    match RetargetTables::new(side, [t(0), t(1), t(2), t(3)]) {
        Ok(t) => t,
        // Unreachable in practice: every default table is validated by a test.
        Err(e) => panic!("default {side}x{side} retarget tables are malformed: {e}"),
    }
}

/// The default 64x64 dither tile: void-and-cluster ranks `0..4096`, sigma 1.9.
///
/// # Panics
/// Never (the data's length is checked at compile time).
pub fn tile_64() -> DitherTile<'static> {
    tile(64, &TILE_64)
}

/// The retarget tables of [`tile_64`], one per step of the 64x64 walk.
///
/// Validation (`RetargetTables::new`) runs on each call: about 4 x 4096 x 169
/// checks, so call once and keep the result.
///
/// # Panics
/// Only if the committed data were corrupt; a test validates them.
pub fn tables_64() -> RetargetTables<'static> {
    tables(64, &TABLES_64)
}

/// The default 128x128 dither tile: void-and-cluster ranks `0..16384`, sigma 1.9.
///
/// # Panics
/// Never (the data's length is checked at compile time).
pub fn tile_128() -> DitherTile<'static> {
    tile(128, &TILE_128)
}

/// The retarget tables of [`tile_128`], one per step of the 128x128 walk.
/// Validates on each call, like [`tables_64`].
///
/// # Panics
/// Only if the committed data were corrupt; a test validates them.
pub fn tables_128() -> RetargetTables<'static> {
    tables(128, &TABLES_128)
}

/// The default 128x128x64 spatiotemporal mask (sigma 1.9 in space and time;
/// each slice holds every rank of `0..16384` once).
///
/// # Panics
/// Never (size and length are fixed above).
pub fn stbn_128() -> SpatiotemporalMask<'static> {
    match SpatiotemporalMask::new(128, 128, 64, STBN_128) {
        Ok(m) => m,
        Err(e) => panic!("default spatiotemporal mask is malformed: {e}"),
    }
}

/// A 64x64x64 spatiotemporal mask, baked like [`stbn_128`] (sigma 1.9 in
/// space and time, same seed; each slice holds every rank of `0..4096`
/// once): the temporally blue permutation's default target
/// ([`temporal_target`]).
///
/// # Panics
/// Never (size and length are fixed above).
pub fn stbn_64() -> SpatiotemporalMask<'static> {
    match SpatiotemporalMask::new(64, 64, 64, STBN_64) {
        Ok(m) => m,
        Err(e) => panic!("default 64x64x64 spatiotemporal mask is malformed: {e}"),
    }
}

/// The temporally blue permutation's default target
/// ([`permute_frame_temporal`](crate::permute_frame_temporal), `gpu-tracer
/// render --mode temporal`): the 64 slices of [`stbn_64`] as 64x64 `u32`
/// rank tiles (ranks `0..4096`, each once per slice) and the 64 exact
/// retarget tables between consecutive slices, table `z` moving seeds ranked
/// like slice `z` so they rank like slice `z + 1` (table 63 from slice 63
/// back to slice 0), read at tile offset 0; offsets in pixels, at most
/// [`RETARGET_RADIUS`](crate::RETARGET_RADIUS) per axis. Made by
/// `bake::bake_slice_tables` (feature `bake`) from [`stbn_64`]; frame `t`
/// uses slice and table `t mod 64`. Its 64x64 slices keep the permutation's
/// cost at the walk's with the 64x64 tile, where the 128x128 slices of
/// [`stbn_128`] cost 1.3x that for the same rendered quality (BENCHMARKS.md
/// and QUALITY.md, "Temporal permutation"). 1 MiB of slices and 1 MiB of
/// tables, zero-initialised statics decoded from the `u16` data by the
/// first call.
///
/// Checks sizes and offsets on each call (call once and keep the result);
/// that every table is a permutation is checked by this module's tests.
///
/// # Panics
/// Only if the committed data were corrupt; a test validates them.
pub fn temporal_target() -> SliceTables<'static> {
    match SliceTables::new_bounded(64, 64, STBN_64_SLICES.words(), STBN_64_TABLES.words()) {
        Ok(t) => t,
        Err(e) => panic!("default temporal target is malformed: {e}"),
    }
}

/// The default filter-adapted 128x128x64 mask: per-slice ranks like
/// [`stbn_128`] (each slice holds every rank of `0..16384` once), arranged
/// so that the thresholded error after an exponential history (TAA-like,
/// alpha 0.1) and a Gaussian blur of sigma 1.3435 is low (the
/// filter-adapted bake of module `bake`, feature `bake`, refining
/// [`stbn_128`]). Use it where the renderer accumulates with an EMA and
/// denoises spatially; [`stbn_128`] where the filters are unknown.
///
/// # Panics
/// Never (size and length are fixed above).
pub fn filter_adapted_128() -> SpatiotemporalMask<'static> {
    match SpatiotemporalMask::new(128, 128, 64, FILTER_ADAPTED_128) {
        Ok(m) => m,
        Err(e) => panic!("default filter-adapted mask is malformed: {e}"),
    }
}

/// The default keys of the screen-space Sobol sampler
/// ([`screen_sobol`](crate::sequences::screen_sobol)): 64x64 tiles for 4 dimension pairs
/// (dimensions 0..8) and 5 spp levels (optimised for 1, 2, 4, 8 and 16 spp),
/// trained on 128 random Heaviside integrands with energy sigma `sqrt 2`
/// (blur of 1 pixel) plus line terms of weight 16 for edges along rows,
/// columns and diagonals (the keys docs of module `bake`, feature `bake`). 320 KiB.
///
/// # Panics
/// Never (the layout is valid and the length fixed above).
pub fn screen_sobol_keys() -> ScreenSobolKeys<'static> {
    let (side, pairs, levels) = KEYS_LAYOUT;
    match ScreenSobolLayout::new(side, pairs, levels)
        .and_then(|l| ScreenSobolKeys::new(l, &SCREEN_SOBOL_KEYS))
    {
        Ok(k) => k,
        Err(e) => panic!("default screen-space sampler keys are malformed: {e}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn exact(values: &[u32]) -> bool {
        let mut seen = [false; 1 << 16];
        values
            .iter()
            .all(|&v| (v as usize) < values.len() && !core::mem::replace(&mut seen[v as usize], true))
    }

    #[test]
    fn defaults_are_valid() {
        assert!(exact(tile_64().values()));
        assert!(exact(tile_128().values()));
        assert_eq!(tables_64().tile(), 64);
        assert_eq!(tables_128().tile(), 128);
        for m in [stbn_128(), filter_adapted_128()] {
            assert_eq!((m.width(), m.height(), m.depth()), (128, 128, 64));
            for z in 0..64 {
                let mut seen = [false; 128 * 128];
                for y in 0..128 {
                    for x in 0..128 {
                        let r = m.rank(x, y, z) as usize;
                        assert!(
                            r < seen.len() && !core::mem::replace(&mut seen[r], true),
                            "slice {z}"
                        );
                    }
                }
                let v = m.value(0, 0, z);
                assert!(v > 0.0 && v < 1.0);
            }
        }
        let m = stbn_64();
        for z in 0..64 {
            let mut slice = [0u32; 64 * 64];
            for (i, r) in slice.iter_mut().enumerate() {
                *r = m.rank(i as u32 % 64, i as u32 / 64, z);
            }
            assert!(exact(&slice), "64x64x64 slice {z}");
        }
        let k = screen_sobol_keys();
        assert_eq!(k.keys().len(), k.layout().key_count());
    }

    /// The slice tables form a valid target (every table a radius-bounded
    /// permutation), its slices are the mask's, and its tables take each
    /// slice's ranks close to the next slice's.
    #[test]
    fn default_slice_tables_are_valid_and_follow_the_mask() {
        use crate::permutation::retarget::RetargetTable;
        let target = temporal_target();
        let mask = stbn_64();
        assert_eq!((target.tile(), target.depth()), (64, 64));
        assert_eq!((mask.width(), mask.height(), mask.depth()), (64, 64, 64));
        SliceTables::new(64, 64, target.slices_packed(), target.tables_packed()).unwrap();
        for z in [0u32, 17, 63] {
            let slice = target.slice(z).values();
            for (i, &r) in slice.iter().enumerate() {
                assert_eq!(r, mask.rank(i as u32 % 64, i as u32 / 64, z), "slice {z}");
            }
            // Moving slice z's ranks with table z lowers their mean
            // mismatch against slice z + 1 (mod 64) well below the identity's.
            let table = RetargetTable::new(64, target.table(z).packed()).unwrap();
            let next = target.slice((z + 1) % 64).values();
            let (mut moved, mut still) = (0u64, 0u64);
            for y in 0..64 {
                for x in 0..64 {
                    let d = table.destination_in_tile(glam::UVec2::new(x, y));
                    let r = slice[(y * 64 + x) as usize] as i64;
                    moved += (r - next[(d.y * 64 + d.x) as usize] as i64).unsigned_abs();
                    still += (r - next[(y * 64 + x) as usize] as i64).unsigned_abs();
                }
            }
            assert!(
                2 * moved < still,
                "slice {z}: mismatch {moved} vs identity {still}"
            );
        }
    }
}
