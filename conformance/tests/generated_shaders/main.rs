//! The generated shader sources in `sampler-core/shaders/` (written by
//! `cargo run -p shader-sources` from the committed rust-gpu SPIR-V):
//!
//! - they are fresh: generating them again in memory gives the committed
//!   bytes (so CI fails on stale files);
//! - the **WGSL** module, created through wgpu from WGSL source, runs every
//!   pass (seed init, intensity, sort, retarget, the feature-aware sort,
//!   record-source and retarget, and the six reprojection passes) and
//!   matches `sampler_core` on the CPU bit for bit over chained frames,
//!   several surfaces with creases and background, and adversarial motion;
//! - the a-priori samplers' entry points (screen-space Sobol, ZSobol) give
//!   every pixel's pair bit for bit as `kernels::sampler_entry` on the CPU;
//! - the **GLSL** files, compiled by `glslangValidator` to SPIR-V and loaded
//!   through wgpu, do the same;
//! - the **HLSL** files compile with glslang's HLSL front end to SPIR-V (not
//!   run: naga's SPIR-V front end rejects glslang's HLSL output);
//! - the **HLSL** and **MSL** files are also checked statically (no MSL
//!   compiler or naga HLSL/MSL front end exists here): generated header,
//!   every entry point declared with 64-wide workgroups, the atomic minimum
//!   of `claim_cs` present, nothing of the path tracer.
//!
//! GPU tests need an adapter (Mesa's lavapipe counts) and the GLSL test
//! `glslangValidator` (Debian `glslang-tools`). Without them the test prints
//! `SKIPPED` with the reason; `BLUENOISE_REQUIRE_GPU=1` (set in CI) turns
//! that into a failure.
//!
//! - here: the committed files are fresh;
//! - [`text`]: the static checks of the generated text;
//! - [`glslang`]: the GLSL and HLSL files compiled by glslang;
//! - [`passes`]: the WGSL and GLSL passes run against the CPU.

mod glslang;
mod passes;
mod text;

use shader_sources::{
    generate_from_workspace, stale_files, workspace_root, Entry, COMMAND, ENTRIES, OUTPUT_DIR,
};
use std::path::PathBuf;

fn shaders_dir() -> PathBuf {
    workspace_root().join(OUTPUT_DIR)
}

fn read_generated(path: &str) -> String {
    let full = shaders_dir().join(path);
    std::fs::read_to_string(&full).unwrap_or_else(|e| panic!("{}: {e}; run `{COMMAND}`", full.display()))
}

fn entry(pass: &str) -> &'static Entry {
    ENTRIES
        .iter()
        .find(|e| e.pass() == pass)
        .unwrap_or_else(|| panic!("no entry point for pass {pass}"))
}

#[test]
fn committed_sources_are_fresh() {
    let files = generate_from_workspace(&workspace_root()).expect("generate");
    let problems = stale_files(&shaders_dir(), &files);
    assert!(
        problems.is_empty(),
        "{OUTPUT_DIR} is stale; run `{COMMAND}`:\n{}",
        problems.join("\n")
    );
}
