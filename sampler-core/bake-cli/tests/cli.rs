//! Runs the `bake` binary as a user would.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn bake(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_bake"))
        .args(args)
        .output()
        .expect("bake runs")
}

/// A fresh scratch directory per test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("bake-cli-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Regenerates the given default sets and compares them with the committed
/// files byte for byte (a missing committed file fails).
fn check_defaults(sets: &[&str], dir: &Path) {
    let mut args = vec!["defaults", "--out", dir.to_str().unwrap()];
    for s in sets {
        args.extend(["--only", s]);
    }
    let out = bake(&args);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let committed = bake::committed_data_dir();
    for set in bake::DefaultSet::ALL {
        let name = format!("{set:?}").to_lowercase();
        if !sets.iter().any(|s| s.replace('-', "") == name) {
            continue;
        }
        for file in set.files() {
            let fresh = std::fs::read(dir.join(file)).unwrap();
            let old = std::fs::read(committed.join(file))
                .unwrap_or_else(|e| panic!("committed {file} missing ({e}); run `bake defaults`"));
            assert!(
                fresh == old,
                "{file} differs from the committed file: rerun `bake defaults --out sampler-core/data`"
            );
        }
    }
}

#[test]
fn default_tiles_and_tables_regenerate_byte_for_byte() {
    check_defaults(&["tile64", "tile128"], &scratch("tiles"));
}

#[test]
fn default_stbn_regenerates_byte_for_byte() {
    check_defaults(&["stbn"], &scratch("stbn"));
}

/// The STBN bake plus 8 sweeps: about 18 s in the test profile on 2 cores.
#[test]
fn default_filter_adapted_regenerates_byte_for_byte() {
    check_defaults(&["filter-adapted"], &scratch("filter-adapted"));
}

/// The temporal permutation's 64x64x64 target and its 64 slice tables
/// (about 3 s in release on 2 cores).
#[test]
fn default_temporal_target_regenerates_byte_for_byte() {
    check_defaults(&["temporal64"], &scratch("temporal64"));
}

#[test]
fn filter_adapted_writes_ranks_slices_and_exr() {
    let dir = scratch("filter-adapted-small");
    let d = dir.to_str().unwrap();
    let out = bake(&[
        "filter-adapted",
        "--size",
        "16x16x4",
        "--spatial",
        "box:3",
        "--temporal",
        "exp:0.2:0.2",
        "--sweeps",
        "2",
        "--distribution",
        "gaussian",
        "--bits",
        "8",
        "--out",
        d,
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let ranks = std::fs::read(dir.join("filter_adapted_16x16x4.bin")).unwrap();
    assert_eq!(ranks.len(), 2 * 16 * 16 * 4);
    let values = std::fs::read(dir.join("values_16x16x4.bin")).unwrap();
    assert_eq!(values.len(), 4 * 16 * 16 * 4);
    for z in 0..4 {
        let png = image::open(dir.join(format!("slice_{z:03}.png"))).unwrap();
        assert_eq!((png.width(), png.height()), (16, 16));
        let exr = image::open(dir.join(format!("slice_{z:03}.exr")))
            .unwrap()
            .into_rgb32f();
        // Gaussian values: the EXR holds them (negative ones too).
        assert!(exr.pixels().any(|p| p[0] < 0.0) && exr.pixels().any(|p| p[0] > 0.0));
    }
    let out = bake(&[
        "filter-adapted",
        "--size",
        "16x16x4",
        "--value",
        "cosine",
        "--sweeps",
        "1",
        "--out",
        d,
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(
        std::fs::read(dir.join("values_16x16x4.bin")).unwrap().len(),
        4 * 3 * 16 * 16 * 4
    );
    let out = bake(&[
        "filter-adapted",
        "--size",
        "16x16x4",
        "--temporal",
        "exp:nan",
        "--out",
        d,
    ]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("alpha"), "{}", text(&out.stderr));
}

#[test]
fn default_sampler_keys_regenerate_byte_for_byte() {
    check_defaults(&["keys"], &scratch("keys"));
}

#[test]
fn keys_and_vector_masks_are_written() {
    let dir = scratch("apriori");
    let keys = dir.join("k.bin");
    let out = bake(&[
        "keys",
        "--side",
        "16",
        "--pairs",
        "2",
        "--levels",
        "3",
        "--sweeps",
        "8",
        "--out",
        keys.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    println!("{}", text(&out.stdout));
    assert_eq!(std::fs::metadata(&keys).unwrap().len(), 4 * 16 * 16 * 2 * 3);
    let out = bake(&[
        "vector-stbn",
        "--kind",
        "cosine",
        "--size",
        "8x8x4",
        "--sweeps",
        "8",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    println!("{}", text(&out.stdout));
    let bin = dir.join("vector_stbn_cosine_8x8x4.bin");
    assert_eq!(std::fs::metadata(&bin).unwrap().len(), 4 * 3 * 8 * 8 * 4);
    for z in 0..4 {
        assert!(dir.join(format!("slice_{z:03}.png")).exists());
    }
    let out = bake(&["keys", "--side", "48", "--out", keys.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("48"), "{}", text(&out.stderr));
}

#[test]
fn bad_sizes_are_clear_errors() {
    let dir = scratch("sizes");
    let out_file = dir.join("m.bin");
    for size in ["48", "0", "64x24", "abc", "1x2x4"] {
        let out = bake(&["mask", "--size", size, "--out", out_file.to_str().unwrap()]);
        assert!(!out.status.success(), "size {size}");
        let err = text(&out.stderr);
        assert!(err.contains("size"), "size {size}: {err}");
    }
    let out = bake(&["stbn", "--size", "64x64", "--out", dir.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("WxHxD"));
    let out = bake(&[
        "mask",
        "--size",
        "16",
        "--sigma",
        "-1",
        "--out",
        out_file.to_str().unwrap(),
    ]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("sigma"));
}

#[test]
fn unwritable_paths_are_clear_errors() {
    let dir = scratch("unwritable");
    // A regular file where a directory is needed.
    let blocker = dir.join("file");
    std::fs::write(&blocker, b"x").unwrap();
    let inside = blocker.join("m.bin");
    let out = bake(&["mask", "--size", "16", "--out", inside.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("cannot write"),
        "{}",
        text(&out.stderr)
    );
    let out = bake(&["defaults", "--out", inside.to_str().unwrap(), "--only", "tile64"]);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("cannot create directory"),
        "{}",
        text(&out.stderr)
    );
    let out = bake(&[
        "mask",
        "--size",
        "16",
        "--out",
        dir.join("m.txt").to_str().unwrap(),
    ]);
    assert!(!out.status.success());
}

#[test]
fn mask_png_and_retarget_round_trip() {
    let dir = scratch("roundtrip");
    let png = dir.join("m.png");
    let out = bake(&[
        "mask",
        "--size",
        "16x8",
        "--bits",
        "8",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let img = image::open(&png).unwrap().to_luma8();
    assert_eq!(img.dimensions(), (16, 8));
    // 128 ranks on 256 levels: levels 0, 2, 4, ..., 254, each once.
    let mut levels: Vec<u8> = img.pixels().map(|p| p.0[0]).collect();
    levels.sort_unstable();
    assert!(levels.iter().enumerate().all(|(i, &l)| l as usize == 2 * i));

    let bin = dir.join("m.bin");
    let out = bake(&[
        "mask",
        "--size",
        "32",
        "--seed",
        "4",
        "--out",
        bin.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(std::fs::metadata(&bin).unwrap().len(), 32 * 32 * 4);
    let out = bake(&[
        "retarget",
        "--tile",
        bin.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
        "--anneal",
        "10",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let report = text(&out.stdout);
    assert_eq!(report.matches("-> exact").count(), 4, "{report}");
    assert_eq!(report.matches("annealing").count(), 4, "{report}");
    let tables = bake::decode_u32(&std::fs::read(dir.join("tables_32.bin")).unwrap()).unwrap();
    assert_eq!(tables.len(), 4 * 32 * 32);
    for t in tables.chunks(32 * 32) {
        assert!(sampler_core::RetargetTable::new(32, t).is_ok());
    }
}

#[test]
fn stbn_writes_slices_and_binary() {
    let dir = scratch("stbn-small");
    let out = bake(&["stbn", "--size", "8x8x4", "--out", dir.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let bytes = std::fs::read(dir.join("stbn_8x8x4.bin")).unwrap();
    let mask = sampler_core::SpatiotemporalMask::new(8, 8, 4, &bytes).unwrap();
    for z in 0..4 {
        let mut ranks: Vec<u32> = (0..64).map(|i| mask.rank(i % 8, i / 8, z)).collect();
        ranks.sort_unstable();
        assert!(ranks.iter().enumerate().all(|(i, &r)| r == i as u32));
        let img = image::open(dir.join(format!("slice_{z:03}.png"))).unwrap();
        assert_eq!((img.width(), img.height()), (8, 8));
    }
}
