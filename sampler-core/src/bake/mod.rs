//! Host-only baking of blue-noise masks, spatiotemporal masks and retarget
//! tables (cargo feature `bake`; uses `alloc`, never compiled for shaders).
//!
//! - [`bake_mask`]: 2D toroidal void-and-cluster (Ulichney 1993) with a
//!   Gaussian energy; exact histogram (ranks `0..W*H`, each once).
//! - [`bake_stbn`]: scalar spatiotemporal blue noise `W x H x D` (the energy
//!   of Wolfe et al.'s STBN), re-ranked so every slice holds `0..W*H` once.
//! - [`bake_retarget_table`] / [`bake_retarget_tables`]: retarget tables as
//!   an exact sparse assignment problem ([`solve_assignment`], auction with
//!   epsilon scaling), following the convention of
//!   [`retarget`](crate::permutation::retarget).
//! - [`bake_slice_tables`]: the tables between consecutive slices of a
//!   spatiotemporal mask, for the temporally blue permutation
//!   ([`temporal`](crate::permutation::temporal)).
//! - [`anneal_retarget_table`]: the paper's simulated annealing from the
//!   identity, kept as a baseline for comparison only.
//! - [`bake_sampler_keys`] / [`bake_key_tile`]: per-pixel keys of the
//!   screen-space sampler ([`screen_sobol`](crate::sequences::screen_sobol)), arranged by
//!   a swap optimiser so errors on random Heaviside integrands are blue.
//! - [`bake_vector_stbn`]: vector spatiotemporal masks (2D/3D values, unit
//!   and cosine-hemisphere directions) with the same swap optimiser and the
//!   STBN coupling.
//! - [`bake_shift_tile`]: jointly blue 2D shifts of the spatiotemporal
//!   sampler, arranged for the error after a history filter
//!   ([`field_quality`] measures it on held-out integrands).
//! - [`bake_filter_adapted`] / [`refine_filter_adapted`]: masks adapted to
//!   the spatial and temporal filters a renderer applies (the idea of FAST,
//!   Donnelly et al. 2024): scalar values of several distributions and
//!   vectors, [`SpatialFilter`]s and [`TemporalFilter`]s combined as a
//!   product or separately ([`FilterCombine`]).
//! - [`search_placement`]: the search behind ZSobol's one-sample-per-pixel
//!   placement map ([`ZSOBOL_PLACEMENT`](crate::sequences::zsobol::ZSOBOL_PLACEMENT)).
//!
//! Everything is deterministic: the same parameters and seed give the same
//! output bit for bit on every machine (integer energies; the only floating
//! point is the kernel construction with `libm`, which is pure software).
//! Bad parameters are a [`BakeError`], never a panic.

mod anneal;
mod assignment;
mod energy;
mod extrema;
mod filter_adapted;
mod filter_swap;
mod filters;
mod history_sequence;
mod keys;
mod kronecker_search;
mod retarget_bake;
mod shift_quality;
mod shift_tile;
mod slice_tables;
mod stbn;
mod swap;
mod threshold_swap;
mod vector_stbn;
mod void_and_cluster;
mod zsobol_placement;

pub use anneal::{anneal_retarget_table, AnnealParams};
pub use assignment::{solve_assignment, Assignment, SparseCosts, SparseMatrix};
pub use filter_adapted::{
    bake_filter_adapted, refine_filter_adapted, Distribution, FilterAdapted, FilterAdaptedParams,
    FilterCombine, FilterValue,
};
pub use filters::{
    spatial_autocorrelation, SpatialFilter, TemporalFilter, GAUSSIAN_TRUNCATION, MAX_FILTER_SIGMA,
    MAX_FILTER_TAPS,
};
pub use history_sequence::{bake_history_sequence, history_sequence_figures, HistorySequenceParams};
pub use keys::{
    bake_key_tile, bake_sampler_keys, heaviside_integrands, key_errors, line_integrands, HeavisideIntegrand,
    KeyParams, LINE_INTEGRANDS, LINE_STEPS,
};
pub use kronecker_search::{
    kronecker_score, resonates, search_kronecker_generators, KroneckerSearch, HISTORY_ALPHA, MEAN_WEIGHT,
    RESONANCE_GAP, RESONANCE_NEIGHBOURS, SCORE_FRAMES,
};
pub use retarget_bake::{
    bake_retarget_between, bake_retarget_table, bake_retarget_table_with, bake_retarget_tables,
    mean_displacement, retarget_energy, RetargetBake, RetargetCosts, DISPLACEMENT_COST,
};
pub use shift_quality::{field_quality, FieldQuality};
pub use shift_tile::{
    bake_shift_tile, pack_shift, refine_shift_tile_words, unpack_shift, ShiftTile, ShiftTileParams,
};
pub use slice_tables::{bake_slice_table, bake_slice_tables, slice_ranks, slices_packed};
pub use stbn::{bake_stbn, StbnParams};
pub use swap::SwapReport;
pub use vector_stbn::{bake_vector_stbn, VectorKind, VectorStbn, VectorStbnParams};
pub use void_and_cluster::{bake_mask, MaskParams};
pub use zsobol_placement::{
    edge_scores, placement_is_valid, search_placement, PlacementSearch, DEFAULT_PLACEMENT_DRAWS,
    DEFAULT_PLACEMENT_SEED, FINAL_TRIALS, PLACEMENT_BITS,
};

use alloc::vec;
use alloc::vec::Vec;
use core::fmt;

/// Largest mask side (each of width, height, depth) the bakers accept.
///
/// Keeps every index in `u32` and the energies of the widest kernel in `i32`.
pub const MAX_MASK_SIDE: u32 = 4096;
/// Largest number of texels of a mask or spatiotemporal volume (`2^26`,
/// 64 Mi texels: about 0.6 GiB of working memory).
pub const MAX_MASK_TEXELS: u64 = 1 << 26;
/// Smallest accepted Gaussian sigma, in texels (or slices).
pub const MIN_SIGMA: f64 = 0.25;
/// Largest accepted Gaussian sigma, in texels (or slices): the kernel spans
/// `2 * ceil(4 sigma) + 1` texels per axis.
pub const MAX_SIGMA: f64 = 16.0;

/// What can be wrong with a bake request.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum BakeError {
    /// A side is zero, not a power of two, above [`MAX_MASK_SIDE`], or the
    /// volume exceeds [`MAX_MASK_TEXELS`].
    Size {
        /// Requested width in texels.
        width: u32,
        /// Requested height in texels.
        height: u32,
        /// Requested depth in slices (1 for 2D masks).
        depth: u32,
    },
    /// Sigma is not finite or outside [`MIN_SIGMA`]`..=`[`MAX_SIGMA`].
    Sigma {
        /// The rejected sigma.
        sigma: f64,
    },
    /// A weight (e.g. [`KeyParams::line_weight`]) is negative or not finite.
    Weight {
        /// The rejected weight.
        weight: f64,
    },
    /// A filter parameter is out of range or not finite (see
    /// [`SpatialFilter`] and [`TemporalFilter`] for the ranges).
    Filter {
        /// Which parameter: `"sigma"`, `"alpha"`, `"beta"`, `"box size"`, `"binomial order"`.
        parameter: &'static str,
        /// The rejected value.
        value: f64,
    },
    /// The dither tile or retarget table is invalid.
    Core(crate::Error),
    /// A retarget-table index is not below [`STEP_COUNT`](crate::STEP_COUNT).
    StepIndex {
        /// The rejected index.
        index: u32,
    },
    /// Costs are so large that the assignment solver's scaled integer
    /// arithmetic could overflow `i64`.
    CostRange {
        /// Largest edge cost found.
        max_cost: u64,
        /// Number of sources.
        size: usize,
    },
    /// The sparse cost graph has no perfect matching (some destination can
    /// never be reached by an unmatched source).
    Infeasible,
}

impl fmt::Display for BakeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            BakeError::Size { width, height, depth } => write!(
                f,
                "size {width}x{height}x{depth} is invalid: every side must be a power of two in \
                 1..={MAX_MASK_SIDE} and the volume at most {MAX_MASK_TEXELS} texels"
            ),
            BakeError::Sigma { sigma } => {
                write!(f, "sigma {sigma} is outside {MIN_SIGMA}..={MAX_SIGMA}")
            }
            BakeError::Weight { weight } => write!(f, "weight {weight} is negative or not finite"),
            BakeError::Filter { parameter, value } => {
                write!(f, "filter {parameter} {value} is out of range or not finite")
            }
            BakeError::Core(e) => write!(f, "{e}"),
            BakeError::StepIndex { index } => {
                write!(
                    f,
                    "retarget step index {index} is not below {}",
                    crate::STEP_COUNT
                )
            }
            BakeError::CostRange { max_cost, size } => write!(
                f,
                "assignment costs up to {max_cost} with {size} sources overflow the solver's integer range"
            ),
            BakeError::Infeasible => f.write_str("the sparse assignment problem has no perfect matching"),
        }
    }
}

impl core::error::Error for BakeError {
    fn source(&self) -> Option<&(dyn core::error::Error + 'static)> {
        match self {
            BakeError::Core(e) => Some(e),
            _ => None,
        }
    }
}

impl From<crate::Error> for BakeError {
    fn from(e: crate::Error) -> Self {
        BakeError::Core(e)
    }
}

/// Reports progress of a long bake: called with `(done, total)` work units,
/// at most about a thousand times per bake, `done` non-decreasing.
pub type Progress<'a> = &'a mut dyn FnMut(u64, u64);

/// A progress callback that ignores its reports.
pub fn no_progress(_done: u64, _total: u64) {}

/// Checks that a mask of `width x height x depth` is bakeable.
/// `pixel_major` (`texels * depth` values, texel `p`'s slice `z` at
/// `p * depth + z`) rearranged slice-major (`z * texels + p`), the layout
/// the bakes return.
pub(crate) fn slice_major(pixel_major: &[u32], texels: usize, depth: usize) -> Vec<u32> {
    let mut out = vec![0u32; texels * depth];
    for p in 0..texels {
        for z in 0..depth {
            out[z * texels + p] = pixel_major[p * depth + z];
        }
    }
    out
}

fn check_size(width: u32, height: u32, depth: u32) -> Result<(), BakeError> {
    let side_ok = |s: u32| s.is_power_of_two() && s <= MAX_MASK_SIDE;
    let texels = width as u64 * height as u64 * depth as u64;
    if side_ok(width) && side_ok(height) && side_ok(depth) && texels <= MAX_MASK_TEXELS {
        Ok(())
    } else {
        Err(BakeError::Size { width, height, depth })
    }
}

/// Checks a Gaussian sigma.
fn check_sigma(sigma: f64) -> Result<(), BakeError> {
    if sigma.is_finite() && (MIN_SIGMA..=MAX_SIGMA).contains(&sigma) {
        Ok(())
    } else {
        Err(BakeError::Sigma { sigma })
    }
}

/// SplitMix64 (Steele, Lea & Flood 2014): the bakers' deterministic random
/// source, seeded by the user's `u64` seed.
#[derive(Clone, Debug)]
pub(crate) struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    pub(crate) fn new(seed: u64) -> Self {
        SplitMix64 { state: seed }
    }
    pub(crate) fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in `0..n` (`n > 0`), by the multiply-high method (bias below 2^-32 for n < 2^32).
    pub(crate) fn below(&mut self, n: u64) -> u64 {
        ((self.next_u64() as u128 * n as u128) >> 64) as u64
    }
    /// Uniform in `[0, 1)` with 53 bits.
    pub(crate) fn unit_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// Calls `progress` about every thousandth of `total`.
pub(crate) struct Throttle {
    step: u64,
    next: u64,
}

impl Throttle {
    pub(crate) fn new(total: u64) -> Self {
        let step = (total / 1000).max(1);
        Throttle { step, next: 0 }
    }
    #[inline]
    pub(crate) fn tick(&mut self, done: u64, total: u64, progress: &mut dyn FnMut(u64, u64)) {
        if done >= self.next || done == total {
            self.next = done + self.step;
            progress(done, total);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_and_sigmas_are_validated() {
        assert!(check_size(64, 32, 1).is_ok());
        assert!(check_size(1, 1, 1).is_ok());
        for (w, h, d) in [(0, 4, 1), (3, 4, 1), (4, 4, 0), (8192, 2, 1), (4096, 4096, 8)] {
            assert_eq!(
                check_size(w, h, d),
                Err(BakeError::Size {
                    width: w,
                    height: h,
                    depth: d
                })
            );
        }
        assert!(check_sigma(1.9).is_ok());
        for s in [0.0, -1.0, f64::NAN, f64::INFINITY, 17.0] {
            assert!(check_sigma(s).is_err());
        }
    }

    #[test]
    fn splitmix_below_stays_in_range() {
        let mut r = SplitMix64::new(7);
        for n in [1u64, 2, 3, 1000, u32::MAX as u64] {
            for _ in 0..1000 {
                assert!(r.below(n) < n);
            }
        }
        let u = r.unit_f64();
        assert!((0.0..1.0).contains(&u));
    }
}
