//! Issue 5, part 2: end-to-end quality on rendered frames, at a CI size.
//!
//! The Cornell box at 128x128, 1 spp, 64 frames per method, against a 512-spp reference
//! (cached under `target/quality-cache`), and a short 4-spp run. Every test prints the
//! figures it measures; the full-size figures are in QUALITY.md
//! (`cargo run -p conformance --release -- report --out DIR`).
//!
//! Goals (issue 5), relative to fresh white-noise seeds:
//! - by frame 8, permute's error low-frequency power on the flat insets <= 0.15;
//! - by frame 8, permute's blurred RMSE (sigma 1, whole image) <= 0.6;
//! - accumulated RMSE <= 1.05 at 64 frames (128 does not fit the CI budget).

use conformance::study::{default_cache_dir, Method, Metric, Study, StudyConfig, StudyResult, GOAL_FRAME};
use std::sync::OnceLock;

const SIZE: u32 = 128;
const FRAMES: u32 = 64;
const REF_SPP: u32 = 512;

fn study(spp: u32, frames: u32, methods: &[Method]) -> StudyResult {
    let config = StudyConfig::new(SIZE, spp, frames, REF_SPP);
    let start = std::time::Instant::now();
    let study = Study::new(config, Some(&default_cache_dir()), |_, _| {}).expect("study setup");
    let reference = start.elapsed();
    let result = study.run(methods, |_, _| {}).expect("study run");
    println!(
        "{spp} spp: reference {:.1} s, {} methods x {frames} frames {:.1} s",
        reference.as_secs_f64(),
        methods.len(),
        (start.elapsed() - reference).as_secs_f64()
    );
    println!("{}", result.summary());
    result
}

/// The rows measured here: every method of issue 5 and 6. The feature-aware rows
/// (issue 14) are measured at full size by `conformance study` (QUALITY.md), not in
/// this CI run.
const METHODS: [Method; 11] = [
    Method::White,
    Method::Sort,
    Method::Permute,
    Method::PermuteJitter,
    Method::FixedStep,
    Method::Dither,
    Method::ScreenSobol,
    Method::ZSobol,
    Method::Spatiotemporal,
    Method::SpatiotemporalKronecker,
    Method::TemporalPermuteJitter,
];

fn one_spp() -> &'static StudyResult {
    static RESULT: OnceLock<StudyResult> = OnceLock::new();
    RESULT.get_or_init(|| study(1, FRAMES, &METHODS))
}

fn rel(r: &StudyResult, m: Method, metric: Metric, i: usize) -> f64 {
    r.relative(m, metric, i).expect("measured")
}

#[test]
fn frame_zero_is_the_same_white_start_for_every_permutation_method() {
    let r = one_spp();
    for m in [Method::Sort, Method::Permute, Method::FixedStep] {
        let lf = rel(r, m, Metric::LowFrequency, 0);
        let blur = rel(r, m, Metric::Blur1, 0);
        println!("{}: frame 0 LF {lf:.6}, blur1 {blur:.6} (white = 1)", m.name());
        assert_eq!(
            (lf, blur),
            (1.0, 1.0),
            "{} must start from white's seeds",
            m.name()
        );
    }
}

#[test]
fn insets_are_flat() {
    let r = one_spp();
    for inset in &r.insets {
        println!(
            "inset {}: ({}, {}) side {}, max relative gradient of the reference {:.3}",
            inset.name, inset.x0, inset.y0, inset.side, inset.max_gradient
        );
        // Reference noise alone (512 spp) gives a few percent; an edge or a shadow
        // boundary gives far more than 0.5.
        assert!(inset.max_gradient < 0.5, "{} is not flat", inset.name);
    }
}

#[test]
#[ignore = "issue 5 goal not met yet (see QUALITY.md); run with --ignored"]
fn permute_error_low_frequency_power_by_frame_8() {
    let r = one_spp();
    let t = GOAL_FRAME as usize;
    for m in METHODS {
        let per_frame: Vec<String> = (0..=t + 4)
            .map(|i| format!("{:.3}", rel(r, m, Metric::LowFrequency, i)))
            .collect();
        println!(
            "LF power (white = 1), frames 0..={}: {:<10} {}",
            t + 4,
            m.name(),
            per_frame.join(" ")
        );
    }
    let run = r.run(Method::Permute).unwrap();
    println!("permute per inset at frame {t}: {:?}", run.lf_insets[t]);
    let lf = rel(r, Method::Permute, Metric::LowFrequency, t);
    println!("permute LF at frame {t}: {lf:.3} (goal <= 0.15)");
    assert!(
        lf <= 0.15,
        "permute's LF power at frame {t} is {lf:.3} of white's (goal 0.15)"
    );
}

#[test]
#[ignore = "issue 5 goal not met yet (see QUALITY.md); run with --ignored"]
fn permute_blurred_rmse_by_frame_8() {
    let r = one_spp();
    let t = GOAL_FRAME as usize;
    for m in METHODS {
        println!(
            "{:<10} frame {t}: blur1 {:.3} blur2 {:.3} unblurred {:.3} (white = 1)",
            m.name(),
            rel(r, m, Metric::Blur1, t),
            rel(r, m, Metric::Blur2, t),
            rel(r, m, Metric::Rmse, t)
        );
    }
    for m in [Method::Permute, Method::PermuteJitter] {
        println!(
            "{:<14} blurred RMSE (sigma 1) over frames {t}..: {:.3}",
            m.name(),
            r.pooled(m, Metric::Blur1, t).unwrap()
        );
    }
    let b = rel(r, Method::Permute, Metric::Blur1, t);
    println!("permute blurred RMSE (sigma 1) at frame {t}: {b:.3} (goal <= 0.6)");
    assert!(
        b <= 0.6,
        "permute's blurred RMSE at frame {t} is {b:.3} of white's (goal 0.6)"
    );
}

/// Met at this CI size (128x128, 64 frames: about 1.03); at the issue's
/// full size (256x256) the same goal is missed, 1.11 at 64 and 128 frames
/// (QUALITY.md).
#[test]
fn permute_accumulates_like_white() {
    let r = one_spp();
    for m in METHODS {
        let f: Vec<String> = [8usize, 16, 32, 64]
            .iter()
            .map(|&n| {
                format!(
                    "{n}: {:.3} (raw {:.3})",
                    rel(r, m, Metric::Accumulated, n - 1),
                    rel(r, m, Metric::AccumulatedRaw, n - 1)
                )
            })
            .collect();
        println!("accumulated RMSE (white = 1) {:<10} {}", m.name(), f.join(", "));
    }
    let a = rel(r, Method::Permute, Metric::Accumulated, FRAMES as usize - 1);
    println!("permute accumulated RMSE at {FRAMES} frames: {a:.3} (goal <= 1.05)");
    assert!(
        a <= 1.05,
        "permute's accumulated RMSE at {FRAMES} frames is {a:.3} of white's (goal 1.05)"
    );
}

/// The permutation with the pixel jitter from the screen-space Sobol sampler
/// (`--sampler screen-sobol-jitter`, [`Method::PermuteJitter`]): silhouettes,
/// where a seed's estimate depends on little but its jitter and moving seeds
/// cannot help, get a jitter stratified along rows and columns and a new key
/// every frame. It must keep the permutation's low-frequency power on the
/// flat insets, lower the whole-image blurred RMSE clearly below the plain
/// permutation's, and converge like the sampler's jitter alone: the
/// accumulated error is set by the ~100 silhouette pixels, whose per-frame
/// jitter comes from the key tile walked by the R2 offsets (deterministic:
/// 1.12 of white at this size for the screen-space sampler with white
/// seeds, 0.92-0.95 at 256x256; QUALITY.md), so the permutation may add
/// at most 0.05 to it.
#[test]
fn permute_with_sampler_jitter_blurs_better_and_converges_like_the_sampler() {
    let r = one_spp();
    let n = FRAMES as usize;
    let from = GOAL_FRAME as usize;
    let lf_mean = |m| (from..n).map(|i| rel(r, m, Metric::LowFrequency, i)).sum::<f64>() / (n - from) as f64;
    let blur = |m| r.pooled(m, Metric::Blur1, from).unwrap();
    let (acc, acc_plain, acc_sampler) = (
        rel(r, Method::PermuteJitter, Metric::Accumulated, n - 1),
        rel(r, Method::Permute, Metric::Accumulated, n - 1),
        rel(r, Method::ScreenSobol, Metric::Accumulated, n - 1),
    );
    let (lf, lf_plain) = (lf_mean(Method::PermuteJitter), lf_mean(Method::Permute));
    let (b, b_plain) = (blur(Method::PermuteJitter), blur(Method::Permute));
    println!(
        "permute-jitter (permute): accumulated at {n} frames {acc:.3} ({acc_plain:.3}; screen-sobol \
         {acc_sampler:.3}); LF mean {from}.. {lf:.3} ({lf_plain:.3}); blurred RMSE over frames {from}.. \
         {b:.3} ({b_plain:.3}); white = 1"
    );
    assert!(
        acc <= acc_sampler + 0.05,
        "accumulated RMSE {acc:.3}, screen-sobol jitter with white seeds {acc_sampler:.3}"
    );
    assert!(
        lf <= lf_plain + 0.1,
        "LF power {lf:.3}, plain permutation {lf_plain:.3}"
    );
    assert!(
        b <= b_plain - 0.1,
        "blurred RMSE {b:.3}, plain permutation {b_plain:.3}"
    );
}

#[test]
fn the_r2_walk_accumulates_better_than_the_fixed_step() {
    let r = one_spp();
    let n = FRAMES as usize;
    let fixed = rel(r, Method::FixedStep, Metric::Accumulated, n - 1);
    let walk = rel(r, Method::Permute, Metric::Accumulated, n - 1);
    println!("accumulated RMSE at {n} frames (white = 1): R2 walk {walk:.3}, fixed step (48, 36) {fixed:.3}");
    // The fixed step repeats every 16 frames, so it must not beat the aperiodic walk.
    assert!(
        fixed > walk,
        "the fixed step accumulated better ({fixed:.3}) than the R2 walk ({walk:.3})"
    );
}

#[test]
#[ignore = "issue 5 goal not met yet (see QUALITY.md); run with --ignored"]
fn four_spp_by_frame_8() {
    let r = study(4, GOAL_FRAME + 1, &[Method::White, Method::Permute]);
    let t = GOAL_FRAME as usize;
    let lf = rel(&r, Method::Permute, Metric::LowFrequency, t);
    let b = rel(&r, Method::Permute, Metric::Blur1, t);
    println!("4 spp, frame {t}: permute LF {lf:.3} (goal <= 0.15), blur1 {b:.3} (goal <= 0.6)");
    assert!(
        lf <= 0.15 && b <= 0.6,
        "4 spp: LF {lf:.3} (goal 0.15), blur1 {b:.3} (goal 0.6)"
    );
}

/// Issue 15: every method is measured after the real-time filters, and the
/// figures behave as filters must: they lower white noise's error, TAA
/// leaves a still reference unchanged (no bias), the a-trous filter has a
/// bias of its own, and blue-noise error keeps an advantage in the noise part.
#[test]
fn every_method_is_measured_after_the_real_time_filters() {
    use conformance::metrics::regions::Region;
    use conformance::study::filtered::STUDY_FILTERS;
    use gpu_tracer::filter::FilterChain;
    let r = one_spp();
    let from = GOAL_FRAME as usize;
    for run in &r.runs {
        assert_eq!(run.filtered.len(), STUDY_FILTERS.len(), "{}", run.method.name());
        for f in &run.filtered {
            assert_eq!(
                f.regions.len(),
                FRAMES as usize,
                "{} {}",
                run.method.name(),
                f.chain
            );
            assert_eq!(
                f.noise.len(),
                FRAMES as usize,
                "{} {}",
                run.method.name(),
                f.chain
            );
        }
    }
    let white = r.run(Method::White).unwrap();
    let pixels = (SIZE * SIZE) as f64;
    let filtered_rms = |c: FilterChain| {
        let e = &white.filtered(c).unwrap().regions[from..];
        (e.iter().map(|v| v.iter().sum::<f64>()).sum::<f64>() / (e.len() as f64 * pixels)).sqrt()
    };
    let raw_rms =
        (white.rmse[from..].iter().map(|v| v * v).sum::<f64>() / (FRAMES as usize - from) as f64).sqrt();
    let head = FilterChain::TaaAtrous;
    let taa_bias = r.filter_bias(FilterChain::Taa, None, from).unwrap();
    let atrous_bias = r.filter_bias(FilterChain::Atrous, None, from).unwrap();
    println!(
        "white RMSE raw {raw_rms:.4}, after taa {:.4}, atrous {:.4}, taa+atrous {:.4}; bias (white = 1) taa {taa_bias:.2e}, atrous {atrous_bias:.3}",
        filtered_rms(FilterChain::Taa),
        filtered_rms(FilterChain::Atrous),
        filtered_rms(head)
    );
    for c in STUDY_FILTERS {
        assert!(
            filtered_rms(c) < raw_rms,
            "{c} does not lower white noise's error"
        );
    }
    assert!(taa_bias < 1e-3, "TAA changes a still reference: {taa_bias}");
    assert!(
        atrous_bias > 0.01,
        "the a-trous filter should blur some detail: {atrous_bias}"
    );
    println!("{}", r.filtered_markdown(from));
    let pj = r
        .pooled_filtered_noise(Method::PermuteJitter, head, Some(Region::Interior), from)
        .unwrap();
    assert!(
        pj < 1.0,
        "permute-jitter's noise part after {head} on the interior is not below white's: {pj}"
    );
}

/// Issue 15's rendered goal: after `taa+atrous` the best method's RMSE is at
/// most 0.75 of white's on the whole image and on the interior, and no
/// method is more than 2% worse than white. Missed: the whole image is met
/// since the a-trous passes the lights' silhouettes through (0.63 at CI size;
/// QUALITY.md, "The filter passes the lights' silhouettes through"), the
/// interior (about 0.8 at this size, 0.70 at 256x256) and the 2% are not (the
/// sort-only and walk permutation rows are white or worse in time).
#[test]
#[ignore = "issue 15 goal not met (see QUALITY.md); run with --ignored"]
fn best_method_after_taa_atrous_is_at_most_three_quarters_of_white() {
    use conformance::metrics::regions::Region;
    use gpu_tracer::filter::FilterChain;
    let r = one_spp();
    let from = GOAL_FRAME as usize;
    let head = FilterChain::TaaAtrous;
    for region in [None, Some(Region::Interior)] {
        let best = METHODS[1..]
            .iter()
            .filter_map(|&m| r.pooled_filtered(m, head, region, from))
            .fold(f64::INFINITY, f64::min);
        println!("{region:?}: best after {head} {best:.3} (goal <= 0.75)");
        assert!(best <= 0.75, "{region:?}: best {best:.3}");
    }
    for &m in &METHODS[1..] {
        let v = r.pooled_filtered(m, head, None, from).unwrap();
        assert!(v <= 1.02, "{} after {head}: {v:.3} of white", m.name());
    }
}

/// Issue 14's textured-scene goal, at this file's CI size: the flat-inset LF of the
/// feature-aware permutation (demodulated keys) on the checker-textured glTF Cornell
/// box is within 1.2x of the same on its untextured twin. Missed (QUALITY.md, "The
/// textured scene and the sort keys": 2.87x at 256x256; about 1.5x here): at texel
/// edges the estimate follows the pixel's jitter across a 15:1 albedo step, and that
/// part of the error stays with the pixel when its seed moves.
#[test]
#[ignore = "issue 14 textured-scene goal not met (see QUALITY.md); run with --ignored"]
fn textured_inset_lf_is_within_1_2x_of_the_untextured_twin() {
    use conformance::study::StudyScene;
    let from = GOAL_FRAME as usize;
    let mut lf = Vec::new();
    for scene in [StudyScene::CornellTextured, StudyScene::CornellUntextured] {
        let config = StudyConfig {
            scene,
            filters: false,
            ..StudyConfig::new(SIZE, 1, 48, 128)
        };
        let study = Study::new(config, Some(&default_cache_dir()), |_, _| {}).expect("study setup");
        let r = study
            .run(&[Method::White, Method::FeaturePermute], |_, _| {})
            .expect("study run");
        let frames = r.run(Method::White).unwrap().lf_insets.len();
        let mean = (from..frames)
            .map(|i| {
                r.relative(Method::FeaturePermute, Metric::LowFrequency, i)
                    .unwrap()
            })
            .sum::<f64>()
            / (frames - from) as f64;
        let demodulated = r.lf_demodulated_mean(Method::FeaturePermute, from).unwrap();
        println!(
            "{}: feature-permute LF mean {mean:.3}, with the albedo divided out {demodulated:.3}",
            scene.name()
        );
        lf.push(mean);
    }
    let ratio = lf[0] / lf[1];
    println!("textured / untextured: {ratio:.2} (goal <= 1.2)");
    assert!(ratio <= 1.2, "textured / untextured LF {ratio:.2}");
}

/// `StudyConfig::modulate_by` (`conformance study --modulate-by`): each inset's error
/// multiplied by another scene's albedo over the rendered one's. Modulated by the scene
/// itself (a ratio of 1 at every pixel) it is the plain LF; by the textured box it is
/// not; a room seen by another camera is refused. (What it measures at full size:
/// QUALITY.md, "Filtered textures".)
#[test]
fn the_modulated_lf_is_the_error_times_the_albedo_ratio() {
    use conformance::study::StudyScene;
    let frames = 10;
    let config = |scene, modulate_by| StudyConfig {
        scene,
        modulate_by: Some(modulate_by),
        filters: false,
        ..StudyConfig::new(64, 1, frames, 16)
    };
    let run = |modulate_by| {
        let study = Study::new(
            config(StudyScene::CornellUntextured, modulate_by),
            Some(&default_cache_dir()),
            |_, _| {},
        )
        .expect("study setup");
        study
            .run(&[Method::White, Method::Permute], |_, _| {})
            .expect("study run")
    };
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let itself = run(StudyScene::CornellUntextured);
    let textured = run(StudyScene::CornellTextured);
    let mut differs = 0.0f64;
    for m in [Method::White, Method::Permute] {
        let (a, b) = (itself.run(m).unwrap(), textured.run(m).unwrap());
        assert_eq!(a.lf_modulated.len(), frames as usize, "{}", m.name());
        for (t, (lf, modulated)) in a.lf_insets.iter().zip(&a.lf_modulated).enumerate() {
            assert!(
                (mean(lf) - modulated).abs() <= 1e-12 * mean(lf).abs().max(1.0),
                "{} frame {t}: modulated by itself {modulated} against {}",
                m.name(),
                mean(lf)
            );
        }
        for (lf, modulated) in b.lf_insets.iter().zip(&b.lf_modulated) {
            differs = differs.max((mean(lf) - modulated).abs() / mean(lf));
        }
    }
    println!(
        "modulated by the checker: LF moves by up to {:.1}%",
        100.0 * differs
    );
    assert!(
        differs > 0.01,
        "the checker did not change the modulated LF: {differs}"
    );
    let refused = Study::new(
        config(StudyScene::Cornell, StudyScene::CornellTextured),
        None,
        |_, _| {},
    );
    let why = refused
        .expect_err("another room's albedo was accepted")
        .to_string();
    assert!(why.contains("modulate_by"), "{why}");
}

/// The feature-aware permutation against the temporal target, with ZSobol's
/// jitter (`--mode temporal --features on --sampler zsobol-jitter`), on the
/// held-out textured box: the feature-aware sort keeps the flat walls' low
/// frequencies that the plain temporal permutation loses on the texture, and
/// the history's gain stays. At 256x256 with 128 frames (QUALITY.md, "The
/// feature-aware permutation with the temporal target"): LF 0.468 against
/// 0.871, EMA interior 0.922 against 0.974, EMA whole 0.597 for both; at
/// this size (128x128, 48 frames, 2026-11-27) LF 0.706 against 0.897, EMA
/// interior 0.870 against 0.968, EMA whole 0.692.
#[test]
fn the_feature_aware_temporal_permutation_keeps_textured_walls_blue() {
    use conformance::metrics::regions::Region;
    use conformance::study::{HistoryMetric, StudyScene};
    let config = StudyConfig {
        scene: StudyScene::CornellTextured,
        filters: false,
        ..StudyConfig::new(SIZE, 1, 48, 128)
    };
    let study = Study::new(config, Some(&default_cache_dir()), |_, _| {}).expect("study setup");
    let (plain, featured) = (
        Method::TemporalPermuteJitter,
        Method::FeatureTemporalPermuteJitter,
    );
    let r = study
        .run(&[Method::White, plain, featured], |_, _| {})
        .expect("study run");
    let from = GOAL_FRAME as usize;
    let frames = r.run(Method::White).unwrap().lf_insets.len();
    let lf = |m| {
        (from..frames)
            .map(|i| rel(&r, m, Metric::LowFrequency, i))
            .sum::<f64>()
            / (frames - from) as f64
    };
    let ema = |m, region| r.pooled_history(m, HistoryMetric::Ema, region).expect("measured");
    let (lf_plain, lf_featured) = (lf(plain), lf(featured));
    let (interior_plain, interior_featured) = (
        ema(plain, Some(Region::Interior)),
        ema(featured, Some(Region::Interior)),
    );
    let whole = ema(featured, None);
    println!(
        "textured box: flat-inset LF {lf_featured:.3} with features, {lf_plain:.3} without; EMA interior \
         {interior_featured:.3} / {interior_plain:.3}; EMA whole {whole:.3} (white = 1)"
    );
    assert!(
        lf_featured <= 0.85 * lf_plain,
        "LF {lf_featured:.3} with features against {lf_plain:.3}"
    );
    assert!(
        interior_featured <= interior_plain + 0.01,
        "EMA interior {interior_featured:.3} with features against {interior_plain:.3}"
    );
    assert!(
        whole <= 0.8,
        "after the EMA the whole image reads {whole:.3} of white"
    );
}

/// Issue 29: what a history keeps. The spatiotemporal sampler (each pixel one
/// progressive sequence across frames) is the row whose error survives an
/// exponential history (EMA alpha 0.1, no clamp, still camera) clearly below
/// white's, and whose mean over frames converges faster than white's. Measured
/// at this size (2026-11-26): EMA whole 0.646, interior 0.868; EMA + Gaussian
/// whole 0.565; mean of 32 frames whole 0.431 (QUALITY.md, "Blue in time",
/// has the full-size figures and the goals it does not reach yet).
#[test]
fn the_spatiotemporal_sampler_keeps_less_error_in_a_history() {
    use conformance::metrics::regions::Region;
    use conformance::study::HistoryMetric;
    let r = one_spp();
    println!("{}", r.temporal_markdown());
    let m = Method::Spatiotemporal;
    let ema = |region| r.pooled_history(m, HistoryMetric::Ema, region).expect("measured");
    let (whole, interior) = (ema(None), ema(Some(Region::Interior)));
    let blurred = r
        .pooled_history(m, HistoryMetric::EmaBlur1, None)
        .expect("measured");
    let mean32 = r.accumulated_region(m, 32, None).expect("measured");
    let mean64 = r.accumulated_region(m, 64, None).expect("measured");
    println!(
        "spatiotemporal: EMA whole {whole:.3}, interior {interior:.3}; EMA + G1 whole {blurred:.3}; \
         mean of 32 frames {mean32:.3}, of 64 {mean64:.3} (white = 1)"
    );
    assert!(
        whole <= 0.75,
        "after the EMA the whole image reads {whole:.3} of white"
    );
    assert!(
        interior <= 0.95,
        "after the EMA the interior reads {interior:.3} of white"
    );
    assert!(
        blurred <= 0.70,
        "after the EMA and a blur the whole image reads {blurred:.3} of white"
    );
    assert!(
        mean32 <= 0.60 && mean64 <= 0.60,
        "means of 32 / 64 frames: {mean32:.3} / {mean64:.3}"
    );
    // White noise's own history keeps alpha / (2 - alpha) of its per-frame
    // variance: the metric itself is checked against that in `study::history`.
}

/// A history's sliding window wants every window of consecutive frames well
/// spread: the Kronecker sequence keeps less error after the EMA than the
/// Sobol one, on the whole image and in the interior. Measured at this size
/// (2026-11-26): EMA whole 0.573 against 0.646, interior 0.825 against
/// 0.868; mean of 32 frames 0.493 against 0.431 (QUALITY.md, "Blue in
/// time", has the full-size figures).
#[test]
fn a_kronecker_sequence_in_time_keeps_less_error_in_a_history() {
    use conformance::metrics::regions::Region;
    use conformance::study::HistoryMetric;
    let r = one_spp();
    let ema = |m, region| r.pooled_history(m, HistoryMetric::Ema, region).expect("measured");
    let (sobol, kronecker) = (Method::Spatiotemporal, Method::SpatiotemporalKronecker);
    let whole = (ema(sobol, None), ema(kronecker, None));
    let interior = (
        ema(sobol, Some(Region::Interior)),
        ema(kronecker, Some(Region::Interior)),
    );
    let mean32 = r.accumulated_region(kronecker, 32, None).expect("measured");
    println!(
        "EMA whole Sobol {:.3} / Kronecker {:.3}; interior {:.3} / {:.3}; Kronecker mean of 32 frames {mean32:.3}",
        whole.0, whole.1, interior.0, interior.1
    );
    assert!(
        whole.1 <= 0.95 * whole.0,
        "EMA whole {whole:?} (Sobol, Kronecker)"
    );
    assert!(
        interior.1 < interior.0,
        "EMA interior {interior:?} (Sobol, Kronecker)"
    );
    assert!(mean32 <= 0.60, "Kronecker mean of 32 frames {mean32:.3}");
}

/// The spatiotemporal sampler shifts its pixel jitter by a 2D net (ZSobol's
/// one-sample points, `sampler_core::sequences::spatiotemporal::net_shift_u32`)
/// instead of two scalar reads of the blue-noise tile: neighbours' jitters are
/// stratified jointly, so each frame's error at the silhouettes is bluer.
/// Measured at this size (2026-11-29): raw blur whole 0.806 (Sobol) / 0.816
/// (Kronecker) against 0.906 / 0.904 with the tile's shifts (the Kronecker row
/// over three draws of each kind of shift: 0.770-0.816 against 0.852-0.904);
/// behind the history the two kinds of shift read alike within the scatter of
/// their draws (QUALITY.md, "The jitter's shifts: a net").
#[test]
fn the_spatiotemporal_samplers_frames_are_blue_at_the_silhouettes() {
    let r = one_spp();
    for m in [Method::Spatiotemporal, Method::SpatiotemporalKronecker] {
        let blur = r.pooled(m, Metric::Blur1, GOAL_FRAME as usize).expect("measured");
        println!("{}: raw blur whole {blur:.3} (white = 1)", m.name());
        assert!(blur <= 0.84, "{}: raw blurred error {blur:.3} of white", m.name());
    }
}

/// ZSobol's frames are digital shifts of one point set by a (0, 2)-sequence
/// (`sampler_core::zsobol_frame_sample_u32`): each frame keeps ZSobol's
/// blue-noise error (raw blur) and a pixel's frames converge as one
/// progressive net, so the history and the running means read far below
/// white. Re-randomised every frame (its first form) it read about 1 of white
/// on both (QUALITY.md, "Blue in time"). Measured at this size (2026-11-27):
/// raw blur whole 0.686, EMA whole 0.611, means of 8 / 32 / 64 frames 0.400 /
/// 0.354 / 0.350.
#[test]
fn zsobol_frames_converge_while_each_stays_blue() {
    use conformance::study::HistoryMetric;
    let r = one_spp();
    let m = Method::ZSobol;
    let blur = r.pooled(m, Metric::Blur1, GOAL_FRAME as usize).expect("measured");
    let ema = r.pooled_history(m, HistoryMetric::Ema, None).expect("measured");
    let means = running_means(r, m, &[8, 32, 64]);
    println!("zsobol: raw blur whole {blur:.3}, EMA whole {ema:.3}, means of 8 / 32 / 64 frames {means:.3?} (white = 1)");
    assert!(blur <= 0.80, "raw blurred error {blur:.3} of white");
    assert!(
        ema <= 0.75,
        "after the EMA the whole image reads {ema:.3} of white"
    );
    for (n, v) in [8, 32, 64].iter().zip(&means) {
        assert!(*v <= 0.70, "mean of {n} frames reads {v:.3} of white");
    }
}

/// The temporal permutation with ZSobol's jitter (`--mode temporal --sampler
/// zsobol-jitter`): the permutation's flat-wall gain per frame, the jitter's
/// blue-noise silhouettes, and both blue in time, so the history and the
/// running means read far below white. Measured at this size (2026-11-27, the
/// 64x64x64 target): raw blur whole 0.689, flat-inset LF 0.780, EMA whole
/// 0.617, means of 8 / 32 / 64 frames 0.408 / 0.376 / 0.372 (at 256x256 with
/// 128 frames, QUALITY.md: 0.778, 0.610, 0.626, 0.524 / 0.412).
#[test]
fn the_temporal_permutation_with_a_zsobol_jitter_is_blue_per_frame_and_in_time() {
    use conformance::study::HistoryMetric;
    let r = one_spp();
    let m = Method::TemporalPermuteJitter;
    let from = GOAL_FRAME as usize;
    let blur = r.pooled(m, Metric::Blur1, from).expect("measured");
    let n = r.run(m).expect("measured").lf_insets.len();
    let lf = (from..n).map(|i| rel(r, m, Metric::LowFrequency, i)).sum::<f64>() / (n - from) as f64;
    let ema = r.pooled_history(m, HistoryMetric::Ema, None).expect("measured");
    let means = running_means(r, m, &[8, 32, 64]);
    println!(
        "temporal-permute-jitter: raw blur whole {blur:.3}, flat-inset LF {lf:.3}, EMA whole {ema:.3}, \
         means of 8 / 32 / 64 frames {means:.3?} (white = 1)"
    );
    assert!(blur <= 0.85, "raw blurred error {blur:.3} of white");
    assert!(lf <= 0.85, "flat-inset LF {lf:.3} of white");
    assert!(
        ema <= 0.80,
        "after the EMA the whole image reads {ema:.3} of white"
    );
    for (n, v) in [8, 32, 64].iter().zip(&means) {
        assert!(*v <= 0.80, "mean of {n} frames reads {v:.3} of white");
    }
}

/// `m`'s error in the mean of its first `n` frames, whole image (white = 1), for
/// each `n` of `frames`.
fn running_means(r: &StudyResult, m: Method, frames: &[usize]) -> Vec<f64> {
    frames
        .iter()
        .map(|&n| r.accumulated_region(m, n, None).expect("measured"))
        .collect()
}

/// On the diffuse Cornell box no first hit is glossy: the interior's history
/// on diffuse first hits is the interior's history, the glossy split has no
/// pixel, and the study prints no table for it.
#[test]
fn the_diffuse_box_has_no_glossy_interior() {
    use conformance::metrics::regions::Region;
    use conformance::study::HistoryMetric;
    let r = one_spp();
    assert_eq!(r.glossy_interior_share, 0.0);
    assert!(r.surfaces_markdown().is_empty());
    assert_eq!(r.glossy_error_share(Method::White), Some(0.0));
    for m in [Method::Permute, Method::TemporalPermuteJitter] {
        let diffuse = r.history_by_surface(m, false).expect("measured");
        let interior = r
            .pooled_history(m, HistoryMetric::Ema, Some(Region::Interior))
            .expect("measured");
        println!(
            "{}: EMA interior {interior:.4}, on diffuse first hits {diffuse:.4}",
            m.name()
        );
        assert!((diffuse - interior).abs() < 1e-9, "{diffuse} vs {interior}");
        assert_eq!(r.history_by_surface(m, true), None);
    }
}
