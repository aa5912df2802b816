//! Compiles the `kernels` crate to one SPIR-V module with rust-gpu.
//!
//! ```text
//! shader-builder <kernels-dir> <out.spv> [--check]
//! ```
//!
//! Without `--check` the module is written to `<out.spv>`; with it, the fresh
//! module is compared byte for byte with `<out.spv>` and the exit code is 1
//! when they differ (the committed module is stale). Intermediate builds go
//! to `$SHADER_TARGET_DIR` (default `<out dir>/../target/shaders`), which CI
//! keeps outside the clone.

use spirv_builder::{ModuleResult, SpirvBuilder};
use std::path::PathBuf;
use std::process::ExitCode;

/// The nightly rust-gpu 0.11 requires; the kernels crate has no
/// `rust-toolchain.toml` of its own (it also builds on stable for the host).
const TOOLCHAIN: &str = "nightly-2026-08-15";
const TARGET: &str = "spirv-unknown-vulkan1.2";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let check = args.iter().any(|a| a == "--check");
    let paths: Vec<&String> = args.iter().filter(|a| !a.starts_with("--")).collect();
    let [crate_dir, out] = paths.as_slice() else {
        eprintln!("usage: shader-builder <kernels-dir> <out.spv> [--check]");
        return ExitCode::from(2);
    };
    let crate_dir = std::fs::canonicalize(crate_dir).expect("kernels directory exists");
    let out = PathBuf::from(out);
    let target_dir = std::env::var_os("SHADER_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| crate_dir.join("../../target/shaders"));
    std::fs::create_dir_all(&target_dir).expect("can create the shader target directory");
    let target_dir = std::fs::canonicalize(target_dir).expect("target dir exists");

    let mut builder = SpirvBuilder::new(&crate_dir, TARGET)
        .release(true)
        .target_dir_path(target_dir)
        .shader_crate_default_features(false);
    builder.toolchain_overwrite = Some(TOOLCHAIN.to_string());
    let result = match builder.build() {
        Ok(r) => r,
        Err(e) => {
            eprintln!("shader build failed: {e}");
            return ExitCode::FAILURE;
        }
    };
    let ModuleResult::SingleModule(module) = &result.module else {
        eprintln!("expected a single SPIR-V module");
        return ExitCode::FAILURE;
    };
    let fresh = std::fs::read(module).expect("rust-gpu wrote the module");
    eprintln!(
        "built {} ({} bytes), entry points: {}",
        module.display(),
        fresh.len(),
        result.entry_points.join(", ")
    );
    if check {
        match std::fs::read(&out) {
            Ok(committed) if committed == fresh => {
                eprintln!("{} is up to date", out.display());
                ExitCode::SUCCESS
            }
            Ok(_) => {
                eprintln!("{} is STALE: rebuild it with gpu-tracer/build-shaders.sh and commit it", out.display());
                ExitCode::FAILURE
            }
            Err(e) => {
                eprintln!("cannot read {}: {e}", out.display());
                ExitCode::FAILURE
            }
        }
    } else {
        let tmp = out.with_extension("spv.tmp");
        std::fs::write(&tmp, &fresh).expect("can write the module");
        std::fs::rename(&tmp, &out).expect("can move the module into place");
        eprintln!("wrote {}", out.display());
        ExitCode::SUCCESS
    }
}
