//! The CPU fast path of the feature-aware permutation (issue 14) against
//! its reference form, bit for bit: `permute_frame_features` (which takes
//! the fast path for block sides 2, 4, 8 and tiles of 16 to 128 texels)
//! must equal `permute_frame_features_reference` for every input, on odd
//! frame sizes, with several surfaces (ids, depth jumps, creases, curved
//! normals, NaN depths, `NO_SURFACE`) and NaN / infinite / tied
//! intensities. Kept CI-lean: a few dozen cases, a few seconds in debug.

use conformance::fixtures::{random_table, random_tile};
use glam::Vec3;
use proptest::prelude::*;
use sampler_core::features::permute::permute_frame_features_reference;
use sampler_core::sequences::seed::hash_u32;
use sampler_core::*;

/// A random frame of surfaces: `regions` rectangles of `cell` pixels per
/// id (so blocks straddle them), per-pixel depth jumps, creases and curved
/// normals, some NaN depths and some pixels showing nothing.
fn random_features(width: u32, height: u32, cell: u32, kinds: u32, salt: u32) -> Vec<SurfaceFeature> {
    (0..width * height)
        .map(|i| {
            let (x, y) = (i % width, i / width);
            let h = hash_u32(i ^ salt.wrapping_mul(0x9E37_79B9));
            let region = hash_u32((x / cell) ^ ((y / cell) << 12) ^ salt) % kinds;
            if region == 0 || h.is_multiple_of(97) {
                return SurfaceFeature::none();
            }
            // Depth: smooth, with a jump in every other region's lower half.
            let mut depth = 2.0
                + 0.01 * x as f32
                + if region % 2 == 1 && y % cell > cell / 2 {
                    3.0
                } else {
                    0.0
                };
            if h % 211 == 1 {
                depth = f32::NAN;
            }
            let normal = match region % 3 {
                0 => Vec3::Z,
                // A crease: two flat faces at right angles.
                1 => {
                    if (x + y) % 7 < 3 {
                        Vec3::X
                    } else {
                        Vec3::Z
                    }
                }
                // Curved: every pixel its own normal, some beyond the threshold.
                _ => Vec3::new((x % 9) as f32 * 0.08, (y % 5) as f32 * 0.1, 1.0).normalize(),
            };
            SurfaceFeature::new(region % 3 + (h % 2) * (region / 3), depth, normal)
        })
        .collect()
}

/// Intensities with NaN, infinities, signed zeros and many ties.
fn random_intensities(n: u32, salt: u32) -> Vec<f32> {
    (0..n)
        .map(|i| {
            let h = hash_u32(i ^ hash_u32(salt));
            match h % 13 {
                0 => f32::NAN,
                1 => f32::INFINITY,
                2 => f32::NEG_INFINITY,
                3 => -0.0,
                4 => 0.0,
                5..=7 => (h >> 29) as f32, // ties
                _ => (h >> 8) as f32 / (1 << 24) as f32,
            }
        })
        .collect()
}

/// One of the two permutations, writing into `(sorted, sources, seeds_out)`.
type Permutation<'a> = &'a dyn Fn(&mut [u32], &mut [u32], &mut [u32]) -> Result<(), Error>;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(40))]

    #[test]
    fn fast_path_equals_reference_bit_for_bit(
        (width, height) in (1u32..=150, 1u32..=90),
        block_log2 in 1u32..=3,
        tile_log2 in 4u32..=7,
        (cell, kinds) in (1u32..=12, 1u32..=6),
        salt in any::<u32>(),
        ties in any::<bool>(),
        frame in 0u32..300,
    ) {
        let (block, tile_side) = (1 << block_log2, 1 << tile_log2);
        let layout = FrameLayout::new(width, height, block, tile_side).unwrap();
        let tile_values = random_tile(tile_side, salt, ties);
        let tile = DitherTile::new(tile_side, &tile_values).unwrap();
        let packed: Vec<Vec<u32>> = (0..4)
            .map(|i| random_table(tile_side, salt ^ i, 6 * tile_side * tile_side))
            .collect();
        let tables = RetargetTables::new(tile_side, [&packed[0], &packed[1], &packed[2], &packed[3]]).unwrap();
        let features = random_features(width, height, cell, kinds, salt);
        let values = random_intensities(width * height, salt);
        let n = layout.seed_count();
        let seeds: Vec<u32> = (0..n as u32).map(|i| hash_u32(i ^ salt)).collect();
        // A refreshed seed equal to another input (a hash collision) would
        // make the permutation check below undecidable.
        prop_assume!(!conformance::fixtures::refreshes_collide(&seeds));
        let t = FeatureThresholds::DEFAULT;
        let run = |f: Permutation<'_>| {
            // Scratch filled with junk: neither path may depend on it.
            let (mut sorted, mut sources, mut out) = (vec![u32::MAX; n], vec![0x5555_5555; n], vec![7; n]);
            f(&mut sorted, &mut sources, &mut out).unwrap();
            out
        };
        let want = run(&|s, src, out| permute_frame_features_reference(
            &layout, frame, &values, &features, &t, &tile, &tables, &seeds, s, src, out));
        let got = run(&|s, src, out| permute_frame_features(
            &layout, frame, &values, &features, &t, &tile, &tables, &seeds, s, src, out));
        prop_assert!(got == want, "{}x{} B={} W={} frame {}", width, height, block, tile_side, frame);
        let origins = conformance::fixtures::feature_permutation_origins(&got, &seeds);
        let (mut a, mut b): (Vec<u32>, Vec<u32>) = (origins.iter().flatten().copied().collect(), seeds.clone());
        a.sort_unstable();
        b.sort_unstable();
        prop_assert!(a == b, "not a permutation up to refreshed seeds");
    }
}
