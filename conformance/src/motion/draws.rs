//! The motion study over several draws (`conformance motion --draws N`): the
//! same sequences at consecutive salts (each salt draws the white seeds and
//! the a-priori samplers' placement, [`MotionConfig::salt`](super::config::MotionConfig::salt)),
//! then per sequence and row every figure's mean and range, and each later
//! row's figures minus the first row's, draw by draw. Single runs of two
//! reprojection settings scatter by up to 4.4% (QUALITY.md, "Slow surfaces
//! keep their seeds"); issue 29's 2% criterion is a paired question.

use super::case::MotionCase;
use super::method::MotionMethod;
use super::result::{CaseResult, Figure};
use super::tables::table_header;
use crate::study::Spread;

/// Markdown tables of `draws` (one [`run_study`](super::sequence::run_study)
/// result per draw, the same sequences and rows in each): white = 1 in each
/// draw, mean (least-greatest); with the still sequence among them, each
/// other sequence's figures over the same row's still ones; then, with two
/// rows or more besides white and the null row
/// ([`MotionMethod::WhiteControl`]), each later row minus the first, draw by
/// draw.
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
            s += &row_cells(|f| figure(k, m, f), Spread::cell);
        }
    }
    // Issue 29's motion figure: each sequence against the same row still,
    // draw by draw (the still sequence's own draw).
    let still = first.iter().position(|c| c.case == MotionCase::Still);
    if let Some(still) = still {
        s += "\nIn motion / the same row still (both white = 1 in their draw), mean (least-greatest) over the \
              draws:\n\n";
        s += &header("sequence");
        for (k, case) in first.iter().enumerate().filter(|&(k, _)| k != still) {
            for &m in &rows {
                s += &format!("| {} | {} |", case.case.name(), m.name());
                s += &row_cells(
                    |f| {
                        draws
                            .iter()
                            .map(|d| d.get(k)?.versus_static(d.get(still)?, m, f))
                            .collect()
                    },
                    Spread::cell,
                );
            }
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
            s += &row_cells(
                |f| {
                    figure(k, m, f)
                        .into_iter()
                        .zip(figure(k, base, f))
                        .map(|(a, b)| Some((a? - b?) / b?))
                        .collect()
                },
                Spread::signed_cell,
            );
        }
    }
    s
}

/// One table row's cells: per figure of [`Figure::COLUMNS`], the spread of
/// its draws' values written by `cell` (`-` where a draw lacks it), and the
/// row's end.
fn row_cells(values: impl Fn(Figure) -> Vec<Option<f64>>, cell: fn(&Spread) -> String) -> String {
    let mut s = String::new();
    for f in Figure::COLUMNS {
        let v = Spread::of(&values(f)).map_or("-".to_string(), |v| cell(&v));
        s += &format!(" {v} |");
    }
    s + "\n"
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::config::MotionConfig;
    use crate::motion::result::{MotionRun, SequenceStats};
    use crate::study::insets::inset_layout;

    /// A case where white's mean squared error is 4 and the permutation's
    /// `blur` (its figure `sqrt(blur / 4)`).
    fn case(case: MotionCase, blur: f64) -> CaseResult {
        let run = |method, b: f64| MotionRun {
            method,
            lf: vec![vec![1.0]; 20],
            blur: vec![[b, b, 0.0, 0.0]; 20],
            ema: vec![[b, 0.0, b, 0.0]; 20],
            filtered: vec![[b, b]; 20],
        };
        CaseResult {
            case,
            description: String::new(),
            config: MotionConfig::new(32, 20, 4),
            stats: SequenceStats::default(),
            insets: inset_layout(crate::study::StudyScene::Cornell, 32)[..1].to_vec(),
            own_insets: vec![true],
            runs: vec![run(MotionMethod::White, 4.0), run(MotionMethod::Permute, blur)],
        }
    }

    #[test]
    fn the_draws_read_each_sequence_against_the_same_row_still() {
        let orbit = MotionCase::Orbit { px_per_frame: 2.0 };
        // Still 0.5 of white in both draws; in motion 0.75 and 0.6: 1.5 and 1.2.
        let draws = [
            vec![case(MotionCase::Still, 1.0), case(orbit, 2.25)],
            vec![case(MotionCase::Still, 1.0), case(orbit, 1.44)],
        ];
        let table = draws_markdown(&draws);
        let (_, versus) = table
            .split_once("In motion / the same row still")
            .expect("the table");
        let row = versus
            .lines()
            .find(|l| l.starts_with("| orbit 2 px/frame | permute, no reprojection |"))
            .expect("the orbit's row");
        assert!(row.contains(" 1.350 (1.200-1.500) |"), "{row}");
        assert!(!versus.contains("| still |"), "{versus}");
    }
}
