//! Property tests of the seed permutation (issue 2): for arbitrary frame
//! sizes, block sizes, tiles, retarget tables and intensities (NaN, infinities,
//! signed zeros and ties included) the passes are bijections that do what the
//! paper's algorithms say.

use conformance::fixtures::{random_table, random_tile};
use proptest::prelude::*;
use sampler_core::*;

/// Intensities mixing ordinary values, ties and every special f32.
fn intensity() -> impl Strategy<Value = f32> {
    prop_oneof![
        4 => (0u32..8).prop_map(|i| i as f32 * 0.25),   // many ties
        4 => any::<f32>(),                               // NaN payloads, subnormals, both signs
        1 => Just(f32::NAN),
        1 => Just(-f32::NAN),
        1 => Just(f32::INFINITY),
        1 => Just(f32::NEG_INFINITY),
        1 => Just(-0.0f32),
        1 => Just(0.0f32),
    ]
}

#[derive(Debug, Clone)]
struct Case {
    width: u32,
    height: u32,
    block: u32,
    tile: u32,
    frame: u32,
    salt: u32,
    intensities: Vec<f32>,
}

fn case() -> impl Strategy<Value = Case> {
    (
        1u32..=70,
        1u32..=45,
        MIN_BLOCK..=MAX_BLOCK,
        1u32..=7,
        any::<u32>(),
        any::<u32>(),
    )
        .prop_flat_map(|(width, height, block, tile_log2, frame, salt)| {
            prop::collection::vec(intensity(), (width * height) as usize).prop_map(move |intensities| Case {
                width,
                height,
                block,
                tile: 1 << tile_log2,
                frame,
                salt,
                intensities,
            })
        })
}

fn seeds_for(layout: &FrameLayout, salt: u32) -> Vec<u32> {
    (0..layout.seed_count() as u32)
        .map(|i| sequences::seed::hash_u32(i ^ salt))
        .collect()
}

fn sorted(v: &[u32]) -> Vec<u32> {
    let mut v = v.to_vec();
    v.sort_unstable();
    v
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// Reprojection (issue 13) never duplicates or loses a seed, whatever
    /// the motion field (random, NaN, infinities, huge, convergent), and
    /// keeps the padding's seeds in place.
    #[test]
    fn reprojection_is_a_permutation_for_any_motion_field(
        (width, height, block, tile_log2, salt) in (1u32..=70, 1u32..=45, MIN_BLOCK..=MAX_BLOCK, 1u32..=7, any::<u32>()),
        kind in 0u32..5,
        scale in prop_oneof![Just(0.3f32), Just(2.0), Just(40.0), Just(1e30)],
    ) {
        let layout = FrameLayout::new(width, height, block, 1 << tile_log2).unwrap();
        let seeds = seeds_for(&layout, salt);
        let motion: Vec<[f32; 2]> = (0..width * height)
            .map(|i| {
                let (x, y) = ((i % width) as f32, (i / width) as f32);
                let h = sequences::seed::hash_u32(i ^ salt);
                let r = |k: u32| random_f32(h, k) * 2.0 - 1.0;
                match kind {
                    0 => [r(0) * scale, r(1) * scale],
                    1 => [width as f32 * 0.5 - x, height as f32 * 0.5 - y], // all to the centre
                    2 => if h.is_multiple_of(3) { [f32::NAN, 0.0] } else { [r(0) * scale, f32::INFINITY * r(1).signum()] },
                    3 => [(y - height as f32 * 0.5) * 0.2, -(x - width as f32 * 0.5) * 0.2], // rotation
                    _ => [-scale, 0.0], // uniform shift
                }
            })
            .collect();
        let mut claims = vec![0u32; layout.seed_count()];
        let mut out = vec![0u32; layout.seed_count()];
        let stats = reproject_frame(&layout, &motion, &seeds, &mut claims, &mut out).unwrap();
        prop_assert_eq!(sorted(&out), sorted(&seeds));
        prop_assert_eq!(stats.followed + stats.recycled, width * height);
        let pw = layout.padded_width() as usize;
        for (i, (a, b)) in out.iter().zip(&seeds).enumerate() {
            if i % pw >= width as usize || i / pw >= height as usize {
                prop_assert_eq!(a, b, "padding seed {} moved", i);
            }
        }
    }


    #[test]
    fn sorting_is_a_blockwise_permutation_that_follows_dither_ranks(c in case()) {
        let layout = FrameLayout::new(c.width, c.height, c.block, c.tile).unwrap();
        let tile_values = random_tile(c.tile, c.salt, true);
        let tile = DitherTile::new(c.tile, &tile_values).unwrap();
        let seeds = seeds_for(&layout, c.salt);
        let mut out = vec![0; seeds.len()];
        sort_frame(&layout, c.frame, &c.intensities, &tile, &seeds, &mut out).unwrap();
        prop_assert_eq!(sorted(&out), sorted(&seeds));

        let p = layout.params(c.frame);
        let offset = walk_offset(c.frame, p.tile_log2);
        let pw = p.padded_width;
        for by in 0..p.blocks_y() {
            for bx in 0..p.blocks_x() {
                // Visible pixels of the block, in row-major in-block order.
                let mut px = Vec::new();
                for y in by * c.block..((by + 1) * c.block).min(p.padded_height) {
                    for x in bx * c.block..((bx + 1) * c.block).min(pw) {
                        if x < c.width && y < c.height {
                            px.push((x, y));
                        } else {
                            // Padding is never sorted.
                            prop_assert_eq!(out[(y * pw + x) as usize], seeds[(y * pw + x) as usize]);
                        }
                    }
                }
                // Reference ranks by std sort with the documented tie-breaks.
                let mut by_intensity: Vec<usize> = (0..px.len()).collect();
                by_intensity.sort_by_key(|&i| {
                    let (x, y) = px[i];
                    (intensity_key(c.intensities[(y * c.width + x) as usize]), i)
                });
                let mut by_dither: Vec<usize> = (0..px.len()).collect();
                by_dither.sort_by_key(|&i| {
                    let (x, y) = px[i];
                    (tile_values[tile_texel(glam::UVec2::new(x, y), offset, p.tile_log2) as usize], i)
                });
                for k in 0..px.len() {
                    let (sx, sy) = px[by_intensity[k]];
                    let (dx, dy) = px[by_dither[k]];
                    prop_assert_eq!(out[(dy * pw + dx) as usize], seeds[(sy * pw + sx) as usize]);
                }
            }
        }
    }

    #[test]
    fn retargeting_is_a_bijection_within_radius(c in case(), swaps in 0u32..400) {
        let layout = FrameLayout::new(c.width, c.height, c.block, c.tile).unwrap();
        let packed: Vec<Vec<u32>> = (0..STEP_COUNT as u32)
            .map(|i| random_table(c.tile, c.salt ^ i, swaps))
            .collect();
        let tables = RetargetTables::new(c.tile, [&packed[0], &packed[1], &packed[2], &packed[3]]).unwrap();
        // Distinct values make the permutation visible.
        let seeds: Vec<u32> = (0..layout.seed_count() as u32).collect();
        let mut out = vec![u32::MAX; seeds.len()];
        retarget_frame(&layout, c.frame, &tables, &seeds, &mut out).unwrap();
        prop_assert_eq!(sorted(&out), seeds.clone());
        let (pw, ph) = (layout.padded_width() as i32, layout.padded_height() as i32);
        for (dst, &src) in out.iter().enumerate() {
            let (sx, sy) = ((src as i32) % pw, (src as i32) / pw);
            let (dx, dy) = ((dst as i32) % pw, (dst as i32) / pw);
            // Toroidal distance over the padded buffer.
            let ddx = (dx - sx).rem_euclid(pw).min((sx - dx).rem_euclid(pw));
            let ddy = (dy - sy).rem_euclid(ph).min((sy - dy).rem_euclid(ph));
            prop_assert!(ddx <= RETARGET_RADIUS && ddy <= RETARGET_RADIUS);
        }
    }

    #[test]
    fn fused_frame_pass_equals_sort_then_retarget(c in case(), swaps in 0u32..400) {
        let layout = FrameLayout::new(c.width, c.height, c.block, c.tile).unwrap();
        let tile_values = random_tile(c.tile, c.salt, false);
        let tile = DitherTile::new(c.tile, &tile_values).unwrap();
        let packed: Vec<Vec<u32>> = (0..STEP_COUNT as u32)
            .map(|i| random_table(c.tile, c.salt.wrapping_add(i), swaps))
            .collect();
        let tables = RetargetTables::new(c.tile, [&packed[0], &packed[1], &packed[2], &packed[3]]).unwrap();
        let seeds = seeds_for(&layout, c.salt);
        let mut fused = vec![0; seeds.len()];
        permute_frame(&layout, c.frame, &c.intensities, &tile, &tables, &seeds, &mut fused).unwrap();
        let mut mid = vec![0; seeds.len()];
        let mut two_pass = vec![0; seeds.len()];
        sort_frame(&layout, c.frame, &c.intensities, &tile, &seeds, &mut mid).unwrap();
        retarget_frame(&layout, c.frame, &tables, &mid, &mut two_pass).unwrap();
        prop_assert_eq!(fused, two_pass);
    }

    #[test]
    fn rgb_input_ranks_by_luma(c in case()) {
        let layout = FrameLayout::new(c.width, c.height, c.block, c.tile).unwrap();
        let tile_values = random_tile(c.tile, c.salt, false);
        let tile = DitherTile::new(c.tile, &tile_values).unwrap();
        let rgb: Vec<[f32; 3]> = c.intensities.iter().map(|&v| [v, v * 0.5, 1.0]).collect();
        let luma_values: Vec<f32> = rgb.iter().map(|&p| p.intensity()).collect();
        let seeds = seeds_for(&layout, c.salt);
        let (mut a, mut b) = (vec![0; seeds.len()], vec![0; seeds.len()]);
        sort_frame(&layout, c.frame, &rgb, &tile, &seeds, &mut a).unwrap();
        sort_frame(&layout, c.frame, &luma_values, &tile, &seeds, &mut b).unwrap();
        prop_assert_eq!(a, b);
    }
}

#[test]
fn offset_walk_is_aperiodic_and_takes_the_documented_steps() {
    for log2 in 1..=10u32 {
        let w = 1u32 << log2;
        let base = sequences::walk::base_step(log2);
        let offsets: Vec<_> = (0..8192u32).map(|t| walk_offset(t, log2)).collect();
        assert!(offsets.iter().all(|o| o.x < w && o.y < w));
        // No period p <= 4096 over the first 4096 frames.
        for p in 1..=4096usize {
            assert!(
                (0..4096).any(|t| offsets[t + p] != offsets[t]),
                "W {w}: period {p}"
            );
        }
        for t in 0..8191u32 {
            let s = walk_step(t, log2);
            let ok = |v: u32, b: u32| v == b || v == (b + 1) % w;
            assert!(ok(s.x, base.x) && ok(s.y, base.y), "W {w} t {t}: step {s}");
        }
    }
    // W = 64: every one of the four steps occurs, and an offset is revisited
    // no sooner than 1000 frames later (a fixed step (48, 36) revisits after 16).
    let steps: std::collections::BTreeSet<u32> = (0..4096).map(|t| step_index(t, 6)).collect();
    assert_eq!(steps.len(), 4);
    let mut last = std::collections::HashMap::new();
    for t in 0..4096u32 {
        let o = walk_offset(t, 6);
        if let Some(prev) = last.insert((o.x, o.y), t) {
            assert!(t - prev > 1000, "offset {o} revisited after {} frames", t - prev);
        }
    }
    let fixed: std::collections::BTreeSet<_> = (0..4096u32).map(|t| ((t * 48) % 64, (t * 36) % 64)).collect();
    assert_eq!(fixed.len(), 16, "the fixed step the notes warn about");
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let layout = FrameLayout::new(7, 5, 4, 8).unwrap();
    let tile_values = random_tile(8, 1, false);
    let tile = DitherTile::new(8, &tile_values).unwrap();
    let id = [IDENTITY_PACKED; 64];
    let tables = RetargetTables::new(8, [&id; 4]).unwrap();
    let img = vec![0.5f32; 35];
    let seeds = vec![0u32; layout.seed_count()];
    let mut out = vec![0u32; layout.seed_count()];
    let err = permute_frame(&layout, 0, &img[..34], &tile, &tables, &seeds, &mut out).unwrap_err();
    assert_eq!(
        err,
        Error::BufferSize {
            buffer: Buffer::Intensities,
            expected: 35,
            actual: 34
        }
    );
    let err = permute_frame(&layout, 0, &img, &tile, &tables, &seeds[1..], &mut out).unwrap_err();
    assert_eq!(
        err,
        Error::BufferSize {
            buffer: Buffer::SeedsIn,
            expected: 64,
            actual: 63
        }
    );
    let mut short = vec![0u32; 10];
    let err = sort_frame(&layout, 0, &img, &tile, &seeds, &mut short).unwrap_err();
    assert!(matches!(
        err,
        Error::BufferSize {
            buffer: Buffer::SeedsOut,
            ..
        }
    ));
    assert!(err
        .to_string()
        .contains("output seed buffer has 10 elements, expected 64"));
    // A tile of another size than the layout's.
    let t16 = random_tile(16, 1, false);
    let err = sort_frame(
        &layout,
        0,
        &img,
        &DitherTile::new(16, &t16).unwrap(),
        &seeds,
        &mut out,
    )
    .unwrap_err();
    assert_eq!(err, Error::TileSize { tile: 16 });
    assert!(matches!(
        DitherTile::new(8, &t16),
        Err(Error::BufferSize {
            buffer: Buffer::DitherTile,
            ..
        })
    ));
    assert!(matches!(
        DitherTile::new(12, &t16),
        Err(Error::TileSize { tile: 12 })
    ));
}

/// The fast path's vector groups (8 or 16 blocks side by side) only run on
/// frames wider than `properties`' cases: frames of a
/// few hundred pixels, every fast-path block size and tile, intensities with
/// ties and special values, against the two separate passes.
#[test]
fn fused_frame_pass_equals_sort_then_retarget_on_large_frames() {
    let mut state = 0x1234_5678u32;
    let mut next = move || {
        state = sequences::seed::hash_u32(state);
        state
    };
    for (width, height) in [(300u32, 200u32), (256, 128), (517, 93)] {
        for block in [2u32, 4, 8] {
            for tile_size in [16u32, 64, 128] {
                let layout = FrameLayout::new(width, height, block, tile_size).unwrap();
                let intensities: Vec<f32> = (0..layout.pixel_count())
                    .map(|_| match next() % 8 {
                        0 => f32::NAN,
                        1 => f32::NEG_INFINITY,
                        2 | 3 => (next() % 4) as f32, // ties
                        _ => f32::from_bits(next()),
                    })
                    .collect();
                let salt = next();
                let tile_values = random_tile(tile_size, salt, false);
                let tile = DitherTile::new(tile_size, &tile_values).unwrap();
                let packed: Vec<Vec<u32>> = (0..STEP_COUNT as u32)
                    .map(|i| random_table(tile_size, salt.wrapping_add(i), 300))
                    .collect();
                let tables =
                    RetargetTables::new(tile_size, [&packed[0], &packed[1], &packed[2], &packed[3]]).unwrap();
                let seeds = seeds_for(&layout, salt);
                for frame in [0u32, 5] {
                    let mut fused = vec![0; seeds.len()];
                    permute_frame(&layout, frame, &intensities, &tile, &tables, &seeds, &mut fused).unwrap();
                    let mut mid = vec![0; seeds.len()];
                    let mut two_pass = vec![0; seeds.len()];
                    sort_frame(&layout, frame, &intensities, &tile, &seeds, &mut mid).unwrap();
                    retarget_frame(&layout, frame, &tables, &mid, &mut two_pass).unwrap();
                    assert!(
                        fused == two_pass,
                        "{width}x{height}, block {block}, tile {tile_size}, frame {frame}"
                    );
                    // The baseline-ISA fast path (what CPUs without AVX2 run).
                    let mut baseline = vec![0; seeds.len()];
                    permute_frame_baseline_isa(
                        &layout,
                        frame,
                        &intensities,
                        &tile,
                        &tables,
                        &seeds,
                        &mut baseline,
                    )
                    .unwrap();
                    assert!(
                        baseline == two_pass,
                        "baseline ISA: {width}x{height}, block {block}, tile {tile_size}, frame {frame}"
                    );
                }
            }
        }
    }
}
