//! `smooth_sphere.gltf` + `.bin`: a coarse UV sphere (radius 1 at the
//! origin, [`RINGS`] x [`SEGMENTS`], 80 triangles, shared vertices) whose
//! `NORMAL` is the unit position (the true sphere's normal), Lambertian
//! grey, lit by a directional light from the upper left front, with a
//! camera at `(0, 0, 4)` looking at the centre. Flat shading shows its
//! facets; the vertex normals make it look round.

use super::{asset, look_rotation, material, write_gltf, Bin, MeshData, ARRAY_BUFFER};
use glam::{Vec2, Vec3};
use serde_json::json;
use std::path::Path;

/// Latitude bands of the sphere (pole to pole).
const RINGS: usize = 6;
/// Longitude segments of the sphere.
const SEGMENTS: usize = 8;

/// The sphere's vertices (a `(RINGS + 1) x (SEGMENTS + 1)` grid, the seam
/// and the poles repeated) and its triangles, counter-clockwise seen from
/// outside, the pole caps' degenerate halves dropped.
fn sphere() -> MeshData {
    let mut m = MeshData::default();
    for i in 0..=RINGS {
        let theta = std::f32::consts::PI * i as f32 / RINGS as f32;
        for j in 0..=SEGMENTS {
            let phi = std::f32::consts::TAU * j as f32 / SEGMENTS as f32;
            m.positions.push(Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                -theta.sin() * phi.sin(),
            ));
            m.uvs
                .push(Vec2::new(j as f32 / SEGMENTS as f32, i as f32 / RINGS as f32));
        }
    }
    let at = |i: usize, j: usize| (i * (SEGMENTS + 1) + j) as u16;
    for i in 0..RINGS {
        for j in 0..SEGMENTS {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            for tri in [[a, b, c], [a, c, d]] {
                let [p, q, r] = tri.map(|k| m.positions[k as usize]);
                let n = (q - p).cross(r - p);
                if n.length() < 1e-6 {
                    continue; // the pole's collapsed half of the quad
                }
                let outward = n.dot(p + q + r) > 0.0;
                m.indices
                    .extend(if outward { tri } else { [tri[0], tri[2], tri[1]] });
            }
        }
    }
    m
}

/// Writes the fixture (module docs).
pub(super) fn smooth_sphere(dir: &Path) {
    let mut bin = Bin::default();
    let mesh = sphere();
    assert_eq!(mesh.indices.len(), 3 * 80);
    let mut prim = bin.primitive(&mesh, Some(0), false);
    let normals: Vec<f32> = mesh
        .positions
        .iter()
        .flat_map(|p| p.normalize().to_array())
        .collect();
    prim["attributes"]["NORMAL"] = json!(bin.floats(&normals, 3, "VEC3", Some(ARRAY_BUFFER)));
    let eye = Vec3::new(0.0, 0.0, 4.0);
    let sun = look_rotation(Vec3::new(-2.0, 2.0, 3.0), Vec3::ZERO);
    let doc = json!({
        "asset": asset(),
        "extensionsUsed": ["KHR_materials_specular", "KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"name": "sun", "type": "directional", "intensity": 3.0}
        ]}},
        "materials": [material("grey", [0.8, 0.8, 0.8], None)],
        "meshes": [{"name": "sphere", "primitives": [prim]}],
        "cameras": [{
            "name": "view", "type": "perspective",
            "perspective": {"yfov": 40f32.to_radians(), "znear": 0.05, "aspectRatio": 1.0}
        }],
        "nodes": [
            {"name": "sphere", "mesh": 0},
            {"name": "sun", "rotation": sun.to_array(), "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"name": "camera", "camera": 0, "translation": eye.to_array(),
             "rotation": look_rotation(eye, Vec3::ZERO).to_array()}
        ],
        "scenes": [{"name": "smooth_sphere", "nodes": [0, 1, 2]}],
        "scene": 0
    });
    write_gltf(dir, "smooth_sphere", doc, bin);
}
