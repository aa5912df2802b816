//! Scenes the integration tests share.

use glam::Vec3;
use gpu_tracer::scene::{Camera, EnvironmentMap, Light, Material, Scene, Triangle};

/// A Lambertian floor of albedo `albedo` (y = 0, 40 units wide, facing up)
/// under `lights` and `environment_map`, seen straight down from 1 unit
/// above the origin through a 2-degree field of view (every pixel sees the
/// floor within 0.02 units of the origin).
pub fn floor_scene(albedo: f32, lights: Vec<Light>, environment_map: Option<EnvironmentMap>) -> Scene {
    let (a, b, c, d) = (
        Vec3::new(-20.0, 0.0, 20.0),
        Vec3::new(20.0, 0.0, 20.0),
        Vec3::new(20.0, 0.0, -20.0),
        Vec3::new(-20.0, 0.0, -20.0),
    );
    Scene {
        triangles: vec![Triangle::new([a, b, c], 0), Triangle::new([a, c, d], 0)],
        materials: vec![Material::new("floor", Vec3::splat(albedo), Vec3::ZERO)],
        images: Vec::new(),
        lights,
        environment_map,
        camera: Camera {
            origin: Vec3::new(0.0, 1.0, 0.0),
            target: Vec3::ZERO,
            up: Vec3::Z,
            fov_y_degrees: 2.0,
        },
    }
}
