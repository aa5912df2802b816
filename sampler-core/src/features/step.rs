//! One feature-aware step's inputs, checked: the data the walk's and the
//! temporal entry points hand to the CPU fast path and to the reference
//! passes (`features::permute`, `features::cpu`).

use crate::features::surface::{FeatureThresholds, SurfaceFeature};
use crate::permutation::layout::FrameParams;
use crate::permutation::retarget::RetargetTable;

/// One feature-aware step's checked inputs: frame parameters (the sorting
/// target is read at tile offset `walk_offset(params.frame)`), sort keys and
/// surface features (`width * height` each), thresholds, the sorting target
/// (`W * W` ranks) and the retarget table. Shared by
/// [`permute_frame_features`](crate::permute_frame_features) (the walk's tile and table of the frame) and
/// [`permute_frame_features_temporal`](crate::features::temporal::permute_frame_features_temporal)
/// (a slice and its table, frame 0's parameters).
/// Its `run` and `reference` are in `features::permute`.
pub(crate) struct FeatureStep<'a, T> {
    /// The frame's parameters.
    pub params: FrameParams,
    /// Sort keys, `width * height`.
    pub intensities: &'a [T],
    /// Surface features, `width * height`.
    pub features: &'a [SurfaceFeature],
    /// When two pixels are one surface.
    pub thresholds: &'a FeatureThresholds,
    /// The sorting target's ranks, `W * W`.
    pub tile: &'a [u32],
    /// The retarget table.
    pub table: RetargetTable<'a>,
}
