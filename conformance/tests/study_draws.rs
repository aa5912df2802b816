//! The study over several draws (`conformance study --draws N`): each salt
//! draws the a-priori samplers' placement as well as the white seeds, and
//! the draws' table reads every draw.

use conformance::study::{
    draws_markdown, Method, Metric, Spread, Study, StudyConfig, StudyResult, GOAL_FRAME,
};

/// A tiny study of `rows` at `salt` (no reference cache: 32x32, 16 spp).
fn tiny(salt: u32, rows: &[Method]) -> StudyResult {
    let config = StudyConfig {
        salt,
        filters: false,
        ..StudyConfig::new(32, 1, 20, 16)
    };
    let study = Study::new(config, None, |_, _| {}).expect("study setup");
    study.run(rows, |_, _| {}).expect("study run")
}

#[test]
fn a_salt_draws_the_a_priori_samplers_and_the_table_reads_every_draw() {
    let rows = [Method::White, Method::SpatiotemporalKronecker, Method::ZSobol];
    let draws = [tiny(1, &rows), tiny(2, &rows)];
    let from = GOAL_FRAME as usize;
    for m in [Method::SpatiotemporalKronecker, Method::ZSobol] {
        // White seeds drive nothing in these rows: a different figure at
        // another salt is the samplers' origin moving.
        let blur: Vec<f64> = draws
            .iter()
            .map(|r| r.run(m).expect("row").blur1[from..].iter().sum())
            .collect();
        assert_ne!(blur[0], blur[1], "{}: the same frames at two salts", m.name());
        let rel: Vec<Option<f64>> = draws.iter().map(|r| r.pooled(m, Metric::Blur1, from)).collect();
        let spread = Spread::of(&rel).expect("both draws");
        assert!((spread.mean - (rel[0].unwrap() + rel[1].unwrap()) / 2.0).abs() < 1e-12);
    }
    let table = draws_markdown(&draws);
    assert!(table.contains("Over 2 draws (salts 1, 2)"), "{table}");
    assert!(table.contains("| spatiotemporal-kronecker | "), "{table}");
    assert!(
        table.contains("| zsobol - spatiotemporal-kronecker | "),
        "{table}"
    );
    assert!(!table.contains("| white |"), "{table}");
}
