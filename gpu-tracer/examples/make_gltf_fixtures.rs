//! Writes the glTF test fixtures of `gpu-tracer/tests/data/gltf/` (or of
//! the directory given as the first argument):
//!
//! - `checker.png`: a 4x4 high-contrast checker (texel (0, 0), top left,
//!   light);
//! - `textured_quad.gltf` + `.bin`: a 2x2 quad in the `z = 0` plane with the
//!   checker (NEAREST, REPEAT, UVs 0..2), an emissive quad light and a
//!   camera node at `(0, 0, 3)` looking along `-Z`;
//! - `emissive_quad.glb`: a grey floor and an emissive quad
//!   (`KHR_materials_emissive_strength` 4), no camera;
//! - `animated_room.gltf` + `.bin`: floor and three checker walls, a ceiling
//!   light, a cube under a scaled and rotated "table" node moving with a
//!   LINEAR translation, and a camera with 3 LINEAR keys (translation and
//!   rotation) over 2 seconds;
//! - `hierarchy.glb`: a triangle under a translated, rotated and scaled
//!   parent (plus a mirrored instance), with a STEP and a CUBICSPLINE channel;
//! - `cornell_textured.gltf` + `.bin`: the built-in Cornell box
//!   (`gpu_tracer::cornell::cornell_box`, same triangles, object order,
//!   material order and camera) with the checker on every surface but the
//!   light: planar texture coordinates, one checker texel per
//!   [`CORNELL_TEXEL`] world units (about 5 px at 256x256). The textured
//!   scene of issue 14's demodulation study;
//! - `metal_rough.png`: a 2x2 metallic-roughness texture (linear data: green
//!   roughness, blue metallic; [`METAL_ROUGH_TEXELS`]);
//! - `metallic_quad.gltf` + `.bin`: two quads and a light: `brushed`
//!   (metallic 0.8, roughness 0.5, the metallic-roughness texture, NEAREST)
//!   and `plain` (no factors: glTF's defaults, metallic 1 and roughness 1);
//! - `punctual_lights.gltf` + `.bin`: a floor and a table lit only by
//!   `KHR_lights_punctual` lights;
//! - `smooth_sphere.gltf` + `.bin`: a coarse sphere with `NORMAL`s (the
//!   `smooth_sphere` module).
//!
//! The diffuse materials of every other fixture are written as exactly
//! Lambertian glTF: `metallicFactor` 0, an explicit `roughnessFactor` 1 and
//! `KHR_materials_specular` with `specularFactor` 0 (no specular lobe), so
//! that they render as the Lambertian scenes they stand for (the loader
//! follows the specification: without the extension a dielectric has a 4%
//! specular layer).
//!
//! Run with `cargo run -p gpu-tracer --example make_gltf_fixtures`.

#[path = "make_gltf_fixtures/smooth_sphere.rs"]
mod smooth_sphere;

use glam::{Mat3, Quat, Vec2, Vec3};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

const GENERATOR: &str = "gpu-tracer/examples/make_gltf_fixtures.rs";
const NEAREST: u32 = 9728;
const REPEAT: u32 = 10497;
const FLOAT: u32 = 5126;
const UNSIGNED_SHORT: u32 = 5123;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;

/// World units per checker texel in `cornell_textured` (the room is 556
/// units wide and fills about 170 of 256 pixels: one texel is about 5 px,
/// so most 4x4 sorting blocks straddle a texel edge).
const CORNELL_TEXEL: f32 = 16.0;

/// Light and dark texels of the checker (sRGB).
const LIGHT: [u8; 3] = [230, 220, 200];
const DARK: [u8; 3] = [40, 60, 90];

/// Texels of `metal_rough.png`, row-major from the top left, RGB (linear
/// data: red unused, green roughness, blue metallic).
const METAL_ROUGH_TEXELS: [[u8; 3]; 4] = [[0, 255, 255], [0, 128, 64], [0, 0, 255], [0, 255, 0]];

/// The extensions every fixture with Lambertian materials uses.
const EXTENSIONS: [&str; 2] = ["KHR_materials_emissive_strength", "KHR_materials_specular"];

/// A binary buffer with its buffer views and accessors.
#[derive(Default)]
struct Bin {
    data: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Bin {
    fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        while self.data.len() & 3 != 0 {
            self.data.push(0);
        }
        let mut v = json!({"buffer": 0, "byteOffset": self.data.len(), "byteLength": bytes.len()});
        if let Some(t) = target {
            v["target"] = json!(t);
        }
        self.data.extend_from_slice(bytes);
        self.views.push(v);
        self.views.len() - 1
    }

    /// A float accessor of `values.len() / components` elements of type `ty`
    /// (with min/max).
    fn floats(&mut self, values: &[f32], components: usize, ty: &str, target: Option<u32>) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, target);
        let mut min = vec![f32::INFINITY; components];
        let mut max = vec![f32::NEG_INFINITY; components];
        for e in values.chunks_exact(components) {
            for c in 0..components {
                min[c] = min[c].min(e[c]);
                max[c] = max[c].max(e[c]);
            }
        }
        self.accessors.push(json!({
            "bufferView": view, "componentType": FLOAT, "count": values.len() / components,
            "type": ty, "min": min, "max": max
        }));
        self.accessors.len() - 1
    }

    fn indices(&mut self, indices: &[u16]) -> usize {
        let bytes: Vec<u8> = indices.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, Some(ELEMENT_ARRAY_BUFFER));
        self.accessors.push(json!({
            "bufferView": view, "componentType": UNSIGNED_SHORT, "count": indices.len(), "type": "SCALAR"
        }));
        self.accessors.len() - 1
    }

    /// A primitive from positions, UVs and triangle indices.
    fn primitive(&mut self, mesh: &MeshData, material: Option<usize>, with_uvs: bool) -> Value {
        let p: Vec<f32> = mesh.positions.iter().flat_map(|v| v.to_array()).collect();
        let uv: Vec<f32> = mesh.uvs.iter().flat_map(|v| v.to_array()).collect();
        let position = self.floats(&p, 3, "VEC3", Some(ARRAY_BUFFER));
        let mut attributes = json!({"POSITION": position});
        if with_uvs {
            attributes["TEXCOORD_0"] = json!(self.floats(&uv, 2, "VEC2", Some(ARRAY_BUFFER)));
        }
        let indices = self.indices(&mesh.indices);
        let mut prim = json!({"attributes": attributes, "indices": indices});
        if let Some(m) = material {
            prim["material"] = json!(m);
        }
        prim
    }
}

#[derive(Default)]
struct MeshData {
    positions: Vec<Vec3>,
    uvs: Vec<Vec2>,
    indices: Vec<u16>,
}

impl MeshData {
    /// Adds a rectangle centred at `centre` whose front faces `normal`, with
    /// half sizes `half_u` along `u` and `half_v` along `normal x u`; UVs run
    /// over `[0, uv_scale.x] x [0, uv_scale.y]`, `v = 0` on the `+v` edge
    /// (glTF: `v` grows downwards in the image).
    fn quad(mut self, centre: Vec3, normal: Vec3, u: Vec3, half_u: f32, half_v: f32, uv_scale: Vec2) -> Self {
        let u = u.normalize() * half_u;
        let v = normal.normalize().cross(u).normalize() * half_v;
        let base = self.positions.len() as u16;
        self.positions
            .extend([centre - u - v, centre + u - v, centre + u + v, centre - u + v]);
        self.uvs.extend([
            Vec2::new(0.0, uv_scale.y),
            uv_scale,
            Vec2::new(uv_scale.x, 0.0),
            Vec2::ZERO,
        ]);
        self.indices.extend([0, 1, 2, 0, 2, 3].map(|i| base + i));
        self
    }

    /// An axis-aligned cube of half size `h` centred at the origin, faces
    /// outwards.
    fn cube(h: f32) -> Self {
        let mut m = MeshData::default();
        for (n, u) in [
            (Vec3::X, Vec3::NEG_Z),
            (Vec3::NEG_X, Vec3::Z),
            (Vec3::Y, Vec3::X),
            (Vec3::NEG_Y, Vec3::X),
            (Vec3::Z, Vec3::X),
            (Vec3::NEG_Z, Vec3::NEG_X),
        ] {
            m = m.quad(n * h, n, u, h, h, Vec2::ONE);
        }
        m
    }
}

fn checker_png() -> Vec<u8> {
    let img = image::RgbImage::from_fn(4, 4, |x, y| {
        image::Rgb(if (x + y) % 2 == 0 { LIGHT } else { DARK })
    });
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png)
        .expect("PNG encoding");
    out.into_inner()
}

fn metal_rough_png() -> Vec<u8> {
    let img = image::RgbImage::from_fn(2, 2, |x, y| image::Rgb(METAL_ROUGH_TEXELS[(y * 2 + x) as usize]));
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png)
        .expect("PNG encoding");
    out.into_inner()
}

fn asset() -> Value {
    json!({"version": "2.0", "generator": GENERATOR})
}

/// A Lambertian material (see the module docs).
fn material(name: &str, base: [f32; 3], texture: Option<usize>) -> Value {
    let mut pbr = json!({
        "baseColorFactor": [base[0], base[1], base[2], 1.0],
        "metallicFactor": 0.0,
        "roughnessFactor": 1.0
    });
    if let Some(t) = texture {
        pbr["baseColorTexture"] = json!({"index": t});
    }
    json!({
        "name": name,
        "pbrMetallicRoughness": pbr,
        "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}
    })
}

/// A black Lambertian emitter.
fn emissive(name: &str, factor: [f32; 3], strength: f32) -> Value {
    json!({
        "name": name,
        "pbrMetallicRoughness": {
            "baseColorFactor": [0.0, 0.0, 0.0, 1.0],
            "metallicFactor": 0.0,
            "roughnessFactor": 1.0
        },
        "emissiveFactor": factor,
        "extensions": {
            "KHR_materials_emissive_strength": {"emissiveStrength": strength},
            "KHR_materials_specular": {"specularFactor": 0.0}
        }
    })
}

/// The rotation of a camera at `eye` looking at `target` with `+Y` up
/// (glTF cameras look along local `-Z`).
fn look_rotation(eye: Vec3, target: Vec3) -> Quat {
    let forward = (target - eye).normalize();
    let right = forward.cross(Vec3::Y).normalize();
    let up = right.cross(forward);
    Quat::from_mat3(&Mat3::from_cols(right, up, -forward)).normalize()
}

fn write_gltf(dir: &Path, name: &str, mut doc: Value, bin: Bin) {
    let bin_name = format!("{name}.bin");
    doc["buffers"] = json!([{"uri": bin_name, "byteLength": bin.data.len()}]);
    doc["bufferViews"] = json!(bin.views);
    doc["accessors"] = json!(bin.accessors);
    write(dir, &bin_name, &bin.data);
    let text = serde_json::to_string_pretty(&doc).expect("JSON") + "\n";
    write(dir, &format!("{name}.gltf"), text.as_bytes());
}

fn write_glb(dir: &Path, name: &str, mut doc: Value, bin: Bin) {
    doc["buffers"] = json!([{"byteLength": bin.data.len()}]);
    doc["bufferViews"] = json!(bin.views);
    doc["accessors"] = json!(bin.accessors);
    let mut json_chunk = serde_json::to_vec(&doc).expect("JSON");
    while json_chunk.len() & 3 != 0 {
        json_chunk.push(b' ');
    }
    let mut bin_chunk = bin.data;
    while bin_chunk.len() & 3 != 0 {
        bin_chunk.push(0);
    }
    let total = 12 + 8 + json_chunk.len() + 8 + bin_chunk.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json_chunk.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json_chunk);
    out.extend_from_slice(&(bin_chunk.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin_chunk);
    write(dir, &format!("{name}.glb"), &out);
}

fn write(dir: &Path, name: &str, bytes: &[u8]) {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
    println!("{:>6} bytes  {}", bytes.len(), path.display());
}

fn checker_texture_parts() -> Value {
    json!({
        "images": [{"uri": "checker.png", "name": "checker"}],
        "samplers": [{"magFilter": NEAREST, "minFilter": NEAREST, "wrapS": REPEAT, "wrapT": REPEAT}],
        "textures": [{"sampler": 0, "source": 0}],
    })
}

fn textured_quad(dir: &Path) {
    let mut bin = Bin::default();
    let quad = MeshData::default().quad(Vec3::ZERO, Vec3::Z, Vec3::X, 1.0, 1.0, Vec2::splat(2.0));
    let light_normal = Vec3::new(0.0, -1.0, -1.0).normalize();
    let light = MeshData::default().quad(
        Vec3::new(0.0, 1.5, 1.5),
        light_normal,
        Vec3::X,
        0.25,
        0.25,
        Vec2::ONE,
    );
    let quad_prim = bin.primitive(&quad, Some(0), true);
    let light_prim = bin.primitive(&light, Some(1), false);
    let mut doc = checker_texture_parts();
    doc["asset"] = asset();
    doc["extensionsUsed"] = json!(EXTENSIONS);
    doc["materials"] = json!([
        material("checker", [1.0, 1.0, 1.0], Some(0)),
        emissive("light", [1.0, 0.9, 0.8], 30.0)
    ]);
    doc["meshes"] = json!([
        {"name": "checker_quad", "primitives": [quad_prim]},
        {"name": "light_quad", "primitives": [light_prim]}
    ]);
    doc["cameras"] = json!([{
        "name": "front", "type": "perspective",
        "perspective": {"yfov": 45f32.to_radians(), "znear": 0.1, "aspectRatio": 1.0}
    }]);
    doc["nodes"] = json!([
        {"name": "quad", "mesh": 0},
        {"name": "light", "mesh": 1},
        {"name": "camera", "camera": 0, "translation": [0.0, 0.0, 3.0]}
    ]);
    doc["scenes"] = json!([{"name": "textured_quad", "nodes": [0, 1, 2]}]);
    doc["scene"] = json!(0);
    write_gltf(dir, "textured_quad", doc, bin);
}

fn emissive_quad(dir: &Path) {
    let mut bin = Bin::default();
    let floor = MeshData::default().quad(Vec3::ZERO, Vec3::Y, Vec3::X, 2.0, 2.0, Vec2::ONE);
    let lamp = MeshData::default().quad(Vec3::ZERO, Vec3::NEG_Y, Vec3::X, 0.5, 0.5, Vec2::ONE);
    let floor_prim = bin.primitive(&floor, Some(0), false);
    let lamp_prim = bin.primitive(&lamp, Some(1), false);
    let doc = json!({
        "asset": asset(),
        "extensionsUsed": EXTENSIONS,
        "materials": [material("grey", [0.5, 0.5, 0.5], None), emissive("lamp", [1.0, 0.8, 0.6], 4.0)],
        "meshes": [
            {"name": "floor", "primitives": [floor_prim]},
            {"name": "lamp", "primitives": [lamp_prim]}
        ],
        "nodes": [
            {"name": "floor", "mesh": 0},
            {"name": "lamp", "mesh": 1, "translation": [0.0, 1.5, 0.0]}
        ],
        "scenes": [{"name": "emissive_quad", "nodes": [0, 1]}],
        "scene": 0
    });
    write_glb(dir, "emissive_quad", doc, bin);
}

fn animated_room(dir: &Path) {
    let mut bin = Bin::default();
    let wall_h = 1.25;
    let floor = MeshData::default().quad(Vec3::ZERO, Vec3::Y, Vec3::X, 2.0, 2.0, Vec2::splat(4.0));
    let back = MeshData::default().quad(
        Vec3::new(0.0, wall_h, -2.0),
        Vec3::Z,
        Vec3::X,
        2.0,
        wall_h,
        Vec2::new(4.0, 2.5),
    );
    let left = MeshData::default().quad(
        Vec3::new(-2.0, wall_h, 0.0),
        Vec3::X,
        Vec3::NEG_Z,
        2.0,
        wall_h,
        Vec2::new(4.0, 2.5),
    );
    let right = MeshData::default().quad(
        Vec3::new(2.0, wall_h, 0.0),
        Vec3::NEG_X,
        Vec3::Z,
        2.0,
        wall_h,
        Vec2::new(4.0, 2.5),
    );
    let light = MeshData::default().quad(
        Vec3::new(0.0, 2.45, -0.5),
        Vec3::NEG_Y,
        Vec3::X,
        0.5,
        0.3,
        Vec2::ONE,
    );
    let cube = MeshData::cube(0.2);
    let prims = [
        bin.primitive(&floor, Some(0), true),
        bin.primitive(&back, Some(0), true),
        bin.primitive(&left, Some(0), true),
        bin.primitive(&right, Some(0), true),
        bin.primitive(&light, Some(1), false),
        bin.primitive(&cube, Some(2), false),
    ];

    // Cube: LINEAR translation in the table's space over 2 s.
    let times = [0.0f32, 1.0, 2.0];
    let cube_keys = [
        Vec3::new(-0.6, 0.2, 0.0),
        Vec3::new(0.0, 0.2, 0.3),
        Vec3::new(0.6, 0.2, 0.0),
    ];
    // Camera: 3 LINEAR keys of translation and rotation over 2 s.
    let eyes = [
        Vec3::new(0.0, 1.3, 3.6),
        Vec3::new(0.8, 1.4, 3.3),
        Vec3::new(-0.6, 1.2, 3.4),
    ];
    let look_at = [
        Vec3::new(0.0, 0.7, -0.6),
        Vec3::new(0.2, 0.6, -0.5),
        Vec3::new(-0.1, 0.7, -0.7),
    ];
    let rotations: Vec<Quat> = eyes
        .iter()
        .zip(look_at)
        .map(|(&e, t)| look_rotation(e, t))
        .collect();
    let time_acc = bin.floats(&times, 1, "SCALAR", None);
    let cube_acc = bin.floats(
        &cube_keys.iter().flat_map(|v| v.to_array()).collect::<Vec<_>>(),
        3,
        "VEC3",
        None,
    );
    let eye_acc = bin.floats(
        &eyes.iter().flat_map(|v| v.to_array()).collect::<Vec<_>>(),
        3,
        "VEC3",
        None,
    );
    let rot_acc = bin.floats(
        &rotations.iter().flat_map(|q| q.to_array()).collect::<Vec<_>>(),
        4,
        "VEC4",
        None,
    );
    let table_rotation = Quat::from_rotation_y(20f32.to_radians());

    let mut doc = checker_texture_parts();
    doc["asset"] = asset();
    doc["extensionsUsed"] = json!(EXTENSIONS);
    doc["materials"] = json!([
        material("checker_wall", [0.9, 0.9, 0.9], Some(0)),
        emissive("ceiling_light", [1.0, 0.9, 0.75], 20.0),
        material("cube", [0.8, 0.3, 0.2], None)
    ]);
    let names = [
        "floor",
        "back_wall",
        "left_wall",
        "right_wall",
        "ceiling_light",
        "cube",
    ];
    doc["meshes"] = json!(names
        .iter()
        .zip(prims)
        .map(|(n, p)| json!({"name": n, "primitives": [p]}))
        .collect::<Vec<_>>());
    doc["cameras"] = json!([{
        "name": "walkthrough", "type": "perspective",
        "perspective": {"yfov": 50f32.to_radians(), "znear": 0.05, "aspectRatio": 1.5}
    }]);
    doc["nodes"] = json!([
        {"name": "room", "children": [1, 2, 3, 4, 5, 6]},
        {"name": "floor", "mesh": 0},
        {"name": "back_wall", "mesh": 1},
        {"name": "left_wall", "mesh": 2},
        {"name": "right_wall", "mesh": 3},
        {"name": "ceiling_light", "mesh": 4},
        {
            "name": "table", "children": [7],
            "translation": [0.3, 0.0, -0.5], "rotation": table_rotation.to_array(), "scale": [1.5, 1.5, 1.5]
        },
        {"name": "cube", "mesh": 5, "translation": cube_keys[0].to_array()},
        {
            "name": "camera", "camera": 0,
            "translation": eyes[0].to_array(), "rotation": rotations[0].to_array()
        }
    ]);
    doc["animations"] = json!([{
        "name": "walkthrough",
        "samplers": [
            {"input": time_acc, "output": cube_acc, "interpolation": "LINEAR"},
            {"input": time_acc, "output": eye_acc, "interpolation": "LINEAR"},
            {"input": time_acc, "output": rot_acc, "interpolation": "LINEAR"}
        ],
        "channels": [
            {"sampler": 0, "target": {"node": 7, "path": "translation"}},
            {"sampler": 1, "target": {"node": 8, "path": "translation"}},
            {"sampler": 2, "target": {"node": 8, "path": "rotation"}}
        ]
    }]);
    doc["scenes"] = json!([{"name": "animated_room", "nodes": [0, 8]}]);
    doc["scene"] = json!(0);
    write_gltf(dir, "animated_room", doc, bin);
}

fn hierarchy(dir: &Path) {
    let mut bin = Bin::default();
    let tri = MeshData {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
        uvs: vec![Vec2::ZERO; 3],
        indices: vec![0, 1, 2],
    };
    let prim = bin.primitive(&tri, None, false);
    // STEP translation of "child": 3 keys.
    let step_times = bin.floats(&[0.0, 1.0, 2.0], 1, "SCALAR", None);
    let step_values = bin.floats(&[1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 1.0, 2.0, 0.0], 3, "VEC3", None);
    // CUBICSPLINE scale of "parent": keys at 0 and 2 s, (in, value, out) per key.
    let cubic_times = bin.floats(&[0.0, 2.0], 1, "SCALAR", None);
    let cubic_values = bin.floats(
        &[
            0.0, 0.0, 0.0, // in-tangent, key 0 (unused)
            2.0, 2.0, 2.0, // value, key 0
            1.0, 0.5, 0.0, // out-tangent, key 0
            0.0, -1.0, 2.0, // in-tangent, key 1
            4.0, 3.0, 2.0, // value, key 1
            0.0, 0.0, 0.0, // out-tangent, key 1 (unused)
        ],
        3,
        "VEC3",
        None,
    );
    let doc = json!({
        "asset": asset(),
        "meshes": [{"name": "tri", "primitives": [prim]}],
        "nodes": [
            {
                "name": "parent", "children": [1, 2],
                "translation": [1.0, 2.0, 3.0],
                "rotation": Quat::from_rotation_y(std::f32::consts::FRAC_PI_2).to_array(),
                "scale": [2.0, 2.0, 2.0]
            },
            {"name": "child", "mesh": 0, "translation": [1.0, 0.0, 0.0]},
            {"name": "mirror", "mesh": 0, "translation": [0.0, 0.0, 1.0], "scale": [-1.0, 1.0, 1.0]}
        ],
        "animations": [{
            "name": "hierarchy_anim",
            "samplers": [
                {"input": step_times, "output": step_values, "interpolation": "STEP"},
                {"input": cubic_times, "output": cubic_values, "interpolation": "CUBICSPLINE"}
            ],
            "channels": [
                {"sampler": 0, "target": {"node": 1, "path": "translation"}},
                {"sampler": 1, "target": {"node": 0, "path": "scale"}}
            ]
        }],
        "scenes": [{"name": "hierarchy", "nodes": [0]}],
        "scene": 0
    });
    write_glb(dir, "hierarchy", doc, bin);
}

/// Planar texture coordinates of a point on a face with normal `n`: the two
/// world axes across the face's dominant axis, [`CORNELL_TEXEL`] units per
/// texel of the 4-texel checker.
fn planar_uv(p: Vec3, n: Vec3) -> Vec2 {
    let a = n.abs();
    let (u, v) = if a.x >= a.y && a.x >= a.z {
        (p.z, p.y)
    } else if a.y >= a.z {
        (p.x, p.z)
    } else {
        (p.x, p.y)
    };
    Vec2::new(u, v) / (4.0 * CORNELL_TEXEL)
}

fn cornell_textured(dir: &Path) {
    use gpu_tracer::cornell::{cornell_box, LIGHT};
    let scene = cornell_box();
    let mut bin = Bin::default();
    let objects = scene
        .triangles
        .iter()
        .map(|t| t.object)
        .max()
        .map_or(0, |m| m + 1);
    let mut meshes = Vec::new();
    let mut nodes = Vec::new();
    for object in 0..objects {
        let tris: Vec<_> = scene.triangles.iter().filter(|t| t.object == object).collect();
        let material = tris[0].material;
        assert!(
            tris.iter().all(|t| t.material == material),
            "object {object} has one material"
        );
        let mut mesh = MeshData::default();
        for t in &tris {
            let [a, b, c] = t.vertices;
            let n = (b - a).cross(c - a);
            for p in t.vertices {
                mesh.indices.push(mesh.positions.len() as u16);
                mesh.positions.push(p);
                mesh.uvs.push(planar_uv(p, n));
            }
        }
        let textured = material != LIGHT;
        meshes.push(json!({
            "name": format!("object_{object}"),
            "primitives": [bin.primitive(&mesh, Some(material as usize), textured)]
        }));
        nodes.push(json!({"name": format!("object_{object}"), "mesh": object}));
    }
    let materials: Vec<Value> = scene
        .materials
        .iter()
        .enumerate()
        .map(|(i, m)| {
            if i as u32 == LIGHT {
                let e = m.emission;
                let strength = e.max_element();
                let mut v = emissive(&m.name, (e / strength).to_array(), strength);
                v["pbrMetallicRoughness"]["baseColorFactor"] =
                    json!([m.albedo.x, m.albedo.y, m.albedo.z, 1.0]);
                v
            } else {
                material(&m.name, m.albedo.to_array(), Some(0))
            }
        })
        .collect();
    let cam = scene.camera;
    nodes.push(json!({
        "name": "camera", "camera": 0,
        "translation": cam.origin.to_array(),
        "rotation": look_rotation(cam.origin, cam.target).to_array()
    }));
    let mut doc = checker_texture_parts();
    doc["asset"] = asset();
    doc["extensionsUsed"] = json!(EXTENSIONS);
    doc["materials"] = json!(materials);
    doc["meshes"] = json!(meshes);
    doc["cameras"] = json!([{
        "name": "cornell", "type": "perspective",
        "perspective": {"yfov": cam.fov_y_degrees.to_radians(), "znear": 1.0, "aspectRatio": 1.0}
    }]);
    doc["nodes"] = json!(nodes);
    doc["scenes"] = json!([{"name": "cornell_textured", "nodes": (0..=objects).collect::<Vec<_>>()}]);
    doc["scene"] = json!(0);
    write_gltf(dir, "cornell_textured", doc, bin);
}

fn metallic_quad(dir: &Path) {
    let mut bin = Bin::default();
    let brushed = MeshData::default().quad(Vec3::new(-1.1, 0.0, 0.0), Vec3::Z, Vec3::X, 1.0, 1.0, Vec2::ONE);
    let plain = MeshData::default().quad(Vec3::new(1.1, 0.0, 0.0), Vec3::Z, Vec3::X, 1.0, 1.0, Vec2::ONE);
    let light = MeshData::default().quad(
        Vec3::new(0.0, 0.0, 2.0),
        Vec3::NEG_Z,
        Vec3::X,
        0.5,
        0.5,
        Vec2::ONE,
    );
    let prims = [
        bin.primitive(&brushed, Some(0), true),
        bin.primitive(&plain, Some(1), false),
        bin.primitive(&light, Some(2), false),
    ];
    let mut doc = json!({
        "images": [{"uri": "metal_rough.png", "name": "metal_rough"}],
        "samplers": [{"magFilter": NEAREST, "minFilter": NEAREST, "wrapS": REPEAT, "wrapT": REPEAT}],
        "textures": [{"sampler": 0, "source": 0}],
    });
    doc["asset"] = asset();
    doc["extensionsUsed"] = json!(EXTENSIONS);
    doc["materials"] = json!([
        {
            "name": "brushed",
            "pbrMetallicRoughness": {
                "baseColorFactor": [0.9, 0.6, 0.3, 1.0],
                "metallicFactor": 0.8,
                "roughnessFactor": 0.5,
                "metallicRoughnessTexture": {"index": 0}
            }
        },
        {"name": "plain"},
        emissive("light", [1.0, 1.0, 1.0], 5.0)
    ]);
    doc["meshes"] = json!([
        {"name": "brushed", "primitives": [prims[0]]},
        {"name": "plain", "primitives": [prims[1]]},
        {"name": "light", "primitives": [prims[2]]}
    ]);
    doc["nodes"] =
        json!([{"name": "brushed", "mesh": 0}, {"name": "plain", "mesh": 1}, {"name": "light", "mesh": 2}]);
    doc["scenes"] = json!([{"name": "metallic_quad", "nodes": [0, 1, 2]}]);
    doc["scene"] = json!(0);
    write_gltf(dir, "metallic_quad", doc, bin);
}

/// A scene lit only by `KHR_lights_punctual` lights (which it requires): a
/// grey floor and a raised table top, a warm point light, a spot light
/// aimed down through the table's edge and a dim directional light; no
/// emissive material, so without the extension it would render black.
fn punctual_lights(dir: &Path) {
    let mut bin = Bin::default();
    let floor = MeshData::default().quad(Vec3::ZERO, Vec3::Y, Vec3::X, 3.0, 3.0, Vec2::ONE);
    let top = MeshData::default().quad(Vec3::new(0.3, 0.6, 0.0), Vec3::Y, Vec3::X, 0.6, 0.4, Vec2::ONE);
    let prims = [
        bin.primitive(&floor, Some(0), false),
        bin.primitive(&top, Some(1), false),
    ];
    let eye = Vec3::new(0.0, 3.0, 4.0);
    let camera = look_rotation(eye, Vec3::new(0.0, 0.3, 0.0));
    // A spot light above the table shining straight down (-z turned to -y).
    let down = Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2);
    let sun = Quat::from_rotation_x(-1.0) * Quat::from_rotation_y(0.6);
    let doc = json!({
        "asset": asset(),
        "extensionsUsed": ["KHR_materials_specular", "KHR_lights_punctual"],
        "extensionsRequired": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"name": "bulb", "type": "point", "color": [1.0, 0.85, 0.7], "intensity": 6.0, "range": 20.0},
            {"name": "spot", "type": "spot", "intensity": 12.0,
             "spot": {"innerConeAngle": 0.25, "outerConeAngle": 0.45}},
            {"name": "sun", "type": "directional", "color": [0.9, 0.95, 1.0], "intensity": 0.4}
        ]}},
        "materials": [material("floor", [0.6, 0.6, 0.6], None), material("table", [0.7, 0.45, 0.3], None)],
        "meshes": [
            {"name": "floor", "primitives": [prims[0]]},
            {"name": "table", "primitives": [prims[1]]}
        ],
        "cameras": [{
            "name": "view", "type": "perspective",
            "perspective": {"yfov": 50f32.to_radians(), "znear": 0.05, "aspectRatio": 1.0}
        }],
        "nodes": [
            {"name": "floor", "mesh": 0},
            {"name": "table", "mesh": 1},
            {"name": "bulb", "translation": [-1.2, 1.5, 0.8], "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"name": "spot", "translation": [0.8, 2.0, 0.0], "rotation": down.to_array(),
             "extensions": {"KHR_lights_punctual": {"light": 1}}},
            {"name": "sun", "rotation": sun.to_array(), "extensions": {"KHR_lights_punctual": {"light": 2}}},
            {"name": "camera", "camera": 0, "translation": eye.to_array(), "rotation": camera.to_array()}
        ],
        "scenes": [{"name": "punctual_lights", "nodes": [0, 1, 2, 3, 4, 5]}],
        "scene": 0
    });
    write_gltf(dir, "punctual_lights", doc, bin);
}

fn main() {
    let dir = std::env::args_os().nth(1).map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gltf"),
        PathBuf::from,
    );
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("cannot create {}: {e}", dir.display()));
    write(&dir, "checker.png", &checker_png());
    textured_quad(&dir);
    emissive_quad(&dir);
    animated_room(&dir);
    hierarchy(&dir);
    cornell_textured(&dir);
    write(&dir, "metal_rough.png", &metal_rough_png());
    metallic_quad(&dir);
    punctual_lights(&dir);
    smooth_sphere::smooth_sphere(&dir);
}
