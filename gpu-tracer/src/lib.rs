//! Host side of the path tracer: scenes (the built-in Cornell box, OBJ and
//! glTF files), their BVH and buffer form, what moves between frames, the
//! CPU renderer that runs the kernels' own functions, the wgpu passes, the
//! real-time filters and image output.
//!
//! # Guide
//!
//! Scenes:
//! - [`scene`]: [`Scene`] (triangles, materials, camera), its buffer form
//!   for the kernels [`SceneGpu`], and the trace pass's [`TraceSettings`].
//! - [`bvh`]: [`bvh::build_bvh`] builds the BVH of a scene with obvhs.
//! - [`cornell`]: [`cornell::cornell_box`], the built-in Cornell box, and
//!   its glossy twin; [`outdoor`]: [`outdoor::sun_and_sky`], objects on open
//!   ground under a sun and a sky.
//! - [`obj`]: [`obj::load_obj`] loads a Wavefront OBJ file and its MTL.
//! - [`environment_file`]: [`environment_file::load_environment_map`] reads an
//!   equirectangular `.exr` or `.hdr` environment map.
//! - [`gltf`]: [`gltf::load_gltf`] loads a glTF 2.0 file (`.gltf` or
//!   `.glb`): meshes, materials, textures, camera and animation.
//!
//! What moves:
//! - [`animation`]: the node hierarchy and keyframe channels of a scene
//!   ([`animation::Rig`]), posed at any time by [`animation::Rig::pose`].
//! - [`camera_path`]: simple camera paths ([`camera_path::CameraPath`])
//!   that move the camera of any scene.
//! - [`timeline`]: what moves between frames ([`timeline::Timeline`]) and
//!   the scene of each frame with its motion ([`timeline::SceneSequence`]).
//!
//! Rendering:
//! - [`sampler_data`]: the a-priori samplers' keys and shift tile, as the
//!   trace kernel reads them ([`sampler_data::sampler_buffer`]).
//! - [`cpu`]: [`cpu::render_frame`] traces a frame with rayon over rows by
//!   calling `kernels::trace_pixel`, exactly what the GPU's `trace_cs` runs
//!   per pixel; [`cpu::accumulate_frame`] is the running mean.
//! - [`gpu`]: the wgpu side: the device ([`gpu::Gpu`]) and one struct per
//!   group of GPU passes (trace, permute, reproject, filter).
//! - [`feature_keys`]: what the feature-aware seed permutation sorts, per
//!   pixel, on the CPU ([`feature_keys::FeatureKeys`]).
//! - [`motion`]: the motion vectors of the seed reprojection on the CPU.
//! - [`method_choice`]: the permutation mode and sampler a render takes
//!   when its caller names none ([`method_choice::choose_method`]: the
//!   temporal permutation with ZSobol's pixel jitter, or behind a history
//!   without TAA's clamp the spatiotemporal sampler).
//! - [`render`]: the temporal render loop on the CPU or the GPU
//!   ([`render_sequence_cpu`], [`render_sequence_gpu`]), with the G-buffer
//!   and motion vectors of `kernels::gbuffer` when asked.
//! - [`filter`]: the real-time filters after a frame on the CPU
//!   ([`filter::FrameFilter`]: TAA, Gaussian, a-trous, TAA + a-trous) with
//!   the kernels' per-pixel filter functions.
//!
//! Output:
//! - [`image_out`]: tone-mapped PNG and linear EXR, written atomically.
//! - [`aov`]: the G-buffer as EXR images for a compositor or a denoiser.
//! - [`error`]: the crate's [`Error`].
//!
//! ```
//! use gpu_tracer::{cornell::cornell_box, cpu, scene::{SceneGpu, TraceSettings}};
//! use glam::Vec4;
//! let scene = SceneGpu::build(&cornell_box()).unwrap();
//! let params = scene.trace_params(&TraceSettings::new(8, 8), 0).unwrap();
//! let seeds: Vec<u32> = (0..64).collect();
//! let mut color = vec![Vec4::ZERO; 64];
//! cpu::render_frame(&scene, &params, &seeds, &mut color).unwrap();
//! assert!(color.iter().all(|c| c.is_finite() && c.min_element() >= 0.0 && c.w == 1.0));
//! ```
#![warn(missing_docs)]

pub mod animation;
pub mod aov;
pub mod bvh;
pub mod camera_path;
pub mod cornell;
pub mod cpu;
pub mod environment_file;
pub mod error;
pub mod feature_keys;
pub mod filter;
pub mod gltf;
pub mod gpu;
pub mod image_out;
pub mod method_choice;
pub mod motion;
pub mod obj;
pub mod outdoor;
pub mod render;
pub mod sampler_data;
pub mod scene;
pub mod timeline;

pub use error::{Error, Result};
pub use gpu::PermuteMode;
pub use render::{
    render_cpu, render_gpu, render_sequence_cpu, render_sequence_gpu, FrameView, RenderJob, RenderOutput,
    SequenceOptions, TileChoice,
};
pub use scene::{Scene, SceneGpu, TraceSettings, TraceVariant};
