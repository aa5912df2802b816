//! What a render computes: every mode's images, the a-priori samplers, the
//! feature-aware permutation and its sort keys, and the real-time filters.

use super::{png_size, tracer};
use e2e_tests::{gpu_required, run, text};
use std::path::Path;

#[test]
fn cpu_render_writes_every_image_for_every_mode() {
    let exe = tracer();
    for mode in ["white", "sort", "permute", "temporal"] {
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
        ("spatiotemporal", "white"),
        ("spatiotemporal", "hold"),
        ("zsobol", "hold"),
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

/// `--features on`: the feature-aware permutation renders on the CPU and
/// on the GPU (the same passes, bit for bit: conformance), and says so.
#[test]
fn feature_aware_permutation_renders_on_cpu_and_gpu() {
    let exe = tracer();
    let dir = tempfile::tempdir().unwrap();
    for device in ["cpu", "gpu"] {
        let out = dir.path().join(device);
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
                "--mode",
                "permute",
                "--features",
                "on",
                "--device",
                device,
                "--out",
                out.to_str().unwrap(),
            ],
        );
        let t = text(&o);
        if device == "gpu" && !o.status.success() {
            assert!(t.contains("no GPU adapter"), "{t}");
            assert!(!gpu_required(), "BLUENOISE_REQUIRE_GPU=1 and no GPU: {t}");
            eprintln!("SKIPPED (GPU features): {t}");
            continue;
        }
        assert!(o.status.success() && t.contains("features on"), "{device}: {t}");
        assert_eq!(png_size(&out.join("mean.png")), (24, 16));
    }
}

/// `--mode temporal` on the CPU and the GPU, with the seeds alone, with
/// ZSobol's jitter (QUALITY.md's `temporal-permute-jitter` row) and with the
/// feature-aware permutation: the 64 tile by default, and the mode and
/// features named in the summary.
#[test]
fn temporal_mode_renders_on_cpu_and_gpu() {
    let exe = tracer();
    let dir = tempfile::tempdir().unwrap();
    for (device, sampler, features) in [
        ("cpu", "seeds", "off"),
        ("gpu", "seeds", "off"),
        ("cpu", "zsobol-jitter", "off"),
        ("gpu", "zsobol-jitter", "off"),
        ("cpu", "seeds", "on"),
        ("gpu", "seeds", "on"),
    ] {
        let out = dir.path().join(format!("{device}-{sampler}-{features}"));
        let args = [
            "render",
            "--width",
            "24",
            "--height",
            "16",
            "--frames",
            "3",
            "--mode",
            "temporal",
            "--sampler",
            sampler,
            "--features",
            features,
            "--device",
            device,
            "--out",
        ];
        let o = run(&exe, &[&args[..], &[out.to_str().unwrap()]].concat());
        let t = text(&o);
        if device == "gpu" && !o.status.success() {
            assert!(t.contains("no GPU adapter"), "{t}");
            assert!(!gpu_required(), "BLUENOISE_REQUIRE_GPU=1 and no GPU: {t}");
            eprintln!("SKIPPED (GPU temporal mode): {t}");
            continue;
        }
        let summary = format!(
            "features {}",
            if features == "on" {
                "on, demodulated key"
            } else {
                "off"
            }
        );
        assert!(
            o.status.success() && t.contains("Temporal mode") && t.contains(&summary),
            "{device}, {sampler}, features {features}: {t}"
        );
        assert_eq!(png_size(&out.join("mean.png")), (24, 16));
    }
}

/// `--feature-key`: the textured glTF Cornell box with each key on the CPU;
/// a key the GPU does not compute, or a key without `--features on`, is a
/// clear error before anything is written.
#[test]
fn feature_keys_render_the_textured_gltf_scene() {
    let exe = tracer();
    let dir = tempfile::tempdir().unwrap();
    let scene =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../gpu-tracer/tests/data/gltf/cornell_textured.gltf");
    let scene = scene.to_str().unwrap();
    let args = |key: &str, device: &str, features: &str, out: &Path| -> Vec<String> {
        [
            "render",
            "--scene",
            scene,
            "--width",
            "32",
            "--height",
            "32",
            "--frames",
            "3",
            "--mode",
            "permute",
            "--features",
            features,
            "--feature-key",
            key,
            "--device",
            device,
            "--out",
        ]
        .iter()
        .map(|s| s.to_string())
        .chain([out.to_str().unwrap().to_string()])
        .collect()
    };
    let mut means = Vec::new();
    for key in ["demodulated", "raw", "history"] {
        let out = dir.path().join(key);
        let a = args(key, "cpu", "on", &out);
        let o = run(&exe, &a.iter().map(String::as_str).collect::<Vec<_>>());
        let t = text(&o);
        assert!(
            o.status.success() && t.contains(&format!("features on, {key} key")),
            "{key}: {t}"
        );
        let img = image::open(out.join("mean.exr")).unwrap().into_rgb32f();
        means.push(img.into_raw());
    }
    // The keys change the seeds' order, so the frames after the first differ.
    assert_ne!(means[0], means[1]);
    assert_ne!(means[0], means[2]);

    let out = dir.path().join("no-features");
    let a = args("raw", "cpu", "off", &out);
    let o = run(&exe, &a.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(
        !o.status.success() && text(&o).contains("--features on"),
        "{}",
        text(&o)
    );
    assert!(!out.exists(), "nothing is written for a refused command line");

    let out = dir.path().join("gpu-history");
    let a = args("history", "gpu", "on", &out);
    let o = run(&exe, &a.iter().map(String::as_str).collect::<Vec<_>>());
    let t = text(&o);
    assert!(!o.status.success(), "{t}");
    if t.contains("no GPU adapter") {
        assert!(!gpu_required(), "BLUENOISE_REQUIRE_GPU=1 and no GPU: {t}");
        eprintln!("SKIPPED (GPU feature key): {t}");
    } else {
        assert!(
            t.contains("not supported on the GPU") && t.contains("history"),
            "{t}"
        );
    }
}

/// Mean absolute difference between horizontally adjacent pixels' luma of
/// an EXR: how rough (noisy) an image is.
fn roughness(path: &Path) -> f32 {
    let img = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb32f();
    let luma = |x: u32, y: u32| {
        let p = img.get_pixel(x, y);
        0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]
    };
    let mut sum = 0.0;
    for y in 0..img.height() {
        for x in 1..img.width() {
            sum += (luma(x, y) - luma(x - 1, y)).abs();
        }
    }
    sum / (img.height() * (img.width() - 1)) as f32
}

/// Renders `frames` frames of the 48x40 Cornell box on the CPU with
/// `--save-frames` and `extra` arguments into a new temporary directory;
/// returns the output, the directory (removed when dropped) and the output path.
fn render_small_box(
    exe: &std::path::PathBuf,
    frames: &str,
    extra: &[&str],
) -> (std::process::Output, tempfile::TempDir, std::path::PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let mut args = vec![
        "render",
        "--scene",
        "cornell",
        "--width",
        "48",
        "--height",
        "40",
        "--frames",
        frames,
        "--device",
        "cpu",
        "--save-frames",
    ];
    args.extend_from_slice(extra);
    args.extend_from_slice(&["--out", out.to_str().unwrap()]);
    (run(exe, &args), dir, out)
}

#[test]
fn filters_write_filtered_frames_beside_raw_ones() {
    let exe = tracer();
    for filter in ["taa", "gauss", "atrous", "taa+atrous"] {
        let (o, _dir, out) = render_small_box(&exe, "6", &["--mode", "permute", "--filter", filter]);
        assert!(o.status.success(), "--filter {filter}: {}", text(&o));
        for t in 0..6 {
            for ext in ["exr", "png"] {
                let f = out.join(format!("frames/filtered_{t:05}.{ext}"));
                assert!(f.is_file(), "--filter {filter}: no {}", f.display());
            }
        }
        assert_eq!(png_size(&out.join("last_filtered.png")), (48, 40));
        let (raw, filtered) = (
            roughness(&out.join("last.exr")),
            roughness(&out.join("last_filtered.exr")),
        );
        println!("--filter {filter}: neighbour luma difference {filtered:.4} (raw {raw:.4})");
        assert!(
            filtered < 0.8 * raw,
            "--filter {filter} did not smooth: {filtered} vs raw {raw}"
        );
    }
    for bad in [
        &["--filter", "blur"][..],
        &["--filter", "taa", "--taa-alpha", "0"],
        &["--filter", "atrous", "--taa-clamp", "off"],
    ] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let mut args = vec![
            "render",
            "--width",
            "8",
            "--height",
            "8",
            "--device",
            "cpu",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(bad);
        let o = run(&exe, &args);
        assert!(!o.status.success(), "{bad:?} was accepted");
        let msg = text(&o);
        assert!(
            msg.contains("filter") || msg.contains("alpha"),
            "{bad:?}: unclear message: {msg}"
        );
        assert!(!out.exists(), "{bad:?} created the output directory");
    }
}

/// `--taa-clamp off` runs the history without its clamp: with a still camera the
/// filtered frame is then the exponential history (alpha 0.1) of the raw frames,
/// where the clamped one departs from it.
#[test]
fn taa_without_its_clamp_is_the_exponential_history() {
    let exe = tracer();
    let frames = 8;
    let render = |clamp: &str| {
        let (o, _dir, out) = render_small_box(&exe, "8", &["--filter", "taa", "--taa-clamp", clamp]);
        assert!(o.status.success(), "--taa-clamp {clamp}: {}", text(&o));
        let read = |name: String| image::open(out.join(name)).unwrap().into_rgb32f().into_raw();
        let mut history = read(format!("frames/frame_{:05}.exr", 0));
        for t in 1..frames {
            for (h, c) in history.iter_mut().zip(read(format!("frames/frame_{t:05}.exr"))) {
                *h += 0.1 * (c - *h);
            }
        }
        let filtered = read("last_filtered.exr".into());
        let far = history
            .iter()
            .zip(&filtered)
            .filter(|(h, f)| (*h - *f).abs() > 1e-3 * (1.0 + h.abs()))
            .count();
        (far, history.len())
    };
    let (off, n) = render("off");
    assert_eq!(
        off, 0,
        "{off} of {n} values away from the exponential history without the clamp"
    );
    let (on, _) = render("on");
    println!("values away from the exponential history: clamp on {on} of {n}, off {off}");
    assert!(on > n / 100, "the clamp changed only {on} of {n} values");
}

/// `--sampler spatiotemporal` defaults to the hold mode, and with a moving
/// camera its homes follow the picture (reprojection on by default).
#[test]
fn spatiotemporal_defaults_to_hold_and_follows_a_pan() {
    let exe = tracer();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = run(
        &exe,
        &[
            "render",
            "--width",
            "32",
            "--height",
            "24",
            "--frames",
            "4",
            "--sampler",
            "spatiotemporal",
            "--camera-path",
            "pan",
            "--camera-speed",
            "1.5",
            "--device",
            "cpu",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    let t = text(&o);
    assert!(o.status.success(), "{t}");
    // The homes follow every surface: no speed below which they stay.
    assert!(t.contains("Hold mode") && t.contains("reprojection on,"), "{t}");
    let img = image::open(out.join("mean.exr")).unwrap().into_rgb32f();
    let mean: f32 = img.pixels().map(|p| p[0] + p[1] + p[2]).sum::<f32>() / (32.0 * 24.0);
    assert!(mean.is_finite() && mean > 0.01, "mean radiance {mean}");
}

/// What `render` takes when `--mode` or `--sampler` is left out: the
/// temporal permutation with ZSobol's jitter; the walk with `--tile 128`;
/// white noise stays white noise; past ZSobol's limits the seed stream, with
/// a note; `--mode hold` alone takes the Kronecker spatiotemporal sampler, and
/// so does a history without TAA's clamp when nothing is named; a sampler that
/// draws every decision takes white seeds.
#[test]
fn render_defaults_to_the_temporal_permutation_with_zsobols_jitter() {
    let exe = tracer();
    let cases: [(&[&str], &str, bool); 9] = [
        (&[], "(Temporal mode, zsobol-jitter sampler", false),
        (&["--tile", "128"], "(Permute mode, zsobol-jitter sampler", false),
        (&["--mode", "white"], "(White mode, seeds sampler", false),
        (
            &["--mode", "permute"],
            "(Permute mode, zsobol-jitter sampler",
            false,
        ),
        (&["--spp", "257"], "(Temporal mode, seeds sampler", true),
        (
            &["--mode", "hold"],
            "(Hold mode, spatiotemporal-kronecker sampler",
            false,
        ),
        (&["--sampler", "zsobol"], "(White mode, zsobol sampler", false),
        (
            &["--filter", "taa", "--taa-clamp", "off"],
            "(Hold mode, spatiotemporal-kronecker sampler",
            false,
        ),
        (
            &["--filter", "taa", "--taa-clamp", "off", "--mode", "temporal"],
            "(Temporal mode, zsobol-jitter sampler",
            false,
        ),
    ];
    for (extra, summary, note) in cases {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let mut args = vec![
            "render",
            "--width",
            "16",
            "--height",
            "12",
            "--frames",
            "2",
            "--max-depth",
            "2",
            "--device",
            "cpu",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let o = run(&exe, &args);
        let t = text(&o);
        assert!(o.status.success() && t.contains(summary), "{extra:?}: {t}");
        assert_eq!(
            t.contains("note: the default pixel jitter (zsobol-jitter) takes at most 256 spp"),
            note,
            "{extra:?}: {t}"
        );
    }
}
