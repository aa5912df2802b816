//! Issue 13, part 4: the seed permutation in motion, at a CI size.
//!
//! The Cornell box at 96x96, 1 spp, depth 8, 24 frames (one sway period), still and
//! with the camera orbiting at 2 px/frame at the image centre, each frame against a
//! 64-spp reference of its pose (cached under `target/quality-cache`; about 20 s in
//! release without the cache). The full-size figures are in
//! QUALITY.md ("Seeds in motion", `cargo run -p conformance --release -- motion`).
//!
//! Run in release: `cargo test -p conformance --release --test motion_quality -- --nocapture`.

use conformance::metrics::regions::{classify_regions, Region, EMITTER_ZONE_RADIUS};
use conformance::motion::{
    fit_insets, markdown, run_study, Figure, InsetAnchor, MotionCase, MotionConfig, MotionMethod,
    MotionSequence,
};
use conformance::study::default_cache_dir;
use gpu_tracer::cornell::cornell_box;
use gpu_tracer::{cpu, SceneGpu, TraceSettings};
use kernels::abi::{GBufferGpu, GBUFFER_EMITTER, GBUFFER_HIT};

const SIZE: u32 = 96;
const FRAMES: u32 = 24;
const REF_SPP: u32 = 64;

fn own(anchors: Vec<InsetAnchor>) -> Vec<(InsetAnchor, bool)> {
    anchors.into_iter().map(|a| (a, true)).collect()
}

/// At 2 px/frame with reprojection, the permutation's blurred error stays within the
/// issue's 1.25x of its static figure (whole image and interior), and moving the seeds
/// with the picture beats leaving them in place around the light, where a seed left in
/// place lands on the other side of the silhouette (QUALITY.md, "Seeds in motion").
/// The inset LF is printed but not asserted: on this image the one inset that stays on
/// the back wall is 16 px, where even the still camera's LF is near white's.
#[test]
fn reprojection_keeps_the_static_quality_at_2_px_per_frame() {
    let start = std::time::Instant::now();
    let config = MotionConfig::new(SIZE, FRAMES, REF_SPP);
    let orbit = MotionCase::Orbit { px_per_frame: 2.0 };
    let methods = [
        MotionMethod::White,
        MotionMethod::Permute,
        MotionMethod::PermuteReproject,
    ];
    let results = run_study(config, &[orbit], &methods, Some(&default_cache_dir()), |m| {
        println!("[{:5.1} s] {m}", start.elapsed().as_secs_f64())
    })
    .expect("study");
    println!("{}", markdown(&results));
    let (still, moving) = (&results[0], &results[1]);
    assert_eq!((still.case, moving.case), (MotionCase::Still, orbit));
    let s = &moving.stats;
    assert!(
        (1.5..3.5).contains(&s.centre_speed),
        "centre speed {} px/frame",
        s.centre_speed
    );
    assert!(s.followed > 0.8 && s.stayed < 0.2, "{s:?}");
    // A still camera keeps every home; an orbit breaks some neighbours apart.
    assert!(
        (still.stats.homes_in_order - 1.0).abs() < 1e-9,
        "{:?}",
        still.stats
    );
    assert!(s.homes_in_order > 0.0 && s.homes_in_order < 1.0, "{s:?}");
    let interior = Figure::Blur(Some(Region::Interior));
    for figure in [Figure::Blur(None), interior] {
        let v = moving
            .versus_static(still, MotionMethod::PermuteReproject, figure)
            .expect("figure");
        assert!(v <= 1.25, "{figure:?}: {v:.3} of the static figure (goal 1.25)");
    }
    let fig = |m, f| moving.relative(m, f).expect("figure");
    for figure in [Figure::Blur(Some(Region::Emitter)), Figure::Blur(None)] {
        let (without, with) = (
            fig(MotionMethod::Permute, figure),
            fig(MotionMethod::PermuteReproject, figure),
        );
        assert!(
            with < without,
            "{figure:?}: with reprojection {with:.3} should be below without {without:.3}"
        );
    }
    println!("{:.1} s", start.elapsed().as_secs_f64());
}

/// The still sequence's insets do not all stay on their walls under a 2 px/frame
/// orbit: the per-frame check must say which one leaves, in which frame.
#[test]
fn an_inset_that_leaves_its_surface_fails_clearly() {
    let config = MotionConfig::new(SIZE, FRAMES, 2);
    let still = fit_insets(&config, &[MotionCase::Still]).expect("still insets");
    assert_eq!(still.len(), 3, "all three insets fit a still camera");
    let orbit = MotionCase::Orbit { px_per_frame: 2.0 };
    let err = MotionSequence::new(config, orbit, &own(still), None, |_| {}).expect_err("must fail");
    let text = format!("{err:#}");
    println!("{text}");
    assert!(
        text.contains("frame") && text.contains("left its surface"),
        "{text}"
    );
    assert!(text.contains("wall"), "{text}");
    // fit_insets drops the side walls (they narrow below 8 px) and keeps the back wall.
    let fitted = fit_insets(&config, &[orbit]).expect("orbit insets");
    assert!(fitted.iter().any(|a| a.inset.name == "back wall"), "{fitted:?}");
    MotionSequence::new(config, orbit, &own(fitted), None, |_| {}).expect("fitted insets pass every frame");
}

/// Every pixel gets exactly one region, the emitter zone holds the light, and interior
/// pixels see one flat surface around them.
#[test]
fn regions_partition_the_cornell_box() {
    let size = 64u32;
    let scene = SceneGpu::build(&cornell_box()).unwrap();
    let params = scene.trace_params(&TraceSettings::new(size, size), 0).unwrap();
    let mut g = vec![GBufferGpu::default(); (size * size) as usize];
    cpu::gbuffer_frame(&scene, &params, &mut g).unwrap();
    let regions = classify_regions(&g, size, size);
    assert_eq!(regions.len(), g.len());
    let count = |r: Region| regions.iter().filter(|&&x| x == r).count();
    let counts: Vec<usize> = Region::ALL.iter().map(|&r| count(r)).collect();
    println!("emitter / edges / interior pixels at {size}x{size}: {counts:?}");
    assert_eq!(counts.iter().sum::<usize>(), g.len());
    assert!(counts.iter().all(|&c| c > 0), "{counts:?}");
    let w = size as usize;
    let is_light = |i: usize| g[i].ids.w & (GBUFFER_EMITTER | GBUFFER_HIT) == (GBUFFER_EMITTER | GBUFFER_HIT);
    assert!((0..g.len()).any(is_light), "the light is visible");
    let r = EMITTER_ZONE_RADIUS as usize;
    for i in 0..g.len() {
        let (x, y) = (i % w, i / w);
        let near_light = (y.saturating_sub(r)..(y + r + 1).min(w))
            .any(|ny| (x.saturating_sub(r)..(x + r + 1).min(w)).any(|nx| is_light(ny * w + nx)));
        assert_eq!(regions[i] == Region::Emitter, near_light, "pixel ({x}, {y})");
        if regions[i] == Region::Interior {
            for ny in y.saturating_sub(1)..(y + 2).min(w) {
                for nx in x.saturating_sub(1)..(x + 2).min(w) {
                    assert_eq!(
                        g[ny * w + nx].ids.x,
                        g[i].ids.x,
                        "interior pixel ({x}, {y}) at an edge"
                    );
                }
            }
        }
    }
    // The regions of a moving sequence cover every frame.
    let config = MotionConfig::new(size, 6, 2);
    let case = MotionCase::Object { px_per_frame: 1.0 };
    let anchors = fit_insets(&config, &[case]).unwrap();
    let seq = MotionSequence::new(config, case, &own(anchors), None, |_| {}).unwrap();
    for t in 0..6 {
        assert_eq!(seq.regions(t).len(), g.len());
        assert!(seq.regions(t).contains(&Region::Interior));
    }
}
