//! Tests of the loader as a whole on the fixtures of `tests/data/gltf`, and
//! the helpers the other files' tests share.

use super::*;
use crate::animation::Interpolation;
use crate::error::Error;
use crate::scene::{Bsdf, Filter, SceneGpu, TextureRef, Wrap};
use glam::Vec2;
use serde_json::{json, Value};
use std::fs;
use std::path::PathBuf;

/// The fixtures written by `examples/make_gltf_fixtures.rs`.
pub(super) fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/gltf")
        .join(name)
}

/// A temp dir holding a copy of every fixture.
pub(super) fn fixture_copy() -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("temp dir");
    for entry in fs::read_dir(fixture("")).expect("fixture dir") {
        let entry = entry.expect("entry");
        fs::copy(entry.path(), dir.path().join(entry.file_name())).expect("copy");
    }
    dir
}

pub(super) fn read_json(path: &Path) -> Value {
    serde_json::from_slice(&fs::read(path).expect("read")).expect("JSON")
}

pub(super) fn write_json(path: &Path, v: &Value) {
    fs::write(path, serde_json::to_vec_pretty(v).expect("JSON")).expect("write");
}

/// Byte offset of accessor `a`'s first element in its buffer.
pub(super) fn accessor_offset(doc: &Value, a: usize) -> usize {
    let acc = &doc["accessors"][a];
    let view = &doc["bufferViews"][acc["bufferView"].as_u64().expect("view") as usize];
    (view["byteOffset"].as_u64().unwrap_or(0) + acc["byteOffset"].as_u64().unwrap_or(0)) as usize
}

pub(super) fn load(path: &Path) -> GltfScene {
    load_gltf(path, None).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

pub(super) fn content_error(result: Result<GltfScene>) -> (String, String) {
    match result {
        Err(Error::GltfContent { element, reason, .. }) => (element, reason),
        other => panic!("expected GltfContent, got {other:?}"),
    }
}

fn normal(t: [Vec3; 3]) -> Vec3 {
    (t[1] - t[0]).cross(t[2] - t[0]).normalize()
}

const LIGHT: [u8; 4] = [230, 220, 200, 255];
const DARK: [u8; 4] = [40, 60, 90, 255];

/// Loads fixture `<stem>.gltf` after `edit` changed its JSON and its
/// `<stem>.bin` (in a temp dir holding all fixtures).
pub(super) fn load_fixture_patched(
    stem: &str,
    edit: impl FnOnce(&mut Value, &mut Vec<u8>),
) -> Result<GltfScene> {
    let dir = fixture_copy();
    let path = dir.path().join(format!("{stem}.gltf"));
    let bin_path = dir.path().join(format!("{stem}.bin"));
    let mut doc = read_json(&path);
    let mut bin = fs::read(&bin_path).expect("bin");
    edit(&mut doc, &mut bin);
    doc["buffers"][0]["byteLength"] = json!(bin.len());
    write_json(&path, &doc);
    fs::write(&bin_path, &bin).expect("write");
    load_gltf(&path, None)
}

/// `textured_quad.gltf` after `edit`.
pub(super) fn load_patched(edit: impl FnOnce(&mut Value, &mut Vec<u8>)) -> Result<GltfScene> {
    load_fixture_patched("textured_quad", edit)
}

/// Accessor indices of the checker quad's primitive.
pub(super) fn quad_accessor(doc: &Value, attribute: &str) -> usize {
    let prim = &doc["meshes"][0]["primitives"][0];
    let v = if attribute == "indices" {
        &prim["indices"]
    } else {
        &prim["attributes"][attribute]
    };
    v.as_u64().expect("accessor") as usize
}

#[test]
fn textured_quad_loads_geometry_materials_texture_and_camera() {
    let g = load(&fixture("textured_quad.gltf"));
    let s = &g.scene;
    assert_eq!(s.triangles.len(), 4);
    let objects: Vec<u32> = s.triangles.iter().map(|t| t.object).collect();
    assert_eq!(objects, [0, 0, 1, 1]);
    // The quad's first vertex (-1, -1, 0) has UV (0, 2); its front faces +Z.
    let t = s.triangles[0];
    assert_eq!(t.vertices[0], Vec3::new(-1.0, -1.0, 0.0));
    assert_eq!(t.uvs[0], Vec2::new(0.0, 2.0));
    assert!(normal(t.vertices).abs_diff_eq(Vec3::Z, 1e-6));
    // Materials.
    assert_eq!(s.materials.len(), 2);
    let checker = &s.materials[0];
    assert_eq!(checker.name, "checker");
    assert_eq!(checker.albedo, Vec3::ONE);
    assert_eq!(
        checker.base_color_texture,
        Some(TextureRef {
            image: 0,
            wrap_u: Wrap::Repeat,
            wrap_v: Wrap::Repeat,
            filter: Filter::Nearest,
            transform: None
        })
    );
    assert!(s.materials[1]
        .emission
        .abs_diff_eq(Vec3::new(30.0, 27.0, 24.0), 1e-5));
    assert_eq!(s.materials[1].albedo, Vec3::ZERO);
    // The generator writes its diffuse materials as exactly Lambertian glTF.
    assert!(s.materials.iter().all(|m| m.bsdf == Bsdf::Lambert));
    // The checker image, top row first.
    let img = &s.images[0];
    assert_eq!((img.name.as_str(), img.width, img.height), ("checker", 4, 4));
    assert_eq!(img.texels[0], LIGHT); // (0, 0)
    assert_eq!(img.texels[1], DARK); // (1, 0)
    assert_eq!(img.texels[3 * 4], DARK); // (0, 3): rows are not flipped
    assert_eq!(img.texels[3 * 4 + 1], LIGHT);
    // Camera node at (0, 0, 3) looking along -Z.
    assert_eq!(s.camera.origin, Vec3::new(0.0, 0.0, 3.0));
    assert!((s.camera.target - s.camera.origin).abs_diff_eq(Vec3::NEG_Z, 1e-6));
    assert!(s.camera.up.abs_diff_eq(Vec3::Y, 1e-6));
    assert!((s.camera.fov_y_degrees - 45.0).abs() < 1e-4);
    assert_eq!(g.rig.camera.map(|c| c.node), Some(2));
    assert!(g.notices.is_empty(), "{:?}", g.notices);
    assert_eq!(g.rig.local.len(), 4);
    assert_eq!(g.rig.duration(), 0.0);
    assert_eq!(g.rig.pose(1.0).triangles[0], t.vertices);

    // The kernels' texture lookup: NEAREST + REPEAT.
    let gpu = SceneGpu::build(s).expect("builds");
    assert_eq!(gpu.emitter_count, 2);
    let tex = gpu.materials[0].textures;
    let sample = |u: f32, v: f32| {
        kernels::texture::sample_image(&gpu.images, gpu.image_count, tex.x, tex.y, Vec2::new(u, v))
    };
    let light = sample(0.1, 0.1);
    let dark = sample(0.3, 0.1);
    assert!(light.min_element() > dark.max_element(), "{light} {dark}");
    assert_eq!(sample(1.1, 0.1), light); // repeats
    assert_eq!(sample(0.1, 1.9), dark); // row 3 of the second repetition
    assert_eq!(sample(0.1 + 1.0 / 8.0, 0.1), light); // same texel (nearest)
}

#[test]
fn emissive_quad_glb_without_camera_is_framed() {
    let g = load(&fixture("emissive_quad.glb"));
    let s = &g.scene;
    assert_eq!(s.triangles.len(), 4);
    assert_eq!(s.materials[0].albedo, Vec3::splat(0.5));
    assert!(s.materials[1]
        .emission
        .abs_diff_eq(Vec3::new(4.0, 3.2, 2.4), 1e-5));
    assert!(s.images.is_empty());
    // The lamp node sits at y = 1.5 and faces down.
    let lamp = s.triangles[2];
    assert!(lamp.vertices.iter().all(|v| v.y == 1.5));
    assert!(normal(lamp.vertices).abs_diff_eq(Vec3::NEG_Y, 1e-6));
    assert_eq!(g.rig.camera, None);
    let (lo, hi) = s.bounds();
    assert_eq!(s.camera, Camera::framing(lo, hi));
    assert!(g.notices.is_empty(), "{:?}", g.notices);
    let gpu = SceneGpu::build(s).expect("builds");
    assert_eq!(gpu.emitter_count, 2);
}

#[test]
fn hierarchy_glb_transforms_and_animates() {
    let g = load(&fixture("hierarchy.glb"));
    let rig = &g.rig;
    let names: Vec<&str> = rig.nodes.iter().map(|n| n.name.as_str()).collect();
    assert_eq!(names, ["parent", "child", "mirror"]);
    assert_eq!(rig.nodes[1].parent, Some(0));
    assert_eq!(g.scene.triangles.len(), 2);
    assert_eq!(rig.instances.len(), 2);
    assert_eq!(g.scene.materials.len(), 1); // the default material
    assert_eq!(g.scene.materials[0].albedo, DEFAULT_ALBEDO);
    assert_eq!(
        g.scene.materials[0].bsdf,
        Bsdf::MetallicRoughness {
            metallic: 1.0,
            roughness: 1.0,
            texture: None
        },
        "glTF's default material is a rough white metal"
    );
    // Child vertex (0,0,0) at parent * (1,0,0): (1,2,3) + R_y(90) * 2 * (1,0,0) = (1,2,1).
    let child = g.scene.triangles[0].vertices;
    assert!(child[0].abs_diff_eq(Vec3::new(1.0, 2.0, 1.0), 1e-5), "{child:?}");
    assert!(child[1].abs_diff_eq(Vec3::new(1.0, 2.0, -1.0), 1e-5));
    assert!(child[2].abs_diff_eq(Vec3::new(1.0, 4.0, 1.0), 1e-5));
    // The authored front (+Z locally) maps to +X under R_y(90).
    assert!(normal(child).abs_diff_eq(Vec3::X, 1e-5));
    // The mirrored instance keeps its front facing R_y(90) * +Z = +X too.
    let mirror = g.scene.triangles[1].vertices;
    assert!(normal(mirror).abs_diff_eq(Vec3::X, 1e-5), "{mirror:?}");
    assert!(rig
        .pose(0.0)
        .triangles
        .iter()
        .zip(&g.scene.triangles)
        .all(|(p, t)| { p.iter().zip(t.vertices).all(|(a, b)| a.abs_diff_eq(b, 1e-5)) }));

    assert_eq!(rig.channels.len(), 2);
    assert_eq!(rig.channels[0].interpolation, Interpolation::Step);
    assert_eq!(rig.channels[1].interpolation, Interpolation::CubicSpline);
    assert_eq!(rig.duration(), 2.0);
    assert!(rig.animates_geometry() && !rig.animates_camera());
    // STEP: the child's translation jumps to (1, 1, 0) at t = 1, i.e. by
    // R_y(90) * S * (0,1,0) = (0, s, 0) with the parent's scale s at t.
    let scale_at = |t: f32| {
        let (s, _, _) = rig.world_transforms(t)[0].to_scale_rotation_translation();
        s
    };
    let before = rig.pose(0.999).triangles[0][0];
    let after = rig.pose(1.0).triangles[0][0];
    let s1 = scale_at(1.0);
    assert!((after - before).y > 0.9 * s1.y, "{before} {after}");
    // CUBICSPLINE scale at t = 1 (s = 0.5, d = 2): 0.5 v0 + 0.25 b0 + 0.5 v1 - 0.25 a1.
    let expected = Vec3::new(3.25, 2.875, 1.5);
    assert!(s1.abs_diff_eq(expected, 1e-4), "{s1}");
    assert!(scale_at(0.0).abs_diff_eq(Vec3::splat(2.0), 1e-5));
    assert!(scale_at(5.0).abs_diff_eq(Vec3::new(4.0, 3.0, 2.0), 1e-5));
    let child_world = rig.world_transforms(1.0)[1];
    let expected_origin = rig.world_transforms(1.0)[0].transform_point3(Vec3::new(1.0, 1.0, 0.0));
    assert!(child_world.w_axis.truncate().abs_diff_eq(expected_origin, 1e-5));
    assert!(after.abs_diff_eq(expected_origin, 1e-5));
}

#[test]
fn animated_room_has_camera_and_object_motion() {
    let g = load(&fixture("animated_room.gltf"));
    let (s, rig) = (&g.scene, &g.rig);
    assert_eq!(s.triangles.len(), 4 * 2 + 2 + 12);
    assert_eq!(rig.instances.len(), 6);
    assert!(g.notices.is_empty(), "{:?}", g.notices);
    let index = |name: &str| rig.nodes.iter().position(|n| n.name == name).expect(name);
    let (table, cube, camera) = (index("table"), index("cube"), index("camera"));
    assert_eq!(rig.nodes[cube].parent, Some(table));
    assert_eq!(rig.nodes[table].parent, Some(index("room")));
    assert_eq!(rig.camera.map(|c| c.node), Some(camera));
    assert!((rig.camera.expect("camera").fov_y_degrees - 50.0).abs() < 1e-4);
    assert_eq!(rig.duration(), 2.0);
    assert!(rig.animates_geometry() && rig.animates_camera());

    // Camera keys: translation at and between keyframes.
    let eyes = [
        Vec3::new(0.0, 1.3, 3.6),
        Vec3::new(0.8, 1.4, 3.3),
        Vec3::new(-0.6, 1.2, 3.4),
    ];
    assert!(s.camera.origin.abs_diff_eq(eyes[0], 1e-5));
    let at = |t: f32| rig.pose(t).camera.expect("camera");
    assert!(at(1.0).origin.abs_diff_eq(eyes[1], 1e-5));
    assert!(at(2.0).origin.abs_diff_eq(eyes[2], 1e-5));
    assert!(at(9.0).origin.abs_diff_eq(eyes[2], 1e-5));
    assert!(at(0.5).origin.abs_diff_eq((eyes[0] + eyes[1]) * 0.5, 1e-5));
    // Rotation halfway between keys 1 and 2 is their slerp.
    let rot = |t: f32| rig.world_transforms(t)[camera].to_scale_rotation_translation().1;
    let halfway = rot(1.0).slerp(rot(2.0), 0.5);
    let forward = (at(1.5).target - at(1.5).origin).normalize();
    assert!(forward.abs_diff_eq(halfway * Vec3::NEG_Z, 1e-4), "{forward}");
    // The rest camera looks at the room (down and along -Z).
    let f = s.camera.target - s.camera.origin;
    assert!(f.z < -0.9 && f.y < 0.0, "{f}");

    // The cube moves in the scaled, rotated table's space.
    let table_m = rig.world_transforms(1.0)[table];
    let centre = rig.world_transforms(1.0)[cube].w_axis.truncate();
    assert!(centre.abs_diff_eq(table_m.transform_point3(Vec3::new(0.0, 0.2, 0.3)), 1e-5));
    let inst = rig
        .instances
        .iter()
        .find(|i| i.node == cube)
        .expect("cube instance");
    assert_eq!(inst.triangle_count, 12);
    let mean = |t: f32| {
        let p = rig.pose(t);
        let tris = &p.triangles[inst.first_triangle..inst.first_triangle + inst.triangle_count];
        tris.iter().flatten().copied().sum::<Vec3>() / (3 * tris.len()) as f32
    };
    assert!(mean(1.0).abs_diff_eq(centre, 1e-4));
    assert!(mean(0.0).distance(mean(2.0)) > 1.0);
    // The cube sits on the floor: table scale 1.5, half size 0.2, at y 0.2.
    let lowest = rig.pose(0.5).triangles[inst.first_triangle..inst.first_triangle + 12]
        .iter()
        .flatten()
        .map(|v| v.y)
        .fold(f32::INFINITY, f32::min);
    assert!(lowest.abs() < 1e-5, "{lowest}");

    let gpu = SceneGpu::build(s).expect("builds");
    assert_eq!(gpu.emitter_count, 2);

    // Camera selection.
    assert_eq!(
        load_gltf(fixture("animated_room.gltf"), Some(0)).expect("camera 0"),
        g
    );
    let (element, reason) = content_error(load_gltf(fixture("animated_room.gltf"), Some(1)));
    assert!(
        element.contains("camera index 1") && reason.contains("1 camera node"),
        "{reason}"
    );
    let (_, reason) = content_error(load_gltf(fixture("emissive_quad.glb"), Some(0)));
    assert!(reason.contains("0 camera node"), "{reason}");
}

#[test]
fn unusable_content_is_an_error() {
    // Only the camera node: no triangle.
    let (element, reason) = content_error(load_patched(|doc, _| doc["scenes"][0]["nodes"] = json!([2])));
    assert_eq!(
        (element.as_str(), reason.as_str()),
        ("scene 'textured_quad'", "contains no triangles")
    );
    let (_, reason) = content_error(load_patched(|doc, _| {
        let o = doc.as_object_mut().expect("object");
        o.remove("scenes");
        o.remove("scene");
    }));
    assert!(reason.contains("no scene"), "{reason}");
    // POINTS.
    let (element, reason) = content_error(load_patched(|doc, _| {
        doc["meshes"][1]["primitives"][0]["mode"] = json!(0)
    }));
    assert_eq!(element, "mesh 'light_quad' primitive 0");
    assert!(reason.contains("Points"), "{reason}");
    // Textured material, no UVs.
    let (_, reason) = content_error(load_patched(|doc, _| {
        let attributes = doc["meshes"][0]["primitives"][0]["attributes"]
            .as_object_mut()
            .expect("map");
        attributes.remove("TEXCOORD_0");
    }));
    assert!(reason.contains("no TEXCOORD_0"), "{reason}");
    // Different sets for base colour and emission.
    let (element, _) = content_error(load_patched(|doc, _| {
        doc["materials"][0]["emissiveTexture"] = json!({"index": 0, "texCoord": 1});
    }));
    assert_eq!(element, "material 'checker'");
    // Negative colour.
    let (element, _) = content_error(load_patched(|doc, _| {
        doc["materials"][1]["emissiveFactor"] = json!([1, -1, 0])
    }));
    assert_eq!(element, "material 'light'");
    // Orthographic camera.
    let (element, reason) = content_error(load_patched(|doc, _| {
        doc["cameras"][0] =
            json!({"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 1, "znear": 0.1, "zfar": 10}});
    }));
    assert_eq!(element, "camera 0");
    assert!(reason.contains("not supported"), "{reason}");
    // A node that is its own grandchild.
    let (element, _) = content_error(load_patched(|doc, _| {
        doc["nodes"][0]["children"] = json!([1]);
        doc["nodes"][1]["children"] = json!([0]);
    }));
    assert_eq!(element, "node 'quad'");
    // Non-finite node transform.
    let (element, _) = content_error(load_patched(|doc, _| {
        doc["nodes"][0]["scale"] = json!([1e39, 1, 1])
    }));
    assert_eq!(element, "node 'quad'");
}

#[test]
fn ignored_features_give_notices() {
    let g = load_patched(|doc, _| {
        doc["materials"][0]["pbrMetallicRoughness"]
            .as_object_mut()
            .expect("pbr")
            .remove("metallicFactor"); // glTF's default: 1
        doc["materials"][1]["occlusionTexture"] = json!({"index": 0});
        doc["extensionsUsed"] = json!(["KHR_materials_emissive_strength", "KHR_materials_sheen"]);
        doc["materials"][0]["extensions"]["KHR_materials_sheen"] = json!({"sheenColorFactor": [1, 1, 1]});
    })
    .expect("loads");
    let n = &g.notices;
    // Without metallicFactor the material is glTF's default metal, and its
    // specularFactor 0 no longer makes it Lambertian: that is noticed.
    assert_eq!(
        g.scene.materials[0].bsdf,
        Bsdf::MetallicRoughness {
            metallic: 1.0,
            roughness: 1.0,
            texture: None
        }
    );
    assert_eq!(
        n.iter().filter(|l| l.contains("KHR_materials_specular")).count(),
        1,
        "{n:?}"
    );
    assert!(n.iter().any(|l| l.contains("KHR_materials_sheen")), "{n:?}");
    assert!(
        n.iter().any(|l| l.contains("occlusion textures are ignored")),
        "{n:?}"
    );
    assert!(!n.iter().any(|l| l.contains("emissive_strength")), "{n:?}");
    // A required extension that is not supported is an error.
    let err = load_patched(|doc, _| doc["extensionsRequired"] = json!(["KHR_materials_sheen"]))
        .expect_err("required");
    assert!(matches!(err, Error::GltfLoad { .. }), "{err}");
}

/// `metallic_quad.gltf`: factors and the metallic-roughness texture are
/// read (its image as written: linear bytes, green roughness, blue
/// metallic), omitted factors take glTF's defaults (1, 1), and the GPU form
/// carries the model, factors and texture.
#[test]
fn metallic_roughness_factors_and_texture_are_read() {
    let g = load(&fixture("metallic_quad.gltf"));
    assert!(g.notices.is_empty(), "{:?}", g.notices);
    let m = &g.scene.materials;
    assert_eq!(m.len(), 3);
    assert_eq!(m[0].name, "brushed");
    assert!(m[0].albedo.abs_diff_eq(Vec3::new(0.9, 0.6, 0.3), 1e-6));
    let texture = TextureRef {
        image: 0,
        wrap_u: Wrap::Repeat,
        wrap_v: Wrap::Repeat,
        filter: Filter::Nearest,
        transform: None,
    };
    assert_eq!(
        m[0].bsdf,
        Bsdf::MetallicRoughness {
            metallic: 0.8,
            roughness: 0.5,
            texture: Some(texture)
        }
    );
    assert_eq!(
        m[1].bsdf,
        Bsdf::MetallicRoughness {
            metallic: 1.0,
            roughness: 1.0,
            texture: None
        }
    );
    assert_eq!(m[2].bsdf, Bsdf::Lambert);
    let img = &g.scene.images[0];
    assert_eq!((img.name.as_str(), img.width, img.height), ("metal_rough", 2, 2));
    assert_eq!(
        img.texels,
        [
            [0, 255, 255, 255],
            [0, 128, 64, 255],
            [0, 0, 255, 255],
            [0, 255, 0, 255]
        ]
    );
    let gpu = SceneGpu::build(&g.scene).expect("builds");
    use kernels::abi::{MODEL_LAMBERT, MODEL_METALLIC_ROUGHNESS, TEXTURE_NONE};
    let mat = gpu.materials[0];
    assert_eq!(mat.model.x, MODEL_METALLIC_ROUGHNESS);
    assert_eq!((mat.pbr.x, mat.pbr.y), (0.8, 0.5));
    assert_eq!(mat.model.y, 0);
    assert_eq!(gpu.materials[1].model.y, TEXTURE_NONE);
    assert_eq!(gpu.materials[2].model.x, MODEL_LAMBERT);
    // The kernel's lookup: texel (1, 0) (u in [0.5, 1), v in [0, 0.5)) has
    // green 128 and blue 64: metallic 0.8 * 64/255, roughness 0.5 * 128/255.
    let mr = kernels::surface::surface_metallic_roughness(
        &mat,
        &gpu.images,
        gpu.image_count,
        Vec2::new(0.75, 0.25),
    );
    assert!((mr.x - 0.8 * 64.0 / 255.0).abs() < 1e-6, "{mr}");
    assert!((mr.y - 0.5 * 128.0 / 255.0).abs() < 1e-6, "{mr}");
    // Out-of-range factors (which the schema forbids) are refused.
    let bad = load_fixture_patched("metallic_quad", |doc, _| {
        doc["materials"][0]["pbrMetallicRoughness"]["roughnessFactor"] = json!(1.5)
    });
    let refused = match bad {
        Err(e) => e.to_string(),
        Ok(g) => SceneGpu::build(&g.scene).expect_err("roughness 1.5").to_string(),
    };
    assert!(refused.contains("1.5"), "{refused}");
}

/// Single-byte corruptions of the fixtures (JSON, GLB container and
/// binary data) give errors or scenes, never panics.
#[test]
fn corrupted_files_never_panic() {
    let dir = fixture_copy();
    for name in ["hierarchy.glb", "emissive_quad.glb", "textured_quad.gltf"] {
        let path = dir.path().join(name);
        let bytes = fs::read(&path).expect("read");
        let mut loaded = 0;
        // (Whitespace of the pretty-printed JSON is skipped: editing it is pointless.)
        for at in (0..bytes.len()).filter(|&i| !bytes[i].is_ascii_whitespace()) {
            for value in [b'9', b'-', 0xff] {
                let mut b = bytes.clone();
                b[at] = value;
                fs::write(&path, &b).expect("write");
                match std::panic::catch_unwind(|| load_gltf(&path, None)) {
                    Ok(Ok(_)) => loaded += 1,
                    Ok(Err(_)) => {}
                    Err(_) => panic!("{name}: panic with byte {at} set to {value}"),
                }
            }
        }
        assert!(loaded > 0, "{name}");
    }
}
