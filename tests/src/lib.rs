//! End-to-end tests of the command-line tools (see `tests/`): each test
//! builds the tool with cargo, runs it as a user would and checks what it
//! wrote and said.

pub mod module_graph;

use std::path::PathBuf;
use std::process::{Command, Output};

/// Builds `bin` of package `package` (test profile, so artifacts are shared
/// with `cargo test`) and returns its path.
///
/// # Panics
/// If cargo fails to build it.
pub fn build_bin(package: &str, bin: &str) -> PathBuf {
    build_target(package, "--bin", bin, "")
}

/// `cargo build --profile test --workspace --tests <kind> name` (`name`
/// belongs to `package`); the artifact is in `target/debug/<subdir>/name`.
///
/// `--workspace --tests` resolves features exactly as `cargo test --workspace`
/// does (dev-dependencies' features included), so after that command's build
/// this one has nothing to do; with `-p package` alone the tool's dependencies
/// (wgpu, naga, image) were compiled a second time with other features, which
/// took minutes of a cold test run.
fn build_target(package: &str, kind: &str, name: &str, subdir: &str) -> PathBuf {
    let status = Command::new(env!("CARGO"))
        .args([
            "build",
            "--profile",
            "test",
            "--workspace",
            "--tests",
            kind,
            name,
            "--quiet",
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .status()
        .expect("cargo runs");
    assert!(status.success(), "cargo build of {package} {kind} {name} failed");
    // target/debug/deps/<this test> -> target/debug/<subdir>/<name>
    let exe = std::env::current_exe().expect("test executable path");
    let dir = exe.parent().and_then(|d| d.parent()).expect("target/<profile>");
    let path = dir.join(subdir).join(name);
    assert!(path.exists(), "{} was not built", path.display());
    path
}

/// Builds example `example` of package `package` (test profile) and returns
/// its path.
///
/// # Panics
/// If cargo fails to build it.
pub fn build_example(package: &str, example: &str) -> PathBuf {
    build_target(package, "--example", example, "examples")
}

/// Runs `exe` with `args`; returns its output (stdout, stderr, status).
pub fn run(exe: &PathBuf, args: &[&str]) -> Output {
    Command::new(exe)
        .args(args)
        .env(
            "XDG_RUNTIME_DIR",
            std::env::var("XDG_RUNTIME_DIR").unwrap_or_else(|_| "/tmp".into()),
        )
        .output()
        .expect("the tool starts")
}

/// `stdout` and `stderr` of `out` as one string, for messages.
pub fn text(out: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}

/// True when GPU tests must not skip (`BLUENOISE_REQUIRE_GPU=1`, set in CI).
pub fn gpu_required() -> bool {
    std::env::var("BLUENOISE_REQUIRE_GPU").as_deref() == Ok("1")
}
