//! The blue-noise-dither baseline of the quality study: a path tracer
//! whose first bounce reads a caller-supplied blue-noise mask value.
//!
//! [`trace_pixel_dithered`] with `seed_mode ==`
//! [`SEED_MODE_BLUE_NOISE_DITHER`] replaces the two numbers of vertex 0's
//! BSDF direction (dimensions `2 + 3`, `2 + 4`) by a per-pixel dither value
//! supplied by the caller (a spatiotemporal blue-noise mask), Cranley-Patterson
//! rotated by the R2 sequence for sample `s`: `frac(dither + s * (a1, a2))`.
//! Every other dimension still comes from the seed's stream. The first
//! bounce's direction is the dimension pair that matters most on flat,
//! unshadowed regions: next-event estimation of a large area light there is a
//! smooth integrand with little variance, while the indirect light gathered
//! through the first bounce (which hemisphere direction, hence which wall,
//! the path sees) carries most of the per-pixel variance.
//!

use crate::abi::{
    BvhNodeGpu, EmitterGpu, MaterialGpu, TraceParams, TriangleAttrGpu, TriangleGpu,
    SEED_MODE_BLUE_NOISE_DITHER,
};
use crate::numbers::{stream_sample, PathNumbers, DIMS_PER_SAMPLE};
use crate::trace::{trace_pixel, trace_sample_with};
use glam::{UVec2, Vec2, Vec3, Vec4};
use sampler_core::RandomStream;

/// Mean radiance of the pixel's `params.spp` samples, as [`trace_pixel`],
/// except that with `params.seed_mode ==` [`SEED_MODE_BLUE_NOISE_DITHER`]
/// sample `s` takes vertex 0's BSDF direction numbers from
/// `frac(dither + s * (a1, a2))` (R2 constants) instead of the stream (see
/// the module docs). `dither` is the pixel's value of a blue-noise mask for
/// this frame, each component in `[0, 1)`. With any other seed mode this is
/// exactly [`trace_pixel`] with an empty key buffer (so with
/// [`SAMPLER_SCREEN_SOBOL`](crate::abi::SAMPLER_SCREEN_SOBOL) every pixel reads key 0: pass the keys to
/// [`trace_pixel`] instead). The dither takes precedence over
/// `params.sampler`.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn trace_pixel_dithered(
    params: &TraceParams,
    pixel: UVec2,
    seed: u32,
    dither: Vec2,
    nodes: &[BvhNodeGpu],
    triangles: &[TriangleGpu],
    materials: &[MaterialGpu],
    emitters: &[EmitterGpu],
    attrs: &[TriangleAttrGpu],
    images: &[u32],
    environment: &[f32],
) -> Vec4 {
    let dithered = params.seed_mode == SEED_MODE_BLUE_NOISE_DITHER;
    if !dithered {
        return trace_pixel(
            params,
            pixel,
            seed,
            &[],
            nodes,
            triangles,
            materials,
            emitters,
            attrs,
            images,
            environment,
        );
    }
    let spp = params.spp.max(1);
    let mut sum = Vec3::ZERO;
    let mut s = 0u32;
    while s < spp {
        // R2 rotation in 0.32 fixed point (sampler_core's walk constants), so
        // the value stays exact for any sample index.
        let rx = s.wrapping_mul(0xC13F_A9A9) as f32 * (1.0 / 4_294_967_296.0);
        let ry = s.wrapping_mul(0x91E1_0DA6) as f32 * (1.0 / 4_294_967_296.0);
        let stream = RandomStream::new(seed, stream_sample(params, s), DIMS_PER_SAMPLE);
        let numbers = PathNumbers::from_stream(stream, pixel)
            .with_first_bsdf(Vec2::new(frac01(dither.x + rx), frac01(dither.y + ry)));
        let mut rays = 0u32;
        sum += trace_sample_with::<{ crate::trace_variant::FULL }>(
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
        );
        s += 1;
    }
    (sum / spp as f32).extend(1.0)
}

/// `x - floor(x)` for `x >= 0`, clamped below 1 (f32 rounding of values just
/// under an integer).
#[inline]
fn frac01(x: f32) -> f32 {
    let f = x - (x as u32) as f32;
    if f < 1.0 {
        f
    } else {
        0.999_999_94
    }
}
