//! The motion study over several draws (`conformance motion --draws N`): the
//! same sequences at consecutive salts (each salt draws the white seeds and
//! the a-priori samplers' placement, [`MotionConfig::salt`](super::config::MotionConfig::salt)),
//! then per sequence and row every figure's mean and range, and each later
//! row's figures minus the first row's, draw by draw. Single runs of two
//! reprojection settings scatter by up to 4.4% (QUALITY.md, "Slow surfaces
//! keep their seeds"); issue 29's 2% criterion is a paired question.

use super::method::MotionMethod;
use super::result::{CaseResult, Figure};
use super::tables::table_header;
use crate::study::Spread;

/// Markdown tables of `draws` (one [`run_study`](super::sequence::run_study)
/// result per draw, the same sequences and rows in each): white = 1 in each
/// draw, mean (least-greatest); then, with two rows or more besides white
/// and the null row ([`MotionMethod::WhiteControl`]), each later row minus
/// the first, draw by draw.
pub fn draws_markdown(draws: &[Vec<CaseResult>]) -> String {
    let Some(first) = draws.first() else {
        return String::new();
    };
    let rows: Vec<MotionMethod> = first
        .first()
        .map_or(Vec::new(), |c| c.runs.iter().map(|r| r.method).collect())
        .into_iter()
        .filter(|&m| m != MotionMethod::White)
        .collect();
    let salts: Vec<String> = draws
        .iter()
        .filter_map(|d| d.first().map(|c| c.config.salt.to_string()))
        .collect();
    let header = table_header;
    let figure = |case: usize, m: MotionMethod, f: Figure| -> Vec<Option<f64>> {
        draws
            .iter()
            .map(|d| d.get(case).and_then(|c| c.relative(m, f)))
            .collect()
    };
    let mut s = format!(
        "Over {} draws (salts {}): mean (least-greatest), white = 1 in each draw:\n\n",
        draws.len(),
        salts.join(", ")
    );
    s += &header("sequence");
    for (k, case) in first.iter().enumerate() {
        for &m in &rows {
            s += &format!("| {} | {} |", case.case.name(), m.name());
            for f in Figure::COLUMNS {
                let cell = Spread::of(&figure(k, m, f)).map_or("-".to_string(), |v| v.cell());
                s += &format!(" {cell} |");
            }
            s += "\n";
        }
    }
    // The null row (another draw of white) is read in the first table, not
    // paired: its figures say how far from 1 chance alone moves a row.
    let paired: Vec<MotionMethod> = rows
        .iter()
        .copied()
        .filter(|&m| m != MotionMethod::WhiteControl)
        .collect();
    let Some((&base, others)) = paired.split_first() else {
        return s;
    };
    if others.is_empty() {
        return s;
    }
    s += &format!(
        "\nPaired by draw: each row's figure minus {}'s in the same draw and sequence, relative to {}'s \
         (mean (least..greatest) of (row - first) / first); one sign in every draw is a difference the draws \
         do not explain:\n\n",
        base.name(),
        base.name()
    );
    s += &header("sequence");
    for (k, case) in first.iter().enumerate() {
        for &m in others {
            s += &format!("| {} | {} |", case.case.name(), m.name());
            for f in Figure::COLUMNS {
                let rel: Vec<Option<f64>> = figure(k, m, f)
                    .into_iter()
                    .zip(figure(k, base, f))
                    .map(|(a, b)| Some((a? - b?) / b?))
                    .collect();
                let cell = Spread::of(&rel).map_or("-".to_string(), |v| v.signed_cell());
                s += &format!(" {cell} |");
            }
            s += "\n";
        }
    }
    s
}
