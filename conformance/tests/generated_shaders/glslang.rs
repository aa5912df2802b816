//! glslang as a second compiler: the generated GLSL and HLSL compiled to
//! SPIR-V (the GLSL is then run by [`super::passes`]).

use super::{read_generated, shaders_dir};
use gpu_tracer::gpu::REQUIRE_GPU_ENV;
use shader_sources::{glsl_file, hlsl_file, ENTRIES};
use std::collections::BTreeMap;
use std::process::Command;

/// `glslangValidator` on PATH, or why not (a skip, or a failure in CI).
pub(super) fn glslang() -> Option<&'static str> {
    const TOOL: &str = "glslangValidator";
    match Command::new(TOOL).arg("--version").output() {
        Ok(out) if out.status.success() => Some(TOOL),
        result => {
            let why = match result {
                Ok(out) => format!(
                    "`{TOOL} --version` failed: {}",
                    String::from_utf8_lossy(&out.stderr)
                ),
                Err(e) => format!("{TOOL} not found ({e}); install Debian's glslang-tools"),
            };
            if std::env::var(REQUIRE_GPU_ENV).as_deref() == Ok("1") {
                panic!("{why}, and {REQUIRE_GPU_ENV}=1");
            }
            eprintln!("SKIPPED glsl_passes_match_the_cpu_bit_for_bit: {why}; set {REQUIRE_GPU_ENV}=1 to fail instead");
            None
        }
    }
}

/// A generated language that glslang compiles to SPIR-V.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(super) enum Front {
    Glsl,
    /// glslang's HLSL front end (`-D`), entry point named as in the file.
    Hlsl,
}

/// glslang's HLSL front end rejects the zero-cast of an array that naga
/// writes and DXC accepts (`uint local[4][32] = (uint[4][32])0;`): spell it
/// as a (nested) initialiser list of zeros in a declaration, and as a loop
/// of zero stores in an assignment (naga's zeroing of workgroup memory,
/// `global_2 = (uint[64])0;`, where an initialiser list is not allowed).
/// Nothing else is touched.
fn hlsl_for_glslang(text: &str) -> String {
    /// `{0, ...}` for dimensions `dims` (outermost first).
    fn zeros(dims: &[usize]) -> String {
        match dims {
            [] => "0".to_string(),
            [n, inner @ ..] => format!("{{{}}}", vec![zeros(inner); *n].join(", ")),
        }
    }
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find("])0;") {
        let open = rest[..at].rfind('(').expect("a cast");
        let dims: Vec<usize> = rest[open..=at]
            .split('[')
            .skip(1)
            .map(|d| d.trim_end_matches(']').parse().expect("array length"))
            .collect();
        let line = rest[..open].rfind('\n').map_or(0, |i| i + 1);
        let target = rest[line..open].trim().trim_end_matches('=').trim();
        let assignment = !target.is_empty() && target.chars().all(|c| c.is_alphanumeric() || c == '_');
        if assignment {
            // `target = (T[a][b])0;` -> nested loops storing 0 to each element.
            out.push_str(&rest[..line]);
            let mut index = String::new();
            for (k, n) in dims.iter().enumerate() {
                out.push_str(&format!(
                    "for (uint zero_{k} = 0u; zero_{k} < {n}u; ++zero_{k}) {{ "
                ));
                index.push_str(&format!("[zero_{k}]"));
            }
            out.push_str(&format!("{target}{index} = 0;"));
            out.push_str(&" }".repeat(dims.len()));
        } else {
            out.push_str(&rest[..open]);
            out.push_str(&zeros(&dims));
            out.push(';');
        }
        rest = &rest[at + 4..];
    }
    out.push_str(rest);
    out
}

/// Compiles every generated GLSL or HLSL file to SPIR-V for Vulkan 1.1.
pub(super) fn compile_with_glslang(tool: &str, front: Front) -> BTreeMap<&'static str, Vec<u8>> {
    let dir = std::env::temp_dir().join(format!("bluenoise-generated-{front:?}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let spirv = ENTRIES
        .iter()
        .map(|e| {
            let out = dir.join(format!("{}.spv", e.name));
            let mut command = Command::new(tool);
            command
                .args(["-V", "--target-env", "vulkan1.1", "-S", "comp", "-o"])
                .arg(&out);
            let source = match front {
                Front::Glsl => shaders_dir().join(glsl_file(e)),
                Front::Hlsl => {
                    let text = read_generated(&hlsl_file(e));
                    let shimmed = dir.join(format!("{}.hlsl", e.name));
                    std::fs::write(&shimmed, hlsl_for_glslang(&text)).unwrap();
                    command.args(["-D", "-e", e.name]);
                    shimmed
                }
            };
            let result = command.arg(&source).output().unwrap();
            assert!(
                result.status.success(),
                "{tool} rejected {}:\n{}{}",
                source.display(),
                String::from_utf8_lossy(&result.stdout),
                String::from_utf8_lossy(&result.stderr)
            );
            (e.name, std::fs::read(&out).unwrap())
        })
        .collect();
    let _ = std::fs::remove_dir_all(&dir);
    spirv
}

/// Every HLSL file compiles with glslang's HLSL front end (not DXC or FXC,
/// which do not run here) to Vulkan SPIR-V: its syntax, types, registers
/// and entry point are accepted by a second compiler. Not run: naga's
/// SPIR-V front end (which wgpu uses) rejects glslang's HLSL output (an
/// `OpIAdd` of a signed and an unsigned operand, which SPIR-V allows).
#[test]
fn hlsl_compiles_with_glslang() {
    let Some(tool) = glslang() else {
        return;
    };
    let spirv = compile_with_glslang(tool, Front::Hlsl);
    assert_eq!(spirv.len(), ENTRIES.len());
    for (name, words) in &spirv {
        // A SPIR-V module: the magic number, and the entry point by name.
        assert_eq!(words[..4], 0x0723_0203u32.to_le_bytes(), "{name}");
        assert!(words.windows(name.len()).any(|w| w == name.as_bytes()), "{name}");
    }
}

#[test]
fn the_hlsl_shim_only_rewrites_array_zero_casts() {
    let text = "uint a[3] = (uint[3])0;\nS s = (S)0;\nfloat b[2][1] = (float[2][1])0;";
    assert_eq!(
        hlsl_for_glslang(text),
        "uint a[3] = {0, 0, 0};\nS s = (S)0;\nfloat b[2][1] = {{0}, {0}};"
    );
    let assign = "    if (i == 0) {\n        g = (uint[2])0;\n    }";
    assert_eq!(
        hlsl_for_glslang(assign),
        "    if (i == 0) {\nfor (uint zero_0 = 0u; zero_0 < 2u; ++zero_0) { g[zero_0] = 0; }\n    }"
    );
}
