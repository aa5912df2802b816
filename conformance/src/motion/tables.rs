//! Markdown tables of the motion study: column headers and the per-sequence,
//! versus-static and diagnostics tables.

use super::case::MotionCase;
use super::history::HISTORY_ALPHA;
use super::method::MotionMethod;
use super::result::{CaseResult, Figure, EMA_FROM};
use crate::metrics::regions::Region;
use crate::study::GOAL_FRAME;

impl Figure {
    /// The columns of the tables, in order.
    pub const COLUMNS: [Figure; 11] = [
        Figure::LowFrequency,
        Figure::Blur(None),
        Figure::Blur(Some(Region::Emitter)),
        Figure::Blur(Some(Region::Edge)),
        Figure::Blur(Some(Region::Interior)),
        Figure::Ema { interior: false },
        Figure::Ema { interior: true },
        Figure::EmaNoise { interior: false },
        Figure::EmaNoise { interior: true },
        Figure::Filtered { interior: false },
        Figure::Filtered { interior: true },
    ];

    /// Column header.
    pub fn header(self) -> &'static str {
        match self {
            Figure::LowFrequency => "LF mean 8..",
            Figure::Blur(None) => "blur s1",
            Figure::Blur(Some(Region::Emitter)) => "blur emitter",
            Figure::Blur(Some(Region::Edge)) => "blur edges",
            Figure::Blur(Some(Region::Interior)) => "blur interior",
            Figure::Ema { interior: false } => "EMA",
            Figure::Ema { interior: true } => "EMA interior",
            Figure::EmaNoise { interior: false } => "EMA noise part",
            Figure::EmaNoise { interior: true } => "EMA noise part interior",
            Figure::Filtered { interior: false } => "taa+atrous",
            Figure::Filtered { interior: true } => "taa+atrous interior",
        }
    }
}

/// The header of a table with one row per sequence and method: the `first`
/// column, the method, then [`Figure::COLUMNS`].
pub(crate) fn table_header(first: &str) -> String {
    let mut h = format!("| {first} | method |");
    let mut sep = "|---|---|".to_string();
    for f in Figure::COLUMNS {
        h += &format!(" {} |", f.header());
        sep += "---|";
    }
    format!("{h}\n{sep}\n")
}

/// The study's markdown tables: figures relative to white per sequence, the moving
/// sequences relative to the same method's static figures, and the diagnostics. The
/// first result must be the still sequence (as
/// [`run_study`](super::sequence::run_study) returns them).
pub fn markdown(results: &[CaseResult]) -> String {
    let mut s = String::new();
    let Some(first) = results.first() else {
        return s;
    };
    let c = &first.config;
    s += &format!(
        "Cornell box {0}x{0}, 1 spp, {1} frames, depth {2}, reference {3} spp per pose, block {4}, tile {5}; \
         LF and blur over frames {6}.., EMA (alpha {7}) over frames {8}..\n\n",
        c.size,
        c.frames,
        c.max_depth,
        c.ref_spp / 2 * 2,
        c.block,
        c.tile.side(),
        GOAL_FRAME,
        HISTORY_ALPHA,
        EMA_FROM
    );
    s += "LF insets (x0, y0, side at frame 0; they follow their surface):\n";
    for r in results {
        s += &format!("- {}:", r.case.name());
        for (i, _) in r.insets.iter().zip(&r.own_insets).filter(|(_, own)| **own) {
            s += &format!(" {} ({}, {}, {});", i.name, i.x0, i.y0, i.side);
        }
        s += "\n";
    }
    s += "\n";
    let header = table_header;
    let cell = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.3}"));
    s += "White = 1:\n\n";
    s += &header("sequence");
    for r in results {
        for run in &r.runs {
            s += &format!("| {} | {} |", r.case.name(), run.method.name());
            for f in Figure::COLUMNS {
                s += &format!(" {} |", cell(r.relative(run.method, f)));
            }
            s += "\n";
        }
    }
    let still = results.iter().find(|r| r.case == MotionCase::Still);
    if let Some(still) = still {
        s += "\nIn motion / the same method's static figure (both white = 1; goals: <= 1.1 at 0.5 px/frame, \
              <= 1.25 at 2 px/frame, with reprojection):\n\n";
        s += &header("sequence");
        for r in results.iter().filter(|r| r.case != MotionCase::Still) {
            for run in r.runs.iter().filter(|x| x.method != MotionMethod::White) {
                s += &format!("| {} | {} |", r.case.name(), run.method.name());
                for f in Figure::COLUMNS {
                    s += &format!(" {} |", cell(r.versus_static(still, run.method, f)));
                }
                s += "\n";
            }
        }
    }
    s += "\nSequences (fractions of the image, mean over frames 1..):\n\n";
    s += "| sequence | motion | centre px/frame | mean px/frame | seeds followed | recycled | stayed in pixel | homes in order | moving rigidly | frames following \
          | rigid motion spread | frames moving the pan offset | history resets | emitter / edges / interior | poses |\n\
          |---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for r in results {
        let st = &r.stats;
        s += &format!(
            "| {} | {} | {:.2} | {:.2} | {:.3} | {:.4} | {:.3} | {:.3} | {:.3} | {:.3} | {} | {:.3} | {:.4} | {:.3} / {:.3} / {:.3} | {} |\n",
            r.case.name(),
            r.description,
            st.centre_speed,
            st.mean_speed,
            st.followed,
            st.recycled,
            st.stayed,
            st.homes_in_order,
            st.rigid_share,
            st.frames_following,
            if st.frames_sampled > 0.0 { format!("{:.3}", st.rigid_spread) } else { "-".into() },
            st.frames_moving_offset,
            st.history_resets,
            st.region_share[0],
            st.region_share[1],
            st.region_share[2],
            st.poses
        );
    }
    s
}
