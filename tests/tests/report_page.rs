//! Issue 5, part 3: the quality report opens in a browser and every image loads.
//!
//! Runs `conformance report` at a tiny size, opens `index.html` in headless Chromium
//! with `--dump-dom`, and reads the `data-images-loaded="ok/total"` attribute the
//! page's own script sets on `load` (an image counts when `naturalWidth > 0`).
//! Without Chromium the test prints SKIPPED, unless `BLUENOISE_REQUIRE_GPU=1` or
//! `BLUENOISE_REQUIRE_BROWSER=1` is set (CI), then it fails.

use e2e_tests::{build_bin, gpu_required, run, text};
use std::path::Path;
use std::process::Command;

const CHROMIUM: &str = "/usr/bin/chromium";

fn browser_required() -> bool {
    gpu_required() || std::env::var("BLUENOISE_REQUIRE_BROWSER").as_deref() == Ok("1")
}

#[test]
fn report_page_loads_every_image() {
    if !Path::new(CHROMIUM).exists() {
        let why = format!("{CHROMIUM} is not installed (Debian package `chromium`)");
        assert!(!browser_required(), "{why}, and a browser is required");
        println!("SKIPPED: {why}");
        return;
    }
    let exe = build_bin("conformance", "conformance");
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("report");
    let out_str = out.to_str().expect("utf-8 path");
    let start = std::time::Instant::now();
    let o = run(
        &exe,
        &[
            "report",
            "--out",
            out_str,
            "--size",
            "32",
            "--frames",
            "4",
            "--ref-spp",
            "16",
            "--no-cache",
        ],
    );
    assert!(o.status.success(), "report failed: {}", text(&o));
    println!("report written in {:.1} s", start.elapsed().as_secs_f64());
    let html = std::fs::read_to_string(out.join("index.html")).expect("index.html");
    let imgs = html.matches("<img ").count();
    println!("index.html: {} bytes, {imgs} <img> tags", html.len());
    assert!(
        imgs >= 20,
        "expected the frames, insets, spectra and plots, found {imgs} images"
    );

    let profile = tempfile::tempdir().expect("profile dir");
    let url = format!("file://{}", out.join("index.html").display());
    let o = Command::new(CHROMIUM)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
            &format!("--user-data-dir={}", profile.path().display()),
            "--virtual-time-budget=5000",
            "--dump-dom",
            &url,
        ])
        .output()
        .expect("chromium starts");
    let dom = String::from_utf8_lossy(&o.stdout);
    let attr = dom
        .split("data-images-loaded=\"")
        .nth(1)
        .and_then(|rest| rest.split('"').next())
        .map(str::to_owned);
    println!(
        "chromium: exit {:?}, data-images-loaded = {attr:?}",
        o.status.code()
    );
    let attr = attr.unwrap_or_else(|| {
        panic!(
            "the page's load script did not run; chromium said: {}",
            String::from_utf8_lossy(&o.stderr)
        )
    });
    let (ok, total) = attr.split_once('/').expect("ok/total");
    let (ok, total): (usize, usize) = (ok.parse().expect("count"), total.parse().expect("count"));
    assert_eq!(total, imgs, "the browser saw {total} images, the HTML has {imgs}");
    assert_eq!(ok, total, "only {ok} of {total} images loaded");
}
