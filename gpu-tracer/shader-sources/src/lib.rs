//! Generates the seed-permutation passes in WGSL, GLSL, HLSL and MSL from
//! the one Rust source: the committed rust-gpu module
//! `gpu-tracer/shaders/kernels.spv`, translated by `naga` (the version wgpu
//! uses) into `sampler-core/shaders/{wgsl,glsl,hlsl,msl}/`.
//!
//! ```text
//! cargo run -p shader-sources             # (re)writes the generated files
//! cargo run -p shader-sources -- --check  # exit 1 when a committed file is stale
//! ```
//!
//! Only the ten entry points of [`ENTRIES`] are kept (the permutation and the
//! reprojection passes); the path tracer's entry points are removed from the
//! naga module and everything only they used is compacted away, so a renderer
//! that includes a generated file does not carry the tracer.
//!
//! WGSL gets one module with all ten entry points; GLSL, HLSL and MSL one
//! file per entry point, each compacted to what that pass uses (GLSL needs
//! one `main` per shader; in HLSL and MSL this keeps registers and the MSL
//! buffer-size struct specific to one pass). rust-gpu's SPIR-V carries no
//! names, so the generator names the types and buffers before translating:
//! `FrameParams` with `sampler_core::FrameParams`'s fields, buffers after the
//! kernel parameters (`seeds_in`; `sort_seeds_in` in the shared WGSL module).
//!
//! `naga` cannot name a function `permute_entry::sort_cs`; every entry point
//! is renamed to [`Entry::name`] (`::` replaced by `_`, which is what naga's
//! namer would pick) before any back end runs, so the names are the same in
//! every language and do not depend on the namer.
//!
//! ```
//! let sort = shader_sources::ENTRIES.iter().find(|e| e.name == "permute_entry_sort_cs").unwrap();
//! assert_eq!(sort.spirv, kernels::permute_entry::SORT_ENTRY);
//! ```
//!
//! Examples: `cargo run -p shader-sources --example wgsl_integration` (a
//! small wgpu renderer calling the generated WGSL between frames) and
//! `--example cpu_permute` (the same loop with `sampler_core::permute_frame`).
//!
//! The bindings, dispatch sizes and pass order are documented in
//! `sampler-core/shaders/README.md`; conformance's `generated_shaders` test
//! checks the committed files are fresh and runs the WGSL and GLSL against
//! the CPU.

mod sha256;

pub use sha256::sha256_hex;

use kernels::permute_entry::{
    INTENSITY_ENTRY, PERMUTE_WORKGROUP, RETARGET_ENTRY, SEED_INIT_ENTRY, SORT_ENTRY,
};
use kernels::reproject_entry::{
    CLAIM_ENTRY, CLEAR_CLAIMS_ENTRY, LIST_FREE_ENTRY, RECYCLE_ENTRY, SCAN_ENTRY, TAKE_ENTRY,
};
use naga::valid::{Capabilities, ModuleInfo, ValidationFlags, Validator};
use naga::{Module, ShaderStage};
use std::collections::{BTreeMap, BTreeSet};
use std::fmt;
use std::path::{Path, PathBuf};

/// The command that regenerates the files (named in every header).
pub const COMMAND: &str = "cargo run -p shader-sources";

/// The SPIR-V the files are generated from, relative to the workspace root.
pub const SPIRV_PATH: &str = "gpu-tracer/shaders/kernels.spv";

/// Where the generated files live, relative to the workspace root. Its
/// subfolders [`LANGUAGE_DIRS`] hold only generated files; `README.md` beside
/// them is written by hand.
pub const OUTPUT_DIR: &str = "sampler-core/shaders";

/// The subfolders of [`OUTPUT_DIR`] the generator owns entirely: a file in
/// them that it does not produce is stale.
pub const LANGUAGE_DIRS: [&str; 4] = ["wgsl", "glsl", "hlsl", "msl"];

/// Metal Shading Language version of the MSL output: 2.4 (naga's default,
/// 1.0, rejects the `reverse_bits` the kernels use).
pub const MSL_VERSION: (u8, u8) = (2, 4);

/// GLSL version of the GLSL output: `#version 450 core` (Vulkan 1.x through
/// glslang, or OpenGL 4.5).
pub const GLSL_VERSION: u16 = 450;

/// One entry point kept in the generated sources.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Entry {
    /// Its name in the SPIR-V: rust-gpu's module path, a constant of
    /// `kernels::permute_entry` or `kernels::reproject_entry`.
    pub spirv: &'static str,
    /// Its name in every generated language: [`Entry::spirv`] with `::`
    /// replaced by `_`. Also the stem of its GLSL file.
    pub name: &'static str,
    /// What binding `i` (group 0) holds, for `i` in `0..bindings.len()`: the
    /// kernel's parameter name. Binding 0 is always `params`, the uniform
    /// `sampler_core::FrameParams`.
    pub bindings: &'static [&'static str],
}

/// The entry points kept, in the order a frame dispatches them within each
/// group (permutation, then reprojection). All have 64-wide workgroups
/// (`kernels::permute_entry::PERMUTE_WORKGROUP`).
pub const ENTRIES: [Entry; 10] = [
    Entry {
        spirv: SEED_INIT_ENTRY,
        name: "permute_entry_seed_init_cs",
        bindings: &["params", "seeds_out"],
    },
    Entry {
        spirv: INTENSITY_ENTRY,
        name: "permute_entry_intensity_cs",
        bindings: &["params", "color", "intensity"],
    },
    Entry {
        spirv: SORT_ENTRY,
        name: "permute_entry_sort_cs",
        bindings: &["params", "intensity", "tile", "seeds_in", "seeds_out"],
    },
    Entry {
        spirv: RETARGET_ENTRY,
        name: "permute_entry_retarget_cs",
        bindings: &["params", "table", "seeds_in", "seeds_out"],
    },
    Entry {
        spirv: CLEAR_CLAIMS_ENTRY,
        name: "reproject_entry_clear_claims_cs",
        bindings: &["params", "claims"],
    },
    Entry {
        spirv: CLAIM_ENTRY,
        name: "reproject_entry_claim_cs",
        bindings: &["params", "motion", "claims"],
    },
    Entry {
        spirv: TAKE_ENTRY,
        name: "reproject_entry_take_cs",
        bindings: &["params", "motion", "claims", "seeds_in", "seeds_out", "counts"],
    },
    Entry {
        spirv: SCAN_ENTRY,
        name: "reproject_entry_scan_cs",
        bindings: &["params", "counts"],
    },
    Entry {
        spirv: LIST_FREE_ENTRY,
        name: "reproject_entry_list_free_cs",
        bindings: &["params", "claims", "counts", "free"],
    },
    Entry {
        spirv: RECYCLE_ENTRY,
        name: "reproject_entry_recycle_cs",
        bindings: &[
            "params",
            "motion",
            "claims",
            "counts",
            "free",
            "seeds_in",
            "seeds_out",
        ],
    },
];

impl Entry {
    /// The pass's short name: [`Entry::name`] without the module prefix and
    /// the `_cs` suffix (`sort`, `clear_claims`); prefixes the names of its
    /// buffers in the generated code (`sort_seeds_in`).
    pub fn pass(&self) -> &'static str {
        let name = self.name.strip_suffix("_cs").unwrap_or(self.name);
        name.strip_prefix("permute_entry_")
            .or_else(|| name.strip_prefix("reproject_entry_"))
            .unwrap_or(name)
    }
}

/// Path of the WGSL module (all entry points), relative to [`OUTPUT_DIR`].
pub const WGSL_FILE: &str = "wgsl/seed_permutation.wgsl";
/// Path of the GLSL file of `entry` (a compute shader whose function is
/// `main`), relative to [`OUTPUT_DIR`].
pub fn glsl_file(entry: &Entry) -> String {
    format!("glsl/{}.comp", entry.name)
}

/// Path of the HLSL file of `entry` (function [`Entry::name`]), relative to
/// [`OUTPUT_DIR`].
pub fn hlsl_file(entry: &Entry) -> String {
    format!("hlsl/{}.hlsl", entry.name)
}

/// Path of the MSL file of `entry` (kernel [`Entry::name`]), relative to
/// [`OUTPUT_DIR`].
pub fn msl_file(entry: &Entry) -> String {
    format!("msl/{}.metal", entry.name)
}

/// The workspace root (two levels above this crate).
pub fn workspace_root() -> PathBuf {
    let here = Path::new(env!("CARGO_MANIFEST_DIR"));
    here.parent().and_then(Path::parent).unwrap_or(here).to_path_buf()
}

/// One generated file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GeneratedFile {
    /// Path relative to [`OUTPUT_DIR`], `/`-separated, e.g. [`WGSL_FILE`].
    pub path: String,
    /// The whole text, header included, ending in a newline.
    pub text: String,
}

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
    /// An entry point's bindings differ from [`Entry::bindings`] (the
    /// kernels changed; update [`ENTRIES`] and the README).
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
fn chain(e: &dyn std::error::Error) -> String {
    let mut message = e.to_string();
    let mut cause = e.source();
    while let Some(c) = cause {
        message.push_str(": ");
        message.push_str(&c.to_string());
        cause = c.source();
    }
    message
}

fn validate(module: &Module, what: &str) -> Result<ModuleInfo, Error> {
    Validator::new(ValidationFlags::all(), Capabilities::default())
        .validate(module)
        .map_err(|e| Error::Validation {
            what: what.to_string(),
            message: chain(e.as_inner()),
        })
}

/// Keeps only the entry points named (by their [`Entry::name`]) in `keep`
/// and drops everything nothing kept uses.
fn retain_entries(module: &mut Module, keep: &[&str]) {
    module.entry_points.retain(|ep| keep.contains(&ep.name.as_str()));
    naga::compact::compact(module, naga::compact::KeepUnused::No);
}

/// The naga module of the ten [`ENTRIES`], renamed, compacted and
/// validated: everything the generated files are written from.
///
/// # Errors
/// [`Error::Spirv`], [`Error::MissingEntry`], [`Error::WorkgroupSize`] or
/// [`Error::Validation`].
pub fn permutation_module(spirv: &[u8]) -> Result<(Module, ModuleInfo), Error> {
    let options = naga::front::spv::Options {
        // Compute only: no position to flip.
        adjust_coordinate_space: false,
        // As wgpu parses SPIR-V: capabilities naga does not know are errors.
        strict_capabilities: true,
        block_ctx_dump_prefix: None,
    };
    let mut module = naga::front::spv::parse_u8_slice(spirv, &options).map_err(Error::Spirv)?;
    for entry in &ENTRIES {
        let ep = module
            .entry_points
            .iter_mut()
            .find(|ep| ep.name == entry.spirv)
            .ok_or(Error::MissingEntry(entry.spirv))?;
        if ep.stage != ShaderStage::Compute || ep.workgroup_size != [PERMUTE_WORKGROUP, 1, 1] {
            return Err(Error::WorkgroupSize {
                entry: entry.spirv,
                size: ep.workgroup_size,
            });
        }
        ep.name = entry.name.to_string();
    }
    let names: Vec<&str> = ENTRIES.iter().map(|e| e.name).collect();
    retain_entries(&mut module, &names);
    spill_break_conditions(&mut module);
    let info = validate(&module, "the seed-permutation entry points")?;
    name_globals(&mut module, &info)?;
    name_types(&mut module)?;
    Ok((module, info))
}

/// Names every bound global variable after the kernel parameter it is
/// (rust-gpu's SPIR-V carries no names, so naga would call them `global_N`):
/// `<pass>_<parameter>`, e.g. `sort_seeds_in` for binding 3 of
/// `permute_entry_sort_cs`. rust-gpu may share one variable among entry
/// points that declare the same binding with the same type; such a variable
/// is named after the parameter alone when all users agree (`params`), else
/// after all users joined by `_or_`. Checks that each entry point uses
/// exactly the bindings of [`Entry::bindings`].
fn name_globals(module: &mut Module, info: &ModuleInfo) -> Result<(), Error> {
    let mut users: BTreeMap<naga::Handle<naga::GlobalVariable>, Vec<(&str, &str)>> = BTreeMap::new();
    for (i, ep) in module.entry_points.iter().enumerate() {
        let entry = ENTRIES
            .iter()
            .find(|e| e.name == ep.name)
            .expect("only ENTRIES are kept");
        let used = info.get_entry_point(i);
        let mut found = Vec::new();
        for (handle, global) in module.global_variables.iter() {
            if let Some(b) = global.binding.filter(|_| !used[handle].is_empty()) {
                found.push((b.group, b.binding));
                if let Some(role) = entry.bindings.get(b.binding as usize) {
                    users.entry(handle).or_default().push((entry.pass(), role));
                }
            }
        }
        found.sort_unstable();
        let expected: Vec<(u32, u32)> = (0..entry.bindings.len() as u32).map(|b| (0, b)).collect();
        if found != expected {
            return Err(Error::Bindings {
                entry: entry.name,
                found,
            });
        }
    }
    for (handle, users) in users {
        let name = match users.as_slice() {
            [(pass, role)] => format!("{pass}_{role}"),
            [(_, role), ..] if users.len() == ENTRIES.len() && users.iter().all(|u| u.1 == *role) => {
                role.to_string()
            }
            _ => users
                .iter()
                .map(|(pass, role)| format!("{pass}_{role}"))
                .collect::<Vec<_>>()
                .join("_or_"),
        };
        module.global_variables.get_mut(handle).name = Some(name);
    }
    Ok(())
}

/// `sampler_core::FrameParams`'s fields and byte offsets, in order: the
/// members of the uniform at binding 0.
pub const FRAME_PARAMS_FIELDS: [(&str, usize); 8] = {
    use core::mem::offset_of;
    use sampler_core::FrameParams as P;
    [
        ("width", offset_of!(P, width)),
        ("height", offset_of!(P, height)),
        ("padded_width", offset_of!(P, padded_width)),
        ("padded_height", offset_of!(P, padded_height)),
        ("block", offset_of!(P, block)),
        ("tile_log2", offset_of!(P, tile_log2)),
        ("frame", offset_of!(P, frame)),
        ("reserved", offset_of!(P, reserved)),
    ]
};
const _: () = assert!(core::mem::size_of::<sampler_core::FrameParams>() == 32);

/// Gives the anonymous types of rust-gpu's SPIR-V names a reader can follow:
/// the uniform's `FrameParamsBlock { value: FrameParams }` with
/// [`FRAME_PARAMS_FIELDS`], and each storage buffer's
/// `<Element>Array { values: array<Element> }` (`U32Array`, `F32Array`,
/// `Vec2Array`, `Vec4Array`, `AtomicU32Array`).
///
/// # Errors
/// [`Error::Validation`] if the uniform is not the 32-byte `FrameParams`.
fn name_types(module: &mut Module) -> Result<(), Error> {
    use naga::{ArraySize, Scalar, ScalarKind, TypeInner, VectorSize};
    let bad = |message: String| Error::Validation {
        what: "the FrameParams uniform".to_string(),
        message,
    };
    let uniform = module
        .global_variables
        .iter()
        .find(|(_, g)| g.space == naga::AddressSpace::Uniform)
        .map(|(_, g)| g.ty)
        .ok_or_else(|| bad("no uniform".to_string()))?;
    let params = match &module.types[uniform].inner {
        TypeInner::Struct { members, .. } if members.len() == 1 => members[0].ty,
        other => return Err(bad(format!("unexpected type {other:?}"))),
    };
    let mut renames = vec![(uniform, "FrameParamsBlock".to_string(), vec!["value".to_string()])];
    match &module.types[params].inner {
        TypeInner::Struct { members, span: 32 }
            if members.len() == FRAME_PARAMS_FIELDS.len()
                && members.iter().zip(FRAME_PARAMS_FIELDS).all(|(m, (_, offset))| {
                    m.offset as usize == offset && module.types[m.ty].inner == TypeInner::Scalar(Scalar::U32)
                }) =>
        {
            renames.push((
                params,
                "FrameParams".to_string(),
                FRAME_PARAMS_FIELDS.iter().map(|f| f.0.to_string()).collect(),
            ));
        }
        other => return Err(bad(format!("not sampler_core::FrameParams: {other:?}"))),
    }
    for (handle, ty) in module.types.iter() {
        let TypeInner::Struct { members, .. } = &ty.inner else {
            continue;
        };
        let [member] = members.as_slice() else {
            continue;
        };
        let TypeInner::Array {
            base,
            size: ArraySize::Dynamic,
            ..
        } = module.types[member.ty].inner
        else {
            continue;
        };
        let element = match module.types[base].inner {
            TypeInner::Scalar(Scalar::U32) => "U32",
            TypeInner::Scalar(Scalar::F32) => "F32",
            TypeInner::Atomic(Scalar {
                kind: ScalarKind::Uint,
                width: 4,
            }) => "AtomicU32",
            TypeInner::Vector {
                size: VectorSize::Bi,
                scalar: Scalar::F32,
            } => "Vec2",
            TypeInner::Vector {
                size: VectorSize::Quad,
                scalar: Scalar::F32,
            } => "Vec4",
            _ => continue,
        };
        renames.push((handle, format!("{element}Array"), vec!["values".to_string()]));
    }
    for (handle, name, member_names) in renames {
        let mut ty = module.types[handle].clone();
        ty.name = Some(name);
        if let TypeInner::Struct { members, .. } = &mut ty.inner {
            for (m, n) in members.iter_mut().zip(member_names) {
                m.name = Some(n);
            }
        }
        module.types.replace(handle, ty);
    }
    Ok(())
}

/// Works around a naga 30 back-end bug that breaks rust-gpu's loops in GLSL,
/// HLSL and MSL (WGSL is unaffected).
///
/// Those writers emit a loop's `continuing` block and its `break if` at the
/// top of the next iteration (`if (!loop_init) { continuing; if (cond)
/// break; }`) and write the condition inline, re-reading the variables it
/// was computed from. rust-gpu's loops compute the exit condition in the
/// body from a phi variable that `continuing` then reassigns, so the
/// translated loop tests the *next* iteration's value and leaves one
/// iteration early (`take_cs` lost the last index of every chunk: found by
/// `conformance/tests/generated_shaders.rs` on GLSL). This stores each such
/// condition in a local variable where the body computes it, and makes the
/// `break if` load that variable, which every writer translates faithfully.
/// Upstream: <https://github.com/gfx-rs/wgpu/issues/4558>.
fn spill_break_conditions(module: &mut Module) {
    use naga::{Block, Expression, Span, Statement};
    fn walk(
        block: &mut Block,
        expressions: &mut naga::Arena<Expression>,
        locals: &mut naga::Arena<naga::LocalVariable>,
        bool_ty: &mut dyn FnMut() -> naga::Handle<naga::Type>,
    ) {
        for (statement, _) in block.span_iter_mut() {
            match statement {
                Statement::Block(inner) => walk(inner, expressions, locals, bool_ty),
                Statement::If { accept, reject, .. } => {
                    walk(accept, expressions, locals, bool_ty);
                    walk(reject, expressions, locals, bool_ty);
                }
                Statement::Switch { cases, .. } => {
                    for case in cases {
                        walk(&mut case.body, expressions, locals, bool_ty);
                    }
                }
                Statement::Loop {
                    body,
                    continuing,
                    break_if,
                } => {
                    walk(body, expressions, locals, bool_ty);
                    walk(continuing, expressions, locals, bool_ty);
                    let Some(condition) = *break_if else {
                        continue;
                    };
                    // The condition, or the operand of a `!condition` that
                    // `continuing` computes: emitted at the body's top level
                    // (the one place outside `continuing` it can come from).
                    let emitted_in = |block: &Block, e: naga::Handle<Expression>| {
                        block.iter().position(|s| {
                            matches!(s, Statement::Emit(range)
                                if range.index_range().contains(&(e.index() as u32)))
                        })
                    };
                    let (spilled, negate) = match expressions[condition] {
                        _ if emitted_in(body, condition).is_some() => (condition, false),
                        Expression::Unary {
                            op: naga::UnaryOperator::LogicalNot,
                            expr,
                        } if emitted_in(body, expr).is_some() => (expr, true),
                        _ => continue,
                    };
                    let k = emitted_in(body, spilled).expect("checked");
                    let local = locals.append(
                        naga::LocalVariable {
                            name: Some("break_condition".to_string()),
                            ty: bool_ty(),
                            init: None,
                        },
                        Span::UNDEFINED,
                    );
                    let pointer = expressions.append(Expression::LocalVariable(local), Span::UNDEFINED);
                    let store = Statement::Store {
                        pointer,
                        value: spilled,
                    };
                    body.splice(k + 1..k + 1, Block::from_vec(vec![store]));
                    let load = expressions.append(Expression::Load { pointer }, Span::UNDEFINED);
                    let mut last = load;
                    if negate {
                        last = expressions.append(
                            Expression::Unary {
                                op: naga::UnaryOperator::LogicalNot,
                                expr: load,
                            },
                            Span::UNDEFINED,
                        );
                    }
                    continuing.push(
                        Statement::Emit(naga::Range::new_from_bounds(load, last)),
                        Span::UNDEFINED,
                    );
                    *break_if = Some(last);
                }
                _ => {}
            }
        }
    }
    let types = &mut module.types;
    let mut bool_ty = || {
        types.insert(
            naga::Type {
                name: None,
                inner: naga::TypeInner::Scalar(naga::Scalar::BOOL),
            },
            Span::UNDEFINED,
        )
    };
    let functions = module
        .functions
        .iter_mut()
        .map(|(_, f)| f)
        .chain(module.entry_points.iter_mut().map(|ep| &mut ep.function));
    for function in functions {
        walk(
            &mut function.body,
            &mut function.expressions,
            &mut function.local_variables,
            &mut bool_ty,
        );
    }
}

/// The header every generated file starts with (`//` comments, valid in all
/// four languages; GLSL allows comments before `#version`).
fn header(spirv_sha256: &str, contents: &str) -> String {
    format!(
        "// GENERATED FILE, DO NOT EDIT. Generated by `{COMMAND}` (naga 30)\n\
         // from {SPIRV_PATH}, SHA-256 {spirv_sha256}.\n\
         // Edit the Rust source instead (gpu-tracer/kernels/src/permute_entry.rs,\n\
         // reproject_entry.rs, sampler-core), rebuild the SPIR-V with\n\
         // gpu-tracer/build-shaders.sh, then rerun `{COMMAND}`.\n\
         // Bindings, buffer sizes, dispatch sizes and pass order: sampler-core/shaders/README.md.\n\
         // {contents}\n\n"
    )
}

fn finish(mut text: String) -> String {
    if !text.ends_with('\n') {
        text.push('\n');
    }
    text
}

fn entry_list() -> String {
    ENTRIES.iter().map(|e| e.name).collect::<Vec<_>>().join(", ")
}

fn backend_error(language: &'static str, e: &dyn std::error::Error) -> Error {
    Error::Backend {
        language,
        message: chain(e),
    }
}

/// Every resource binding of the module (all in group 0).
fn bindings(module: &Module) -> BTreeSet<naga::ResourceBinding> {
    module
        .global_variables
        .iter()
        .filter_map(|(_, g)| g.binding)
        .collect()
}

fn write_wgsl(module: &Module, info: &ModuleInfo, sha: &str) -> Result<String, Error> {
    let body = naga::back::wgsl::write_string(module, info, naga::back::wgsl::WriterFlags::empty())
        .map_err(|e| backend_error("wgsl", &e))?;
    // The output must parse and validate as WGSL, with every entry point.
    let reparsed = naga::front::wgsl::parse_str(&body).map_err(|e| Error::Backend {
        language: "wgsl",
        message: format!("the output does not parse: {}", e.emit_to_string(&body)),
    })?;
    validate(&reparsed, "the WGSL output")?;
    for entry in &ENTRIES {
        if !reparsed.entry_points.iter().any(|ep| ep.name == entry.name) {
            return Err(Error::Backend {
                language: "wgsl",
                message: format!("entry point {} is missing", entry.name),
            });
        }
    }
    Ok(finish(
        header(
            sha,
            &format!("WGSL, one module with the entry points {}.", entry_list()),
        ) + &body,
    ))
}

/// The module of one entry point: everything else compacted away.
fn single_entry(module: &Module, entry: &Entry) -> Result<(Module, ModuleInfo), Error> {
    let mut single = module.clone();
    retain_entries(&mut single, &[entry.name]);
    // One entry point: its buffers are named after the kernel's parameters.
    for (_, global) in single.global_variables.iter_mut() {
        if let Some(role) = global
            .binding
            .and_then(|b| entry.bindings.get(b.binding as usize))
        {
            global.name = Some(role.to_string());
        }
    }
    let info = validate(&single, entry.name)?;
    Ok((single, info))
}

fn write_glsl(module: &Module, info: &ModuleInfo, entry: &Entry, sha: &str) -> Result<String, Error> {
    let options = naga::back::glsl::Options {
        version: naga::back::glsl::Version::Desktop(GLSL_VERSION),
        // No coordinate flip (compute only); only what this entry uses.
        writer_flags: naga::back::glsl::WriterFlags::empty(),
        binding_map: bindings(module)
            .into_iter()
            .map(|b| (b, b.binding as u8))
            .collect(),
        zero_initialize_workgroup_memory: true,
    };
    let pipeline = naga::back::glsl::PipelineOptions {
        shader_stage: ShaderStage::Compute,
        entry_point: entry.name.to_string(),
        multiview: None,
    };
    let mut body = String::new();
    naga::back::glsl::Writer::new(
        &mut body,
        module,
        info,
        &options,
        &pipeline,
        naga::proc::BoundsCheckPolicies::default(),
    )
    .and_then(|mut w| w.write())
    .map_err(|e| backend_error("glsl", &e))?;
    Ok(finish(
        header(
            sha,
            &format!(
                "GLSL {GLSL_VERSION} core compute shader of {} ({}); its function is `main`.\n\
                 // Set 0 (Vulkan) / binding N: the uniform block and the std430 buffers, see the README.",
                entry.name, entry.spirv
            ),
        ) + &body,
    ))
}

fn write_hlsl(module: &Module, info: &ModuleInfo, entry: &Entry, sha: &str) -> Result<String, Error> {
    use naga::back::hlsl;
    let options = hlsl::Options {
        shader_model: hlsl::ShaderModel::V5_1,
        // Register = binding, space = group (0); naga picks the register
        // class: b for the uniform, t for read-only, u for read-write buffers.
        binding_map: bindings(module)
            .into_iter()
            .map(|b| {
                (
                    b,
                    hlsl::BindTarget {
                        space: b.group as u8,
                        register: b.binding,
                        ..Default::default()
                    },
                )
            })
            .collect(),
        fake_missing_bindings: false,
        ..Default::default()
    };
    let pipeline = hlsl::PipelineOptions { entry_point: None };
    let mut body = String::new();
    let reflection = hlsl::Writer::new(&mut body, &options, &pipeline)
        .write(module, info, None)
        .map_err(|e| backend_error("hlsl", &e))?;
    check_names("hlsl", entry, &reflection.entry_point_names)?;
    Ok(finish(
        header(
            sha,
            &format!(
                "HLSL (shader model 5.1: FXC cs_5_1, or DXC cs_6_0 and later) of {} ({}).\n\
                 // Register N, space 0 = binding N: b0 the FrameParams cbuffer, tN read-only and uN\n\
                 // read-write (RW)ByteAddressBuffers, see the README.",
                entry.name, entry.spirv
            ),
        ) + &body,
    ))
}

/// The entry point was written, under its [`Entry::name`].
fn check_names<E: std::error::Error>(
    language: &'static str,
    entry: &Entry,
    names: &[Result<String, E>],
) -> Result<(), Error> {
    let written: Vec<&str> = names
        .iter()
        .map(|n| n.as_deref().map_err(|e| backend_error(language, e)))
        .collect::<Result<_, _>>()?;
    if written != [entry.name] {
        return Err(Error::Backend {
            language,
            message: format!("entry points written as {written:?}, expected [{:?}]", entry.name),
        });
    }
    Ok(())
}

/// The MSL buffer slot of the runtime-array sizes (`_mslBufferSizes`): one
/// past the highest binding of any entry point.
pub const MSL_SIZES_SLOT: u8 = 7;

fn write_msl(module: &Module, info: &ModuleInfo, entry: &Entry, sha: &str) -> Result<String, Error> {
    use naga::back::msl;
    let resources: msl::BindingMap = bindings(module)
        .into_iter()
        .map(|b| {
            (
                b,
                msl::BindTarget {
                    buffer: Some(b.binding as u8),
                    ..Default::default()
                },
            )
        })
        .collect();
    let per_entry_point_map = BTreeMap::from([(
        entry.name.to_string(),
        msl::EntryPointResources {
            resources,
            immediates_buffer: None,
            sizes_buffer: Some(MSL_SIZES_SLOT),
        },
    )]);
    let options = msl::Options {
        lang_version: MSL_VERSION,
        per_entry_point_map,
        fake_missing_bindings: false,
        ..Default::default()
    };
    let (body, translation) = msl::write_string(module, info, &options, &msl::PipelineOptions::default())
        .map_err(|e| backend_error("msl", &e))?;
    check_names("msl", entry, &translation.entry_point_names)?;
    // The members of `_mslBufferSizes`, in the order naga declares them
    // (global variable order), named after the bindings they size.
    let sized: Vec<String> = module
        .global_variables
        .iter()
        .filter(|(_, g)| {
            module.types[g.ty]
                .inner
                .needs_host_buffer_byte_size(&module.types)
        })
        .map(|(_, g)| {
            let binding = g.binding.map_or(u32::MAX, |b| b.binding);
            let role = entry.bindings.get(binding as usize).copied().unwrap_or("?");
            format!("binding {binding} ({role})")
        })
        .collect();
    let declared = body
        .split("struct _mslBufferSizes {\n")
        .nth(1)
        .and_then(|rest| rest.split("};").next())
        .map_or(0, |members| members.lines().count());
    if declared != sized.len() {
        return Err(Error::Backend {
            language: "msl",
            message: format!(
                "_mslBufferSizes of {} has {declared} members, expected {}",
                entry.name,
                sized.len()
            ),
        });
    }
    Ok(finish(
        header(
            sha,
            &format!(
                "Metal Shading Language {}.{} kernel {} ({}), 64 threads per threadgroup.\n\
                 // [[buffer(N)]] = binding N (see the README); [[buffer({MSL_SIZES_SLOT})]]: _mslBufferSizes,\n\
                 // the byte sizes of, in member order: {}.",
                MSL_VERSION.0,
                MSL_VERSION.1,
                entry.name,
                entry.spirv,
                sized.join(", ")
            ),
        ) + &body,
    ))
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
    use super::*;

    #[test]
    fn names_are_the_spirv_names_with_underscores() {
        for e in &ENTRIES {
            assert_eq!(e.name, e.spirv.replace("::", "_"));
            assert!(e.name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'));
        }
        let unique: BTreeSet<&str> = ENTRIES.iter().map(|e| e.name).collect();
        assert_eq!(unique.len(), ENTRIES.len());
    }
}
