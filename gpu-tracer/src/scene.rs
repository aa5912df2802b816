//! Scenes: triangles with diffuse/emissive materials and a pinhole camera
//! ([`Scene`]), and their buffer form for the kernels ([`SceneGpu`]).
//!
//! A scene comes from the built-in Cornell box ([`crate::cornell`]) or an OBJ
//! file ([`crate::obj`]). [`SceneGpu::build`] validates it, builds the BVH,
//! reorders triangles into BVH leaf order and builds the emitter list for
//! next-event estimation. The CPU renderer and the GPU host upload exactly
//! these arrays.

use crate::bvh::build_bvh;
use crate::error::{Error, Result};
use glam::{UVec4, Vec4};
use glam::{Vec2, Vec3};
use kernels::abi::{
    BvhNodeGpu, EmitterGpu, MaterialGpu, TraceParams, TriangleAttrGpu, TriangleGpu, FILTER_BILINEAR,
    GBUFFER_NO_HIT, IMAGE_HEADER_WORDS, MAX_DEPTH_LIMIT, SAMPLER_JITTER_ONLY, SAMPLER_KIND_MASK,
    SAMPLER_SCREEN_SOBOL, SAMPLER_ZSOBOL, SEED_MODE_ADVANCE, TEXTURE_NONE, WRAP_CLAMP, WRAP_MIRROR,
    WRAP_REPEAT,
};
use kernels::trace::normal_and_area;

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
}

impl Triangle {
    /// A triangle of object 0 without texture coordinates.
    pub fn new(vertices: [Vec3; 3], material: u32) -> Self {
        Triangle {
            vertices,
            uvs: [Vec2::ZERO; 3],
            material,
            object: 0,
        }
    }
}

/// How a texture is sampled along one axis outside `[0, 1]` (glTF's
/// sampler wrap modes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Wrap {
    /// Tile (glTF `REPEAT`, the default).
    #[default]
    Repeat,
    /// Clamp to the edge texel (`CLAMP_TO_EDGE`).
    Clamp,
    /// Tile, mirrored every other repetition (`MIRRORED_REPEAT`).
    Mirror,
}

/// Texture filtering (glTF's magnification filter; mipmaps are not used).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Filter {
    /// The nearest texel.
    Nearest,
    /// Bilinear interpolation of the four nearest texels (after sRGB
    /// decoding), the glTF default.
    #[default]
    Bilinear,
}

/// An RGBA8 image in sRGB encoding (colour textures: glTF base colour and
/// emissive textures are sRGB).
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Name for messages (file name or glTF image name/index).
    pub name: String,
    /// Width in texels, `>= 1`.
    pub width: u32,
    /// Height in texels, `>= 1`.
    pub height: u32,
    /// `width * height` texels, row-major from the top row, `[r, g, b, a]`
    /// sRGB-encoded (alpha is ignored).
    pub texels: Vec<[u8; 4]>,
}

/// A texture: an image of [`Scene::images`] and how to sample it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TextureRef {
    /// Index into [`Scene::images`].
    pub image: u32,
    /// Wrap mode along `u`.
    pub wrap_u: Wrap,
    /// Wrap mode along `v`.
    pub wrap_v: Wrap,
    /// Filter.
    pub filter: Filter,
}

/// A Lambertian material with optional emission and textures.
///
/// Albedo at a surface point = `albedo * decode(base_color_texture(uv))`,
/// emitted radiance = `emission * decode(emission_texture(uv))` (sRGB
/// decoding per texel; the texture factor is 1 without a texture).
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Name (from the MTL or glTF file, or descriptive for built-in scenes).
    pub name: String,
    /// Diffuse albedo, linear RGB; each channel is clamped to `[0, 1]` when
    /// the GPU form is built.
    pub albedo: Vec3,
    /// Emitted radiance from the front side, linear RGB, `>= 0` (for glTF:
    /// emissive factor x `KHR_materials_emissive_strength`).
    pub emission: Vec3,
    /// Texture multiplying the albedo.
    pub base_color_texture: Option<TextureRef>,
    /// Texture multiplying the emission.
    pub emission_texture: Option<TextureRef>,
}

impl Material {
    /// An untextured material.
    pub fn new(name: impl Into<String>, albedo: Vec3, emission: Vec3) -> Self {
        Material {
            name: name.into(),
            albedo,
            emission,
            base_color_texture: None,
            emission_texture: None,
        }
    }
}

/// A pinhole camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position, world units.
    pub origin: Vec3,
    /// Point looked at (the image centre), `!= origin`.
    pub target: Vec3,
    /// Approximate up direction, not parallel to `target - origin`.
    pub up: Vec3,
    /// Vertical field of view in degrees, in `(0, 180)`.
    pub fov_y_degrees: f32,
}

/// The orthonormal basis of a [`Camera`]: the camera part of [`TraceParams`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraBasis {
    /// Eye position.
    pub origin: Vec3,
    /// Unit viewing direction.
    pub forward: Vec3,
    /// Unit vector to the image's right: `forward x up`, normalised.
    pub right: Vec3,
    /// Unit vector to the image's top: `right x forward`.
    pub up: Vec3,
    /// `tan(fov_y / 2)`.
    pub tan_half_fov_y: f32,
}

impl Camera {
    /// The camera's orthonormal basis.
    ///
    /// # Errors
    /// [`Error::InvalidCamera`] when a vector is non-finite, `target ==
    /// origin`, `up` is (nearly) parallel to the view direction, or the field
    /// of view is outside `(0, 180)` degrees.
    pub fn basis(&self) -> Result<CameraBasis> {
        let finite = self.origin.is_finite() && self.target.is_finite() && self.up.is_finite();
        let fov_ok = self.fov_y_degrees > 0.0 && self.fov_y_degrees < 180.0;
        let forward = (self.target - self.origin).normalize_or_zero();
        let right = forward.cross(self.up.normalize_or_zero());
        if !finite || !fov_ok || forward == Vec3::ZERO || right.length() < 1e-6 {
            return Err(Error::InvalidCamera);
        }
        let right = right.normalize();
        Ok(CameraBasis {
            origin: self.origin,
            forward,
            right,
            up: right.cross(forward),
            tan_half_fov_y: (self.fov_y_degrees.to_radians() * 0.5).tan(),
        })
    }

    /// A camera framing the box `[min, max]` from its `+z` side, looking
    /// along `-z` with `+y` up and a 40-degree vertical field of view, far
    /// enough that the box's bounding sphere fits the vertical field of view.
    /// Used for OBJ files, which carry no camera.
    pub fn framing(min: Vec3, max: Vec3) -> Camera {
        let centre = (min + max) * 0.5;
        let radius = ((max - min).length() * 0.5).max(1e-3);
        let fov_y_degrees = 40.0f32;
        let distance = radius / (fov_y_degrees.to_radians() * 0.5).sin();
        Camera {
            origin: centre + Vec3::Z * distance,
            target: centre,
            up: Vec3::Y,
            fov_y_degrees,
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

/// Settings of the trace pass that do not depend on the scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TraceSettings {
    /// Visible width in pixels, `>= 1`.
    pub width: u32,
    /// Visible height in pixels, `>= 1`.
    pub height: u32,
    /// Seed-buffer stride in seeds, `>= width` (the padded width of
    /// `sampler_core::FrameLayout`).
    pub padded_width: u32,
    /// Samples per pixel per frame, `>= 1`.
    pub spp: u32,
    /// Maximum path length in segments, `1..=MAX_DEPTH_LIMIT`.
    pub max_depth: u32,
    /// First path vertex subject to Russian roulette (see
    /// [`TraceParams::rr_depth`]).
    pub rr_depth: u32,
    /// [`kernels::abi::SEED_MODE_FIXED`] or [`SEED_MODE_ADVANCE`].
    pub seed_mode: u32,
    /// Source of the path's 2D decisions (jitter, light samples, BSDF
    /// directions): [`kernels::abi::SAMPLER_SEEDS`]
    /// (the seed stream), [`SAMPLER_SCREEN_SOBOL`] (at most
    /// [`screen_sobol_max_spp`] spp) or [`SAMPLER_ZSOBOL`] (at most
    /// [`ZSOBOL_MAX_SPP`] spp, width and height at most
    /// `sampler_core::zsobol::ZSOBOL_TILE`); either a-priori sampler may be
    /// ORed with [`SAMPLER_JITTER_ONLY`] (only the position inside the pixel
    /// from the sampler, the rest from the seeds: for the seed permutation).
    /// See [`TraceParams::sampler`].
    pub sampler: u32,
}

/// Largest spp per frame of [`SAMPLER_ZSOBOL`]: `2^ZSOBOL_MAX_LOG2_SPP` = 256.
pub const ZSOBOL_MAX_SPP: u32 = 1 << sampler_core::zsobol::ZSOBOL_MAX_LOG2_SPP;

/// Largest spp per frame of [`SAMPLER_SCREEN_SOBOL`] with the default keys
/// (`sampler_core::defaults::screen_sobol_keys()`): the spp its last key
/// level is optimised for, `2^(levels - 1)` (16).
pub fn screen_sobol_max_spp() -> u32 {
    1 << (sampler_core::defaults::screen_sobol_keys().layout().levels - 1)
}

impl TraceSettings {
    /// Settings for a `width x height` frame with an unpadded seed buffer,
    /// 1 spp, max depth 8, Russian roulette from vertex 3 and
    /// [`kernels::abi::SEED_MODE_FIXED`].
    pub fn new(width: u32, height: u32) -> Self {
        TraceSettings {
            width,
            height,
            padded_width: width,
            spp: 1,
            max_depth: 8,
            rr_depth: 3,
            seed_mode: kernels::abi::SEED_MODE_FIXED,
            sampler: kernels::abi::SAMPLER_SEEDS,
        }
    }
}

/// Largest material count: indices are stored as exact `f32` integers.
pub const MAX_MATERIALS: usize = 1 << 24;
/// Largest triangle count the `u32` indices of the kernels address
/// (node indices of a BVH2 reach twice the primitive count).
pub const MAX_TRIANGLES: usize = (u32::MAX / 2) as usize;

/// The buffers of a scene, ready to upload (or to hand to the CPU renderer).
#[derive(Clone, Debug, PartialEq)]
pub struct SceneGpu {
    /// BVH2 nodes, root at index 0.
    pub nodes: Vec<BvhNodeGpu>,
    /// Triangles in BVH leaf order.
    pub triangles: Vec<TriangleGpu>,
    /// Materials with albedo clamped to `[0, 1]`.
    pub materials: Vec<MaterialGpu>,
    /// Texture coordinates and ids, parallel to `triangles`.
    pub attrs: Vec<TriangleAttrGpu>,
    /// The images buffer (`kernels::abi::IMAGE_HEADER_WORDS`); one zero word
    /// for a scene without images (wgpu refuses empty buffers).
    pub images: Vec<u32>,
    /// Number of images in `images`.
    pub image_count: u32,
    /// The previous frame's vertex positions, parallel to `triangles`
    /// (`w` = 0): equal to the current ones until
    /// [`SceneGpu::set_previous_positions`] says otherwise.
    pub previous: Vec<TriangleGpu>,
    /// The previous frame's camera (motion vectors); the current one until
    /// [`SceneGpu::set_cameras`] says otherwise.
    pub prev_camera: CameraBasis,
    /// Emitter list; holds one [`EmitterGpu::NONE`] when the scene has no
    /// emitter (wgpu refuses empty buffers): use [`SceneGpu::emitter_count`].
    pub emitters: Vec<EmitterGpu>,
    /// Number of meaningful entries of `emitters`.
    pub emitter_count: u32,
    /// `original_index[i]` = index in [`Scene::triangles`] of `triangles[i]`.
    pub original_index: Vec<u32>,
    /// Depth of the deepest BVH leaf (root = 0).
    pub bvh_depth: usize,
    /// The camera's basis.
    pub camera: CameraBasis,
}

impl SceneGpu {
    /// Validates `scene` and builds its buffers: BVH (obvhs, medium
    /// preset), triangles reordered to leaf order with material index and
    /// emitter-selection probability in `w`, materials, and the emitter list
    /// (every front-emitting triangle with positive area and emission,
    /// picked with probability proportional to `area * mean(emission)`).
    ///
    /// # Errors
    /// [`Error::NoTriangles`] for an empty scene, [`Error::NonFiniteVertex`],
    /// [`Error::InvalidMaterial`], [`Error::MaterialIndex`],
    /// [`Error::SceneTooLarge`], [`Error::InvalidCamera`],
    /// [`Error::BvhTooDeep`].
    pub fn build(scene: &Scene) -> Result<SceneGpu> {
        if scene.triangles.is_empty() {
            return Err(Error::NoTriangles {
                path: "<scene>".into(),
            });
        }
        if scene.triangles.len() > MAX_TRIANGLES {
            return Err(Error::SceneTooLarge {
                what: "triangles",
                count: scene.triangles.len(),
                limit: MAX_TRIANGLES,
            });
        }
        if scene.materials.len() > MAX_MATERIALS {
            return Err(Error::SceneTooLarge {
                what: "materials",
                count: scene.materials.len(),
                limit: MAX_MATERIALS,
            });
        }
        let camera = scene.camera.basis()?;
        let mut materials = Vec::with_capacity(scene.materials.len());
        for m in &scene.materials {
            let ok = m.albedo.is_finite()
                && m.emission.is_finite()
                && m.albedo.min_element() >= 0.0
                && m.emission.min_element() >= 0.0;
            if !ok {
                return Err(Error::InvalidMaterial { name: m.name.clone() });
            }
            let texture = |t: &Option<TextureRef>| -> Result<(u32, u32)> {
                match t {
                    None => Ok((TEXTURE_NONE, 0)),
                    Some(t) if (t.image as usize) < scene.images.len() => Ok((t.image, sampler_flags(t))),
                    Some(t) => Err(Error::InvalidTexture {
                        material: m.name.clone(),
                        reason: format!("image {} of {}", t.image, scene.images.len()),
                    }),
                }
            };
            let (base, base_flags) = texture(&m.base_color_texture)?;
            let (emit, emit_flags) = texture(&m.emission_texture)?;
            materials.push(MaterialGpu {
                albedo: m.albedo.clamp(Vec3::ZERO, Vec3::ONE).extend(0.0),
                emission: m.emission.extend(0.0),
                textures: UVec4::new(base, base_flags, emit, emit_flags),
            });
        }
        let (images, image_count) = pack_images(&scene.images)?;
        for (i, t) in scene.triangles.iter().enumerate() {
            if t.object == GBUFFER_NO_HIT {
                return Err(Error::InvalidParameter {
                    name: "object id",
                    value: t.object,
                    expected: "below kernels::abi::GBUFFER_NO_HIT",
                });
            }
            check_triangle(i, &t.vertices, "<scene>")?;
            if t.material as usize >= materials.len() {
                return Err(Error::MaterialIndex {
                    triangle: i,
                    material: t.material,
                    count: materials.len(),
                });
            }
        }

        let g = build_geometry(&scene.triangles, &materials)?;
        let previous = g.triangles.iter().map(positions_only).collect();
        Ok(SceneGpu {
            nodes: g.nodes,
            triangles: g.triangles,
            materials,
            attrs: g.attrs,
            images,
            image_count,
            previous,
            prev_camera: camera,
            emitters: g.emitters,
            emitter_count: g.emitter_count,
            original_index: g.original_index,
            bvh_depth: g.bvh_depth,
            camera,
        })
    }

    /// Moves the scene's vertices to `positions` (given in the order of
    /// [`Scene::triangles`] of the scene this was built from), keeping
    /// materials, images, texture coordinates and ids: rebuilds the BVH, the
    /// leaf order and the emitter list (areas change). The previous
    /// positions become the new positions too: call
    /// [`SceneGpu::set_previous_positions`] afterwards for motion vectors.
    ///
    /// # Errors
    /// [`Error::BufferSize`] when `positions` does not have one entry per
    /// triangle, [`Error::NonFiniteVertex`], [`Error::BvhTooDeep`]; nothing
    /// changes then.
    pub fn set_positions(&mut self, positions: &[[Vec3; 3]]) -> Result<()> {
        if positions.len() != self.triangles.len() {
            return Err(Error::BufferSize {
                buffer: "positions",
                expected: self.triangles.len(),
                actual: positions.len(),
            });
        }
        check_positions(positions, "<positions>")?;
        let mut scene_order = vec![Triangle::new([Vec3::ZERO; 3], 0); positions.len()];
        for ((t, a), &orig) in self.triangles.iter().zip(&self.attrs).zip(&self.original_index) {
            let o = orig as usize;
            scene_order[o] = Triangle {
                vertices: positions[o],
                uvs: [
                    Vec2::new(a.uv01.x, a.uv01.y),
                    Vec2::new(a.uv01.z, a.uv01.w),
                    Vec2::new(a.uv2.x, a.uv2.y),
                ],
                material: t.v0.w as u32,
                object: a.ids.x,
            };
        }
        let g = build_geometry(&scene_order, &self.materials)?;
        self.previous = g.triangles.iter().map(positions_only).collect();
        self.nodes = g.nodes;
        self.triangles = g.triangles;
        self.attrs = g.attrs;
        self.emitters = g.emitters;
        self.emitter_count = g.emitter_count;
        self.original_index = g.original_index;
        self.bvh_depth = g.bvh_depth;
        Ok(())
    }
    /// The [`TraceParams`] of frame `frame` with these settings.
    ///
    /// # Errors
    /// [`Error::FrameSize`] for a zero size or `padded_width < width`;
    /// [`Error::InvalidParameter`] for `spp == 0`, `max_depth` outside
    /// `1..=MAX_DEPTH_LIMIT`, an unknown `seed_mode` or `sampler`, or a
    /// sampler that does not support the settings (spp above
    /// [`screen_sobol_max_spp`] for screen-space Sobol; spp above
    /// [`ZSOBOL_MAX_SPP`] or a side above 4096 for ZSobol).
    ///
    /// The key-layout fields are those of
    /// `sampler_core::defaults::screen_sobol_keys()`, the keys the CPU
    /// renderer and the GPU tracer use.
    pub fn trace_params(&self, settings: &TraceSettings, frame: u32) -> Result<TraceParams> {
        let s = settings;
        if s.width == 0 || s.height == 0 || s.padded_width < s.width {
            return Err(Error::FrameSize {
                width: s.width,
                height: s.height,
                padded_width: s.padded_width,
            });
        }
        if s.spp == 0 {
            return Err(Error::InvalidParameter {
                name: "spp",
                value: s.spp,
                expected: ">= 1",
            });
        }
        if s.max_depth == 0 || s.max_depth > MAX_DEPTH_LIMIT {
            return Err(Error::InvalidParameter {
                name: "max_depth",
                value: s.max_depth,
                expected: "1..=64 (kernels::abi::MAX_DEPTH_LIMIT)",
            });
        }
        if s.seed_mode > SEED_MODE_ADVANCE {
            return Err(Error::InvalidParameter {
                name: "seed_mode",
                value: s.seed_mode,
                expected: "0 (fixed) or 1 (advance by frame)",
            });
        }
        let zsobol_tile = sampler_core::zsobol::ZSOBOL_TILE;
        let kind = s.sampler & SAMPLER_KIND_MASK;
        let flags = s.sampler & !SAMPLER_KIND_MASK;
        let sampler_checks: [(&'static str, u32, bool, &'static str); 4] = [
            (
                "sampler",
                s.sampler,
                kind <= SAMPLER_ZSOBOL
                    && (flags == 0 || (flags == SAMPLER_JITTER_ONLY && kind != kernels::abi::SAMPLER_SEEDS)),
                "0 (seeds), 1 (screen-sobol) or 2 (zsobol), the last two optionally ORed with 256 (jitter only)",
            ),
            (
                "spp",
                s.spp,
                kind != SAMPLER_SCREEN_SOBOL || s.spp <= screen_sobol_max_spp(),
                "at most 16 with the screen-sobol sampler (its keys are optimised for 1, 2, 4, 8 and 16 spp)",
            ),
            (
                "spp",
                s.spp,
                kind != SAMPLER_ZSOBOL || s.spp <= ZSOBOL_MAX_SPP,
                "at most 256 with the zsobol sampler (its sample index is 32 bits)",
            ),
            (
                "width or height",
                s.width.max(s.height),
                kind != SAMPLER_ZSOBOL || s.width.max(s.height) <= zsobol_tile,
                "at most 4096 with the zsobol sampler (its pixel order repeats every 4096 pixels)",
            ),
        ];
        for (name, value, ok, expected) in sampler_checks {
            if !ok {
                return Err(Error::InvalidParameter {
                    name,
                    value,
                    expected,
                });
            }
        }
        let key_layout = sampler_core::defaults::screen_sobol_keys().layout();
        let c = &self.camera;
        Ok(TraceParams {
            width: s.width,
            height: s.height,
            padded_width: s.padded_width,
            spp: s.spp,
            max_depth: s.max_depth,
            frame,
            triangle_count: self.triangles.len() as u32,
            emitter_count: self.emitter_count,
            seed_mode: s.seed_mode,
            node_count: self.nodes.len() as u32,
            rr_depth: s.rr_depth,
            tan_half_fov_y: c.tan_half_fov_y,
            camera_origin: c.origin.extend(0.0),
            camera_forward: c.forward.extend(0.0),
            camera_right: c.right.extend(0.0),
            camera_up: c.up.extend(0.0),
            sampler: s.sampler,
            key_side_log2: key_layout.side_log2,
            key_pairs: key_layout.pairs,
            key_levels: key_layout.levels,
            prev_camera_origin: self.prev_camera.origin.extend(0.0),
            prev_camera_forward: self.prev_camera.forward.extend(0.0),
            prev_camera_right: self.prev_camera.right.extend(0.0),
            prev_camera_up: self.prev_camera.up.extend(0.0),
            prev_tan_half_fov_y: self.prev_camera.tan_half_fov_y,
            image_count: self.image_count,
            pad0: 0,
            pad1: 0,
        })
    }

    /// Sets this frame's camera and the previous frame's (for motion
    /// vectors; pass the same camera twice for a still one).
    ///
    /// # Errors
    /// [`Error::InvalidCamera`] when either is degenerate; nothing changes
    /// then.
    pub fn set_cameras(&mut self, current: &Camera, previous: &Camera) -> Result<()> {
        let (current, previous) = (current.basis()?, previous.basis()?);
        self.camera = current;
        self.prev_camera = previous;
        Ok(())
    }

    /// Sets the previous frame's vertex positions, given in the order of
    /// [`Scene::triangles`] (the scene this was built from): where each
    /// triangle was one frame ago, for the motion vectors of moving objects.
    ///
    /// # Errors
    /// [`Error::BufferSize`] when `previous` does not have one entry per
    /// triangle; [`Error::NonFiniteVertex`] for a NaN or infinite
    /// coordinate. Nothing changes then.
    pub fn set_previous_positions(&mut self, previous: &[[Vec3; 3]]) -> Result<()> {
        if previous.len() != self.triangles.len() {
            return Err(Error::BufferSize {
                buffer: "previous positions",
                expected: self.triangles.len(),
                actual: previous.len(),
            });
        }
        check_positions(previous, "<previous positions>")?;
        for (p, &orig) in self.previous.iter_mut().zip(&self.original_index) {
            let [a, b, c] = previous[orig as usize];
            *p = TriangleGpu {
                v0: a.extend(0.0),
                v1: b.extend(0.0),
                v2: c.extend(0.0),
            };
        }
        Ok(())
    }

    /// Total emitted power `sum(area * mean(emission))` over the emitter
    /// list, in radiance units x area (useful to compare scenes' brightness).
    pub fn emitted_power(&self) -> f32 {
        self.emitters[..self.emitter_count as usize]
            .iter()
            .map(|e| {
                let t = &self.triangles[e.triangle as usize];
                let m = &self.materials[t.v0.w as usize];
                e.area * (m.emission.x + m.emission.y + m.emission.z) / 3.0
            })
            .sum()
    }
}

/// The geometry part of a [`SceneGpu`]: BVH, leaf-ordered triangles and
/// attributes, emitter list.
struct Geometry {
    nodes: Vec<BvhNodeGpu>,
    triangles: Vec<TriangleGpu>,
    attrs: Vec<TriangleAttrGpu>,
    emitters: Vec<EmitterGpu>,
    emitter_count: u32,
    original_index: Vec<u32>,
    bvh_depth: usize,
}

/// Builds the BVH of `triangles_in` (validated), reorders them into leaf
/// order with their attributes, and builds the emitter list (every
/// front-emitting triangle with positive area and emission, picked with
/// probability proportional to `area * mean(emission)`).
fn build_geometry(triangles_in: &[Triangle], materials: &[MaterialGpu]) -> Result<Geometry> {
    let vertices: Vec<[Vec3; 3]> = triangles_in.iter().map(|t| t.vertices).collect();
    let bvh = build_bvh(&vertices)?;

    // Triangles in leaf order; emitters with power-proportional selection.
    let mut triangles = Vec::with_capacity(bvh.primitive_indices.len());
    let mut attrs = Vec::with_capacity(bvh.primitive_indices.len());
    let mut emitters = Vec::new();
    let mut total_power = 0.0f64;
    for (i, &orig) in bvh.primitive_indices.iter().enumerate() {
        let t = triangles_in[orig as usize];
        let [a, b, c] = t.vertices;
        triangles.push(TriangleGpu {
            v0: a.extend(t.material as f32),
            v1: b.extend(0.0),
            v2: c.extend(0.0),
        });
        attrs.push(TriangleAttrGpu {
            uv01: Vec4::new(t.uvs[0].x, t.uvs[0].y, t.uvs[1].x, t.uvs[1].y),
            uv2: Vec4::new(t.uvs[2].x, t.uvs[2].y, 0.0, 0.0),
            ids: UVec4::new(t.object, orig, 0, 0),
        });
        let emission = materials[t.material as usize].emission.truncate();
        let (_, area) = normal_and_area(a, b, c);
        let power = area as f64 * (emission.x as f64 + emission.y as f64 + emission.z as f64) / 3.0;
        if power > 0.0 {
            total_power += power;
            emitters.push(EmitterGpu {
                triangle: i as u32,
                cdf: total_power as f32, // normalised below
                pdf: power as f32,
                area,
            });
        }
    }
    let emitter_count = emitters.len() as u32;
    let mut running = 0.0f64;
    let n = emitters.len();
    for (k, e) in emitters.iter_mut().enumerate() {
        let p = e.pdf as f64 / total_power;
        running += p;
        e.pdf = p as f32;
        e.cdf = if k + 1 == n { 1.0 } else { running as f32 };
        triangles[e.triangle as usize].v1.w = e.pdf;
    }
    if emitters.is_empty() {
        emitters.push(EmitterGpu::NONE);
    }
    Ok(Geometry {
        nodes: bvh.nodes,
        triangles,
        attrs,
        emitters,
        emitter_count,
        original_index: bvh.primitive_indices,
        bvh_depth: bvh.depth,
    })
}

/// [`Error::NonFiniteVertex`] for the first triangle of `positions` with a
/// NaN or infinite coordinate.
fn check_positions(positions: &[[Vec3; 3]], path: &str) -> Result<()> {
    for (i, t) in positions.iter().enumerate() {
        check_triangle(i, t, path)?;
    }
    Ok(())
}

/// [`Error::NonFiniteVertex`] when a vertex of triangle `i` is NaN or
/// infinite.
fn check_triangle(i: usize, vertices: &[Vec3; 3], path: &str) -> Result<()> {
    match vertices.iter().position(|v| !v.is_finite()) {
        Some(vertex) => Err(Error::NonFiniteVertex {
            path: path.into(),
            model: format!("triangle {i}"),
            vertex,
        }),
        None => Ok(()),
    }
}

/// A triangle's positions with the `w` words cleared.
fn positions_only(t: &TriangleGpu) -> TriangleGpu {
    TriangleGpu {
        v0: t.v0.truncate().extend(0.0),
        v1: t.v1.truncate().extend(0.0),
        v2: t.v2.truncate().extend(0.0),
    }
}

/// The kernels' sampler flags of a texture (`kernels::abi::WRAP_REPEAT` ...).
fn sampler_flags(t: &TextureRef) -> u32 {
    let wrap = |w: Wrap| match w {
        Wrap::Repeat => WRAP_REPEAT,
        Wrap::Clamp => WRAP_CLAMP,
        Wrap::Mirror => WRAP_MIRROR,
    };
    let filter = match t.filter {
        Filter::Nearest => 0,
        Filter::Bilinear => FILTER_BILINEAR,
    };
    wrap(t.wrap_u) | wrap(t.wrap_v) << 2 | filter
}

/// Largest images buffer, in `u32` words: offsets are `u32`, and wgpu
/// binds at most 2^31 bytes on common adapters.
pub const MAX_IMAGE_WORDS: usize = 1 << 29;

/// The images buffer of `images` (`kernels::abi::IMAGE_HEADER_WORDS`) and
/// the image count.
fn pack_images(images: &[Image]) -> Result<(Vec<u32>, u32)> {
    let header = images.len() * IMAGE_HEADER_WORDS as usize;
    let texels: usize = images.iter().map(|i| i.texels.len()).sum();
    if header + texels > MAX_IMAGE_WORDS {
        return Err(Error::SceneTooLarge {
            what: "texels",
            count: header + texels,
            limit: MAX_IMAGE_WORDS,
        });
    }
    let mut out = vec![0u32; header];
    for (i, image) in images.iter().enumerate() {
        let expected = image.width as usize * image.height as usize;
        if image.width == 0 || image.height == 0 || image.texels.len() != expected {
            return Err(Error::InvalidImage {
                name: image.name.clone(),
                width: image.width,
                height: image.height,
                texels: image.texels.len(),
            });
        }
        let h = i * IMAGE_HEADER_WORDS as usize;
        out[h] = out.len() as u32;
        out[h + 1] = image.width;
        out[h + 2] = image.height;
        out.extend(image.texels.iter().map(|t| u32::from_le_bytes(*t)));
    }
    if out.is_empty() {
        out.push(0);
    }
    Ok((out, images.len() as u32))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

    fn quad_scene(emission: Vec3) -> Scene {
        let a = Vec3::new(0.0, 0.0, 0.0);
        let b = Vec3::new(1.0, 0.0, 0.0);
        let c = Vec3::new(1.0, 1.0, 0.0);
        let d = Vec3::new(0.0, 1.0, 0.0);
        let big = |p: Vec3| p * 3.0 + Vec3::new(-1.0, -1.0, -1.0);
        Scene {
            triangles: vec![
                Triangle::new([a, b, c], 1),
                Triangle::new([a, c, d], 1),
                Triangle::new([big(a), big(b), big(c)], 0),
            ],
            materials: vec![
                Material::new("grey", Vec3::new(0.5, 2.0, 0.5), Vec3::ZERO),
                Material::new("light", Vec3::ZERO, emission),
            ],
            images: Vec::new(),
            camera: Camera {
                origin: Vec3::new(0.5, 0.5, 3.0),
                target: Vec3::new(0.5, 0.5, 0.0),
                up: Vec3::Y,
                fov_y_degrees: 60.0,
            },
        }
    }

    #[test]
    fn emitter_list_and_leaf_order() {
        let scene = quad_scene(Vec3::new(3.0, 2.0, 1.0));
        let gpu = SceneGpu::build(&scene).expect("valid");
        assert_eq!(gpu.emitter_count, 2);
        assert_eq!(gpu.emitters.len(), 2);
        // Equal areas and emission: 1/2 each, cdf ends at exactly 1.
        assert!((gpu.emitters[0].pdf - 0.5).abs() < 1e-6);
        assert_eq!(gpu.emitters[1].cdf, 1.0);
        for e in &gpu.emitters {
            let t = gpu.triangles[e.triangle as usize];
            assert_eq!(t.v1.w, e.pdf);
            assert!((e.area - 0.5).abs() < 1e-6);
            assert_eq!(gpu.materials[t.v0.w as usize].emission.x, 3.0);
        }
        // Reordered triangles are a permutation of the input.
        let mut seen = gpu.original_index.clone();
        seen.sort_unstable();
        assert_eq!(seen, vec![0, 1, 2]);
        for (i, &o) in gpu.original_index.iter().enumerate() {
            assert_eq!(
                gpu.triangles[i].v0.truncate(),
                scene.triangles[o as usize].vertices[0]
            );
        }
        // Albedo clamped to [0, 1].
        assert_eq!(gpu.materials[0].albedo, Vec4::new(0.5, 1.0, 0.5, 0.0));
        assert!((gpu.emitted_power() - 2.0).abs() < 1e-5);
    }

    #[test]
    fn scene_without_emitters_gets_a_padding_entry() {
        let gpu = SceneGpu::build(&quad_scene(Vec3::ZERO)).expect("valid");
        assert_eq!(gpu.emitter_count, 0);
        assert_eq!(gpu.emitters, vec![EmitterGpu::NONE]);
        assert!(gpu.triangles.iter().all(|t| t.v1.w == 0.0));
    }

    #[test]
    fn invalid_scenes_are_errors() {
        let mut s = quad_scene(Vec3::ONE);
        s.triangles[1].material = 9;
        assert!(matches!(
            SceneGpu::build(&s),
            Err(Error::MaterialIndex {
                triangle: 1,
                material: 9,
                count: 2
            })
        ));
        let mut s = quad_scene(Vec3::ONE);
        s.triangles[2].vertices[1].y = f32::NAN;
        assert!(matches!(
            SceneGpu::build(&s),
            Err(Error::NonFiniteVertex { vertex: 1, .. })
        ));
        let mut s = quad_scene(Vec3::ONE);
        s.materials[0].emission.x = -1.0;
        assert!(matches!(SceneGpu::build(&s), Err(Error::InvalidMaterial { .. })));
        let mut s = quad_scene(Vec3::ONE);
        s.camera.up = Vec3::Z;
        assert!(matches!(SceneGpu::build(&s), Err(Error::InvalidCamera)));
        let mut s = quad_scene(Vec3::ONE);
        s.triangles.clear();
        assert!(matches!(SceneGpu::build(&s), Err(Error::NoTriangles { .. })));
    }

    #[test]
    fn trace_params_validation() {
        let gpu = SceneGpu::build(&quad_scene(Vec3::ONE)).expect("valid");
        let ok = TraceSettings::new(16, 8);
        let p = gpu.trace_params(&ok, 5).expect("valid");
        assert_eq!(
            (p.width, p.height, p.padded_width, p.frame, p.emitter_count),
            (16, 8, 16, 5, 2)
        );
        assert_eq!(p.node_count as usize, gpu.nodes.len());
        let bad = [
            TraceSettings { width: 0, ..ok },
            TraceSettings {
                padded_width: 15,
                ..ok
            },
            TraceSettings { spp: 0, ..ok },
            TraceSettings { max_depth: 0, ..ok },
            TraceSettings { max_depth: 65, ..ok },
            TraceSettings { seed_mode: 2, ..ok },
            TraceSettings { sampler: 3, ..ok },
            TraceSettings {
                sampler: SAMPLER_JITTER_ONLY,
                ..ok
            },
            TraceSettings {
                sampler: SAMPLER_ZSOBOL | 1 << 9,
                ..ok
            },
            TraceSettings {
                sampler: SAMPLER_SCREEN_SOBOL,
                spp: 17,
                ..ok
            },
            TraceSettings {
                sampler: SAMPLER_SCREEN_SOBOL | SAMPLER_JITTER_ONLY,
                spp: 17,
                ..ok
            },
            TraceSettings {
                sampler: SAMPLER_ZSOBOL,
                spp: 257,
                ..ok
            },
            TraceSettings {
                sampler: SAMPLER_ZSOBOL | SAMPLER_JITTER_ONLY,
                width: 4097,
                padded_width: 4097,
                ..ok
            },
            TraceSettings {
                sampler: SAMPLER_ZSOBOL,
                width: 4097,
                padded_width: 4097,
                ..ok
            },
        ];
        for s in bad {
            assert!(gpu.trace_params(&s, 0).is_err(), "{s:?}");
        }
        for (sampler, spp) in [
            (SAMPLER_SCREEN_SOBOL, 16),
            (SAMPLER_ZSOBOL, 256),
            (SAMPLER_SCREEN_SOBOL | SAMPLER_JITTER_ONLY, 16),
            (SAMPLER_ZSOBOL | SAMPLER_JITTER_ONLY, 256),
        ] {
            let p = gpu
                .trace_params(&TraceSettings { sampler, spp, ..ok }, 0)
                .expect("supported");
            let layout = sampler_core::defaults::screen_sobol_keys().layout();
            assert_eq!(
                (p.sampler, p.key_side_log2, p.key_pairs, p.key_levels),
                (sampler, layout.side_log2, layout.pairs, layout.levels)
            );
        }
    }

    #[test]
    fn camera_basis_and_framing() {
        let b = Camera {
            origin: Vec3::new(278.0, 273.0, -800.0),
            target: Vec3::new(278.0, 273.0, 0.0),
            up: Vec3::Y,
            fov_y_degrees: 90.0,
        }
        .basis()
        .expect("valid");
        assert_eq!(b.forward, Vec3::Z);
        assert_eq!(b.right, -Vec3::X);
        assert_eq!(b.up, Vec3::Y);
        assert!((b.tan_half_fov_y - 1.0).abs() < 1e-6);
        let cam = Camera::framing(Vec3::splat(-1.0), Vec3::splat(1.0));
        assert!(cam.basis().is_ok());
        assert!(cam.origin.z > 1.0 && cam.target == Vec3::ZERO);
        let bad = Camera {
            fov_y_degrees: 180.0,
            ..cam
        };
        assert!(bad.basis().is_err());
    }

    #[test]
    fn set_positions_rebuilds_the_geometry_and_keeps_the_attributes() {
        let mut scene = quad_scene(Vec3::ONE);
        scene.triangles[2].object = 5;
        scene.triangles[2].uvs = [Vec2::new(0.1, 0.2), Vec2::new(0.3, 0.4), Vec2::new(0.5, 0.6)];
        let mut gpu = SceneGpu::build(&scene).expect("valid");
        let moved: Vec<[Vec3; 3]> = scene
            .triangles
            .iter()
            .map(|t| t.vertices.map(|v| v + Vec3::new(0.0, 2.0, 0.0)))
            .collect();
        gpu.set_positions(&moved).expect("valid");
        let mut want = scene.clone();
        for (t, m) in want.triangles.iter_mut().zip(&moved) {
            t.vertices = *m;
        }
        let rebuilt = SceneGpu::build(&want).expect("valid");
        assert_eq!(gpu.triangles, rebuilt.triangles);
        assert_eq!(gpu.attrs, rebuilt.attrs);
        assert_eq!(gpu.nodes, rebuilt.nodes);
        assert_eq!(gpu.emitters, rebuilt.emitters);
        // Previous positions: the new ones until set, then the given ones.
        assert_eq!(gpu.previous[0].v0.truncate(), gpu.triangles[0].v0.truncate());
        let before: Vec<[Vec3; 3]> = scene.triangles.iter().map(|t| t.vertices).collect();
        gpu.set_previous_positions(&before).expect("valid");
        for (p, &o) in gpu.previous.iter().zip(&gpu.original_index) {
            assert_eq!(p.v1.truncate(), before[o as usize][1]);
        }
        assert!(matches!(
            gpu.set_positions(&moved[..2]),
            Err(Error::BufferSize {
                expected: 3,
                actual: 2,
                ..
            })
        ));
        let mut nan = moved.clone();
        nan[1][2].z = f32::NAN;
        assert!(matches!(
            gpu.set_positions(&nan),
            Err(Error::NonFiniteVertex { .. })
        ));
        assert!(matches!(
            gpu.set_previous_positions(&nan),
            Err(Error::NonFiniteVertex { .. })
        ));
    }

    #[test]
    fn textures_are_packed_and_validated() {
        let mut scene = quad_scene(Vec3::ONE);
        scene.images = vec![
            Image {
                name: "a".into(),
                width: 2,
                height: 1,
                texels: vec![[1, 2, 3, 4], [5, 6, 7, 8]],
            },
            Image {
                name: "b".into(),
                width: 1,
                height: 1,
                texels: vec![[9, 9, 9, 9]],
            },
        ];
        scene.materials[0].base_color_texture = Some(TextureRef {
            image: 1,
            wrap_u: Wrap::Clamp,
            wrap_v: Wrap::Mirror,
            filter: Filter::Bilinear,
        });
        let gpu = SceneGpu::build(&scene).expect("valid");
        assert_eq!(gpu.image_count, 2);
        assert_eq!(&gpu.images[..8], &[8, 2, 1, 0, 10, 1, 1, 0]);
        assert_eq!(gpu.images[8], 0x0403_0201);
        assert_eq!(gpu.images[10], 0x0909_0909);
        let m = gpu.materials[0].textures;
        assert_eq!(
            (m.x, m.y, m.z),
            (1, WRAP_CLAMP | WRAP_MIRROR << 2 | FILTER_BILINEAR, TEXTURE_NONE)
        );
        let mut bad = scene.clone();
        bad.materials[1].emission_texture = bad.materials[0]
            .base_color_texture
            .map(|t| TextureRef { image: 2, ..t });
        assert!(matches!(SceneGpu::build(&bad), Err(Error::InvalidTexture { .. })));
        let mut bad = scene.clone();
        bad.images[0].texels.pop();
        assert!(matches!(SceneGpu::build(&bad), Err(Error::InvalidImage { .. })));
    }
}
