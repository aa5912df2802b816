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
use glam::Vec3;
use kernels::abi::{
    BvhNodeGpu, EmitterGpu, MaterialGpu, TraceParams, TriangleGpu, MAX_DEPTH_LIMIT, SAMPLER_JITTER_ONLY,
    SAMPLER_KIND_MASK, SAMPLER_SCREEN_SOBOL, SAMPLER_ZSOBOL, SEED_MODE_ADVANCE,
};
use kernels::trace::normal_and_area;

/// A triangle with its material. The front side (the only one that emits)
/// is the one the right-hand normal `(v1 - v0) x (v2 - v0)` points to, i.e.
/// vertices are counter-clockwise seen from the front (the OBJ convention).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    /// Vertices in world units.
    pub vertices: [Vec3; 3],
    /// Index into [`Scene::materials`].
    pub material: u32,
}

/// A Lambertian material with optional emission.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Name (from the MTL file, or descriptive for built-in scenes).
    pub name: String,
    /// Diffuse albedo, linear RGB; each channel is clamped to `[0, 1]` when
    /// the GPU form is built.
    pub albedo: Vec3,
    /// Emitted radiance from the front side, linear RGB, `>= 0`.
    pub emission: Vec3,
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

/// A scene: triangles, materials and a camera.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// All triangles; at least one for a renderable scene.
    pub triangles: Vec<Triangle>,
    /// Materials indexed by [`Triangle::material`].
    pub materials: Vec<Material>,
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
            materials.push(MaterialGpu {
                albedo: m.albedo.clamp(Vec3::ZERO, Vec3::ONE).extend(0.0),
                emission: m.emission.extend(0.0),
            });
        }
        for (i, t) in scene.triangles.iter().enumerate() {
            if let Some(vertex) = t.vertices.iter().position(|v| !v.is_finite()) {
                return Err(Error::NonFiniteVertex {
                    path: "<scene>".into(),
                    model: format!("triangle {i}"),
                    vertex,
                });
            }
            if t.material as usize >= materials.len() {
                return Err(Error::MaterialIndex {
                    triangle: i,
                    material: t.material,
                    count: materials.len(),
                });
            }
        }

        let vertices: Vec<[Vec3; 3]> = scene.triangles.iter().map(|t| t.vertices).collect();
        let bvh = build_bvh(&vertices)?;

        // Triangles in leaf order; emitters with power-proportional selection.
        let mut triangles = Vec::with_capacity(bvh.primitive_indices.len());
        let mut emitters = Vec::new();
        let mut total_power = 0.0f64;
        for (i, &orig) in bvh.primitive_indices.iter().enumerate() {
            let t = scene.triangles[orig as usize];
            let [a, b, c] = t.vertices;
            triangles.push(TriangleGpu {
                v0: a.extend(t.material as f32),
                v1: b.extend(0.0),
                v2: c.extend(0.0),
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
        Ok(SceneGpu {
            nodes: bvh.nodes,
            triangles,
            materials,
            emitters,
            emitter_count,
            original_index: bvh.primitive_indices,
            bvh_depth: bvh.depth,
            camera,
        })
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
        })
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
                Triangle {
                    vertices: [a, b, c],
                    material: 1,
                },
                Triangle {
                    vertices: [a, c, d],
                    material: 1,
                },
                Triangle {
                    vertices: [big(a), big(b), big(c)],
                    material: 0,
                },
            ],
            materials: vec![
                Material {
                    name: "grey".into(),
                    albedo: Vec3::new(0.5, 2.0, 0.5),
                    emission: Vec3::ZERO,
                },
                Material {
                    name: "light".into(),
                    albedo: Vec3::ZERO,
                    emission,
                },
            ],
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
}
