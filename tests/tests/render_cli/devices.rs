//! Where a render runs: `--device auto` falls back to the CPU and says why,
//! `--device gpu` renders on the adapter or fails clearly.

use super::{png_size, tracer};
use e2e_tests::{gpu_required, run, text};

#[test]
fn auto_device_renders_on_gpu_or_says_it_fell_back() {
    let exe = tracer();
    let dir = tempfile::tempdir().unwrap();
    let o = run(
        &exe,
        &[
            "render",
            "--width",
            "32",
            "--height",
            "32",
            "--frames",
            "2",
            "--out",
            dir.path().to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    if t.contains("on CPU") && t.contains("software rasteriser") {
        // lavapipe (CI): the native CPU renderer is faster, and says why.
        assert!(t.contains("--device gpu forces the adapter"), "{t}");
    } else if t.contains("on CPU") {
        assert!(
            t.contains("notice: no GPU adapter") || t.contains("warning: the GPU could not be used"),
            "{t}"
        );
        assert!(
            !gpu_required(),
            "BLUENOISE_REQUIRE_GPU=1 but the render fell back to the CPU: {t}"
        );
        eprintln!("SKIPPED GPU part: fell back to the CPU: {t}");
    } else {
        assert!(!t.contains("warning"), "{t}");
    }
    assert_eq!(png_size(&dir.path().join("last.png")), (32, 32));
}

#[test]
fn gpu_device_renders_or_fails_clearly() {
    let exe = tracer();
    let dir = tempfile::tempdir().unwrap();
    let o = run(
        &exe,
        &[
            "render",
            "--device",
            "gpu",
            "--width",
            "40",
            "--height",
            "24",
            "--frames",
            "3",
            "--mode",
            "permute",
            "--tile",
            "128",
            "--out",
            dir.path().to_str().unwrap(),
        ],
    );
    if o.status.success() {
        assert!(!text(&o).contains("on CPU"), "{}", text(&o));
        assert_eq!(png_size(&dir.path().join("mean.png")), (40, 24));
    } else {
        let t = text(&o);
        assert!(
            t.contains("--device gpu was requested") && t.contains("no GPU adapter"),
            "{t}"
        );
        assert!(!gpu_required(), "BLUENOISE_REQUIRE_GPU=1 and no GPU: {t}");
        assert!(!dir.path().join("last.png").exists());
        eprintln!("SKIPPED: {t}");
    }
}

/// On a headless machine (no `XDG_RUNTIME_DIR`) a render prints no `error:`
/// line: the Vulkan loader's window-system complaint is kept away by giving
/// the process a private runtime directory (`gpu::prepare_headless_environment`).
#[test]
fn a_headless_render_prints_no_error_line() {
    let exe = tracer();
    let dir = tempfile::tempdir().unwrap();
    let o = std::process::Command::new(&exe)
        .args([
            "render", "--device", "gpu", "--width", "16", "--height", "16", "--frames", "1", "--out",
        ])
        .arg(dir.path())
        .env_remove("XDG_RUNTIME_DIR")
        .output()
        .expect("the tool starts");
    let t = text(&o);
    assert!(
        !t.lines()
            .any(|l| l.trim_start().starts_with("error:") && l.contains("XDG_RUNTIME_DIR")),
        "{t}"
    );
    if o.status.success() {
        assert_eq!(png_size(&dir.path().join("last.png")), (16, 16));
    } else {
        assert!(t.contains("no GPU adapter") && !gpu_required(), "{t}");
        eprintln!("SKIPPED GPU part: {t}");
    }
}
