//! `gpu-tracer render` as a user runs it.
//!
//! - [`modes`]: every mode's images, the samplers, the feature-aware
//!   permutation and its keys, the real-time filters.
//! - [`devices`]: `--device auto` and `--device gpu`.
//! - [`inputs`]: OBJ and glTF scenes, camera paths, the glTF fixtures, bad
//!   input.

mod devices;
mod inputs;
mod modes;

use e2e_tests::build_bin;
use std::path::Path;

fn tracer() -> std::path::PathBuf {
    build_bin("gpu-tracer", "gpu-tracer")
}

fn png_size(path: &Path) -> (u32, u32) {
    let img = image::open(path).unwrap_or_else(|e| panic!("{} is not a readable image: {e}", path.display()));
    (img.width(), img.height())
}

/// The committed glTF fixtures (`cargo run -p gpu-tracer --example make_gltf_fixtures`).
fn gltf_fixture(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../gpu-tracer/tests/data/gltf")
        .join(name)
}
