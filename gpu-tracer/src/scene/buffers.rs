//! The buffers of a scene for the kernels ([`SceneGpu`]): BVH, triangles in
//! leaf order with their attributes, materials, images and the emitter list.

use super::emitters::{emitter_list, environment_power, scene_radius};
use super::image_pack::pack_images;
use super::tangent::tangent_gpu;
use super::vertex_normals::normals_gpu;
use super::{Alpha, Bsdf, Camera, CameraBasis, Filter, Light, Scene, TextureRef, Triangle, Wrap};
use crate::bvh::build_bvh;
use crate::error::{Error, Result};
use glam::{UVec4, Vec4};
use glam::{Vec2, Vec3};
use kernels::abi::{
    BvhNodeGpu, EmitterGpu, MaterialGpu, TriangleAttrGpu, TriangleGpu, UvTransformGpu, CUT_OUT,
    EMITTER_TRIANGLE, FILTER_BILINEAR, GBUFFER_NO_HIT, MODEL_LAMBERT, MODEL_METALLIC_ROUGHNESS, TEXEL_LINEAR,
    TEXTURE_NONE, UV_TRANSFORM, WRAP_CLAMP, WRAP_MIRROR, WRAP_REPEAT,
};

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
    /// Texture coordinates, ids, tangents and vertex normals, parallel to
    /// `triangles`.
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
    /// The scene's punctual lights (validated), kept to rebuild the emitter
    /// list when the geometry moves ([`SceneGpu::set_positions`]).
    pub lights: Vec<Light>,
    /// The environment map's buffer for binding 10 (sampling table, then
    /// texels: `kernels::environment::environment_texel`); one zero when the
    /// scene has none (wgpu refuses empty buffers).
    pub environment: Vec<f32>,
    /// The environment map's size and rotation; `width` 0 when there is none.
    pub environment_map: sampler_core::EnvironmentParams,
    /// The map's mean radiance over directions
    /// ([`EnvironmentMap::mean_radiance`](super::EnvironmentMap::mean_radiance)),
    /// its selection power in the emitter list; 0 without a map.
    pub environment_mean: f64,
    /// `original_index[i]` = index in [`Scene::triangles`] of `triangles[i]`.
    pub original_index: Vec<u32>,
    /// Depth of the deepest BVH leaf (root = 0).
    pub bvh_depth: usize,
    /// The camera's basis.
    pub camera: CameraBasis,
}

impl SceneGpu {
    /// Validates `scene` and builds its buffers: BVH (obvhs, medium
    /// preset), triangles reordered to leaf order with material index,
    /// emitter-selection probability and cut-out flag in `w`, materials, and
    /// the emitter list (every front-emitting triangle with positive area
    /// and emission and an opaque material, then every light and the
    /// environment map, picked with probability proportional to power: the
    /// `emitters` module).
    ///
    /// # Errors
    /// [`Error::NoTriangles`] for an empty scene, [`Error::NonFiniteVertex`],
    /// [`Error::InvalidMaterial`], [`Error::InvalidMaterialParameter`]
    /// (metallic, roughness or alpha factor NaN or outside `[0, 1]`, alpha
    /// cutoff NaN, infinite or negative), [`Error::InvalidTexture`] (an image
    /// index out of range, a non-finite texture transform), [`Error::MaterialIndex`],
    /// [`Error::SceneTooLarge`], [`Error::InvalidCamera`],
    /// [`Error::InvalidLight`], [`Error::InvalidEnvironmentMap`],
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
        for light in &scene.lights {
            light.validate()?;
        }
        let (environment, environment_map, environment_mean) = match &scene.environment_map {
            Some(map) => {
                map.validate()?;
                let (data, params) = map.buffer()?;
                (data, params, map.mean_radiance())
            }
            None => (vec![0.0], sampler_core::EnvironmentParams::default(), 0.0),
        };
        let mut materials = Vec::with_capacity(scene.materials.len());
        for m in &scene.materials {
            let ok = m.albedo.is_finite()
                && m.emission.is_finite()
                && m.albedo.min_element() >= 0.0
                && m.emission.min_element() >= 0.0;
            if !ok {
                return Err(Error::InvalidMaterial { name: m.name.clone() });
            }
            // (image, sampler flags, coordinate transform) of a texture.
            let texture = |t: &Option<TextureRef>| -> Result<(u32, u32, UvTransformGpu)> {
                match t {
                    None => Ok((TEXTURE_NONE, 0, UvTransformGpu::IDENTITY)),
                    Some(t) if (t.image as usize) >= scene.images.len() => Err(Error::InvalidTexture {
                        material: m.name.clone(),
                        reason: format!("image {} of {}", t.image, scene.images.len()),
                    }),
                    Some(t) => match t.transform {
                        None => Ok((t.image, sampler_flags(t), UvTransformGpu::IDENTITY)),
                        Some(x) if x.rows.iter().flatten().all(|v| v.is_finite()) => {
                            let [a, b] = x.rows;
                            let row = |r: [f32; 3]| Vec3::from(r).extend(0.0);
                            let gpu = UvTransformGpu { u: row(a), v: row(b) };
                            Ok((t.image, sampler_flags(t) | UV_TRANSFORM, gpu))
                        }
                        Some(x) => Err(Error::InvalidTexture {
                            material: m.name.clone(),
                            reason: format!("texture transform {:?} is not finite", x.rows),
                        }),
                    },
                }
            };
            let (base, base_flags, base_color_uv) = texture(&m.base_color_texture)?;
            let (emit, emit_flags, emission_uv) = texture(&m.emission_texture)?;
            let mut metal_rough_uv = UvTransformGpu::IDENTITY;
            let (mut pbr, model) = match m.bsdf {
                Bsdf::Lambert => (Vec4::ZERO, UVec4::new(MODEL_LAMBERT, TEXTURE_NONE, 0, 0)),
                Bsdf::MetallicRoughness {
                    metallic,
                    roughness,
                    texture: t,
                } => {
                    for (parameter, value) in [("metallic", metallic), ("roughness", roughness)] {
                        if !(0.0..=1.0).contains(&value) {
                            return Err(Error::InvalidMaterialParameter {
                                name: m.name.clone(),
                                parameter,
                                value,
                                expected: "a number in [0, 1]",
                            });
                        }
                    }
                    let (image, flags, uv) = texture(&t)?;
                    metal_rough_uv = uv;
                    (
                        Vec4::new(metallic, roughness, 0.0, 0.0),
                        UVec4::new(MODEL_METALLIC_ROUGHNESS, image, flags, 0),
                    )
                }
            };
            let (normal, normal_uv, normal_scale) = match m.normal_texture {
                None => (UVec4::new(TEXTURE_NONE, 0, 0, 0), UvTransformGpu::IDENTITY, 0.0),
                Some(n) if !n.scale.is_finite() => {
                    return Err(Error::InvalidMaterialParameter {
                        name: m.name.clone(),
                        parameter: "normal texture scale",
                        value: n.scale,
                        expected: "a finite number",
                    })
                }
                Some(n) => {
                    let (image, flags, uv) = texture(&Some(n.texture))?;
                    (UVec4::new(image, flags | TEXEL_LINEAR, 0, 0), uv, n.scale)
                }
            };
            pbr.z = normal_scale;
            let alpha = match m.alpha {
                Alpha::Opaque => Vec4::ZERO,
                Alpha::Mask { cutoff, factor } => {
                    for (parameter, value, ok, expected) in [
                        (
                            "alpha cutoff",
                            cutoff,
                            cutoff.is_finite() && cutoff >= 0.0,
                            "a finite number >= 0",
                        ),
                        (
                            "alpha factor",
                            factor,
                            (0.0..=1.0).contains(&factor),
                            "a number in [0, 1]",
                        ),
                    ] {
                        if !ok {
                            return Err(Error::InvalidMaterialParameter {
                                name: m.name.clone(),
                                parameter,
                                value,
                                expected,
                            });
                        }
                    }
                    Vec4::new(cutoff, factor, 0.0, 0.0)
                }
            };
            materials.push(MaterialGpu {
                albedo: m.albedo.clamp(Vec3::ZERO, Vec3::ONE).extend(0.0),
                emission: m.emission.extend(0.0),
                textures: UVec4::new(base, base_flags, emit, emit_flags),
                pbr,
                model,
                alpha,
                base_color_uv,
                emission_uv,
                metal_rough_uv,
                normal,
                normal_uv,
            });
        }
        // Images read as colour (base colour, emission) get their mip levels
        // averaged in linear light; the others (data) as stored.
        let mut colour = vec![false; scene.images.len()];
        for m in &scene.materials {
            for t in [&m.base_color_texture, &m.emission_texture].into_iter().flatten() {
                if let Some(c) = colour.get_mut(t.image as usize) {
                    *c = true;
                }
            }
        }
        let (images, image_count) = pack_images(&scene.images, &colour)?;
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

        let g = build_geometry(&scene.triangles, &materials, &scene.lights, environment_mean)?;
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
            lights: scene.lights.clone(),
            environment,
            environment_map,
            environment_mean,
            original_index: g.original_index,
            bvh_depth: g.bvh_depth,
            camera,
        })
    }

    /// Moves the scene's vertices to `positions` (given in the order of
    /// [`Scene::triangles`] of the scene this was built from), keeping
    /// materials, images, texture coordinates, tangents, vertex normals and
    /// ids: rebuilds the BVH, the leaf order and the emitter list (areas
    /// change). Vertex normals are world vectors, so a moving object that
    /// rotates or scales needs [`SceneGpu::set_normals`] as well (the
    /// animation timeline calls both). The previous
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
                tangent: None,
                normals: None,
            };
        }
        // Tangents are edge coefficients: they hold for the moved vertices.
        // Vertex normals are kept as they are (`set_normals` moves them).
        let mut kept = vec![TriangleAttrGpu::default(); positions.len()];
        for (a, &orig) in self.attrs.iter().zip(&self.original_index) {
            kept[orig as usize] = *a;
        }
        let mut g = build_geometry(&scene_order, &self.materials, &self.lights, self.environment_mean)?;
        for a in &mut g.attrs {
            let k = &kept[a.ids.y as usize];
            a.tangent = k.tangent;
            (a.normal0, a.normal1, a.normal2) = (k.normal0, k.normal1, k.normal2);
        }
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

    /// Sets the vertex normals, given in the order of [`Scene::triangles`]
    /// (the scene this was built from), as [`Triangle::normals`] says (world
    /// space, any length): zero or otherwise unusable normals make a
    /// triangle shade flat. Used with [`SceneGpu::set_positions`] when
    /// animation moves the geometry.
    ///
    /// # Errors
    /// [`Error::BufferSize`] when `normals` does not have one entry per
    /// triangle; nothing changes then.
    pub fn set_normals(&mut self, normals: &[[Vec3; 3]]) -> Result<()> {
        if normals.len() != self.triangles.len() {
            return Err(Error::BufferSize {
                buffer: "normals",
                expected: self.triangles.len(),
                actual: normals.len(),
            });
        }
        for (a, &orig) in self.attrs.iter_mut().zip(&self.original_index) {
            let t = Triangle {
                normals: Some(normals[orig as usize]),
                ..Triangle::new([Vec3::ZERO; 3], 0)
            };
            [a.normal0, a.normal1, a.normal2] = normals_gpu(&t);
        }
        Ok(())
    }

    /// The probability that next-event estimation picks the environment
    /// map's entry of the emitter list; 0 when there is none.
    pub fn environment_select_pdf(&self) -> f32 {
        self.emitters[..self.emitter_count as usize]
            .iter()
            .find(|e| e.kind == kernels::abi::EMITTER_ENVIRONMENT)
            .map_or(0.0, |e| e.pdf)
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

    /// Total emitted power over pi, `sum(area * mean(emission))` over the
    /// emissive triangles plus [`Light::power`] of the lights and the
    /// environment map's (the `emitters` module), in radiance units x area
    /// (useful to compare scenes' brightness).
    pub fn emitted_power(&self) -> f32 {
        let triangles: f32 = self.emitters[..self.emitter_count as usize]
            .iter()
            .filter(|e| e.kind == EMITTER_TRIANGLE)
            .map(|e| {
                let t = &self.triangles[e.triangle as usize];
                let m = &self.materials[t.v0.w as usize];
                e.area() * (m.emission.x + m.emission.y + m.emission.z) / 3.0
            })
            .sum();
        let radius = scene_radius(&self.triangles);
        let environment = environment_power(radius, self.environment_mean);
        triangles + self.lights.iter().map(|l| l.power(radius) as f32).sum::<f32>() + environment as f32
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
/// order with their attributes, and builds the emitter list of those
/// triangles, `lights` (validated) and an environment map of mean radiance
/// `environment_mean` (0 for none).
fn build_geometry(
    triangles_in: &[Triangle],
    materials: &[MaterialGpu],
    lights: &[Light],
    environment_mean: f64,
) -> Result<Geometry> {
    let vertices: Vec<[Vec3; 3]> = triangles_in.iter().map(|t| t.vertices).collect();
    let bvh = build_bvh(&vertices)?;

    // Triangles in leaf order; emitters with power-proportional selection.
    let mut triangles = Vec::with_capacity(bvh.primitive_indices.len());
    let mut attrs = Vec::with_capacity(bvh.primitive_indices.len());
    for &orig in &bvh.primitive_indices {
        let t = triangles_in[orig as usize];
        let [a, b, c] = t.vertices;
        let cut_out = materials[t.material as usize].alpha.x > 0.0;
        let normals = normals_gpu(&t);
        triangles.push(TriangleGpu {
            v0: a.extend(t.material as f32),
            v1: b.extend(0.0),
            v2: c.extend(if cut_out { CUT_OUT } else { 0.0 }),
        });
        attrs.push(TriangleAttrGpu {
            uv01: Vec4::new(t.uvs[0].x, t.uvs[0].y, t.uvs[1].x, t.uvs[1].y),
            uv2: Vec4::new(t.uvs[2].x, t.uvs[2].y, 0.0, 0.0),
            ids: UVec4::new(t.object, orig, 0, 0),
            tangent: tangent_gpu(&t),
            normal0: normals[0],
            normal1: normals[1],
            normal2: normals[2],
        });
    }
    let (emitters, emitter_count) = emitter_list(&mut triangles, materials, lights, environment_mean);
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

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::scene::{Image, Material};
    use glam::Vec4;

    /// A unit quad of material `light` (emitting `emission`) in front of a
    /// bigger grey triangle, with the camera on `+z`.
    pub(in crate::scene) fn quad_scene(emission: Vec3) -> Scene {
        let a = Vec3::new(0.0, 0.0, 0.0);
        let b = Vec3::new(1.0, 0.0, 0.0);
        let c = Vec3::new(1.0, 1.0, 0.0);
        let d = Vec3::new(0.0, 1.0, 0.0);
        let big = |p: Vec3| p * 3.0 + Vec3::new(-1.0, -1.0, -1.0);
        Scene {
            lights: Vec::new(),
            environment_map: None,
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
            assert!((e.area() - 0.5).abs() < 1e-6);
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
        // Metallic and roughness: NaN and values outside [0, 1] are refused
        // with the parameter named; the bounds themselves are accepted.
        for (metallic, roughness, bad) in [
            (f32::NAN, 0.5, Some("metallic")),
            (0.5, f32::NAN, Some("roughness")),
            (-0.01, 0.5, Some("metallic")),
            (0.5, 1.01, Some("roughness")),
            (0.0, 1.0, None),
            (1.0, 0.0, None),
        ] {
            let mut s = quad_scene(Vec3::ONE);
            s.materials[0].bsdf = Bsdf::MetallicRoughness {
                metallic,
                roughness,
                texture: None,
            };
            match (SceneGpu::build(&s), bad) {
                (Err(e @ Error::InvalidMaterialParameter { parameter, .. }), Some(want)) => {
                    assert_eq!(parameter, want);
                    assert!(e.to_string().contains("[0, 1]"), "{e}");
                }
                (Ok(g), None) => assert_eq!(
                    (g.materials[0].pbr.x, g.materials[0].pbr.y),
                    (metallic, roughness)
                ),
                (other, _) => panic!("{metallic} {roughness}: {other:?}"),
            }
        }
        let mut s = quad_scene(Vec3::ONE);
        s.triangles.clear();
        assert!(matches!(SceneGpu::build(&s), Err(Error::NoTriangles { .. })));
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
            transform: None,
        });
        let gpu = SceneGpu::build(&scene).expect("valid");
        assert_eq!(gpu.image_count, 2);
        // Headers (first word, width, height, mip levels); image a's level 1
        // (its 2x1 texels averaged as data: it is no colour texture) follows
        // its level 0.
        assert_eq!(&gpu.images[..8], &[8, 2, 1, 2, 11, 1, 1, 1]);
        assert_eq!(gpu.images[8], 0x0403_0201);
        assert_eq!(gpu.images[10], 0x0605_0403);
        assert_eq!(gpu.images[11], 0x0909_0909);
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
