//! Where the generated files live, [`generate`] (all of them, in memory),
//! and writing them or checking the committed ones are fresh.

use crate::select::{permutation_module, single_entry};
use crate::translate::{write_glsl, write_hlsl, write_msl, write_wgsl};
use crate::{glsl_file, hlsl_file, msl_file, Error, ENTRIES, LANGUAGE_DIRS, SPIRV_PATH, WGSL_FILE};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// The workspace root (two levels above this crate).
pub fn workspace_root() -> PathBuf {
    let here = Path::new(env!("CARGO_MANIFEST_DIR"));
    here.parent().and_then(Path::parent).unwrap_or(here).to_path_buf()
}

/// One generated file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GeneratedFile {
    /// Path relative to [`OUTPUT_DIR`](crate::OUTPUT_DIR), `/`-separated, e.g. [`WGSL_FILE`].
    pub path: String,
    /// The whole text, header included, ending in a newline.
    pub text: String,
}

/// The SHA-256 digest of `data` as 64 lowercase hex digits (what
/// `sha256sum` prints), naming the SPIR-V in every header.
pub fn sha256_hex(data: &[u8]) -> String {
    Sha256::digest(data).iter().map(|b| format!("{b:02x}")).collect()
}

/// Translates `spirv` (the bytes of [`SPIRV_PATH`]) into every generated
/// file, in memory, sorted by path: the WGSL module with all entry points,
/// and one GLSL, HLSL and MSL file per entry point. Deterministic: the same bytes give the same files.
///
/// # Errors
/// As [`permutation_module`], and [`Error::Backend`] / [`Error::Validation`]
/// when a back end fails or the WGSL output does not re-validate.
pub fn generate(spirv: &[u8]) -> Result<Vec<GeneratedFile>, Error> {
    let sha = sha256_hex(spirv);
    let (module, info) = permutation_module(spirv)?;
    let mut files = vec![GeneratedFile {
        path: WGSL_FILE.to_string(),
        text: write_wgsl(&module, &info, &sha)?,
    }];
    for entry in &ENTRIES {
        let (single, single_info) = single_entry(&module, entry)?;
        files.push(GeneratedFile {
            path: glsl_file(entry),
            text: write_glsl(&single, &single_info, entry, &sha)?,
        });
        files.push(GeneratedFile {
            path: hlsl_file(entry),
            text: write_hlsl(&single, &single_info, entry, &sha)?,
        });
        files.push(GeneratedFile {
            path: msl_file(entry),
            text: write_msl(&single, &single_info, entry, &sha)?,
        });
    }
    files.sort_by(|a, b| a.path.cmp(&b.path));
    Ok(files)
}

/// Reads [`SPIRV_PATH`] under `root` and [`generate`]s from it.
///
/// # Errors
/// [`Error::Io`] if the SPIR-V cannot be read, else as [`generate`].
pub fn generate_from_workspace(root: &Path) -> Result<Vec<GeneratedFile>, Error> {
    let path = root.join(SPIRV_PATH);
    let spirv = std::fs::read(&path).map_err(|source| Error::Io { path, source })?;
    generate(&spirv)
}

/// Files in the [`LANGUAGE_DIRS`] of `out_dir`, relative and `/`-separated.
fn existing_files(out_dir: &Path) -> Vec<String> {
    let mut found = Vec::new();
    for dir in LANGUAGE_DIRS {
        if let Ok(entries) = std::fs::read_dir(out_dir.join(dir)) {
            for e in entries.flatten() {
                if e.path().is_file() {
                    found.push(format!("{dir}/{}", e.file_name().to_string_lossy()));
                }
            }
        }
    }
    found.sort();
    found
}

/// How the committed files in `out_dir` differ from `files`: one line per
/// stale, missing or extra file; empty when they are fresh.
pub fn stale_files(out_dir: &Path, files: &[GeneratedFile]) -> Vec<String> {
    let mut problems = Vec::new();
    for f in files {
        match std::fs::read_to_string(out_dir.join(&f.path)) {
            Ok(text) if text == f.text => {}
            Ok(_) => problems.push(format!("{}: stale", f.path)),
            Err(e) => problems.push(format!("{}: missing ({e})", f.path)),
        }
    }
    for path in existing_files(out_dir) {
        if !files.iter().any(|f| f.path == path) {
            problems.push(format!("{path}: not generated any more (remove it)"));
        }
    }
    problems
}

/// Writes `files` under `out_dir` and removes the files of the
/// [`LANGUAGE_DIRS`] that are not among them.
///
/// # Errors
/// [`Error::Io`] for the first file that cannot be written or removed.
pub fn write_files(out_dir: &Path, files: &[GeneratedFile]) -> Result<(), Error> {
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| Error::Io { path, source }
    };
    for f in files {
        let path = out_dir.join(&f.path);
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(io(dir))?;
        }
        std::fs::write(&path, &f.text).map_err(io(&path))?;
    }
    for path in existing_files(out_dir) {
        if !files.iter().any(|f| f.path == path) {
            let path = out_dir.join(path);
            std::fs::remove_file(&path).map_err(io(&path))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::sha256_hex;

    /// FIPS 180-4 example vectors (one block, two blocks, empty).
    #[test]
    fn matches_the_standard_vectors() {
        assert_eq!(
            sha256_hex(b""),
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"
        );
        assert_eq!(
            sha256_hex(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
        assert_eq!(
            sha256_hex(b"abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1"
        );
    }
}
