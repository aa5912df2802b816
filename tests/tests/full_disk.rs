//! `gpu-tracer render` onto a full file system: a clear error, a non-zero
//! exit, and no half-written image left behind. Needs permission to mount a
//! tiny tmpfs (root, as in CI); elsewhere it prints SKIPPED.

use e2e_tests::{build_bin, run, text};
use std::process::Command;

struct Mount(std::path::PathBuf);

impl Drop for Mount {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg(&self.0).status();
    }
}

#[test]
fn full_disk_fails_cleanly() {
    let exe = build_bin("gpu-tracer", "gpu-tracer");
    let dir = tempfile::tempdir().unwrap();
    let mounted = Command::new("mount")
        .args(["-t", "tmpfs", "-o", "size=24k", "tmpfs"])
        .arg(dir.path())
        .output();
    match mounted {
        Ok(o) if o.status.success() => {}
        Ok(o) => {
            eprintln!(
                "SKIPPED full_disk_fails_cleanly: cannot mount a tmpfs: {}",
                text(&o)
            );
            return;
        }
        Err(e) => {
            eprintln!("SKIPPED full_disk_fails_cleanly: no mount command: {e}");
            return;
        }
    }
    let _unmount = Mount(dir.path().to_path_buf());
    // 96x96: each PNG is a few KiB, each EXR ~100 KiB: the 24 KiB disk fills.
    let o = run(
        &exe,
        &[
            "render", "--width", "96", "--height", "96", "--frames", "1", "--device", "cpu", "--out",
        ]
        .into_iter()
        .chain([dir.path().to_str().unwrap()])
        .collect::<Vec<_>>(),
    );
    let t = text(&o);
    assert!(!o.status.success(), "writing to a full disk must fail: {t}");
    assert!(
        t.contains("cannot write") && t.contains("No space left on device"),
        "unclear message: {t}"
    );
    // Whatever is left must be complete images, and no temporary files.
    for entry in std::fs::read_dir(dir.path()).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        assert!(
            name.ends_with(".png") || name.ends_with(".exr"),
            "left behind: {name}"
        );
        image::open(&path).unwrap_or_else(|e| panic!("{name} is half-written: {e}"));
    }
}
