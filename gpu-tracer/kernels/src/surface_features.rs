//! The feature-aware permutation's inputs from the tracer's G-buffer: a
//! `sampler_core::SurfaceFeature` and a demodulated sort key per pixel.
//! The CPU renderer and the GPU's feature pass call the same functions.

use crate::abi::{GBufferGpu, GBUFFER_HIT};
use glam::{Vec3, Vec4};
use sampler_core::{demodulated_luma, SurfaceFeature};

/// The surface feature of a G-buffer texel: its object id, linear depth and
/// normal, or `SurfaceFeature::none()` without a hit.
#[inline]
pub fn surface_feature(g: &GBufferGpu) -> SurfaceFeature {
    if g.ids.w & GBUFFER_HIT == 0 {
        SurfaceFeature::none()
    } else {
        SurfaceFeature::new(g.ids.x, g.normal_depth.w, g.normal_depth.truncate())
    }
}

/// The sort key of a pixel of colour `color` whose primary hit is `g`: the
/// colour's luma divided by the hit's albedo luma
/// (`sampler_core::demodulated_luma`; no division without a hit or below
/// the albedo floor).
#[inline]
pub fn demodulated_intensity(color: Vec4, g: &GBufferGpu) -> f32 {
    let albedo = if g.ids.w & GBUFFER_HIT == 0 {
        Vec3::ZERO
    } else {
        g.albedo.truncate()
    };
    demodulated_luma(color.truncate(), albedo)
}
