//! Host side of the path tracer: scenes (built-in Cornell box and OBJ files),
//! their BVH and buffer form, the CPU renderer that runs the kernels' own
//! functions, and image output.
//!
//! # Guide
//!
//! - [`scene`]: [`Scene`] (triangles, materials, camera) and [`SceneGpu`]
//!   (the buffers the kernels read), built by [`cornell::cornell_box`] or
//!   [`obj::load_obj`]; [`bvh`] builds the BVH with obvhs.
//! - [`gltf_scene`]: [`gltf_scene::load_gltf`] loads a glTF 2.0 file
//!   (`.gltf` or `.glb`): meshes, materials, textures, camera and animation.
//! - [`animation`]: the node hierarchy and keyframe channels of a glTF
//!   scene ([`animation::Rig`]), posed at any time by [`animation::Rig::pose`].
//! - [`cpu`]: [`cpu::render_frame`] traces a frame with rayon over rows by
//!   calling `kernels::trace_pixel`, exactly what the GPU's `trace_cs` runs
//!   per pixel; [`cpu::accumulate_frame`] is the running mean.
//! - [`timeline`]: what moves between frames ([`timeline::Timeline`]: a
//!   glTF rig and/or a [`camera_path::CameraPath`]) and the scene of each
//!   frame with its motion ([`timeline::SceneSequence`]); [`render`] renders
//!   a sequence on the CPU or the GPU, with the G-buffer and motion vectors
//!   of `kernels::gbuffer` when asked.
//! - [`filter`]: the real-time filters after a frame on the CPU
//!   ([`filter::FrameFilter`]: TAA, Gaussian, a-trous, TAA + a-trous) with
//!   the kernels' per-pixel filter functions.
//! - [`image_out`]: tone-mapped PNG and linear EXR, written atomically.
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
pub mod error;
pub mod feature_keys;
pub mod filter;
pub mod gltf_scene;
pub mod gpu;
pub mod image_out;
pub mod motion;
pub mod obj;
pub mod render;
pub mod scene;
pub mod timeline;

pub use error::{Error, Result};
pub use gpu::PermuteMode;
pub use render::{
    render_cpu, render_gpu, render_sequence_cpu, render_sequence_gpu, FrameView, RenderJob, RenderOutput,
    SequenceOptions, TileChoice,
};
pub use scene::{Scene, SceneGpu, TraceSettings};
