//! The report's page: runs the [still-camera study](crate::study) and writes
//! `index.html` with PNG images and plots.
//!
//! Pictures per method: the frame at [`GOAL_FRAME`], the signed luma error on the
//! back-wall inset (grey = 0, white/black = +/- 3 white-mode RMS of that inset) and its
//! power spectrum (centred, `log10` of power relative to white's mean, mapped from -2
//! (black) to +1 (white)). Plots ([`super::plot`]: SVG with axes, ticks, legends and
//! labelled goal lines; data beside each as CSV): radial power of the error, LF
//! power and blurred RMSE against frame, accumulated RMSE against frame count, and
//! the R2-walk against the fixed-step accumulated RMSE.

use super::plot::{Curve, LinePlot};
use crate::study::{crop, Method, Metric, Study, StudyConfig, StudyResult, ACCUMULATION_POINTS, GOAL_FRAME};
use crate::{Grid, SpectrumAnalyzer};
use anyhow::{Context, Result};
use glam::Vec4;
use plotters::prelude::*;
use std::fmt::Write as _;
use std::path::Path;

/// What the report renders.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReportConfig {
    /// Image side.
    pub size: u32,
    /// Frames for the single-frame figures; the 1-spp run renders twice as many for
    /// the accumulation figure.
    pub frames: u32,
    /// Reference samples per pixel.
    pub ref_spp: u32,
    /// Maximum path length in segments (8 in the study; 2 = direct light only).
    pub max_depth: u32,
}

/// Colour of each method in the plots (and the page's legend).
fn colour(m: Method) -> RGBColor {
    match m {
        Method::White => RGBColor(128, 128, 128),
        Method::WhiteControl => RGBColor(190, 190, 190),
        Method::Sort => RGBColor(230, 159, 0),
        Method::Permute => RGBColor(0, 114, 178),
        Method::PermuteJitter => RGBColor(0, 60, 110),
        Method::PermuteZSobolJitter => RGBColor(60, 150, 220),
        Method::FixedStep => RGBColor(213, 94, 0),
        Method::Dither => RGBColor(0, 158, 115),
        Method::DitherFilterAdapted => RGBColor(110, 190, 50),
        Method::ScreenSobol => RGBColor(204, 121, 167),
        Method::ZSobol => RGBColor(86, 180, 233),
        Method::Spatiotemporal => RGBColor(240, 228, 66),
        Method::SpatiotemporalKronecker => RGBColor(120, 94, 240),
        Method::TemporalSort => RGBColor(150, 150, 150),
        Method::TemporalSortAdvance => RGBColor(90, 90, 90),
        Method::TemporalPermute => RGBColor(200, 120, 40),
        Method::TemporalPermuteJitter => RGBColor(160, 80, 20),
        Method::TemporalPermuteKroneckerJitter => RGBColor(200, 60, 90),
        Method::FeaturePermute => RGBColor(0, 170, 170),
        Method::FeaturePermuteJitter => RGBColor(0, 100, 100),
        Method::FeaturePermuteRawKey => RGBColor(120, 120, 40),
        Method::FeaturePermuteHistoryKey => RGBColor(150, 60, 150),
        Method::FeatureTemporalPermute => RGBColor(230, 160, 0),
        Method::FeatureTemporalPermuteJitter => RGBColor(170, 110, 0),
    }
}

fn css(m: Method) -> String {
    let RGBColor(r, g, b) = colour(m);
    format!("rgb({r},{g},{b})")
}

/// Runs the study for 1 spp (`2 * frames` frames) and 4 spp (`frames` frames) and
/// writes `out/index.html` with its images. `log` receives progress lines.
///
/// # Errors
/// Rendering or I/O errors.
pub fn write_report(
    cfg: &ReportConfig,
    out: &Path,
    cache_dir: Option<&Path>,
    mut progress: impl FnMut(&str, u64, u64),
) -> Result<Vec<StudyResult>> {
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let mut results = Vec::new();
    let mut picture_sections = Vec::new();
    for (spp, frames) in [(1u32, 2 * cfg.frames), (4, cfg.frames)] {
        let mut config = StudyConfig::new(cfg.size, spp, frames, cfg.ref_spp);
        config.max_depth = cfg.max_depth;
        let label = format!("reference {} spp", cfg.ref_spp);
        let study = Study::new(config, cache_dir, |d, t| progress(&label, d as u64, t as u64))?;
        let total = frames as u64 * Method::REPORT.len() as u64;
        let mut done = 0;
        let label = format!("{spp} spp");
        let result = study.run(&Method::REPORT, |_, _| {
            done += 1;
            progress(&label, done, total);
        })?;
        write_images(&study, &result, out)?;
        write_table_csv(&result, out)?;
        if super::filtered::has_filters(&result) {
            super::filtered::write_csv(&result, out)?;
        }
        super::spectra::write_spectra(&result, out, |m| prefix(&result, m))?;
        super::spectra::write_radial_plots(&result, out, |m| prefix(&result, m), colour)?;
        picture_sections.push(super::pictures::write_pictures(
            &study,
            &result,
            out,
            |m| prefix(&result, m),
            css,
        )?);
        results.push(result);
    }
    write_plots(&results[0], out)?;
    super::spectra::write_temporal_plot(&results[0], out, colour)?;
    std::fs::write(out.join("index.html"), html(cfg, &results, &picture_sections))?;
    Ok(results)
}

/// A figure's links: to the command at the top of the page and to `data`
/// (a file beside the page).
fn links(data: &str) -> String {
    format!("<a href=\"#command\">command</a> &middot; <a href=\"{data}\">data (CSV)</a>")
}

fn prefix(r: &StudyResult, m: Method) -> String {
    format!("spp{}-{}", r.config.spp, m.name())
}

fn write_images(study: &Study, result: &StudyResult, out: &Path) -> Result<()> {
    let size = study.config.size;
    let inset = &study.insets[0];
    let white = result.run(Method::White).context("white run")?;
    let scale = 3.0 * crop(&white.snapshot.error, size as usize, inset).rms() as f32;
    let mut analyzer = SpectrumAnalyzer::new();
    let white_mean = analyzer
        .power_spectrum(&crop(&white.snapshot.error, size as usize, inset))
        .mean_power();
    let reference: Vec<Vec4> = study.reference.rgb.iter().map(|c| c.extend(1.0)).collect();
    gpu_tracer::image_out::write_png(
        out.join(format!("spp{}-reference.png", study.config.spp)),
        size,
        size,
        &reference,
        Default::default(),
    )?;
    for run in &result.runs {
        let p = prefix(result, run.method);
        let rgb: Vec<Vec4> = run.snapshot.rgb.iter().map(|c| c.extend(1.0)).collect();
        gpu_tracer::image_out::write_png(
            out.join(format!("{p}-frame.png")),
            size,
            size,
            &rgb,
            Default::default(),
        )?;
        let err = crop(&run.snapshot.error, size as usize, inset);
        let grey: Vec<u8> = err
            .data()
            .iter()
            .map(|e| (127.5 + 127.5 * (e / scale).clamp(-1.0, 1.0)) as u8)
            .collect();
        save_grey(&out.join(format!("{p}-error.png")), inset.side, &grey)?;
        let whole: Vec<u8> = run
            .snapshot
            .error
            .iter()
            .map(|e| (127.5 + 127.5 * (e / scale).clamp(-1.0, 1.0)) as u8)
            .collect();
        save_grey(&out.join(format!("{p}-error-full.png")), size, &whole)?;
        let spectrum = analyzer.power_spectrum(&err);
        let s = inset.side as usize;
        let shifted = Grid::from_fn(s, s, |x, y| {
            let kx = (x + s - s / 2) % s;
            let ky = (y + s - s / 2) % s;
            spectrum.get(kx, ky) as f32
        })?;
        let grey: Vec<u8> = shifted
            .data()
            .iter()
            .map(|&v| {
                let l = ((v as f64 / white_mean).max(1e-12)).log10();
                (((l + 2.0) / 3.0).clamp(0.0, 1.0) * 255.0) as u8
            })
            .collect();
        save_grey(&out.join(format!("{p}-spectrum.png")), inset.side, &grey)?;
    }
    Ok(())
}

fn save_grey(path: &Path, side: u32, data: &[u8]) -> Result<()> {
    image::save_buffer(path, data, side, side, image::ExtendedColorType::L8)
        .with_context(|| format!("cannot write {}", path.display()))
}

type Series = (Method, Vec<(f64, f64)>);

/// The plots of the report: file stem (`<stem>.svg`, `<stem>.csv`) and caption.
const PLOTS: [(&str, &str); 6] = [
    ("plot-radial", "Radially averaged power of the error on the back-wall inset, averaged over frames from 8 on, relative to white noise's mean power (white noise is flat at 1; blue noise is low at low frequencies)."),
    ("plot-lf", "Low-frequency power of the error on the flat insets against frame (white = 1)."),
    ("plot-blur1", "RMSE after a Gaussian blur (sigma 1, whole image) against frame (white = 1)."),
    ("plot-accumulated", "RMSE of the accumulated image against the number of frames (white = 1)."),
    ("plot-temporal", "Temporal power spectrum of a pixel's error on the back-wall inset, frames from 8 on, averaged over its pixels, relative to white noise's mean power (white noise is flat at 1; error that alternates between frames is high at 0.5 cycles per frame)."),
    ("plot-walk", "Aperiodic R2 walk (permute) against the fixed step floor(W (a1, a2)) = (48, 36) (fixed-step): accumulated RMSE against frames (white = 1)."),
];

/// Writes `out/<stem>.svg` and `.csv` with one curve per method of `series`.
fn plot(
    out: &Path,
    stem: &str,
    (x_title, y_title): (&str, &str),
    series: &[Series],
    log_y: bool,
    lines: &[(f64, &str)],
) -> Result<()> {
    let curves: Vec<Curve> = series
        .iter()
        .map(|(m, points)| Curve {
            label: m.name().to_string(),
            colour: colour(*m),
            points: points.clone(),
        })
        .collect();
    let title = PLOTS.iter().find(|p| p.0 == stem).map(|p| p.1).unwrap_or(stem);
    let title = title.split([',', '(', ':']).next().unwrap_or(title).trim();
    let plot = LinePlot {
        title,
        x_title,
        y_title,
        log_y,
        lines,
        curves: &curves,
    };
    plot.write(&out.join(format!("{stem}.svg")), &out.join(format!("{stem}.csv")))
}

fn rel_series(r: &StudyResult, m: Method, metric: Metric, count_from_one: bool) -> Vec<(f64, f64)> {
    let n = r.run(m).map(|run| run.rmse.len()).unwrap_or(0);
    (0..n)
        .filter_map(|i| {
            let x = if count_from_one { i + 1 } else { i } as f64;
            r.relative(m, metric, i).map(|v| (x, v))
        })
        .collect()
}

fn write_plots(r: &StudyResult, out: &Path) -> Result<()> {
    let white_radial = r.run(Method::White).context("white")?;
    let side = r.insets[0].side as f64;
    let norm = mean_nonzero(&white_radial.radial);
    let radial: Vec<Series> = r
        .runs
        .iter()
        .map(|run| {
            let s = run
                .radial
                .iter()
                .enumerate()
                .skip(1)
                .filter(|(k, _)| (*k as f64) <= side / 2.0)
                .map(|(k, &p)| (k as f64 / side, p / norm))
                .collect();
            (run.method, s)
        })
        .collect();
    let relative = "relative to white (white = 1)";
    plot(
        out,
        "plot-radial",
        ("frequency (cycles per pixel)", "power / white's mean power"),
        &radial,
        true,
        &[(1.0, "white noise")],
    )?;
    let all = |metric, one| -> Vec<Series> {
        r.runs
            .iter()
            .map(|run| (run.method, rel_series(r, run.method, metric, one)))
            .collect()
    };
    plot(
        out,
        "plot-lf",
        ("frame", relative),
        &all(Metric::LowFrequency, false),
        true,
        &[(0.15, "goal"), (1.0, "white")],
    )?;
    plot(
        out,
        "plot-blur1",
        ("frame", relative),
        &all(Metric::Blur1, false),
        false,
        &[(0.6, "goal"), (1.0, "white")],
    )?;
    plot(
        out,
        "plot-accumulated",
        ("frames accumulated", relative),
        &all(Metric::Accumulated, true),
        false,
        &[(1.0, "white"), (1.05, "goal")],
    )?;
    let walk: Vec<Series> = [Method::White, Method::Permute, Method::FixedStep]
        .iter()
        .map(|&m| (m, rel_series(r, m, Metric::Accumulated, true)))
        .collect();
    plot(
        out,
        "plot-walk",
        ("frames accumulated", relative),
        &walk,
        false,
        &[(1.0, "white"), (1.05, "goal")],
    )?;
    Ok(())
}

fn mean_nonzero(v: &[f64]) -> f64 {
    let nz: Vec<f64> = v.iter().copied().skip(1).filter(|x| *x > 0.0).collect();
    (nz.iter().sum::<f64>() / nz.len().max(1) as f64).max(1e-30)
}

/// The headline table of `r`: header and one row per method (name, then
/// values), relative to white = 1. Shared by the HTML and its CSV.
fn table_rows(r: &StudyResult) -> (Vec<String>, Vec<(Method, Vec<f64>)>) {
    let t = GOAL_FRAME.min(r.config.frames - 1) as usize;
    let points: Vec<u32> = ACCUMULATION_POINTS
        .iter()
        .copied()
        .filter(|&n| n <= r.config.frames)
        .collect();
    let mut header: Vec<String> = vec![
        format!("LF power, frame {t}"),
        format!("LF mean, frames {t}.."),
        format!("blur sigma 1, frame {t}"),
        format!("blur sigma 2, frame {t}"),
        format!("blur sigma 1, mean of frame ratios {t}.."),
        format!("blur sigma 1, RMSE over frames {t}.."),
    ];
    for n in &points {
        header.push(format!("accumulated, {n} frames"));
        header.push(format!("accumulated raw, {n} frames"));
    }
    let rows = r
        .runs
        .iter()
        .map(|run| {
            let m = run.method;
            let rel = |metric, i| r.relative(m, metric, i).unwrap_or(f64::NAN);
            let frames = run.rmse.len();
            let avg = |metric| (t..frames).map(|i| rel(metric, i)).sum::<f64>() / (frames - t).max(1) as f64;
            let mut v = vec![
                rel(Metric::LowFrequency, t),
                avg(Metric::LowFrequency),
                rel(Metric::Blur1, t),
                rel(Metric::Blur2, t),
                avg(Metric::Blur1),
                r.pooled(m, Metric::Blur1, t.min(frames.saturating_sub(1)))
                    .unwrap_or(f64::NAN),
            ];
            for &n in &points {
                let i = n as usize - 1;
                v.push(rel(Metric::Accumulated, i));
                v.push(rel(Metric::AccumulatedRaw, i));
            }
            (m, v)
        })
        .collect();
    (header, rows)
}

/// Writes the headline table of `r` as `table-spp<N>.csv`; returns the file name.
fn write_table_csv(r: &StudyResult, out: &Path) -> Result<String> {
    let (header, rows) = table_rows(r);
    let quoted: Vec<String> = header.iter().map(|c| format!("\"{c}\"")).collect();
    let mut csv = format!("method,{}\n", quoted.join(","));
    for (m, v) in rows {
        let values: Vec<String> = v.iter().map(|x| x.to_string()).collect();
        let _ = writeln!(csv, "{},{}", m.name(), values.join(","));
    }
    let file = format!("table-spp{}.csv", r.config.spp);
    std::fs::write(out.join(&file), csv)?;
    Ok(file)
}

fn figure_table(r: &StudyResult) -> String {
    let (header, rows) = table_rows(r);
    let mut h = String::from("<table><tr><th>method</th>");
    // Accumulated columns come in (corrected, raw) pairs, shown as "v (raw)".
    let first_acc = header
        .iter()
        .position(|c| c.starts_with("accumulated"))
        .unwrap_or(header.len());
    for c in &header[..first_acc] {
        let _ = write!(h, "<th>{}</th>", c.replace("sigma ", "&sigma;"));
    }
    for c in header[first_acc..].iter().step_by(2) {
        let _ = write!(h, "<th>{c} (raw)</th>");
    }
    h += "</tr>\n";
    for (m, v) in rows {
        let _ = write!(h, "<tr><td style=\"color:{}\">{}</td>", css(m), m.name());
        for x in &v[..first_acc] {
            let _ = write!(h, "<td>{x:.3}</td>");
        }
        for pair in v[first_acc..].chunks(2) {
            let _ = write!(h, "<td>{:.3} ({:.3})</td>", pair[0], pair[1]);
        }
        h += "</tr>\n";
    }
    h += "</table>\n";
    h
}

fn pictures(r: &StudyResult) -> String {
    let spp = r.config.spp;
    let mut h = format!(
        "<div class=\"row\"><figure><img src=\"spp{spp}-reference.png\" alt=\"reference\"><figcaption>reference, {} spp</figcaption></figure></div>\n",
        r.config.ref_spp
    );
    for run in &r.runs {
        let p = prefix(r, run.method);
        let _ = writeln!(
            h,
            "<div class=\"row\"><h3 style=\"color:{c}\">{n}: {d}</h3>\
<figure><img src=\"{p}-frame.png\" alt=\"{n} frame\"><figcaption>frame {f}</figcaption></figure>\
<figure><img src=\"{p}-error-full.png\" alt=\"{n} error\"><figcaption>luma error, whole frame</figcaption></figure>\
<figure><img class=\"inset\" src=\"{p}-error.png\" alt=\"{n} error inset\"><figcaption>error, {i} inset</figcaption></figure>\
<figure><img class=\"inset\" src=\"{p}-spectrum.png\" alt=\"{n} spectrum\"><figcaption>its power spectrum, this frame</figcaption></figure>\
<figure><img class=\"inset\" src=\"{p}-spectrum-avg.png\" alt=\"{n} averaged spectrum\"><figcaption>power spectrum averaged over frames {f}.. and insets</figcaption></figure></div>",
            c = css(run.method),
            n = run.method.name(),
            d = run.method.describe(),
            f = run.snapshot.frame,
            i = r.insets[0].name,
        );
    }
    h
}

/// The generated opening paragraph: which method wins each headline figure
/// of `r` (1 spp), in numbers, and the region split of the blurred error.
fn summary_text(r: &StudyResult) -> String {
    use crate::metrics::regions::Region;
    let t = GOAL_FRAME.min(r.config.frames.saturating_sub(1)) as usize;
    // The null row's value of every figure ranked below, for the chance sentence.
    let null = std::cell::RefCell::new(Vec::new());
    let best = |value: &dyn Fn(Method) -> Option<f64>| -> Option<(Method, f64)> {
        if r.run(Method::WhiteControl).is_some() {
            null.borrow_mut().extend(value(Method::WhiteControl));
        }
        r.runs
            .iter()
            .filter(|run| !run.method.is_white_noise())
            .filter_map(|run| {
                value(run.method)
                    .filter(|v| v.is_finite() && *v > 0.0)
                    .map(|v| (run.method, v))
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
    };
    let name = |b: Option<(Method, f64)>| match b {
        Some((m, v)) => format!("<b style=\"color:{}\">{}</b> ({v:.3})", css(m), m.name()),
        None => "n/a".to_string(),
    };
    let frames = r.config.frames as usize;
    let lf_mean = |m| {
        let v: Vec<f64> = (t..frames)
            .filter_map(|i| r.relative(m, Metric::LowFrequency, i))
            .collect();
        (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
    };
    let acc_n = ACCUMULATION_POINTS
        .iter()
        .copied()
        .filter(|&n| n <= r.config.frames)
        .max();
    let mut h = format!(
        "<p class=\"summary\"><b>In short</b> ({} spp, {} frames, figures relative to white noise = 1, lower is better; \
generated from the tables below): the lowest blurred error (&sigma; 1, RMSE over frames {t}..) is {}; the lowest \
low-frequency power on the flat insets (mean over frames {t}..) is {}",
        r.config.spp,
        r.config.frames,
        name(best(&|m| r.pooled(m, Metric::Blur1, t))),
        name(best(&lf_mean)),
    );
    if let Some(n) = acc_n {
        let _ = write!(
            h,
            "; the lowest error of the image accumulated over {n} frames is {}",
            name(best(&|m| r.relative(m, Metric::Accumulated, n as usize - 1)))
        );
    }
    h += ". By region (blurred error, frames from {t}):";
    let h = h.replace("{t}", &t.to_string());
    let mut h = h;
    for (region, label) in [
        (Region::Emitter, "emitter zone"),
        (Region::Edge, "edges"),
        (Region::Interior, "interior"),
    ] {
        let _ = write!(
            h,
            " {label}: {};",
            name(best(&|m| r.pooled_region(m, Some(region), t)))
        );
    }
    h += " (0 would mean below the reference's own noise: not ranked).";
    let head = gpu_tracer::filter::FilterChain::TaaAtrous;
    if super::filtered::has_filters(r) {
        let _ = write!(
            h,
            " After the real-time filter ({head}), the lowest error is {} on the whole image and {} on the interior; \
the filter's own error on the reference is {} of white's filtered error on the whole image (interior {}), so where \
that is near 1 the filter, not the noise, decides; without it (noise part) the lowest is {} (interior {}).",
            name(best(&|m| r.pooled_filtered(m, head, None, t))),
            name(best(&|m| r.pooled_filtered(m, head, Some(Region::Interior), t))),
            r.filter_bias(head, None, t).map_or("n/a".into(), |v| format!("{v:.3}")),
            r.filter_bias(head, Some(Region::Interior), t).map_or("n/a".into(), |v| format!("{v:.3}")),
            name(best(&|m| r.pooled_filtered_noise(m, head, None, t))),
            name(best(&|m| r.pooled_filtered_noise(m, head, Some(Region::Interior), t))),
        );
    }
    h += " The permutation's figures are in the rows <i>permute</i> and <i>permute-jitter</i>; the render \
defaults' (the temporally blue permutation with ZSobol's pixel jitter) in <i>temporal-permute-jitter</i>.";
    h += &super::chance::sentence(super::chance::range(&null.borrow()));
    h += "</p>\n";
    h
}

fn legend() -> String {
    Method::REPORT
        .iter()
        .map(|&m| format!("<span style=\"color:{}\">&#9632; {}</span>", css(m), m.name()))
        .collect::<Vec<_>>()
        .join(" ")
}

fn html(cfg: &ReportConfig, results: &[StudyResult], picture_sections: &[String]) -> String {
    let r1 = &results[0];
    let mut h = String::from(
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>Blue-noise seed permutation: rendered quality</title>\n\
<style>body{font-family:sans-serif;margin:1em} img{image-rendering:pixelated;width:256px;height:256px;border:1px solid #ccc}\
 figure{display:inline-block;margin:4px} table{border-collapse:collapse} td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}\
 img.plot{width:760px;height:440px;image-rendering:auto} img.radial{width:330px;height:225px;image-rendering:auto;border:none}\
 img.bar{width:520px;height:70px;border:none;image-rendering:auto} img.inset{width:160px;height:160px}\
 table.pictures img{width:192px;height:192px} table.pictures img.crop{width:256px;height:256px}</style></head>\n<body>\n",
    );
    let _ = write!(
        h,
        "<h1>Rendered quality of the blue-noise seed permutation</h1>\n<p>Cornell box {s}x{s}, static camera, CPU renderer, \
reference {r} spp. Command (every figure below links here): <code id=\"command\">cargo run -p conformance --release -- report --out DIR --size {s} --frames {f} --ref-spp {r}</code>. \
Error = luma(frame) - luma(reference). Figures relative to white (fresh white-noise seeds every frame) = 1; frame numbers from 0 \
(frame 0 is the white start, frame {g} has had {g} permutation passes). Accumulated RMSE has the reference's own noise removed \
(raw value in brackets). Goals (issue 5): by frame 8 LF power &le; 0.15 and blurred RMSE (&sigma; 1) &le; 0.6; accumulated RMSE &le; 1.05 at 64 and 128 frames.</p>\n",
        s = cfg.size,
        f = cfg.frames,
        r = cfg.ref_spp,
        g = GOAL_FRAME
    );
    h += &summary_text(r1);
    h += "<p>Insets (flat regions, checked by casting each pixel's centre ray):";
    for i in &r1.insets {
        let _ = write!(
            h,
            " {} at ({}, {}), side {} (max relative reference gradient {:.3});",
            i.name, i.x0, i.y0, i.side, i.max_gradient
        );
    }
    h += "</p>\n";
    for r in results.iter().filter(|r| super::filtered::has_filters(r)) {
        let _ = write!(
            h,
            "<h2>What the viewer sees: error after the real-time filter, {spp} spp</h2>\n<p>RMSE of luma(filtered frame) - \
luma(reference) over frames {t}.., relative to white noise after the same filter (= 1), whole image and interior region. \
<i>taa</i>: exponential history (&alpha; 0.1) with 3x3 colour clamping; <i>atrous</i>: SVGF's edge-avoiding a-trous \
wavelet filter, 5 iterations, guided by depth, normal and luminance; <i>taa+atrous</i>: both, in SVGF's order (the \
headline). Both filter the illumination demodulated by the albedo. The last row is the filter's own error on the \
reference (its bias): where it is close to 1 the filter's blur, not the noise, dominates. The row <i>white-control</i> \
is another draw of white noise (the null row): its distance from 1 is what chance reads in each column. The last two columns leave \
that bias out: luma(filtered frame) - luma(filtered reference), what the seeds control after the filter. Best per \
column in bold.</p>\n\
{table}<p><a href=\"table-filtered-spp{spp}.csv\">table as CSV</a> &middot; <a href=\"#command\">command</a></p>\n",
            spp = r.config.spp,
            t = GOAL_FRAME.min(r.config.frames - 1),
            table = super::filtered::html_table(r, css),
        );
    }
    for r in results {
        let _ = write!(
            h,
            "<h2>Raw frames, {} spp, {} frames</h2>\n{}<p><a href=\"table-spp{}.csv\">table as CSV</a> &middot; <a href=\"#command\">command</a></p>\n",
            r.config.spp,
            r.config.frames,
            figure_table(r),
            r.config.spp
        );
    }
    let _ = writeln!(
        h,
        "<h2>Plots (1 spp, {} frames)</h2><p>Colours: {}. Dashed lines: white noise and the goals, labelled with their values. Each plot's data is linked below it.</p>",
        r1.config.frames,
        legend()
    );
    for (stem, caption) in PLOTS {
        let _ = writeln!(
            h,
            "<figure><img class=\"plot\" src=\"{stem}.svg\" alt=\"{stem}\"><figcaption>{caption} \
{links}</figcaption></figure>",
            links = links(&format!("{stem}.csv"))
        );
    }
    for r in results {
        let _ = write!(
            h,
            "<h2>Averaged spectra, {spp} spp</h2><p>Power spectrum of the error, DC at the centre, averaged over \
frames {t}.. and over the flat insets (each cropped to the smallest inset's side), on one colour scale for every \
method: white noise is flat around 1; blue noise is dark near the centre (low frequencies). Beside each, its radially \
averaged power (log scale) with white noise's curve in grey.</p>\n\
<figure><img class=\"bar\" src=\"{bar}\" alt=\"colour scale\"><figcaption>colour scale</figcaption></figure><div class=\"row\">",
            spp = r.config.spp,
            t = GOAL_FRAME.min(r.config.frames - 1),
            bar = super::spectra::scale_file(r),
        );
        for run in &r.runs {
            let _ = write!(
                h,
                "<figure class=\"pair\"><img class=\"inset\" src=\"{p}-spectrum-avg.png\" alt=\"{n} averaged spectrum\">\
<img class=\"radial\" src=\"{p}-spectrum-radial.svg\" alt=\"{n} radial power\">\
<figcaption><span style=\"color:{c}\">{n}</span>: averaged spectrum and its radial mean. {l}</figcaption></figure>",
                l = links(&format!("{}-spectrum-radial.csv", prefix(r, run.method))),
                p = prefix(r, run.method),
                n = run.method.name(),
                c = css(run.method),
            );
        }
        h += "</div>\n";
    }
    for section in picture_sections {
        h += section;
    }
    for r in results {
        let _ = write!(
            h,
            "<h2>Images, {} spp, frame {}</h2>\n{}",
            r.config.spp,
            GOAL_FRAME.min(r.config.frames - 1),
            pictures(r)
        );
    }
    h += "<pre>";
    for r in results {
        h += &r.summary();
    }
    h += "</pre>\n<script>window.addEventListener('load', function () {\n\
  var imgs = Array.prototype.slice.call(document.images);\n\
  var ok = imgs.filter(function (i) { return i.complete && i.naturalWidth > 0; }).length;\n\
  document.body.dataset.imagesLoaded = ok + '/' + imgs.length;\n\
});</script>\n</body></html>\n";
    h
}
