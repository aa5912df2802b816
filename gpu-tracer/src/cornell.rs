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
//!
//! [`cornell_glossy`] is the same room and light with three glTF
//! metallic-roughness spheres in place of the blocks (the scene of issue 30).

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
    add_room(&mut triangles);
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
        lights: Vec::new(),
        environment_map: None,
        triangles,
        images: Vec::new(),
        materials: room_materials(),
        camera: camera(),
    }
}

/// Material index of the first glossy sphere ([`cornell_glossy`]); sphere
/// `k` (left to right in the image) uses `GLOSSY_FIRST + k`.
pub const GLOSSY_FIRST: u32 = 4;
/// Roughness of the glossy spheres, left to right in the image (glTF
/// perceptual roughness; GGX `alpha = roughness^2`).
pub const GLOSSY_ROUGHNESS: [f32; 3] = [0.1, 0.3, 0.6];
/// Base colour (linear RGB) and metallic factor of the glossy spheres, left
/// to right: a near-mirror silver metal, a gold metal, and a blue
/// dielectric (diffuse base under the 4% GGX layer) so that both lobes of
/// the model and its lobe choice are exercised.
pub const GLOSSY_BASE: [(Vec3, f32); 3] = [
    (Vec3::new(0.95, 0.93, 0.88), 1.0),
    (Vec3::new(1.0, 0.78, 0.34), 1.0),
    (Vec3::new(0.15, 0.35, 0.75), 0.0),
];
/// Sphere radius (mm) of [`cornell_glossy`].
pub const GLOSSY_RADIUS: f32 = 75.0;
/// Centres `(x, z)` of the spheres on the floor, left to right in the image
/// (`x` decreases to the camera's right); the middle one sits further back.
pub const GLOSSY_CENTRES: [(f32, f32); 3] = [(436.0, 330.0), (278.0, 250.0), (120.0, 330.0)];
/// Tessellation of each sphere: segments around, rings from pole to pole
/// (`2 * SEGMENTS * (RINGS - 1)` triangles each; flat-shaded facets, about
/// 11 degrees wide, show in the sharpest highlight).
const SPHERE_SEGMENTS: u32 = 32;
const SPHERE_RINGS: u32 = 16;

/// The glossy Cornell box: the room and light of [`cornell_box`] (same
/// triangles, materials 0..=3 and camera) with three spheres resting on
/// the floor instead of the blocks, of roughness [`GLOSSY_ROUGHNESS`]
/// (materials `GLOSSY_FIRST..GLOSSY_FIRST + 3`, object ids 6, 7, 8): 12 +
/// 3 x 960 triangles.
pub fn cornell_glossy() -> Scene {
    let mut triangles = Vec::with_capacity(12 + 3 * 960);
    add_room(&mut triangles);
    for (i, t) in triangles.iter_mut().enumerate() {
        t.object = (i / 2) as u32;
    }
    let mut materials = room_materials();
    for (k, ((x, z), (base, metallic))) in GLOSSY_CENTRES.into_iter().zip(GLOSSY_BASE).enumerate() {
        let first = triangles.len();
        let centre = Vec3::new(x, GLOSSY_RADIUS, z);
        add_sphere(&mut triangles, centre, GLOSSY_RADIUS, GLOSSY_FIRST + k as u32);
        for t in &mut triangles[first..] {
            t.object = 6 + k as u32;
        }
        let roughness = GLOSSY_ROUGHNESS[k];
        materials.push(Material::metallic_roughness(
            format!("glossy {roughness}"),
            base,
            metallic,
            roughness,
        ));
    }
    Scene {
        lights: Vec::new(),
        environment_map: None,
        triangles,
        images: Vec::new(),
        materials,
        camera: camera(),
    }
}

/// The room's materials: white, red, green, light (indices [`WHITE`],
/// [`RED`], [`GREEN`], [`LIGHT`]).
fn room_materials() -> Vec<Material> {
    vec![
        material("white", WHITE_ALBEDO, Vec3::ZERO),
        material("red", RED_ALBEDO, Vec3::ZERO),
        material("green", GREEN_ALBEDO, Vec3::ZERO),
        material("light", Vec3::splat(0.78), LIGHT_EMISSION),
    ]
}

/// The Cornell data's camera.
fn camera() -> Camera {
    Camera {
        origin: Vec3::new(278.0, 273.0, -800.0),
        target: Vec3::new(278.0, 273.0, 0.0),
        up: Vec3::Y,
        fov_y_degrees: 39.3,
    }
}

/// Adds a UV sphere, faces pointing outwards, skipping the degenerate
/// triangles at the poles.
pub(crate) fn add_sphere(out: &mut Vec<Triangle>, centre: Vec3, radius: f32, material: u32) {
    use std::f32::consts::{PI, TAU};
    let point = |ring: u32, seg: u32| {
        let theta = PI * ring as f32 / SPHERE_RINGS as f32;
        let phi = TAU * (seg % SPHERE_SEGMENTS) as f32 / SPHERE_SEGMENTS as f32;
        centre + radius * Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin())
    };
    let mut push = |a: Vec3, b: Vec3, c: Vec3| {
        let n = (b - a).cross(c - a);
        let outward = n.dot((a + b + c) / 3.0 - centre) > 0.0;
        out.push(Triangle::new(
            if outward { [a, b, c] } else { [a, c, b] },
            material,
        ));
    };
    for ring in 0..SPHERE_RINGS {
        for seg in 0..SPHERE_SEGMENTS {
            let (a, b) = (point(ring, seg), point(ring, seg + 1));
            let (c, d) = (point(ring + 1, seg + 1), point(ring + 1, seg));
            if ring > 0 {
                push(a, b, c);
            }
            if ring + 1 < SPHERE_RINGS {
                push(a, c, d);
            }
        }
    }
}

/// Adds the five walls and the light (12 triangles, in the order of
/// [`cornell_box`]).
fn add_room(triangles: &mut Vec<Triangle>) {
    let inside = Vec3::new(278.0, 274.4, 279.6);
    let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);

    // Floor, ceiling, back wall (white), facing into the room.
    add_quad(
        triangles,
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
        triangles,
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
        triangles,
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
        triangles,
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
        triangles,
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
        triangles,
        [
            v(x1, LIGHT_Y, z0),
            v(x1, LIGHT_Y, z1),
            v(x0, LIGHT_Y, z1),
            v(x0, LIGHT_Y, z0),
        ],
        v(278.0, 0.0, 279.5),
        LIGHT,
    );
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
        let total_area: f32 = gpu.emitters.iter().map(|e| e.area()).sum();
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

    /// The glossy box: the same room, light, camera and first four
    /// materials as the Cornell box, three closed outward-facing spheres
    /// resting on the floor inside the room, and their metallic-roughness
    /// materials with the documented roughness.
    #[test]
    fn glossy_box_is_well_formed() {
        use crate::scene::Bsdf;
        let plain = cornell_box();
        let glossy = cornell_glossy();
        assert_eq!(glossy.triangles.len(), 12 + 3 * 960);
        assert_eq!(glossy.triangles[..12], plain.triangles[..12]);
        assert_eq!(glossy.materials[..4], plain.materials[..4]);
        assert_eq!(glossy.camera, plain.camera);
        for (k, (x, z)) in GLOSSY_CENTRES.into_iter().enumerate() {
            let centre = Vec3::new(x, GLOSSY_RADIUS, z);
            let tris: Vec<_> = glossy
                .triangles
                .iter()
                .filter(|t| t.object == 6 + k as u32)
                .collect();
            assert_eq!(tris.len(), 960);
            let mut area = 0.0;
            for t in tris {
                assert_eq!(t.material, GLOSSY_FIRST + k as u32);
                let [a, b, c] = t.vertices;
                let n = (b - a).cross(c - a);
                assert!(
                    n.length() > 0.0 && n.dot((a + b + c) / 3.0 - centre) > 0.0,
                    "sphere {k}: inward or degenerate"
                );
                area += 0.5 * n.length();
            }
            // Inscribed polyhedron: a little under 4 pi r^2.
            let sphere = 4.0 * std::f32::consts::PI * GLOSSY_RADIUS * GLOSSY_RADIUS;
            assert!(
                area < sphere && area > 0.97 * sphere,
                "sphere {k}: {area} vs {sphere}"
            );
            match glossy.materials[(GLOSSY_FIRST as usize) + k].bsdf {
                Bsdf::MetallicRoughness {
                    roughness,
                    texture: None,
                    ..
                } => assert_eq!(roughness, GLOSSY_ROUGHNESS[k]),
                other => panic!("sphere {k}: {other:?}"),
            }
        }
        let (lo, hi) = glossy.bounds();
        assert!(lo.min_element() >= 0.0 && hi.x <= 556.0 && hi.y <= 548.8 && hi.z <= 559.2);
        let gpu = SceneGpu::build(&glossy).expect("valid scene");
        assert_eq!(gpu.emitter_count, 2);
    }
}
