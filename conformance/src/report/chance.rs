//! What chance reads in the report: the null row
//! ([`crate::study::Method::WhiteControl`]) is white noise from an independent
//! draw, equal to white in expectation, so its distance from 1 in a figure is
//! how far that figure moves by luck alone at the report's size and frame
//! count. A lead smaller than that distance is not evidence.

use crate::study::Spread;

/// The lowest and highest of the finite, positive values of `values` (the null
/// row's figures; 0 marks a figure below the reference's own noise, not ranked);
/// `None` when there is none.
pub fn range(values: &[f64]) -> Option<(f64, f64)> {
    let ranked: Vec<Option<f64>> = values
        .iter()
        .filter(|v| v.is_finite() && **v > 0.0)
        .map(|&v| Some(v))
        .collect();
    Spread::of(&ranked).map(|s| (s.min, s.max))
}

/// How far from 1 a range strays: the larger of `|1 - lowest|` and
/// `|highest - 1|`.
pub fn distance((lo, hi): (f64, f64)) -> f64 {
    (1.0 - lo).abs().max((hi - 1.0).abs())
}

/// The summary's sentence on chance, from the null row's range over the
/// figures the summary ranks; empty without the null row.
pub fn sentence(null: Option<(f64, f64)>) -> String {
    let Some((lo, hi)) = null else {
        return String::new();
    };
    format!(
        " <b>Chance</b>: the row <i>white-control</i> is white noise from an independent draw (the null row), \
equal to white in expectation; in the figures ranked above it reads {lo:.3}-{hi:.3}, so a lead smaller than about \
{:.0}% of white's error there is within chance at this size and frame count.",
        100.0 * distance((lo, hi))
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn range_skips_what_is_not_ranked() {
        assert_eq!(
            range(&[f64::NAN, 1.2, 0.0, 0.9, f64::INFINITY, 1.0]),
            Some((0.9, 1.2))
        );
        assert_eq!(range(&[f64::NAN, 0.0]), None);
        assert_eq!(range(&[]), None);
    }

    #[test]
    fn distance_is_the_farther_side_from_one() {
        assert!((distance((0.95, 1.02)) - 0.05).abs() < 1e-12);
        assert!((distance((0.98, 1.08)) - 0.08).abs() < 1e-12);
        assert_eq!(distance((1.0, 1.0)), 0.0);
    }

    #[test]
    fn the_sentence_gives_the_range_and_the_distance() {
        let s = sentence(Some((0.97, 1.04)));
        assert!(s.contains("reads 0.970-1.040"), "{s}");
        assert!(s.contains("about 4% of white's error"), "{s}");
        assert_eq!(sentence(None), "");
    }
}
