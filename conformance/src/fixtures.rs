//! Deterministic test inputs: dither tiles, valid retarget tables, and
//! surface-feature frames.

use glam::Vec3;
use sampler_core::sequences::seed::hash_u32;
use sampler_core::{pack_offset, SurfaceFeature, IDENTITY_PACKED, RETARGET_RADIUS};

/// A `tile x tile` dither tile from `salt`: a random permutation of the
/// ranks `0..tile*tile`, or, with `ties`, values in `0..4` so that many
/// texels tie.
pub fn random_tile(tile: u32, salt: u32, ties: bool) -> Vec<u32> {
    let n = (tile * tile) as usize;
    if ties {
        return (0..n as u32).map(|i| hash_u32(i ^ hash_u32(salt)) % 4).collect();
    }
    let mut v: Vec<u32> = (0..n as u32).collect();
    // Fisher-Yates with the crate's hash as the random source.
    for i in (1..n).rev() {
        let j = hash_u32(i as u32 ^ hash_u32(salt.wrapping_add(7))) as usize % (i + 1);
        v.swap(i, j);
    }
    v
}

/// A valid retarget table for a `tile x tile` tile: the identity changed by
/// up to `swaps` random exchanges of destinations between texels, each kept
/// only if both offsets stay within [`RETARGET_RADIUS`] (toroidally).
pub fn random_table(tile: u32, salt: u32, swaps: u32) -> Vec<u32> {
    let n = tile * tile;
    let w = tile as i32;
    // dest[q] = destination texel of q.
    let mut dest: Vec<u32> = (0..n).collect();
    let offset = |from: u32, to: u32| -> (i32, i32) {
        let wrap = |d: i32| {
            let d = d.rem_euclid(w);
            if d > w / 2 {
                d - w
            } else {
                d
            }
        };
        (
            wrap((to % tile) as i32 - (from % tile) as i32),
            wrap((to / tile) as i32 - (from / tile) as i32),
        )
    };
    let within = |(x, y): (i32, i32)| x.abs() <= RETARGET_RADIUS && y.abs() <= RETARGET_RADIUS;
    for k in 0..swaps {
        let a = hash_u32(k ^ hash_u32(salt)) % n;
        // A partner near `a` so the swap usually stays within the radius.
        let r = hash_u32(k.wrapping_mul(3) ^ hash_u32(salt ^ 0x5bd1e995));
        let dx = (r % 13) as i32 - 6;
        let dy = ((r / 13) % 13) as i32 - 6;
        let bx = ((a % tile) as i32 + dx).rem_euclid(w) as u32;
        let by = ((a / tile) as i32 + dy).rem_euclid(w) as u32;
        let b = by * tile + bx;
        if within(offset(a, dest[b as usize])) && within(offset(b, dest[a as usize])) {
            dest.swap(a as usize, b as usize);
        }
    }
    (0..n)
        .map(|q| {
            let (x, y) = offset(q, dest[q as usize]);
            if (x, y) == (0, 0) {
                IDENTITY_PACKED
            } else {
                pack_offset(glam::IVec2::new(x, y))
            }
        })
        .collect()
}

/// Features of a frame made of `surfaces` regions: vertical bands, a disc,
/// and (when `creases`) a normal that flips in a checkerboard of 5-px cells
/// on surface 0; depths vary smoothly. Surface id per pixel, or
/// `NO_SURFACE` on the band of id `surfaces`.
pub fn banded_features(
    width: u32,
    height: u32,
    surfaces: u32,
    creases: bool,
    salt: u32,
) -> Vec<SurfaceFeature> {
    (0..width * height)
        .map(|i| {
            let (x, y) = (i % width, i / width);
            let (cx, cy) = (width as f32 * 0.6, height as f32 * 0.4);
            let in_disc =
                (x as f32 - cx).powi(2) + (y as f32 - cy).powi(2) < (width.min(height) as f32 * 0.25).powi(2);
            let band = (x * (surfaces + 1) / width.max(1) + salt) % (surfaces + 1);
            let id = if in_disc { surfaces + 7 } else { band };
            if id == surfaces {
                return SurfaceFeature::none();
            }
            let normal = if creases && id == 0 && ((x / 5) + (y / 5)) % 2 == 1 {
                Vec3::X
            } else {
                Vec3::Z
            };
            SurfaceFeature::new(id, 5.0 + 0.01 * y as f32, normal)
        })
        .collect()
}

/// Whether the fresh seed of some input
/// (`sampler_core::features::permute::refresh_isolated_seed`) is itself one
/// of `inputs`: a 32-bit hash collision (about `inputs.len()^2 / 2^32` likely
/// for random inputs), after which a refreshed seed cannot be told from a
/// moved one and [`feature_permutation_origins`] cannot decide. Property
/// tests with random seeds assume it away.
pub fn refreshes_collide(inputs: &[u32]) -> bool {
    use sampler_core::features::permute::refresh_isolated_seed;
    let plain: std::collections::HashSet<u32> = inputs.iter().copied().collect();
    inputs.iter().any(|&s| plain.contains(&refresh_isolated_seed(s)))
}

/// The input seed each output seed of the feature-aware permutation came
/// from: the seed itself if it is one of `inputs` (moved), else the input
/// whose `sampler_core::features::permute::refresh_isolated_seed` it is (an
/// isolated position's fresh seed), else `None`. With every entry `Some`
/// and the origins a rearrangement of `inputs`, the output is a permutation
/// up to the refreshed seeds. Meaningful only where [`refreshes_collide`] is
/// false.
pub fn feature_permutation_origins(out: &[u32], inputs: &[u32]) -> Vec<Option<u32>> {
    use sampler_core::features::permute::refresh_isolated_seed;
    use std::collections::{HashMap, HashSet};
    let plain: HashSet<u32> = inputs.iter().copied().collect();
    let refreshed: HashMap<u32, u32> = inputs.iter().map(|&s| (refresh_isolated_seed(s), s)).collect();
    out.iter()
        .map(|s| {
            if plain.contains(s) {
                Some(*s)
            } else {
                refreshed.get(s).copied()
            }
        })
        .collect()
}
