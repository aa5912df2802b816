//! The feature-aware permutation (`sampler_core::features::permute`, issue
//! 14) on random frames: always a permutation up to the fresh seeds of
//! isolated positions, no seed ever lands on another surface than the one it
//! sampled, and with one surface it is the plain permutation bit for bit.

use conformance::fixtures::{
    banded_features, feature_permutation_origins, random_table, random_tile, refreshes_collide,
};
use glam::Vec3;
use proptest::prelude::*;
use sampler_core::sequences::seed::hash_u32;
use sampler_core::*;

/// A surface label per padded-buffer index: the feature id, or a label of
/// its own for padding. Same-surface moves keep it.
fn labels(layout: &FrameLayout, f: &[SurfaceFeature]) -> Vec<u64> {
    let (w, h, pw) = (layout.width(), layout.height(), layout.padded_width());
    (0..layout.seed_count() as u32)
        .map(|i| {
            let (x, y) = (i % pw, i / pw);
            if x < w && y < h {
                f[(y * w + x) as usize].id as u64
            } else {
                1 << 40
            }
        })
        .collect()
}

fn tables_for(tile: u32, salt: u32) -> Vec<Vec<u32>> {
    (0..4)
        .map(|i| random_table(tile, salt + i, 6 * tile * tile))
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    /// Whatever the frame, block, tile, table and features: the output is a
    /// permutation of the input up to the fresh seeds of isolated positions
    /// (each the hash of the seed it replaces), and every seed ends on the
    /// surface (or in the padding) it started on.
    #[test]
    fn feature_aware_permutation_is_a_permutation_that_stays_on_surfaces(
        (width, height, block, tile_log2, salt) in (1u32..=70, 1u32..=45, MIN_BLOCK..=MAX_BLOCK, 2u32..=6, any::<u32>()),
        surfaces in 1u32..5,
        creases in any::<bool>(),
        frame in 0u32..200,
    ) {
        let tile_side = 1 << tile_log2;
        let layout = FrameLayout::new(width, height, block, tile_side).unwrap();
        let tile_values = random_tile(tile_side, salt, salt % 2 == 0);
        let tile = DitherTile::new(tile_side, &tile_values).unwrap();
        let packed = tables_for(tile_side, salt);
        let tables = RetargetTables::new(tile_side, [&packed[0], &packed[1], &packed[2], &packed[3]]).unwrap();
        let feats = banded_features(width, height, surfaces, creases, salt);
        let values: Vec<f32> = (0..width * height).map(|i| (hash_u32(i ^ salt) % 1000) as f32 / 999.0).collect();
        let seeds: Vec<u32> = (0..layout.seed_count() as u32).collect();
        prop_assume!(!refreshes_collide(&seeds));
        let n = layout.seed_count();
        let (mut sorted_buf, mut sources, mut out) = (vec![0; n], vec![0; n], vec![0; n]);
        permute_frame_features(
            &layout, frame, &values, &feats, &FeatureThresholds::DEFAULT, &tile, &tables,
            &seeds, &mut sorted_buf, &mut sources, &mut out,
        ).unwrap();
        let origins = feature_permutation_origins(&out, &seeds);
        prop_assert!(origins.iter().all(Option::is_some), "a seed from nowhere");
        let mut check: Vec<u32> = origins.iter().flatten().copied().collect();
        check.sort_unstable();
        prop_assert_eq!(&check, &seeds, "not a permutation up to refreshed seeds");
        let label = labels(&layout, &feats);
        for (q, s) in origins.iter().flatten().enumerate() {
            prop_assert_eq!(label[q], label[*s as usize], "seed {} moved from surface {} to {}", s, label[*s as usize], label[q]);
        }
    }

    /// Features that make the whole frame one surface give exactly the
    /// plain permutation (in frames without padding: padding is a surface
    /// of its own).
    #[test]
    fn one_surface_is_the_plain_permutation_bit_for_bit(
        (kx, ky, block, tile_log2, salt) in (1u32..=4, 1u32..=3, MIN_BLOCK..=MAX_BLOCK, 2u32..=4, any::<u32>()),
        frame in 0u32..200,
    ) {
        let tile_side = 1 << tile_log2;
        let (width, height) = (kx * tile_side, ky * tile_side);
        let layout = FrameLayout::new(width, height, block, tile_side).unwrap();
        let tile_values = random_tile(tile_side, salt, salt % 3 == 0);
        let tile = DitherTile::new(tile_side, &tile_values).unwrap();
        let packed = tables_for(tile_side, salt);
        let tables = RetargetTables::new(tile_side, [&packed[0], &packed[1], &packed[2], &packed[3]]).unwrap();
        let feats = vec![SurfaceFeature::new(2, 3.0, Vec3::Y); (width * height) as usize];
        let values: Vec<f32> = (0..width * height)
            .map(|i| match hash_u32(i ^ salt) % 9 { 0 => f32::NAN, 1 => -0.0, 2 => 0.5, k => k as f32 * 0.1 })
            .collect();
        let seeds: Vec<u32> = (0..layout.seed_count() as u32).map(|i| hash_u32(i.wrapping_add(salt))).collect();
        let n = layout.seed_count();
        let (mut sorted_buf, mut sources, mut out) = (vec![0; n], vec![0; n], vec![0; n]);
        permute_frame_features(
            &layout, frame, &values, &feats, &FeatureThresholds::DEFAULT, &tile, &tables,
            &seeds, &mut sorted_buf, &mut sources, &mut out,
        ).unwrap();
        let mut plain = vec![0; n];
        permute_frame(&layout, frame, &values, &tile, &tables, &seeds, &mut plain).unwrap();
        prop_assert_eq!(out, plain);
    }
}

/// Within one block, two surfaces are sorted apart: each keeps its own
/// seeds and positions, and the grouping is the connected components.
#[test]
fn groups_are_connected_components_and_sort_apart() {
    use sampler_core::features::permute::{block_groups, sort_block_grouped};
    let t = FeatureThresholds::DEFAULT;
    let mut f = [SurfaceFeature::default(); MAX_BLOCK_PIXELS];
    // 2x2: pixels 0 and 3 on surface 1, 1 and 2 on surface 2.
    for (i, id) in [1u32, 2, 2, 1].iter().enumerate() {
        f[i] = SurfaceFeature::new(*id, 4.0, Vec3::Z);
    }
    let mut g = [0u32; MAX_BLOCK_PIXELS];
    block_groups(4, &f, &t, &mut g);
    assert_eq!(g[..4], [0, 1, 1, 0]);
    // Values and dither ranks that would cross surfaces in a plain sort.
    let mut keys = [0u32; MAX_BLOCK_PIXELS];
    let mut dither = [0u32; MAX_BLOCK_PIXELS];
    let mut seeds = [0u32; MAX_BLOCK_PIXELS];
    for i in 0..4 {
        keys[i] = intensity_key([0.9f32, 0.1, 0.5, 0.3][i]);
        dither[i] = [3u32, 0, 1, 2][i];
        seeds[i] = 100 + i as u32;
    }
    let mut out = [0u32; MAX_BLOCK_PIXELS];
    sort_block_grouped(4, &g, &keys, &dither, &seeds, &mut out);
    // Surface 1 (pixels 0, 3): seed 103 (0.3) to the lower rank (pixel 3, rank 2).
    // Surface 2 (pixels 1, 2): seed 101 (0.1) to pixel 1 (rank 0).
    assert_eq!(out[..4], [100, 101, 102, 103]);
    let mut plain = [0u32; MAX_BLOCK_PIXELS];
    sort_block(4, &keys, &dither, &seeds, &mut plain);
    assert_eq!(
        plain[..4],
        [100, 101, 103, 102],
        "the plain sort crosses surfaces here"
    );
    // A chain of similar normals links three pixels whose ends differ by more
    // than the threshold: one group (connected components).
    let n = |deg: f32| Vec3::new(deg.to_radians().sin(), 0.0, deg.to_radians().cos());
    for (i, deg) in [0.0f32, 20.0, 40.0].iter().enumerate() {
        f[i] = SurfaceFeature::new(5, 4.0, n(*deg));
    }
    block_groups(3, &f, &t, &mut g);
    assert_eq!(g[..3], [0, 0, 0]);
}
