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
//! With `TraceParams::glossy_regularization` above 0, glossy surfaces met
//! after rough ones are made rougher ([`crate::regularization`]: biased, off
//! by default).
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
use crate::bvh::{any_hit_variant, closest_hit_variant};
use crate::camera::primary_ray;
use crate::environment::{environment_mis_weight, environment_radiance};
use crate::footprint::{cone_footprint, pixel_spread, primary_footprint};
use crate::geometry::offset_point;
use crate::intersect::Ray;
use crate::lights::sample_emitter_variant;
use crate::normal_map::shading_normal_variant;
use crate::regularization::{path_roughness_after, roughness_floor};
use crate::shading::Shading;
use crate::surface::{has_textures, surface_emission_filtered, triangle_uv};
use crate::trace_variant;
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
    trace_pixel_variant::<{ trace_variant::FULL }>(
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
}

/// [`trace_pixel`] compiled as one of the variants of
/// [`crate::trace_variant`]: `FEATURES` = [`trace_variant::FULL`] is
/// [`trace_pixel`]; a smaller set leaves out what its features do not
/// name ([`trace_variant::TEXTURES`]: textures, normal maps, cut-outs;
/// [`trace_variant::SHADING`]: the metallic-roughness model, vertex
/// normals, lights other than emissive triangles, the environment map) and
/// returns the same value bit for bit on scenes that use none of it (and a
/// wrong one on others: the host checks, [`crate::trace_variant`]).
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn trace_pixel_variant<const FEATURES: u32>(
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
    trace_pixel_counted_variant::<FEATURES>(
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

/// [`trace_pixel_variant`] and the number of rays it traced (camera,
/// continuation and shadow rays: every BVH query), for throughput
/// measurements.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn trace_pixel_counted_variant<const FEATURES: u32>(
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
        sum += trace_sample_with::<FEATURES>(
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
    trace_sample_with::<{ trace_variant::FULL }>(
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
/// traces to `rays`. `FEATURES` is the variant's feature set
/// ([`crate::trace_variant`]): every step a variant leaves out tests
/// `textured` or `shaded` below or goes through a `_variant` function.
#[allow(clippy::too_many_arguments)]
#[inline]
pub(crate) fn trace_sample_with<const FEATURES: u32>(
    params: &TraceParams,
    keys: &[u32],
    mut numbers: PathNumbers,
    nodes: &[BvhNodeGpu],
    triangles: &[TriangleGpu],
    materials: &[MaterialGpu],
    emitters: &[EmitterGpu],
    attrs: &[TriangleAttrGpu],
    images: &[u32],
    environment: &[f32],
    rays: &mut u32,
) -> Vec3 {
    // The variant's features (constants once compiled: the branches they
    // guard vanish from the smaller variants).
    let textured = FEATURES & trace_variant::TEXTURES != 0;
    let shaded = FEATURES & trace_variant::SHADING != 0;
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

    // The roughest lobe that continued the path so far (`crate::regularization`).
    let mut path_roughness = 0.0f32;
    let mut depth = 0u32;
    while depth < max_depth {
        // f32::MAX, not INFINITY: naga rejects infinite literals in SPIR-V.
        *rays += 1;
        let hit = closest_hit_variant::<FEATURES>(
            nodes,
            triangles,
            materials,
            attrs,
            images,
            params.image_count,
            &ray,
            0.0,
            f32::MAX,
        );
        let hit = match hit {
            Some(h) => h,
            None => {
                if shaded {
                    let weight = environment_mis_weight(params, environment, ray.dir, bsdf_pdf);
                    radiance += throughput * environment_radiance(params, environment, ray.dir) * weight;
                } else {
                    radiance += throughput * params.environment.truncate() * 1.0;
                }
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
        let (uv, footprint) = if !textured || !has_textures(&material) {
            (hit_uv, 0.0)
        } else if depth == 0 {
            primary_footprint(params, pixel, (v0, v1, v2), attr, hit_uv, hit.t)
        } else {
            (hit_uv, cone_footprint(cone_width, ray.dir, (v0, v1, v2), attr))
        };
        let cos_out = -ray.dir.dot(geo_normal);

        // Emission found by the BSDF sample (or seen from the camera).
        let emission = if textured {
            surface_emission_filtered(&material, images, params.image_count, uv, footprint)
        } else {
            material.emission.truncate()
        };
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
        let shading_normal = shading_normal_variant::<FEATURES>(
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
        let shading = Shading::at_variant::<FEATURES>(
            &material,
            images,
            params.image_count,
            uv,
            footprint,
            shading_normal,
            -ray.dir,
            roughness_floor(params.glossy_regularization, path_roughness),
        );
        numbers.set_sharp_first_hit(depth, if shading.is_sharp() { 1 } else { 0 });
        let u_light = numbers.light(params, keys, depth);
        let origin = offset_point(point, normal);

        // Next-event estimation.
        if params.emitter_count > 0 && depth + 2 <= max_depth && shading.reflects() {
            let (index, u_point) = select_emitter_reusing(emitters, params.emitter_count, u_light);
            let emitter = &emitters[index as usize];
            let light = sample_emitter_variant::<FEATURES>(
                emitter,
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
                    let blocked = any_hit_variant::<FEATURES>(
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
        let u_bsdf = numbers.bsdf(params, keys, depth);
        let sample = shading.sample(u_bsdf);
        if sample.pdf <= 0.0 || sample.wi.dot(normal) <= 0.0 {
            break;
        }
        // Unconditional (a compare and a select): a branch on the strength
        // would cost lavapipe more than the update.
        path_roughness = path_roughness_after(path_roughness, shading.continuation_roughness(u_bsdf));
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
mod tests;
