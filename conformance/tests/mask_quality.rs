//! Issue 3's quality targets for the baked blue-noise masks, measured with the metrics of
//! `shared/notes/quality.md` (validated against white-noise baselines in `spectra.rs`).
//!
//! Targets (issue 3, "Quality targets"):
//! - 2D 128x128, void-and-cluster sigma 1.5 (baked here; the default tiles' sigma may
//!   differ, see `MAX_RMS_BLUR_1_OTHER_SIGMA`): low-frequency power <= 0.001 of white;
//!   thresholded-mask RMS after a Gaussian blur of sigma 1.0 <= 0.040 (white 0.115);
//!   anisotropy <= -5 dB.
//! - Spatiotemporal 128x128x64: per-slice low-frequency power <= 0.005 (mean over slices);
//!   temporal low-frequency power <= 0.05; EMA(0.1)-only thresholded RMS at frame 63
//!   <= 0.045; EMA(0.1) + Gaussian 1.3435 at frame 63 <= 0.0050.
//!
//! Issue 15 (filter-adapted masks), for the default filter-adapted 128x128x64 mask
//! (`defaults::filter_adapted_128`): EMA(0.1) + Gaussian 1.3435 at frame 63 <= 0.0036;
//! per-slice low-frequency power <= 0.005. And a mask adapted to a 3x3 box and an 8-frame
//! box must beat the Gaussian-adapted masks of the same size on that filter's own metric.
//!
//! Every test prints its figures so CI logs record them (`cargo test -- --nocapture`).

use conformance::{
    anisotropy_db, low_frequency_ratio, slice_low_frequency_ratios, stratified_thresholds,
    temporal_low_frequency_ratio, temporal_power, thresholded_ema_rms, thresholded_rms, white_noise_rms,
    GaussianBlur, Grid, SpectrumAnalyzer, Volume, DEFAULT_THRESHOLDS,
};
use sampler_core::bake::{
    bake_filter_adapted, bake_mask, no_progress, FilterAdaptedParams, MaskParams, SpatialFilter,
    TemporalFilter,
};
use sampler_core::{defaults, random_f32, DitherTile, SpatiotemporalMask};

/// Issue 3: 2D low-frequency power, fraction of white noise's.
const MAX_LF_2D: f64 = 0.001;
/// Issue 3: thresholded-mask RMS after a Gaussian blur of sigma 1.0, sigma-1.5 mask.
const MAX_RMS_BLUR_1: f64 = 0.040;
/// Issue 3: anisotropy in dB (see `conformance::anisotropy_db` for the definition).
const MAX_ANISOTROPY_DB: f64 = -5.0;
/// Quality.md's reference figure for a void-and-cluster mask of sigma 1.9 after a
/// sigma-1.0 blur is 0.0444: issue 3 sets 0.040 only for sigma 1.5, so masks of another
/// sigma (the default tiles use 1.9, see `sampler_core::defaults`) are held to the
/// reference figure, rounded up to 0.045.
const MAX_RMS_BLUR_1_OTHER_SIGMA: f64 = 0.045;

/// Issue 3: spatiotemporal per-slice low-frequency power (mean over slices).
const MAX_LF_SLICE: f64 = 0.005;
/// Issue 3: temporal low-frequency power (`k <= D/8`).
const MAX_LF_TEMPORAL: f64 = 0.05;
/// Issue 3: EMA(0.1)-only thresholded RMS at frame 63.
const MAX_RMS_EMA: f64 = 0.045;
/// Issue 3: EMA(0.1) + Gaussian 1.3435 thresholded RMS at frame 63.
const MAX_RMS_EMA_BLUR: f64 = 0.0050;
/// EMA factor of the temporal targets (quality.md, FAST).
const ALPHA: f64 = 0.1;
/// Filter sigma matching an energy sigma of 1.9 (1.9 / sqrt 2, quality.md).
const SIGMA_STBN_FILTER: f64 = 1.3435;

/// The three 2D figures of a mask.
#[derive(Debug)]
struct Figures {
    low_frequency: f64,
    rms_blur_1: f64,
    anisotropy_db: f64,
}

fn measure(mask: &Grid) -> Figures {
    let spectrum = SpectrumAnalyzer::new().power_spectrum(mask);
    let thresholds = stratified_thresholds(DEFAULT_THRESHOLDS).unwrap();
    let blur = GaussianBlur::new(1.0).unwrap();
    Figures {
        low_frequency: low_frequency_ratio(&spectrum),
        rms_blur_1: thresholded_rms(mask, Some(&blur), &thresholds).unwrap(),
        anisotropy_db: anisotropy_db(&spectrum),
    }
}

fn tile_grid(tile: &DitherTile<'_>) -> Grid {
    let w = tile.tile() as usize;
    Grid::from_ranks(w, w, tile.values()).unwrap()
}

/// Checks `figures` against the 2D targets; `rms_limit` depends on the mask's sigma and
/// `anisotropy_limit` on its size.
fn check_2d(name: &str, f: &Figures, rms_limit: f64, anisotropy_limit: f64) {
    let white = white_noise_rms(Some(&GaussianBlur::new(1.0).unwrap()));
    println!(
        "{name}: LF {:.5} (<= {MAX_LF_2D}), blur-1.0 RMS {:.4} (<= {rms_limit}, white {white:.4}), anisotropy {:.2} dB (<= {anisotropy_limit:.2})",
        f.low_frequency, f.rms_blur_1, f.anisotropy_db
    );
    assert!(f.low_frequency <= MAX_LF_2D, "{name}: LF {}", f.low_frequency);
    assert!(f.rms_blur_1 <= rms_limit, "{name}: blur-1.0 RMS {}", f.rms_blur_1);
    assert!(
        f.anisotropy_db <= anisotropy_limit,
        "{name}: anisotropy {} dB",
        f.anisotropy_db
    );
}

#[test]
fn baked_128_sigma_1_5_mask_meets_targets() {
    let params = MaskParams {
        width: 128,
        height: 128,
        sigma: 1.5,
        seed: 1,
    };
    let ranks = bake_mask(&params, &mut no_progress).unwrap();
    let grid = Grid::from_ranks(128, 128, &ranks).unwrap();
    check_2d(
        "baked 128x128 sigma 1.5 (seed 1)",
        &measure(&grid),
        MAX_RMS_BLUR_1,
        MAX_ANISOTROPY_DB,
    );
}

/// Anisotropy limit for a `side x side` mask other than 128x128, where issue 3's -5 dB
/// does not apply: the periodogram's estimation noise sets anisotropy's floor, and it
/// grows as the grid shrinks (white noise: about -6 dB at 128x128, -4.3 dB at 64x64). A
/// mask passes when it is no more anisotropic than white noise of its size, at three
/// standard deviations of white noise's spread over 16 seeds.
fn white_anisotropy_limit(side: usize) -> f64 {
    let mut analyzer = SpectrumAnalyzer::new();
    let figures: Vec<f64> = (0..16u32)
        .map(|seed| {
            let g = Grid::from_fn(side, side, |x, y| random_f32(7000 + seed, (y * side + x) as u32)).unwrap();
            anisotropy_db(&analyzer.power_spectrum(&g))
        })
        .collect();
    let n = figures.len() as f64;
    let mean = figures.iter().sum::<f64>() / n;
    let std = (figures.iter().map(|f| (f - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    println!("white noise {side}x{side}: anisotropy {mean:.2} dB +- {std:.2} dB");
    mean + 3.0 * std
}

#[test]
fn default_tiles_meet_targets() {
    for (name, tile) in [
        ("default tile 64", defaults::tile_64()),
        ("default tile 128", defaults::tile_128()),
    ] {
        let grid = tile_grid(&tile);
        // Every rank once, so each thresholded mask has exactly the density t.
        let mut sorted = tile.values().to_vec();
        sorted.sort_unstable();
        assert!(
            sorted.iter().enumerate().all(|(i, &r)| r == i as u32),
            "{name} is not a permutation of ranks"
        );
        let side = grid.width();
        let anisotropy_limit = if side == 128 {
            MAX_ANISOTROPY_DB
        } else {
            white_anisotropy_limit(side)
        };
        check_2d(
            name,
            &measure(&grid),
            MAX_RMS_BLUR_1_OTHER_SIGMA,
            anisotropy_limit,
        );
    }
}

fn mask_volume(mask: &SpatiotemporalMask<'_>) -> Volume {
    Volume::from_fn(
        mask.width() as usize,
        mask.height() as usize,
        mask.depth() as usize,
        |x, y, z| mask.value(x as u32, y as u32, z as u32),
    )
    .unwrap()
}

#[test]
fn default_spatiotemporal_mask_meets_targets() {
    let mask = defaults::stbn_128();
    assert_eq!((mask.width(), mask.height(), mask.depth()), (128, 128, 64));
    let volume = mask_volume(&mask);
    let mut analyzer = SpectrumAnalyzer::new();

    let slices = slice_low_frequency_ratios(&mut analyzer, &volume).unwrap();
    let mean_slice = slices.iter().sum::<f64>() / slices.len() as f64;
    let max_slice = slices.iter().cloned().fold(f64::MIN, f64::max);
    let temporal = temporal_low_frequency_ratio(&temporal_power(&mut analyzer, &volume));
    let thresholds = stratified_thresholds(DEFAULT_THRESHOLDS).unwrap();
    let last = volume.depth() - 1;
    let blur = GaussianBlur::new(SIGMA_STBN_FILTER).unwrap();
    let rms_ema = thresholded_ema_rms(&volume, ALPHA, last, None, &thresholds).unwrap();
    let rms_ema_blur = thresholded_ema_rms(&volume, ALPHA, last, Some(&blur), &thresholds).unwrap();
    println!(
        "default STBN 128x128x64: per-slice LF mean {mean_slice:.5} (max {max_slice:.5}, <= {MAX_LF_SLICE}), \
         temporal LF {temporal:.4} (<= {MAX_LF_TEMPORAL}), EMA({ALPHA}) RMS at frame {last} {rms_ema:.4} \
         (<= {MAX_RMS_EMA}), EMA + blur {SIGMA_STBN_FILTER} {rms_ema_blur:.5} (<= {MAX_RMS_EMA_BLUR})"
    );
    assert!(mean_slice <= MAX_LF_SLICE, "per-slice LF {mean_slice}");
    assert!(temporal <= MAX_LF_TEMPORAL, "temporal LF {temporal}");
    assert!(rms_ema <= MAX_RMS_EMA, "EMA RMS {rms_ema}");
    assert!(rms_ema_blur <= MAX_RMS_EMA_BLUR, "EMA + blur RMS {rms_ema_blur}");
}

/// Issue 15: EMA(0.1) + Gaussian 1.3435 thresholded RMS at frame 63 of the filter-adapted
/// default (FAST publishes 0.0038, STBN 0.0051).
const MAX_RMS_EMA_BLUR_ADAPTED: f64 = 0.0036;

/// Thresholded-mask RMS after a causal temporal filter ending at the last slice and a
/// separable toroidal spatial filter: for each threshold `t`, the errors `[v_z < t] - t`
/// are summed with `temporal[k]` weighing the `k`-th slice back from the last, filtered
/// with `spatial` (odd length, centred) along rows and columns; the mean square over
/// pixels and thresholds is rooted (the definition of `conformance::metrics::threshold`). Checked
/// against `thresholded_ema_rms` for the EMA and a Gaussian in
/// `filter_adapted_default_meets_targets`.
fn filtered_threshold_rms(volume: &Volume, temporal: &[f64], spatial: &[f64], thresholds: &[f32]) -> f64 {
    let (w, h, d) = (volume.width(), volume.height(), volume.depth());
    let r = spatial.len() / 2;
    let mut total = 0.0;
    for &t in thresholds {
        let mut acc = vec![0.0f64; w * h];
        for (k, &g) in temporal.iter().enumerate().take(d) {
            for (a, &v) in acc.iter_mut().zip(volume.slice_data(d - 1 - k).unwrap()) {
                *a += g * if v < t { 1.0 - t as f64 } else { -(t as f64) };
            }
        }
        let pass = |src: &[f64], step: (usize, usize)| -> Vec<f64> {
            let mut out = vec![0.0; w * h];
            for y in 0..h {
                for x in 0..w {
                    let mut a = 0.0;
                    for (j, &g) in spatial.iter().enumerate() {
                        let o = j + w.max(h) * 4 - r;
                        let (xx, yy) = ((x + o * step.0) % w, (y + o * step.1) % h);
                        a += g * src[yy * w + xx];
                    }
                    out[y * w + x] = a;
                }
            }
            out
        };
        let blurred = pass(&pass(&acc, (1, 0)), (0, 1));
        total += blurred.iter().map(|v| v * v).sum::<f64>() / (w * h) as f64;
    }
    (total / thresholds.len() as f64).sqrt()
}

/// EMA weights of slices back from frame `last` (`a_0 = v_0`), as `thresholded_ema_rms`.
fn ema_weights(alpha: f64, last: usize) -> Vec<f64> {
    (0..=last)
        .map(|k| {
            if k < last {
                alpha * (1.0 - alpha).powi(k as i32)
            } else {
                (1.0 - alpha).powi(k as i32)
            }
        })
        .collect()
}

/// The default filter-adapted mask: EMA + blur at frame 63 (and at 61 thresholds, to show
/// it is not fitted to the 64 of the metric), per-slice and temporal LF, against the
/// default STBN mask.
#[test]
fn filter_adapted_default_meets_targets() {
    let thresholds = stratified_thresholds(DEFAULT_THRESHOLDS).unwrap();
    let other = stratified_thresholds(61).unwrap();
    let blur = GaussianBlur::new(SIGMA_STBN_FILTER).unwrap();
    let mut analyzer = SpectrumAnalyzer::new();
    let mut figures = Vec::new();
    for (name, mask) in [
        ("filter-adapted", defaults::filter_adapted_128()),
        ("STBN", defaults::stbn_128()),
    ] {
        let volume = mask_volume(&mask);
        let last = volume.depth() - 1;
        let rms = thresholded_ema_rms(&volume, ALPHA, last, Some(&blur), &thresholds).unwrap();
        let rms_61 = thresholded_ema_rms(&volume, ALPHA, last, Some(&blur), &other).unwrap();
        let ema_only = thresholded_ema_rms(&volume, ALPHA, last, None, &thresholds).unwrap();
        let slices = slice_low_frequency_ratios(&mut analyzer, &volume).unwrap();
        let mean_slice = slices.iter().sum::<f64>() / slices.len() as f64;
        let temporal = temporal_low_frequency_ratio(&temporal_power(&mut analyzer, &volume));
        println!(
            "default {name} 128x128x64: EMA({ALPHA}) + blur {SIGMA_STBN_FILTER} at frame {last} {rms:.5} \
             (61 thresholds {rms_61:.5}), EMA only {ema_only:.4}, per-slice LF {mean_slice:.5}, temporal LF {temporal:.4}"
        );
        figures.push((rms, rms_61, mean_slice));
        if name == "STBN" {
            // The generic filter of the box comparison below agrees with the library's EMA + blur.
            let taps: Vec<f64> = blur.taps().iter().map(|&g| g as f64).collect();
            let generic = filtered_threshold_rms(&volume, &ema_weights(ALPHA, last), &taps, &thresholds);
            assert!(
                (generic - rms).abs() < 1e-6 * rms.max(1e-3) + 1e-7,
                "{generic} vs {rms}"
            );
        }
    }
    let (rms, rms_61, mean_slice) = figures[0];
    assert!(rms <= MAX_RMS_EMA_BLUR_ADAPTED, "EMA + blur RMS {rms}");
    assert!(
        rms_61 <= MAX_RMS_EMA_BLUR_ADAPTED,
        "EMA + blur RMS at 61 thresholds {rms_61}"
    );
    assert!(rms < figures[1].0, "no better than STBN");
    assert!(mean_slice <= MAX_LF_SLICE, "per-slice LF {mean_slice}");
}

/// A 128x128x64 mask adapted to a 3x3 box and an 8-frame box (product) beats the
/// Gaussian-adapted defaults on that filter (mean of frames 56..=63, then the 3x3 box).
/// Bakes the mask (about 16 s in release on 2 cores).
#[test]
fn box_adapted_mask_beats_gaussian_masks_on_its_filter() {
    let params = FilterAdaptedParams {
        spatial: SpatialFilter::Box { size: 3 },
        temporal: TemporalFilter::Box { size: 8 },
        seed: 3,
        ..FilterAdaptedParams::default()
    };
    let adapted = bake_filter_adapted(&params, &mut no_progress).unwrap();
    let adapted_volume = Volume::from_fn(128, 128, 64, |x, y, z| {
        ((adapted.ranks[(z * 128 + y) * 128 + x] as f64 + 0.5) / 16384.0) as f32
    })
    .unwrap();
    let thresholds = stratified_thresholds(DEFAULT_THRESHOLDS).unwrap();
    let (temporal, spatial) = (vec![1.0 / 8.0; 8], vec![1.0 / 3.0; 3]);
    let measure = |v: &Volume| filtered_threshold_rms(v, &temporal, &spatial, &thresholds);
    let box_rms = measure(&adapted_volume);
    let stbn_rms = measure(&mask_volume(&defaults::stbn_128()));
    let ema_gauss_rms = measure(&mask_volume(&defaults::filter_adapted_128()));
    println!(
        "box 3x3 x box 8 thresholded RMS at frame 63: box-adapted {box_rms:.5}, STBN (Gaussian 1.9) {stbn_rms:.5}, \
         EMA x Gaussian-adapted default {ema_gauss_rms:.5}"
    );
    assert!(box_rms < stbn_rms && box_rms < ema_gauss_rms);
}
