//! Scenes from Wavefront OBJ files with MTL materials (tobj 4).
//!
//! Polygons are triangulated; points and lines are ignored. Vertex normals
//! (`vn`, the `v/vt/vn` or `v//vn` face corners) make smooth shading
//! ([`Triangle::normals`]); a triangle with a NaN, infinite or zero-length
//! normal shades flat, and so do files without `vn`. (A face without
//! normals in a file whose other faces have them gets the normal tobj
//! makes up for it: the previous corner's, or the file's first.) From each MTL
//! material the diffuse colour `Kd` becomes the albedo (default 0.8 grey
//! when absent) and the emissive colour `Ke` the emitted radiance (default
//! 0). Faces without a material get a 0.8 grey diffuse default. Emission
//! leaves the front side: counter-clockwise vertex order, the OBJ
//! convention. OBJ files carry no camera: [`Camera::framing`] frames the
//! model from `+z`.
//!
//! # Specular materials
//!
//! A material without `Ks`, or with `Ks 0 0 0`, is Lambertian (exactly as
//! before specular support). A non-zero `Ks` makes it a glTF
//! metallic-roughness material ([`mtl_bsdf`]):
//! - roughness from the Phong exponent `Ns` (0 when absent, negative values
//!   as 0) by the Blinn-Phong-to-Beckmann relation, used for GGX:
//!   `alpha = sqrt(2 / (Ns + 2))`, `roughness = sqrt(alpha)` (glTF's
//!   `alpha = roughness^2`); `Ns` 0 gives roughness 1, 1000 about 0.21;
//! - metallic and base colour from `Kd` and `Ks` read as a
//!   specular-glossiness pair, by Khronos' conversion to metallic-roughness
//!   (`KHR_materials_pbrSpecularGlossiness`, "convert-between-workflows"
//!   example, `solveMetallic`): a grey `Ks` at or below 0.04 with any `Kd`
//!   is a dielectric with base colour about `Kd`, a bright coloured `Ks`
//!   with a black `Kd` a metal with base colour `Ks`, and mixtures fall
//!   between.

use crate::error::{Error, Result};
use crate::scene::{usable_normals, Bsdf, Camera, Material, Scene, Triangle};
use glam::Vec3;
use std::path::Path;

/// Albedo of faces without a material, and of materials without `Kd`.
pub const DEFAULT_ALBEDO: Vec3 = Vec3::splat(0.8);

/// Loads an OBJ file (and the MTL libraries it names, relative to it).
///
/// # Errors
/// - [`Error::ObjLoad`]: the file is missing or unreadable, or malformed
///   (bad numbers, face indices out of range, ...);
/// - [`Error::MtlLoad`]: a named material library is missing or malformed;
/// - [`Error::NoTriangles`]: no face with at least three vertices;
/// - [`Error::NonFiniteVertex`]: a vertex coordinate is NaN or infinite;
/// - [`Error::InvalidMaterial`]: a colour (`Kd`, `Ke`, `Ks`) is NaN,
///   infinite or negative;
/// - [`Error::InvalidMaterialParameter`]: `Ns` is NaN or infinite.
pub fn load_obj(path: impl AsRef<Path>) -> Result<Scene> {
    let path = path.as_ref();
    let options = tobj::LoadOptions {
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    let (models, mtl) = tobj::load_obj(path, &options).map_err(|source| Error::ObjLoad {
        path: path.to_path_buf(),
        source,
    })?;
    let mtl = mtl.map_err(|source| Error::MtlLoad {
        path: path.to_path_buf(),
        source,
    })?;

    let mut materials = Vec::with_capacity(mtl.len());
    for m in &mtl {
        let mut material = Material::new(
            m.name.clone(),
            m.diffuse.map_or(DEFAULT_ALBEDO, Vec3::from_array),
            m.emissive.map_or(Vec3::ZERO, Vec3::from_array),
        );
        let specular = m.specular.map_or(Vec3::ZERO, Vec3::from_array);
        let ok = [material.albedo, material.emission, specular]
            .iter()
            .all(|c| c.is_finite() && c.min_element() >= 0.0);
        if !ok {
            return Err(Error::InvalidMaterial { name: m.name.clone() });
        }
        let shininess = m.shininess.unwrap_or(0.0);
        if !shininess.is_finite() {
            return Err(Error::InvalidMaterialParameter {
                name: m.name.clone(),
                parameter: "shininess (Ns)",
                value: shininess,
                expected: "a finite number",
            });
        }
        (material.albedo, material.bsdf) = mtl_bsdf(material.albedo, specular, shininess);
        materials.push(material);
    }
    let default_material = materials.len() as u32;
    let mut uses_default = false;

    let mut triangles = Vec::new();
    for (object, model) in (0u32..).zip(&models) {
        let mesh = &model.mesh;
        if let Some(vertex) = mesh
            .positions
            .chunks_exact(3)
            .position(|p| !p.iter().all(|c| c.is_finite()))
        {
            return Err(Error::NonFiniteVertex {
                path: path.to_path_buf(),
                model: model.name.clone(),
                vertex,
            });
        }
        let material = match mesh.material_id {
            Some(id) if id < materials.len() => id as u32,
            _ => {
                uses_default = true;
                default_material
            }
        };
        let vertex = |i: u32| {
            let i = i as usize * 3;
            Vec3::new(mesh.positions[i], mesh.positions[i + 1], mesh.positions[i + 2])
        };
        // `vn` normals: tobj's normal indices run parallel to the position
        // indices when the model has any.
        let has_normals = !mesh.normals.is_empty() && mesh.normal_indices.len() == mesh.indices.len();
        let normal = |k: usize| {
            let i = mesh.normal_indices[k] as usize * 3;
            match mesh.normals.get(i..i + 3) {
                Some(n) => Vec3::new(n[0], n[1], n[2]),
                None => Vec3::ZERO,
            }
        };
        for (f, face) in mesh.indices.chunks_exact(3).enumerate() {
            let normals = has_normals.then(|| [normal(3 * f), normal(3 * f + 1), normal(3 * f + 2)]);
            triangles.push(Triangle {
                object,
                normals: normals.and_then(usable_normals),
                ..Triangle::new([vertex(face[0]), vertex(face[1]), vertex(face[2])], material)
            });
        }
    }
    if triangles.is_empty() {
        return Err(Error::NoTriangles {
            path: path.to_path_buf(),
        });
    }
    if uses_default {
        materials.push(Material::new("default", DEFAULT_ALBEDO, Vec3::ZERO));
    }
    let mut scene = Scene {
        lights: Vec::new(),
        environment_map: None,
        triangles,
        images: Vec::new(),
        materials,
        camera: Camera::framing(Vec3::ZERO, Vec3::ONE),
    };
    let (lo, hi) = scene.bounds();
    scene.camera = Camera::framing(lo, hi);
    Ok(scene)
}

/// glTF's dielectric normal-incidence reflectance (`kernels::bsdf::fresnel::DIELECTRIC_F0`).
const DIELECTRIC_F0: f32 = kernels::bsdf::fresnel::DIELECTRIC_F0;

/// The base colour and reflectance model of an MTL material with diffuse
/// colour `kd`, specular colour `ks` and Phong exponent `ns` (module docs):
/// `(kd, Lambert)` when `ks` is zero, else a metallic-roughness material.
/// Inputs finite, colours `>= 0`; the outputs are in `[0, 1]`.
pub fn mtl_bsdf(kd: Vec3, ks: Vec3, ns: f32) -> (Vec3, Bsdf) {
    if ks.max_element() <= 0.0 {
        return (kd, Bsdf::Lambert);
    }
    let alpha = (2.0 / (ns.max(0.0) + 2.0)).sqrt();
    let roughness = alpha.sqrt().clamp(0.0, 1.0);
    // Khronos' specular-glossiness to metallic-roughness conversion.
    let brightness = |c: Vec3| (0.299 * c.x * c.x + 0.587 * c.y * c.y + 0.114 * c.z * c.z).sqrt();
    let one_minus_specular = 1.0 - ks.max_element().min(1.0);
    let (diffuse, specular) = (brightness(kd), brightness(ks));
    let metallic = if specular < DIELECTRIC_F0 {
        0.0
    } else {
        let a = DIELECTRIC_F0;
        let b = diffuse * one_minus_specular / (1.0 - a) + specular - 2.0 * a;
        let c = a - specular;
        let d = (b * b - 4.0 * a * c).max(0.0);
        ((-b + d.sqrt()) / (2.0 * a)).clamp(0.0, 1.0)
    };
    let eps = 1e-6;
    let from_diffuse = kd * (one_minus_specular / (1.0 - DIELECTRIC_F0) / (1.0 - metallic).max(eps));
    let from_specular = (ks - Vec3::splat(DIELECTRIC_F0 * (1.0 - metallic))) / metallic.max(eps);
    let base = from_diffuse
        .lerp(from_specular, metallic * metallic)
        .clamp(Vec3::ZERO, Vec3::ONE);
    let bsdf = Bsdf::MetallicRoughness {
        metallic,
        roughness,
        texture: None,
    };
    (base, bsdf)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::SceneGpu;
    use std::fs;
    use std::path::PathBuf;

    /// A fresh directory under the system temp dir, removed on drop.
    struct TempDir(PathBuf);
    impl TempDir {
        fn new(tag: &str) -> Self {
            let p = std::env::temp_dir().join(format!("gpu-tracer-obj-{tag}-{}", std::process::id()));
            let _ = fs::remove_dir_all(&p);
            fs::create_dir_all(&p).expect("temp dir");
            TempDir(p)
        }
        fn write(&self, name: &str, text: &str) -> PathBuf {
            let p = self.0.join(name);
            fs::write(&p, text).expect("write");
            p
        }
    }
    impl Drop for TempDir {
        fn drop(&mut self) {
            let _ = fs::remove_dir_all(&self.0);
        }
    }

    const QUAD_MTL: &str = "newmtl wall\nKd 0.5 0.25 0.125\nnewmtl lamp\nKd 0 0 0\nKe 4 5 6\n";
    const QUAD_OBJ: &str = "mtllib scene.mtl\n\
        v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
        v 0 0 1\nv 1 0 1\nv 1 1 1\n\
        o loose\nf 1 3 7\n\
        o tiles\nusemtl wall\nf 1 2 3 4\n\
        usemtl lamp\nf 5 6 7\n";

    #[test]
    fn loads_geometry_and_materials() {
        let dir = TempDir::new("ok");
        dir.write("scene.mtl", QUAD_MTL);
        let path = dir.write("scene.obj", QUAD_OBJ);
        let scene = load_obj(&path).expect("loads");
        // One triangle without a material, a quad -> 2 triangles, the lamp triangle.
        assert_eq!(scene.triangles.len(), 4);
        let names: Vec<&str> = scene.materials.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(names, ["wall", "lamp", "default"]);
        assert_eq!(scene.materials[0].albedo, Vec3::new(0.5, 0.25, 0.125));
        assert_eq!(scene.materials[1].emission, Vec3::new(4.0, 5.0, 6.0));
        let materials: Vec<u32> = scene.triangles.iter().map(|t| t.material).collect();
        assert_eq!(materials, [2, 0, 0, 1]);
        assert_eq!(scene.triangles[3].vertices[2], Vec3::new(1.0, 1.0, 1.0));
        assert_eq!(scene.triangles[0].vertices[1], Vec3::new(1.0, 1.0, 0.0));
        let gpu = SceneGpu::build(&scene).expect("builds");
        assert_eq!(gpu.emitter_count, 1);
    }

    /// `vn` corners become unit vertex normals (in face-corner order,
    /// shared or not); a zero `vn` makes its triangle flat; no `vn`, none.
    #[test]
    fn vertex_normals_are_read() {
        let dir = TempDir::new("vn");
        let path = dir.write(
            "bent.obj",
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
             vn 0 0 2\nvn 1 0 1\nvn 0 0 0\n\
             o smooth\nf 1//1 2//2 3//1\n\
             o degenerate\nf 1//1 3//1 4//3\n",
        );
        let scene = load_obj(&path).expect("loads");
        assert_eq!(scene.triangles.len(), 2);
        let s = 0.5f32.sqrt();
        assert_eq!(
            scene.triangles[0].normals,
            Some([Vec3::Z, Vec3::new(s, 0.0, s), Vec3::Z])
        );
        assert_eq!(scene.triangles[1].normals, None);
        dir.write("scene.mtl", QUAD_MTL);
        let plain = load_obj(dir.write("scene.obj", QUAD_OBJ)).expect("loads");
        assert!(plain.triangles.iter().all(|t| t.normals.is_none()));
    }

    #[test]
    fn missing_file_is_an_error() {
        let dir = TempDir::new("missing");
        let err = load_obj(dir.0.join("nope.obj")).expect_err("missing");
        assert!(
            matches!(
                err,
                Error::ObjLoad {
                    source: tobj::LoadError::OpenFileFailed,
                    ..
                }
            ),
            "{err}"
        );
        assert!(err.to_string().contains("nope.obj"));
        assert!(std::error::Error::source(&err).is_some());
    }

    #[test]
    fn malformed_obj_is_an_error() {
        let dir = TempDir::new("malformed");
        let bad_number = dir.write("a.obj", "v 0 zero 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        assert!(matches!(load_obj(bad_number), Err(Error::ObjLoad { .. })));
        let bad_index = dir.write("b.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
        assert!(matches!(load_obj(bad_index), Err(Error::ObjLoad { .. })));
        let missing_mtl = dir.write("c.obj", "mtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        assert!(matches!(load_obj(missing_mtl), Err(Error::MtlLoad { .. })));
    }

    #[test]
    fn no_triangles_is_an_error() {
        let dir = TempDir::new("empty");
        let only_points = dir.write("p.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\n");
        let err = load_obj(only_points).expect_err("no triangles");
        assert!(matches!(err, Error::NoTriangles { .. }), "{err}");
        let empty = dir.write("e.obj", "# nothing here\n");
        assert!(matches!(load_obj(empty), Err(Error::NoTriangles { .. })));
    }

    #[test]
    fn non_finite_vertices_are_an_error() {
        let dir = TempDir::new("nan");
        for (name, text) in [
            ("nan.obj", "v 0 0 0\nv 1 NaN 0\nv 0 1 0\nf 1 2 3\n"),
            ("inf.obj", "v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n"),
        ] {
            let path = dir.write(name, text);
            // tobj parses "NaN" and "inf" like `str::parse::<f32>`; the loader rejects them.
            match load_obj(&path) {
                Err(e @ Error::NonFiniteVertex { vertex, .. }) => {
                    assert!(vertex == 1 || vertex == 2, "{name}: vertex {vertex}");
                    assert!(e.to_string().contains(name), "{e}");
                }
                other => panic!("{name}: {other:?}"),
            }
        }
    }

    /// `Ks` absent or zero keeps the material Lambertian and its `Kd`
    /// exactly; a small grey `Ks` is a dielectric, a bright one with black
    /// `Kd` a metal of base colour `Ks`; `Ns` maps to roughness by
    /// `sqrt(sqrt(2 / (Ns + 2)))`.
    #[test]
    fn mtl_specular_maps_to_metallic_roughness() {
        let kd = Vec3::new(0.5, 0.25, 0.125);
        assert_eq!(mtl_bsdf(kd, Vec3::ZERO, 500.0), (kd, Bsdf::Lambert));
        let parts = |(base, bsdf): (Vec3, Bsdf)| match bsdf {
            Bsdf::MetallicRoughness {
                metallic,
                roughness,
                texture: None,
            } => (base, metallic, roughness),
            other => panic!("{other:?}"),
        };
        let (base, metallic, roughness) = parts(mtl_bsdf(kd, Vec3::splat(0.04), 0.0));
        assert_eq!((metallic, roughness), (0.0, 1.0));
        assert!((base - kd).abs().max_element() < 1e-6, "{base}");
        let gold = Vec3::new(1.0, 0.78, 0.34);
        let (base, metallic, roughness) = parts(mtl_bsdf(Vec3::ZERO, gold, 1000.0));
        assert!(metallic > 0.99, "{metallic}");
        assert!((base - gold).abs().max_element() < 0.01, "{base}");
        assert!(
            (roughness - (2.0f32 / 1002.0).sqrt().sqrt()).abs() < 1e-6 && (roughness - 0.2114).abs() < 1e-3
        );
        // A typical exporter default (Kd 0.8, Ks 0.5, Ns 96) lands between.
        let (base, metallic, roughness) = parts(mtl_bsdf(Vec3::splat(0.8), Vec3::splat(0.5), 96.0));
        assert!(metallic > 0.0 && metallic < 1.0, "{metallic}");
        assert!(base.min_element() >= 0.0 && base.max_element() <= 1.0, "{base}");
        assert!((roughness - (2.0f32 / 98.0).sqrt().sqrt()).abs() < 1e-6);
        // Negative Ns reads as 0.
        assert_eq!(parts(mtl_bsdf(kd, Vec3::splat(0.04), -5.0)).2, 1.0);
    }

    /// The loader reads `Ks`/`Ns` into [`mtl_bsdf`], keeps `Kd`-only
    /// materials Lambertian, and refuses NaN `Ns` and negative `Ks`.
    #[test]
    fn loads_specular_materials() {
        let dir = TempDir::new("specular");
        dir.write(
            "s.mtl",
            "newmtl matte\nKd 0.5 0.5 0.5\nKs 0 0 0\nNs 50\nnewmtl shiny\nKd 0 0 0\nKs 0.9 0.9 0.9\nNs 200\n",
        );
        let obj = "mtllib s.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl matte\nf 1 2 3\nusemtl shiny\nf 1 3 2\n";
        let scene = load_obj(dir.write("s.obj", obj)).expect("loads");
        assert_eq!(scene.materials[0].bsdf, Bsdf::Lambert);
        assert_eq!(scene.materials[0].albedo, Vec3::splat(0.5));
        let want = mtl_bsdf(Vec3::ZERO, Vec3::splat(0.9), 200.0);
        assert_eq!((scene.materials[1].albedo, scene.materials[1].bsdf), want);
        SceneGpu::build(&scene).expect("builds");
        dir.write("bad.mtl", "newmtl bad\nKd 0.5 0.5 0.5\nKs 0.5 0.5 0.5\nNs NaN\n");
        let bad = "mtllib bad.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl bad\nf 1 2 3\n";
        let err = load_obj(dir.write("bad.obj", bad)).expect_err("NaN Ns");
        assert!(
            matches!(
                err,
                Error::InvalidMaterialParameter {
                    parameter: "shininess (Ns)",
                    ..
                }
            ),
            "{err}"
        );
        assert!(
            err.to_string().contains("NaN") && err.to_string().contains("finite"),
            "{err}"
        );
        dir.write("neg.mtl", "newmtl neg\nKd 0.5 0.5 0.5\nKs 0.5 -1 0.5\n");
        let neg = "mtllib neg.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl neg\nf 1 2 3\n";
        assert!(matches!(
            load_obj(dir.write("neg.obj", neg)),
            Err(Error::InvalidMaterial { .. })
        ));
    }

    #[test]
    fn negative_colours_are_an_error() {
        let dir = TempDir::new("neg");
        dir.write("n.mtl", "newmtl bad\nKd 0.5 -0.1 0.5\n");
        let path = dir.write(
            "n.obj",
            "mtllib n.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl bad\nf 1 2 3\n",
        );
        assert!(matches!(load_obj(path), Err(Error::InvalidMaterial { .. })));
    }
}
