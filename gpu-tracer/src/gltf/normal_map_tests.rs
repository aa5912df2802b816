//! Tests of normal maps on the patched `textured_quad` fixture: the
//! `normalTexture` (scale, sampler, `KHR_texture_transform`), the `TANGENT`
//! attribute, bad input, and CPU renders under a directional light whose
//! radiance follows the cosine the tilted normal predicts.

use super::tests::{content_error, load_patched, quad_accessor};
use super::GltfScene;
use crate::scene::{Light, Scene, SceneGpu, TraceSettings, UvTransform};
use glam::{Vec3, Vec4};
use serde_json::{json, Value};

/// PNG bytes of a 1x1 RGB image holding `texel`.
fn png(texel: [u8; 3]) -> Vec<u8> {
    let img = image::RgbImage::from_pixel(1, 1, image::Rgb(texel));
    let mut png = std::io::Cursor::new(Vec::new());
    img.write_to(&mut png, image::ImageFormat::Png).expect("PNG");
    png.into_inner()
}

/// `bytes` appended to `bin` (4-byte aligned) as a new buffer view; its index.
fn push_view(doc: &mut Value, bin: &mut Vec<u8>, bytes: &[u8]) -> usize {
    bin.resize(bin.len().next_multiple_of(4), 0);
    let offset = bin.len();
    bin.extend_from_slice(bytes);
    let views = doc["bufferViews"].as_array_mut().expect("views");
    views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": bytes.len()}));
    views.len() - 1
}

/// `textured_quad` without its light quad (only the checker quad is in the
/// scene), material 0 given `normalTexture` = `normal` (its `index` set to
/// a new texture holding the 1x1 PNG `texel`, NEAREST sampler); `edit`
/// changes the file further.
fn load_normal_mapped(
    texel: [u8; 3],
    mut normal: Value,
    edit: impl FnOnce(&mut Value, &mut Vec<u8>),
) -> crate::Result<GltfScene> {
    load_patched(|doc, bin| {
        doc["scenes"][0]["nodes"] = json!([0, 2]);
        let view = push_view(doc, bin, &png(texel));
        let images = doc["images"].as_array_mut().expect("images");
        images.push(json!({"bufferView": view, "mimeType": "image/png", "name": "normals"}));
        let image = images.len() - 1;
        let textures = doc["textures"].as_array_mut().expect("textures");
        textures.push(json!({"sampler": 0, "source": image}));
        if normal.get("index").is_none() {
            normal["index"] = json!(textures.len() - 1);
        }
        doc["materials"][0]["normalTexture"] = normal;
        edit(doc, bin);
    })
}

/// The checker quad's front normal and its tangent and bitangent as the
/// kernels build them from the scene's first triangle.
fn frame(scene: &Scene) -> (Vec3, Vec3, Vec3) {
    let gpu = SceneGpu::build(scene).expect("builds");
    let tri = gpu.triangles[0];
    let (v0, v1, v2) = (tri.v0.truncate(), tri.v1.truncate(), tri.v2.truncate());
    let n = (v1 - v0).cross(v2 - v0).normalize();
    let (t, b) = kernels::normal_map::tangent_frame(v1 - v0, v2 - v0, n, gpu.attrs[0].tangent);
    (n, t, b)
}

/// CPU radiance (24x24, 4 spp, direct light only: camera ray plus
/// next-event estimation, black sky) of `scene` lit by a white directional
/// light of 2 lux arriving from the unit direction `towards_light`.
fn render(scene: &Scene, towards_light: Vec3) -> Vec<Vec3> {
    let mut scene = scene.clone();
    scene.lights = vec![Light::directional("sun", -towards_light, 2.0, 0.0)];
    let gpu = SceneGpu::build(&scene).expect("builds");
    let mut settings = TraceSettings::new(24, 24);
    settings.spp = 4;
    settings.max_depth = 2;
    settings.environment = Vec3::ZERO;
    let params = gpu.trace_params(&settings, 0).expect("params");
    let seeds = crate::cpu::white_seeds(params.padded_width, 24, 1);
    let mut color = vec![Vec4::ZERO; 24 * 24];
    crate::cpu::render_frame(&gpu, &params, &seeds, &mut color).expect("renders");
    color.iter().map(|c| c.truncate()).collect()
}

/// Per-pixel ratios `mapped / plain` over the pixels `plain` lights.
fn ratios(mapped: &[Vec3], plain: &[Vec3]) -> Vec<f32> {
    let r: Vec<f32> = mapped
        .iter()
        .zip(plain)
        .filter(|(_, p)| p.x > 1e-4)
        .map(|(m, p)| m.x / p.x)
        .collect();
    assert!(r.len() > 100, "the quad covers {} pixels", r.len());
    r
}

fn assert_ratio(mapped: &[Vec3], plain: &[Vec3], want: f32, tolerance: f32, what: &str) {
    for r in ratios(mapped, plain) {
        assert!(
            (r - want).abs() <= tolerance,
            "{what}: ratio {r}, expected {want}"
        );
    }
}

/// The quad's normal map, its scale and the loader's notices.
#[test]
fn normal_textures_are_read_with_scale_and_transform() {
    let g = load_normal_mapped([128, 128, 255], json!({"scale": 0.5}), |doc, _| {
        doc["materials"][0]["occlusionTexture"] = json!({"index": 0});
    })
    .expect("loads");
    let n = g.scene.materials[0].normal_texture.expect("normal texture");
    assert_eq!(n.scale, 0.5);
    assert_eq!(n.texture.transform, None);
    assert!(g.notices.iter().all(|m| !m.contains("normal")), "{:?}", g.notices);
    assert!(
        g.notices.iter().any(|m| m.contains("occlusion")),
        "{:?}",
        g.notices
    );
    let gpu = SceneGpu::build(&g.scene).expect("builds");
    let m = gpu.materials[0];
    assert_eq!(m.pbr.z, 0.5);
    assert_eq!(m.normal.x, n.texture.image);
    assert!(m.normal.y & kernels::abi::TEXEL_LINEAR != 0);

    // KHR_texture_transform on the normal texture, with its texCoord.
    let transform = json!({"KHR_texture_transform": {"offset": [0.5, 0.0], "rotation": 0.25, "texCoord": 0}});
    let g = load_normal_mapped([128, 128, 255], json!({"extensions": transform}), |doc, _| {
        doc["extensionsUsed"] = json!(["KHR_texture_transform"]);
    })
    .expect("loads");
    let n = g.scene.materials[0].normal_texture.expect("normal texture");
    assert_eq!(n.scale, 1.0, "glTF's default");
    assert_eq!(
        n.texture.transform,
        Some(UvTransform::from_offset_rotation_scale(
            [0.5, 0.0],
            0.25,
            [1.0, 1.0]
        ))
    );
    let gpu = SceneGpu::build(&g.scene).expect("builds");
    assert!(gpu.materials[0].normal.y & kernels::abi::UV_TRANSFORM != 0);
}

/// Bad normal textures: an index out of range, an infinite scale (1e39
/// overflows f32), a malformed transform, a set the primitive lacks, and a
/// NaN scale (JSON cannot hold one) when the GPU form is built.
#[test]
fn bad_normal_textures_are_errors() {
    let err = load_normal_mapped([128, 128, 255], json!({"index": 9}), |_, _| {}).expect_err("index 9");
    assert!(err.to_string().contains("normalTexture"), "{err}");

    let (element, reason) = content_error(load_normal_mapped(
        [128, 128, 255],
        json!({"scale": 1e39}),
        |_, _| {},
    ));
    assert_eq!(element, "material 'checker'");
    assert!(reason.contains("normalTexture scale inf"), "{reason}");

    let bad = json!({"extensions": {"KHR_texture_transform": {"rotation": "left"}}});
    let (_, reason) = content_error(load_normal_mapped([128, 128, 255], bad, |_, _| {}));
    assert!(reason.contains("KHR_texture_transform rotation"), "{reason}");

    let (_, reason) = content_error(load_normal_mapped(
        [128, 128, 255],
        json!({"texCoord": 1}),
        |_, _| {},
    ));
    assert!(reason.contains("normal texture reads TEXCOORD_1"), "{reason}");

    let mut scene = load_normal_mapped([128, 128, 255], json!({}), |_, _| {})
        .expect("loads")
        .scene;
    scene.materials[0]
        .normal_texture
        .as_mut()
        .expect("normal texture")
        .scale = f32::NAN;
    let err = SceneGpu::build(&scene).expect_err("NaN scale");
    assert!(err.to_string().contains("normal texture scale"), "{err}");
}

/// Under a directional light 45 degrees from the quad's normal (in the
/// plane of normal and tangent): flat maps reproduce the untextured image
/// (bit for bit with scale 0, within the 8-bit texel's 1/255 offset for
/// `(128, 128, 255)`), a map tilted 45 degrees towards the light brightens
/// by `1 / cos 45` (the light then arrives along the shading normal), one
/// tilted away turns the quad black (cos 90), and one tilted along the
/// bitangent gives `cos 60 / cos 45`.
#[test]
fn tilted_normal_maps_change_radiance_as_the_cosine_predicts() {
    let plain_scene = load_normal_mapped([128, 128, 255], json!({}), |_, _| {})
        .expect("loads")
        .scene;
    let (n, t, b) = frame(&plain_scene);
    assert!(n.z > 0.99, "the quad faces the camera: {n}");
    let light = (t + n).normalize();
    let mut untextured = plain_scene.clone();
    untextured.materials[0].normal_texture = None;
    let plain = render(&untextured, light);

    let mapped = |texel: [u8; 3], scale: f32| {
        let scene = load_normal_mapped(texel, json!({"scale": scale}), |_, _| {})
            .expect("loads")
            .scene;
        render(&scene, light)
    };
    assert_ratio(&mapped([255, 0, 255], 0.0), &plain, 1.0, 1e-5, "scale 0");
    assert_ratio(&mapped([128, 128, 255], 1.0), &plain, 1.0, 0.01, "flat texel");
    let sqrt2 = std::f32::consts::SQRT_2;
    assert_ratio(
        &mapped([255, 128, 255], 1.0),
        &plain,
        sqrt2,
        0.01,
        "towards the light",
    );
    assert_ratio(
        &mapped([0, 128, 255], 1.0),
        &plain,
        0.0,
        0.01,
        "away from the light",
    );
    assert_ratio(
        &mapped([128, 255, 255], 1.0),
        &plain,
        0.5 * sqrt2,
        0.01,
        "along the bitangent",
    );
    // The bitangent is the image's up, `n x t` for this unmirrored mapping.
    assert!((b - n.cross(t)).length() < 1e-5, "{b}");
}

/// A `TANGENT` attribute replaces the tangent derived from the texture
/// coordinates: tangent = the derived bitangent, `w = -1`; the kernels'
/// frame then has `t` = that direction and `b = -(n x t)`, and a map tilted
/// along `b` brightens under a light on that side.
#[test]
fn tangent_attributes_set_the_frame_and_their_sign_flips_the_bitangent() {
    let plain_scene = load_normal_mapped([128, 128, 255], json!({}), |_, _| {})
        .expect("loads")
        .scene;
    let (n, _, derived_b) = frame(&plain_scene);
    let with_tangents = |texel: [u8; 3], w: f32| {
        load_normal_mapped(texel, json!({}), |doc, bin| {
            let values: Vec<u8> = (0..4)
                .flat_map(|_| derived_b.extend(w).to_array())
                .flat_map(f32::to_le_bytes)
                .collect();
            let view = push_view(doc, bin, &values);
            let accessors = doc["accessors"].as_array_mut().expect("accessors");
            accessors.push(json!({"bufferView": view, "componentType": 5126, "count": 4, "type": "VEC4"}));
            let a = accessors.len() - 1;
            assert_eq!(doc["accessors"][quad_accessor(doc, "POSITION")]["count"], 4);
            doc["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] = json!(a);
        })
        .expect("loads")
        .scene
    };
    let scene = with_tangents([128, 255, 255], -1.0);
    let tangent = scene.triangles[0].tangent.expect("read");
    assert!((tangent.truncate() - 3.0 * derived_b).length() < 1e-5 && tangent.w == -1.0);
    let (_, t, b) = frame(&scene);
    assert!((t - derived_b).length() < 1e-5, "{t}");
    assert!(
        (b + n.cross(t)).length() < 1e-5,
        "w = -1 flips the bitangent: {b}"
    );

    let light = (b + n).normalize();
    let mut untextured = scene.clone();
    untextured.materials[0].normal_texture = None;
    let plain = render(&untextured, light);
    let sqrt2 = std::f32::consts::SQRT_2;
    assert_ratio(&render(&scene, light), &plain, sqrt2, 0.01, "w = -1");
    // With w = +1 the same texel tilts the other way: away from the light.
    let flipped = with_tangents([128, 255, 255], 1.0);
    assert_ratio(&render(&flipped, light), &plain, 0.0, 0.01, "w = +1");
}
