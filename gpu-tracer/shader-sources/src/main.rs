//! `cargo run -p shader-sources [-- --check]`: writes (or, with `--check`,
//! compares) the generated WGSL, GLSL, HLSL and MSL of the seed-permutation
//! passes under `sampler-core/shaders/`. See the library docs.

use shader_sources::{
    generate_from_workspace, stale_files, workspace_root, write_files, COMMAND, OUTPUT_DIR,
};
use std::process::ExitCode;

const USAGE: &str = "usage: cargo run -p shader-sources [-- --check]

Translates gpu-tracer/shaders/kernels.spv (rust-gpu) with naga into
sampler-core/shaders/{wgsl,glsl,hlsl,msl}/, keeping only the seed-permutation
and reprojection entry points.

  --check   write nothing; exit 1 if a committed file is stale, missing or extra";

fn main() -> ExitCode {
    let mut check = false;
    for arg in std::env::args().skip(1) {
        match arg.as_str() {
            "--check" => check = true,
            "-h" | "--help" => {
                println!("{USAGE}");
                return ExitCode::SUCCESS;
            }
            other => {
                eprintln!("unknown argument {other:?}\n\n{USAGE}");
                return ExitCode::from(2);
            }
        }
    }
    let root = workspace_root();
    let out_dir = root.join(OUTPUT_DIR);
    let files = match generate_from_workspace(&root) {
        Ok(files) => files,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    if check {
        let problems = stale_files(&out_dir, &files);
        if problems.is_empty() {
            println!("{} generated files in {OUTPUT_DIR} are fresh", files.len());
            return ExitCode::SUCCESS;
        }
        for p in &problems {
            eprintln!("{OUTPUT_DIR}/{p}");
        }
        eprintln!("generated shader sources are stale: run `{COMMAND}`");
        return ExitCode::FAILURE;
    }
    if let Err(e) = write_files(&out_dir, &files) {
        eprintln!("error: {e}");
        return ExitCode::FAILURE;
    }
    for f in &files {
        println!("{:>9} bytes  {OUTPUT_DIR}/{}", f.text.len(), f.path);
    }
    ExitCode::SUCCESS
}
