//! Tests of the feature-aware permutation (a child module of `permute`).

extern crate std;
use super::*;
use crate::defaults;
use crate::sequences::seed::hash_u32;
use glam::Vec3;
use std::vec;
use std::vec::Vec;

/// [`permute_frame_features`] or its reference form, on `f32` keys.
type Permute = fn(
    &FrameLayout,
    u32,
    &[f32],
    &[SurfaceFeature],
    &FeatureThresholds,
    &DitherTile<'_>,
    &RetargetTables<'_>,
    &[u32],
    &mut [u32],
    &mut [u32],
    &mut [u32],
) -> Result<(), Error>;

/// Every pixel its own surface: each block group is one pixel (the sort
/// moves nothing) and every retarget edge that moves a seed is cut, so
/// every position is either a fixed point of the table (its seed stays)
/// or isolated (its seed is refreshed in place); both CPU paths agree.
#[test]
fn isolated_positions_get_fresh_seeds() {
    let layout = FrameLayout::new(64, 64, 4, 64).unwrap();
    let (tile, tables) = (defaults::tile_64(), defaults::tables_64());
    let n = layout.seed_count();
    let features: Vec<SurfaceFeature> = (0..64 * 64)
        .map(|i| SurfaceFeature::new(i as u32, 5.0, Vec3::Z))
        .collect();
    let values: Vec<f32> = (0..64 * 64).map(|i| ((i * 7919) % 101) as f32).collect();
    let seeds: Vec<u32> = (0..n as u32).map(|i| hash_u32(i ^ 0xABCD)).collect();
    let t = FeatureThresholds::DEFAULT;
    for frame in [0u32, 5] {
        let run = |permute: Permute| {
            let (mut sorted, mut sources, mut out) = (vec![0; n], vec![0; n], vec![0; n]);
            permute(
                &layout,
                frame,
                &values,
                &features,
                &t,
                &tile,
                &tables,
                &seeds,
                &mut sorted,
                &mut sources,
                &mut out,
            )
            .unwrap();
            out
        };
        let (fast, reference) = (run(permute_frame_features), run(permute_frame_features_reference));
        assert_eq!(fast, reference, "frame {frame}");
        let mut refreshed = 0;
        for p in 0..n {
            if fast[p] == refresh_isolated_seed(seeds[p]) {
                refreshed += 1;
            } else {
                assert_eq!(fast[p], seeds[p], "frame {frame}, position {p}");
            }
        }
        assert!(refreshed > n / 2, "frame {frame}: {refreshed} of {n} refreshed");
    }
}

/// The linked walk after 0 to 6 jump rounds (two buffers, as the GPU
/// runs them) equals the serial walk of `retarget_features_pixel`, seed
/// for seed, on frames with padding, many surfaces and long chains.
#[test]
fn linked_walk_equals_the_serial_walk_after_any_rounds() {
    let layout = FrameLayout::new(150, 70, 4, 64).unwrap();
    let tables = defaults::tables_64();
    let n = layout.seed_count();
    let features: Vec<SurfaceFeature> = (0..150u32 * 70)
        .map(|i| {
            let (x, y) = (i % 150, i / 150);
            let id = if (x / 37 + y / 23) % 3 == 0 || (x * 7 + y * 13) % 97 == 0 {
                1
            } else {
                0
            };
            SurfaceFeature::new(id, 5.0, Vec3::Z)
        })
        .collect();
    let thresholds = FeatureThresholds::DEFAULT;
    let seeds: Vec<u32> = (0..n as u32).map(|i| i.wrapping_mul(0x9e37_79b9)).collect();
    let mut longest = 0u32;
    for frame in [0u32, 1, 7, 30] {
        let params = layout.params(frame);
        let offset = walk_offset(frame, params.tile_log2);
        let table = tables.table(step_index(frame, params.tile_log2)).packed();
        let (mut sources, mut serial) = (vec![0u32; n], vec![0u32; n]);
        for p in 0..n as u32 {
            record_source(&params, offset, table, p, &mut sources);
        }
        for p in 0..n as u32 {
            retarget_features_pixel(
                &params,
                offset,
                table,
                &sources,
                &features,
                &thresholds,
                p,
                &seeds,
                &mut serial,
            );
        }
        let mut links = vec![0u32; n];
        for p in 0..n as u32 {
            record_link(&params, offset, table, &features, &thresholds, p, &mut links);
        }
        for q in 0..n as u32 {
            // The chain length behind q, for the assertion below.
            let (mut v, mut steps) = (links[q as usize], 0u32);
            while v & LINK_START == 0 && steps <= n as u32 {
                v = links[v as usize];
                steps += 1;
            }
            if steps <= n as u32 {
                longest = longest.max(steps);
            }
        }
        for rounds in 0..=6 {
            let mut next = vec![0u32; n];
            let mut other = vec![0u32; n];
            let mut cur = links.clone();
            for _ in 0..rounds {
                for q in 0..n as u32 {
                    jump_link(q, &cur, &mut other);
                }
                core::mem::swap(&mut cur, &mut other);
            }
            for p in 0..n as u32 {
                retarget_features_linked(
                    &params,
                    offset,
                    table,
                    &cur,
                    &features,
                    &thresholds,
                    p,
                    &seeds,
                    &mut next,
                );
            }
            assert_eq!(next, serial, "frame {frame}, {rounds} rounds");
        }
    }
    assert!(
        longest > 64,
        "chains of {longest} seeds: too short to test the jumps"
    );
}
