//! Scenes from Wavefront OBJ files with MTL materials (tobj 4).
//!
//! Polygons are triangulated; points and lines are ignored. From each MTL
//! material the diffuse colour `Kd` becomes the albedo (default 0.8 grey
//! when absent) and the emissive colour `Ke` the emitted radiance (default
//! 0). Faces without a material get a 0.8 grey diffuse default. Emission
//! leaves the front side: counter-clockwise vertex order, the OBJ
//! convention. OBJ files carry no camera: [`Camera::framing`] frames the
//! model from `+z`.

use crate::error::{Error, Result};
use crate::scene::{Camera, Material, Scene, Triangle};
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
/// - [`Error::InvalidMaterial`]: a colour is NaN, infinite or negative.
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

    let mut materials: Vec<Material> = mtl
        .iter()
        .map(|m| {
            Material::new(
                m.name.clone(),
                m.diffuse.map_or(DEFAULT_ALBEDO, Vec3::from_array),
                m.emissive.map_or(Vec3::ZERO, Vec3::from_array),
            )
        })
        .collect();
    for m in &materials {
        let ok = m.albedo.is_finite()
            && m.emission.is_finite()
            && m.albedo.min_element() >= 0.0
            && m.emission.min_element() >= 0.0;
        if !ok {
            return Err(Error::InvalidMaterial { name: m.name.clone() });
        }
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
        for face in mesh.indices.chunks_exact(3) {
            triangles.push(Triangle {
                object,
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
        triangles,
        images: Vec::new(),
        materials,
        camera: Camera::framing(Vec3::ZERO, Vec3::ONE),
    };
    let (lo, hi) = scene.bounds();
    scene.camera = Camera::framing(lo, hi);
    Ok(scene)
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
