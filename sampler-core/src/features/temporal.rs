//! The feature-aware permutation against the temporally blue target: the
//! grouped sort and the retarget cut at edges of [`permute`](super::permute),
//! with the sorting target and table of the temporal permutation
//! ([`permute_frame_temporal`](crate::permute_frame_temporal)): slice
//! `z = frame mod D` of a [`SliceTables`] target and the table from slice
//! `z` to slice `z + 1`, read at tile offset 0.
//!
//! Everything [`permute`](super::permute) guarantees holds (no seed crosses
//! an edge, isolated positions get a fresh seed, a permutation otherwise);
//! where every pixel is one surface the output equals
//! [`permute_frame_temporal`](crate::permute_frame_temporal)'s.

use crate::error::Error;
use crate::features::permute::check_feature_buffers;
use crate::features::step::FeatureStep;
use crate::features::surface::{FeatureThresholds, SurfaceFeature};
use crate::permutation::layout::FrameLayout;
use crate::permutation::sort::Intensity;
use crate::permutation::temporal::SliceTables;

/// The feature-aware permutation's step after frame `frame` against
/// `target`: every block of `seeds_in` sorted in groups of one surface so
/// that `intensities` (`width * height` sort keys, e.g. demodulated luma)
/// rank like slice `z = frame mod depth` at tile offset 0, then scattered
/// with table `z` (to slice `z + 1`) cut at the edges `features` shows
/// (`width * height`). `sorted` and `sources` are scratch (`seed_count`
/// each). Identical to what the GPU's feature-aware kernels compute with
/// frame 0's parameters and slice and table `z` bound.
///
/// # Errors
/// [`Error::TileSize`] if the target's tile differs from the layout's;
/// [`Error::BufferSize`] for a buffer of the wrong length.
///
/// ```
/// use sampler_core::{defaults, permute_frame_features_temporal, FeatureThresholds, FrameLayout, SurfaceFeature};
/// use glam::Vec3;
/// let layout = FrameLayout::new(64, 32, 4, 64)?;
/// let target = defaults::temporal_target();
/// let (w, n) = (layout.padded_width(), layout.seed_count());
/// let features: Vec<SurfaceFeature> = (0..64 * 32)
///     .map(|i| SurfaceFeature::new(if i % 64 < 30 { 0 } else { 1 }, 5.0, Vec3::Z))
///     .collect();
/// let image: Vec<f32> = (0..64 * 32).map(|i| (i * 7919 % 101) as f32).collect();
/// let seeds: Vec<u32> = (0..n as u32).collect(); // seed = its pixel index
/// let (mut sorted, mut sources, mut next) = (vec![0; n], vec![0; n], vec![0; n]);
/// permute_frame_features_temporal(&layout, 5, &image, &features, &FeatureThresholds::DEFAULT,
///                                 &target, &seeds, &mut sorted, &mut sources, &mut next)?;
/// for (p, &s) in next.iter().enumerate() {
///     let (x, y, sx, sy) = (p as u32 % w, p as u32 / w, s % w, s / w);
///     if x < 64 && y < 32 && sx < 64 && sy < 32 {
///         assert_eq!(x < 30, sx < 30, "seed {s} crossed the edge"); // stays on its surface
///     }
/// }
/// # Ok::<(), sampler_core::Error>(())
/// ```
#[allow(clippy::too_many_arguments)]
pub fn permute_frame_features_temporal<T: Intensity>(
    layout: &FrameLayout,
    frame: u32,
    intensities: &[T],
    features: &[SurfaceFeature],
    thresholds: &FeatureThresholds,
    target: &SliceTables<'_>,
    seeds_in: &[u32],
    sorted: &mut [u32],
    sources: &mut [u32],
    seeds_out: &mut [u32],
) -> Result<(), Error> {
    if target.tile() != layout.tile() {
        return Err(Error::TileSize { tile: target.tile() });
    }
    check_feature_buffers(
        layout,
        intensities,
        features,
        seeds_in,
        sorted,
        sources,
        seeds_out,
    )?;
    step(layout, frame, intensities, features, thresholds, target).run(seeds_in, sorted, sources, seeds_out);
    Ok(())
}

/// Frame `frame`'s step against `target`: slice and table `frame mod D`,
/// frame 0's parameters (the walk's offset `o_0` is (0, 0)).
fn step<'a, T: Intensity>(
    layout: &FrameLayout,
    frame: u32,
    intensities: &'a [T],
    features: &'a [SurfaceFeature],
    thresholds: &'a FeatureThresholds,
    target: &SliceTables<'a>,
) -> FeatureStep<'a, T> {
    let z = target.slice_index(frame);
    FeatureStep {
        params: layout.params(0),
        intensities,
        features,
        thresholds,
        tile: target.slice(z).values(),
        table: target.table(z),
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::defaults;
    use crate::features::permute::refresh_isolated_seed;
    use crate::permutation::temporal::permute_frame_temporal;
    use crate::sequences::seed::{hash_u32, random_f32};
    use glam::Vec3;
    use std::vec;
    use std::vec::Vec;

    /// One surface everywhere, on a frame without padding: exactly the
    /// plain temporal step (fast path, 4x4 and 8x8 blocks), across the wrap
    /// from slice 63 to slice 0.
    #[test]
    fn one_surface_is_the_plain_temporal_step() {
        let target = defaults::temporal_target();
        for block in [4, 8] {
            let layout = FrameLayout::new(128, 64, block, 64).unwrap();
            let n = layout.seed_count();
            assert_eq!(n, layout.pixel_count());
            let features = vec![SurfaceFeature::new(3, 2.0, Vec3::Z); n];
            let seeds: Vec<u32> = (0..n as u32).map(|i| hash_u32(i ^ 7)).collect();
            for frame in [62u32, 63, 64] {
                let values: Vec<f32> = (0..n as u32).map(|i| random_f32(hash_u32(i), frame)).collect();
                let (mut sorted, mut sources, mut got) = (vec![0; n], vec![0; n], vec![0; n]);
                permute_frame_features_temporal(
                    &layout,
                    frame,
                    &values,
                    &features,
                    &FeatureThresholds::DEFAULT,
                    &target,
                    &seeds,
                    &mut sorted,
                    &mut sources,
                    &mut got,
                )
                .unwrap();
                let mut want = vec![0; n];
                permute_frame_temporal(&layout, frame, &values, &target, &seeds, &mut want).unwrap();
                assert!(got == want, "block {block}, frame {frame}");
            }
        }
    }

    /// Two surfaces on a padded frame: no seed crosses the edge, every seed
    /// but refreshed ones appears once, and the fast path (4x4 blocks)
    /// equals the reference passes seed for seed.
    #[test]
    fn seeds_stay_on_their_surface_and_the_paths_agree() {
        let target = defaults::temporal_target();
        let layout = FrameLayout::new(100, 60, 4, 64).unwrap();
        let (n, pw) = (layout.seed_count(), layout.padded_width());
        let features: Vec<SurfaceFeature> = (0..layout.pixel_count() as u32)
            .map(|i| SurfaceFeature::new(u32::from(i % 100 >= 37), 4.0, Vec3::Z))
            .collect();
        let seeds: Vec<u32> = (0..n as u32).collect();
        let values: Vec<f32> = (0..layout.pixel_count() as u32)
            .map(|i| random_f32(hash_u32(i), 9))
            .collect();
        let thresholds = FeatureThresholds::DEFAULT;
        for frame in [41u32, 63] {
            let (mut sorted, mut sources, mut next) = (vec![0; n], vec![0; n], vec![0; n]);
            permute_frame_features_temporal(
                &layout,
                frame,
                &values,
                &features,
                &thresholds,
                &target,
                &seeds,
                &mut sorted,
                &mut sources,
                &mut next,
            )
            .unwrap();
            let mut seen = vec![false; n];
            for (p, &s) in next.iter().enumerate() {
                if (s as usize) < n {
                    assert!(!core::mem::replace(&mut seen[s as usize], true), "seed {s} twice");
                    let (x, y, sx, sy) = (p as u32 % pw, p as u32 / pw, s % pw, s / pw);
                    if x < 100 && y < 60 && sx < 100 && sy < 60 {
                        assert_eq!(x >= 37, sx >= 37, "seed {s} crossed the edge to {p}");
                    }
                } else {
                    assert!(
                        (0..n as u32).any(|q| refresh_isolated_seed(q) == s),
                        "stray seed {s}"
                    );
                }
            }
            let fresh = next.iter().filter(|&&s| s as usize >= n).count();
            assert!(fresh * 10 < n, "{fresh} refreshed of {n}");
            let mut reference = vec![0; n];
            step(&layout, frame, &values, &features, &thresholds, &target).reference(
                &seeds,
                &mut sorted,
                &mut sources,
                &mut reference,
            );
            assert!(
                reference == next,
                "frame {frame}: the fast path differs from the reference"
            );
        }
    }

    #[test]
    fn a_target_of_another_tile_is_refused() {
        let target = defaults::temporal_target();
        let layout = FrameLayout::new(32, 32, 4, 128).unwrap();
        let n = layout.seed_count();
        let (mut a, mut b, mut c) = (vec![0; n], vec![0; n], vec![0; n]);
        let e = permute_frame_features_temporal(
            &layout,
            0,
            &vec![0.0f32; 32 * 32],
            &vec![SurfaceFeature::default(); 32 * 32],
            &FeatureThresholds::DEFAULT,
            &target,
            &vec![0; n],
            &mut a,
            &mut b,
            &mut c,
        );
        assert!(matches!(e, Err(Error::TileSize { tile: 64 })), "{e:?}");
    }
}
