//! Baking retarget tables as exact assignment problems.
//!
//! Convention (that of [`retarget`](crate::permutation::retarget) and
//! [`walk`](crate::sequences::walk)): table index `i` serves the step
//! `s = step_of_index(i, k)`; the seed at tile texel `q` moves to
//! `d = (q + R(q)) mod W` with `|R|_inf <=` [`RETARGET_RADIUS`], the map
//! `q -> d` is a permutation of the tile, and the baker minimises the L1
//! energy
//!
//! ```text
//! E(R) = sum over q of |tile[q] - tile[(q + R(q) + s) mod W]|
//! ```
//!
//! i.e. after the move, the next frame's dither value at the seed's new
//! place is as close as possible to the one it was sorted against. Each
//! texel has `(2 r + 1)^2 = 169` candidate destinations: a sparse
//! assignment problem, solved exactly by [`solve_assignment`]. The identity
//! (`R = 0`) is the "before" energy.
//!
//! A [`DISPLACEMENT_COST`] per texel of `|dx| + |dy|` can be added to each
//! edge ([`bake_retarget_table_with`]) to prefer short moves.
//!
//! Offsets are stored in their canonical form per axis: `-6..=6` on tiles of
//! at least 13 texels; on smaller tiles every destination is reachable and
//! the offsets are `-(W/2 - 1)..=W/2`.

use super::assignment::{solve_assignment, SparseCosts};
use super::BakeError;
use crate::permutation::dither::DitherTile;
use crate::permutation::retarget::{
    pack_offset, unpack_offset, RetargetTable, IDENTITY_PACKED, RETARGET_RADIUS,
};
use crate::sequences::walk::{step_of_index, STEP_COUNT};
use alloc::vec;
use alloc::vec::Vec;
use glam::{IVec2, UVec2};

/// Candidate offsets along one axis of a tile of side `w`.
fn axis_offsets(w: u32) -> Vec<i32> {
    let w = w as i32;
    if w > 2 * RETARGET_RADIUS {
        (-RETARGET_RADIUS..=RETARGET_RADIUS).collect()
    } else {
        (-(w / 2 - 1)..=w / 2).collect()
    }
}

/// The sparse cost graph of one retarget table: source `q` (row-major tile
/// texel) to destination `d` within the radius, cost
/// `|tile[q] - tile[(d + s) mod W]|`.
#[derive(Clone, Debug)]
pub struct RetargetCosts<'a> {
    tile: DitherTile<'a>,
    /// Added cost per texel of `|dx| + |dy|`.
    displacement_cost: u32,
    /// `tile[(d + s) mod W]` for every destination `d`.
    shifted: Vec<u32>,
    /// Candidate offsets as `(dx, dy)`, row-major over the square of
    /// [`axis_offsets`].
    offsets: Vec<IVec2>,
}

impl<'a> RetargetCosts<'a> {
    /// The graph for step `step` (each component in `0..W`), costs
    /// `|tile[q] - tile[(d + s) mod W]| + displacement_cost * (|dx| + |dy|)`.
    pub fn new(tile: DitherTile<'a>, step: UVec2, displacement_cost: u32) -> Self {
        let w = tile.tile();
        let m = w - 1;
        let k = tile.tile_log2();
        let v = tile.values();
        let mut shifted = Vec::with_capacity(v.len());
        for y in 0..w {
            for x in 0..w {
                shifted.push(v[((((y + step.y) & m) << k) | ((x + step.x) & m)) as usize]);
            }
        }
        RetargetCosts::with_target(tile, shifted, displacement_cost)
    }

    /// The graph from `tile` to the target ranks `target[d]` per destination.
    fn with_target(tile: DitherTile<'a>, target: Vec<u32>, displacement_cost: u32) -> Self {
        let axis = axis_offsets(tile.tile());
        let offsets = axis
            .iter()
            .flat_map(|&dy| axis.iter().map(move |&dx| IVec2::new(dx, dy)))
            .collect();
        RetargetCosts {
            tile,
            displacement_cost,
            shifted: target,
            offsets,
        }
    }

    /// The graph from `source`'s arrangement to another tile's, `target`
    /// (same side, ranks of its own): costs `|source[q] - target[d]| +
    /// displacement_cost * (|dx| + |dy|)`. For targets that are not a shift of
    /// the source, such as consecutive slices of a spatiotemporal mask.
    ///
    /// # Errors
    /// [`BakeError::Size`] (the target's side) if `target` has another side.
    pub fn between(
        source: DitherTile<'a>,
        target: &DitherTile<'_>,
        displacement_cost: u32,
    ) -> Result<Self, BakeError> {
        if target.tile() != source.tile() {
            return Err(BakeError::Size {
                width: target.tile(),
                height: target.tile(),
                depth: 1,
            });
        }
        Ok(RetargetCosts::with_target(
            source,
            target.values().to_vec(),
            displacement_cost,
        ))
    }

    #[inline]
    fn destination(&self, q: usize, o: IVec2) -> usize {
        let k = self.tile.tile_log2();
        let m = (1i32 << k) - 1;
        let (x, y) = ((q as i32) & m, (q as i32) >> k);
        ((((y + o.y) & m) << k) | ((x + o.x) & m)) as usize
    }

    /// The canonical offset that moves `q` to `d` (must be a candidate).
    fn offset_between(&self, q: usize, d: usize) -> IVec2 {
        self.offsets
            .iter()
            .copied()
            .find(|&o| self.destination(q, o) == d)
            .unwrap_or(IVec2::ZERO)
    }
}

impl SparseCosts for RetargetCosts<'_> {
    fn size(&self) -> usize {
        self.shifted.len()
    }
    #[inline]
    fn for_each_edge(&self, source: usize, mut edge: impl FnMut(usize, u64)) {
        let a = self.tile.values()[source];
        for &o in &self.offsets {
            let d = self.destination(source, o);
            let moved = (o.x.unsigned_abs() + o.y.unsigned_abs()) * self.displacement_cost;
            edge(d, a.abs_diff(self.shifted[d]) as u64 + moved as u64);
        }
    }
}

/// The L1 energy `sum |tile[q] - tile[(q + R(q) + step) mod W]|` of a
/// packed table (offsets wrap toroidally; `table.len()` must equal the
/// tile's texel count, extra or missing entries are ignored).
pub fn retarget_energy(tile: &DitherTile<'_>, step: UVec2, table: &[u32]) -> u64 {
    let w = tile.tile() as i32;
    let k = tile.tile_log2();
    let m = w - 1;
    let v = tile.values();
    let mut e = 0u64;
    for (q, &p) in table.iter().enumerate().take(v.len()) {
        let o = unpack_offset(p);
        let (x, y) = ((q as i32) & m, (q as i32) >> k);
        let tx = (x + o.x + step.x as i32) & m;
        let ty = (y + o.y + step.y as i32) & m;
        e += v[q].abs_diff(v[((ty << k) | tx) as usize]) as u64;
    }
    e
}

/// Default cost per texel of displacement (`|dx| + |dy|`), in dither-rank
/// units, added to the dither energy: 0, the paper's objective.
///
/// With cost 0 the exact tables move a seed 6.0 texels (`|dx| + |dy|`) on
/// average for the default 64x64 tile; cost 32 gives 2.4 texels at 3x the
/// dither energy (0.032 of the identity's instead of 0.011), cost 128 1.5
/// texels (0.073). A renderer's estimate decorrelates as its seed moves, so
/// shorter moves can help; on the Cornell box (256x256, QUALITY.md) cost 32
/// lowered the error's low-frequency power from 0.61 to 0.51 of white's in
/// one run and cost 128 did not (0.58), too little evidence to change the
/// default.
pub const DISPLACEMENT_COST: u32 = 0;

/// Mean displacement `|dx| + |dy|` in texels of a packed table.
pub fn mean_displacement(table: &[u32]) -> f64 {
    let sum: u64 = table
        .iter()
        .map(|&p| {
            let o = unpack_offset(p);
            (o.x.unsigned_abs() + o.y.unsigned_abs()) as u64
        })
        .sum();
    sum as f64 / table.len().max(1) as f64
}

/// A baked retarget table and its energies.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RetargetBake {
    /// Step index `0..STEP_COUNT` the table serves.
    pub index: u32,
    /// The step vector `step_of_index(index)`.
    pub step: UVec2,
    /// Packed offsets (see [`pack_offset`]), row-major; validated with
    /// [`RetargetTable::new`].
    pub packed: Vec<u32>,
    /// Energy of the identity table (no retargeting).
    pub energy_identity: u64,
    /// Energy of `packed`: the exact minimum.
    pub energy: u64,
    /// Auction bids spent (work measure).
    pub bids: u64,
}

impl RetargetBake {
    /// `energy / energy_identity` (0 if the identity energy is 0).
    pub fn energy_ratio(&self) -> f64 {
        if self.energy_identity == 0 {
            0.0
        } else {
            self.energy as f64 / self.energy_identity as f64
        }
    }
}

/// Bakes the retarget table of step index `index` for `tile` exactly.
///
/// # Errors
/// [`BakeError::StepIndex`] if `index >= STEP_COUNT`;
/// [`BakeError::CostRange`] if the tile's values are too large for the
/// solver (never for rank tiles up to 512x512);
/// [`BakeError::Core`] if the result failed validation (a bug).
pub fn bake_retarget_table(tile: &DitherTile<'_>, index: u32) -> Result<RetargetBake, BakeError> {
    bake_retarget_table_with(tile, index, DISPLACEMENT_COST)
}

/// The exact retarget table (packed offsets, as [`RetargetTable`] reads them)
/// that moves seeds ranked like `source` so they rank like `target`, another
/// tile of the same side ([`RetargetCosts::between`]); radius-bounded like
/// the walk's tables. Applied with a tile offset `o`, it reads and moves as
/// the walk's tables do at `o`.
///
/// # Errors
/// [`BakeError::Size`] for tiles of different sides; as [`solve_assignment`].
pub fn bake_retarget_between(
    source: &DitherTile<'_>,
    target: &DitherTile<'_>,
    displacement_cost: u32,
) -> Result<Vec<u32>, BakeError> {
    let costs = RetargetCosts::between(*source, target, displacement_cost)?;
    let (packed, _) = solve_packed(&costs)?;
    RetargetTable::new(source.tile(), &packed)?;
    Ok(packed)
}

/// The exact assignment of `costs` as packed offsets, and the solver's bid count.
fn solve_packed(costs: &RetargetCosts<'_>) -> Result<(Vec<u32>, u64), BakeError> {
    let solution = solve_assignment(costs)?;
    let packed = solution
        .destination
        .iter()
        .enumerate()
        .map(|(q, &d)| pack_offset(costs.offset_between(q, d as usize)))
        .collect();
    Ok((packed, solution.bids))
}

/// [`bake_retarget_table`] with another cost per texel of displacement
/// (0: the dither energy alone, as in the paper).
///
/// # Errors
/// As [`bake_retarget_table`].
pub fn bake_retarget_table_with(
    tile: &DitherTile<'_>,
    index: u32,
    displacement_cost: u32,
) -> Result<RetargetBake, BakeError> {
    if index >= STEP_COUNT as u32 {
        return Err(BakeError::StepIndex { index });
    }
    let step = step_of_index(index, tile.tile_log2());
    let costs = RetargetCosts::new(*tile, step, displacement_cost);
    let (packed, bids) = solve_packed(&costs)?;
    RetargetTable::new(tile.tile(), &packed)?;
    let identity = vec![IDENTITY_PACKED; packed.len()];
    Ok(RetargetBake {
        index,
        step,
        energy_identity: retarget_energy(tile, step, &identity),
        energy: retarget_energy(tile, step, &packed),
        packed,
        bids,
    })
}

/// Bakes the tables of all [`STEP_COUNT`] steps, one after another (a
/// caller with threads can call [`bake_retarget_table`] per index instead).
///
/// # Errors
/// As [`bake_retarget_table`].
pub fn bake_retarget_tables(tile: &DitherTile<'_>) -> Result<Vec<RetargetBake>, BakeError> {
    (0..STEP_COUNT as u32)
        .map(|i| bake_retarget_table(tile, i))
        .collect()
}

#[cfg(test)]
mod tests {

    /// A table between two different tiles is a radius-bounded permutation
    /// whose rank mismatch is the identity's or less, and tiles of different
    /// sides are refused.
    #[test]
    fn tables_between_two_tiles_lower_the_mismatch() {
        use crate::permutation::retarget::unpack_offset;
        let a_values: Vec<u32> = (0..64u32).map(|i| (i * 37 + 11) % 64).collect();
        let b_values: Vec<u32> = (0..64u32).map(|i| (i * 13 + 5) % 64).collect();
        let (a, b) = (
            DitherTile::new(8, &a_values).unwrap(),
            DitherTile::new(8, &b_values).unwrap(),
        );
        let packed = bake_retarget_between(&a, &b, 0).unwrap();
        let mut hit = [false; 64];
        let mut mismatch = 0u32;
        for (q, &p) in packed.iter().enumerate() {
            let o = unpack_offset(p);
            let (x, y) = ((q as i32 + o.x).rem_euclid(8), (q as i32 / 8 + o.y).rem_euclid(8));
            let d = (y * 8 + x) as usize;
            assert!(!core::mem::replace(&mut hit[d], true), "destination {d} twice");
            mismatch += a_values[q].abs_diff(b_values[d]);
        }
        let identity: u32 = a_values.iter().zip(&b_values).map(|(x, y)| x.abs_diff(*y)).sum();
        assert!(mismatch <= identity, "{mismatch} > {identity}");
        assert!(
            mismatch < identity / 2,
            "an exact assignment should do far better: {mismatch} / {identity}"
        );
        let small: Vec<u32> = (0..16).collect();
        let c = DitherTile::new(4, &small).unwrap();
        assert!(matches!(
            bake_retarget_between(&a, &c, 0),
            Err(BakeError::Size { .. })
        ));
    }
    use super::*;
    use crate::bake::{anneal_retarget_table, bake_mask, no_progress, AnnealParams, MaskParams};

    fn mask(w: u32, seed: u64) -> Vec<u32> {
        bake_mask(
            &MaskParams {
                width: w,
                height: w,
                sigma: 1.9,
                seed,
            },
            &mut no_progress,
        )
        .unwrap()
    }

    #[test]
    fn small_tiles_give_valid_tables_with_no_more_energy_than_identity() {
        for w in [2u32, 4, 8, 16] {
            let ranks = mask(w, 3);
            let tile = DitherTile::new(w, &ranks).unwrap();
            for b in bake_retarget_tables(&tile).unwrap() {
                assert!(RetargetTable::new(w, &b.packed).is_ok());
                assert!(b.energy <= b.energy_identity, "w {w}");
                assert_eq!(b.step, step_of_index(b.index, tile.tile_log2()));
            }
        }
    }

    /// The exact solver never loses to the annealing baseline on the same
    /// problem, and its energy is the recomputed energy of its table.
    #[test]
    fn exact_beats_annealing() {
        let ranks = mask(32, 8);
        let tile = DitherTile::new(32, &ranks).unwrap();
        let exact = bake_retarget_table(&tile, 1).unwrap();
        let sa = anneal_retarget_table(
            &tile,
            1,
            &AnnealParams {
                sweeps: 20,
                ..AnnealParams::default()
            },
        )
        .unwrap();
        assert!(
            exact.energy <= sa.energy,
            "exact {} anneal {}",
            exact.energy,
            sa.energy
        );
        assert!(sa.energy < sa.energy_identity);
        assert_eq!(exact.energy_identity, sa.energy_identity);
    }

    /// A displacement cost trades the dither fit for shorter moves: the
    /// mean displacement falls, the dither energy rises, the table stays a
    /// valid permutation, and cost 0 is the default bake.
    #[test]
    fn displacement_cost_shortens_moves() {
        let ranks = mask(32, 5);
        let tile = DitherTile::new(32, &ranks).unwrap();
        let free = bake_retarget_table_with(&tile, 2, 0).unwrap();
        assert_eq!(free, bake_retarget_table(&tile, 2).unwrap());
        let tight = bake_retarget_table_with(&tile, 2, 64).unwrap();
        assert!(RetargetTable::new(32, &tight.packed).is_ok());
        let (d_free, d_tight) = (mean_displacement(&free.packed), mean_displacement(&tight.packed));
        assert!(d_tight < 0.7 * d_free, "displacement {d_free} -> {d_tight}");
        assert!(tight.energy > free.energy && tight.energy < tight.energy_identity);
        assert_eq!(mean_displacement(&[IDENTITY_PACKED; 4]), 0.0);
    }

    #[test]
    fn bad_index_is_an_error() {
        let ranks = mask(8, 1);
        let tile = DitherTile::new(8, &ranks).unwrap();
        assert_eq!(
            bake_retarget_table(&tile, 4),
            Err(BakeError::StepIndex { index: 4 })
        );
    }
}
