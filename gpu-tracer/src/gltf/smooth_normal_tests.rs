//! Tests of vertex normals on the `smooth_sphere` fixture: `NORMAL` read
//! and carried through node transforms, its `KHR_mesh_quantization` forms,
//! bad values, and CPU renders in which the sphere's shading is continuous
//! across its triangle edges where flat shading jumps.

use super::tests::{accessor_offset, fixture, load, load_fixture_patched};
use super::GltfScene;
use crate::scene::{SceneGpu, TraceSettings};
use glam::{Vec2, Vec3, Vec4};
use serde_json::{json, Value};

/// `smooth_sphere` with `edit` applied to its JSON and binary buffer.
fn load_sphere(edit: impl FnOnce(&mut Value, &mut Vec<u8>)) -> crate::Result<GltfScene> {
    load_fixture_patched("smooth_sphere", edit)
}

/// The sphere primitive's `NORMAL` accessor index.
fn normal_accessor(doc: &Value) -> usize {
    doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"]
        .as_u64()
        .expect("NORMAL") as usize
}

/// Element `k` of the float `VEC3` accessor named `attribute` of the
/// sphere primitive.
fn stored_vec3(doc: &Value, bin: &[u8], attribute: &str, k: usize) -> Vec3 {
    let a = doc["meshes"][0]["primitives"][0]["attributes"][attribute]
        .as_u64()
        .expect("accessor") as usize;
    let at = accessor_offset(doc, a) + 12 * k;
    let f = |c: usize| f32::from_le_bytes(bin[at + 4 * c..at + 4 * c + 4].try_into().expect("4 bytes"));
    Vec3::new(f(0), f(1), f(2))
}

/// The sphere's float normals, as stored in the file.
fn stored_normals(doc: &Value, bin: &[u8]) -> Vec<Vec3> {
    let count = doc["accessors"][normal_accessor(doc)]["count"]
        .as_u64()
        .expect("count") as usize;
    (0..count).map(|k| stored_vec3(doc, bin, "NORMAL", k)).collect()
}

#[test]
fn sphere_normals_are_read_and_follow_the_node_transform() {
    let g = load(&fixture("smooth_sphere.gltf"));
    assert_eq!(g.scene.triangles.len(), 80);
    assert!(g.notices.is_empty(), "{:?}", g.notices);
    for t in &g.scene.triangles {
        let n = t.normals.expect("normals");
        for (p, n) in t.vertices.iter().zip(n) {
            assert!((n - p.normalize()).length() < 1e-5, "{n} at {p}");
        }
    }
    assert_eq!(g.rig.local_normals.len(), 80);
    // Stretched 2x along y and rotated: the normals are the ellipsoid's,
    // the inverse transpose's (x, y / 4, z) at the world point (x, y, z)
    // before the rotation.
    let rotation = glam::Quat::from_rotation_z(0.5);
    let g = load_sphere(|doc, _| {
        doc["nodes"][0]["scale"] = json!([1.0, 2.0, 1.0]);
        doc["nodes"][0]["rotation"] = json!(rotation.to_array());
    })
    .expect("loads");
    for t in &g.scene.triangles {
        for (p, n) in t.vertices.iter().zip(t.normals.expect("normals")) {
            let q = rotation.inverse() * *p;
            let want = rotation * Vec3::new(q.x, q.y / 4.0, q.z).normalize();
            assert!((n.normalize() - want).length() < 1e-4, "{n} vs {want} at {p}");
        }
    }
    // A mirroring node: the swapped vertices keep their own normals, which
    // point out of the mirrored sphere.
    let g = load_sphere(|doc, _| doc["nodes"][0]["scale"] = json!([-1.0, 1.0, 1.0])).expect("loads");
    for t in &g.scene.triangles {
        for (p, n) in t.vertices.iter().zip(t.normals.expect("normals")) {
            assert!((n.normalize() - p.normalize()).length() < 1e-5, "{n} at {p}");
        }
    }
}

/// `NORMAL` as normalised `i8` (stride 4) and `i16` (stride 8) with
/// `KHR_mesh_quantization`: the same normals within one quantisation step
/// (1/127, 1/32767 per component, before renormalising).
#[test]
fn quantized_normals_match_the_float_ones() {
    let float = load(&fixture("smooth_sphere.gltf"));
    for (component, step, bytes_per) in [(5120u32, 1.0 / 127.0, 1usize), (5122, 1.0 / 32767.0, 2)] {
        let g = load_sphere(|doc, bin| {
            let values = stored_normals(doc, bin);
            let scale = if bytes_per == 1 { 127.0 } else { 32767.0 };
            let stride = 4 * bytes_per;
            bin.resize(bin.len().next_multiple_of(4), 0);
            let offset = bin.len();
            for (k, n) in values.iter().enumerate() {
                for c in n.to_array() {
                    let q = (c * scale).round();
                    if bytes_per == 1 {
                        bin.push(q as i8 as u8);
                    } else {
                        bin.extend_from_slice(&(q as i16).to_le_bytes());
                    }
                }
                bin.resize(offset + stride * (k + 1), 0);
            }
            let views = doc["bufferViews"].as_array_mut().expect("views");
            views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": bin.len() - offset, "byteStride": stride}));
            let view = views.len() - 1;
            let a = normal_accessor(doc);
            doc["accessors"][a] = json!({
                "bufferView": view, "componentType": component, "normalized": true,
                "count": values.len(), "type": "VEC3"
            });
            let used = doc["extensionsUsed"].as_array_mut().expect("extensionsUsed");
            used.push(json!("KHR_mesh_quantization"));
            doc["extensionsRequired"] = json!(["KHR_mesh_quantization"]);
        })
        .unwrap_or_else(|e| panic!("component {component}: {e}"));
        for (q, f) in g.scene.triangles.iter().zip(&float.scene.triangles) {
            for (a, b) in q
                .normals
                .expect("normals")
                .iter()
                .zip(f.normals.expect("normals"))
            {
                let err = (*a - b).abs().max_element();
                assert!(err <= step, "component {component}: {a} vs {b}");
            }
        }
    }
    // Not normalised, or unsigned: refused with the accepted types named.
    let err = load_sphere(|doc, _| {
        let a = normal_accessor(doc);
        doc["accessors"][a]["componentType"] = json!(5121);
        doc["accessors"][a]["normalized"] = json!(true);
    })
    .expect_err("u8 normals");
    assert!(err.to_string().contains("NORMAL"), "{err}");
}

/// A NaN and a zero-length normal: the triangles that use them shade flat
/// (no normals, counted in a notice), the others keep theirs.
#[test]
fn bad_normals_shade_their_triangles_flat() {
    let (nan_vertex, zero_vertex) = (10usize, 30usize);
    let mut bad = [Vec3::ZERO; 2];
    let g = load_sphere(|doc, bin| {
        bad = [nan_vertex, zero_vertex].map(|v| stored_vec3(doc, bin, "POSITION", v));
        let at = accessor_offset(doc, normal_accessor(doc));
        bin[at + 12 * nan_vertex..at + 12 * nan_vertex + 4].copy_from_slice(&f32::NAN.to_le_bytes());
        bin[at + 12 * zero_vertex..at + 12 * zero_vertex + 12].fill(0);
    })
    .expect("loads");
    let mut flat = 0;
    for t in &g.scene.triangles {
        let touches = t.vertices.iter().any(|p| bad.contains(p));
        if t.normals.is_none() {
            flat += 1;
        }
        assert_eq!(t.normals.is_none(), touches, "{:?}", t.vertices);
    }
    assert!(flat >= 6, "{flat} flat triangles");
    assert!(
        g.notices
            .iter()
            .any(|m| m.contains(&format!("{flat} triangles")) && m.contains("NORMAL")),
        "{:?}",
        g.notices
    );
}

/// CPU radiance (`size` square, 16 spp (the pixel jitter is the only noise), direct light only: the fixture's
/// directional light, black sky) of the sphere, and the triangle (scene
/// order) its pixel centres see (`None`: background).
fn render(g: &GltfScene, size: u32) -> (Vec<f32>, Vec<Option<u32>>) {
    let gpu = SceneGpu::build(&g.scene).expect("builds");
    let mut settings = TraceSettings::new(size, size);
    settings.spp = 16;
    settings.max_depth = 2;
    settings.environment = Vec3::ZERO;
    let params = gpu.trace_params(&settings, 0).expect("params");
    let seeds = crate::cpu::white_seeds(params.padded_width, size, 1);
    let mut color = vec![Vec4::ZERO; (size * size) as usize];
    crate::cpu::render_frame(&gpu, &params, &seeds, &mut color).expect("renders");
    let ids = (0..size * size)
        .map(|i| {
            let ray = kernels::camera::primary_ray(&params, i % size, i / size, Vec2::splat(0.5));
            gpu.closest_hit(&ray)
                .map(|h| gpu.original_index[h.triangle as usize])
        })
        .collect();
    (color.iter().map(|c| c.x).collect(), ids)
}

/// Across the sphere's interior edges, flat shading jumps by the facets'
/// cosine difference; with the vertex normals the shading is continuous.
/// Measured on triples of pixels `(a, b, c)` in a row or column, lit and
/// away from the silhouette, whose outer centres see different triangles
/// (an edge lies between): the second difference `|a - 2b + c|` removes
/// the smooth image's gradient and keeps a jump whole. Its mean must
/// shrink at least fourfold (measured at 64x64: 0.0061 smooth vs 0.0762
/// flat, 12x), and inside triangles the smooth image must vary where the
/// flat one is constant (0.0143 vs 0.0012).
#[test]
fn smooth_shading_is_continuous_across_triangle_edges() {
    let smooth = load(&fixture("smooth_sphere.gltf"));
    let flat = load_sphere(|doc, _| {
        let attrs = doc["meshes"][0]["primitives"][0]["attributes"]
            .as_object_mut()
            .expect("attributes");
        attrs.remove("NORMAL");
    })
    .expect("loads");
    assert!(flat.scene.triangles.iter().all(|t| t.normals.is_none()));
    let size = 64usize;
    let (s, ids) = render(&smooth, size as u32);
    let (f, flat_ids) = render(&flat, size as u32);
    assert_eq!(ids, flat_ids);
    // (sum of second differences smooth, flat, count) across edges; (sum
    // of first differences smooth, flat, count) inside triangles.
    let (mut edge, mut inside) = ([0.0f32; 2], [0.0f32; 2]);
    let (mut edges, mut insides) = (0usize, 0usize);
    // Pixels whose whole 3x3 neighbourhood sees the sphere: no pixel
    // partly covered by the background at the silhouette.
    let interior = |k: usize| {
        let (x, y) = (k % size, k / size);
        (x.saturating_sub(1)..=(x + 1).min(size - 1))
            .all(|x| (y.saturating_sub(1)..=(y + 1).min(size - 1)).all(|y| ids[y * size + x].is_some()))
    };
    for y in 1..size - 1 {
        for x in 1..size - 1 {
            let i = y * size + x;
            for step in [1, size] {
                let t = [i - step, i, i + step];
                // Interior and well lit in both images (away from the
                // silhouette and the terminator).
                if t.iter().any(|&k| !interior(k) || s[k] < 0.1 || f[k] < 0.1) {
                    continue;
                }
                let seen = t.map(|k| ids[k].expect("interior"));
                if seen[0] != seen[2] {
                    for (sum, img) in edge.iter_mut().zip([&s, &f]) {
                        *sum += (img[t[0]] - 2.0 * img[t[1]] + img[t[2]]).abs();
                    }
                    edges += 1;
                } else if seen[0] == seen[1] {
                    for (sum, img) in inside.iter_mut().zip([&s, &f]) {
                        *sum += (img[t[0]] - img[t[1]]).abs();
                    }
                    insides += 1;
                }
            }
        }
    }
    let edge = edge.map(|v| v / edges as f32);
    let inside = inside.map(|v| v / insides as f32);
    eprintln!(
        "{edges} triples across edges: mean |a - 2b + c| {:.4} smooth vs {:.4} flat; \
         {insides} pairs inside triangles: mean |a - b| {:.4} smooth vs {:.4} flat",
        edge[0], edge[1], inside[0], inside[1]
    );
    assert!(edges >= 100 && insides >= 500, "{edges} {insides}");
    assert!(edge[0] * 4.0 < edge[1], "smooth {} vs flat {}", edge[0], edge[1]);
    assert!(
        inside[0] > 2.0 * inside[1],
        "the smooth sphere is shaded per pixel"
    );
}

/// Animation: a scale channel stretching the sphere 2x along y. After the
/// sequence advances to the stretched pose, the scene buffers hold the
/// ellipsoid's normals (`(x, y / 4, z)` at the world point `(x, y, z)`),
/// not the rest pose's.
#[test]
fn animated_nodes_carry_their_normals() {
    use crate::animation::{Channel, Interpolation, Property};
    use crate::timeline::{SceneSequence, Timeline};
    let mut g = load(&fixture("smooth_sphere.gltf"));
    let node = g.rig.instances[0].node;
    g.rig.channels.push(Channel {
        node,
        property: Property::Scale,
        interpolation: Interpolation::Linear,
        times: vec![0.0, 1.0],
        values: vec![Vec4::ONE, Vec4::new(1.0, 2.0, 1.0, 0.0)],
    });
    let timeline = Timeline {
        rig: Some(g.rig),
        fps: 1.0,
        ..Timeline::still()
    };
    let mut seq = SceneSequence::new(&g.scene, timeline, 16).expect("sequence");
    assert!(seq.advance().expect("advances"));
    let scene = seq.scene();
    for (t, a) in scene.triangles.iter().zip(&scene.attrs) {
        for (p, n) in [(t.v0, a.normal0), (t.v1, a.normal1), (t.v2, a.normal2)] {
            let want = Vec3::new(p.x, p.y / 4.0, p.z).normalize();
            assert!((n.truncate() - want).length() < 1e-4, "{n} vs {want} at {p}");
        }
    }
}
