//! What a render reads: OBJ and glTF scenes (animated ones with every frame
//! and AOV saved), camera paths, the committed glTF fixtures, and bad input
//! of every kind failing clearly with nothing written.

use super::{gltf_fixture, png_size, tracer};
use e2e_tests::{gpu_required, run, text};
use std::path::Path;

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
        (
            vec!["--mode", "hold", "--sampler", "seeds"],
            "only --sampler spatiotemporal",
        ),
        (
            vec!["--mode", "hold", "--sampler", "zsobol-jitter"],
            "and --sampler zsobol, which advance",
        ),
        (
            vec!["--sampler", "spatiotemporal", "--mode", "permute"],
            "nothing to permute with --sampler spatiotemporal",
        ),
        (vec!["--mode", "temporal", "--tile", "128"], "use --tile 64"),
        (
            vec!["--sampler", "spatiotemporal", "--mode", "temporal"],
            "--mode temporal has nothing to permute with --sampler spatiotemporal",
        ),
        (vec!["--reproject-hold-below", "-1"], "not a finite speed >= 0"),
        (vec!["--reproject-hold-below", "nan"], "not a finite speed >= 0"),
        (
            vec!["--reproject-follow-share", "1.5"],
            "not a share of the frame in [0, 1]",
        ),
        (
            vec!["--reproject-follow-share", "nan"],
            "not a share of the frame in [0, 1]",
        ),
        (vec!["--pan-offset", "maybe"], "invalid value 'maybe'"),
        (
            vec!["--glossy-regularization", "-0.1"],
            "not a strength in [0, 1]",
        ),
        (vec!["--glossy-regularization", "1.5"], "not a strength in [0, 1]"),
        (vec!["--glossy-regularization", "nan"], "not a strength in [0, 1]"),
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

/// Every file below `dir`, sorted.
fn files_below(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(files_below(&p));
        } else {
            out.push(p.display().to_string());
        }
    }
    out.sort();
    out
}

/// 60 frames of the animated glTF room (moving camera node, moving object,
/// textures) with every frame and AOV saved, on the CPU and on the GPU
/// (lavapipe in CI): 60 numbered EXR+PNG frames and 60 x 5 AOVs each, the
/// camera's motion shows in the motion AOV, and the two devices' G-buffers
/// agree on the object ids.
#[test]
fn animated_gltf_sequence_saves_frames_and_aovs_on_cpu_and_gpu() {
    let exe = tracer();
    let scene = gltf_fixture("animated_room.gltf");
    let mut ids = Vec::new();
    for device in ["cpu", "gpu"] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let o = run(
            &exe,
            &[
                "render",
                "--scene",
                scene.to_str().unwrap(),
                "--width",
                "32",
                "--height",
                "24",
                "--frames",
                "60",
                "--fps",
                "30",
                "--device",
                device,
                "--save-frames",
                "--save-aovs",
                "--out",
                out.to_str().unwrap(),
            ],
        );
        let t = text(&o);
        if device == "gpu" && !o.status.success() && t.contains("no GPU adapter") {
            assert!(!gpu_required(), "BLUENOISE_REQUIRE_GPU=1 and no GPU: {t}");
            eprintln!("SKIPPED GPU part: {t}");
            continue;
        }
        assert!(o.status.success(), "{device}: {t}");
        assert!(!t.contains("warning"), "{device}: {t}");
        let frames = files_below(&out.join("frames"));
        let aovs = files_below(&out.join("aovs"));
        assert_eq!(frames.len(), 120, "{device}: {frames:?}");
        assert_eq!(aovs.len(), 300, "{device}");
        assert!(frames[0].ends_with("frame_00000.exr") && frames[119].ends_with("frame_00059.png"));
        // No temporary files left behind.
        assert!(files_below(&out).iter().all(|f| !f.ends_with(".tmp")));
        let read = |name: String| image::open(out.join("aovs").join(name)).unwrap().into_rgb32f();
        // Frame 0 has no previous frame: zero motion; later frames move.
        let still = read("frame_00000.motion.exr".into());
        assert!(still.pixels().all(|p| p[0] == 0.0 && p[1] == 0.0), "{device}");
        let moving = read("frame_00030.motion.exr".into());
        let max = moving
            .pixels()
            .map(|p| p[0].abs().max(p[1].abs()))
            .fold(0.0f32, f32::max);
        assert!(max > 0.05 && max < 20.0, "{device}: max motion {max} px");
        let depth = read("frame_00030.depth.exr".into());
        assert!(depth.pixels().any(|p| p[0] > 0.0), "{device}");
        ids.push(read("frame_00059.id.exr".into()).into_raw());
    }
    if ids.len() == 2 {
        assert_eq!(ids[0], ids[1], "object ids differ between CPU and GPU");
    }
}

/// Broken glTF inputs: a clear message naming the file, a non-zero exit,
/// and nothing written (the output directory is not even created).
#[test]
fn bad_gltf_inputs_fail_clearly_and_write_nothing() {
    let exe = tracer();
    let dir = tempfile::tempdir().unwrap();
    let fixture = gltf_fixture("textured_quad.gltf");
    let json = std::fs::read_to_string(&fixture).unwrap();
    let bin = std::fs::read(gltf_fixture("textured_quad.bin")).unwrap();
    let png = std::fs::read(gltf_fixture("checker.png")).unwrap();
    let glb = std::fs::read(gltf_fixture("emissive_quad.glb")).unwrap();
    let case_dir = |name: &str| {
        let d = dir.path().join(name);
        std::fs::create_dir_all(&d).unwrap();
        d
    };
    let mut cases = Vec::new();
    // Truncated .glb.
    let d = case_dir("truncated");
    std::fs::write(d.join("scene.glb"), &glb[..glb.len() / 2]).unwrap();
    cases.push(d.join("scene.glb"));
    // Missing .bin.
    let d = case_dir("missing_bin");
    std::fs::write(d.join("scene.gltf"), &json).unwrap();
    std::fs::write(d.join("checker.png"), &png).unwrap();
    cases.push(d.join("scene.gltf"));
    // Bad accessor index.
    let d = case_dir("bad_accessor");
    let patched = json.replacen("\"POSITION\": 0", "\"POSITION\": 99", 1);
    assert_ne!(
        patched, json,
        "fixture layout changed: POSITION accessor not found"
    );
    std::fs::write(d.join("scene.gltf"), patched).unwrap();
    std::fs::write(d.join("textured_quad.bin"), &bin).unwrap();
    std::fs::write(d.join("checker.png"), &png).unwrap();
    cases.push(d.join("scene.gltf"));
    // NaN in the positions (the first float of the buffer is a position).
    let d = case_dir("nan");
    let mut nan_bin = bin.clone();
    nan_bin[..4].copy_from_slice(&f32::NAN.to_le_bytes());
    std::fs::write(d.join("scene.gltf"), &json).unwrap();
    std::fs::write(d.join("textured_quad.bin"), &nan_bin).unwrap();
    std::fs::write(d.join("checker.png"), &png).unwrap();
    cases.push(d.join("scene.gltf"));
    for scene in cases {
        let out = dir.path().join("never-created");
        let o = run(
            &exe,
            &[
                "render",
                "--scene",
                scene.to_str().unwrap(),
                "--width",
                "8",
                "--height",
                "8",
                "--frames",
                "1",
                "--device",
                "cpu",
                "--out",
                out.to_str().unwrap(),
            ],
        );
        let t = text(&o);
        assert!(!o.status.success(), "{}: {t}", scene.display());
        assert!(
            t.contains("cannot load scene") && t.contains(scene.to_str().unwrap()),
            "{t}"
        );
        assert!(!t.contains("panicked"), "{t}");
        assert!(!out.exists(), "{}: output written", scene.display());
        eprintln!("{}: {}", scene.display(), t.lines().last().unwrap_or(""));
    }
}

/// A camera given on the command line with a pan path on the Cornell box:
/// the AOVs of frame 1 show the pan (pixels per frame, motion to the right
/// for a camera moving right), and a scene without emitters warns.
#[test]
fn camera_path_motion_and_emitterless_warning() {
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
            "--device",
            "cpu",
            "--camera-from",
            "278,273,-800",
            "--camera-at",
            "278,273,559.2",
            "--fov",
            "39.3",
            "--camera-path",
            "pan",
            "--camera-speed",
            "1.5",
            "--save-aovs",
            "--out",
            dir.path().to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", text(&o));
    // A moving camera on the CPU reprojects seeds by default, those of
    // surfaces from 6 px/frame on, and every seed in frames half rigid,
    // where ZSobol's jitter follows too (the pan offset).
    assert!(
        text(&o).contains(
            "reprojection on from 6 px/frame, everywhere in frames 0.5 rigid, ZSobol following them"
        ),
        "{}",
        text(&o)
    );
    // `--pan-offset off`: the same rule, ZSobol on the screen.
    let o = run(
        &exe,
        &[
            "render",
            "--width",
            "16",
            "--height",
            "16",
            "--frames",
            "2",
            "--device",
            "cpu",
            "--camera-path",
            "pan",
            "--pan-offset",
            "off",
            "--out",
            dir.path().join("screen").to_str().unwrap(),
        ],
    );
    let t = text(&o);
    assert!(o.status.success(), "{t}");
    assert!(
        t.contains("everywhere in frames 0.5 rigid") && !t.contains("ZSobol following"),
        "{t}"
    );
    let m = image::open(dir.path().join("aovs/frame_00001.motion.exr"))
        .unwrap()
        .into_rgb32f();
    // The back wall is the plane through the looked-at point: 1.5 px exactly.
    let centre = m.get_pixel(16, 9);
    let o = run(
        &exe,
        &[
            "render",
            "--width",
            "16",
            "--height",
            "16",
            "--frames",
            "3",
            "--device",
            "cpu",
            "--camera-path",
            "orbit",
            "--reproject",
            "off",
            "--out",
            dir.path().join("off").to_str().unwrap(),
        ],
    );
    assert!(
        o.status.success() && text(&o).contains("reprojection off"),
        "{}",
        text(&o)
    );
    // The GPU reprojects too (the same passes, bit for bit: conformance).
    let o = run(
        &exe,
        &[
            "render",
            "--width",
            "24",
            "--height",
            "16",
            "--frames",
            "3",
            "--device",
            "gpu",
            "--camera-path",
            "pan",
            "--out",
            dir.path().join("gpu").to_str().unwrap(),
        ],
    );
    if o.status.success() {
        assert!(
            text(&o).contains("reprojection on") && !text(&o).contains("on CPU"),
            "{}",
            text(&o)
        );
        assert_eq!(png_size(&dir.path().join("gpu/mean.png")), (24, 16));
    } else {
        let t = text(&o);
        assert!(t.contains("no GPU adapter"), "{t}");
        assert!(!gpu_required(), "BLUENOISE_REQUIRE_GPU=1 and no GPU: {t}");
        eprintln!("SKIPPED (GPU reprojection): {t}");
    }
    assert!(
        (centre[0] - 1.5).abs() < 1e-2 && centre[1].abs() < 1e-2,
        "{centre:?}"
    );
    // A glTF scene with no emissive material and no lights: a warning.
    let o = run(
        &exe,
        &[
            "render",
            "--scene",
            gltf_fixture("hierarchy.glb").to_str().unwrap(),
            "--width",
            "8",
            "--height",
            "8",
            "--frames",
            "1",
            "--device",
            "cpu",
            "--out",
            dir.path().join("dark").to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("has no emitter"), "{}", text(&o));
}

/// The committed glTF fixtures are what their generator writes today (the
/// `--check` pattern of generated files): a change to the generator without
/// regenerating the files fails here.
#[test]
fn gltf_fixtures_are_fresh() {
    let dir = tempfile::tempdir().unwrap();
    let status = std::process::Command::new(env!("CARGO"))
        .args([
            "run",
            "--quiet",
            "--profile",
            "test",
            "-p",
            "gpu-tracer",
            "--example",
            "make_gltf_fixtures",
            "--",
            dir.path().to_str().unwrap(),
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .status()
        .expect("cargo runs");
    assert!(status.success(), "the fixture generator failed");
    let committed = gltf_fixture("");
    let mut names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    names.sort();
    assert!(names.len() >= 7, "{names:?}");
    for name in names {
        let fresh = std::fs::read(dir.path().join(&name)).unwrap();
        let old = std::fs::read(committed.join(&name))
            .unwrap_or_else(|e| panic!("{name:?} is generated but not committed: {e}"));
        assert!(
            fresh == old,
            "{name:?} is stale: run `cargo run -p gpu-tracer --example make_gltf_fixtures` and commit"
        );
    }
}

/// `--env r,g,b`: a constant sky lights an open scene with no emitter (no
/// warning then), the CPU and the GPU agree on it, an environment map of
/// the same radiance (`--env sky.exr`, importance-sampled) gives the same
/// image, and bad values fail before any work with nothing written.
#[test]
fn a_constant_sky_lights_an_open_scene() {
    let exe = tracer();
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("floor.obj");
    std::fs::write(
        &obj,
        "mtllib floor.mtl\nv -50 0 -50\nv 50 0 -50\nv 50 0 50\nv -50 0 50\nusemtl grey\nf 1 3 2\nf 1 4 3\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("floor.mtl"), "newmtl grey\nKd 0.8 0.8 0.8\n").unwrap();
    let render = |device: &str, env: &str, out: &str| {
        run(
            &exe,
            &[
                "render",
                "--scene",
                obj.to_str().unwrap(),
                "--camera-from",
                "0,10,10",
                "--camera-at",
                "0,0,0",
                "--width",
                "24",
                "--height",
                "16",
                "--frames",
                "4",
                "--spp",
                "4",
                "--env",
                env,
                "--device",
                device,
                "--out",
                dir.path().join(out).to_str().unwrap(),
            ],
        )
    };
    let mean_of = |out: &str| {
        let img = image::open(dir.path().join(out).join("mean.exr"))
            .unwrap()
            .into_rgb32f();
        img.pixels().map(|p| p[0] + p[1] + p[2]).sum::<f32>() / (3.0 * 24.0 * 16.0)
    };
    let o = render("cpu", "0.5,0.5,0.5", "cpu");
    let t = text(&o);
    assert!(o.status.success(), "{t}");
    assert!(!t.contains("has no emitter"), "{t}");
    // The floor reflects 0.8 of the sky (one bounce: nothing above it), the
    // sky itself is 0.5 where the camera misses the floor.
    let cpu = mean_of("cpu");
    assert!((0.39..=0.51).contains(&cpu), "mean radiance {cpu}");
    let o = render("gpu", "0.5,0.5,0.5", "gpu");
    if o.status.success() {
        let gpu = mean_of("gpu");
        assert!((gpu - cpu).abs() < 0.02, "GPU {gpu} against CPU {cpu}");
    } else {
        assert!(
            !gpu_required(),
            "BLUENOISE_REQUIRE_GPU=1 and no GPU: {}",
            text(&o)
        );
        eprintln!("SKIPPED the GPU half: {}", text(&o));
    }
    // The same sky as a map, written as a 16x8 EXR.
    let sky = dir.path().join("sky.exr");
    let img = image::Rgb32FImage::from_pixel(16, 8, image::Rgb([0.5, 0.5, 0.5]));
    image::DynamicImage::ImageRgb32F(img).save(&sky).unwrap();
    let o = render("cpu", sky.to_str().unwrap(), "map");
    assert!(o.status.success(), "{}", text(&o));
    let map = mean_of("map");
    assert!((map - cpu).abs() < 0.02, "map {map} against constant {cpu}");
    let missing = dir.path().join("missing.hdr");
    for (env, needle) in [
        ("-1,0,0", "cannot be negative"),
        ("1,nan,0", "finite"),
        ("1,2", "three finite numbers"),
        (missing.to_str().unwrap(), "cannot open"),
    ] {
        let o = render("cpu", env, "bad");
        assert!(!o.status.success(), "--env {env} must fail");
        assert!(text(&o).contains(needle), "--env {env}: {}", text(&o));
        assert!(!dir.path().join("bad").exists(), "--env {env} wrote output");
    }
}

#[test]
fn glossy_regularization_is_named_and_changes_the_glossy_box() {
    let exe = tracer();
    let dir = tempfile::tempdir().unwrap();
    let render = |extra: &[&str], out: &str| {
        let out = dir.path().join(out);
        let mut args = vec![
            "render",
            "--scene",
            "cornell-glossy",
            "--width",
            "24",
            "--height",
            "24",
            "--frames",
            "2",
            "--spp",
            "4",
            "--device",
            "cpu",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend(extra);
        let o = run(&exe, &args);
        assert!(o.status.success(), "{}", text(&o));
        let mean = image::open(out.join("mean.exr")).unwrap().into_rgb32f();
        (text(&o), mean.into_raw())
    };
    let (plain_text, plain) = render(&[], "plain");
    assert!(!plain_text.contains("glossy regularization"), "{plain_text}");
    let (text_on, regularized) = render(&["--glossy-regularization", "1"], "regularized");
    assert!(text_on.contains("glossy regularization 1"), "{text_on}");
    // Same seeds: only the paths through a glossy vertex after a rough lobe change.
    let changed = plain.iter().zip(&regularized).filter(|(a, b)| a != b).count();
    assert!(changed > 0, "--glossy-regularization 1 changed no pixel");
    assert!(changed < plain.len(), "every channel changed: {changed}");
}
