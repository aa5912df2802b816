//! Path tracing: the radiance of one path sample for a pixel, drawn entirely
//! from the pixel's seed.
//!
//! # Light transport
//!
//! Materials are Lambertian (albedo `a`, BRDF `a / pi`, two-sided) or the
//! glTF metallic-roughness BRDF (two-sided too: the shading normal is the
//! geometric normal flipped towards the outgoing direction, smoothed by
//! the triangle's vertex normals where it has them,
//! [`crate::vertex_normal`], tilted by the material's normal map where it
//! has one, [`crate::normal_map`]), plus emission
//! from the front side of a triangle (see [`TriangleGpu`]); [`crate::shading`]
//! evaluates and samples them. Rays leaving the scene see the environment
//! ([`crate::environment`], found by BSDF sampling only, weight 1). At every
//! path vertex the estimator combines
//! - **next-event estimation**: an emitter picked with probability
//!   proportional to its power, a light sample on it
//!   ([`crate::lights`]: a uniform point on an emissive triangle, or the
//!   direction to a point, spot or directional light), and a shadow ray,
//!   weighted by `f cos` ([`Shading::eval_cos`]);
//! - **BSDF sampling**: a cosine-weighted direction (Lambertian) or the
//!   metallic-roughness sampler's (GGX visible normals or cosine, the lobe
//!   chosen by reusing the BSDF pair's first number); when it hits an
//!   emitter the emission is counted too.
//!
//! Both strategies are weighted by the power heuristic (Veach 1997, MIS with
//! beta = 2), so each path is counted once in expectation, never twice;
//! punctual lights, which BSDF sampling cannot find, are counted by
//! next-event estimation alone with weight 1.
//! Emission seen directly from the camera is counted with weight 1. An
//! emitter absent from the emitter list (or with `emitter_count == 0`) is
//! only found by BSDF sampling and counted with weight 1.
//!
//! Path length: `max_depth` counts segments including the camera segment.
//! Emission hit at vertex `d` (0-based) makes a path of `d + 1` segments;
//! next-event estimation at vertex `d` makes one of `d + 2`, so it runs only
//! while `d + 2 <= max_depth`. Both strategies therefore cover exactly the
//! same path lengths, which MIS requires. Russian roulette applies at
//! vertices `d >= rr_depth`: the path continues with probability
//! `min(max channel of throughput, 0.95)` and its throughput is divided by it.
//!
//! Where each number of a path comes from (the seed stream's layout, the
//! a-priori samplers) is [`crate::numbers`], whose items are re-exported
//! here; the blue-noise-dither baseline ([`crate::dither`]) builds on this
//! module.

pub use crate::geometry::{normal_and_area, RAY_OFFSET};
pub use crate::lights::{select_emitter, select_emitter_reusing};
pub use crate::mis::power_heuristic;
pub use crate::numbers::*;

use crate::abi::{
    BvhNodeGpu, EmitterGpu, MaterialGpu, TraceParams, TriangleAttrGpu, TriangleGpu, MAX_DEPTH_LIMIT,
};
use crate::bvh::{any_hit, closest_hit};
use crate::camera::primary_ray;
use crate::environment::{environment_mis_weight, environment_radiance};
use crate::footprint::{cone_footprint, pixel_spread, primary_footprint};
use crate::geometry::offset_point;
use crate::intersect::Ray;
use crate::lights::sample_emitter;
use crate::normal_map::shading_normal;
use crate::shading::Shading;
use crate::surface::{has_textures, surface_emission_filtered, triangle_uv};
use glam::{UVec2, Vec2, Vec3, Vec4};
use sampler_core::RandomStream;

/// Largest Russian-roulette survival probability: paths with a bright
/// throughput still end with probability >= 5%, which bounds path length in
/// closed scenes with albedo near 1.
pub const RR_MAX_SURVIVAL: f32 = 0.95;

/// Mean radiance of the pixel's `params.spp` samples for this frame, as
/// `(r, g, b, 1)`: the value the trace pass writes to the frame colour
/// buffer. Identical to what [`TRACE_ENTRY`](crate::abi::TRACE_ENTRY) computes
/// on the GPU. `seed` is the pixel's seed; `keys` the screen-space Sobol key
/// buffer (binding 7; read only with [`SAMPLER_SCREEN_SOBOL`](crate::abi::SAMPLER_SCREEN_SOBOL), may be
/// empty otherwise). With an a-priori `params.sampler`, the path's 2D
/// decisions come from [`apriori_pair`] (module docs).
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn trace_pixel(
    params: &TraceParams,
    pixel: UVec2,
    seed: u32,
    keys: &[u32],
    nodes: &[BvhNodeGpu],
    triangles: &[TriangleGpu],
    materials: &[MaterialGpu],
    emitters: &[EmitterGpu],
    attrs: &[TriangleAttrGpu],
    images: &[u32],
    environment: &[f32],
) -> Vec4 {
    trace_pixel_counted(
        params,
        pixel,
        seed,
        keys,
        nodes,
        triangles,
        materials,
        emitters,
        attrs,
        images,
        environment,
    )
    .0
}

/// [`trace_pixel`] and the number of rays it traced (camera, continuation
/// and shadow rays: every BVH query), for throughput measurements.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn trace_pixel_counted(
    params: &TraceParams,
    pixel: UVec2,
    seed: u32,
    keys: &[u32],
    nodes: &[BvhNodeGpu],
    triangles: &[TriangleGpu],
    materials: &[MaterialGpu],
    emitters: &[EmitterGpu],
    attrs: &[TriangleAttrGpu],
    images: &[u32],
    environment: &[f32],
) -> (Vec4, u32) {
    let spp = params.spp.max(1);
    let mut sum = Vec3::ZERO;
    let mut rays = 0u32;
    let mut s = 0u32;
    while s < spp {
        let numbers = PathNumbers::new(params, pixel, seed, s);
        sum += trace_sample_with(
            params,
            keys,
            numbers,
            nodes,
            triangles,
            materials,
            emitters,
            attrs,
            images,
            environment,
            &mut rays,
        );
        s += 1;
    }
    ((sum / spp as f32).extend(1.0), rays)
}

/// Radiance (linear RGB, `>= 0`) carried by one path through `pixel`, using
/// the numbers of `stream` from its current index on (see the module docs
/// for the layout). Non-finite results (which only degenerate input can
/// cause) are returned as 0.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn trace_sample(
    params: &TraceParams,
    pixel: UVec2,
    stream: RandomStream,
    nodes: &[BvhNodeGpu],
    triangles: &[TriangleGpu],
    materials: &[MaterialGpu],
    emitters: &[EmitterGpu],
    attrs: &[TriangleAttrGpu],
    images: &[u32],
    environment: &[f32],
) -> Vec3 {
    let mut rays = 0u32;
    let numbers = PathNumbers::from_stream(stream, pixel);
    trace_sample_with(
        params,
        &[],
        numbers,
        nodes,
        triangles,
        materials,
        emitters,
        attrs,
        images,
        environment,
        &mut rays,
    )
}

/// One path sample (as [`trace_sample`]) drawing its numbers from
/// `numbers`; `keys` is the screen-space Sobol key buffer. Adds the rays it
/// traces to `rays`.
#[allow(clippy::too_many_arguments)]
#[inline]
pub(crate) fn trace_sample_with(
    params: &TraceParams,
    keys: &[u32],
    numbers: PathNumbers,
    nodes: &[BvhNodeGpu],
    triangles: &[TriangleGpu],
    materials: &[MaterialGpu],
    emitters: &[EmitterGpu],
    attrs: &[TriangleAttrGpu],
    images: &[u32],
    environment: &[f32],
    rays: &mut u32,
) -> Vec3 {
    let max_depth = params.max_depth.min(MAX_DEPTH_LIMIT);
    let pixel = numbers.pixel;
    let jitter = numbers.jitter(params, keys);
    let mut ray = primary_ray(params, pixel.x, pixel.y, jitter);
    let mut throughput = Vec3::ONE;
    let mut radiance = Vec3::ZERO;
    // Solid-angle density of the BSDF sample that produced `ray`; 0 for the camera ray.
    let mut bsdf_pdf = 0.0f32;
    // The path's ray cone (`crate::footprint`): width (world units) at the
    // last hit and spread (radians) of the current ray.
    let (mut cone_width, mut cone_spread) = (0.0f32, pixel_spread(params));

    let mut depth = 0u32;
    while depth < max_depth {
        // f32::MAX, not INFINITY: naga rejects infinite literals in SPIR-V.
        *rays += 1;
        let hit = match closest_hit(
            nodes,
            triangles,
            materials,
            attrs,
            images,
            params.image_count,
            &ray,
            0.0,
            f32::MAX,
        ) {
            Some(h) => h,
            None => {
                let weight = environment_mis_weight(params, environment, ray.dir, bsdf_pdf);
                radiance += throughput * environment_radiance(params, environment, ray.dir) * weight;
                break;
            }
        };
        let tri = triangles[hit.triangle as usize];
        let (v0, v1, v2) = (tri.v0.truncate(), tri.v1.truncate(), tri.v2.truncate());
        let (geo_normal, area) = normal_and_area(v0, v1, v2);
        let point = v0 + (v1 - v0) * hit.u + (v2 - v0) * hit.v;
        let material = materials[tri.v0.w as u32 as usize];
        let attr = &attrs[hit.triangle as usize];
        let hit_uv = triangle_uv(attr, hit.u, hit.v);
        // Textures at the camera ray's first hit: read at the pixel centre,
        // filtered over the pixel's footprint (`crate::footprint`).
        // Later hits: filtered over the path's ray cone there.
        cone_width += hit.t * cone_spread;
        let (uv, footprint) = if !has_textures(&material) {
            (hit_uv, 0.0)
        } else if depth == 0 {
            primary_footprint(params, pixel, (v0, v1, v2), attr, hit_uv, hit.t)
        } else {
            (hit_uv, cone_footprint(cone_width, ray.dir, (v0, v1, v2), attr))
        };
        let cos_out = -ray.dir.dot(geo_normal);

        // Emission found by the BSDF sample (or seen from the camera).
        let emission = surface_emission_filtered(&material, images, params.image_count, uv, footprint);
        if cos_out > 0.0 && emission.max_element() > 0.0 {
            let select_pdf = tri.v1.w;
            let weight = if bsdf_pdf > 0.0 && select_pdf > 0.0 && params.emitter_count > 0 {
                let light_pdf = select_pdf * hit.t * hit.t / (area * cos_out);
                power_heuristic(bsdf_pdf, light_pdf)
            } else {
                1.0
            };
            radiance += throughput * emission * weight;
        }

        // Shading frame faces the incoming ray (two-sided materials); vertex
        // normals smooth it (`crate::vertex_normal`) and a normal map tilts
        // it (`crate::normal_map`), the geometric `normal` stays for
        // offsets and for what lies below the surface.
        let normal = if cos_out > 0.0 { geo_normal } else { -geo_normal };
        let shading_normal = shading_normal(
            &material,
            images,
            params.image_count,
            uv,
            attr,
            (v1 - v0, v2 - v0),
            geo_normal,
            normal,
            Vec2::new(hit.u, hit.v),
            -ray.dir,
        );
        let shading = Shading::at_filtered(
            &material,
            images,
            params.image_count,
            uv,
            footprint,
            shading_normal,
            -ray.dir,
        );
        let u_light = numbers.light(params, keys, depth);
        let origin = offset_point(point, normal);

        // Next-event estimation.
        if params.emitter_count > 0 && depth + 2 <= max_depth && shading.reflects() {
            let (index, u_point) = select_emitter_reusing(emitters, params.emitter_count, u_light);
            let light = sample_emitter(
                &emitters[index as usize],
                origin,
                u_point,
                triangles,
                materials,
                attrs,
                images,
                params,
                environment,
            );
            if light.is_some() {
                // Above the geometric surface, and the BSDF's cosine against
                // the shading normal (the same number without a normal map).
                let cos_surface = light.wi.dot(normal);
                let cos_shading = light.wi.dot(shading_normal);
                if cos_surface > 0.0 && cos_shading > 0.0 && light.t_max > 0.0 {
                    let (brdf_cos, brdf_pdf) = shading.eval_cos(light.wi, cos_shading);
                    let weight = if light.mis {
                        power_heuristic(light.pdf, brdf_pdf)
                    } else {
                        1.0
                    };
                    *rays += 1;
                    let shadow = Ray::new(origin, light.wi);
                    let blocked = any_hit(
                        nodes,
                        triangles,
                        materials,
                        attrs,
                        images,
                        params.image_count,
                        &shadow,
                        0.0,
                        light.t_max,
                    );
                    if !blocked {
                        radiance += throughput * brdf_cos * light.radiance * (weight / light.pdf);
                    }
                }
            }
        }

        if depth + 1 >= max_depth {
            break;
        }

        // BSDF sampling: throughput times f cos / pdf (the albedo for a
        // cosine-weighted Lambertian direction).
        // Directions below the geometric surface (possible with a normal
        // map's tilted frame) end the path rather than leak through it.
        let sample = shading.sample(numbers.bsdf(params, keys, depth));
        if sample.pdf <= 0.0 || sample.wi.dot(normal) <= 0.0 {
            break;
        }
        let wi = sample.wi;
        throughput *= sample.weight;
        bsdf_pdf = sample.pdf;
        cone_spread += shading.cone_spread();

        if depth >= params.rr_depth {
            let survive = throughput.max_element().min(RR_MAX_SURVIVAL);
            if numbers.roulette(params, keys, depth) >= survive {
                break;
            }
            throughput /= survive;
        }
        ray = Ray::new(origin, wi);
        depth += 1;
    }

    // Not `is_finite()`: glam compares against an infinite literal, which
    // naga rejects. `|x| <= f32::MAX` is false for NaN and infinities.
    if radiance.abs().cmple(Vec3::splat(f32::MAX)).all() {
        radiance.max(Vec3::ZERO)
    } else {
        Vec3::ZERO
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::abi::{
        SAMPLER_JITTER_ONLY, SAMPLER_SCREEN_SOBOL, SAMPLER_SEEDS, SAMPLER_ZSOBOL, SEED_MODE_ADVANCE,
    };
    use glam::Vec2;
    use sampler_core::sequences::screen_sobol::ScreenSobolLayout;

    #[test]
    fn stream_sample_modes() {
        let mut p = TraceParams {
            spp: 4,
            frame: 3,
            ..Default::default()
        };
        assert_eq!(stream_sample(&p, 2), 2);
        p.seed_mode = SEED_MODE_ADVANCE;
        assert_eq!(stream_sample(&p, 2), 14);
        p.seed_mode = 7;
        assert_eq!(stream_sample(&p, 2), 2);
    }

    /// A diffuse floor (y = 0, albedo 0.5) under an emitter covering the
    /// half-plane x > 0 at y = 1 (facing down, emission 1), seen from above
    /// the floor at x = 0; no emitter list, so light arrives only through
    /// vertex 0's BSDF direction: each sample is 0 or 0.5.
    struct HalfLit {
        nodes: [BvhNodeGpu; 1],
        triangles: [TriangleGpu; 2],
        materials: [MaterialGpu; 2],
        emitters: [EmitterGpu; 1],
        attrs: [TriangleAttrGpu; 2],
    }

    fn half_lit() -> HalfLit {
        let floor = TriangleGpu {
            v0: Vec4::new(-100.0, 0.0, -100.0, 0.0),
            v1: Vec4::new(-100.0, 0.0, 200.0, 0.0),
            v2: Vec4::new(200.0, 0.0, -100.0, 0.0),
        };
        let light = TriangleGpu {
            v0: Vec4::new(0.0, 1.0, -100.0, 1.0),
            v1: Vec4::new(100.0, 1.0, 0.0, 0.0),
            v2: Vec4::new(0.0, 1.0, 100.0, 0.0),
        };
        HalfLit {
            nodes: [BvhNodeGpu {
                min: Vec4::new(-100.0, 0.0, -100.0, 0.0),
                max: Vec4::new(200.0, 1.0, 200.0, 0.0),
                info: glam::UVec4::new(2, 0, 0, 0),
            }],
            triangles: [floor, light],
            materials: [
                MaterialGpu::untextured(Vec4::new(0.5, 0.5, 0.5, 0.0), Vec4::ZERO),
                MaterialGpu::untextured(Vec4::ZERO, Vec4::new(1.0, 1.0, 1.0, 0.0)),
            ],
            emitters: [EmitterGpu::NONE],
            attrs: [TriangleAttrGpu::default(); 2],
        }
    }

    fn half_lit_params(sampler: u32, spp: u32, frame: u32) -> TraceParams {
        TraceParams {
            width: 16,
            height: 16,
            padded_width: 16,
            spp,
            max_depth: 2,
            frame,
            triangle_count: 2,
            node_count: 1,
            rr_depth: 3,
            tan_half_fov_y: 0.2,
            camera_origin: Vec4::new(0.0, 0.5, 0.0, 0.0),
            camera_forward: Vec4::new(0.0, -1.0, 0.0, 0.0),
            camera_right: Vec4::X,
            camera_up: Vec4::Z,
            sampler,
            key_side_log2: 2,
            key_pairs: 1,
            key_levels: 3,
            ..Default::default()
        }
    }

    fn test_keys() -> [u32; 48] {
        core::array::from_fn(|i| sampler_core::sequences::seed::hash_u32(i as u32 ^ 0x5bd1_e995))
    }

    fn render(
        scene: &HalfLit,
        params: &TraceParams,
        keys: &[u32],
        seed_of: impl Fn(u32, u32) -> u32,
    ) -> [f32; 256] {
        core::array::from_fn(|i| {
            let (x, y) = (i as u32 % 16, i as u32 / 16);
            trace_pixel(
                params,
                UVec2::new(x, y),
                seed_of(x, y),
                keys,
                &scene.nodes,
                &scene.triangles,
                &scene.materials,
                &scene.emitters,
                &scene.attrs,
                &[0],
                &[0.0],
            )
            .x
        })
    }

    /// With an a-priori sampler every decision of these paths (depth 2, no
    /// Russian roulette) comes from the sampler: the image does not depend
    /// on the seeds, differs from the seed stream's, and equals the mean of
    /// `spp` samples built from `PathNumbers::new`.
    #[test]
    fn apriori_samplers_drive_every_pair() {
        let scene = half_lit();
        let keys = test_keys();
        let seed_of = |x: u32, y: u32| sampler_core::initial_seed(x, y, 16, 7);
        let other_seed_of = |x: u32, y: u32| sampler_core::initial_seed(x, y, 16, 8);
        for spp in [1u32, 4] {
            let seeds_img = render(&scene, &half_lit_params(SAMPLER_SEEDS, spp, 3), &keys, seed_of);
            assert_ne!(
                seeds_img,
                render(
                    &scene,
                    &half_lit_params(SAMPLER_SEEDS, spp, 3),
                    &keys,
                    other_seed_of
                ),
                "the seed stream depends on the seeds"
            );
            for sampler in [SAMPLER_SCREEN_SOBOL, SAMPLER_ZSOBOL] {
                let params = half_lit_params(sampler, spp, 3);
                let img = render(&scene, &params, &keys, seed_of);
                assert_eq!(
                    img,
                    render(&scene, &params, &keys, other_seed_of),
                    "sampler {sampler}"
                );
                let differing = img.iter().zip(&seeds_img).filter(|(a, b)| a != b).count();
                assert!(
                    differing > 16,
                    "sampler {sampler} spp {spp}: only {differing} pixels differ"
                );
                for (x, y) in [(0u32, 0u32), (5, 9), (15, 15)] {
                    let pixel = UVec2::new(x, y);
                    let mut sum = Vec3::ZERO;
                    for s in 0..spp {
                        let numbers = PathNumbers::new(&params, pixel, seed_of(x, y), s);
                        assert_eq!(
                            numbers.jitter(&params, &keys),
                            apriori_pair(&params, &keys, pixel, s, 0)
                        );
                        assert_eq!(
                            numbers.bsdf(&params, &keys, 1),
                            apriori_pair(&params, &keys, pixel, s, pair_bsdf(1))
                        );
                        sum += trace_sample_with(
                            &params,
                            &keys,
                            numbers,
                            &scene.nodes,
                            &scene.triangles,
                            &scene.materials,
                            &scene.emitters,
                            &scene.attrs,
                            &[0],
                            &[0.0],
                            &mut 0,
                        );
                    }
                    assert_eq!(
                        img[(y * 16 + x) as usize],
                        (sum / spp as f32).x,
                        "pixel ({x}, {y})"
                    );
                }
            }
            // Unknown sampler values fall back to the seed stream.
            assert_eq!(
                render(&scene, &half_lit_params(9, spp, 3), &keys, seed_of),
                seeds_img
            );
        }
    }

    /// With [`SAMPLER_JITTER_ONLY`] the jitter is the sampler's pair 0 (not
    /// the stream's) and every other pair the seed stream's: the image
    /// depends on the seeds and differs from the full sampler's.
    #[test]
    fn jitter_only_takes_pair_zero_from_the_sampler() {
        let scene = half_lit();
        let keys = test_keys();
        let seed_of = |x: u32, y: u32| sampler_core::initial_seed(x, y, 16, 7);
        let other_seed_of = |x: u32, y: u32| sampler_core::initial_seed(x, y, 16, 8);
        for sampler in [SAMPLER_SCREEN_SOBOL, SAMPLER_ZSOBOL] {
            let params = half_lit_params(sampler | SAMPLER_JITTER_ONLY, 1, 3);
            let full = half_lit_params(sampler, 1, 3);
            let seeds = half_lit_params(SAMPLER_SEEDS, 1, 3);
            for (x, y) in [(0u32, 0u32), (5, 9), (15, 15)] {
                let pixel = UVec2::new(x, y);
                let numbers = PathNumbers::new(&params, pixel, seed_of(x, y), 0);
                let stream = PathNumbers::new(&seeds, pixel, seed_of(x, y), 0);
                assert_eq!(
                    numbers.jitter(&params, &keys),
                    apriori_pair(&full, &keys, pixel, 0, PAIR_JITTER)
                );
                assert_ne!(numbers.jitter(&params, &keys), stream.jitter(&seeds, &keys));
                for depth in 0..3 {
                    assert_eq!(
                        numbers.light(&params, &keys, depth),
                        stream.light(&seeds, &keys, depth)
                    );
                    assert_eq!(
                        numbers.bsdf(&params, &keys, depth),
                        stream.bsdf(&seeds, &keys, depth)
                    );
                }
            }
            let img = render(&scene, &params, &keys, seed_of);
            assert_ne!(
                img,
                render(&scene, &params, &keys, other_seed_of),
                "sampler {sampler}"
            );
            assert_ne!(img, render(&scene, &full, &keys, seed_of), "sampler {sampler}");
        }
        // Screen-space Sobol reads the key buffer: other keys, other image.
        let params = half_lit_params(SAMPLER_SCREEN_SOBOL, 1, 0);
        let other: [u32; 48] = core::array::from_fn(|i| keys[(i + 1) % 48]);
        assert_ne!(
            render(&scene, &params, &keys, seed_of),
            render(&scene, &params, &other, seed_of)
        );
    }

    /// Degenerate key layouts never panic: a 1x1 key tile (`key_side_log2`
    /// 0) with any frame reads key 0 for every pixel.
    #[test]
    fn screen_sobol_with_a_one_texel_tile_does_not_overflow() {
        let keys = [0x1234_5678u32; 3];
        let p = TraceParams {
            key_side_log2: 0,
            frame: 0xFFFF_FFF0,
            ..half_lit_params(SAMPLER_SCREEN_SOBOL, 1, 0)
        };
        let a = apriori_pair(&p, &keys, UVec2::new(u32::MAX, 7), 0, 0);
        assert_eq!(a, apriori_pair(&p, &keys, UVec2::new(0, 0), 0, 0));
        assert!((0.0..1.0).contains(&a.x) && (0.0..1.0).contains(&a.y));
    }

    /// The pair layout: jitter 0, then light and BSDF of each vertex.
    #[test]
    fn apriori_pair_layout() {
        assert_eq!(PAIR_JITTER, 0);
        assert_eq!(
            (pair_light(0), pair_bsdf(0), pair_light(1), pair_bsdf(1)),
            (1, 2, 3, 4)
        );
    }

    /// `apriori_pair` returns the sampler-core samplers' values for the
    /// documented indices, for optimised and padded pairs.
    #[test]
    fn apriori_pair_matches_sampler_core() {
        let keys = test_keys();
        let layout = ScreenSobolLayout::new(4, 1, 3).unwrap();
        for (spp, frame, s) in [(1u32, 0u32, 0u32), (2, 5, 1), (4, 2, 3), (3, 1, 2)] {
            for pixel in [UVec2::new(0, 0), UVec2::new(6, 3), UVec2::new(1023, 77)] {
                for pair in [0u32, 1, 5] {
                    let p = TraceParams {
                        frame,
                        ..half_lit_params(SAMPLER_SCREEN_SOBOL, spp, 0)
                    };
                    let d = 2 * pair;
                    let at = pixel + sampler_core::walk_offset(frame, p.key_side_log2);
                    let want = Vec2::new(
                        sampler_core::sequences::screen_sobol::screen_sobol_sample(
                            &keys, layout, spp, at, s, d,
                        ),
                        sampler_core::sequences::screen_sobol::screen_sobol_sample(
                            &keys,
                            layout,
                            spp,
                            at,
                            s,
                            d + 1,
                        ),
                    );
                    assert_eq!(apriori_pair(&p, &keys, pixel, s, pair), want);
                    let p = TraceParams {
                        sampler: SAMPLER_ZSOBOL,
                        ..p
                    };
                    let log2 = 32 - (spp - 1).leading_zeros();
                    let want = Vec2::new(
                        sampler_core::zsobol_sample(pixel, s, d, log2, frame),
                        sampler_core::zsobol_sample(pixel, s, d + 1, log2, frame),
                    );
                    assert_eq!(apriori_pair(&p, &keys, pixel, s, pair), want);
                }
            }
        }
    }

    /// Screen-space Sobol: frame `t` reads the key tile shifted by the R2
    /// walk offset `o_t`, and a pixel's samples of one frame (here 4 spp,
    /// key level 2) form a (0, 2, 2)-net: one point in each elementary
    /// interval of area 1/4.
    #[test]
    fn screen_sobol_frames_shift_the_keys_and_keep_the_net() {
        let keys = test_keys();
        let params = |frame: u32| half_lit_params(SAMPLER_SCREEN_SOBOL, 4, frame);
        for t in [1u32, 2, 7] {
            let o = sampler_core::walk_offset(t, params(t).key_side_log2);
            assert_ne!(o, UVec2::ZERO);
            for pixel in [UVec2::new(0, 0), UVec2::new(3, 1)] {
                for s in 0..4 {
                    assert_eq!(
                        apriori_pair(&params(t), &keys, pixel, s, 1),
                        apriori_pair(&params(0), &keys, pixel + o, s, 1)
                    );
                }
            }
        }
        for pixel in [UVec2::new(0, 0), UVec2::new(3, 1), UVec2::new(2, 2)] {
            let pts: [Vec2; 4] =
                core::array::from_fn(|s| apriori_pair(&params(5), &keys, pixel, s as u32, 0));
            for (nx, ny) in [(4.0f32, 1.0f32), (2.0, 2.0), (1.0, 4.0)] {
                let mut cells: [u32; 4] = pts.map(|p| (p.x * nx) as u32 * ny as u32 + (p.y * ny) as u32);
                cells.sort_unstable();
                assert_eq!(cells, [0, 1, 2, 3], "pixel {pixel} {pts:?}");
            }
        }
    }
}
