//! Environment maps light a scene as their radiance says: a white floor
//! under a uniform map returns the map (a white furnace), and a floor under
//! a map with a bright spot reads the cosine-weighted integral of the map
//! over the upper hemisphere, computed independently on the host from the
//! texels (importance sampling and MIS change the noise, not the mean).

use glam::{Vec2, Vec3, Vec4};
use gpu_tracer::cpu::{render_frame, white_seeds};
use gpu_tracer::scene::{EnvironmentMap, SceneGpu};
use gpu_tracer::TraceSettings;
use sampler_core::distributions::environment::uv_to_direction;
use std::f64::consts::PI;

mod common;

/// The shared floor of albedo `albedo` under `map`.
fn floor(albedo: f32, map: EnvironmentMap) -> SceneGpu {
    SceneGpu::build(&common::floor_scene(albedo, Vec::new(), Some(map))).expect("scene")
}

/// Mean and standard error of the red channel over 16x16 pixels x `spp`.
fn render(scene: &SceneGpu, spp: u32, max_depth: u32) -> (f64, f64) {
    let mut settings = TraceSettings::new(16, 16);
    settings.spp = spp;
    settings.max_depth = max_depth;
    let params = scene.trace_params(&settings, 0).expect("params");
    let seeds = white_seeds(settings.padded_width, settings.height, 9);
    let mut color = vec![Vec4::ZERO; 256];
    render_frame(scene, &params, &seeds, &mut color).expect("render");
    let n = color.len() as f64;
    let mean = color.iter().map(|c| c.x as f64).sum::<f64>() / n;
    let var = color.iter().map(|c| (c.x as f64 - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

#[test]
fn a_white_floor_under_a_uniform_map_returns_the_map() {
    let scene = floor(1.0, EnvironmentMap::constant(Vec3::ONE));
    assert_eq!(scene.emitter_count, 1, "the map is light-sampled");
    let (mean, err) = render(&scene, 16, 8);
    assert!(
        (mean - 1.0).abs() < 0.01 && err < 0.01,
        "furnace: {mean} (se {err})"
    );
}

#[test]
fn a_map_with_a_bright_spot_gives_its_cosine_weighted_integral() {
    let (w, h) = (32u32, 16u32);
    // A dim sky with a bright spot 40 degrees above the horizon, and some
    // light below the horizon that the floor must not see.
    let spot = uv_to_direction(Vec2::new(0.3, 0.28), 0.0);
    let texel = |x: u32, y: u32| {
        let d = uv_to_direction(
            Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32),
            0.0,
        );
        let bright = 40.0 * (-(1.0 - d.dot(spot)) * 30.0).exp();
        let below = if d.y < 0.0 { 5.0 } else { 0.0 };
        [0.2 + bright + below, 0.1 + bright, 0.3]
    };
    let map = EnvironmentMap {
        name: "spot".into(),
        width: w,
        height: h,
        texels: (0..w * h).map(|i| texel(i % w, i / w)).collect(),
        rotation_degrees: 30.0,
    };
    // Irradiance on the floor: sum over texels of L * int cos+ d omega,
    // each texel split into 16x16 sub-cells (the rotation turns the map,
    // not the floor's view of it: the integral over the upper hemisphere
    // is the same for any turn about +Y).
    let sub = 16;
    let mut irradiance = 0.0f64;
    for y in 0..h {
        for x in 0..w {
            let l = texel(x, y)[0] as f64;
            for j in 0..sub {
                for _ in 0..sub {
                    let v = (y as f64 + (j as f64 + 0.5) / sub as f64) / h as f64;
                    let theta = PI * v;
                    let d_omega = (2.0 * PI / (w * sub) as f64) * (PI / (h * sub) as f64) * theta.sin();
                    irradiance += l * theta.cos().max(0.0) * d_omega;
                }
            }
        }
    }
    let albedo = 0.5;
    let want = albedo / PI * irradiance;
    let scene = floor(albedo as f32, map);
    let (mean, err) = render(&scene, 64, 2);
    assert!(
        (mean - want).abs() < 5.0 * err + 1e-3 * want,
        "rendered {mean} (se {err}), integral {want}"
    );
    // Light sampling makes it a low-noise estimate: under 1% per pixel mean.
    assert!(err < 0.01 * want, "standard error {err} of {want}");
}

#[test]
fn a_constant_sky_and_a_map_are_exclusive() {
    let scene = floor(0.5, EnvironmentMap::constant(Vec3::ONE));
    let mut settings = TraceSettings::new(4, 4);
    settings.environment = Vec3::splat(0.5);
    let err = scene.trace_params(&settings, 0).unwrap_err();
    assert!(err.to_string().contains("environment"), "{err}");
}
