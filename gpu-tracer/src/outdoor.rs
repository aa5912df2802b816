//! The built-in outdoor scene ([`sun_and_sky`]): a few objects on open
//! ground, lit by a sun with a visible disk (soft shadows) and a constant
//! sky ([`SKY`], ambient occlusion where objects meet the ground). Its
//! integrands are the ones real-time renderers use blue noise for most:
//! a 2D soft-shadow integral over the sun's disk and the 2D
//! hemisphere integral of sky occlusion, rather than the interreflection of
//! a closed room.
//!
//! Units are metres; `y` is up. The camera looks down at the group from
//! the front (`+z`); the sun shines from behind on the left, so the shadows
//! fall towards the camera's right. The ground reaches 50 m in every
//! direction, so that the sky shows only above the far horizon at the top
//! of the image.

use crate::cornell::add_sphere;
use crate::scene::{Camera, Light, Material, Scene, Triangle};
use glam::Vec3;

/// Radiance of the constant sky the scene is meant to be rendered with
/// (`--env` of `gpu-tracer render`; `TraceSettings::environment`): a pale
/// blue of irradiance `pi * SKY` on open ground.
pub const SKY: Vec3 = Vec3::new(0.30, 0.36, 0.45);
/// Illuminance of the sun on a surface facing it, lux (the renderer's unit).
pub const SUN_ILLUMINANCE: f32 = 3.0;
/// Angular radius of the sun's disk, radians: about nine times the real
/// sun's 0.00465, for penumbrae a few pixels wide.
pub const SUN_ANGULAR_RADIUS: f32 = 0.04;
/// Unit direction towards the sun: 35 degrees above the horizon, from
/// behind the objects on the camera's left.
pub fn sun_direction() -> Vec3 {
    let elevation = 35f32.to_radians();
    let azimuth = Vec3::new(-0.55, 0.0, -0.83).normalize();
    (azimuth * elevation.cos() + Vec3::Y * elevation.sin()).normalize()
}

/// Material index of the ground.
pub const GROUND: u32 = 0;
/// Material index of the wall behind the objects.
pub const WALL: u32 = 1;
/// Material index of the box and the pillar.
pub const BLOCK: u32 = 2;
/// Material index of the sphere.
pub const SPHERE: u32 = 3;

/// The outdoor scene: ground (object 0), a wall 6 m wide and 2 m high
/// behind the group (object 1), a 1 m box (2), a 1.8 m pillar (3) and a
/// sphere of radius 0.6 m resting on the ground (4), all Lambertian, with
/// the sun as a directional light of [`SUN_ILLUMINANCE`] lux and angular
/// radius [`SUN_ANGULAR_RADIUS`] from [`sun_direction`]. Render it with
/// the environment [`SKY`].
pub fn sun_and_sky() -> Scene {
    let mut triangles = Vec::new();
    let ground = 50.0;
    add_quad(
        &mut triangles,
        [
            Vec3::new(-ground, 0.0, ground),
            Vec3::new(ground, 0.0, ground),
            Vec3::new(ground, 0.0, -ground),
            Vec3::new(-ground, 0.0, -ground),
        ],
        GROUND,
        0,
    );
    add_box(
        &mut triangles,
        Vec3::new(-3.0, 0.0, -2.3),
        Vec3::new(3.0, 2.0, -2.0),
        WALL,
        1,
    );
    add_box(
        &mut triangles,
        Vec3::new(-2.0, 0.0, -0.2),
        Vec3::new(-1.0, 1.0, 0.8),
        BLOCK,
        2,
    );
    add_box(
        &mut triangles,
        Vec3::new(1.3, 0.0, -0.6),
        Vec3::new(1.9, 1.8, 0.0),
        BLOCK,
        3,
    );
    let first = triangles.len();
    add_sphere(&mut triangles, Vec3::new(0.2, 0.6, 1.3), 0.6, SPHERE);
    for t in &mut triangles[first..] {
        t.object = 4;
    }
    let materials = vec![
        Material::new("ground", Vec3::new(0.45, 0.42, 0.38), Vec3::ZERO),
        Material::new("wall", Vec3::splat(0.7), Vec3::ZERO),
        Material::new("block", Vec3::new(0.65, 0.55, 0.45), Vec3::ZERO),
        Material::new("sphere", Vec3::splat(0.75), Vec3::ZERO),
    ];
    Scene {
        triangles,
        materials,
        images: Vec::new(),
        lights: vec![Light::directional(
            "sun",
            -sun_direction(),
            SUN_ILLUMINANCE,
            SUN_ANGULAR_RADIUS,
        )],
        environment_map: None,
        camera: Camera {
            origin: Vec3::new(0.0, 5.5, 9.0),
            target: Vec3::new(0.0, 0.6, 0.0),
            up: Vec3::Y,
            fov_y_degrees: 40.0,
        },
    }
}

/// Adds the quad `q` (counter-clockwise seen from its front) as two
/// triangles of `object`.
fn add_quad(out: &mut Vec<Triangle>, q: [Vec3; 4], material: u32, object: u32) {
    for tri in [[q[0], q[1], q[2]], [q[0], q[2], q[3]]] {
        out.push(Triangle {
            object,
            ..Triangle::new(tri, material)
        });
    }
}

/// Adds the axis-aligned box `lo..hi` standing on the ground (five faces,
/// no bottom), fronts facing out.
fn add_box(out: &mut Vec<Triangle>, lo: Vec3, hi: Vec3, material: u32, object: u32) {
    let c = |x: bool, y: bool, z: bool| {
        Vec3::new(
            if x { hi.x } else { lo.x },
            if y { hi.y } else { lo.y },
            if z { hi.z } else { lo.z },
        )
    };
    let faces = [
        [
            c(false, true, true),
            c(true, true, true),
            c(true, true, false),
            c(false, true, false),
        ], // top
        [
            c(false, false, true),
            c(true, false, true),
            c(true, true, true),
            c(false, true, true),
        ], // +z
        [
            c(true, false, false),
            c(false, false, false),
            c(false, true, false),
            c(true, true, false),
        ], // -z
        [
            c(true, false, true),
            c(true, false, false),
            c(true, true, false),
            c(true, true, true),
        ], // +x
        [
            c(false, false, false),
            c(false, false, true),
            c(false, true, true),
            c(false, true, false),
        ], // -x
    ];
    let centre = 0.5 * (lo + hi);
    for q in faces {
        let n = (q[1] - q[0]).cross(q[2] - q[0]);
        let q = if n.dot(q[0] - centre) < 0.0 {
            [q[3], q[2], q[1], q[0]]
        } else {
            q
        };
        add_quad(out, q, material, object);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::SceneGpu;

    #[test]
    fn the_scene_builds_with_the_sun_as_its_only_emitter() {
        let scene = sun_and_sky();
        let gpu = SceneGpu::build(&scene).expect("scene");
        assert_eq!(gpu.emitter_count, 1);
        assert_eq!(gpu.emitters[0].kind, kernels::abi::EMITTER_DIRECTIONAL);
        assert!((gpu.emitters[0].direction.truncate() + sun_direction()).length() < 1e-6);
        // Every face of the boxes points away from its box; the ground up.
        let (ground_n, _) = kernels::trace::normal_and_area(
            scene.triangles[0].vertices[0],
            scene.triangles[0].vertices[1],
            scene.triangles[0].vertices[2],
        );
        assert!(ground_n.abs_diff_eq(Vec3::Y, 1e-6), "{ground_n}");
        let objects: std::collections::BTreeSet<u32> = scene.triangles.iter().map(|t| t.object).collect();
        assert_eq!(objects.into_iter().collect::<Vec<_>>(), [0, 1, 2, 3, 4]);
        assert!(sun_direction().y > 0.5 && sun_direction().z < 0.0);
    }
}
