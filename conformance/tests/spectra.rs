//! The measurement library reproduces the analytic white-noise baselines of
//! `shared/notes/quality.md` (within 3%, averaged over seeds), and tells white, blue-ish
//! (high-pass), low-pass and directional noise apart.
//!
//! Noise comes from `sampler_core::random_f32` with fixed seeds, so every figure is
//! deterministic; each test prints what it measured.

use conformance::{
    anisotropy_db, ema, ema_variance_factor, low_frequency_ratio, radial_power, stratified_thresholds,
    temporal_low_frequency_ratio, temporal_power, thresholded_ema_rms, thresholded_rms, white_noise_rms,
    GaussianBlur, Grid, SpectrumAnalyzer, Volume, DEFAULT_THRESHOLDS,
};
use sampler_core::random_f32;

/// Relative tolerance of every baseline check (issue 3: "within 3%").
const TOLERANCE: f64 = 0.03;

/// Side of the square test grids (the size quality.md's figures are for).
const SIDE: usize = 128;

/// Frames of the spatiotemporal test volumes (quality.md: 128x128x64).
const FRAMES: usize = 64;

/// i.i.d. uniform `[0, 1)` noise, `side x side`, stream `seed`.
fn white_grid(side: usize, seed: u32) -> Grid {
    Grid::from_fn(side, side, |x, y| random_f32(seed, (y * side + x) as u32)).unwrap()
}

/// i.i.d. uniform `[0, 1)` noise, `side x side x depth`, stream `seed`.
fn white_volume(side: usize, depth: usize, seed: u32) -> Volume {
    Volume::from_fn(side, side, depth, |x, y, z| {
        random_f32(seed, ((z * side + y) * side + x) as u32)
    })
    .unwrap()
}

fn relative_error(measured: f64, expected: f64) -> f64 {
    (measured / expected - 1.0).abs()
}

#[test]
fn thresholded_rms_of_white_noise_matches_sum_g2_over_6() {
    let thresholds = stratified_thresholds(DEFAULT_THRESHOLDS).unwrap();
    let seeds = 0..8u32;
    let grids: Vec<Grid> = seeds.clone().map(|s| white_grid(SIDE, 1000 + s)).collect();
    // (sigma, figure quoted in quality.md from the continuous 1 / (4 pi sigma^2)); None = unfiltered.
    let cases = [
        (None, 0.408),
        (Some(1.0), 0.1152),
        (Some(1.3435), 0.0857),
        (Some(1.5), 0.0768),
        (Some(1.9), 0.0606),
    ];
    for (sigma, quoted) in cases {
        let blur = sigma.map(|s| GaussianBlur::new(s).unwrap());
        // Expected from our own discrete kernel: sqrt(sum g^2 / 6), plus the stratified
        // thresholds' exact mean of t(1 - t), 1/6 + 1/(12 n^2).
        let n = DEFAULT_THRESHOLDS as f64;
        let g2 = blur.as_ref().map_or(1.0, GaussianBlur::sum_of_squares_2d);
        let expected = (g2 * (1.0 / 6.0 + 1.0 / (12.0 * n * n))).sqrt();
        let measured = grids
            .iter()
            .map(|g| thresholded_rms(g, blur.as_ref(), &thresholds).unwrap())
            .sum::<f64>()
            / grids.len() as f64;
        println!(
            "white thresholded RMS, sigma {sigma:?}: measured {measured:.5}, sqrt(sum g^2/6) {:.5}, quoted {quoted}",
            white_noise_rms(blur.as_ref())
        );
        assert!(
            relative_error(expected, quoted) < TOLERANCE,
            "kernel gives {expected}, quality.md {quoted}"
        );
        assert!(
            relative_error(measured, expected) < TOLERANCE,
            "measured {measured}, expected {expected}"
        );
    }
}

#[test]
fn ema_of_white_noise_scales_variance_by_alpha_over_2_minus_alpha() {
    let alpha = 0.1;
    let last = FRAMES - 1;
    let factor = ema_variance_factor(alpha, last);
    // quality.md: x0.229 RMS for alpha 0.1 (the steady state alpha / (2 - alpha)).
    println!(
        "EMA({alpha}) RMS factor at frame {last}: {:.5} (steady state {:.5})",
        factor.sqrt(),
        (alpha / (2.0 - alpha)).sqrt()
    );
    assert!(relative_error(factor.sqrt(), 0.229) < TOLERANCE);

    let volumes: Vec<Volume> = (0..2u32).map(|s| white_volume(SIDE, FRAMES, 2000 + s)).collect();
    // Plain EMA of the values: variance 1/12 * factor.
    let var = volumes
        .iter()
        .map(|v| ema(v, alpha, last).unwrap().variance())
        .sum::<f64>()
        / volumes.len() as f64;
    println!(
        "EMA({alpha}) variance of uniform noise: measured {var:.6}, expected {:.6}",
        factor / 12.0
    );
    assert!(relative_error(var, factor / 12.0) < TOLERANCE);

    let thresholds = stratified_thresholds(DEFAULT_THRESHOLDS).unwrap();
    let blur = GaussianBlur::new(1.3435).unwrap();
    for (b, quoted) in [(None, 0.093), (Some(&blur), 0.0857 * 0.229)] {
        let g2 = b.map_or(1.0, GaussianBlur::sum_of_squares_2d);
        let expected = (factor * g2 / 6.0).sqrt();
        let measured = volumes
            .iter()
            .map(|v| thresholded_ema_rms(v, alpha, last, b, &thresholds).unwrap())
            .sum::<f64>()
            / volumes.len() as f64;
        println!(
            "white EMA({alpha}) thresholded RMS at frame {last}, blur {:?}: measured {measured:.5}, expected {expected:.5}, quoted {quoted:.4}",
            b.map(GaussianBlur::sigma)
        );
        assert!(relative_error(expected, quoted) < TOLERANCE);
        assert!(
            relative_error(measured, expected) < TOLERANCE,
            "measured {measured}, expected {expected}"
        );
    }
}

#[test]
fn white_noise_has_unit_low_frequency_ratio() {
    let mut analyzer = SpectrumAnalyzer::new();
    let ratios: Vec<f64> = (0..32u32)
        .map(|s| low_frequency_ratio(&analyzer.power_spectrum(&white_grid(SIDE, 3000 + s))))
        .collect();
    let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
    let (lo, hi) = ratios
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &r| (a.min(r), b.max(r)));
    println!(
        "white LF ratio over {} seeds: mean {mean:.4}, range [{lo:.3}, {hi:.3}]",
        ratios.len()
    );
    assert!(relative_error(mean, 1.0) < TOLERANCE, "{mean}");

    // The radially averaged spectrum of white noise is flat at the variance 1/12.
    let radial = radial_power(&analyzer.power_spectrum(&white_grid(SIDE, 3100)));
    let inner: Vec<f64> = radial.mean()[1..=SIDE / 2].to_vec();
    let flat = inner.iter().sum::<f64>() / inner.len() as f64;
    println!(
        "white RAPS mean over r = 1..=64: {flat:.5} (variance 1/12 = {:.5})",
        1.0 / 12.0
    );
    assert!(relative_error(flat, 1.0 / 12.0) < TOLERANCE);
}

#[test]
fn white_noise_has_unit_temporal_low_frequency_ratio() {
    let mut analyzer = SpectrumAnalyzer::new();
    let ratios: Vec<f64> = (0..2u32)
        .map(|s| {
            temporal_low_frequency_ratio(&temporal_power(
                &mut analyzer,
                &white_volume(SIDE, FRAMES, 4000 + s),
            ))
        })
        .collect();
    let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
    println!("white temporal LF ratio (128x128x64): {ratios:.4?}, mean {mean:.4}");
    assert!(relative_error(mean, 1.0) < TOLERANCE, "{mean}");
}

/// `white - blur(white)` (high-pass), and `blur(white)` (low-pass), sigma 2.
fn filtered_pair(blur: &GaussianBlur, seed: u32) -> (Grid, Grid) {
    let white = white_grid(SIDE, seed);
    let low = blur.apply(&white);
    let high = Grid::from_fn(SIDE, SIDE, |x, y| white.get(x, y) - low.get(x, y)).unwrap();
    (high, low)
}

/// Expected LF ratio of white noise through a filter of squared response `h2(kx, ky)`
/// (signed DFT indices): every bin's expected power is `s^2 |H|^2`, so the ratio is the
/// mean of `|H|^2` over the LF disc divided by its mean over all non-DC bins.
fn filtered_lf_ratio(h2: impl Fn(i64, i64) -> f64) -> f64 {
    let n = SIDE as i64;
    let (mut low, mut n_low, mut all) = (0.0, 0usize, 0.0);
    for ky in -n / 2..n / 2 {
        for kx in -n / 2..n / 2 {
            if kx == 0 && ky == 0 {
                continue;
            }
            let p = h2(kx, ky);
            all += p;
            if ((kx * kx + ky * ky) as f64).sqrt() / SIDE as f64 <= conformance::LOW_FREQUENCY_CUTOFF {
                low += p;
                n_low += 1;
            }
        }
    }
    (low / n_low as f64) / (all / (SIDE * SIDE - 1) as f64)
}

#[test]
fn metrics_tell_high_pass_from_low_pass() {
    let mut analyzer = SpectrumAnalyzer::new();
    let thresholds = stratified_thresholds(DEFAULT_THRESHOLDS).unwrap();
    let blur = GaussianBlur::new(1.0).unwrap();
    let wide = GaussianBlur::new(2.0).unwrap();
    // Frequency response of the discrete 1D kernel at signed index k: sum_i g_i cos(2 pi k i / N).
    let r = (wide.taps().len() / 2) as i64;
    let response = |k: i64| -> f64 {
        let w = std::f64::consts::TAU * k as f64 / SIDE as f64;
        wide.taps()
            .iter()
            .enumerate()
            .map(|(j, &g)| g as f64 * (w * (j as i64 - r) as f64).cos())
            .sum()
    };
    let expected_low = filtered_lf_ratio(|kx, ky| (response(kx) * response(ky)).powi(2));
    let expected_high = filtered_lf_ratio(|kx, ky| (1.0 - response(kx) * response(ky)).powi(2));
    let pairs: Vec<(Grid, Grid)> = (0..8u32).map(|s| filtered_pair(&wide, 5000 + s)).collect();
    let mean_lf = |pick: fn(&(Grid, Grid)) -> &Grid, analyzer: &mut SpectrumAnalyzer| {
        pairs
            .iter()
            .map(|p| low_frequency_ratio(&analyzer.power_spectrum(pick(p))))
            .sum::<f64>()
            / pairs.len() as f64
    };
    let lf_high = mean_lf(|p| &p.0, &mut analyzer);
    let lf_low = mean_lf(|p| &p.1, &mut analyzer);
    println!("LF ratio: high-pass {lf_high:.4} (expected {expected_high:.4}), low-pass {lf_low:.2} (expected {expected_low:.2})");
    assert!(
        expected_high < 0.5 && expected_low > 4.0,
        "the filters must be far from white"
    );
    // Averaged over 8 seeds.
    assert!(
        relative_error(lf_high, expected_high) < TOLERANCE,
        "{lf_high} vs {expected_high}"
    );
    assert!(
        relative_error(lf_low, expected_low) < TOLERANCE,
        "{lf_low} vs {expected_low}"
    );
    let (high, low) = &pairs[0];

    // A mask whose values are ranked like high-pass noise dithers better than white; one
    // ranked like low-pass noise worse (ranks make the value histogram uniform again).
    let rank = |g: &Grid| {
        let mut order: Vec<usize> = (0..g.data().len()).collect();
        order.sort_by(|&a, &b| g.data()[a].total_cmp(&g.data()[b]));
        let mut ranks = vec![0u32; order.len()];
        for (r, &i) in order.iter().enumerate() {
            ranks[i] = r as u32;
        }
        Grid::from_ranks(g.width(), g.height(), &ranks).unwrap()
    };
    let white_rms = white_noise_rms(Some(&blur));
    let rms_high = thresholded_rms(&rank(high), Some(&blur), &thresholds).unwrap();
    let rms_low = thresholded_rms(&rank(low), Some(&blur), &thresholds).unwrap();
    println!("blur-1.0 thresholded RMS: ranked high-pass {rms_high:.4}, ranked low-pass {rms_low:.4}, white {white_rms:.4}");
    assert!(rms_high < 0.9 * white_rms && rms_low > 1.5 * white_rms);
}

#[test]
fn anisotropy_separates_directional_noise() {
    let mut analyzer = SpectrumAnalyzer::new();
    let seeds = 6000..6008u32;
    let white: Vec<f64> = seeds
        .clone()
        .map(|s| anisotropy_db(&analyzer.power_spectrum(&white_grid(SIDE, s))))
        .collect();
    // Box-average 4 neighbours along x only: power falls along kx, not along ky.
    let streaks: Vec<f64> = seeds
        .map(|s| {
            let w = white_grid(SIDE, s);
            let g = Grid::from_fn(SIDE, SIDE, |x, y| {
                (0..4).map(|i| w.get((x + i) % SIDE, y)).sum::<f32>() / 4.0
            })
            .unwrap();
            anisotropy_db(&analyzer.power_spectrum(&g))
        })
        .collect();
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    println!(
        "anisotropy: white {:.2} dB (per seed {white:.2?}), x-streaked {:.2} dB",
        mean(&white),
        mean(&streaks)
    );
    // White noise is isotropic: its figure is the periodogram's estimation noise, well below 0 dB.
    assert!(mean(&white) < -3.0);
    assert!(mean(&streaks) > mean(&white) + 6.0);
}

#[test]
fn size_mismatches_are_errors() {
    let blur = GaussianBlur::new(1.0).unwrap();
    let src = Grid::zeros(8, 8).unwrap();
    let mut tmp = Grid::zeros(8, 4).unwrap();
    let mut dst = Grid::zeros(8, 8).unwrap();
    let err = blur.apply_into(&src, &mut tmp, &mut dst).unwrap_err();
    println!("{err}");
    assert!(matches!(
        err,
        conformance::Error::ShapeMismatch {
            expected: [8, 8, 1],
            actual: [8, 4, 1]
        }
    ));
    let v = white_volume(8, 4, 1);
    assert!(matches!(
        thresholded_ema_rms(&v, 0.1, 4, None, &[0.5]),
        Err(conformance::Error::FrameIndex { .. })
    ));
    assert!(matches!(
        thresholded_ema_rms(&v, 1.5, 3, None, &[0.5]),
        Err(conformance::Error::Parameter { .. })
    ));
}
