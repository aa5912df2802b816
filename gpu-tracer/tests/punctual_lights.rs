//! Point, spot and directional lights light a Lambertian floor as the
//! `KHR_lights_punctual` formulas say: rendered on the CPU, a pixel looking
//! straight down at the floor reads `albedo / pi * E`, with `E` the
//! irradiance the light's formula gives there.

use glam::{Vec3, Vec4};
use gpu_tracer::cpu::{render_frame, white_seeds};
use gpu_tracer::scene::{Light, LightKind, Scene, SceneGpu};
use gpu_tracer::TraceSettings;
use std::f32::consts::PI;

mod common;

const ALBEDO: f32 = 0.5;

/// The shared floor of albedo [`ALBEDO`] under `lights`.
fn floor(lights: Vec<Light>) -> SceneGpu {
    SceneGpu::build(&common::floor_scene(ALBEDO, lights, None)).expect("scene")
}

/// Mean and standard error of the red channel over an 8x8 frame of `spp`
/// samples per pixel, direct light only (depth 2).
fn render(scene: &SceneGpu, spp: u32) -> (f64, f64) {
    let mut settings = TraceSettings::new(8, 8);
    settings.spp = spp;
    settings.max_depth = 2;
    let params = scene.trace_params(&settings, 0).expect("params");
    let seeds = white_seeds(settings.padded_width, settings.height, 3);
    let mut color = vec![Vec4::ZERO; 64];
    render_frame(scene, &params, &seeds, &mut color).expect("render");
    let n = color.len() as f64;
    let mean = color.iter().map(|c| c.x as f64).sum::<f64>() / n;
    let var = color.iter().map(|c| (c.x as f64 - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

fn assert_close(got: f64, want: f32, rel: f64, what: &str) {
    let want = want as f64;
    assert!(
        (got - want).abs() <= rel * want.abs() + 1e-7,
        "{what}: rendered {got}, formula {want}"
    );
}

#[test]
fn a_point_light_follows_the_inverse_square_law() {
    // 8 cd at height 2: E = 8 / 4 = 2 under the light.
    let scene = floor(vec![Light::point("bulb", Vec3::new(0.0, 2.0, 0.0), 8.0)]);
    let (mean, _) = render(&scene, 1);
    assert_close(mean, ALBEDO / PI * 2.0, 1e-3, "point");
    // With range 4, the window 1 - (2/4)^4 = 15/16.
    let ranged = floor(vec![Light {
        range: Some(4.0),
        ..Light::point("bulb", Vec3::new(0.0, 2.0, 0.0), 8.0)
    }]);
    assert_close(
        render(&ranged, 1).0,
        ALBEDO / PI * 2.0 * 15.0 / 16.0,
        1e-3,
        "ranged point",
    );
    // Coloured: each channel scales.
    let red = floor(vec![Light {
        color: Vec3::new(0.5, 0.0, 0.0),
        ..Light::point("bulb", Vec3::new(0.0, 2.0, 0.0), 8.0)
    }]);
    assert_close(render(&red, 1).0, ALBEDO / PI, 1e-3, "coloured point");
}

#[test]
fn a_spot_light_follows_the_extension_falloff() {
    // A spot 2 units above the floor at x = -2 * tan(0.3), aimed straight
    // down: the floor under the camera is 0.3 rad off its axis, between
    // the inner (0.2) and outer (0.4) angles.
    let (inner, outer, angle) = (0.2f32, 0.4f32, 0.3f32);
    let position = Vec3::new(-2.0 * angle.tan(), 2.0, 0.0);
    let spot = |direction: Vec3| Light {
        name: "spot".into(),
        kind: LightKind::Spot {
            inner_cone_angle: inner,
            outer_cone_angle: outer,
        },
        position,
        direction,
        color: Vec3::ONE,
        intensity: 10.0,
        range: None,
    };
    let d2 = position.length_squared();
    let t = ((angle.cos() - outer.cos()) / (inner.cos() - outer.cos())).clamp(0.0, 1.0);
    let cos_surface = 2.0 / d2.sqrt();
    let want = ALBEDO / PI * 10.0 * t * t * cos_surface / d2;
    assert_close(
        render(&floor(vec![spot(-Vec3::Y)]), 1).0,
        want,
        2e-3,
        "spot in its falloff",
    );
    // Aimed at the floor point itself: full intensity.
    let aimed = spot(-position);
    assert_close(
        render(&floor(vec![aimed]), 1).0,
        ALBEDO / PI * 10.0 * cos_surface / d2,
        2e-3,
        "spot on its axis",
    );
    // Aimed away by more than the outer angle: dark.
    let away = spot(Vec3::new(-1.0, -1.0, 0.0));
    assert_eq!(render(&floor(vec![away]), 1).0, 0.0);
}

#[test]
fn a_directional_light_gives_its_illuminance_with_or_without_a_disk() {
    // 3 lux at 60 degrees from the vertical: E = 3 cos 60 = 1.5.
    let travel = Vec3::new(60f32.to_radians().sin(), -60f32.to_radians().cos(), 0.0);
    let delta = floor(vec![Light::directional("sun", travel, 3.0, 0.0)]);
    assert_close(render(&delta, 1).0, ALBEDO / PI * 1.5, 1e-3, "delta sun");
    // A disk of 0.1 rad: the mean over the disk of cos is cos 60 times
    // (1 + cos 0.1) / 2 exactly; sampling noise is small.
    let disk = floor(vec![Light::directional("sun", travel, 3.0, 0.1)]);
    let (mean, err) = render(&disk, 64);
    let want = ALBEDO / PI * 1.5 * (1.0 + 0.1f32.cos()) / 2.0;
    assert!(
        (mean - want as f64).abs() < 5.0 * err + 1e-4,
        "disk sun: {mean} vs {want} (se {err})"
    );
}

/// Two lights of different power: each sample picks one by power and
/// divides by its probability, so the mean is the sum of both.
#[test]
fn lights_picked_by_power_add_up() {
    let lights = vec![
        Light::point("near", Vec3::new(0.0, 2.0, 0.0), 8.0),
        Light::directional("sun", -Vec3::Y, 0.5, 0.0),
    ];
    let scene = floor(lights);
    assert_eq!(scene.emitter_count, 2);
    let pdfs: Vec<f32> = scene.emitters.iter().map(|e| e.pdf).collect();
    assert!(
        (pdfs[0] + pdfs[1] - 1.0).abs() < 1e-6 && pdfs[0] != pdfs[1],
        "{pdfs:?}"
    );
    let (mean, err) = render(&scene, 256);
    let want = ALBEDO / PI * (2.0 + 0.5);
    assert!(
        (mean - want as f64).abs() < 5.0 * err + 1e-4,
        "{mean} vs {want} (se {err})"
    );
}

#[test]
fn invalid_lights_are_refused_when_the_scene_is_built() {
    let bad = Light {
        intensity: -1.0,
        ..Light::point("bulb", Vec3::Y, 1.0)
    };
    let scene = Scene {
        lights: vec![bad],
        ..gpu_tracer::cornell::cornell_box()
    };
    let err = SceneGpu::build(&scene).unwrap_err();
    assert!(matches!(err, gpu_tracer::Error::InvalidLight { .. }), "{err:?}");
}
