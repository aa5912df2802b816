//! Numeric oracles from `shared/notes/algorithm.md`, checked through the
//! public API.

use sampler_core::*;

#[test]
fn paper_oracle_through_the_frame_api() {
    // 2x2 frame, one 2x2 block, 2x2 tile whose ranks order like
    // dither [0.2, 0.8, 0.6, 0.4]; frame 0 reads the tile unshifted.
    let layout = FrameLayout::new(2, 2, 2, 2).unwrap();
    let tile = [0u32, 3, 2, 1];
    let intensities = [0.9f32, 0.1, 0.5, 0.3];
    let seeds = [10u32, 11, 12, 13];
    let mut out = [0u32; 4];
    sort_frame(
        &layout,
        0,
        &intensities,
        &DitherTile::new(2, &tile).unwrap(),
        &seeds,
        &mut out,
    )
    .unwrap();
    assert_eq!(out, [11, 10, 12, 13]);
}

#[test]
fn r2_points() {
    let want = [
        (1, 0.254_877_666_2, 0.069_840_291_0),
        (2, 0.009_755_332_5, 0.639_680_582_0),
        (3, 0.764_632_998_7, 0.209_520_873_0),
        (4, 0.519_510_665_0, 0.779_361_164_0),
    ];
    for (n, x, y) in want {
        let p = r2(n, 0.5);
        assert!(
            (p.x as f64 - x).abs() < 2e-7 && (p.y as f64 - y).abs() < 2e-7,
            "n {n}: {p}"
        );
    }
    assert!((r1(1, 0.0) as f64 - 0.618_034).abs() < 1e-6);
}

#[test]
fn walk_offsets_and_fixed_steps() {
    let want = [(1, 48, 36), (2, 32, 8), (3, 16, 45), (4, 1, 17), (5, 49, 54)];
    for (t, x, y) in want {
        assert_eq!(walk_offset(t, 6), glam::UVec2::new(x, y), "t {t}");
    }
    for (log2, x, y) in [(6, 48, 36), (7, 96, 72), (8, 193, 145), (9, 386, 291)] {
        assert_eq!(sequences::walk::base_step(log2), glam::UVec2::new(x, y));
    }
    // The four steps of W = 64 (three-distance theorem).
    let steps: Vec<_> = (0..4).map(|i| step_of_index(i, 6)).collect();
    let want: Vec<_> = [(48, 36), (49, 36), (48, 37), (49, 37)]
        .map(|(x, y)| glam::UVec2::new(x, y))
        .to_vec();
    assert_eq!(steps, want);
}

#[test]
fn fixed_point_walk_matches_the_f64_formula_except_at_boundary_roundings() {
    let a = [sequences::r2::R2_A1, sequences::r2::R2_A2];
    let mut differ = 0;
    for t in 0..100_000u32 {
        let o = walk_offset(t, 6);
        let f = |ai: f64| ((t as f64 * ai).fract() * 64.0).floor() as u32;
        if o.x != f(a[0]) || o.y != f(a[1]) {
            differ += 1;
        }
    }
    // algorithm.md reports 18 such frames out of 100,000.
    assert!(differ <= 40, "{differ} frames differ");
}
