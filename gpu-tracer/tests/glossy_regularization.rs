//! Path regularisation (`TraceSettings::glossy_regularization`,
//! `kernels::regularization`), rendered on the CPU: it changes nothing where
//! no glossy surface follows a rough lobe, and on the glossy Cornell box it
//! trades the walls' caustic noise for a small, bounded bias.

use glam::Vec4;
use gpu_tracer::cornell::{cornell_box, cornell_glossy};
use gpu_tracer::cpu::{render_frame, white_seeds};
use gpu_tracer::scene::SceneGpu;
use gpu_tracer::{Error, TraceSettings};

const SIDE: u32 = 64;

/// `frames` frames of `SIDE x SIDE` pixels at 1 spp, white seeds of salt
/// `frame + 1` (frames independent), luma per pixel, frame after frame.
fn render_luma(scene: &SceneGpu, max_depth: u32, strength: f32, frames: u32) -> Vec<Vec<f32>> {
    let mut settings = TraceSettings::new(SIDE, SIDE);
    settings.max_depth = max_depth;
    settings.glossy_regularization = strength;
    (0..frames)
        .map(|frame| {
            let params = scene.trace_params(&settings, frame).expect("params");
            let seeds = white_seeds(SIDE, SIDE, frame + 1);
            let mut color = vec![Vec4::ZERO; (SIDE * SIDE) as usize];
            render_frame(scene, &params, &seeds, &mut color).expect("render");
            color.iter().map(|c| sampler_core::luma(c.truncate())).collect()
        })
        .collect()
}

#[test]
fn lambertian_scenes_render_bit_for_bit_as_without_it() {
    let scene = SceneGpu::build(&cornell_box()).expect("scene");
    let off = render_luma(&scene, 8, 0.0, 4);
    let on = render_luma(&scene, 8, 1.0, 4);
    assert_eq!(off, on);
}

/// A path of two segments only reads its first vertex's BSDF, which no
/// earlier lobe regularises: glossy surfaces seen from the camera keep
/// their own roughness. Longer paths do change.
#[test]
fn glossy_surfaces_seen_from_the_camera_keep_their_roughness() {
    let scene = SceneGpu::build(&cornell_glossy()).expect("scene");
    assert_eq!(render_luma(&scene, 2, 0.0, 2), render_luma(&scene, 2, 1.0, 2));
    let (off, on) = (render_luma(&scene, 8, 0.0, 2), render_luma(&scene, 8, 1.0, 2));
    let changed = off
        .iter()
        .flatten()
        .zip(on.iter().flatten())
        .filter(|(a, b)| a != b)
        .count();
    assert!(changed > 0, "regularisation changed no pixel of the glossy box");
}

/// The glossy box at depth 8: with strength 1 the per-pixel variance over
/// frames drops (the caustics through the spheres are found often, with
/// small weights), while the image's mean moves by less than its bound.
#[test]
fn the_glossy_box_trades_caustic_noise_for_a_small_bias() {
    let scene = SceneGpu::build(&cornell_glossy()).expect("scene");
    let frames = 64;
    let stats = |strength: f32| {
        let luma = render_luma(&scene, 8, strength, frames);
        let n = (SIDE * SIDE) as usize;
        let (mut mean, mut var) = (0.0f64, 0.0f64);
        for i in 0..n {
            let m = luma.iter().map(|f| f[i] as f64).sum::<f64>() / frames as f64;
            let v = luma.iter().map(|f| (f[i] as f64 - m).powi(2)).sum::<f64>() / (frames - 1) as f64;
            mean += m / n as f64;
            var += v / n as f64;
        }
        (mean, var)
    };
    let ((mean_off, var_off), (mean_on, var_on)) = (stats(0.0), stats(1.0));
    eprintln!(
        "glossy box: mean {mean_off:.4} -> {mean_on:.4}, per-pixel variance {var_off:.5} -> {var_on:.5}"
    );
    assert!(var_on < 0.95 * var_off, "variance {var_off} -> {var_on}");
    assert!(
        (mean_on - mean_off).abs() < 0.05 * mean_off,
        "mean {mean_off} -> {mean_on}"
    );
}

#[test]
fn strengths_outside_zero_to_one_are_refused() {
    let scene = SceneGpu::build(&cornell_glossy()).expect("scene");
    let ok = TraceSettings::new(SIDE, SIDE);
    for strength in [-0.5, 1.01, f32::NAN, f32::INFINITY] {
        let bad = TraceSettings {
            glossy_regularization: strength,
            ..ok
        };
        assert!(
            matches!(
                scene.trace_params(&bad, 0),
                Err(Error::InvalidSetting {
                    name: "glossy_regularization",
                    ..
                })
            ),
            "{strength}"
        );
    }
    // Parameters written by hand are refused by the renderer too.
    let mut params = scene.trace_params(&ok, 0).expect("params");
    params.glossy_regularization = 2.0;
    let seeds = white_seeds(SIDE, SIDE, 1);
    let mut color = vec![Vec4::ZERO; (SIDE * SIDE) as usize];
    assert!(render_frame(&scene, &params, &seeds, &mut color).is_err());
}
