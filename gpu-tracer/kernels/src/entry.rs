//! The `#[spirv]` compute entry points: thin wrappers that index buffers and
//! call the plain functions the CPU renderer also uses. Bindings are listed
//! in [`crate::abi`].

use crate::abi::{
    BvhNodeGpu, EmitterGpu, GBufferGpu, MaterialGpu, TraceParams, TriangleAttrGpu, TriangleGpu,
};
use crate::accumulate::accumulate_pixel;
use crate::gbuffer::gbuffer_pixel_variant;
use crate::motion::{frame_follows, reprojection_motion_pixel, seed_motion, visibility};
use crate::pan_offset::{
    advance_offset, pixel_contribution, region_word, sum_region, FRAME_OFFSET_X, FRAME_OFFSET_Y, FRAME_RIGID,
    REGION_SAMPLED, REGION_SUM_X, REGION_SUM_Y,
};
use crate::surface_features::{demodulated_intensity, surface_feature};
use crate::trace::trace_pixel_variant;
use crate::trace_variant;
use glam::{UVec2, UVec3, Vec2, Vec4};
use sampler_core::SurfaceFeature;
use spirv_std::arch::atomic_i_add;
use spirv_std::memory::{Scope, Semantics};
use spirv_std::spirv;

/// Defines a trace entry point: one invocation per visible pixel `(id.x,
/// id.y)`; writes the frame colour of the pixel's seed, traced by the
/// variant of feature set `$features` ([`trace_pixel_variant`]), with the
/// a-priori samplers' keys of binding 7. Invocations outside the frame do
/// nothing. Every variant has the same bindings
/// ([`TRACE_ENTRY`](crate::abi::TRACE_ENTRY)'s).
macro_rules! trace_entry {
    ($(#[$doc:meta])* $name:ident, $features:expr) => {
        $(#[$doc])*
        #[allow(clippy::too_many_arguments)]
        #[spirv(compute(threads(8, 8)))]
        pub fn $name(
            #[spirv(global_invocation_id)] id: UVec3,
            #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &TraceParams,
            #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] nodes: &[BvhNodeGpu],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] triangles: &[TriangleGpu],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] materials: &[MaterialGpu],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] emitters: &[EmitterGpu],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] seeds: &[u32],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 6)] color: &mut [Vec4],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 7)] keys: &[u32],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 8)] attrs: &[TriangleAttrGpu],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 9)] images: &[u32],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 10)] environment: &[f32],
        ) {
            if id.x >= params.width || id.y >= params.height {
                return;
            }
            let seed = seeds[id.y.wrapping_mul(params.padded_width).wrapping_add(id.x) as usize];
            let value = trace_pixel_variant::<{ $features }>(
                params,
                UVec2::new(id.x, id.y),
                seed,
                keys,
                nodes,
                triangles,
                materials,
                emitters,
                attrs,
                images,
                environment,
            );
            color[id.y.wrapping_mul(params.width).wrapping_add(id.x) as usize] = value;
        }
    };
}

trace_entry!(
    /// [`TRACE_ENTRY`](crate::abi::TRACE_ENTRY): the full trace kernel,
    /// `trace_pixel(...)` per pixel, for any scene.
    trace_cs,
    trace_variant::FULL
);

trace_entry!(
    /// [`TRACE_UNTEXTURED_ENTRY`](crate::abi::TRACE_UNTEXTURED_ENTRY): the
    /// untextured variant ([`crate::trace_variant`]): on a scene that fits
    /// it, [`trace_cs`]'s colours bit for bit.
    trace_untextured_cs,
    trace_variant::UNTEXTURED
);

trace_entry!(
    /// [`TRACE_BASIC_ENTRY`](crate::abi::TRACE_BASIC_ENTRY): the basic
    /// variant ([`crate::trace_variant`]): on a scene that fits it,
    /// [`trace_cs`]'s colours bit for bit.
    trace_basic_cs,
    trace_variant::BASIC
);

/// [`ACCUMULATE_ENTRY`](crate::abi::ACCUMULATE_ENTRY): one invocation per
/// visible pixel; folds frame `params.frame`'s colour into the running mean
/// (`accumulate_pixel`). Invocations outside the frame do nothing.
#[spirv(compute(threads(8, 8)))]
pub fn accumulate_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &TraceParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] color: &[Vec4],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] accum: &mut [Vec4],
) {
    if id.x >= params.width || id.y >= params.height {
        return;
    }
    let i = id.y.wrapping_mul(params.width).wrapping_add(id.x) as usize;
    accum[i] = accumulate_pixel(accum[i], color[i], params.frame);
}

/// Defines a G-buffer entry point: one invocation per visible pixel;
/// writes `gbuffer_pixel_variant::<$features>(...)`. Invocations outside
/// the frame do nothing. Both variants have the same bindings
/// ([`GBUFFER_ENTRY`](crate::abi::GBUFFER_ENTRY)'s).
macro_rules! gbuffer_entry {
    ($(#[$doc:meta])* $name:ident, $features:expr) => {
        $(#[$doc])*
        #[allow(clippy::too_many_arguments)]
        #[spirv(compute(threads(8, 8)))]
        pub fn $name(
            #[spirv(global_invocation_id)] id: UVec3,
            #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &TraceParams,
            #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] nodes: &[BvhNodeGpu],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] triangles: &[TriangleGpu],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] materials: &[MaterialGpu],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] attrs: &[TriangleAttrGpu],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] images: &[u32],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 6)] previous: &[TriangleGpu],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 7)] gbuffer: &mut [GBufferGpu],
        ) {
            if id.x >= params.width || id.y >= params.height {
                return;
            }
            gbuffer[id.y.wrapping_mul(params.width).wrapping_add(id.x) as usize] =
                gbuffer_pixel_variant::<{ $features }>(
                    params,
                    UVec2::new(id.x, id.y),
                    nodes,
                    triangles,
                    materials,
                    attrs,
                    images,
                    previous,
                );
        }
    };
}

gbuffer_entry!(
    /// [`GBUFFER_ENTRY`](crate::abi::GBUFFER_ENTRY): `gbuffer_pixel(...)`
    /// per pixel, for any scene.
    gbuffer_cs,
    trace_variant::FULL
);

gbuffer_entry!(
    /// [`GBUFFER_UNTEXTURED_ENTRY`](crate::abi::GBUFFER_UNTEXTURED_ENTRY):
    /// the G-buffer without texture lookups or cut-outs
    /// (`gbuffer_pixel_variant`): on a scene without them, [`gbuffer_cs`]'s
    /// texels bit for bit.
    gbuffer_untextured_cs,
    trace_variant::UNTEXTURED
);

/// [`RIGID_COUNT_ENTRY`](crate::abi::RIGID_COUNT_ENTRY): one invocation
/// per visible pixel; adds the pixel's contribution
/// (`pan_offset::pixel_contribution`: 1 to the rigid count when it moves
/// rigidly, and on the sum grid 1 to its screen region's sampled count and
/// its fixed-point motion to the region's sums) to the frame-motion buffer's first
/// `FRAME_CLEARED_WORDS` words (cleared by the host before the pass), for
/// the motion pass's frame-wide rule (`frame_follows`) and
/// [`pan_offset_cs`]. Runs
/// only when [`TraceParams::seed_follow_share`] is not 0. Invocations
/// outside the frame do nothing.
#[spirv(compute(threads(8, 8)))]
pub fn rigid_count_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &TraceParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] gbuffer: &[GBufferGpu],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] frame: &mut [u32],
) {
    if id.x >= params.width || id.y >= params.height {
        return;
    }
    let c = pixel_contribution(gbuffer, id.x, id.y, params.width, params.height);
    if c[0] != 0 {
        add(frame, FRAME_RIGID, 1);
    }
    if c[1] != 0 {
        let r = sum_region(id.x, id.y, params.width, params.height);
        add(frame, region_word(r, REGION_SAMPLED), 1);
        add(frame, region_word(r, REGION_SUM_X), c[2]);
        add(frame, region_word(r, REGION_SUM_Y), c[3]);
    }
}

/// Atomically adds `value` (wrapping) to `words[i]`.
#[inline]
fn add(words: &mut [u32], i: usize, value: u32) {
    // SAFETY: an atomic on one element of a storage buffer. Queue-family
    // scope and no ordering, as the reprojection's claims: the sums are read
    // only by the next dispatch, after a barrier, and an integer sum does
    // not depend on the order of the additions.
    unsafe {
        atomic_i_add::<u32, { Scope::QueueFamily as u32 }, { Semantics::NONE.bits() }>(&mut words[i], value);
    }
}

/// [`MOTION_ENTRY`](crate::abi::MOTION_ENTRY): one invocation per visible
/// pixel; writes the pixel's visibility for the next frame and its
/// reprojection motion against the previous frame's visibility
/// (`reprojection_motion_pixel`), zero where the surface moved less than
/// [`TraceParams::seed_hold_below`] unless the frame follows as a whole
/// (`seed_motion`, `frame_follows` of the frame-motion buffer's rigid
/// count, from [`rigid_count_cs`]; not read when
/// [`TraceParams::seed_follow_share`] is 0). Invocations outside the frame
/// do nothing.
#[spirv(compute(threads(8, 8)))]
pub fn motion_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &TraceParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] gbuffer: &[GBufferGpu],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] previous: &[UVec2],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] current: &mut [UVec2],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] motion: &mut [Vec2],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] frame: &[u32],
) {
    if id.x >= params.width || id.y >= params.height {
        return;
    }
    let i = id.y.wrapping_mul(params.width).wrapping_add(id.x) as usize;
    let g = gbuffer[i];
    current[i] = visibility(&g);
    let m = reprojection_motion_pixel(&g, id.x, id.y, params.width, params.height, previous);
    let share = params.seed_follow_share;
    let pixels = params.width.wrapping_mul(params.height);
    let follows_all = share > 0.0 && frame_follows(frame[FRAME_RIGID], pixels, share);
    motion[i] = seed_motion(&g, m, params.seed_hold_below, follows_all);
}

/// [`PAN_OFFSET_ENTRY`](crate::abi::PAN_OFFSET_ENTRY): one invocation (one
/// workgroup of one) after [`rigid_count_cs`]; advances the pan offset in
/// the frame-motion buffer (`pan_offset::advance_offset` of the count's
/// words with [`TraceParams::seed_follow_share`]; the host then copies it
/// into the parameters for the trace). A pass of its own: inside the
/// per-pixel motion pass the regions' loop, masked off everywhere but at
/// one pixel, still cost every SIMD group of a CPU Vulkan driver its
/// divisions (lavapipe: 8 ms of a 720p frame; BENCHMARKS.md).
#[spirv(compute(threads(1)))]
pub fn pan_offset_cs(
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &TraceParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] frame: &mut [u32],
) {
    let pixels = params.width.wrapping_mul(params.height);
    let o = advance_offset(
        [frame[FRAME_OFFSET_X], frame[FRAME_OFFSET_Y]],
        frame,
        pixels,
        params.seed_follow_share,
    );
    frame[FRAME_OFFSET_X] = o[0];
    frame[FRAME_OFFSET_Y] = o[1];
}

/// [`FEATURES_ENTRY`](crate::abi::FEATURES_ENTRY): one invocation per
/// visible pixel; writes the pixel's surface feature and demodulated sort
/// key for the feature-aware permutation (`surface_feature`,
/// `demodulated_intensity`). Invocations outside the frame do nothing.
#[spirv(compute(threads(8, 8)))]
pub fn features_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] params: &TraceParams,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] gbuffer: &[GBufferGpu],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] color: &[Vec4],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] features: &mut [SurfaceFeature],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] intensity: &mut [f32],
) {
    if id.x >= params.width || id.y >= params.height {
        return;
    }
    let i = id.y.wrapping_mul(params.width).wrapping_add(id.x) as usize;
    let g = gbuffer[i];
    features[i] = surface_feature(&g);
    intensity[i] = demodulated_intensity(color[i], &g);
}
