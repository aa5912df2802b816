//! Tests of the material extensions and alpha modes on patched fixtures:
//! `KHR_texture_transform` on every texture, and alpha cut-outs.

use super::tests::{content_error, load_fixture_patched, load_patched};
use crate::scene::{SceneGpu, UvTransform};
use glam::Vec2;
use kernels::abi::MaterialGpu;
use serde_json::{json, Value};

/// `"extensions": {"KHR_texture_transform": transform}` on a texture info.
fn with_transform(info: &mut Value, transform: Value) {
    info["extensions"] = json!({ "KHR_texture_transform": transform });
}

/// The texel-centre grid of the 4x4 checker over `[0, 2)^2` (the quad's UVs).
fn texel_centres() -> impl Iterator<Item = Vec2> {
    (0..8).flat_map(|i| (0..8).map(move |j| Vec2::new(i as f32 + 0.5, j as f32 + 0.5) / 4.0))
}

/// The extension's example (offset `(0, 1)`, rotation `pi / 2`, scale 0.5:
/// "the lower left quadrant of the source image, rotated clockwise 90
/// degrees") maps the corners of the unit square as its README says.
#[test]
fn the_extension_example_maps_to_the_lower_left_quadrant() {
    let t = UvTransform::from_offset_rotation_scale([0.0, 1.0], std::f32::consts::FRAC_PI_2, [0.5, 0.5]);
    for (uv, want) in [
        (Vec2::ZERO, Vec2::new(0.0, 1.0)),
        (Vec2::X, Vec2::new(0.0, 0.5)),
        (Vec2::Y, Vec2::new(0.5, 1.0)),
        (Vec2::ONE, Vec2::new(0.5, 0.5)),
    ] {
        assert!(t.apply(uv).abs_diff_eq(want, 1e-7), "{uv} -> {}", t.apply(uv));
    }
}

/// Base colour and emissive textures of one material with different
/// transforms: each lookup lands where its own transform says (the
/// checker's texel under the transformed coordinates), and both differ from
/// the untransformed lookup somewhere.
#[test]
fn texture_transforms_move_each_texture_by_its_own_transform() {
    let g = load_patched(|doc, _| {
        doc["extensionsUsed"]
            .as_array_mut()
            .expect("extensionsUsed")
            .push(json!("KHR_texture_transform"));
        doc["extensionsRequired"] = json!(["KHR_texture_transform"]);
        let m = &mut doc["materials"][0];
        with_transform(
            &mut m["pbrMetallicRoughness"]["baseColorTexture"],
            json!({"offset": [0.0, 1.0], "rotation": std::f32::consts::FRAC_PI_2, "scale": [0.5, 0.5]}),
        );
        m["emissiveFactor"] = json!([1.0, 1.0, 1.0]);
        m["emissiveTexture"] = json!({"index": 0});
        with_transform(&mut m["emissiveTexture"], json!({"offset": [0.25, 0.0]}));
    })
    .expect("loads with the extension required");
    assert!(g.notices.is_empty(), "{:?}", g.notices);
    let m = &g.scene.materials[0];
    let base = m
        .base_color_texture
        .and_then(|t| t.transform)
        .expect("base transform");
    let emit = m
        .emission_texture
        .and_then(|t| t.transform)
        .expect("emissive transform");
    assert_eq!(
        emit,
        UvTransform::from_offset_rotation_scale([0.25, 0.0], 0.0, [1.0, 1.0])
    );
    let gpu = SceneGpu::build(&g.scene).expect("builds");
    let mat: MaterialGpu = gpu.materials[0];
    let lookup =
        |uv: Vec2| kernels::texture::sample_image(&gpu.images, gpu.image_count, 0, mat.textures.y, uv);
    let (mut moved_base, mut moved_emit) = (0, 0);
    for uv in texel_centres() {
        let albedo = kernels::surface::surface_albedo(&mat, &gpu.images, gpu.image_count, uv);
        assert_eq!(albedo, lookup(base.apply(uv)), "base colour at {uv}");
        let emission = kernels::surface::surface_emission(&mat, &gpu.images, gpu.image_count, uv);
        assert_eq!(emission, lookup(uv + Vec2::new(0.25, 0.0)), "emission at {uv}");
        moved_base += usize::from(albedo != lookup(uv));
        moved_emit += usize::from(emission != lookup(uv));
    }
    // A one-texel shift flips every checker texel.
    assert_eq!(moved_emit, 64);
    assert!(moved_base > 0);
}

/// The metallic-roughness texture's transform (scale 2 with `texCoord`
/// naming set 0 explicitly), and a `texCoord` override naming a set the
/// primitive lacks: the override is what the loader asks for.
#[test]
fn metallic_roughness_transform_and_tex_coord_override() {
    let g = load_fixture_patched("metallic_quad", |doc, _| {
        doc["extensionsUsed"] = json!(["KHR_texture_transform"]);
        with_transform(
            &mut doc["materials"][0]["pbrMetallicRoughness"]["metallicRoughnessTexture"],
            json!({"scale": [2.0, 2.0], "texCoord": 0}),
        );
    })
    .expect("loads");
    let gpu = SceneGpu::build(&g.scene).expect("builds");
    let mat = gpu.materials[0];
    let mr = |uv: Vec2| kernels::surface::surface_metallic_roughness(&mat, &gpu.images, gpu.image_count, uv);
    let mut plain = mat;
    plain.model.z &= !kernels::abi::UV_TRANSFORM;
    let untransformed =
        |uv: Vec2| kernels::surface::surface_metallic_roughness(&plain, &gpu.images, gpu.image_count, uv);
    // uv (0.375, 0.125) reads texel (1, 0) of the 2x2 image once doubled.
    assert_eq!(mr(Vec2::new(0.375, 0.125)), untransformed(Vec2::new(0.75, 0.25)));
    assert_ne!(
        mr(Vec2::new(0.375, 0.125)),
        untransformed(Vec2::new(0.375, 0.125))
    );

    let (element, reason) = content_error(load_patched(|doc, _| {
        with_transform(
            &mut doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"],
            json!({"texCoord": 1}),
        );
    }));
    assert_eq!(element, "mesh 'checker_quad' primitive 0");
    assert!(reason.contains("no TEXCOORD_1"), "{reason}");
}

/// `textured_quad` with material 0 (the 2x2 quad, UVs 0..2) cut out:
/// `alphaMode` `MASK`, default cutoff 0.5, base colour texture a 2x1 RGBA
/// PNG (in a buffer view) whose left texel has alpha 0 and right texel
/// alpha 255, NEAREST and REPEAT: holes where `x` is in `[-1, -0.5)` and
/// `[0, 0.5)`. `edit` changes the material further.
fn load_masked(edit: impl FnOnce(&mut Value)) -> crate::Result<super::GltfScene> {
    load_patched(|doc, bin| {
        let img = image::RgbaImage::from_fn(2, 1, |x, _| {
            image::Rgba([200, 200, 200, if x == 0 { 0 } else { 255 }])
        });
        let mut png = std::io::Cursor::new(Vec::new());
        img.write_to(&mut png, image::ImageFormat::Png).expect("PNG");
        let png = png.into_inner();
        bin.resize(bin.len().next_multiple_of(4), 0);
        let offset = bin.len();
        bin.extend_from_slice(&png);
        let views = doc["bufferViews"].as_array_mut().expect("views");
        views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": png.len()}));
        let view = views.len() - 1;
        doc["images"]
            .as_array_mut()
            .expect("images")
            .push(json!({"bufferView": view, "mimeType": "image/png", "name": "mask"}));
        doc["textures"]
            .as_array_mut()
            .expect("textures")
            .push(json!({"sampler": 0, "source": 1}));
        let m = &mut doc["materials"][0];
        m["alphaMode"] = json!("MASK");
        m["pbrMetallicRoughness"]["baseColorTexture"] = json!({"index": 1});
        edit(m);
    })
}

/// A CPU render (32x32, camera rays only, a white sky) of the masked quad:
/// the sky shows through the holes, the opaque part (not emissive) is black.
#[test]
fn mask_holes_let_the_sky_through_and_the_rest_blocks() {
    use crate::scene::{Alpha, TraceSettings};
    let g = load_masked(|_| {}).expect("loads");
    assert!(g.notices.is_empty(), "{:?}", g.notices);
    assert_eq!(
        g.scene.materials[0].alpha,
        Alpha::Mask {
            cutoff: 0.5,
            factor: 1.0
        }
    );
    let gpu = SceneGpu::build(&g.scene).expect("builds");
    let mut settings = TraceSettings::new(32, 32);
    settings.spp = 4;
    settings.max_depth = 1;
    settings.environment = glam::Vec3::ONE;
    let params = gpu.trace_params(&settings, 0).expect("params");
    let seeds = crate::cpu::white_seeds(params.padded_width, 32, 1);
    let mut color = vec![glam::Vec4::ZERO; 32 * 32];
    crate::cpu::render_frame(&gpu, &params, &seeds, &mut color).expect("renders");
    // Row 16 crosses the quad at y ~ 0; column 6 sees x ~ -0.74 (a hole),
    // 12 sees x ~ -0.27 and 24 x ~ 0.66 (opaque), 18 x ~ 0.19 (a hole).
    let at = |x: usize| color[16 * 32 + x].truncate();
    assert_eq!(at(6), glam::Vec3::ONE, "hole");
    assert_eq!(at(18), glam::Vec3::ONE, "hole");
    assert_eq!(at(12), glam::Vec3::ZERO, "opaque");
    assert_eq!(at(24), glam::Vec3::ZERO, "opaque");

    // The same quad made opaque again blocks everywhere.
    let mut opaque = g.scene.clone();
    opaque.materials[0].alpha = Alpha::Opaque;
    let gpu = SceneGpu::build(&opaque).expect("builds");
    crate::cpu::render_frame(&gpu, &params, &seeds, &mut color).expect("renders");
    assert_eq!(color[16 * 32 + 6].truncate(), glam::Vec3::ZERO);
}

/// Bad cutoffs are refused with the material named; `BLEND` renders opaque
/// with a notice; a NaN cutoff (which JSON cannot hold) is refused when the
/// GPU form is built.
#[test]
fn bad_alpha_cutoffs_are_errors_and_blend_is_noticed() {
    for cutoff in [json!(-0.5), json!(1e39)] {
        let (element, reason) = content_error(load_masked(|m| m["alphaCutoff"] = cutoff.clone()));
        assert_eq!(element, "material 'checker'");
        assert!(reason.contains("alphaCutoff"), "{reason}");
    }
    let g = load_masked(|m| m["alphaMode"] = json!("BLEND")).expect("loads");
    assert_eq!(g.scene.materials[0].alpha, crate::scene::Alpha::Opaque);
    assert!(g.notices.iter().any(|n| n.contains("BLEND")), "{:?}", g.notices);
    let mut scene = load_masked(|_| {}).expect("loads").scene;
    scene.materials[0].alpha = crate::scene::Alpha::Mask {
        cutoff: f32::NAN,
        factor: 1.0,
    };
    let err = SceneGpu::build(&scene).expect_err("NaN cutoff");
    assert!(err.to_string().contains("alpha cutoff"), "{err}");
}
