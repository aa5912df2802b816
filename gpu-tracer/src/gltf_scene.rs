//! Scenes from glTF 2.0 files (`.gltf` with external or embedded buffers
//! and images, and `.glb`), with the `gltf` crate.
//!
//! # What is loaded
//!
//! - **Geometry**: every mesh primitive of the file's default scene (scene 0
//!   when none is marked default) with the node hierarchy's transforms.
//!   `TRIANGLES`, `TRIANGLE_STRIP` and `TRIANGLE_FAN` primitives, indexed or
//!   not (strips and fans are converted to triangles, dropping the
//!   degenerate ones that repeat a vertex); `POINTS` and `LINE*` primitives
//!   are an error. Positions must be `VEC3` floats. A mirroring node
//!   transform (negative determinant) swaps two vertices of each triangle
//!   so that the front side (counter-clockwise, the emitting side) stays the
//!   authored one. Each (node, mesh) pair is one object
//!   ([`Triangle::object`]), numbered in scene traversal order (depth first,
//!   children in file order).
//! - **Materials**: base colour factor (rgb; alpha ignored) is the albedo,
//!   the base colour texture multiplies it; emissive factor times
//!   `KHR_materials_emissive_strength` is the emission, the emissive texture
//!   multiplies it. Textures keep their sampler's wrap modes and
//!   magnification filter (`NEAREST` -> [`Filter::Nearest`], `LINEAR` or
//!   none -> [`Filter::Bilinear`]) and read the `TEXCOORD_n` set the
//!   material names (float or normalised 8/16-bit). Everything is diffuse:
//!   metallic/roughness, normal and occlusion maps and alpha are ignored
//!   with a notice. A primitive without material gets glTF's default (albedo
//!   1, no emission).
//! - **Images**: whatever the `gltf` crate decodes (PNG, JPEG), converted to
//!   8-bit sRGB RGBA: grey (`R8`) and grey-alpha (`R8G8`) images are
//!   expanded, 16-bit channels are rounded to 8 bits, float channels are
//!   taken as already-encoded values in `[0, 1]` and clamped.
//! - **Camera**: a perspective camera attached to a node (the N-th camera
//!   node in traversal order, see [`load_gltf`]), looking along the node's
//!   `-Z` with `+Y` up; its vertical field of view is used and its aspect
//!   ratio ignored (the rendered image's aspect applies). Without a camera,
//!   [`Camera::framing`] frames the scene's bounds. Orthographic cameras are
//!   an error.
//! - **Animation**: translation, rotation and scale channels of all the
//!   file's animations (STEP, LINEAR, CUBICSPLINE), in a [`Rig`];
//!   morph-target weight channels are ignored with a notice. Skins and morph
//!   targets are ignored (bind pose, base mesh) with a notice.
//!
//! [`GltfScene::scene`] is the rest pose (every node at its file transform);
//! [`Rig::pose`] gives the animated triangles and camera at any time.
//!
//! Extensions other than `KHR_materials_emissive_strength` are ignored with
//! a notice when merely used (`KHR_texture_transform`, `KHR_lights_punctual`,
//! ...) and rejected by the `gltf` crate when required.

use crate::animation::{
    camera_from_matrix, Channel, Interpolation, MeshInstance, Node, Property, Rig, RigCamera, Trs,
};
use crate::error::{Error, Result};
use crate::scene::{Camera, Filter, Image, Material, Scene, TextureRef, Triangle, Wrap};
use glam::{Mat4, Quat, Vec2, Vec3, Vec4};
use gltf::accessor::{DataType, Dimensions};
use gltf::json::validation::Checked;
use std::path::Path;

/// Albedo of primitives without a material (glTF's default material: base
/// colour factor 1).
pub const DEFAULT_ALBEDO: Vec3 = Vec3::ONE;

/// Largest element count of a sparse accessor without a base buffer view
/// (its elements are materialised: 2^24 positions are 192 MiB).
const MAX_SPARSE_ONLY_COUNT: usize = 1 << 24;

/// The extensions whose content is used; others are noticed and ignored.
const SUPPORTED_EXTENSIONS: &[&str] = &["KHR_materials_emissive_strength"];

/// A loaded glTF scene.
#[derive(Clone, Debug, PartialEq)]
pub struct GltfScene {
    /// Triangles (at the rest pose), materials, images and camera (the
    /// chosen camera node's, at the rest pose, or an automatic framing).
    pub scene: Scene,
    /// Hierarchy, animation, mesh instances and camera node; its
    /// [`Rig::local`] is parallel to `scene.triangles`.
    pub rig: Rig,
    /// One line per ignored feature of the file (unsupported extension,
    /// metallic/roughness, normal maps, morph targets, ...), for the user.
    pub notices: Vec<String>,
}

/// Loads a glTF 2.0 file: `.gltf` (JSON with external `.bin`/image files or
/// embedded base64 data URIs) or `.glb` (binary container).
///
/// `camera_index` picks the N-th (0-based) node with a camera in scene
/// traversal order (depth first from the scene's root nodes, children in
/// file order); `None` takes the first one, or frames the scene
/// automatically when there is none ([`GltfScene::rig`] then has no
/// camera). See the [module documentation](self) for what is supported.
///
/// # Errors
/// Every error names the file and the element at fault.
/// - [`Error::GltfLoad`]: the file, a buffer or an image cannot be read,
///   parsed or decoded (missing or truncated file, malformed JSON or GLB,
///   missing `.bin`, buffer shorter than declared, undecodable image), or
///   the `gltf` crate's validation fails (an index out of range, a missing
///   required property, an unsupported required extension);
/// - [`Error::NonFiniteVertex`]: a position is NaN or infinite (`model`
///   names the mesh and primitive, `vertex` the vertex of the primitive);
/// - [`Error::GltfContent`]: anything else that makes the content unusable:
///   no scene, no triangle in the scene, a node hierarchy cycle, a
///   non-finite node transform, an accessor of the wrong type, out of its
///   buffer, or with NaN/infinite texture coordinates, a vertex index out of
///   range, a `POINTS`/`LINE*` primitive, a textured material on a primitive
///   without the texture coordinates it names (or base colour and emissive
///   textures naming different sets), an invalid material colour or image,
///   a camera index out of range (the message says how many camera nodes
///   there are), an orthographic or degenerate camera, invalid animation
///   data (times not finite and strictly increasing, values not finite, the
///   wrong number of values).
pub fn load_gltf(path: impl AsRef<Path>, camera_index: Option<usize>) -> Result<GltfScene> {
    Loader::open(path.as_ref())?.load(camera_index)
}

/// `kind 'name'` or `kind index`.
fn label(kind: &str, index: usize, name: Option<&str>) -> String {
    match name {
        Some(n) => format!("{kind} '{n}'"),
        None => format!("{kind} {index}"),
    }
}

/// The loading state: the validated document and its buffers.
struct Loader<'p> {
    path: &'p Path,
    /// Directory that relative URIs are resolved against.
    base: &'p Path,
    document: gltf::Document,
    buffers: Vec<gltf::buffer::Data>,
    notices: Vec<String>,
}

impl<'p> Loader<'p> {
    fn content(&self, element: impl Into<String>, reason: impl Into<String>) -> Error {
        content_error(self.path, element, reason)
    }

    /// Reads, parses and validates the file and imports its buffers.
    fn open(path: &'p Path) -> Result<Self> {
        let load = |element: &str, source| Error::GltfLoad {
            path: path.to_path_buf(),
            element: element.to_string(),
            source,
        };
        let bytes = std::fs::read(path).map_err(|e| load("file", gltf::Error::Io(e)))?;
        check_glb_header(path, &bytes)?;
        let gltf::Gltf { document, mut blob } =
            gltf::Gltf::from_slice_without_validation(&bytes).map_err(|e| load("file", e))?;
        drop(bytes);
        // The gltf crate indexes some arrays without bounds checks (in its
        // validation and accessors): check those first.
        precheck_json(path, document.as_json())?;
        let document =
            gltf::Document::from_json(document.into_json()).map_err(|e| load("JSON validation", e))?;
        check_buffer_views(path, &document)?;
        let base = path.parent().unwrap_or(Path::new("."));

        let mut buffers = Vec::new();
        for buffer in document.buffers() {
            let element = match buffer.source() {
                gltf::buffer::Source::Uri(uri) => {
                    check_uri(path, &format!("buffer {}", buffer.index()), uri)?;
                    format!("buffer {} ('{}')", buffer.index(), short_uri(uri))
                }
                gltf::buffer::Source::Bin => format!("buffer {} (GLB BIN chunk)", buffer.index()),
            };
            let data = gltf::buffer::Data::from_source_and_blob(buffer.source(), Some(base), &mut blob)
                .map_err(|e| load(&element, e))?;
            if data.0.len() < buffer.length() {
                return Err(load(
                    &element,
                    gltf::Error::BufferLength {
                        buffer: buffer.index(),
                        expected: buffer.length(),
                        actual: data.0.len(),
                    },
                ));
            }
            buffers.push(data);
        }
        Ok(Loader {
            path,
            base,
            document,
            buffers,
            notices: Vec::new(),
        })
    }

    fn load(mut self, camera_index: Option<usize>) -> Result<GltfScene> {
        let document = self.document.clone();
        let scene = match document.default_scene().or_else(|| document.scenes().next()) {
            Some(s) => s,
            None => return Err(self.content("scenes", "the file has no scene")),
        };
        let scene_label = label("scene", scene.index(), scene.name());
        if document.scenes().len() > 1 {
            self.notices.push(format!(
                "the file has {} scenes: only {scene_label} is loaded",
                document.scenes().len()
            ));
        }
        for ext in document.extensions_used() {
            if !SUPPORTED_EXTENSIONS.contains(&ext) {
                self.notices
                    .push(format!("extension {ext} is not supported: ignored"));
            }
        }

        // Nodes in depth-first order; `rig_index[gltf node]`.
        let order = self.traverse(&scene)?;
        let mut rig_index = vec![None; document.nodes().len()];
        for (i, (node, _)) in order.iter().enumerate() {
            rig_index[node.index()] = Some(i);
        }
        let mut nodes = Vec::with_capacity(order.len());
        for (node, parent) in &order {
            nodes.push(Node {
                name: node
                    .name()
                    .map_or_else(|| format!("node {}", node.index()), str::to_string),
                parent: *parent,
                rest: self.rest_transform(node)?,
            });
        }
        let mut rig = Rig {
            nodes,
            ..Rig::default()
        };
        let rest_world = rig.rest_transforms();

        let (mut materials, material_sets) = self.materials()?;
        let (images, image_of) = self.images(&materials)?;
        for m in &mut materials {
            for t in [&mut m.base_color_texture, &mut m.emission_texture]
                .into_iter()
                .flatten()
            {
                t.image = image_of.get(t.image as usize).copied().flatten().unwrap_or(0);
            }
        }
        let default_material = materials.len() as u32;

        // Geometry.
        let mut triangles = Vec::new();
        let mut uses_default = false;
        let (mut morph, mut skinned, mut colours) = (false, false, false);
        for (rig_node, (node, _)) in order.iter().enumerate() {
            let Some(mesh) = node.mesh() else { continue };
            skinned |= node.skin().is_some();
            let world = rest_world[rig_node];
            let first_triangle = triangles.len();
            let object = rig.instances.len() as u32;
            let mesh_label = label("mesh", mesh.index(), mesh.name());
            for (k, primitive) in mesh.primitives().enumerate() {
                let element = format!("{mesh_label} primitive {k}");
                morph |= primitive.morph_targets().len() > 0;
                colours |= primitive.get(&gltf::Semantic::Colors(0)).is_some();
                let material = match primitive.material().index() {
                    Some(i) => i as u32,
                    None => {
                        uses_default = true;
                        default_material
                    }
                };
                let set = primitive.material().index().and_then(|i| material_sets[i]);
                let prim = self.primitive(&primitive, &element, set)?;
                for (corners, uvs) in prim {
                    let mut local = corners;
                    let mut uvs = uvs;
                    if world.determinant() < 0.0 {
                        local.swap(1, 2);
                        uvs.swap(1, 2);
                    }
                    let vertices = local.map(|v| world.transform_point3(v));
                    if let Some(vertex) = vertices.iter().position(|v| !v.is_finite()) {
                        return Err(self.content(
                            element,
                            format!(
                                "vertex {vertex} of triangle {} is not finite after the node transforms",
                                triangles.len() - first_triangle
                            ),
                        ));
                    }
                    rig.local.push(local);
                    triangles.push(Triangle {
                        vertices,
                        uvs,
                        material,
                        object,
                    });
                }
            }
            rig.instances.push(MeshInstance {
                node: rig_node,
                first_triangle,
                triangle_count: triangles.len() - first_triangle,
            });
        }
        if triangles.is_empty() {
            return Err(self.content(scene_label, "contains no triangles"));
        }
        if uses_default {
            materials.push(Material::new("default", DEFAULT_ALBEDO, Vec3::ZERO));
        }
        if morph {
            self.notices
                .push("morph targets are not supported: meshes are rendered with their base shape".into());
        }
        if skinned {
            self.notices
                .push("skins are not supported: skinned meshes are rendered at their bind pose".into());
        }
        if colours {
            self.notices.push("vertex colours (COLOR_0) are ignored".into());
        }

        rig.camera = self.camera(&order, camera_index)?;
        rig.channels = self.channels(&rig_index)?;

        let mut scene = Scene {
            triangles,
            materials,
            images,
            camera: Camera::framing(Vec3::ZERO, Vec3::ONE),
        };
        scene.camera = match rig.camera {
            Some(c) => {
                let camera = camera_from_matrix(&rest_world[c.node], c.fov_y_degrees);
                if camera.basis().is_err() {
                    return Err(self.content(
                        format!("camera node '{}'", rig.nodes[c.node].name),
                        "degenerate camera transform",
                    ));
                }
                camera
            }
            None => {
                let (lo, hi) = scene.bounds();
                Camera::framing(lo, hi)
            }
        };
        Ok(GltfScene {
            scene,
            rig,
            notices: self.notices,
        })
    }

    /// The scene's nodes depth first (children in file order) with their
    /// parent's position in that order.
    fn traverse<'d>(&self, scene: &gltf::Scene<'d>) -> Result<Vec<(gltf::Node<'d>, Option<usize>)>> {
        let mut seen = vec![false; self.document.nodes().len()];
        let mut order = Vec::new();
        let mut stack: Vec<(gltf::Node<'d>, Option<usize>)> = scene.nodes().map(|n| (n, None)).collect();
        stack.reverse();
        while let Some((node, parent)) = stack.pop() {
            if std::mem::replace(&mut seen[node.index()], true) {
                return Err(self.content(
                    label("node", node.index(), node.name()),
                    "appears more than once in the scene's hierarchy (a cycle, or two parents)",
                ));
            }
            let me = order.len();
            let first_child = stack.len();
            stack.extend(node.children().map(|c| (c, Some(me))));
            stack[first_child..].reverse();
            order.push((node, parent));
        }
        Ok(order)
    }

    /// A node's file transform as a [`Trs`].
    fn rest_transform(&mut self, node: &gltf::Node) -> Result<Trs> {
        let element = || label("node", node.index(), node.name());
        match node.transform() {
            gltf::scene::Transform::Decomposed {
                translation,
                rotation,
                scale,
            } => {
                let (t, r, s) = (Vec3::from(translation), Vec4::from(rotation), Vec3::from(scale));
                if !(t.is_finite() && r.is_finite() && s.is_finite()) {
                    return Err(self.content(element(), "translation, rotation or scale is NaN or infinite"));
                }
                if r.length() < 1e-6 {
                    return Err(self.content(element(), "rotation is a zero quaternion"));
                }
                Ok(Trs {
                    translation: t,
                    rotation: Quat::from_vec4(r.normalize()),
                    scale: s,
                })
            }
            gltf::scene::Transform::Matrix { matrix } => {
                let m = Mat4::from_cols_array_2d(&matrix);
                if !m.is_finite() {
                    return Err(self.content(element(), "matrix is NaN or infinite"));
                }
                let (scale, rotation, translation) = m.to_scale_rotation_translation();
                let rotation = if rotation.is_finite() && rotation.length() > 1e-6 {
                    rotation.normalize()
                } else {
                    Quat::IDENTITY
                };
                let trs = Trs {
                    translation,
                    rotation,
                    scale: if scale.is_finite() { scale } else { Vec3::ZERO },
                };
                let tolerance = 1e-4 * m.to_cols_array().iter().fold(1.0f32, |a, v| a.max(v.abs()));
                if !trs.matrix().abs_diff_eq(m, tolerance) {
                    self.notices.push(format!(
                        "{}: its matrix has shear, approximated by translation, rotation and scale",
                        element()
                    ));
                }
                Ok(trs)
            }
        }
    }

    /// Scene materials in file order (texture `image` fields still hold
    /// glTF image indices) and the texture coordinate set of each textured
    /// material.
    fn materials(&mut self) -> Result<(Vec<Material>, Vec<Option<u32>>)> {
        let mut materials = Vec::new();
        let mut sets = Vec::new();
        let (mut metallic, mut normal, mut occlusion, mut alpha) = (false, false, false, false);
        for m in self.document.materials() {
            let index = m.index().unwrap_or(materials.len());
            let name = m
                .name()
                .map_or_else(|| format!("material {index}"), str::to_string);
            let element = || label("material", index, m.name());
            let pbr = m.pbr_metallic_roughness();
            metallic |= pbr.metallic_factor() > 0.0 || pbr.metallic_roughness_texture().is_some();
            normal |= m.normal_texture().is_some();
            occlusion |= m.occlusion_texture().is_some();
            alpha |= m.alpha_mode() != gltf::material::AlphaMode::Opaque;
            let albedo = Vec4::from(pbr.base_color_factor()).truncate();
            let strength = m.emissive_strength().unwrap_or(1.0);
            let emission = Vec3::from(m.emissive_factor()) * strength;
            for (what, c) in [("base colour factor", albedo), ("emission", emission)] {
                if !c.is_finite() || c.min_element() < 0.0 {
                    return Err(self.content(element(), format!("{what} {c} is NaN, infinite or negative")));
                }
            }
            let base = pbr.base_color_texture();
            let emissive = m.emissive_texture();
            let set = match (&base, &emissive) {
                (Some(b), Some(e)) if b.tex_coord() != e.tex_coord() => {
                    return Err(self.content(
                        element(),
                        format!(
                            "base colour texture reads TEXCOORD_{} but emissive texture reads TEXCOORD_{}: one set per material is supported",
                            b.tex_coord(),
                            e.tex_coord()
                        ),
                    ))
                }
                (Some(t), _) | (None, Some(t)) => Some(t.tex_coord()),
                (None, None) => None,
            };
            materials.push(Material {
                name,
                albedo,
                emission,
                base_color_texture: base.map(|t| texture_ref(&t.texture())),
                emission_texture: emissive.map(|t| texture_ref(&t.texture())),
            });
            sets.push(set);
        }
        if metallic {
            self.notices
                .push("metallic materials are rendered as diffuse (metallic/roughness not supported)".into());
        }
        if normal || occlusion {
            self.notices
                .push("normal and occlusion textures are ignored".into());
        }
        if alpha {
            self.notices
                .push("alpha (BLEND and MASK alpha modes) is ignored: surfaces are opaque".into());
        }
        Ok((materials, sets))
    }

    /// Decodes the images the materials use; returns them and the map from
    /// glTF image index to scene image index.
    fn images(&self, materials: &[Material]) -> Result<(Vec<Image>, Vec<Option<u32>>)> {
        let mut image_of = vec![None; self.document.images().len()];
        let mut images = Vec::new();
        let used = materials
            .iter()
            .flat_map(|m| [m.base_color_texture, m.emission_texture])
            .flatten()
            .map(|t| t.image as usize);
        for i in used {
            if image_of.get(i).is_none_or(|x| x.is_some()) {
                continue;
            }
            let Some(image) = self.document.images().nth(i) else {
                continue;
            };
            let name = match (image.name(), image.source()) {
                (Some(n), _) => n.to_string(),
                (None, gltf::image::Source::Uri { uri, .. }) if !uri.starts_with("data:") => short_uri(uri),
                _ => format!("image {i}"),
            };
            let element = format!("image {i} ('{name}')");
            if let gltf::image::Source::Uri { uri, .. } = image.source() {
                check_uri(self.path, &element, uri)?;
            }
            let data = gltf::image::Data::from_source(image.source(), Some(self.base), &self.buffers)
                .map_err(|source| Error::GltfLoad {
                    path: self.path.to_path_buf(),
                    element: element.clone(),
                    source,
                })?;
            let image = convert_image(name, &data).map_err(|reason| self.content(&element, reason))?;
            image_of[i] = Some(images.len() as u32);
            images.push(image);
        }
        Ok((images, image_of))
    }

    /// The triangles of a primitive in its node's space: corners and their
    /// texture coordinates (zero when `set` is `None`).
    fn primitive(
        &self,
        primitive: &gltf::Primitive,
        element: &str,
        set: Option<u32>,
    ) -> Result<Vec<([Vec3; 3], [Vec2; 3])>> {
        use gltf::mesh::Mode;
        let strip_or_fan = match primitive.mode() {
            Mode::Triangles => false,
            Mode::TriangleStrip | Mode::TriangleFan => true,
            other => {
                return Err(self.content(
                    element,
                    format!("mode {other:?} is not supported (only triangles, triangle strips and fans)"),
                ))
            }
        };
        let Some(positions) = primitive.get(&gltf::Semantic::Positions) else {
            return Err(self.content(element, "has no POSITION attribute"));
        };
        self.check_accessor(
            &positions,
            element,
            "POSITION",
            &[(DataType::F32, Dimensions::Vec3)],
            false,
        )?;
        let reader = primitive.reader(|b| self.buffers.get(b.index()).map(|d| d.0.as_slice()));
        let points: Vec<Vec3> = reader
            .read_positions()
            .map(|it| it.map(Vec3::from).collect())
            .unwrap_or_default();
        if points.len() != positions.count() {
            return Err(self.content(element, "POSITION data cannot be read"));
        }
        if let Some(vertex) = points.iter().position(|p| !p.is_finite()) {
            return Err(Error::NonFiniteVertex {
                path: self.path.to_path_buf(),
                model: element.to_string(),
                vertex,
            });
        }

        let uvs: Vec<Vec2> = match set {
            None => vec![Vec2::ZERO; points.len()],
            Some(set) => {
                let what = format!("TEXCOORD_{set}");
                let Some(acc) = primitive.get(&gltf::Semantic::TexCoords(set)) else {
                    return Err(self.content(
                        element,
                        format!("its material is textured but the primitive has no {what}"),
                    ));
                };
                self.check_accessor(
                    &acc,
                    element,
                    &what,
                    &[
                        (DataType::F32, Dimensions::Vec2),
                        (DataType::U8, Dimensions::Vec2),
                        (DataType::U16, Dimensions::Vec2),
                    ],
                    true,
                )?;
                let uvs: Vec<Vec2> = reader
                    .read_tex_coords(set)
                    .map(|it| it.into_f32().map(Vec2::from).collect())
                    .unwrap_or_default();
                if uvs.len() != points.len() {
                    return Err(self.content(
                        element,
                        format!("{what} has {} values for {} positions", acc.count(), points.len()),
                    ));
                }
                if let Some(k) = uvs.iter().position(|uv| !uv.is_finite()) {
                    return Err(self.content(element, format!("{what} value {k} is NaN or infinite")));
                }
                uvs
            }
        };

        let indices: Vec<u32> = match primitive.indices() {
            Some(acc) => {
                let int_types = [DataType::U8, DataType::U16, DataType::U32].map(|t| (t, Dimensions::Scalar));
                self.check_accessor(&acc, element, "indices", &int_types, false)?;
                let indices: Vec<u32> = reader
                    .read_indices()
                    .map(|it| it.into_u32().collect())
                    .unwrap_or_default();
                if indices.len() != acc.count() {
                    return Err(self.content(element, "index data cannot be read"));
                }
                if let Some(k) = indices.iter().position(|&i| i as usize >= points.len()) {
                    return Err(self.content(
                        element,
                        format!(
                            "index {k} is {}, out of range: the primitive has {} vertices",
                            indices[k],
                            points.len()
                        ),
                    ));
                }
                indices
            }
            None => (0..points.len() as u32).collect(),
        };
        let corners: Vec<[u32; 3]> = match primitive.mode() {
            Mode::TriangleStrip => (0..indices.len().saturating_sub(2))
                .map(|i| {
                    let odd = i % 2;
                    [indices[i], indices[i + 1 + odd], indices[i + 2 - odd]]
                })
                .collect(),
            Mode::TriangleFan => (1..indices.len().saturating_sub(1))
                .map(|i| [indices[i], indices[i + 1], indices[0]])
                .collect(),
            _ => {
                if !indices.chunks_exact(3).remainder().is_empty() {
                    return Err(self.content(
                        element,
                        format!("{} vertices do not make whole triangles", indices.len()),
                    ));
                }
                indices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
            }
        };
        Ok(corners
            .into_iter()
            .filter(|[a, b, c]| !strip_or_fan || (a != b && b != c && a != c))
            .map(|c| {
                let c = c.map(|i| i as usize);
                (c.map(|i| points[i]), c.map(|i| uvs[i]))
            })
            .collect())
    }

    /// Checks an accessor before the `gltf` readers touch it (they panic on
    /// unexpected types and overflowing ranges): type in `allowed` (integer
    /// types normalised when `normalized_ints`), at least one element, and
    /// every element (base, sparse indices and values) inside its buffer
    /// view, which is inside its buffer. Sparse indices must be strictly
    /// increasing and in range.
    fn check_accessor(
        &self,
        acc: &gltf::Accessor,
        element: &str,
        what: &str,
        allowed: &[(DataType, Dimensions)],
        normalized_ints: bool,
    ) -> Result<()> {
        let fail = |reason: String| {
            Err(self.content(element, format!("{what} (accessor {}): {reason}", acc.index())))
        };
        let ty = (acc.data_type(), acc.dimensions());
        if !allowed.contains(&ty) {
            let expected: Vec<String> = allowed.iter().map(|(t, d)| format!("{d:?} of {t:?}")).collect();
            return fail(format!(
                "is {:?} of {:?}, expected {}",
                ty.1,
                ty.0,
                expected.join(" or ")
            ));
        }
        if normalized_ints && acc.data_type() != DataType::F32 && !acc.normalized() {
            return fail("integer values must be normalized".into());
        }
        let count = acc.count();
        if count == 0 {
            return fail("has no element".into());
        }
        if acc.view().is_none() && count > MAX_SPARSE_ONLY_COUNT {
            // Sparse without a base view: nothing bounds `count` by the file size.
            return fail(format!(
                "{count} elements without a buffer view (at most {MAX_SPARSE_ONLY_COUNT} are accepted)"
            ));
        }
        let size = acc.size();
        if let Some(view) = acc.view() {
            if let Err(reason) =
                self.check_range(&view, acc.offset(), view.stride().unwrap_or(size), size, count)
            {
                return fail(reason);
            }
        }
        if let Some(sparse) = acc.sparse() {
            let n = sparse.count();
            if n == 0 || n > count {
                return fail(format!("sparse count {n} is not in 1..={count}"));
            }
            let indices = sparse.indices();
            let iview = indices.view();
            let isize = indices.index_type().size();
            let istride = iview.stride().unwrap_or(isize);
            if let Err(reason) = self.check_range(&iview, indices.offset(), istride, isize, n) {
                return fail(format!("sparse indices: {reason}"));
            }
            let vview = sparse.values().view();
            if let Err(reason) = self.check_range(
                &vview,
                sparse.values().offset(),
                vview.stride().unwrap_or(size),
                size,
                n,
            ) {
                return fail(format!("sparse values: {reason}"));
            }
            let data = self
                .buffers
                .get(iview.buffer().index())
                .map_or(&[][..], |d| d.0.as_slice());
            let mut previous: Option<u32> = None;
            for k in 0..n {
                // In range: checked by `check_range` above.
                let at = iview.offset() + indices.offset() + k * istride;
                let index = match data.get(at..at + isize) {
                    Some(&[b]) => u32::from(b),
                    Some(&[b0, b1]) => u32::from(u16::from_le_bytes([b0, b1])),
                    Some(&[b0, b1, b2, b3]) => u32::from_le_bytes([b0, b1, b2, b3]),
                    _ => return fail(format!("sparse index {k} cannot be read")),
                };
                if index as usize >= count || previous.is_some_and(|p| index <= p) {
                    return fail(format!(
                        "sparse index {k} is {index}: indices must be strictly increasing and below {count}"
                    ));
                }
                previous = Some(index);
            }
        }
        Ok(())
    }

    /// `count` elements of `size` bytes every `stride` bytes from `offset`
    /// lie inside `view`, and `view` inside its buffer's data.
    fn check_range(
        &self,
        view: &gltf::buffer::View,
        offset: usize,
        stride: usize,
        size: usize,
        count: usize,
    ) -> std::result::Result<(), String> {
        if stride < size {
            return Err(format!(
                "byte stride {stride} is smaller than the element size {size}"
            ));
        }
        let end = stride
            .checked_mul(count - 1)
            .and_then(|x| x.checked_add(offset))
            .and_then(|x| x.checked_add(size));
        if end.is_none_or(|end| end > view.length()) {
            return Err(format!(
                "{count} elements of {size} bytes (stride {stride}) from byte {offset} do not fit buffer view {} of {} bytes",
                view.index(),
                view.length()
            ));
        }
        let buffer_len = self.buffers.get(view.buffer().index()).map_or(0, |d| d.0.len());
        if view
            .offset()
            .checked_add(view.length())
            .is_none_or(|e| e > buffer_len)
        {
            return Err(format!("buffer view {} lies outside its buffer", view.index()));
        }
        Ok(())
    }

    /// The chosen camera node, if any.
    fn camera(
        &self,
        order: &[(gltf::Node, Option<usize>)],
        camera_index: Option<usize>,
    ) -> Result<Option<RigCamera>> {
        let cameras: Vec<(usize, gltf::Camera)> = order
            .iter()
            .enumerate()
            .filter_map(|(i, (n, _))| n.camera().map(|c| (i, c)))
            .collect();
        let wanted = camera_index.unwrap_or(0);
        let Some((node, camera)) = cameras.get(wanted) else {
            if camera_index.is_none() {
                return Ok(None);
            }
            return Err(self.content(
                format!("camera index {wanted}"),
                format!("out of range: the scene has {} camera node(s)", cameras.len()),
            ));
        };
        let element = label("camera", camera.index(), camera.name());
        match camera.projection() {
            gltf::camera::Projection::Orthographic(_) => {
                Err(self.content(element, "orthographic cameras are not supported"))
            }
            gltf::camera::Projection::Perspective(p) => {
                let yfov = p.yfov();
                if !(yfov > 0.0 && yfov < std::f32::consts::PI) {
                    return Err(self.content(element, format!("yfov {yfov} rad is outside (0, pi)")));
                }
                Ok(Some(RigCamera {
                    node: *node,
                    fov_y_degrees: yfov.to_degrees(),
                }))
            }
        }
    }

    /// Translation, rotation and scale channels of every animation.
    fn channels(&mut self, rig_index: &[Option<usize>]) -> Result<Vec<Channel>> {
        let document = self.document.clone();
        let mut channels = Vec::new();
        let (mut weights, mut outside) = (false, 0usize);
        let animation_count = document.animations().len();
        for animation in document.animations() {
            let anim_label = label("animation", animation.index(), animation.name());
            for (c, channel) in animation.channels().enumerate() {
                let element = format!("{anim_label} channel {c}");
                let target = channel.target();
                let property = match target.property() {
                    gltf::animation::Property::Translation => Property::Translation,
                    gltf::animation::Property::Rotation => Property::Rotation,
                    gltf::animation::Property::Scale => Property::Scale,
                    gltf::animation::Property::MorphTargetWeights => {
                        weights = true;
                        continue;
                    }
                };
                let Some(node) = rig_index.get(target.node().index()).copied().flatten() else {
                    outside += 1;
                    continue;
                };
                let sampler = channel.sampler();
                let interpolation = match sampler.interpolation() {
                    gltf::animation::Interpolation::Step => Interpolation::Step,
                    gltf::animation::Interpolation::Linear => Interpolation::Linear,
                    gltf::animation::Interpolation::CubicSpline => Interpolation::CubicSpline,
                };
                self.check_accessor(
                    &sampler.input(),
                    &element,
                    "input (times)",
                    &[(DataType::F32, Dimensions::Scalar)],
                    false,
                )?;
                let outputs: &[(DataType, Dimensions)] = match property {
                    Property::Rotation => &[
                        (DataType::F32, Dimensions::Vec4),
                        (DataType::I8, Dimensions::Vec4),
                        (DataType::U8, Dimensions::Vec4),
                        (DataType::I16, Dimensions::Vec4),
                        (DataType::U16, Dimensions::Vec4),
                    ],
                    Property::Translation | Property::Scale => &[(DataType::F32, Dimensions::Vec3)],
                };
                self.check_accessor(&sampler.output(), &element, "output (values)", outputs, true)?;
                let reader = channel.reader(|b| self.buffers.get(b.index()).map(|d| d.0.as_slice()));
                let times: Vec<f32> = reader.read_inputs().map(|it| it.collect()).unwrap_or_default();
                let values: Vec<Vec4> = match reader.read_outputs() {
                    Some(gltf::animation::util::ReadOutputs::Translations(it))
                    | Some(gltf::animation::util::ReadOutputs::Scales(it)) => {
                        it.map(|v| Vec3::from(v).extend(0.0)).collect()
                    }
                    Some(gltf::animation::util::ReadOutputs::Rotations(r)) => {
                        r.into_f32().map(Vec4::from).collect()
                    }
                    _ => Vec::new(),
                };
                let channel = Channel {
                    node,
                    property,
                    interpolation,
                    times,
                    values,
                };
                if let Some(reason) = channel.problem() {
                    return Err(self.content(element, reason));
                }
                channels.push(channel);
            }
        }
        if weights {
            self.notices
                .push("morph-target weight animation is not supported: ignored".into());
        }
        if outside > 0 {
            self.notices.push(format!(
                "{outside} animation channel(s) target nodes outside the loaded scene: ignored"
            ));
        }
        if animation_count > 1 && !channels.is_empty() {
            self.notices.push(format!(
                "the file's {animation_count} animations are played together"
            ));
        }
        Ok(channels)
    }
}

fn content_error(path: &Path, element: impl Into<String>, reason: impl Into<String>) -> Error {
    Error::GltfContent {
        path: path.to_path_buf(),
        element: element.into(),
        reason: reason.into(),
    }
}

/// A [`TextureRef`] with the texture's sampler settings; `image` holds the
/// glTF image index until remapped.
fn texture_ref(texture: &gltf::Texture) -> TextureRef {
    use gltf::texture::{MagFilter, WrappingMode};
    let sampler = texture.sampler();
    let wrap = |m| match m {
        WrappingMode::Repeat => Wrap::Repeat,
        WrappingMode::ClampToEdge => Wrap::Clamp,
        WrappingMode::MirroredRepeat => Wrap::Mirror,
    };
    TextureRef {
        image: texture.source().index() as u32,
        wrap_u: wrap(sampler.wrap_s()),
        wrap_v: wrap(sampler.wrap_t()),
        filter: match sampler.mag_filter() {
            Some(MagFilter::Nearest) => Filter::Nearest,
            Some(MagFilter::Linear) | None => Filter::Bilinear,
        },
    }
}

/// The GLB header's declared length must be at least the header's and at
/// most the file's (the `gltf` crate would underflow or report a generic
/// error).
fn check_glb_header(path: &Path, bytes: &[u8]) -> Result<()> {
    if !bytes.starts_with(b"glTF") {
        return Ok(());
    }
    let word = |at: usize| {
        bytes
            .get(at..at + 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize)
    };
    match word(8) {
        None => Err(content_error(
            path,
            "GLB header",
            "the file is shorter than the 12-byte header",
        )),
        Some(length) if length < 12 => Err(content_error(
            path,
            "GLB header",
            format!("declared length {length} is shorter than the header"),
        )),
        Some(length) if length > bytes.len() => Err(content_error(
            path,
            "GLB header",
            format!(
                "declares {length} bytes but the file has {} (truncated?)",
                bytes.len()
            ),
        )),
        Some(_) => Ok(()),
    }
}

/// Checks, on the raw JSON, what the `gltf` crate indexes without bounds
/// checks during validation or import.
fn precheck_json(path: &Path, root: &gltf::json::Root) -> Result<()> {
    let accessors = root.accessors.len();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            for (semantic, index) in &primitive.attributes {
                if index.value() >= accessors {
                    let name = match semantic {
                        Checked::Valid(s) => s.to_string(),
                        Checked::Invalid => "attribute".into(),
                    };
                    return Err(content_error(
                        path,
                        format!("{} primitive {p}", label("mesh", m, mesh.name.as_deref())),
                        format!(
                            "{name} names accessor {}, but the file has {accessors} accessors",
                            index.value()
                        ),
                    ));
                }
            }
        }
    }
    for (i, camera) in root.cameras.iter().enumerate() {
        use gltf::json::camera::Type;
        let missing = match camera.type_ {
            Checked::Valid(Type::Perspective) => camera.perspective.is_none(),
            Checked::Valid(Type::Orthographic) => camera.orthographic.is_none(),
            Checked::Invalid => false, // reported by validation
        };
        if missing {
            return Err(content_error(
                path,
                label("camera", i, camera.name.as_deref()),
                "has no parameters for its type",
            ));
        }
    }
    for (i, image) in root.images.iter().enumerate() {
        let element = || label("image", i, image.name.as_deref());
        match (&image.buffer_view, &image.uri) {
            (Some(_), _) if image.mime_type.is_none() => {
                return Err(content_error(
                    path,
                    element(),
                    "is in a buffer view but has no mimeType",
                ))
            }
            (None, None) => return Err(content_error(path, element(), "has neither uri nor bufferView")),
            _ => {}
        }
    }
    for (a, animation) in root.animations.iter().enumerate() {
        for (c, channel) in animation.channels.iter().enumerate() {
            let element = || format!("{} channel {c}", label("animation", a, animation.name.as_deref()));
            if channel.target.node.value() >= root.nodes.len() {
                return Err(content_error(
                    path,
                    element(),
                    format!(
                        "targets node {}, but the file has {} nodes",
                        channel.target.node.value(),
                        root.nodes.len()
                    ),
                ));
            }
            if matches!(channel.target.path, Checked::Invalid) {
                return Err(content_error(path, element(), "unknown target path"));
            }
        }
    }
    Ok(())
}

/// Every buffer view lies inside its buffer's declared length.
fn check_buffer_views(path: &Path, document: &gltf::Document) -> Result<()> {
    for view in document.views() {
        let end = view.offset().checked_add(view.length());
        if end.is_none_or(|e| e > view.buffer().length()) {
            return Err(content_error(
                path,
                format!("buffer view {}", view.index()),
                format!(
                    "bytes {}..+{} exceed buffer {} of {} bytes",
                    view.offset(),
                    view.length(),
                    view.buffer().index(),
                    view.buffer().length()
                ),
            ));
        }
    }
    Ok(())
}

/// A relative URI must percent-decode to UTF-8 (the `gltf` crate panics
/// otherwise).
fn check_uri(path: &Path, element: &str, uri: &str) -> Result<()> {
    if uri.contains(':') {
        return Ok(()); // data: / file: / unsupported schemes are handled by gltf
    }
    let bytes = uri.as_bytes();
    let mut decoded = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        match (bytes[i], bytes.get(i + 1).copied(), bytes.get(i + 2).copied()) {
            (b'%', Some(h), Some(l)) if hex(h).is_some() && hex(l).is_some() => {
                decoded.push((hex(h).unwrap_or(0) * 16 + hex(l).unwrap_or(0)) as u8);
                i += 3;
            }
            (b, _, _) => {
                decoded.push(b);
                i += 1;
            }
        }
    }
    if std::str::from_utf8(&decoded).is_err() {
        return Err(content_error(
            path,
            element,
            format!("URI '{uri}' does not percent-decode to UTF-8"),
        ));
    }
    Ok(())
}

/// A URI for messages: data URIs shortened.
fn short_uri(uri: &str) -> String {
    if uri.starts_with("data:") {
        let head: String = uri.chars().take(32).collect();
        format!("{head}...")
    } else {
        uri.to_string()
    }
}

/// Converts a decoded image to 8-bit sRGB RGBA (see the module docs).
fn convert_image(name: String, data: &gltf::image::Data) -> std::result::Result<Image, String> {
    use gltf::image::Format;
    #[derive(Clone, Copy)]
    enum Kind {
        U8,
        U16,
        F32,
    }
    let (channels, kind) = match data.format {
        Format::R8 => (1, Kind::U8),
        Format::R8G8 => (2, Kind::U8),
        Format::R8G8B8 => (3, Kind::U8),
        Format::R8G8B8A8 => (4, Kind::U8),
        Format::R16 => (1, Kind::U16),
        Format::R16G16 => (2, Kind::U16),
        Format::R16G16B16 => (3, Kind::U16),
        Format::R16G16B16A16 => (4, Kind::U16),
        Format::R32G32B32FLOAT => (3, Kind::F32),
        Format::R32G32B32A32FLOAT => (4, Kind::F32),
    };
    let bytes_per_channel = match kind {
        Kind::U8 => 1,
        Kind::U16 => 2,
        Kind::F32 => 4,
    };
    let texel_bytes = channels * bytes_per_channel;
    let expected = (data.width as usize)
        .checked_mul(data.height as usize)
        .and_then(|n| n.checked_mul(texel_bytes));
    if data.width == 0 || data.height == 0 || expected != Some(data.pixels.len()) {
        return Err(format!(
            "decoded to {}x{} {:?} with {} bytes",
            data.width,
            data.height,
            data.format,
            data.pixels.len()
        ));
    }
    let channel = |c: &[u8]| -> u8 {
        match kind {
            Kind::U8 => c[0],
            Kind::U16 => ((u32::from(u16::from_ne_bytes([c[0], c[1]])) * 255 + 32767) / 65535) as u8,
            Kind::F32 => {
                let v = f32::from_ne_bytes([c[0], c[1], c[2], c[3]]);
                // NaN maps to 0.
                (v.clamp(0.0, 1.0) * 255.0).round().max(0.0) as u8
            }
        }
    };
    let texels = data
        .pixels
        .chunks_exact(texel_bytes)
        .map(|t| {
            let c: Vec<u8> = t.chunks_exact(bytes_per_channel).map(channel).collect();
            match c.as_slice() {
                [l] => [*l, *l, *l, 255],
                [l, a] => [*l, *l, *l, *a],
                [r, g, b] => [*r, *g, *b, 255],
                [r, g, b, a, ..] => [*r, *g, *b, *a],
                [] => [0, 0, 0, 255],
            }
        })
        .collect();
    Ok(Image {
        name,
        width: data.width,
        height: data.height,
        texels,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::SceneGpu;
    use serde_json::{json, Value};
    use std::fs;
    use std::path::PathBuf;

    /// The fixtures written by `examples/make_gltf_fixtures.rs`.
    fn fixture(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/gltf")
            .join(name)
    }

    /// A temp dir holding a copy of every fixture.
    fn fixture_copy() -> tempfile::TempDir {
        let dir = tempfile::tempdir().expect("temp dir");
        for entry in fs::read_dir(fixture("")).expect("fixture dir") {
            let entry = entry.expect("entry");
            fs::copy(entry.path(), dir.path().join(entry.file_name())).expect("copy");
        }
        dir
    }

    fn read_json(path: &Path) -> Value {
        serde_json::from_slice(&fs::read(path).expect("read")).expect("JSON")
    }

    fn write_json(path: &Path, v: &Value) {
        fs::write(path, serde_json::to_vec_pretty(v).expect("JSON")).expect("write");
    }

    /// Byte offset of accessor `a`'s first element in its buffer.
    fn accessor_offset(doc: &Value, a: usize) -> usize {
        let acc = &doc["accessors"][a];
        let view = &doc["bufferViews"][acc["bufferView"].as_u64().expect("view") as usize];
        (view["byteOffset"].as_u64().unwrap_or(0) + acc["byteOffset"].as_u64().unwrap_or(0)) as usize
    }

    /// A `.glb` container of `doc` and `bin`.
    fn glb(doc: &Value, bin: &[u8]) -> Vec<u8> {
        let mut json_chunk = serde_json::to_vec(doc).expect("JSON");
        while json_chunk.len() & 3 != 0 {
            json_chunk.push(b' ');
        }
        let mut bin = bin.to_vec();
        while bin.len() & 3 != 0 {
            bin.push(0);
        }
        let total = 28 + json_chunk.len() + bin.len();
        let mut out = b"glTF".to_vec();
        for word in [2, total as u32, json_chunk.len() as u32] {
            out.extend_from_slice(&word.to_le_bytes());
        }
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&json_chunk);
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&bin);
        out
    }

    fn base64(bytes: &[u8]) -> String {
        const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let mut out = String::new();
        for chunk in bytes.chunks(3) {
            let b = [chunk[0], *chunk.get(1).unwrap_or(&0), *chunk.get(2).unwrap_or(&0)];
            let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
            for k in 0..4 {
                if k <= chunk.len() {
                    out.push(ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char);
                } else {
                    out.push('=');
                }
            }
        }
        out
    }

    fn load(path: &Path) -> GltfScene {
        load_gltf(path, None).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    }

    fn content_error(result: Result<GltfScene>) -> (String, String) {
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
                filter: Filter::Nearest
            })
        );
        assert!(s.materials[1]
            .emission
            .abs_diff_eq(Vec3::new(30.0, 27.0, 24.0), 1e-5));
        assert_eq!(s.materials[1].albedo, Vec3::ZERO);
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

    /// The textured quad as a `.glb` (image in the BIN chunk) and as a
    /// `.gltf` with data URIs load to the same scene as the `.gltf` + `.bin`.
    #[test]
    fn glb_gltf_bin_and_data_uris_give_the_same_scene() {
        let reference = load(&fixture("textured_quad.gltf"));
        let dir = tempfile::tempdir().expect("temp dir");
        let doc = read_json(&fixture("textured_quad.gltf"));
        let bin = fs::read(fixture("textured_quad.bin")).expect("bin");
        let png = fs::read(fixture("checker.png")).expect("png");

        let mut packed = doc.clone();
        let mut data = bin.clone();
        let png_offset = data.len().next_multiple_of(4);
        data.resize(png_offset, 0);
        data.extend_from_slice(&png);
        let views = packed["bufferViews"].as_array_mut().expect("views");
        views.push(json!({"buffer": 0, "byteOffset": png_offset, "byteLength": png.len()}));
        let png_view = views.len() - 1;
        packed["images"] = json!([{"bufferView": png_view, "mimeType": "image/png", "name": "checker"}]);
        packed["buffers"] = json!([{"byteLength": data.len()}]);
        let glb_path = dir.path().join("quad.glb");
        fs::write(&glb_path, glb(&packed, &data)).expect("write");
        assert_eq!(load(&glb_path), reference);

        let mut embedded = doc;
        embedded["buffers"][0]["uri"] =
            json!(format!("data:application/octet-stream;base64,{}", base64(&bin)));
        embedded["images"][0]["uri"] = json!(format!("data:image/png;base64,{}", base64(&png)));
        let path = dir.path().join("embedded.gltf");
        write_json(&path, &embedded);
        assert_eq!(load(&path), reference);
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
    fn missing_file_truncated_glb_and_missing_bin_are_errors() {
        let dir = fixture_copy();
        let err = load_gltf(dir.path().join("nope.gltf"), None).expect_err("missing");
        assert!(
            matches!(&err, Error::GltfLoad { source: gltf::Error::Io(_), element, .. } if element == "file"),
            "{err}"
        );
        assert!(err.to_string().contains("nope.gltf"), "{err}");
        assert!(std::error::Error::source(&err).is_some());

        // Every truncation of a .glb is an error, never a panic.
        let bytes = fs::read(fixture("hierarchy.glb")).expect("glb");
        let path = dir.path().join("cut.glb");
        for len in 0..bytes.len() {
            fs::write(&path, &bytes[..len]).expect("write");
            assert!(load_gltf(&path, None).is_err(), "truncated to {len} bytes");
        }
        fs::write(&path, &bytes[..bytes.len() / 2]).expect("write");
        let (element, reason) = content_error(load_gltf(&path, None));
        assert!(
            element == "GLB header" && reason.contains("truncated"),
            "{reason}"
        );

        fs::remove_file(dir.path().join("textured_quad.bin")).expect("rm");
        let err = load_gltf(dir.path().join("textured_quad.gltf"), None).expect_err("no bin");
        match &err {
            Error::GltfLoad {
                element,
                source: gltf::Error::Io(_),
                ..
            } => assert!(element.contains("textured_quad.bin"), "{element}"),
            other => panic!("{other:?}"),
        }
        assert!(err.to_string().contains("textured_quad.gltf"), "{err}");
        // A .bin shorter than declared.
        fs::write(dir.path().join("textured_quad.bin"), [0u8; 8]).expect("write");
        let err = load_gltf(dir.path().join("textured_quad.gltf"), None).expect_err("short bin");
        assert!(
            matches!(
                err,
                Error::GltfLoad {
                    source: gltf::Error::BufferLength { .. },
                    ..
                }
            ),
            "{err}"
        );
    }

    /// Loads fixture `<stem>.gltf` after `edit` changed its JSON and its
    /// `<stem>.bin` (in a temp dir holding all fixtures).
    fn load_fixture_patched(stem: &str, edit: impl FnOnce(&mut Value, &mut Vec<u8>)) -> Result<GltfScene> {
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
    fn load_patched(edit: impl FnOnce(&mut Value, &mut Vec<u8>)) -> Result<GltfScene> {
        load_fixture_patched("textured_quad", edit)
    }

    /// Makes the quad's POSITION accessor sparse with one replaced vertex:
    /// u16 index `index` (padded to 4 bytes) and `value`, appended to `bin`
    /// with two new buffer views. Returns the accessor's index.
    fn sparse_position(doc: &mut Value, bin: &mut Vec<u8>, index: u16, value: [f32; 3]) -> usize {
        let offset = bin.len();
        bin.extend_from_slice(&index.to_le_bytes());
        bin.extend_from_slice(&[0, 0]);
        for v in value {
            bin.extend_from_slice(&v.to_le_bytes());
        }
        let views = doc["bufferViews"].as_array_mut().expect("views");
        views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": 2}));
        views.push(json!({"buffer": 0, "byteOffset": offset + 4, "byteLength": 12}));
        let n = views.len();
        let a = quad_accessor(doc, "POSITION");
        doc["accessors"][a]["sparse"] = json!({
            "count": 1,
            "indices": {"bufferView": n - 2, "componentType": 5123},
            "values": {"bufferView": n - 1}
        });
        a
    }

    /// Accessor indices of the checker quad's primitive.
    fn quad_accessor(doc: &Value, attribute: &str) -> usize {
        let prim = &doc["meshes"][0]["primitives"][0];
        let v = if attribute == "indices" {
            &prim["indices"]
        } else {
            &prim["attributes"][attribute]
        };
        v.as_u64().expect("accessor") as usize
    }

    #[test]
    fn bad_accessor_indices_are_errors() {
        let (element, reason) = content_error(load_patched(|doc, _| {
            doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(99);
        }));
        assert!(element.contains("mesh 'checker_quad' primitive 0"), "{element}");
        assert!(reason.contains("accessor 99"), "{reason}");
        let err =
            load_patched(|doc, _| doc["meshes"][0]["primitives"][0]["indices"] = json!(99)).expect_err("bad");
        assert!(
            matches!(
                &err,
                Error::GltfLoad {
                    source: gltf::Error::Validation(_),
                    ..
                }
            ),
            "{err}"
        );
        assert!(err.to_string().contains("textured_quad.gltf"), "{err}");
        // An accessor of the wrong type (the gltf readers would panic on it).
        let (_, reason) = content_error(load_patched(|doc, _| {
            let a = quad_accessor(doc, "POSITION");
            doc["accessors"][a]["type"] = json!("VEC4");
        }));
        assert!(reason.contains("POSITION") && reason.contains("Vec4"), "{reason}");
        // An accessor running past its buffer view.
        let (_, reason) = content_error(load_patched(|doc, _| {
            let a = quad_accessor(doc, "TEXCOORD_0");
            doc["accessors"][a]["count"] = json!(1000);
        }));
        assert!(reason.contains("do not fit"), "{reason}");
        // A buffer view past its buffer.
        let (element, _) = content_error(load_patched(|doc, _| {
            doc["bufferViews"][0]["byteLength"] = json!(4000)
        }));
        assert_eq!(element, "buffer view 0");
        // An animation channel naming a node that does not exist.
        let (element, _) = content_error(load_patched(|doc, _| {
            doc["animations"] = json!([{
                "samplers": [{"input": 0, "output": 0}],
                "channels": [{"sampler": 0, "target": {"node": 42, "path": "translation"}}]
            }]);
        }));
        assert_eq!(element, "animation 0 channel 0");
    }

    #[test]
    fn non_finite_data_and_bad_indices_are_errors() {
        let err = load_patched(|doc, bin| {
            let at = accessor_offset(doc, quad_accessor(doc, "POSITION")) + 3 * 4 + 4; // vertex 1, y
            bin[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
        })
        .expect_err("NaN");
        match &err {
            Error::NonFiniteVertex { model, vertex, .. } => {
                assert_eq!((model.as_str(), *vertex), ("mesh 'checker_quad' primitive 0", 1));
            }
            other => panic!("{other:?}"),
        }
        assert!(err.to_string().contains("textured_quad.gltf"), "{err}");
        let (_, reason) = content_error(load_patched(|doc, bin| {
            let at = accessor_offset(doc, quad_accessor(doc, "TEXCOORD_0")) + 2 * 8;
            bin[at..at + 4].copy_from_slice(&f32::INFINITY.to_le_bytes());
        }));
        assert!(reason.contains("TEXCOORD_0 value 2"), "{reason}");
        let (_, reason) = content_error(load_patched(|doc, bin| {
            let at = accessor_offset(doc, quad_accessor(doc, "indices")) + 2 * 4;
            bin[at..at + 2].copy_from_slice(&200u16.to_le_bytes());
        }));
        assert!(reason.contains("index 4 is 200, out of range"), "{reason}");
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
            doc["cameras"][0] = json!({"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 1, "znear": 0.1, "zfar": 10}});
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

    /// `animated_room.gltf` after `edit`.
    fn load_room_patched(edit: impl FnOnce(&mut Value, &mut Vec<u8>)) -> Result<GltfScene> {
        load_fixture_patched("animated_room", edit)
    }

    fn sampler_accessor(doc: &Value, sampler: usize, which: &str) -> usize {
        doc["animations"][0]["samplers"][sampler][which]
            .as_u64()
            .expect("accessor") as usize
    }

    #[test]
    fn invalid_animation_data_is_an_error() {
        // Times 0, 2, 1: not increasing.
        let (element, reason) = content_error(load_room_patched(|doc, bin| {
            let at = accessor_offset(doc, sampler_accessor(doc, 0, "input")) + 4;
            bin[at..at + 4].copy_from_slice(&2.0f32.to_le_bytes());
        }));
        assert_eq!(element, "animation 'walkthrough' channel 0");
        assert!(reason.contains("strictly increasing"), "{reason}");
        // A NaN time.
        let (_, reason) = content_error(load_room_patched(|doc, bin| {
            let at = accessor_offset(doc, sampler_accessor(doc, 0, "input"));
            bin[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
        }));
        assert!(reason.contains("NaN"), "{reason}");
        // A NaN value.
        let (element, reason) = content_error(load_room_patched(|doc, bin| {
            let at = accessor_offset(doc, sampler_accessor(doc, 2, "output")) + 16;
            bin[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
        }));
        assert_eq!(element, "animation 'walkthrough' channel 2");
        assert!(reason.contains("output value 1"), "{reason}");
        // Too few values.
        let (_, reason) = content_error(load_room_patched(|doc, _| {
            let a = sampler_accessor(doc, 1, "output");
            doc["accessors"][a]["count"] = json!(2);
        }));
        assert!(reason.contains("2 output values for 3 keys"), "{reason}");
        // CUBICSPLINE needs three values per key.
        let (_, reason) = content_error(load_room_patched(|doc, _| {
            doc["animations"][0]["samplers"][0]["interpolation"] = json!("CUBICSPLINE");
        }));
        assert!(reason.contains("expected 9"), "{reason}");
        // Morph weights: a notice, not an error.
        let g = load_room_patched(|doc, _| {
            let channels = doc["animations"][0]["channels"].as_array_mut().expect("channels");
            channels.push(json!({"sampler": 0, "target": {"node": 7, "path": "weights"}}));
        })
        .expect("loads");
        assert_eq!(g.rig.channels.len(), 3);
        assert!(
            g.notices.iter().any(|n| n.contains("morph-target weight")),
            "{:?}",
            g.notices
        );
    }

    #[test]
    fn sparse_accessors_strips_fans_and_normalized_uvs_are_read() {
        // Sparse: vertex 0 of the quad replaced by (-1, -1, 5).
        let g = load_patched(|doc, bin| {
            let a = sparse_position(doc, bin, 0, [-1.0, -1.0, 5.0]);
            doc["accessors"][a]["max"][2] = json!(5.0);
        })
        .expect("sparse loads");
        assert_eq!(g.scene.triangles[0].vertices[0], Vec3::new(-1.0, -1.0, 5.0));
        assert_eq!(g.scene.triangles[0].vertices[1], Vec3::new(1.0, -1.0, 0.0));
        // A sparse index out of range.
        let (_, reason) = content_error(load_patched(|doc, bin| {
            sparse_position(doc, bin, 9, [0.0; 3]);
        }));
        assert!(reason.contains("sparse index 0 is 9"), "{reason}");
        // Sparse without a base view: a huge count is refused, not allocated.
        let (_, reason) = content_error(load_patched(|doc, _| {
            let a = quad_accessor(doc, "POSITION");
            let acc = doc["accessors"][a].as_object_mut().expect("accessor");
            acc.remove("bufferView");
            acc.insert("count".into(), json!(1u64 << 40));
            acc.insert(
                "sparse".into(),
                json!({"count": 1, "indices": {"bufferView": 2, "componentType": 5123}, "values": {"bufferView": 0}}),
            );
        }));
        assert!(reason.contains("without a buffer view"), "{reason}");

        // Strip [0, 1, 3, 2] and fan [0, 1, 2, 3]: the same quad, front +Z.
        for (mode, order) in [(5, [0u16, 1, 3, 2]), (6, [0, 1, 2, 3])] {
            let g = load_patched(|doc, bin| {
                let a = quad_accessor(doc, "indices");
                let at = accessor_offset(doc, a);
                for (k, i) in order.iter().enumerate() {
                    bin[at + 2 * k..at + 2 * k + 2].copy_from_slice(&i.to_le_bytes());
                }
                doc["accessors"][a]["count"] = json!(4);
                doc["meshes"][0]["primitives"][0]["mode"] = json!(mode);
            })
            .expect("loads");
            let quad: Vec<&Triangle> = g.scene.triangles.iter().filter(|t| t.object == 0).collect();
            assert_eq!(quad.len(), 2, "mode {mode}");
            let area: f32 = quad
                .iter()
                .map(|t| {
                    (t.vertices[1] - t.vertices[0])
                        .cross(t.vertices[2] - t.vertices[0])
                        .z
                        * 0.5
                })
                .sum();
            assert!((area - 4.0).abs() < 1e-5, "mode {mode}: signed area {area}");
        }

        // Normalised u8 texture coordinates: 255 -> 1.
        let g = load_patched(|doc, bin| {
            let offset = bin.len();
            bin.extend_from_slice(&[0, 255, 255, 255, 255, 0, 0, 0]);
            let views = doc["bufferViews"].as_array_mut().expect("views");
            views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": 8}));
            let view = views.len() - 1;
            let a = quad_accessor(doc, "TEXCOORD_0");
            doc["accessors"][a] = json!({
                "bufferView": view, "componentType": 5121, "normalized": true, "count": 4, "type": "VEC2"
            });
        })
        .expect("u8 UVs load");
        assert_eq!(
            g.scene.triangles[0].uvs,
            [Vec2::new(0.0, 1.0), Vec2::ONE, Vec2::new(1.0, 0.0)]
        );
        // Not normalised: rejected.
        let (_, reason) = content_error(load_patched(|doc, bin| {
            let offset = bin.len();
            bin.extend_from_slice(&[0; 8]);
            let views = doc["bufferViews"].as_array_mut().expect("views");
            views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": 8}));
            let view = views.len() - 1;
            let a = quad_accessor(doc, "TEXCOORD_0");
            doc["accessors"][a] =
                json!({"bufferView": view, "componentType": 5121, "count": 4, "type": "VEC2"});
        }));
        assert!(reason.contains("normalized"), "{reason}");
    }

    #[test]
    fn ignored_features_give_notices() {
        let g = load_patched(|doc, _| {
            doc["materials"][0]["pbrMetallicRoughness"]
                .as_object_mut()
                .expect("pbr")
                .remove("metallicFactor"); // glTF's default: 1
            doc["materials"][1]["normalTexture"] = json!({"index": 0});
            doc["extensionsUsed"] = json!(["KHR_materials_emissive_strength", "KHR_texture_transform"]);
            doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] =
                json!({"KHR_texture_transform": {"scale": [2, 2]}});
        })
        .expect("loads");
        let n = &g.notices;
        assert_eq!(
            n.iter().filter(|l| l.contains("rendered as diffuse")).count(),
            1,
            "{n:?}"
        );
        assert!(n.iter().any(|l| l.contains("KHR_texture_transform")), "{n:?}");
        assert!(n.iter().any(|l| l.contains("normal and occlusion")), "{n:?}");
        assert!(!n.iter().any(|l| l.contains("emissive_strength")), "{n:?}");
        // A required extension that is not supported is an error.
        let err = load_patched(|doc, _| doc["extensionsRequired"] = json!(["KHR_texture_transform"]))
            .expect_err("required");
        assert!(matches!(err, Error::GltfLoad { .. }), "{err}");
    }

    #[test]
    fn images_of_every_decoded_format_become_srgb_rgba8() {
        use gltf::image::{Data, Format};
        let img = |format, pixels: Vec<u8>| Data {
            pixels,
            format,
            width: 1,
            height: 1,
        };
        let cases = [
            (img(Format::R8, vec![7]), [7, 7, 7, 255]),
            (img(Format::R8G8, vec![7, 9]), [7, 7, 7, 9]),
            (img(Format::R8G8B8, vec![1, 2, 3]), [1, 2, 3, 255]),
            (img(Format::R8G8B8A8, vec![1, 2, 3, 4]), [1, 2, 3, 4]),
            (
                img(Format::R16, 65535u16.to_ne_bytes().to_vec()),
                [255, 255, 255, 255],
            ),
            (
                img(
                    Format::R16G16B16A16,
                    [0u16, 257, 32768, 65535]
                        .iter()
                        .flat_map(|v| v.to_ne_bytes())
                        .collect(),
                ),
                [0, 1, 128, 255],
            ),
            (
                img(
                    Format::R32G32B32FLOAT,
                    [0.5f32, -1.0, 2.0].iter().flat_map(|v| v.to_ne_bytes()).collect(),
                ),
                [128, 0, 255, 255],
            ),
            (
                img(
                    Format::R32G32B32A32FLOAT,
                    [f32::NAN, 1.0, 0.0, 0.25]
                        .iter()
                        .flat_map(|v| v.to_ne_bytes())
                        .collect(),
                ),
                [0, 255, 0, 64],
            ),
        ];
        for (data, texel) in cases {
            let format = data.format;
            let image = convert_image("t".into(), &data).unwrap_or_else(|e| panic!("{format:?}: {e}"));
            assert_eq!(image.texels, vec![texel], "{format:?}");
        }
        assert!(convert_image("t".into(), &img(Format::R8G8B8, vec![1, 2])).is_err());
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
}
