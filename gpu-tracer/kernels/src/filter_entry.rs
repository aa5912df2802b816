//! The `#[spirv]` entry points of the real-time filters
//! ([`crate::filters`]): one invocation per pixel (linear index, dispatch
//! `linear_dispatch(width * height)` of [`crate::permute_entry`]), each
//! reading one buffer and writing another (no pass reads what it writes).
//!
//! Bindings (descriptor set 0; binding 0 is always the [`FilterParams`]
//! uniform; colours `[Vec4]`, `width * height`):
//!
//! | entry | 1 | 2 | 3 | 4 |
//! |---|---|---|---|---|
//! | [`DEMODULATE_ENTRY`] | colour | G-buffer `[GBufferGpu]` | out | |
//! | [`REMODULATE_ENTRY`] | illumination | G-buffer | out | |
//! | [`TAA_ENTRY`] | current | history | motion `[Vec2]` | out |
//! | [`GAUSS_ENTRY`] | source | out | | |
//! | [`VARIANCE_ENTRY`] | colour | G-buffer | out | |
//! | [`ATROUS_ENTRY`] | source | G-buffer | out | |

use crate::abi::GBufferGpu;
use crate::filters::atrous::{atrous_pixel, variance_pixel};
use crate::filters::demodulate::{demodulate, remodulate};
use crate::filters::gauss::gauss_pass_pixel;
use crate::filters::taa::taa_pixel;
use crate::filters::FilterParams;
use crate::permute_entry::linear_id;
use glam::{UVec3, Vec2, Vec4};
use spirv_std::spirv;

/// Entry point name of [`demodulate_cs`].
pub const DEMODULATE_ENTRY: &str = "filter_entry::demodulate_cs";
/// Entry point name of [`remodulate_cs`].
pub const REMODULATE_ENTRY: &str = "filter_entry::remodulate_cs";
/// Entry point name of [`taa_cs`].
pub const TAA_ENTRY: &str = "filter_entry::taa_cs";
/// Entry point name of [`gauss_cs`].
pub const GAUSS_ENTRY: &str = "filter_entry::gauss_cs";
/// Entry point name of [`variance_cs`].
pub const VARIANCE_ENTRY: &str = "filter_entry::variance_cs";
/// Entry point name of [`atrous_cs`].
pub const ATROUS_ENTRY: &str = "filter_entry::atrous_cs";

/// `out = colour / albedo` ([`demodulate`]).
#[spirv(compute(threads(64)))]
pub fn demodulate_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FilterParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] color: &[Vec4],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] gbuffer: &[GBufferGpu],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] out: &mut [Vec4],
) {
    let n = linear_id(id);
    if n < params.width.wrapping_mul(params.height) {
        let i = n as usize;
        out[i] = demodulate(color[i], gbuffer[i].albedo.truncate());
    }
}

/// `out = illumination * albedo` with `w = 1` ([`remodulate`]).
#[spirv(compute(threads(64)))]
pub fn remodulate_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FilterParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] illumination: &[Vec4],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] gbuffer: &[GBufferGpu],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] out: &mut [Vec4],
) {
    let n = linear_id(id);
    if n < params.width.wrapping_mul(params.height) {
        let i = n as usize;
        out[i] = remodulate(illumination[i], gbuffer[i].albedo.truncate())
            .truncate()
            .extend(1.0);
    }
}

/// [`taa_pixel`].
#[spirv(compute(threads(64)))]
pub fn taa_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FilterParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] current: &[Vec4],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] history: &[Vec4],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] motion: &[Vec2],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] out: &mut [Vec4],
) {
    let n = linear_id(id);
    if n < params.width.wrapping_mul(params.height) {
        let (x, y, i) = (n % params.width, n / params.width, n as usize);
        out[i] = taa_pixel(params, x, y, current, history, motion);
    }
}

/// [`gauss_pass_pixel`] (`params.step` = axis).
#[spirv(compute(threads(64)))]
pub fn gauss_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FilterParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] src: &[Vec4],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] out: &mut [Vec4],
) {
    let n = linear_id(id);
    if n < params.width.wrapping_mul(params.height) {
        let (x, y, i) = (n % params.width, n / params.width, n as usize);
        out[i] = gauss_pass_pixel(params, x, y, src);
    }
}

/// [`variance_pixel`].
#[spirv(compute(threads(64)))]
pub fn variance_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FilterParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] color: &[Vec4],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] gbuffer: &[GBufferGpu],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] out: &mut [Vec4],
) {
    let n = linear_id(id);
    if n < params.width.wrapping_mul(params.height) {
        let (x, y, i) = (n % params.width, n / params.width, n as usize);
        out[i] = variance_pixel(params, x, y, color, gbuffer);
    }
}

/// [`atrous_pixel`] (`params.step` = tap distance).
#[spirv(compute(threads(64)))]
pub fn atrous_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &FilterParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] src: &[Vec4],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] gbuffer: &[GBufferGpu],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] out: &mut [Vec4],
) {
    let n = linear_id(id);
    if n < params.width.wrapping_mul(params.height) {
        let (x, y, i) = (n % params.width, n / params.width, n as usize);
        out[i] = atrous_pixel(params, x, y, src, gbuffer);
    }
}
