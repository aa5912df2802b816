//! Scenes: triangles with Lambertian or metallic-roughness, possibly
//! emissive materials, punctual lights and a pinhole camera
//! ([`Scene`]), and their buffer form for the kernels ([`SceneGpu`]).
//!
//! A scene comes from the built-in Cornell box ([`crate::cornell`]), an OBJ
//! file ([`crate::obj`]) or a glTF file ([`crate::gltf`]).
//! [`SceneGpu::build`] validates it, builds the BVH ([`crate::bvh`]),
//! reorders triangles into BVH leaf order and builds the emitter list for
//! next-event estimation. The CPU renderer and the GPU host upload exactly
//! these arrays; [`SceneGpu::trace_params`] adds the frame's
//! [`TraceSettings`].
//!
//! - this file: [`Scene`] and its [`Triangle`]s;
//! - `camera`: [`Camera`] and its [`CameraBasis`];
//! - `light`: punctual [`Light`]s ([`LightKind`]: point, spot, directional);
//! - `environment`: [`EnvironmentMap`]s (equirectangular sky images);
//! - `emitters`: the emitter list for next-event estimation (emissive
//!   triangles and lights, picked by power);
//! - `material`: [`Material`], its reflectance model ([`Bsdf`]), its [`TextureRef`]s ([`Wrap`], [`Filter`]), its [`NormalTexture`]
//!   and the [`Image`]s they name;
//! - `buffers`: [`SceneGpu`], the buffers the kernels read, and the limits
//!   on their sizes;
//! - `queries`: ray queries against a built scene (closest hit, occlusion);
//! - `image_pack`: the images buffer (headers, texels, mip levels);
//! - `mips`: the images' mip chains (for footprint-filtered lookups);
//! - `settings`: [`TraceSettings`], the per-frame settings of the trace
//!   pass, and [`SceneGpu::trace_params`];
//! - `tangent`: each triangle's tangent for normal maps in the kernels'
//!   form (edge coefficients, `kernels::abi::TriangleAttrGpu::tangent`),
//!   from [`Triangle::tangent`] or the texture coordinates;
//! - `vertex_normals`: each triangle's vertex normals in the kernels' form
//!   (`kernels::abi::TriangleAttrGpu::normal0` ...), from
//!   [`Triangle::normals`].

mod buffers;
mod camera;
mod emitters;
mod environment;
mod image_pack;
mod light;
mod material;
mod mips;
mod queries;
mod settings;
mod tangent;
mod trace_variant;
mod vertex_normals;

pub use buffers::{SceneGpu, MAX_MATERIALS, MAX_TRIANGLES};
pub use camera::{Camera, CameraBasis};
pub use environment::EnvironmentMap;
pub use image_pack::MAX_IMAGE_WORDS;
pub use light::{Light, LightKind};
pub use material::{Alpha, Bsdf, Filter, Image, Material, NormalTexture, TextureRef, UvTransform, Wrap};
pub(crate) use settings::check_glossy_regularization;
pub use settings::{sampler_origin_of_salt, screen_sobol_max_spp, TraceSettings, ZSOBOL_MAX_SPP};
pub use trace_variant::TraceVariant;
pub use vertex_normals::{usable_normals, MIN_NORMAL_LENGTH};

use glam::{Vec2, Vec3};

/// A triangle with its material. The front side (the only one that emits)
/// is the one the right-hand normal `(v1 - v0) x (v2 - v0)` points to, i.e.
/// vertices are counter-clockwise seen from the front (the OBJ and glTF
/// convention).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    /// Vertices in world units.
    pub vertices: [Vec3; 3],
    /// Texture coordinates of the vertices (glTF convention: `(0, 0)` is the
    /// top-left texel of an image, `v` grows downwards); zero where the
    /// scene has none. Read only when the material has a texture.
    pub uvs: [Vec2; 3],
    /// Index into [`Scene::materials`].
    pub material: u32,
    /// Object id reported by the G-buffer: the same for every triangle of
    /// one object (a glTF mesh instance, an OBJ model, a Cornell-box wall or
    /// block); any value below [`kernels::abi::GBUFFER_NO_HIT`].
    pub object: u32,
    /// Tangent for normal maps, in world space: `xyz` = the direction of
    /// increasing `u` (any length; only its part in the triangle's plane
    /// counts), `w` = bitangent sign (glTF `TANGENT.w`, `-1` or `+1`:
    /// bitangent = `w * (normal x tangent)`), as the file's `TANGENT`
    /// attribute gives it. `None`: derived from [`Triangle::uvs`] (the
    /// `tangent` module). Read only when the material has a normal map.
    pub tangent: Option<glam::Vec4>,
    /// Vertex normals for smooth shading, in world space (the file's
    /// `NORMAL` / `vn` through the node's inverse-transpose transform),
    /// parallel to [`Triangle::vertices`]; any length (the scene buffers
    /// normalise them). `None`: flat shading with the geometric normal. A
    /// triangle whose normals include a NaN, infinite or zero-length one
    /// shades flat too ([`SceneGpu::build`]). The kernels blend them at the
    /// hit and keep the geometric normal for offsets, emission and light
    /// cosines (`kernels::vertex_normal`).
    pub normals: Option<[Vec3; 3]>,
}

impl Triangle {
    /// A triangle of object 0 without texture coordinates.
    pub fn new(vertices: [Vec3; 3], material: u32) -> Self {
        Triangle {
            vertices,
            uvs: [Vec2::ZERO; 3],
            material,
            object: 0,
            tangent: None,
            normals: None,
        }
    }
}

/// A scene: triangles, materials, images and a camera.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// All triangles; at least one for a renderable scene.
    pub triangles: Vec<Triangle>,
    /// Materials indexed by [`Triangle::material`].
    pub materials: Vec<Material>,
    /// Images indexed by [`TextureRef::image`].
    pub images: Vec<Image>,
    /// Punctual lights (point, spot, directional), besides the emissive
    /// triangles; empty for most OBJ scenes.
    pub lights: Vec<Light>,
    /// What rays that leave the scene see, when it is an image: an
    /// importance-sampled environment map. `None`: the constant
    /// `TraceSettings::environment` (black by default).
    pub environment_map: Option<EnvironmentMap>,
    /// The viewpoint.
    pub camera: Camera,
}

impl Scene {
    /// Axis-aligned bounds `(min, max)` of all vertices; `(+inf, -inf)` for
    /// an empty scene.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.triangles.iter().flat_map(|t| t.vertices).fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), v| (lo.min(v), hi.max(v)),
        )
    }
}
