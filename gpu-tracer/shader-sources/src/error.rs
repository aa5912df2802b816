//! The generator's [`Error`] and [`chain`], which flattens a cause chain
//! into one message.

use crate::ENTRIES;
use kernels::permute_entry::PERMUTE_WORKGROUP;
use std::fmt;
use std::path::PathBuf;

/// What can go wrong while generating.
#[derive(Debug)]
#[non_exhaustive]
pub enum Error {
    /// naga's SPIR-V front end rejected the module.
    Spirv(naga::front::spv::Error),
    /// An entry point of [`ENTRIES`] is not in the SPIR-V (the name is
    /// the SPIR-V one).
    MissingEntry(&'static str),
    /// An entry point of [`ENTRIES`] does not have 64x1x1 workgroups.
    WorkgroupSize {
        /// The entry point's SPIR-V name.
        entry: &'static str,
        /// Its workgroup size.
        size: [u32; 3],
    },
    /// An entry point's bindings differ from
    /// [`Entry::bindings`](crate::Entry::bindings) (the kernels changed;
    /// update [`ENTRIES`] and the README).
    Bindings {
        /// The entry point's name.
        entry: &'static str,
        /// The bindings (group, binding) it uses.
        found: Vec<(u32, u32)>,
    },
    /// naga's validator rejected a module (`what` says which).
    Validation {
        /// Which module: the kept entry points, one entry point, or the
        /// re-parsed WGSL output.
        what: String,
        /// The validator's message with its causes.
        message: String,
    },
    /// A back end failed, or its output lacks an entry point.
    Backend {
        /// `"wgsl"`, `"glsl"`, `"hlsl"` or `"msl"`.
        language: &'static str,
        /// What failed.
        message: String,
    },
    /// Reading the SPIR-V or writing an output failed.
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Spirv(e) => write!(f, "naga rejected the SPIR-V: {e}"),
            Error::MissingEntry(name) => write!(f, "entry point {name} is not in the SPIR-V"),
            Error::WorkgroupSize { entry, size } => write!(
                f,
                "entry point {entry} has workgroup size {size:?}, expected [{PERMUTE_WORKGROUP}, 1, 1]"
            ),
            Error::Bindings { entry, found } => write!(
                f,
                "entry point {entry} uses the bindings (group, binding) {found:?}, \
                 not group 0 bindings 0..{} as ENTRIES says",
                ENTRIES
                    .iter()
                    .find(|e| e.name == *entry)
                    .map_or(0, |e| e.bindings.len())
            ),
            Error::Validation { what, message } => write!(f, "validating {what}: {message}"),
            Error::Backend { language, message } => write!(f, "{language} output: {message}"),
            Error::Io { path, source } => write!(f, "{}: {source}", path.display()),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Spirv(e) => Some(e),
            Error::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

/// `e` and its causes, joined by `: `.
pub(crate) fn chain(e: &dyn std::error::Error) -> String {
    let mut message = e.to_string();
    let mut cause = e.source();
    while let Some(c) = cause {
        message.push_str(": ");
        message.push_str(&c.to_string());
        cause = c.source();
    }
    message
}
