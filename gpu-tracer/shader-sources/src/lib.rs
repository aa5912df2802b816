//! Generates the seed-permutation passes in WGSL, GLSL, HLSL and MSL from
//! the one Rust source: the committed rust-gpu module
//! `gpu-tracer/shaders/kernels.spv`, translated by `naga` (the version wgpu
//! uses) into `sampler-core/shaders/{wgsl,glsl,hlsl,msl}/`.
//!
//! ```text
//! cargo run -p shader-sources             # (re)writes the generated files
//! cargo run -p shader-sources -- --check  # exit 1 when a committed file is stale
//! ```
//!
//! Only the sixteen entry points of [`ENTRIES`] are kept (the permutation,
//! its feature-aware form, the reprojection passes and the a-priori samplers);
//! the path tracer's entry points are removed from the
//! naga module and everything only they used is compacted away, so a renderer
//! that includes a generated file does not carry the tracer.
//!
//! WGSL gets one module with all sixteen entry points; GLSL, HLSL and MSL one
//! file per entry point, each compacted to what that pass uses (GLSL needs
//! one `main` per shader; in HLSL and MSL this keeps registers and the MSL
//! buffer-size struct specific to one pass). rust-gpu's SPIR-V carries no
//! names, so the generator names the types and buffers before translating:
//! `FrameParams` with `sampler_core::FrameParams`'s fields (`SamplerParams`
//! for the samplers), buffers after the
//! kernel parameters (`seeds_in`; `sort_seeds_in` in the shared WGSL module).
//!
//! `naga` cannot name a function `permute_entry::sort_cs`; every entry point
//! is renamed to [`Entry::name`] (`::` replaced by `_`, which is what naga's
//! namer would pick) before any back end runs, so the names are the same in
//! every language and do not depend on the namer.
//!
//! ```
//! let sort = shader_sources::ENTRIES.iter().find(|e| e.name == "permute_entry_sort_cs").unwrap();
//! assert_eq!(sort.spirv, kernels::permute_entry::SORT_ENTRY);
//! ```
//!
//! Example: `cargo run -p shader-sources --example integration` (a small
//! wgpu renderer calling the generated WGSL between frames; `-- --cpu`, or no
//! adapter, runs the same loop with `sampler_core::permute_frame`).
//!
//! The bindings, dispatch sizes and pass order are documented in
//! `sampler-core/shaders/README.md`; conformance's `generated_shaders` test
//! checks the committed files are fresh and runs the WGSL and GLSL against
//! the CPU.

//! # Modules
//! - `entries`: [`ENTRIES`], [`Entry`] and the generated file names;
//! - `select`: parsing the SPIR-V and keeping only [`ENTRIES`]
//!   ([`permutation_module`]);
//! - `naming`: names for rust-gpu's anonymous types and buffers;
//! - `loops`: the workaround for naga's loop-exit bug (gfx-rs/wgpu#4558);
//! - `translate`: the WGSL, GLSL, HLSL and MSL back ends and the header;
//! - `generate`: [`generate()`], and writing or checking the files;
//! - `error`: [`Error`].

mod entries;
mod error;
mod generate;
mod loops;
mod naming;
mod select;
mod translate;

pub use entries::{
    glsl_file, hlsl_file, msl_file, Entry, COMMAND, ENTRIES, LANGUAGE_DIRS, OUTPUT_DIR, SPIRV_PATH, WGSL_FILE,
};
pub use error::Error;
pub use generate::{
    generate, generate_from_workspace, sha256_hex, stale_files, workspace_root, write_files, GeneratedFile,
};
pub use naming::{FRAME_PARAMS_FIELDS, SAMPLER_PARAMS_FIELDS};
pub use select::permutation_module;
pub use translate::{GLSL_VERSION, MSL_SIZES_SLOT, MSL_VERSION};
