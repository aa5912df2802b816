//! Quiet start on a headless machine.
//!
//! Creating a Vulkan instance loads Mesa's window-system layer even when no
//! window is ever opened, and on a machine without a desktop session (no
//! `XDG_RUNTIME_DIR`) it prints
//! `error: XDG_RUNTIME_DIR is invalid or not set in the environment.` to
//! stderr, twice, before a render that then succeeds. The line is harmless
//! but reads as a failure. [`prepare_headless_environment`] gives the process
//! a private runtime directory first, so the line never appears.

use std::path::{Path, PathBuf};

/// Name of the environment variable the window-system layer reads.
pub const RUNTIME_DIR_ENV: &str = "XDG_RUNTIME_DIR";

/// Where `XDG_RUNTIME_DIR` points after [`prepare_headless_environment`]:
/// the variable's own value when it names a directory, else a private
/// directory `bluenoise-runtime-<user>` under the system's temporary
/// directory (created with mode `0700` on Unix). `None` when that directory
/// cannot be made (the loader's line may then appear; nothing else changes).
///
/// Call it at the start of `main`, before any thread is spawned: it sets an
/// environment variable of the process.
pub fn prepare_headless_environment() -> Option<PathBuf> {
    if let Some(dir) = std::env::var_os(RUNTIME_DIR_ENV).map(PathBuf::from) {
        if dir.is_dir() {
            return Some(dir);
        }
    }
    let user = std::env::var("USER").unwrap_or_else(|_| "user".into());
    let dir = std::env::temp_dir().join(format!("bluenoise-runtime-{user}"));
    create_private_dir(&dir).ok()?;
    std::env::set_var(RUNTIME_DIR_ENV, &dir);
    Some(dir)
}

#[cfg(unix)]
fn create_private_dir(dir: &Path) -> std::io::Result<()> {
    use std::os::unix::fs::DirBuilderExt;
    match std::fs::DirBuilder::new().mode(0o700).create(dir) {
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && dir.is_dir() => Ok(()),
        other => other,
    }
}

#[cfg(not(unix))]
fn create_private_dir(dir: &Path) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_existing_runtime_dir_is_kept_and_a_missing_one_is_made() {
        // One test touches the variable, so no other test of this binary races it.
        let keep = std::env::var_os(RUNTIME_DIR_ENV);
        let existing = std::env::temp_dir();
        std::env::set_var(RUNTIME_DIR_ENV, &existing);
        assert_eq!(prepare_headless_environment(), Some(existing.clone()));
        std::env::set_var(RUNTIME_DIR_ENV, existing.join("no-such-dir-for-bluenoise"));
        let made = prepare_headless_environment().expect("a private runtime dir");
        assert!(
            made.is_dir() && made.starts_with(std::env::temp_dir()),
            "{}",
            made.display()
        );
        assert_eq!(std::env::var_os(RUNTIME_DIR_ENV).map(PathBuf::from), Some(made));
        match keep {
            Some(v) => std::env::set_var(RUNTIME_DIR_ENV, v),
            None => std::env::remove_var(RUNTIME_DIR_ENV),
        }
    }
}
