//! Simulated annealing of a retarget table from the identity: the method of
//! Heitz & Belcour 2019 (and of the public re-implementations), kept only
//! as a baseline for [`bake_retarget_table`](super::bake_retarget_table),
//! which finds the exact optimum of the same L1 energy.
//!
//! A move picks a texel `q1` and a second texel `q2 = q1 + o` with `o` a
//! candidate offset, and swaps their destinations if both new offsets stay
//! within [`RETARGET_RADIUS`]; it is accepted by the Metropolis rule at a
//! temperature decreasing geometrically from `t_start` to `t_end`.

use super::retarget_bake::{retarget_energy, RetargetBake};
use super::{BakeError, SplitMix64};
use crate::permutation::dither::DitherTile;
use crate::permutation::retarget::{pack_offset, RetargetTable, IDENTITY_PACKED, RETARGET_RADIUS};
use crate::sequences::walk::{step_of_index, STEP_COUNT};
use alloc::vec;
use alloc::vec::Vec;
use glam::IVec2;

/// Parameters of the annealing baseline.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnnealParams {
    /// Number of moves divided by the texel count.
    pub sweeps: u32,
    /// Initial temperature as a fraction of the tile's texel count (the
    /// range of rank values).
    pub t_start: f64,
    /// Final temperature, same unit.
    pub t_end: f64,
    /// Random seed.
    pub seed: u64,
}

impl Default for AnnealParams {
    /// 200 sweeps from 0.01 to 0.0001 of the value range (chosen by
    /// measurement on 64x64 tiles: hotter starts wasted the budget).
    fn default() -> Self {
        AnnealParams {
            sweeps: 200,
            t_start: 0.01,
            t_end: 0.0001,
            seed: 1,
        }
    }
}

/// Canonical toroidal difference `b - a` on an axis of side `w`, in
/// `-(w/2 - 1)..=w/2`.
#[inline]
fn wrap_diff(a: i32, b: i32, w: i32) -> i32 {
    let d = (b - a).rem_euclid(w);
    if d > w / 2 {
        d - w
    } else {
        d
    }
}

/// Anneals the table of step index `index`. The energies in the result
/// follow [`retarget_energy`]; `bids` is the number of accepted moves.
///
/// # Errors
/// [`BakeError::StepIndex`] if `index >= STEP_COUNT`; [`BakeError::Core`]
/// if the result failed validation (a bug).
pub fn anneal_retarget_table(
    tile: &DitherTile<'_>,
    index: u32,
    params: &AnnealParams,
) -> Result<RetargetBake, BakeError> {
    if index >= STEP_COUNT as u32 {
        return Err(BakeError::StepIndex { index });
    }
    let k = tile.tile_log2();
    let w = tile.tile() as i32;
    let m = w - 1;
    let n = tile.values().len();
    let step = step_of_index(index, k);
    let v = tile.values();
    let shifted: Vec<u32> = (0..n as i32)
        .map(|d| {
            let x = ((d & m) + step.x as i32) & m;
            let y = ((d >> k) + step.y as i32) & m;
            v[((y << k) | x) as usize]
        })
        .collect();
    let cost = |q: usize, d: usize| v[q].abs_diff(shifted[d]) as f64;
    let within = |q: usize, d: usize| {
        let dx = wrap_diff(q as i32 & m, d as i32 & m, w);
        let dy = wrap_diff(q as i32 >> k, d as i32 >> k, w);
        dx.abs() <= RETARGET_RADIUS && dy.abs() <= RETARGET_RADIUS
    };
    let r = RETARGET_RADIUS.min(w / 2);
    let span = (2 * r + 1) as u64;
    let mut dest: Vec<usize> = (0..n).collect();
    let mut rng = SplitMix64::new(params.seed);
    let moves = params.sweeps as u64 * n as u64;
    let range = n as f64;
    let (t0, t1) = (params.t_start * range, params.t_end * range);
    let cooling = if moves > 1 && t0 > 0.0 && t1 > 0.0 {
        libm::pow(t1 / t0, 1.0 / (moves - 1) as f64)
    } else {
        1.0
    };
    let mut t = t0;
    let mut accepted = 0u64;
    for _ in 0..moves {
        let q1 = rng.below(n as u64) as usize;
        let ox = rng.below(span) as i32 - r;
        let oy = rng.below(span) as i32 - r;
        let q2 = ((((q1 as i32 >> k) + oy) & m) << k | (((q1 as i32 & m) + ox) & m)) as usize;
        let (d1, d2) = (dest[q1], dest[q2]);
        if q1 != q2 && within(q1, d2) && within(q2, d1) {
            let delta = cost(q1, d2) + cost(q2, d1) - cost(q1, d1) - cost(q2, d2);
            if delta <= 0.0 || (t > 0.0 && rng.unit_f64() < libm::exp(-delta / t)) {
                dest.swap(q1, q2);
                accepted += 1;
            }
        }
        t *= cooling;
    }
    let packed: Vec<u32> = dest
        .iter()
        .enumerate()
        .map(|(q, &d)| {
            pack_offset(IVec2::new(
                wrap_diff(q as i32 & m, d as i32 & m, w),
                wrap_diff(q as i32 >> k, d as i32 >> k, w),
            ))
        })
        .collect();
    RetargetTable::new(tile.tile(), &packed)?;
    let identity = vec![IDENTITY_PACKED; n];
    Ok(RetargetBake {
        index,
        step,
        energy_identity: retarget_energy(tile, step, &identity),
        energy: retarget_energy(tile, step, &packed),
        packed,
        bids: accepted,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_diff_is_canonical() {
        assert_eq!(wrap_diff(0, 63, 64), -1);
        assert_eq!(wrap_diff(63, 0, 64), 1);
        assert_eq!(wrap_diff(0, 32, 64), 32);
        assert_eq!(wrap_diff(0, 3, 4), -1);
        assert_eq!(wrap_diff(1, 3, 4), 2);
    }

    /// On tiles smaller than the radius every move wraps; the result must
    /// still be a valid permutation (checked inside) for every step.
    #[test]
    fn annealing_on_tiny_tiles_stays_valid() {
        for side in [2u32, 4, 8] {
            let values: Vec<u32> = (0..side * side).map(|i| (i * 5) % (side * side)).collect();
            let tile = DitherTile::new(side, &values).unwrap();
            for index in 0..STEP_COUNT as u32 {
                assert!(anneal_retarget_table(&tile, index, &AnnealParams::default()).is_ok());
            }
            assert_eq!(
                anneal_retarget_table(&tile, 9, &AnnealParams::default()),
                Err(BakeError::StepIndex { index: 9 })
            );
        }
    }
}
