//! Textures at a camera ray's first hit are read at the pixel centre and
//! filtered over the pixel's footprint: under a delta light (no other
//! randomness), every sample of a pixel then reads the same radiance, even
//! where the pixel straddles an edge of a nearest-filtered checker, and
//! that radiance is the checker averaged over the pixel.

use glam::{Vec2, Vec3, Vec4};
use gpu_tracer::cpu::{render_frame, white_seeds};
use gpu_tracer::scene::{
    Camera, Filter, Image, Light, Material, Scene, SceneGpu, TextureRef, Triangle, Wrap,
};
use gpu_tracer::TraceSettings;

/// A floor (y = 0, 8 units) with a 4x4 black-and-white checker (2 units a
/// texel), lit straight down by a 1-lux directional light, seen from above
/// through 32 x 32 pixels of 0.25 units each: each texel is 8 pixels.
fn checker_floor() -> SceneGpu {
    let (a, b, c, d) = (
        Vec3::new(-4.0, 0.0, 4.0),
        Vec3::new(4.0, 0.0, 4.0),
        Vec3::new(4.0, 0.0, -4.0),
        Vec3::new(-4.0, 0.0, -4.0),
    );
    // Shifted by half a pixel (0.125 units): texel edges run through pixel
    // centres, so those pixels straddle an edge.
    let uv = |p: Vec3| Vec2::new((p.x + 4.125) / 8.0, (p.z + 4.125) / 8.0);
    let tri = |v: [Vec3; 3]| Triangle {
        uvs: v.map(uv),
        ..Triangle::new(v, 0)
    };
    let texels = (0..16)
        .map(|i| {
            if (i % 4 + i / 4) % 2 == 0 {
                [255, 255, 255, 255]
            } else {
                [0, 0, 0, 255]
            }
        })
        .collect();
    let mut floor = Material::new("checker", Vec3::ONE, Vec3::ZERO);
    floor.base_color_texture = Some(TextureRef {
        image: 0,
        wrap_u: Wrap::Clamp,
        wrap_v: Wrap::Clamp,
        filter: Filter::Nearest,
        transform: None,
    });
    let scene = Scene {
        triangles: vec![tri([a, b, c]), tri([a, c, d])],
        materials: vec![floor],
        images: vec![Image {
            name: "checker".into(),
            width: 4,
            height: 4,
            texels,
        }],
        lights: vec![Light::directional("sun", -Vec3::Y, 1.0, 0.0)],
        environment_map: None,
        camera: Camera {
            origin: Vec3::new(0.0, 10.0, 0.0),
            target: Vec3::ZERO,
            up: Vec3::NEG_Z,
            // 32 pixels over 8 units at distance 10.
            fov_y_degrees: 2.0 * (0.4f32).atan().to_degrees(),
        },
    };
    SceneGpu::build(&scene).expect("scene")
}

fn frame(scene: &SceneGpu, salt: u32) -> Vec<Vec4> {
    let mut settings = TraceSettings::new(32, 32);
    settings.max_depth = 2;
    let params = scene.trace_params(&settings, 0).expect("params");
    let seeds = white_seeds(32, 32, salt);
    let mut color = vec![Vec4::ZERO; 32 * 32];
    render_frame(scene, &params, &seeds, &mut color).expect("render");
    color
}

#[test]
fn samples_of_a_pixel_read_its_filtered_texture() {
    let scene = checker_floor();
    let frames: Vec<Vec<Vec4>> = (1..5).map(|salt| frame(&scene, salt)).collect();
    let white = 1.0 / std::f32::consts::PI;
    let mut blended = 0;
    for i in 0..32 * 32 {
        let v = frames[0][i].x;
        for f in &frames[1..] {
            // Same radiance whatever the jitter (up to the hit point's rounding).
            assert!((f[i].x - v).abs() <= 1e-5 * white, "pixel {i}: {} vs {v}", f[i].x);
        }
        assert!((-1e-6..=white * 1.0001).contains(&v), "pixel {i}: {v}");
        if v > 0.05 * white && v < 0.95 * white {
            blended += 1;
        }
    }
    // The pixels on the texel edges (one column and one row per edge, 3 of
    // each inside the image) read a blend; the others pure black or white.
    assert!((150..=32 * 32 / 3).contains(&blended), "{blended} blended pixels");
}
