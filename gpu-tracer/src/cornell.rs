//! The built-in Cornell box: the classic measured geometry (Cornell Program
//! of Computer Graphics, "Cornell Box Data", dimensions in millimetres,
//! about 556 x 549 x 559), a ceiling area light, and a camera looking in
//! through the open side.
//!
//! Coordinates follow the published data: `x` from the green (right) wall
//! at 0 to the red (left) wall at ~556, `y` up from the floor, `z` from the
//! open front at 0 to the back wall at 559.2. The camera sits at
//! `(278, 273, -800)` looking along `+z`, with the 39.3-degree field of view
//! of the data's 35 mm lens and 25 mm film.
//!
//! The light is lowered 0.5 mm below the ceiling (the data puts both at
//! 548.8, which would make them coplanar) and emits downwards only. Every
//! quad's winding is chosen so its front faces into the room (walls) or out
//! of the block (blocks); only the light's front side matters for emission.

use crate::scene::{Camera, Material, Scene, Triangle};
use glam::Vec3;

/// Material index of the white walls and blocks.
pub const WHITE: u32 = 0;
/// Material index of the red (left) wall.
pub const RED: u32 = 1;
/// Material index of the green (right) wall.
pub const GREEN: u32 = 2;
/// Material index of the light.
pub const LIGHT: u32 = 3;

/// Albedo of the white surfaces (a common linear-RGB approximation of the
/// measured reflectance spectra).
pub const WHITE_ALBEDO: Vec3 = Vec3::new(0.73, 0.73, 0.73);
/// Albedo of the red wall.
pub const RED_ALBEDO: Vec3 = Vec3::new(0.65, 0.05, 0.05);
/// Albedo of the green wall.
pub const GREEN_ALBEDO: Vec3 = Vec3::new(0.12, 0.45, 0.15);
/// Radiance of the light: a warm white bright enough that the walls come
/// out near 0.5 in linear units (a common choice in renderer tests).
pub const LIGHT_EMISSION: Vec3 = Vec3::new(17.0, 12.0, 4.0);

/// Height of the light's plane: 0.5 mm below the ceiling at 548.8.
pub const LIGHT_Y: f32 = 548.3;
/// Corners `(x, z)` of the light's rectangle (130 x 105 mm, centred).
pub const LIGHT_RECT: [(f32, f32); 2] = [(213.0, 227.0), (343.0, 332.0)];

/// The Cornell box scene: 32 triangles (5 walls, light, two blocks).
pub fn cornell_box() -> Scene {
    let mut triangles = Vec::with_capacity(36);
    let inside = Vec3::new(278.0, 274.4, 279.6);
    let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);

    // Floor, ceiling, back wall (white), facing into the room.
    add_quad(
        &mut triangles,
        [
            v(552.8, 0.0, 0.0),
            v(0.0, 0.0, 0.0),
            v(0.0, 0.0, 559.2),
            v(549.6, 0.0, 559.2),
        ],
        inside,
        WHITE,
    );
    add_quad(
        &mut triangles,
        [
            v(556.0, 548.8, 0.0),
            v(556.0, 548.8, 559.2),
            v(0.0, 548.8, 559.2),
            v(0.0, 548.8, 0.0),
        ],
        inside,
        WHITE,
    );
    add_quad(
        &mut triangles,
        [
            v(549.6, 0.0, 559.2),
            v(0.0, 0.0, 559.2),
            v(0.0, 548.8, 559.2),
            v(556.0, 548.8, 559.2),
        ],
        inside,
        WHITE,
    );
    // Green wall at x = 0 (camera's right), red wall at x ~ 556 (camera's left).
    add_quad(
        &mut triangles,
        [
            v(0.0, 0.0, 559.2),
            v(0.0, 0.0, 0.0),
            v(0.0, 548.8, 0.0),
            v(0.0, 548.8, 559.2),
        ],
        inside,
        GREEN,
    );
    add_quad(
        &mut triangles,
        [
            v(552.8, 0.0, 0.0),
            v(549.6, 0.0, 559.2),
            v(556.0, 548.8, 559.2),
            v(556.0, 548.8, 0.0),
        ],
        inside,
        RED,
    );
    // Light, facing down.
    let [(x0, z0), (x1, z1)] = LIGHT_RECT;
    add_quad(
        &mut triangles,
        [
            v(x1, LIGHT_Y, z0),
            v(x1, LIGHT_Y, z1),
            v(x0, LIGHT_Y, z1),
            v(x0, LIGHT_Y, z0),
        ],
        v(278.0, 0.0, 279.5),
        LIGHT,
    );
    // Short block (165 mm) and tall block (330 mm): four side quads and a top, facing out.
    add_block(
        &mut triangles,
        [(130.0, 65.0), (82.0, 225.0), (240.0, 272.0), (290.0, 114.0)],
        165.0,
    );
    add_block(
        &mut triangles,
        [(423.0, 247.0), (265.0, 296.0), (314.0, 456.0), (472.0, 406.0)],
        330.0,
    );

    // Object ids for the G-buffer: one per wall quad and the light (0..=5),
    // one per block (6 short, 7 tall).
    for (i, t) in triangles.iter_mut().enumerate() {
        t.object = match i / 2 {
            q @ 0..=5 => q as u32,
            6..=10 => 6,
            _ => 7,
        };
    }
    Scene {
        triangles,
        images: Vec::new(),
        materials: vec![
            material("white", WHITE_ALBEDO, Vec3::ZERO),
            material("red", RED_ALBEDO, Vec3::ZERO),
            material("green", GREEN_ALBEDO, Vec3::ZERO),
            material("light", Vec3::splat(0.78), LIGHT_EMISSION),
        ],
        camera: Camera {
            origin: v(278.0, 273.0, -800.0),
            target: v(278.0, 273.0, 0.0),
            up: Vec3::Y,
            fov_y_degrees: 39.3,
        },
    }
}

fn material(name: &str, albedo: Vec3, emission: Vec3) -> Material {
    Material::new(name, albedo, emission)
}

/// Adds the planar quad `q` (corners in order around it) as two triangles
/// whose front (right-hand normal) faces the point `towards`.
fn add_quad(out: &mut Vec<Triangle>, q: [Vec3; 4], towards: Vec3, material: u32) {
    let normal = (q[1] - q[0]).cross(q[2] - q[0]);
    let centre = (q[0] + q[1] + q[2] + q[3]) * 0.25;
    let q = if normal.dot(towards - centre) >= 0.0 {
        q
    } else {
        [q[3], q[2], q[1], q[0]]
    };
    out.push(Triangle::new([q[0], q[1], q[2]], material));
    out.push(Triangle::new([q[0], q[2], q[3]], material));
}

/// Adds a white block standing on the floor: footprint corners `(x, z)` in
/// order, height `h`; faces point away from the block's centre.
fn add_block(out: &mut Vec<Triangle>, footprint: [(f32, f32); 4], h: f32) {
    let base: Vec<Vec3> = footprint.iter().map(|&(x, z)| Vec3::new(x, 0.0, z)).collect();
    let top: Vec<Vec3> = base.iter().map(|b| *b + Vec3::Y * h).collect();
    let centre = base.iter().fold(Vec3::ZERO, |a, b| a + *b) / 4.0 + Vec3::Y * (h * 0.5);
    let away = |c: Vec3| c + (c - centre);
    let top_q = [top[0], top[1], top[2], top[3]];
    let top_c = (top[0] + top[1] + top[2] + top[3]) * 0.25;
    add_quad(out, top_q, away(top_c), WHITE);
    for i in 0..4 {
        let j = (i + 1) % 4;
        let q = [base[i], base[j], top[j], top[i]];
        let c = (q[0] + q[1] + q[2] + q[3]) * 0.25;
        add_quad(out, q, away(c), WHITE);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::SceneGpu;

    #[test]
    fn box_is_well_formed() {
        let scene = cornell_box();
        assert_eq!(scene.triangles.len(), 32);
        let gpu = SceneGpu::build(&scene).expect("valid scene");
        // The two light triangles are the only emitters, each picked half the time.
        assert_eq!(gpu.emitter_count, 2);
        for e in &gpu.emitters {
            assert!((e.pdf - 0.5).abs() < 1e-6);
            let t = gpu.triangles[e.triangle as usize];
            let n = (t.v1 - t.v0).truncate().cross((t.v2 - t.v0).truncate());
            assert!(n.normalize().dot(-Vec3::Y) > 0.999, "light must face down: {n}");
        }
        let total_area: f32 = gpu.emitters.iter().map(|e| e.area).sum();
        assert!((total_area - 130.0 * 105.0).abs() < 1.0);
        // Walls face inwards: the floor's normal points up, the red wall's towards -x.
        let floor = scene.triangles[0].vertices;
        assert!((floor[1] - floor[0]).cross(floor[2] - floor[0]).y > 0.0);
        let red = scene
            .triangles
            .iter()
            .find(|t| t.material == RED)
            .expect("red wall")
            .vertices;
        assert!((red[1] - red[0]).cross(red[2] - red[0]).x < 0.0);
        let (lo, hi) = scene.bounds();
        assert!(lo.min_element() >= 0.0 && hi.x <= 556.0 && hi.y <= 548.8 && hi.z <= 559.2);
    }
}
