//! Compute kernels of the tracer: thin `#[spirv]` entry points ([`entry`])
//! over plain functions that also run on the host, where they make the CPU
//! renderer.
//!
//! # Guide
//!
//! - [`abi`]: every buffer structure shared with the host, the binding
//!   table, and the entry-point names.
//! - [`camera`] primary rays, [`intersect`] ray-triangle and ray-box tests,
//!   [`bvh`] BVH2 traversal, [`sampling`] warps, [`numbers`] where a path's numbers come
//!   from (seed stream or a-priori sampler), [`trace`] the path tracer
//!   ([`trace_pixel`] is what the trace entry point runs per pixel,
//!   [`trace_variant`] its basic variant for plain scenes),
//!   [`lights`] next-event estimation's emitter choice and light samples
//!   (emissive triangles, point, spot and directional lights),
//!   [`geometry`] triangle normals and ray offsets, [`mis`] the power heuristic,
//!   [`environment`] what rays leaving the scene see, [`accumulate`] the running mean, [`texture`] image lookup, [`texture_filter`] lookups filtered over a
//!   pixel's footprint (mip maps), [`footprint`] that footprint at a camera ray's first hit,
//!   [`surface`] textured albedo and emission, [`vertex_normal`] smooth
//!   shading normals from vertex normals, [`normal_map`] tangent
//!   frames and normal-mapped shading normals, [`bsdf`] the reflectance
//!   models (GGX microfacets and the glTF metallic-roughness BRDF, not yet
//!   used by [`trace`]), [`gbuffer`] the G-buffer and
//!   motion vectors ([`gbuffer::gbuffer_pixel`]), [`motion`] the motion vectors
//!   the seed reprojection takes (disocclusion marked), [`surface_features`]
//!   the feature-aware permutation's per-pixel features and sort keys,
//!   [`filters`] the real-time filters after the frame (TAA, Gaussian, a-trous).
//! - Entry points: [`entry`] (tracer), [`permute_entry`] (seed permutation),
//!   [`reproject_entry`] (seed reprojection), [`sampler_entry`] (the
//!   a-priori samplers, one pair per pixel), [`filter_entry`] (the real-time
//!   filters).
//!
//! Everything reachable from an entry point follows rust-gpu's rules:
//! `u32`/`f32` arithmetic (`wrapping_*` on integers), fixed-size local
//! arrays, no allocation, recursion or function pointers, `libm` for scalar
//! math.
//!
//! ```
//! use kernels::{abi::*, trace::trace_pixel};
//! use glam::{UVec2, UVec4, Vec4};
//! // One emissive triangle filling the view: a camera ray sees its emission.
//! let tri = TriangleGpu {
//!     v0: Vec4::new(-10.0, -10.0, -1.0, 0.0),
//!     v1: Vec4::new(10.0, -10.0, -1.0, 0.0),
//!     v2: Vec4::new(0.0, 10.0, -1.0, 0.0),
//! };
//! let node = BvhNodeGpu { min: Vec4::new(-10.0, -10.0, -1.0, 0.0), max: Vec4::new(10.0, 10.0, -1.0, 0.0), info: UVec4::new(1, 0, 0, 0) };
//! let material = MaterialGpu::untextured(Vec4::ZERO, Vec4::new(2.0, 1.0, 0.5, 0.0));
//! let params = TraceParams {
//!     width: 4, height: 4, padded_width: 4, spp: 1, max_depth: 4, node_count: 1, triangle_count: 1,
//!     rr_depth: 3, tan_half_fov_y: 0.5,
//!     camera_forward: Vec4::new(0.0, 0.0, -1.0, 0.0), camera_right: Vec4::X, camera_up: Vec4::Y,
//!     ..Default::default()
//! };
//! let attrs = [TriangleAttrGpu::default()];
//! let c = trace_pixel(&params, UVec2::new(1, 2), 12345, &[], &[node], &[tri], &[material], &[EmitterGpu::NONE], &attrs, &[0], &[0.0]);
//! assert_eq!(c, Vec4::new(2.0, 1.0, 0.5, 1.0));
//! ```
#![cfg_attr(target_arch = "spirv", no_std)]
#![warn(missing_docs)]

pub mod abi;
pub mod accumulate;
pub mod bsdf;
pub mod bvh;
pub mod camera;
pub mod dither;
pub mod entry;
pub mod environment;
pub mod filter_entry;
pub mod filters;
pub mod footprint;
pub mod gbuffer;
pub mod geometry;
pub mod intersect;
pub mod lights;
pub mod mis;
pub mod motion;
pub mod normal_map;
pub mod numbers;
pub mod pan_offset;
pub mod permute_entry;
pub mod regularization;
pub mod reproject_entry;
pub mod sampler_entry;
pub mod sampling;
pub mod shading;
pub mod surface;
pub mod surface_features;
pub mod texture;
pub mod texture_filter;
pub mod trace;
pub mod trace_variant;
pub mod vertex_normal;

pub use accumulate::accumulate_pixel;
pub use gbuffer::gbuffer_pixel;
pub use trace::{
    trace_pixel, trace_pixel_counted_variant, trace_pixel_variant, trace_sample, DIMS_PER_SAMPLE,
};
