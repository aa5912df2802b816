//! The `#[spirv]` entry points of the a-priori screen-space samplers, for
//! renderers that take their numbers from a buffer rather than calling
//! `sampler_core` in their own shaders: one invocation per pixel writes the
//! pixel's 2D sample for one sample index and one dimension pair. The same
//! functions ([`screen_sobol_pair`], [`zsobol_pair`]) give the tracer its
//! a-priori pairs ([`crate::numbers::apriori_pair`]), so the generated
//! shaders and the tracer agree bit for bit.
//!
//! Bindings (descriptor set 0), dispatch `linear_dispatch(width * height)`:
//!
//! | entry | 0 | 1 | 2 |
//! |---|---|---|---|
//! | [`SCREEN_SOBOL_ENTRY`] | [`SamplerParams`] (uniform) | keys `[u32]` (`sampler_core::defaults::screen_sobol_keys()`) | samples `[Vec2]` (out, `width * height`) |
//! | [`ZSOBOL_ENTRY`] | [`SamplerParams`] (uniform) | samples `[Vec2]` (out, `width * height`) | |
//! | [`SPATIOTEMPORAL_ENTRY`] | [`SamplerParams`] (uniform; `key_side_log2` = the shift tile's side, 6 for `sampler_core::defaults::tile_64()`) | shift tile `[u32]` (ranks, `4^key_side_log2`) | samples `[Vec2]` (out, `width * height`) |

use crate::permute_entry::linear_id;
use glam::{UVec2, UVec3, Vec2};
use sampler_core::sequences::r2::q32_to_f32;
use sampler_core::sequences::screen_sobol::{screen_sobol_pair_u32, ScreenSobolLayout};
use sampler_core::sequences::spatiotemporal::{
    spatiotemporal_pair_u32, spatiotemporal_shift_u32, SEQUENCE_SOBOL,
};
use sampler_core::sequences::walk::walk_offset;
use sampler_core::sequences::zsobol::{zsobol_frame_pair_u32, ZSOBOL_MAX_LOG2_SPP};
use spirv_std::spirv;

/// Entry point name of [`screen_sobol_cs`].
pub const SCREEN_SOBOL_ENTRY: &str = "sampler_entry::screen_sobol_cs";
/// Entry point name of [`zsobol_cs`].
pub const ZSOBOL_ENTRY: &str = "sampler_entry::zsobol_cs";
/// Entry point name of [`spatiotemporal_cs`].
pub const SPATIOTEMPORAL_ENTRY: &str = "sampler_entry::spatiotemporal_cs";

/// The uniform of the sampler entry points, 48 bytes (twelve `u32`, the
/// same in std140 and std430).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct SamplerParams {
    /// Image width in pixels (`>= 1`); `samples` is row-major with this stride.
    pub width: u32,
    /// Image height in pixels (`>= 1`).
    pub height: u32,
    /// Samples per pixel of the frame (`0` reads as 1): screen-space Sobol
    /// reads its keys' level `ceil(log2 spp)`, ZSobol stratifies
    /// `2^ceil(log2 spp)` samples (at most 256).
    pub spp: u32,
    /// Which of the pixel's samples, `0..spp`.
    pub sample_index: u32,
    /// Dimension pair: the sample's dimensions `2 pair` and `2 pair + 1`.
    pub pair: u32,
    /// Frame index: screen-space Sobol reads its keys at
    /// `pixel + sampler_core::walk_offset(frame, key_side_log2)` (the walk
    /// that also moves the dither tile); ZSobol's scramble seed.
    pub frame: u32,
    /// `sampler_core::ScreenSobolLayout::side_log2` of the key buffer
    /// (screen-space Sobol only).
    pub key_side_log2: u32,
    /// `ScreenSobolLayout::pairs` of the key buffer (`0` reads as 1).
    pub key_pairs: u32,
    /// `ScreenSobolLayout::levels` of the key buffer (`0` reads as 1).
    pub key_levels: u32,
    /// Zero.
    pub reserved0: u32,
    /// Zero.
    pub reserved1: u32,
    /// Zero.
    pub reserved2: u32,
}

const _: () = assert!(core::mem::size_of::<SamplerParams>() == 48);

/// Pair `pair` of sample `s` of `pixel` from the screen-space Sobol keys
/// `keys` laid out as `layout`, at `spp` samples per pixel, in frame `frame`
/// (keys read at `pixel + walk_offset(frame, layout.side_log2)`, wrapping
/// toroidally); each coordinate in `[0, 1)` (24 bits).
#[inline]
pub fn screen_sobol_pair(
    keys: &[u32],
    layout: ScreenSobolLayout,
    spp: u32,
    frame: u32,
    pixel: UVec2,
    s: u32,
    pair: u32,
) -> Vec2 {
    // Wrapping: `key_index` keeps only the low `side_log2` bits.
    let o = walk_offset(frame, layout.side_log2);
    let shifted = UVec2::new(pixel.x.wrapping_add(o.x), pixel.y.wrapping_add(o.y));
    let v = screen_sobol_pair_u32(keys, layout, spp, shifted, s, pair);
    Vec2::new(q32_to_f32(v[0]), q32_to_f32(v[1]))
}

/// Pair `pair` of sample `s` of `pixel` in frame `frame` from ZSobol with
/// `2^ceil(log2 spp)` samples per pixel (at most 256), its frames progressive
/// (`sampler_core::zsobol_frame_sample_u32`: one point set, digitally shifted
/// by a (0, 2)-sequence from frame to frame); each coordinate in `[0, 1)`
/// (24 bits).
#[inline]
pub fn zsobol_pair(spp: u32, frame: u32, pixel: UVec2, s: u32, pair: u32) -> Vec2 {
    let mut log2_spp = 0u32;
    while log2_spp < ZSOBOL_MAX_LOG2_SPP && (1u32 << log2_spp) < spp {
        log2_spp += 1;
    }
    let v = zsobol_frame_pair_u32(pixel, s, pair, log2_spp, frame);
    Vec2::new(q32_to_f32(v[0]), q32_to_f32(v[1]))
}

/// Pair `pair` of sample `s` of `pixel` in frame `frame` at `spp` samples
/// per pixel from the spatiotemporal sampler
/// (`sampler_core::sequences::spatiotemporal`) with its Sobol sequence
/// (`SEQUENCE_SOBOL`; the trace kernel also offers the Kronecker one,
/// `crate::abi::SAMPLER_KRONECKER`), its shift read from the
/// `2^side_log2`-sided rank tile `tile` (pair 0's computed instead:
/// `spatiotemporal::net_shift_u32`); each coordinate in `[0, 1)` (24
/// bits). Pass a pixel's home (`spatiotemporal::home_texel`) as `pixel` to
/// have its shift follow the picture.
#[inline]
pub fn spatiotemporal_pair(
    tile: &[u32],
    side_log2: u32,
    spp: u32,
    frame: u32,
    pixel: UVec2,
    s: u32,
    pair: u32,
) -> Vec2 {
    let shift = spatiotemporal_shift_u32(tile, side_log2, pixel, pair);
    let v = spatiotemporal_pair_u32(SEQUENCE_SOBOL, shift, frame, spp, s, pair);
    Vec2::new(q32_to_f32(v[0]), q32_to_f32(v[1]))
}

/// The key layout `params` names (zero counts read as 1).
#[inline]
pub fn key_layout(params: &SamplerParams) -> ScreenSobolLayout {
    ScreenSobolLayout {
        side_log2: params.key_side_log2,
        pairs: params.key_pairs.max(1),
        levels: params.key_levels.max(1),
        pad: 0,
    }
}

/// One invocation per pixel (linear index): [`screen_sobol_pair`].
#[spirv(compute(threads(64)))]
pub fn screen_sobol_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &SamplerParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] keys: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] samples: &mut [Vec2],
) {
    let i = linear_id(id);
    if i < params.width.wrapping_mul(params.height) {
        let pixel = UVec2::new(i % params.width, i / params.width);
        let spp = params.spp.max(1);
        samples[i as usize] = screen_sobol_pair(
            keys,
            key_layout(params),
            spp,
            params.frame,
            pixel,
            params.sample_index,
            params.pair,
        );
    }
}

/// One invocation per pixel (linear index): [`zsobol_pair`].
#[spirv(compute(threads(64)))]
pub fn zsobol_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &SamplerParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] samples: &mut [Vec2],
) {
    let i = linear_id(id);
    if i < params.width.wrapping_mul(params.height) {
        let pixel = UVec2::new(i % params.width, i / params.width);
        let spp = params.spp.max(1);
        samples[i as usize] = zsobol_pair(spp, params.frame, pixel, params.sample_index, params.pair);
    }
}

/// One invocation per pixel (linear index): [`spatiotemporal_pair`] with the
/// tile side `params.key_side_log2` (1..=15).
#[spirv(compute(threads(64)))]
pub fn spatiotemporal_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &SamplerParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] tile: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] samples: &mut [Vec2],
) {
    let i = linear_id(id);
    if i < params.width.wrapping_mul(params.height) {
        let pixel = UVec2::new(i % params.width, i / params.width);
        samples[i as usize] = spatiotemporal_pair(
            tile,
            params.key_side_log2,
            params.spp.max(1),
            params.frame,
            pixel,
            params.sample_index,
            params.pair,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pairs_are_the_samplers_dimensions() {
        let layout = ScreenSobolLayout::new(16, 3, 4).unwrap();
        let raw: Vec<u32> = (0..layout.key_count() as u32)
            .map(sampler_core::sequences::seed::hash_u32)
            .collect();
        let keys = sampler_core::ScreenSobolKeys::new(layout, &raw).unwrap();
        for (pixel, s, pair, frame) in [(UVec2::new(3, 5), 0, 0, 0), (UVec2::new(70, 1), 3, 2, 9)] {
            let o = walk_offset(frame, layout.side_log2);
            let at = pixel + o;
            let v = screen_sobol_pair(keys.keys(), layout, 4, frame, pixel, s, pair);
            assert_eq!(
                v,
                Vec2::new(
                    keys.sample(at, s, 2 * pair, 4),
                    keys.sample(at, s, 2 * pair + 1, 4)
                )
            );
            let z = zsobol_pair(4, frame, pixel, s, pair);
            let q = |d| {
                sampler_core::sequences::r2::q32_to_f32(sampler_core::zsobol_frame_sample_u32(
                    pixel, s, d, 2, frame,
                ))
            };
            assert_eq!(z.x, q(2 * pair));
            assert_eq!(z.y, q(2 * pair + 1));
        }
    }
}
