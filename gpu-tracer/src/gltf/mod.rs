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
//!   are an error. Positions are `VEC3` floats, or 8/16-bit integers
//!   (normalised or not) in files that declare `KHR_mesh_quantization`
//!   (the dequantising scale and offset live in the node transforms, as
//!   the extension intends). A mirroring node
//!   transform (negative determinant) swaps two vertices of each triangle
//!   so that the front side (counter-clockwise, the emitting side) stays the
//!   authored one. Each (node, mesh) pair is one object
//!   ([`Triangle::object`]), numbered in scene traversal order (depth first,
//!   children in file order).
//! - **Materials**: base colour factor (rgb) is the albedo, the base colour
//!   texture multiplies it; emissive factor times
//!   `KHR_materials_emissive_strength` is the emission, the emissive texture
//!   multiplies it. Textures keep their sampler's wrap modes and
//!   magnification filter (`NEAREST` -> [`Filter::Nearest`], `LINEAR` or
//!   none -> [`Filter::Bilinear`]; the minification filter is the tracer's
//!   own: mip maps built at load, trilinear over the pixel's footprint at a
//!   camera ray's first hit, `kernels::texture_filter`) and read the `TEXCOORD_n` set the
//!   material names (float or normalised unsigned 8/16-bit; with
//!   `KHR_mesh_quantization` also signed and not-normalised 8/16-bit
//!   integers: the `attribute` module's table). Reflection is the
//!   specification's metallic-roughness BRDF with its factors (defaults
//!   metallic 1, roughness 1) and `metallicRoughnessTexture` (blue metallic,
//!   green roughness, linear), or Lambertian for a non-metal with
//!   `KHR_materials_specular` `specularFactor` 0 (the `material` module's
//!   docs). `KHR_texture_transform` (offset, rotation, scale, `texCoord`
//!   override) applies to each of the three textures on its own: the
//!   transform travels with the texture to the kernels
//!   (`kernels::abi::UvTransformGpu`), nothing is baked into the vertices,
//!   so textures of one material may use different transforms (they must
//!   still read one `TEXCOORD_n` set). `alphaMode` `MASK` cuts holes where
//!   the base colour alpha (factor times texture alpha) is below
//!   `alphaCutoff` (default 0.5; negative or infinite cutoffs are an error):
//!   camera, bounce and shadow rays pass through them
//!   ([`Alpha::Mask`](crate::scene::Alpha::Mask)); `BLEND` is rendered
//!   opaque with a notice. `normalTexture` (its `scale`, sampler,
//!   `texCoord` and `KHR_texture_transform`, read as linear data) tilts the
//!   shading normal ([`NormalTexture`](crate::scene::NormalTexture),
//!   `kernels::normal_map`): the texel is a normal in a flat per-triangle
//!   tangent frame, from the primitive's `TANGENT` attribute when it has one
//!   (the three corners' mean, `w` the bitangent sign, flipped by mirroring
//!   node transforms) and from the texture coordinates otherwise
//!   (`scene::tangent`), built around the smooth normal where there is
//!   one. The G-buffer's normal stays the geometric one.
//! - **Vertex normals**: `NORMAL` (float, or with `KHR_mesh_quantization`
//!   normalised 8/16-bit integers) makes smooth shading
//!   ([`Triangle::normals`], `kernels::vertex_normal`): carried to world
//!   space by the inverse transpose of the node transform (and by
//!   [`Rig::pose`] for animated nodes). A triangle with a NaN, infinite or
//!   zero-length normal shades flat, with a notice counting them;
//!   primitives without `NORMAL` shade flat (the specification's "flat
//!   normals").
//!   Occlusion maps are ignored with a notice. A
//!   primitive without material gets glTF's default material: base colour
//!   1, metallic 1, roughness 1, no emission.
//! - **Images**: whatever the `gltf` crate decodes (PNG, JPEG), converted to
//!   8-bit RGBA (sRGB colour, or linear data for the metallic-roughness
//!   texture): grey (`R8`) and grey-alpha (`R8G8`) images are
//!   expanded, 16-bit channels are rounded to 8 bits, float channels are
//!   taken as already-encoded values in `[0, 1]` and clamped.
//! - **Lights**: `KHR_lights_punctual` point, spot and directional lights
//!   on the scene's nodes ([`Light`](crate::scene::Light)), in the
//!   extension's units (candela, lux) with its range window and spot
//!   falloff, placed by the nodes' rest transforms (animation does not move
//!   them, with a notice); lit by next-event estimation.
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
//! Extensions other than `KHR_materials_emissive_strength`,
//! `KHR_materials_specular` (its `specularFactor` 0 only),
//! `KHR_lights_punctual`, `KHR_mesh_quantization` and
//! `KHR_texture_transform` are ignored with a notice when merely used (for
//! example `KHR_materials_transmission`) and rejected by the `gltf` crate
//! when required (for example `KHR_texture_basisu`).
//!
//! [`Filter::Nearest`]: crate::scene::Filter::Nearest
//! [`Filter::Bilinear`]: crate::scene::Filter::Bilinear
//!
//! # Where each part is read
//!
//! [`load_gltf`] opens the file with `loader` and assembles the scene here
//! from what the other parts read:
//! - `loader`: the file, its document and buffers, with the checks the
//!   `gltf` crate needs before it indexes anything (GLB header, raw JSON,
//!   buffer views, URIs, accessors);
//! - `nodes`: the scene's node hierarchy and rest transforms;
//! - `mesh`: the triangles of each mesh primitive;
//! - `attribute`: vertex attributes of every component type (floats and
//!   `KHR_mesh_quantization`'s integers) as `f32`;
//! - `material`: materials, texture references and image conversion;
//! - `camera`: the chosen camera node;
//! - `animation`: the animation channels;
//! - `tests`: tests of the whole loader on the fixtures;
//! - `extension_tests`: texture transforms and alpha cut-outs on patched
//!   fixtures;
//! - `normal_map_tests`: normal textures and tangents on patched fixtures,
//!   rendered under a directional light;
//! - `smooth_normal_tests`: `NORMAL` (float, quantised, bad values) on the
//!   smooth sphere, rendered smooth and flat.

mod animation;
mod attribute;
mod camera;
#[cfg(test)]
mod extension_tests;
mod lights;
mod loader;
mod material;
mod mesh;
mod nodes;
#[cfg(test)]
mod normal_map_tests;
#[cfg(test)]
mod smooth_normal_tests;
#[cfg(test)]
mod tests;

pub use material::DEFAULT_ALBEDO;

use crate::animation::{camera_from_matrix, normal_matrix, MeshInstance, Node, Rig};
use crate::error::Result;
use crate::scene::usable_normals;
use crate::scene::{Camera, Material, Scene, Triangle};
use glam::Vec3;
use loader::{label, Loader};
use mesh::PrimitiveTriangle;
use std::path::Path;

/// The extensions whose content is used; others are noticed and ignored.
const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_materials_emissive_strength",
    "KHR_materials_specular",
    "KHR_lights_punctual",
    "KHR_texture_transform",
    loader::MESH_QUANTIZATION,
];

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
    /// occlusion maps, morph targets, ...), for the user.
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
///   buffer, or with NaN/infinite texture coordinates or tangents, a vertex
///   index out of range, a `POINTS`/`LINE*` primitive, a textured material
///   on a primitive without the texture coordinates it names (or textures
///   of one material naming different sets), an invalid material colour or
///   image, a non-finite `normalTexture` scale or a malformed
///   `KHR_texture_transform` on it, a camera index out of range (the message says how many camera nodes
///   there are), an orthographic or degenerate camera, invalid animation
///   data (times not finite and strictly increasing, values not finite, the
///   wrong number of values).
///
/// [`Error::GltfLoad`]: crate::Error::GltfLoad
/// [`Error::NonFiniteVertex`]: crate::Error::NonFiniteVertex
/// [`Error::GltfContent`]: crate::Error::GltfContent
pub fn load_gltf(path: impl AsRef<Path>, camera_index: Option<usize>) -> Result<GltfScene> {
    Loader::open(path.as_ref())?.load(camera_index)
}

impl<'p> Loader<'p> {
    /// Reads the scene's nodes, meshes, materials, images, camera and
    /// animation, and assembles them into a [`GltfScene`].
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
            let metal_rough = match &mut m.bsdf {
                crate::scene::Bsdf::MetallicRoughness { texture, .. } => texture.as_mut(),
                crate::scene::Bsdf::Lambert => None,
            };
            for t in [
                m.base_color_texture.as_mut(),
                m.emission_texture.as_mut(),
                metal_rough,
                m.normal_texture.as_mut().map(|n| &mut n.texture),
            ]
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
        let mut flat_normals = 0usize;
        for (rig_node, (node, _)) in order.iter().enumerate() {
            let Some(mesh) = node.mesh() else { continue };
            skinned |= node.skin().is_some();
            let world = rest_world[rig_node];
            let normal_matrix = normal_matrix(&world);
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
                let normal_mapped = primitive
                    .material()
                    .index()
                    .is_some_and(|i| materials[i].normal_texture.is_some());
                let prim = self.primitive(&primitive, &element, set, normal_mapped)?;
                for PrimitiveTriangle {
                    corners,
                    uvs,
                    tangents,
                    normals,
                } in prim
                {
                    let mut local = corners;
                    let mut uvs = uvs;
                    let mut local_normals = normals.map(|n| usable_normals(n).ok_or(n));
                    if world.determinant() < 0.0 {
                        local.swap(1, 2);
                        uvs.swap(1, 2);
                        if let Some(Ok(n)) = &mut local_normals {
                            n.swap(1, 2);
                        }
                    }
                    let local_normals = match local_normals {
                        Some(Ok(n)) => Some(n),
                        Some(Err(_)) => {
                            flat_normals += 1;
                            None
                        }
                        None => None,
                    };
                    let normals = local_normals.map(|n| n.map(|n| normal_matrix * n));
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
                    // One flat tangent per triangle: the corners' mean in
                    // world space; a mirroring transform flips handedness.
                    let tangent = tangents.map(|t| {
                        let sum = t[0] + t[1] + t[2];
                        let mirror = world.determinant() < 0.0;
                        let sign = if (sum.w < 0.0) != mirror { -1.0 } else { 1.0 };
                        world.transform_vector3(sum.truncate()).extend(sign)
                    });
                    rig.local.push(local);
                    rig.local_normals.push(local_normals.unwrap_or([Vec3::ZERO; 3]));
                    triangles.push(Triangle {
                        vertices,
                        uvs,
                        material,
                        object,
                        tangent,
                        normals,
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
            materials.push(Material::metallic_roughness("default", DEFAULT_ALBEDO, 1.0, 1.0));
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
        if flat_normals > 0 {
            self.notices.push(format!(
                "{flat_normals} triangles have a NaN, infinite or zero-length NORMAL: they are shaded flat"
            ));
        }

        let lights = self.lights(&order, &rest_world)?;
        rig.camera = self.camera(&order, camera_index)?;
        rig.channels = self.channels(&rig_index)?;
        if !lights.is_empty() && !rig.channels.is_empty() {
            self.notices.push(
                "lights stay at their rest pose: animation moves the meshes and the camera only".into(),
            );
        }

        let mut scene = Scene {
            lights,
            environment_map: None,
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
}
