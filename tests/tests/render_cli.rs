//! `gpu-tracer render` as a user runs it.

use e2e_tests::{build_bin, gpu_required, run, text};
use std::path::Path;

fn tracer() -> std::path::PathBuf {
    build_bin("gpu-tracer", "gpu-tracer")
}

fn png_size(path: &Path) -> (u32, u32) {
    let img = image::open(path).unwrap_or_else(|e| panic!("{} is not a readable image: {e}", path.display()));
    (img.width(), img.height())
}

#[test]
fn cpu_render_writes_every_image_for_every_mode() {
    let exe = tracer();
    for mode in ["white", "sort", "permute"] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("nested/out");
        let o = run(
            &exe,
            &[
                "render",
                "--scene",
                "cornell",
                "--width",
                "45",
                "--height",
                "37",
                "--frames",
                "3",
                "--mode",
                mode,
                "--block",
                "3",
                "--device",
                "cpu",
                "--out",
                out.to_str().unwrap(),
            ],
        );
        assert!(o.status.success(), "{mode}: {}", text(&o));
        assert!(text(&o).contains("on CPU"), "{}", text(&o));
        for f in ["last.png", "mean.png"] {
            assert_eq!(png_size(&out.join(f)), (45, 37), "{mode} {f}");
        }
        for f in ["last.exr", "mean.exr"] {
            let img = image::open(out.join(f)).unwrap().into_rgb32f();
            assert_eq!(img.dimensions(), (45, 37));
            let mean: f32 = img.pixels().map(|p| p[0] + p[1] + p[2]).sum::<f32>() / (45.0 * 37.0);
            assert!(
                mean.is_finite() && mean > 0.01,
                "{mode} {f}: mean radiance {mean}"
            );
        }
    }
}

#[test]
fn cpu_render_with_each_apriori_sampler() {
    let exe = tracer();
    for (sampler, mode) in [
        ("zsobol", "white"),
        ("screen-sobol", "permute"),
        ("screen-sobol-jitter", "permute"),
        ("zsobol-jitter", "permute"),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let o = run(
            &exe,
            &[
                "render",
                "--width",
                "40",
                "--height",
                "24",
                "--spp",
                "4",
                "--frames",
                "3",
                "--mode",
                mode,
                "--sampler",
                sampler,
                "--device",
                "cpu",
                "--out",
                out.to_str().unwrap(),
            ],
        );
        assert!(o.status.success(), "{sampler}: {}", text(&o));
        let t = text(&o);
        assert!(
            t.contains("on CPU") && t.contains(&format!("{sampler} sampler")),
            "{t}"
        );
        let img = image::open(out.join("mean.exr")).unwrap().into_rgb32f();
        assert_eq!(img.dimensions(), (40, 24));
        let mean: f32 = img.pixels().map(|p| p[0] + p[1] + p[2]).sum::<f32>() / (40.0 * 24.0);
        eprintln!("{sampler} ({mode}): mean radiance {mean}");
        assert!(mean.is_finite() && mean > 0.01, "{sampler}: mean radiance {mean}");
    }
}

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
    if t.contains("on CPU") {
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

#[test]
fn obj_scene_with_mtl_renders() {
    let exe = tracer();
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("scene.mtl"),
        "newmtl floor\nKd 0.7 0.7 0.7\nnewmtl lamp\nKd 0 0 0\nKe 8 8 8\n",
    )
    .unwrap();
    // A floor quad and a smaller lamp quad above it facing down.
    std::fs::write(
        dir.path().join("scene.obj"),
        "mtllib scene.mtl\n\
         v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\n\
         v -0.3 1 -0.3\nv 0.3 1 -0.3\nv 0.3 1 0.3\nv -0.3 1 0.3\n\
         usemtl floor\nf 1 4 3\nf 1 3 2\n\
         usemtl lamp\nf 5 6 7\nf 5 7 8\n",
    )
    .unwrap();
    let out = dir.path().join("out");
    let o = run(
        &exe,
        &[
            "render",
            "--scene",
            dir.path().join("scene.obj").to_str().unwrap(),
            "--width",
            "24",
            "--height",
            "24",
            "--frames",
            "2",
            "--device",
            "cpu",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", text(&o));
    let img = image::open(out.join("mean.exr")).unwrap().into_rgb32f();
    let max = img.pixels().map(|p| p[0]).fold(0.0f32, f32::max);
    assert!(max > 0.1, "the lit floor or lamp must show: max {max}");
}

#[test]
fn bad_input_fails_with_a_clear_message_and_writes_nothing() {
    let exe = tracer();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let out_s = out.to_str().unwrap();
    let bad_obj = dir.path().join("broken.obj");
    std::fs::write(&bad_obj, "v 0 0 0\nv 1 0 0\nf 1 2 7\n").unwrap();
    let nan_obj = dir.path().join("nan.obj");
    std::fs::write(&nan_obj, "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n").unwrap();
    let file = dir.path().join("a-file");
    std::fs::write(&file, "x").unwrap();
    let under_file = file.join("out");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["--scene", "/nonexistent/scene.obj"],
            "/nonexistent/scene.obj",
        ),
        (vec!["--scene", bad_obj.to_str().unwrap()], "broken.obj"),
        (vec!["--scene", nan_obj.to_str().unwrap()], "nan.obj"),
        (vec!["--width", "0"], "width"),
        (vec!["--height", "0"], "height"),
        (vec!["--frames", "0"], "frames"),
        (vec!["--spp", "0"], "spp"),
        (vec!["--block", "9"], "block"),
        (vec!["--tile", "48"], "tile"),
        (vec!["--mode", "shuffle"], "mode"),
        (vec!["--sampler", "halton"], "sampler"),
        (
            vec!["--sampler", "screen-sobol", "--spp", "32"],
            "at most 16 with the screen-sobol sampler",
        ),
        (
            vec!["--sampler", "zsobol", "--spp", "512"],
            "at most 256 with the zsobol sampler",
        ),
        (vec!["--out", file.to_str().unwrap()], "not a directory"),
        (
            vec!["--out", under_file.to_str().unwrap()],
            "cannot create output directory",
        ),
    ];
    for (extra, needle) in cases {
        let mut args = vec![
            "render", "--width", "8", "--height", "8", "--frames", "1", "--device", "cpu",
        ];
        if !extra.contains(&"--out") {
            args.extend(["--out", out_s]);
        }
        args.extend(extra.iter().copied());
        let o = run(&exe, &args);
        let t = text(&o);
        assert!(!o.status.success(), "{extra:?} must fail: {t}");
        assert!(
            t.contains(needle),
            "{extra:?}: message should mention {needle:?}: {t}"
        );
        assert!(!out.join("last.png").exists(), "{extra:?} left an image behind");
    }
}
