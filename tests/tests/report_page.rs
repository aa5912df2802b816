//! Issue 5, part 3 and issue 17: the quality report opens in a browser, every image
//! and SVG plot loads, and the page logs no console message.
//!
//! Runs `conformance report` at a tiny size, opens `index.html` in headless Chromium
//! with `--dump-dom`, and reads the `data-images-loaded="ok/total"` attribute the
//! page's own script sets on `load` (an image counts when `naturalWidth > 0`);
//! Chromium's console log (`--enable-logging=stderr`) must hold no message from the
//! page (a failed load or a script error would be one). A screenshot of the top of
//! the page at 1400 px width is written to `target/report_page/top.png` for the record.
//! The null row (`white-control`, another draw of white) is in the tables, never
//! ranked, and the summary says how far it strays from 1.
//! Without Chromium the test prints SKIPPED, unless `BLUENOISE_REQUIRE_GPU=1` or
//! `BLUENOISE_REQUIRE_BROWSER=1` is set (CI), then it fails.

use e2e_tests::{build_bin, gpu_required, run, text};
use std::path::Path;
use std::process::Command;

const CHROMIUM: &str = "/usr/bin/chromium";

fn browser_required() -> bool {
    gpu_required() || std::env::var("BLUENOISE_REQUIRE_BROWSER").as_deref() == Ok("1")
}

/// Headless Chromium with the flags this machine needs (no sandbox, no GPU,
/// no background networking), a fresh profile in `profile`, 5 s of virtual
/// time for the page's load script, and `args`.
fn chromium(profile: &Path, args: &[&str]) -> std::process::Output {
    let user_data = format!("--user-data-dir={}", profile.display());
    Command::new(CHROMIUM)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
            &user_data,
            "--virtual-time-budget=5000",
        ])
        .args(args)
        .output()
        .expect("chromium starts")
}

/// The text of `html` between the first `start` and the next `end`.
fn between<'a>(html: &'a str, start: &str, end: &str) -> Option<&'a str> {
    html.split(start).nth(1).and_then(|t| t.split(end).next())
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
            "6",
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

    // The null row (another draw of white): in the headline table, never
    // marked best there, never named best by the summary, which says what it reads.
    let headline = between(&html, "<table class=\"headline\">", "</table>")
        .expect("the headline table (after the real-time filters)");
    let null_row = headline
        .lines()
        .find(|l| l.contains(">white-control<"))
        .expect("the null row in the headline table");
    assert!(
        !null_row.contains("<b>"),
        "the null row is marked best: {null_row}"
    );
    let summary = between(&html, "<p class=\"summary\">", "</p>").expect("the summary");
    assert!(
        !summary.contains(">white-control</b>"),
        "the summary ranks the null row: {summary}"
    );
    assert!(
        summary.contains("<b>Chance</b>") && summary.contains("% of white's error"),
        "the summary does not say what chance reads: {summary}"
    );

    let profile = tempfile::tempdir().expect("profile dir");
    let url = format!("file://{}", out.join("index.html").display());
    let o = chromium(
        profile.path(),
        &["--enable-logging=stderr", "--v=0", "--dump-dom", &url],
    );
    let dom = String::from_utf8_lossy(&o.stdout);
    let console: Vec<&str> = std::str::from_utf8(&o.stderr)
        .unwrap_or("")
        .lines()
        .filter(|l| l.contains(":CONSOLE"))
        .collect();
    assert!(console.is_empty(), "the page logged to the console: {console:#?}");
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
    let svgs = html.matches(".svg\"").count();
    assert!(svgs >= 5, "expected the SVG plots, found {svgs}");
    // Every link leads somewhere: files beside the page, anchors on it.
    let hrefs: Vec<&str> = html
        .split("href=\"")
        .skip(1)
        .filter_map(|rest| rest.split('"').next())
        .collect();
    assert!(
        hrefs.len() >= 10,
        "expected a link per figure, found {}",
        hrefs.len()
    );
    for href in &hrefs {
        match href.strip_prefix('#') {
            Some(id) => assert!(html.contains(&format!("id=\"{id}\"")), "no element #{id}"),
            None => assert!(out.join(href).is_file(), "link to a missing file: {href}"),
        }
    }
    let radial = html.matches("-spectrum-radial.svg\"").count();
    assert!(
        radial >= 2 * 8,
        "expected a radial plot beside each averaged spectrum, found {radial}"
    );
    for spp in [1, 4] {
        let table = std::fs::read_to_string(out.join(format!("table-spp{spp}.csv"))).expect("table data");
        assert!(
            table.starts_with("method,") && table.lines().count() >= 9,
            "table-spp{spp}.csv"
        );
        assert!(
            html.contains(&format!("table-spp{spp}.csv")),
            "no link to table-spp{spp}.csv"
        );
    }
    for stem in [
        "plot-radial",
        "plot-lf",
        "plot-blur1",
        "plot-accumulated",
        "plot-walk",
        "plot-temporal",
    ] {
        let csv = std::fs::read_to_string(out.join(format!("{stem}.csv"))).expect("plot data");
        assert!(
            csv.starts_with("curve,x,y\n") && csv.lines().count() > 10,
            "{stem}.csv"
        );
    }

    // The top of the page at 1400 px width, for the record.
    let shots = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/report_page");
    std::fs::create_dir_all(&shots).expect("screenshot dir");
    let shot = shots.join("top.png");
    let _ = std::fs::remove_file(&shot);
    let o = chromium(
        profile.path(),
        &[
            "--hide-scrollbars",
            "--window-size=1400,1000",
            &format!("--screenshot={}", shot.display()),
            &url,
        ],
    );
    let size = std::fs::metadata(&shot).map(|m| m.len()).unwrap_or(0);
    assert!(
        size > 10_000,
        "no screenshot ({size} B): {}",
        String::from_utf8_lossy(&o.stderr)
    );
    println!("screenshot: {} ({size} B)", shot.display());
}
