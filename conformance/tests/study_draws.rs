//! The study over several draws (`conformance study --draws N`): each salt
//! draws the a-priori samplers' placement as well as the white seeds, and
//! the draws' table reads every draw; the null row is one more draw of white.

use conformance::study::{
    draws_markdown, pooled_with_null, white_control_salt, Method, Metric, Spread, Study, StudyConfig,
    StudyResult, GOAL_FRAME,
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
    let rows = [
        Method::White,
        Method::WhiteControl,
        Method::SpatiotemporalKronecker,
        Method::ZSobol,
    ];
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
    // The null row: its own figures, every other row against both white
    // draws, and no pair with it.
    assert!(table.contains("| white-control | "), "{table}");
    assert!(table.contains("Against both draws of white"), "{table}");
    assert!(!table.contains("- white-control |"), "{table}");
    let (r, null) = (&draws[0], Method::WhiteControl);
    let figure = |m| r.pooled(m, Metric::Blur1, from).expect("figure");
    let pooled = pooled_with_null(figure(Method::ZSobol), figure(null));
    assert!(
        (pooled - figure(Method::ZSobol)).abs() > 1e-9,
        "the null row moved nothing"
    );
}

#[test]
fn the_null_row_is_another_draw_of_white() {
    let rows = [Method::White, Method::WhiteControl];
    let r = tiny(1, &rows);
    let from = GOAL_FRAME as usize;
    let sum = |m: Method| -> f64 { r.run(m).expect("row").blur1[from..].iter().sum() };
    // Independent seeds: not white's frames again.
    assert_ne!(sum(Method::White), sum(Method::WhiteControl));
    // Equal to white in expectation: pooled over the frames, near 1.
    let blur = r
        .pooled(Method::WhiteControl, Metric::Blur1, from)
        .expect("figure");
    assert!((0.7..1.4).contains(&blur), "white-control raw blur {blur}");
    // Its salt never lands on a draw's salt nor on its own.
    for salt in 0..4096u32 {
        let c = white_control_salt(salt);
        assert!(c >= 4096, "salt {salt} -> {c}");
        assert_eq!(white_control_salt(c), salt);
    }
}
