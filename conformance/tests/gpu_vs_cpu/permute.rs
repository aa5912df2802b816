//! The permutation passes: seed init, sort and retarget, and their
//! feature-aware variants, bit for bit.

use conformance::fixtures::{random_table, random_tile};
use glam::Vec4;
use gpu_tracer::gpu::{Gpu, PassForm, PermuteMode, PermutePipelines, SeedPermuter};
use sampler_core::sequences::seed::hash_u32;
use sampler_core::*;

/// Intensities with NaN, infinities, signed zeros and many ties.
fn intensities(n: usize, salt: u32) -> Vec<f32> {
    (0..n as u32)
        .map(|i| {
            let h = hash_u32(i ^ hash_u32(salt));
            match h % 16 {
                0 => f32::NAN,
                1 => f32::INFINITY,
                2 => f32::NEG_INFINITY,
                3 => -0.0,
                4..=8 => (h >> 8) as f32 % 4.0,
                _ => random_f32(h, 1) * 3.0,
            }
        })
        .collect()
}

struct Case {
    width: u32,
    height: u32,
    block: u32,
    tile: u32,
    frame: u32,
}

const CASES: &[Case] = &[
    Case {
        width: 1,
        height: 1,
        block: 2,
        tile: 4,
        frame: 0,
    },
    Case {
        width: 17,
        height: 13,
        block: 3,
        tile: 8,
        frame: 5,
    },
    Case {
        width: 64,
        height: 64,
        block: 4,
        tile: 64,
        frame: 1,
    },
    Case {
        width: 97,
        height: 61,
        block: 4,
        tile: 64,
        frame: 12345,
    },
    Case {
        width: 131,
        height: 67,
        block: 5,
        tile: 16,
        frame: 77,
    },
    Case {
        width: 200,
        height: 120,
        block: 8,
        tile: 128,
        frame: 3,
    },
    Case {
        width: 33,
        height: 129,
        block: 7,
        tile: 32,
        frame: u32::MAX,
    },
    Case {
        width: 50,
        height: 50,
        block: 6,
        tile: 2,
        frame: 9,
    },
];

#[test]
fn sort_and_retarget_kernels_match_the_cpu_bit_for_bit() {
    let Some(gpu) = Gpu::for_test("sort_and_retarget_kernels_match_the_cpu_bit_for_bit") else {
        return;
    };
    let pipelines = PermutePipelines::new(&gpu).expect("pipelines");
    for (k, c) in CASES.iter().enumerate() {
        let salt = k as u32 * 7919;
        let layout = FrameLayout::new(c.width, c.height, c.block, c.tile).unwrap();
        let tile_values = random_tile(c.tile, salt, k % 2 == 0);
        let tile = DitherTile::new(c.tile, &tile_values).unwrap();
        let packed: Vec<Vec<u32>> = (0..4)
            .map(|i| random_table(c.tile, salt + i, 5 * c.tile * c.tile))
            .collect();
        let tables = RetargetTables::new(c.tile, [&packed[0], &packed[1], &packed[2], &packed[3]]).unwrap();
        let values = intensities(layout.pixel_count(), salt);
        let seeds: Vec<u32> = (0..layout.seed_count() as u32)
            .map(|i| hash_u32(i ^ salt))
            .collect();

        let color = gpu.storage_zeroed::<Vec4>("colour", layout.pixel_count());
        let permuter = SeedPermuter::new(&gpu, &pipelines, layout, &tile, &tables, &color).unwrap();
        permuter.upload_seeds(&gpu, &seeds).unwrap();
        permuter.upload_intensity(&gpu, &values).unwrap();
        permuter.set_frame(&gpu, c.frame);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        permuter.encode_step(&mut encoder, &pipelines, c.frame, PermuteMode::Permute, None);
        gpu.queue.submit([encoder.finish()]);
        let gpu_sorted = permuter.read_sorted(&gpu).unwrap();
        let gpu_next = permuter.read_seeds(&gpu).unwrap();

        let mut cpu_sorted = vec![0; seeds.len()];
        sort_frame(&layout, c.frame, &values, &tile, &seeds, &mut cpu_sorted).unwrap();
        let mut cpu_next = vec![0; seeds.len()];
        permute_frame(&layout, c.frame, &values, &tile, &tables, &seeds, &mut cpu_next).unwrap();
        assert_eq!(gpu_sorted, cpu_sorted, "sort pass (rank + gather), case {k}");
        assert_eq!(gpu_next, cpu_next, "sort + retarget, case {k}");
        assert_ne!(cpu_next, seeds, "case {k} must move seeds");

        // Both forms of the sort write the same sorted seeds (the step above
        // ran the device's).
        permuter.upload_seeds(&gpu, &seeds).unwrap();
        for form in [PassForm::PerGroup, PassForm::PerSeed] {
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            encoder.clear_buffer(permuter.sorted(), 0, None);
            permuter.encode_walk_sort(&mut encoder, &pipelines, form, None);
            gpu.queue.submit([encoder.finish()]);
            assert_eq!(
                permuter.read_sorted(&gpu).unwrap(),
                cpu_sorted,
                "{form:?} sort, case {k}"
            );
        }
    }
}

#[test]
fn seed_init_kernel_matches_the_cpu() {
    let Some(gpu) = Gpu::for_test("seed_init_kernel_matches_the_cpu") else {
        return;
    };
    let pipelines = PermutePipelines::new(&gpu).expect("pipelines");
    let layout = FrameLayout::new(70, 33, 4, 64).unwrap();
    let tile_values = random_tile(64, 1, false);
    let id = vec![IDENTITY_PACKED; 64 * 64];
    let tables = RetargetTables::new(64, [&id, &id, &id, &id]).unwrap();
    let color = gpu.storage_zeroed::<Vec4>("colour", layout.pixel_count());
    let tile = DitherTile::new(64, &tile_values).unwrap();
    let permuter = SeedPermuter::new(&gpu, &pipelines, layout, &tile, &tables, &color).unwrap();
    for salt in [0u32, 1, 99] {
        permuter.set_frame(&gpu, salt);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        permuter.encode_seed_init(&mut encoder, &pipelines);
        gpu.queue.submit([encoder.finish()]);
        let got = permuter.read_seeds(&gpu).unwrap();
        let pw = layout.padded_width();
        let want: Vec<u32> = (0..layout.seed_count() as u32)
            .map(|i| initial_seed(i % pw, i / pw, pw, salt))
            .collect();
        assert_eq!(got, want, "salt {salt}");
    }
}

#[test]
fn mismatched_sizes_are_errors() {
    let Some(gpu) = Gpu::for_test("mismatched_sizes_are_errors") else {
        return;
    };
    let pipelines = PermutePipelines::new(&gpu).expect("pipelines");
    let layout = FrameLayout::new(10, 10, 4, 8).unwrap();
    let t = random_tile(8, 0, false);
    let id = vec![IDENTITY_PACKED; 64];
    let tables = RetargetTables::new(8, [&id, &id, &id, &id]).unwrap();
    let color = gpu.storage_zeroed::<Vec4>("colour", 100);
    let p = SeedPermuter::new(
        &gpu,
        &pipelines,
        layout,
        &DitherTile::new(8, &t).unwrap(),
        &tables,
        &color,
    )
    .unwrap();
    assert!(p.upload_seeds(&gpu, &[0; 5]).is_err());
    assert!(p.upload_intensity(&gpu, &[0.0; 101]).is_err());
    let t16 = random_tile(16, 0, false);
    assert!(SeedPermuter::new(
        &gpu,
        &pipelines,
        layout,
        &DitherTile::new(16, &t16).unwrap(),
        &tables,
        &color
    )
    .is_err());
}

/// The feature-aware permutation on the GPU (`sort_features_cs` or the
/// per-seed sort, `record_link_cs`, `jump_link_cs`, `retarget_features_cs`)
/// against `sampler_core::permute_frame_features`: identical seeds in both
/// sort forms, on frames with several surfaces, creases, background and
/// padding.
#[test]
fn feature_aware_permutation_kernels_match_the_cpu_bit_for_bit() {
    use conformance::fixtures::banded_features;
    let Some(gpu) = Gpu::for_test("feature_aware_permutation_kernels_match_the_cpu_bit_for_bit") else {
        return;
    };
    let pipelines = PermutePipelines::new(&gpu).expect("pipelines");
    for (k, &(w, h, block, tile_side, frame)) in [
        (37u32, 23u32, 4u32, 16u32, 3u32),
        (64, 64, 4, 64, 17),
        (130, 70, 5, 32, 200),
    ]
    .iter()
    .enumerate()
    {
        let salt = k as u32 * 31 + 5;
        let layout = FrameLayout::new(w, h, block, tile_side).unwrap();
        let tile_values = random_tile(tile_side, salt, k == 1);
        let tile = DitherTile::new(tile_side, &tile_values).unwrap();
        let packed: Vec<Vec<u32>> = (0..4)
            .map(|i| random_table(tile_side, salt + i, 6 * tile_side * tile_side))
            .collect();
        let tables =
            RetargetTables::new(tile_side, [&packed[0], &packed[1], &packed[2], &packed[3]]).unwrap();
        let values = intensities(layout.pixel_count(), salt);
        let features = banded_features(w, h, 3, true, salt);
        let seeds: Vec<u32> = (0..layout.seed_count() as u32)
            .map(|i| hash_u32(i ^ salt))
            .collect();
        let thresholds = FeatureThresholds::DEFAULT;

        let color = gpu.storage_zeroed::<Vec4>("colour", layout.pixel_count());
        let mut permuter = SeedPermuter::new(&gpu, &pipelines, layout, &tile, &tables, &color).unwrap();
        permuter.enable_features(&gpu, &pipelines, &thresholds);
        permuter.upload_seeds(&gpu, &seeds).unwrap();
        permuter.upload_intensity(&gpu, &values).unwrap();
        permuter.upload_features(&gpu, &features).unwrap();
        permuter.set_frame(&gpu, frame);
        let mut gpu_next = Vec::new();
        for form in [PassForm::PerGroup, PassForm::PerSeed] {
            permuter.set_sort_form(form);
            permuter.upload_seeds(&gpu, &seeds).unwrap();
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            permuter.encode_step(&mut encoder, &pipelines, frame, PermuteMode::Permute, None);
            gpu.queue.submit([encoder.finish()]);
            let next = permuter.read_seeds(&gpu).unwrap();
            if form == PassForm::PerSeed {
                assert_eq!(
                    next, gpu_next,
                    "{w}x{h}: the per-seed sort against the per-block sort"
                );
            }
            gpu_next = next;
        }

        let n = seeds.len();
        let (mut sorted_buf, mut sources, mut cpu_next) = (vec![0; n], vec![0; n], vec![0; n]);
        permute_frame_features(
            &layout,
            frame,
            &values,
            &features,
            &thresholds,
            &tile,
            &tables,
            &seeds,
            &mut sorted_buf,
            &mut sources,
            &mut cpu_next,
        )
        .unwrap();
        assert_eq!(gpu_next, cpu_next, "{w}x{h}, frame {frame}");
        let mut plain = vec![0; n];
        permute_frame(&layout, frame, &values, &tile, &tables, &seeds, &mut plain).unwrap();
        assert_ne!(cpu_next, plain, "{w}x{h}: the features must change something");
    }
}

/// The temporal mode on the GPU (the sort's and `retarget_cs`'s tile and
/// table bindings on the frame's slice and table of the default target)
/// against `sampler_core::permute_frame_temporal`: identical seeds after
/// every frame of a run that crosses the wrap from slice 63 to slice 0, with
/// a walk step in between on the same permuter (the walk's buffers stay
/// intact), the two sort forms in turn, and whatever frame the parameters
/// were last set to (the temporal passes bind frame 0's).
#[test]
fn temporal_kernels_match_the_cpu_bit_for_bit_across_the_wrap() {
    let Some(gpu) = Gpu::for_test("temporal_kernels_match_the_cpu_bit_for_bit_across_the_wrap") else {
        return;
    };
    let pipelines = PermutePipelines::new(&gpu).expect("pipelines");
    let target = defaults::temporal_target();
    let (tile, tables) = (defaults::tile_64(), defaults::tables_64());
    let layout = FrameLayout::new(150, 70, 4, 64).unwrap();
    let color = gpu.storage_zeroed::<Vec4>("colour", layout.pixel_count());
    let mut permuter = SeedPermuter::new(&gpu, &pipelines, layout, &tile, &tables, &color).unwrap();
    permuter.enable_temporal(&gpu, &pipelines, &target).unwrap();
    let mut seeds: Vec<u32> = (0..layout.seed_count() as u32)
        .map(|i| hash_u32(i ^ 29))
        .collect();
    permuter.upload_seeds(&gpu, &seeds).unwrap();
    let mut next = vec![0; seeds.len()];
    for frame in [61u32, 62, 63, 64, 65] {
        let values = intensities(layout.pixel_count(), frame);
        permuter.upload_intensity(&gpu, &values).unwrap();
        let mode = if frame == 62 {
            permuter.set_frame(&gpu, frame);
            permute_frame(&layout, frame, &values, &tile, &tables, &seeds, &mut next).unwrap();
            PermuteMode::Permute
        } else {
            permuter.set_frame(&gpu, frame.wrapping_mul(7919));
            permute_frame_temporal(&layout, frame, &values, &target, &seeds, &mut next).unwrap();
            PermuteMode::Temporal
        };
        let form = [PassForm::PerGroup, PassForm::PerSeed][frame as usize % 2];
        permuter.set_sort_form(form);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        permuter.encode_step(&mut encoder, &pipelines, frame, mode, None);
        gpu.queue.submit([encoder.finish()]);
        let got = permuter.read_seeds(&gpu).unwrap();
        assert_ne!(next, seeds, "frame {frame} must move seeds");
        assert_eq!(
            got,
            next,
            "frame {frame} ({mode:?}, {form:?} sort) on {}",
            gpu.describe()
        );
        std::mem::swap(&mut seeds, &mut next);
    }
}

/// The feature-aware permutation against the temporal target on the GPU
/// (the feature-aware kernels bound on the frame's slice and table, frame
/// 0's parameters) against `sampler_core::permute_frame_features_temporal`:
/// identical seeds after every frame of a run across the wrap from slice 63
/// to slice 0, with a feature-aware walk step in between on the same
/// permuter, the two sort forms in turn, and the temporal target enabled
/// before the features (the other order is the tracer's).
#[test]
fn feature_aware_temporal_kernels_match_the_cpu_bit_for_bit() {
    use conformance::fixtures::banded_features;
    let Some(gpu) = Gpu::for_test("feature_aware_temporal_kernels_match_the_cpu_bit_for_bit") else {
        return;
    };
    let pipelines = PermutePipelines::new(&gpu).expect("pipelines");
    let target = defaults::temporal_target();
    let (tile, tables) = (defaults::tile_64(), defaults::tables_64());
    let (w, h) = (150, 70);
    let layout = FrameLayout::new(w, h, 4, 64).unwrap();
    let features = banded_features(w, h, 3, true, 11);
    let thresholds = FeatureThresholds::DEFAULT;
    let color = gpu.storage_zeroed::<Vec4>("colour", layout.pixel_count());
    let mut permuter = SeedPermuter::new(&gpu, &pipelines, layout, &tile, &tables, &color).unwrap();
    permuter.enable_temporal(&gpu, &pipelines, &target).unwrap();
    permuter.enable_features(&gpu, &pipelines, &thresholds);
    permuter.upload_features(&gpu, &features).unwrap();
    let mut seeds: Vec<u32> = (0..layout.seed_count() as u32)
        .map(|i| hash_u32(i ^ 31))
        .collect();
    permuter.upload_seeds(&gpu, &seeds).unwrap();
    let n = seeds.len();
    let (mut sorted, mut sources, mut next) = (vec![0; n], vec![0; n], vec![0; n]);
    for frame in [62u32, 63, 64, 65] {
        let values = intensities(layout.pixel_count(), frame);
        permuter.upload_intensity(&gpu, &values).unwrap();
        let mode = if frame == 64 {
            permuter.set_frame(&gpu, frame);
            permute_frame_features(
                &layout,
                frame,
                &values,
                &features,
                &thresholds,
                &tile,
                &tables,
                &seeds,
                &mut sorted,
                &mut sources,
                &mut next,
            )
            .unwrap();
            PermuteMode::Permute
        } else {
            permuter.set_frame(&gpu, frame.wrapping_mul(7919));
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
            let mut plain = vec![0; n];
            permute_frame_temporal(&layout, frame, &values, &target, &seeds, &mut plain).unwrap();
            assert_ne!(next, plain, "frame {frame}: the features must change something");
            PermuteMode::Temporal
        };
        let form = [PassForm::PerGroup, PassForm::PerSeed][frame as usize % 2];
        permuter.set_sort_form(form);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        permuter.encode_step(&mut encoder, &pipelines, frame, mode, None);
        gpu.queue.submit([encoder.finish()]);
        let got = permuter.read_seeds(&gpu).unwrap();
        assert_eq!(
            got,
            next,
            "frame {frame} ({mode:?}, {form:?} sort) on {}",
            gpu.describe()
        );
        std::mem::swap(&mut seeds, &mut next);
    }
}
