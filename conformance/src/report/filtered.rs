//! The report's headline: every method's error after the real-time filters
//! ([`crate::study::filtered`]), whole image and interior, relative to white noise
//! after the same filter, with the filters' bias floor; as HTML and as CSV
//! beside the page.

use crate::metrics::regions::Region;
use crate::study::filtered::STUDY_FILTERS;
use crate::study::{Method, StudyResult, GOAL_FRAME};
use anyhow::Result;
use std::fmt::Write as _;
use std::path::Path;

/// The first frame of the pooled figures of `r`.
fn first_frame(r: &StudyResult) -> usize {
    GOAL_FRAME.min(r.config.frames.saturating_sub(1)) as usize
}

/// Header and rows (`None` for the bias floor row) of the filtered table.
#[allow(clippy::type_complexity)]
fn rows(r: &StudyResult) -> (Vec<String>, Vec<(Option<Method>, Vec<f64>)>) {
    let from = first_frame(r);
    let head = STUDY_FILTERS[0];
    let mut header: Vec<String> = STUDY_FILTERS
        .iter()
        .flat_map(|c| [format!("{c}, whole image"), format!("{c}, interior")])
        .collect();
    header.push(format!("{head} noise part, whole image"));
    header.push(format!("{head} noise part, interior"));
    let noise = |m: Method| {
        [None, Some(Region::Interior)]
            .map(|reg| r.pooled_filtered_noise(m, head, reg, from).unwrap_or(f64::NAN))
    };
    let values = |f: &dyn Fn(gpu_tracer::filter::FilterChain, Option<Region>) -> Option<f64>| -> Vec<f64> {
        STUDY_FILTERS
            .iter()
            .flat_map(|&c| [None, Some(Region::Interior)].map(|reg| f(c, reg).unwrap_or(f64::NAN)))
            .collect()
    };
    let mut rows: Vec<(Option<Method>, Vec<f64>)> = r
        .runs
        .iter()
        .map(|run| {
            let m = run.method;
            let mut v = values(&|c, reg| r.pooled_filtered(m, c, reg, from));
            v.extend(noise(m));
            (Some(m), v)
        })
        .collect();
    let mut bias = values(&|c, reg| r.filter_bias(c, reg, from));
    bias.extend([f64::NAN; 2]);
    rows.push((None, bias));
    (header, rows)
}

/// Whether `r` measured the filters.
pub fn has_filters(r: &StudyResult) -> bool {
    r.runs.iter().any(|run| !run.filtered.is_empty())
}

/// Writes `table-filtered-spp<N>.csv`; returns its file name.
///
/// # Errors
/// I/O errors.
pub fn write_csv(r: &StudyResult, out: &Path) -> Result<String> {
    let (header, rows) = rows(r);
    let quoted: Vec<String> = header.iter().map(|c| format!("\"{c}\"")).collect();
    let mut csv = format!("method,{}\n", quoted.join(","));
    for (m, v) in rows {
        let values: Vec<String> = v.iter().map(|x| x.to_string()).collect();
        let _ = writeln!(
            csv,
            "{},{}",
            m.map_or("filter bias", Method::name),
            values.join(",")
        );
    }
    let file = format!("table-filtered-spp{}.csv", r.config.spp);
    std::fs::write(out.join(&file), csv)?;
    Ok(file)
}

/// The HTML table, methods coloured by `css`, the best value of each column
/// (bias row excluded, white and the null row excluded) in bold.
pub fn html_table(r: &StudyResult, css: impl Fn(Method) -> String) -> String {
    let (header, rows) = rows(r);
    let mut best = vec![f64::INFINITY; header.len()];
    for (m, v) in &rows {
        if matches!(m, Some(m) if !m.is_white_noise()) {
            for (b, x) in best.iter_mut().zip(v) {
                if x.is_finite() {
                    *b = b.min(*x);
                }
            }
        }
    }
    let mut h = String::from("<table class=\"headline\"><tr><th>method</th>");
    for c in &header {
        let _ = write!(h, "<th>{c}</th>");
    }
    h += "</tr>\n";
    for (m, v) in rows {
        match m {
            Some(m) => {
                let _ = write!(h, "<tr><td style=\"color:{}\">{}</td>", css(m), m.name());
            }
            None => h += "<tr><td><i>filter bias (reference filtered)</i></td>",
        }
        for (x, b) in v.iter().zip(&best) {
            if x.is_nan() {
                h += "<td>-</td>";
            } else if m.is_some_and(|m| !m.is_white_noise()) && x == b {
                let _ = write!(h, "<td><b>{x:.3}</b></td>");
            } else {
                let _ = write!(h, "<td>{x:.3}</td>");
            }
        }
        h += "</tr>\n";
    }
    h += "</table>\n";
    h
}
