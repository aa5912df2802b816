//! One study over several draws: the same configuration at consecutive salts
//! (each salt draws the white seeds and where the a-priori samplers' per-pixel
//! data sits on the screen, [`StudyConfig::salt`](super::config::StudyConfig::salt)),
//! and per row the headline figures' mean and range over the draws.
//!
//! Why: one draw of a sampler's per-pixel data moves the figures behind a
//! history by 2-3% and the running means by 10-15% (the few hundred pixels at
//! the lights' silhouettes decide them, and they are the same pixels in every
//! draw), so a difference of that size between two single runs separates two
//! draws, not two methods (QUALITY.md, "The jitter's shifts: a net"). Compare
//! methods by their ranges over draws.
//!
//! Much of that scatter is white's own: every figure is a ratio against one
//! white render, and a row equal to white ([`Method::WhiteControl`], the null
//! row) reads 0.96-1.09 on the whole image behind a history at 256x256
//! (QUALITY.md, "What chance reads: the null row"). With the null row among
//! the rows the tables add each row against both white draws pooled, and the
//! paired table compares the rows with the first row that is not the null row.

use super::config::GOAL_FRAME;
use super::method::Method;
use super::result::{HistoryMetric, Metric, StudyResult};
use crate::metrics::regions::Region;
use gpu_tracer::filter::FilterChain;

/// One headline figure of a row (white = 1), read off one draw's result.
#[derive(Clone, Copy, Debug)]
pub struct DrawFigure {
    /// Column title.
    pub name: &'static str,
    /// The figure of `method` in a draw; `None` where that draw cannot give
    /// it (too few frames, no filters, a missing row).
    pub read: fn(&StudyResult, Method) -> Option<f64>,
    /// Whether the figure is one RMSE over white's in the same pixels and
    /// frames, so that white's draws pool ([`pooled_with_null`]); the flat
    /// insets' LF, a mean of per-frame ratios of self-normalised spectra,
    /// is not.
    pub rmse_ratio: bool,
}

/// A row's figure `r` against white's and the null row's renders pooled,
/// from the null row's figure `c` in the same draw (both white = 1):
/// `r / sqrt((1 + c^2) / 2)`, the row's RMSE over the RMSE of the two white
/// draws' squared errors together. White's own chance then weighs half.
pub fn pooled_with_null(r: f64, c: f64) -> f64 {
    r / ((1.0 + c * c) / 2.0).sqrt()
}

/// First frame the per-frame and filtered figures pool over (as the study's
/// own tables: frame [`GOAL_FRAME`], or the last frame of a shorter run).
fn from(r: &StudyResult) -> usize {
    GOAL_FRAME.min(r.config.frames - 1) as usize
}

/// The flat insets' low-frequency ratio, mean over frames `8..` (the study's
/// "LF mean 8..").
fn lf_mean(r: &StudyResult, m: Method) -> Option<f64> {
    let frames = r.run(m)?.rmse.len();
    let ratios: Vec<f64> = (from(r)..frames)
        .map(|i| r.relative(m, Metric::LowFrequency, i))
        .collect::<Option<_>>()?;
    (!ratios.is_empty()).then(|| ratios.iter().sum::<f64>() / ratios.len() as f64)
}

/// The figures of the draws table, in column order: the raw frame, the
/// flat insets, the history alone and blurred, the running means of 8, 32
/// and 128 frames (issue 29: every shipped sampler at most white's), TAA
/// and TAA + a-trous with its noise part.
pub const DRAW_FIGURES: [DrawFigure; 15] = [
    DrawFigure {
        name: "raw blur σ1 whole",
        read: |r, m| r.pooled(m, Metric::Blur1, from(r)),
        rmse_ratio: true,
    },
    DrawFigure {
        name: "raw blur σ1 interior",
        read: |r, m| r.pooled_region(m, Some(Region::Interior), from(r)),
        rmse_ratio: true,
    },
    DrawFigure {
        name: "LF mean 8..",
        read: lf_mean,
        rmse_ratio: false,
    },
    DrawFigure {
        name: "EMA whole",
        read: |r, m| r.pooled_history(m, HistoryMetric::Ema, None),
        rmse_ratio: true,
    },
    DrawFigure {
        name: "EMA interior",
        read: |r, m| r.pooled_history(m, HistoryMetric::Ema, Some(Region::Interior)),
        rmse_ratio: true,
    },
    DrawFigure {
        name: "EMA + G1 whole",
        read: |r, m| r.pooled_history(m, HistoryMetric::EmaBlur1, None),
        rmse_ratio: true,
    },
    DrawFigure {
        name: "EMA + G1 interior",
        read: |r, m| r.pooled_history(m, HistoryMetric::EmaBlur1, Some(Region::Interior)),
        rmse_ratio: true,
    },
    DrawFigure {
        name: "mean 8 whole",
        read: |r, m| r.accumulated_region(m, 8, None),
        rmse_ratio: true,
    },
    DrawFigure {
        name: "mean 32 whole",
        read: |r, m| r.accumulated_region(m, 32, None),
        rmse_ratio: true,
    },
    DrawFigure {
        name: "mean 32 interior",
        read: |r, m| r.accumulated_region(m, 32, Some(Region::Interior)),
        rmse_ratio: true,
    },
    DrawFigure {
        name: "mean 128 whole",
        read: |r, m| r.accumulated_region(m, 128, None),
        rmse_ratio: true,
    },
    DrawFigure {
        name: "taa whole",
        read: |r, m| r.pooled_filtered(m, FilterChain::Taa, None, from(r)),
        rmse_ratio: true,
    },
    DrawFigure {
        name: "taa+atrous whole",
        read: |r, m| r.pooled_filtered(m, FilterChain::TaaAtrous, None, from(r)),
        rmse_ratio: true,
    },
    DrawFigure {
        name: "taa+atrous interior",
        read: |r, m| r.pooled_filtered(m, FilterChain::TaaAtrous, Some(Region::Interior), from(r)),
        rmse_ratio: true,
    },
    DrawFigure {
        name: "its noise part interior",
        read: |r, m| r.pooled_filtered_noise(m, FilterChain::TaaAtrous, Some(Region::Interior), from(r)),
        rmse_ratio: true,
    },
];

/// Mean, least and greatest of one figure over the draws.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spread {
    /// Arithmetic mean of the draws' figures.
    pub mean: f64,
    /// The least draw's figure.
    pub min: f64,
    /// The greatest draw's figure.
    pub max: f64,
    /// Number of draws.
    pub draws: usize,
}

impl Spread {
    /// The spread of `values`; `None` if any draw lacks the figure (or is
    /// not finite), or there are none: a mean over fewer draws than the
    /// others would not compare.
    pub fn of(values: &[Option<f64>]) -> Option<Spread> {
        let v: Vec<f64> = values.iter().copied().collect::<Option<_>>()?;
        if v.is_empty() || v.iter().any(|x| !x.is_finite()) {
            return None;
        }
        Some(Spread {
            mean: v.iter().sum::<f64>() / v.len() as f64,
            min: v.iter().copied().fold(f64::INFINITY, f64::min),
            max: v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            draws: v.len(),
        })
    }

    /// `mean (min-max)`, three decimals; the value alone for one draw.
    pub fn cell(&self) -> String {
        if self.draws == 1 {
            format!("{:.3}", self.mean)
        } else {
            format!("{:.3} ({:.3}-{:.3})", self.mean, self.min, self.max)
        }
    }

    /// [`Self::cell`] for differences: every number signed, the range as
    /// `min..max`.
    pub fn signed_cell(&self) -> String {
        if self.draws == 1 {
            format!("{:+.3}", self.mean)
        } else {
            format!("{:+.3} ({:+.3}..{:+.3})", self.mean, self.min, self.max)
        }
    }
}

/// Markdown tables of [`DRAW_FIGURES`] over `draws` (one study result per
/// draw, the same rows in each): per row (white left out, it is 1 by
/// definition) each figure's mean and range; with the null row
/// ([`Method::WhiteControl`]) and another row, each other row against both
/// white draws pooled ([`pooled_with_null`]); then, with two rows or more
/// besides the null row, each later row's figures minus the first row's in
/// the same draw, mean and range. A draw moves every row alike (the same
/// white, reference and geometry), so a difference of one sign in every draw
/// says more than two overlapping ranges.
pub fn draws_markdown(draws: &[StudyResult]) -> String {
    let mut s = spread_markdown(draws);
    s += &null_markdown(draws);
    s += &paired_markdown(draws);
    s
}

/// The rows of the draws' tables: the first draw's, white left out.
fn rows(draws: &[StudyResult]) -> Vec<Method> {
    draws.first().map_or(Vec::new(), |r| {
        r.runs
            .iter()
            .map(|run| run.method)
            .filter(|&m| m != Method::White)
            .collect()
    })
}

/// The table header: `first` column, then every figure.
fn header(first: &str) -> String {
    let mut s = format!("| {first}");
    for f in &DRAW_FIGURES {
        s += &format!(" | {}", f.name);
    }
    s += " |\n|---";
    s += &"|---".repeat(DRAW_FIGURES.len());
    s += "|\n";
    s
}

/// Each row's figures over the draws: mean (least-greatest).
fn spread_markdown(draws: &[StudyResult]) -> String {
    let Some(first) = draws.first() else {
        return String::new();
    };
    let salts: Vec<String> = draws.iter().map(|r| r.config.salt.to_string()).collect();
    let mut s = format!(
        "Over {} draws (salts {}) of {}: mean (least-greatest), white = 1 in each draw:\n\n",
        draws.len(),
        salts.join(", "),
        first.config.scene.name()
    );
    s += &header("method");
    for m in rows(draws) {
        s += &format!("| {}", m.name());
        s += &row_cells(draws, |r, f| (f.read)(r, m), Spread::cell);
    }
    s
}

/// One table row's cells: per figure of [`DRAW_FIGURES`], the spread over
/// `draws` of `value(draw, figure)` written by `cell` (`-` where a draw
/// lacks it), and the row's end.
fn row_cells(
    draws: &[StudyResult],
    value: impl Fn(&StudyResult, &DrawFigure) -> Option<f64>,
    cell: fn(&Spread) -> String,
) -> String {
    let mut s = String::new();
    for f in &DRAW_FIGURES {
        let values: Vec<Option<f64>> = draws.iter().map(|r| value(r, f)).collect();
        s += &format!(" | {}", Spread::of(&values).map_or("-".to_string(), |v| cell(&v)));
    }
    s + " |\n"
}

/// Each row but the null row against white and the null row pooled
/// ([`pooled_with_null`]), draw by draw: mean (least-greatest); empty
/// without the null row or without another row.
fn null_markdown(draws: &[StudyResult]) -> String {
    let rows = rows(draws);
    let null = Method::WhiteControl;
    if !rows.contains(&null) || rows.len() < 2 {
        return String::new();
    }
    let mut s = format!(
        "\nAgainst both draws of white (white and {} pooled: each figure r / sqrt((1 + c^2) / 2), c the null \
         row's figure in the same draw; white's own chance weighs half), mean (least-greatest):\n\n",
        null.name()
    );
    s += &header("method");
    for m in rows.into_iter().filter(|&m| m != null) {
        s += &format!("| {}", m.name());
        let pooled = |r: &StudyResult, f: &DrawFigure| {
            if !f.rmse_ratio {
                return None;
            }
            Some(pooled_with_null((f.read)(r, m)?, (f.read)(r, null)?))
        };
        s += &row_cells(draws, pooled, Spread::cell);
    }
    s
}

/// Each later row's figures minus the first row's, draw by draw: mean
/// (least-greatest); the null row takes no part; empty with fewer than two
/// rows.
fn paired_markdown(draws: &[StudyResult]) -> String {
    let rows: Vec<Method> = rows(draws)
        .into_iter()
        .filter(|&m| m != Method::WhiteControl)
        .collect();
    let Some((&base, others)) = rows.split_first() else {
        return String::new();
    };
    if others.is_empty() {
        return String::new();
    }
    let mut s = format!(
        "\nPaired by draw: each row's figure minus {}'s in the same draw, mean (least-greatest); one sign \
         in every draw is a difference the draws do not explain:\n\n",
        base.name()
    );
    s += &header("method");
    for &m in others {
        s += &format!("| {} - {}", m.name(), base.name());
        let difference = |r: &StudyResult, f: &DrawFigure| Some((f.read)(r, m)? - (f.read)(r, base)?);
        s += &row_cells(draws, difference, Spread::signed_cell);
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_spread_is_the_mean_and_range_of_every_draw() {
        let s = Spread::of(&[Some(0.6), Some(0.62), Some(0.59)]).expect("three draws");
        assert!((s.mean - 0.603_333).abs() < 1e-6);
        assert_eq!((s.min, s.max, s.draws), (0.59, 0.62, 3));
        assert_eq!(s.cell(), "0.603 (0.590-0.620)");
        assert_eq!(Spread::of(&[Some(0.5)]).expect("one").cell(), "0.500");
        let d = Spread::of(&[Some(-0.007), Some(-0.005), Some(0.001)]).expect("three");
        assert_eq!(d.signed_cell(), "-0.004 (-0.007..+0.001)");
    }

    #[test]
    fn a_draw_without_the_figure_gives_no_spread() {
        assert_eq!(Spread::of(&[Some(0.6), None]), None);
        assert_eq!(Spread::of(&[Some(0.6), Some(f64::NAN)]), None);
        assert_eq!(Spread::of(&[]), None);
    }

    #[test]
    fn pooling_with_the_null_row_halves_whites_share() {
        // A null row equal to white leaves the figure as it is.
        assert!((pooled_with_null(0.6, 1.0) - 0.6).abs() < 1e-12);
        // White drawn low (the null row reads high): every row reads high
        // against white alone; pooled it reads against the two draws' RMSE.
        let (w, c, m) = (0.9_f64, 1.1_f64, 0.63_f64);
        let pooled = m / ((w * w + c * c) / 2.0).sqrt();
        assert!((pooled_with_null(m / w, c / w) - pooled).abs() < 1e-12);
        assert!(pooled_with_null(m / w, c / w) < m / w);
    }

    #[test]
    fn no_draws_give_no_table() {
        assert!(draws_markdown(&[]).is_empty());
    }
}
