//! Tests of the render loops ([`super`]).

use super::*;
use crate::camera_path::{CameraPath, CameraPathKind};
use crate::cornell::cornell_box;
use crate::timeline::Timeline;
use kernels::abi::SAMPLER_ZSOBOL;

fn job(sampler: u32, mode: PermuteMode) -> RenderJob {
    let mut settings = TraceSettings::new(24, 20);
    settings.sampler = sampler;
    settings.max_depth = 3;
    RenderJob {
        settings,
        frames: 4,
        mode,
        block: 4,
        tile: TileChoice::Tile64,
        salt: 0,
    }
}

/// With nothing moving, the hold mode's homes are the pixels: the same
/// image, bit for bit, as the spatiotemporal sampler reading its shifts
/// at the pixels (white mode, whose seeds it does not read).
#[test]
fn a_still_hold_is_the_screen_fixed_sampler() {
    let scene = SceneGpu::build(&cornell_box()).unwrap();
    let hold = render_cpu(&scene, &job(SAMPLER_SPATIOTEMPORAL, PermuteMode::Hold), |_, _| {}).unwrap();
    let white = render_cpu(
        &scene,
        &job(SAMPLER_SPATIOTEMPORAL, PermuteMode::White),
        |_, _| {},
    )
    .unwrap();
    assert_eq!(hold.last, white.last);
    assert_eq!(hold.mean, white.mean);
    assert!(hold.mean.iter().any(|c| c.x > 0.0), "the Cornell box renders");
}

/// ZSobol on every decision takes the hold mode: still, its homes are
/// the pixels and the image is white mode's bit for bit (depth 3, so no
/// Russian roulette reads the homes' streams); the hold mode tells the
/// kernels that the buffer holds homes and advances their streams by
/// frame; ZSobol's jitter alone (the rest from the stream) is refused.
#[test]
fn zsobol_holds_its_points_at_the_homes() {
    let scene = SceneGpu::build(&cornell_box()).unwrap();
    let hold_job = job(SAMPLER_ZSOBOL, PermuteMode::Hold);
    let hold = render_cpu(&scene, &hold_job, |_, _| {}).unwrap();
    let white = render_cpu(&scene, &job(SAMPLER_ZSOBOL, PermuteMode::White), |_, _| {}).unwrap();
    assert_eq!(hold.last, white.last);
    assert_eq!(hold.mean, white.mean);
    assert!(hold.mean.iter().any(|c| c.x > 0.0), "the Cornell box renders");
    let layout = hold_job.validate().unwrap();
    let settings = hold_job.settings_for(&layout);
    assert_eq!(settings.sampler, SAMPLER_ZSOBOL | SAMPLER_FOLLOW_HOMES);
    assert_eq!(settings.seed_mode, SEED_MODE_ADVANCE);
    let white_job = job(SAMPLER_ZSOBOL, PermuteMode::White);
    let settings = white_job.settings_for(&white_job.validate().unwrap());
    assert_eq!((settings.sampler, settings.seed_mode), (SAMPLER_ZSOBOL, 0));
    for sampler in [SAMPLER_ZSOBOL | SAMPLER_JITTER_ONLY, kernels::abi::SAMPLER_SEEDS] {
        let err = job(sampler, PermuteMode::Hold).validate().unwrap_err();
        assert!(
            matches!(&err, RenderError::Incompatible(m) if m.contains("ZSobol on every decision")),
            "{err}"
        );
    }
}

/// The temporal mode permutes seeds: the spatiotemporal sampler on every
/// decision is refused, its jitter alone (the Kronecker sequence's too, the
/// rest from the seeds) renders and moves the image as a permutation does.
#[test]
fn the_temporal_mode_takes_the_spatiotemporal_jitter_only() {
    use kernels::abi::SAMPLER_KRONECKER;
    let err = job(SAMPLER_SPATIOTEMPORAL, PermuteMode::Temporal)
        .validate()
        .unwrap_err();
    assert!(
        matches!(&err, RenderError::Incompatible(m) if m.contains("draws every number")),
        "{err}"
    );
    let scene = SceneGpu::build(&cornell_box()).unwrap();
    let jitter = SAMPLER_SPATIOTEMPORAL | SAMPLER_KRONECKER | SAMPLER_JITTER_ONLY;
    let temporal = render_cpu(&scene, &job(jitter, PermuteMode::Temporal), |_, _| {}).unwrap();
    let white = render_cpu(&scene, &job(jitter, PermuteMode::White), |_, _| {}).unwrap();
    assert!(temporal.mean.iter().any(|c| c.x > 0.0), "the Cornell box renders");
    assert_ne!(temporal.last, white.last, "the seeds are permuted, not fresh");
}

/// A camera panning `speed` pixels a frame at the back wall.
fn pan_at(speed: f32) -> Timeline {
    Timeline {
        camera_path: Some(CameraPath {
            kind: CameraPathKind::Pan,
            speed,
        }),
        ..Timeline::still()
    }
}

/// In motion, reprojection moves the homes: the frames after the first
/// differ from those of homes left at their pixels, and the first agrees.
/// (For the spatiotemporal sampler and for ZSobol.)
#[test]
fn reprojection_moves_the_homes_in_motion() {
    let base = cornell_box();
    let timeline = pan_at(1.5);
    for sampler in [SAMPLER_SPATIOTEMPORAL, SAMPLER_ZSOBOL] {
        let job = job(sampler, PermuteMode::Hold);
        let mut frames = [Vec::new(), Vec::new()];
        for (k, reproject) in [false, true].into_iter().enumerate() {
            let mut sequence = SceneSequence::new(&base, timeline.clone(), 20).unwrap();
            let options = SequenceOptions {
                reproject,
                ..SequenceOptions::default()
            };
            render_sequence_cpu(&mut sequence, &job, options, |f| frames[k].push(f.color.to_vec())).unwrap();
        }
        assert_eq!(frames[0][0], frames[1][0], "sampler {sampler}");
        assert_ne!(frames[0][3], frames[1][3], "sampler {sampler}");
    }
}

/// Seeds of surfaces slower than `reproject_hold_below` stay: with the
/// threshold above the pan's 1.5 px/frame the frames are those of no
/// reprojection, bit for bit; at 0 they are the reprojected ones, and
/// below the pan's speed they differ from no reprojection; a NaN,
/// infinite or negative threshold is refused. A frame-wide follow share no
/// frame reaches (every pixel rigid, the border included) changes nothing;
/// a share outside `[0, 1]` is refused.
#[test]
fn slow_surfaces_keep_their_seeds_under_reprojection() {
    let base = cornell_box();
    let timeline = pan_at(1.5);
    let job = job(kernels::abi::SAMPLER_SEEDS, PermuteMode::Temporal);
    let render = |reproject: bool, hold_below: f32, follow_share: f32| {
        let mut sequence = SceneSequence::new(&base, timeline.clone(), 20).unwrap();
        let options = SequenceOptions {
            reproject,
            reproject_hold_below: hold_below,
            reproject_follow_share: follow_share,
            ..SequenceOptions::default()
        };
        let mut frames = Vec::new();
        render_sequence_cpu(&mut sequence, &job, options, |f| frames.push(f.color.to_vec())).map(|_| frames)
    };
    let still_seeds = render(false, 0.0, 0.0).unwrap();
    let followed = render(true, 0.0, 0.0).unwrap();
    assert_ne!(followed[3], still_seeds[3]);
    assert_eq!(render(true, 100.0, 0.0).unwrap(), still_seeds);
    assert!(
        render(true, 100.0, 1.0).unwrap() == still_seeds,
        "a share of 1 moved seeds"
    );
    // The back wall slides rigidly at 1.5 px/frame: past a small share the
    // seeds follow in those frames, whatever the speed threshold.
    let rigid = render(true, 100.0, 0.05).unwrap();
    assert!(rigid[3] != still_seeds[3], "no seed followed past the share");
    // Below the walls' 1.5 px/frame: they follow (the background,
    // still under a pan, holds).
    assert_ne!(render(true, 1.0, 0.0).unwrap()[3], still_seeds[3]);
    for bad in [f32::NAN, -1.0, f32::INFINITY] {
        let e = render(true, bad, 0.0).unwrap_err();
        assert!(matches!(e, RenderError::BadOption(_)), "{e}");
    }
    for bad in [f32::NAN, -0.1, 1.5] {
        let e = render(true, 6.0, bad).unwrap_err();
        assert!(matches!(e, RenderError::BadOption(_)), "{e}");
    }
}

/// The temporal mode renders on the CPU: its first frame is the
/// permutation's (the same white seeds), later ones differ (another
/// sorting target); with the feature-aware permutation too, the first
/// frame again and later ones its own; it refuses the 128 tile and the
/// spatiotemporal sampler before any work.
#[test]
fn temporal_mode_renders_and_refuses_what_it_cannot_take() {
    let scene = SceneGpu::build(&cornell_box()).unwrap();
    let features = SequenceOptions {
        features: true,
        ..SequenceOptions::default()
    };
    let mut frames = [Vec::new(), Vec::new(), Vec::new()];
    for (k, (mode, options)) in [
        (PermuteMode::Permute, SequenceOptions::default()),
        (PermuteMode::Temporal, SequenceOptions::default()),
        (PermuteMode::Temporal, features),
    ]
    .into_iter()
    .enumerate()
    {
        let mut sequence = SceneSequence::still(&scene, 20);
        let job = job(kernels::abi::SAMPLER_SEEDS, mode);
        render_sequence_cpu(&mut sequence, &job, options, |f| frames[k].push(f.color.to_vec())).unwrap();
    }
    assert_eq!(frames[0][0], frames[1][0]);
    assert_eq!(frames[0][0], frames[2][0]);
    assert_ne!(frames[0][2], frames[1][2]);
    assert_ne!(frames[1][2], frames[2][2]);
    let temporal = job(kernels::abi::SAMPLER_SEEDS, PermuteMode::Temporal);
    let tile128 = RenderJob {
        tile: TileChoice::Tile128,
        ..temporal
    };
    let spatiotemporal = job(SAMPLER_SPATIOTEMPORAL, PermuteMode::Temporal);
    for (job, says) in [(tile128, "64 tile"), (spatiotemporal, "spatiotemporal sampler")] {
        let e = job.validate().unwrap_err();
        assert!(
            matches!(e, RenderError::Incompatible(_)) && e.to_string().contains(says),
            "{e}"
        );
    }
}

/// The hold mode with a sampler that reads the seeds is refused before
/// any work.
#[test]
fn hold_needs_the_spatiotemporal_sampler() {
    let scene = SceneGpu::build(&cornell_box()).unwrap();
    let mut frames = 0;
    let e = render_cpu(
        &scene,
        &job(kernels::abi::SAMPLER_SEEDS, PermuteMode::Hold),
        |_, _| frames += 1,
    )
    .unwrap_err();
    assert!(matches!(e, RenderError::Incompatible(_)), "{e}");
    assert!(e.to_string().contains("spatiotemporal"), "{e}");
    assert_eq!(frames, 0);
}
