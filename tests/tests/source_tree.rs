//! Issue 31: the source tree keeps one home per job. Every crate's module
//! graph has no cycle between sibling modules (`e2e_tests::module_graph`
//! says what counts), and no source file is longer than 800 lines (generated
//! shaders and test fixtures are not `.rs` files, so none is exempt).

use e2e_tests::module_graph::{rust_files, CrateGraph};
use std::path::{Path, PathBuf};

/// The longest a hand-written source file may be, in lines.
const MAX_LINES: usize = 800;

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("workspace root")
        .to_path_buf()
}

/// Every crate root of the workspace (and the out-of-workspace shader builder).
fn crate_roots() -> Vec<PathBuf> {
    let root = workspace();
    let mut roots = Vec::new();
    for krate in [
        "sampler-core",
        "sampler-core/bake-cli",
        "gpu-tracer",
        "gpu-tracer/kernels",
        "gpu-tracer/shader-sources",
        "gpu-tracer/shader-builder",
        "conformance",
        "tests",
    ] {
        for file in ["src/lib.rs", "src/main.rs"] {
            let path = root.join(krate).join(file);
            if path.exists() {
                roots.push(path);
            }
        }
        // Binaries with modules of their own: `src/bin/<name>/main.rs`.
        if let Ok(bins) = std::fs::read_dir(root.join(krate).join("src/bin")) {
            let mut bins: Vec<PathBuf> = bins
                .filter_map(|e| e.ok().map(|e| e.path().join("main.rs")))
                .filter(|p| p.exists())
                .collect();
            bins.sort();
            roots.extend(bins);
        }
    }
    roots
}

#[test]
fn no_crate_has_a_cycle_between_sibling_modules() {
    let roots = crate_roots();
    assert!(roots.len() >= 8, "crate roots found: {roots:?}");
    let mut report = String::new();
    let mut modules = 0;
    for root in &roots {
        let graph = CrateGraph::read(root).unwrap_or_else(|e| panic!("{e}"));
        modules += graph.len();
        for cycle in graph.cycles() {
            report.push_str(&format!("cycle in {}:\n", root.display()));
            for edge in cycle {
                report.push_str(&format!(
                    "  {} -> {}  ({})\n",
                    edge.from.join("::"),
                    edge.to.join("::"),
                    edge.at
                ));
            }
        }
    }
    println!("{} crate roots, {modules} modules read", roots.len());
    assert!(report.is_empty(), "import cycles between modules:\n{report}");
}

#[test]
fn no_source_file_is_longer_than_800_lines() {
    let root = workspace();
    let mut long = Vec::new();
    let mut count = 0;
    for dir in ["sampler-core", "gpu-tracer", "conformance", "tests"] {
        for file in rust_files(&root.join(dir)) {
            count += 1;
            let lines = std::fs::read_to_string(&file)
                .expect("readable source")
                .lines()
                .count();
            if lines > MAX_LINES {
                long.push(format!(
                    "{} ({lines} lines)",
                    file.strip_prefix(&root).unwrap_or(&file).display()
                ));
            }
        }
    }
    assert!(count > 100, "only {count} source files found");
    assert!(
        long.is_empty(),
        "files over {MAX_LINES} lines:\n{}",
        long.join("\n")
    );
}
