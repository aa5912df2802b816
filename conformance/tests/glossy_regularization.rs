//! Why the glossy box's walls are white in time, checked causally at a CI
//! size (QUALITY.md, "Glossy regularisation"): with path regularisation the
//! caustics the walls receive through the spheres are found often with small
//! weights, and the walls' history turns as blue in time as the Cornell box's;
//! the study reports what that costs in bias.

use conformance::study::{default_cache_dir, Method, Study, StudyConfig, StudyResult, StudyScene};

const SIZE: u32 = 128;
const FRAMES: u32 = 48;
const REF_SPP: u32 = 256;

fn glossy_study(strength: f32) -> StudyResult {
    let config = StudyConfig {
        scene: StudyScene::CornellGlossy,
        filters: false,
        glossy_regularization: strength,
        ..StudyConfig::new(SIZE, 1, FRAMES, REF_SPP)
    };
    let study = Study::new(config, Some(&default_cache_dir()), |_, _| {}).expect("study setup");
    study
        .run(&[Method::White, Method::SpatiotemporalKronecker], |_, _| {})
        .expect("study run")
}

#[test]
fn regularised_caustics_make_the_walls_blue_in_time() {
    let row = Method::SpatiotemporalKronecker;
    let (plain, regularized) = (glossy_study(0.0), glossy_study(1.0));
    let walls = |r: &StudyResult| r.history_by_surface(row, false).expect("measured");
    let (before, after) = (walls(&plain), walls(&regularized));
    println!(
        "{}: EMA on the walls (diffuse first hits), white = 1: {before:.3} -> {after:.3}",
        row.name()
    );
    assert!(plain.regularization.is_none());
    let effect = regularized.regularization.as_ref().expect("measured");
    print!("{}", effect.markdown());
    // The walls' history: white-ish without, blue with: 0.94 -> 0.77 at this size
    // with the Kronecker jitter pair searched for the means; since the pair is
    // (sqrt 2, sqrt 3) (QUALITY.md, "The jitter's generator") the walls' edges keep
    // less without regularisation already, 0.85 -> 0.78.
    assert!(after < before - 0.05, "walls {before:.3} -> {after:.3}");
    // The interior's noise halves or so, at a bias well below white's history error.
    let interior = 2;
    assert!(effect.noise[interior] < 0.8, "{effect:?}");
    assert!(effect.bias[interior] < 0.4, "{effect:?}");
    // Where no glossy surface is seen after a rough lobe (the light), nothing moves.
    assert!((effect.noise[0] - 1.0).abs() < 0.05, "{effect:?}");
}
