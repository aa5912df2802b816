//! The temporally blue permutation's shipped data and its step
//! (`sampler_core::defaults::temporal_target`,
//! `sampler_core::permute_frame_temporal`); the GPU's is in `gpu_vs_cpu`.

use sampler_core::bake::bake_slice_table;
use sampler_core::sequences::seed::hash_u32;
use sampler_core::{defaults, permute_frame_temporal, random_f32, FrameLayout};

/// The shipped tables of slices 0 (to 1) and 63 (back to 0) equal a fresh
/// bake from the target's mask, word for word (`cargo test -p bake`
/// regenerates the mask and all 64 tables from the mask's seed).
#[test]
fn shipped_slice_tables_equal_a_fresh_bake_at_both_ends() {
    let target = defaults::temporal_target();
    let mask = defaults::stbn_64();
    for z in [0, 63] {
        let fresh = bake_slice_table(&mask, z).unwrap();
        assert!(
            fresh == target.table(z).packed(),
            "table {z} differs from a fresh bake"
        );
    }
}

/// Every step from frame 60 to 66 (slices 60..63, then 0..2) keeps the seeds
/// a permutation, on a frame whose sides are not multiples of the tile and
/// with 2x2 to 8x8 blocks; frames one slice cycle apart take the same step.
#[test]
fn temporal_steps_are_permutations_across_the_wrap() {
    let target = defaults::temporal_target();
    for block in [2, 4, 5, 8] {
        let layout = FrameLayout::new(150, 70, block, 64).unwrap();
        let seeds: Vec<u32> = (0..layout.seed_count() as u32).collect();
        let mut current = seeds.clone();
        let mut next = vec![u32::MAX; seeds.len()];
        for frame in 60..67 {
            let values: Vec<f32> = (0..layout.pixel_count() as u32)
                .map(|i| random_f32(hash_u32(i), frame))
                .collect();
            permute_frame_temporal(&layout, frame, &values, &target, &current, &mut next).unwrap();
            let mut check = next.clone();
            check.sort_unstable();
            assert!(
                check == seeds,
                "block {block}, frame {frame}: seeds lost or repeated"
            );
            assert_ne!(next, current, "block {block}, frame {frame}: nothing moved");
            let mut again = vec![0; seeds.len()];
            permute_frame_temporal(&layout, frame + 64, &values, &target, &current, &mut again).unwrap();
            assert!(again == next, "frame {frame} and {} differ", frame + 64);
            std::mem::swap(&mut current, &mut next);
        }
    }
}
