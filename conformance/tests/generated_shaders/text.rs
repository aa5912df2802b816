//! Static checks of the generated text in every language: headers, no
//! path-tracer code, loop exits, the one atomic, entry points and bindings.

use super::{entry, read_generated};
use shader_sources::{
    generate_from_workspace, glsl_file, hlsl_file, msl_file, workspace_root, COMMAND, ENTRIES, WGSL_FILE,
};

/// Every generated file: the header, and nothing of the path tracer.
#[test]
fn every_file_names_its_source_and_leaves_the_tracer_out() {
    let files = generate_from_workspace(&workspace_root()).expect("generate");
    assert_eq!(files.len(), 1 + 3 * ENTRIES.len());
    for f in &files {
        assert!(
            f.text.starts_with("// GENERATED FILE, DO NOT EDIT."),
            "{}",
            f.path
        );
        assert!(f.text.contains(COMMAND), "{}", f.path);
        assert!(f.text.contains("SHA-256 "), "{}", f.path);
        // The tracer's entry points are `entry::*` (`entry_*` once renamed);
        // the kept passes are `permute_entry_*` and `reproject_entry_*`.
        for tracer in [
            "trace_cs",
            "accumulate_cs",
            "gbuffer_cs",
            "motion_cs",
            "features_cs",
        ] {
            // A kept pass may end in the same words (`sort_features_cs`): a
            // match leaks only where its identifier (`_` and `::` joined) is
            // not a kept pass's.
            let leaked = f.text.match_indices(tracer).any(|(at, _)| {
                let before = &f.text[..at];
                let start = before
                    .rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == ':'))
                    .map_or(0, |i| i + 1);
                let identifier = &f.text[start..];
                !["permute_entry", "reproject_entry", "sampler_entry"]
                    .iter()
                    .any(|kept| identifier.starts_with(kept))
            });
            assert!(!leaked, "{} carries {tracer}", f.path);
        }
    }
}

/// Regression guard for the naga 30 loop bug the generator works around
/// (`spill_break_conditions` in shader-sources): GLSL, HLSL and MSL write a
/// loop's exit test at the top of the next iteration, so it must read the
/// condition stored by the body, never recompute it from variables the
/// `continuing` block has just reassigned (that left `take_cs`'s loop one
/// iteration early in GLSL).
#[test]
fn every_translated_loop_tests_the_stored_exit_condition() {
    for e in &ENTRIES {
        for path in [glsl_file(e), hlsl_file(e), msl_file(e)] {
            let text = read_generated(&path);
            let loops = text.matches("bool loop_init = true;").count();
            let stored_tests = text.matches(" = break_condition;").count();
            assert_eq!(
                loops, stored_tests,
                "{path}: loops vs loops exiting on a stored condition"
            );
        }
    }
}

/// The atomic minimum of the claim pass survives in every language, and
/// no other pass is atomic.
#[test]
fn the_claim_atomic_survives_in_every_language() {
    let claim = entry("claim");
    assert_eq!(read_generated(WGSL_FILE).matches("atomicMin(").count(), 1);
    assert!(read_generated(&glsl_file(claim)).contains("atomicMin("));
    assert!(read_generated(&hlsl_file(claim)).contains("InterlockedMin("));
    assert!(read_generated(&msl_file(claim)).contains("metal::atomic_fetch_min_explicit("));
    for e in ENTRIES.iter().filter(|e| e.pass() != "claim") {
        for path in [glsl_file(e), hlsl_file(e), msl_file(e)] {
            assert!(!read_generated(&path).contains("atomic"), "{path}");
            assert!(!read_generated(&path).contains("Interlocked"), "{path}");
        }
    }
}

/// HLSL and MSL can only be checked statically here (no HLSL or MSL
/// compiler, and naga has no HLSL or MSL front end): each file declares its
/// entry point once, as a 64-wide compute kernel, and binds what the README
/// says. GLSL's declarations are checked the same way (glslang compiles
/// them in `glsl_passes_match_the_cpu_bit_for_bit`).
#[test]
fn every_file_declares_its_entry_point_and_bindings() {
    for e in &ENTRIES {
        let block = match e.pass() {
            "screen_sobol" | "zsobol" | "spatiotemporal" => "SamplerParamsBlock",
            _ => "FrameParamsBlock",
        };
        let hlsl = read_generated(&hlsl_file(e));
        let declaration = format!("[numthreads(64, 1, 1)]\nvoid {}(", e.name);
        assert_eq!(hlsl.matches(&declaration).count(), 1, "HLSL: {declaration}");
        assert!(
            hlsl.contains(&format!("cbuffer params : register(b0) {{ {block} params; }}")),
            "{}",
            e.name
        );
        let msl = read_generated(&msl_file(e));
        let kernel = format!(
            "[[max_total_threads_per_threadgroup(64)]] kernel void {}(",
            e.name
        );
        assert_eq!(msl.matches(&kernel).count(), 1, "MSL: {kernel}");
        assert!(msl.contains("#include <metal_stdlib>"));
        assert!(
            msl.contains(&format!("constant {block}& params [[buffer(0)]]")),
            "{}",
            e.name
        );
        let glsl = read_generated(&glsl_file(e));
        assert!(glsl.contains("#version 450 core"), "{}", e.name);
        assert!(
            glsl.contains("layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;"),
            "{}",
            e.name
        );
        assert_eq!(glsl.matches("void main()").count(), 1, "{}", e.name);
        for (binding, role) in e.bindings.iter().enumerate().skip(1) {
            let register = format!(" {role} : register(");
            let at = hlsl
                .find(&register)
                .unwrap_or_else(|| panic!("HLSL {}: no {role}", e.name));
            let slot = &hlsl[at + register.len()..at + register.len() + 3];
            assert!(
                slot == format!("t{binding})") || slot == format!("u{binding})"),
                "HLSL {}: {role} at {slot}",
                e.name
            );
            assert!(
                msl.contains(&format!(" {role} [[buffer({binding})]]")),
                "MSL {}: {role}",
                e.name
            );
            assert!(
                glsl.contains(&format!("layout(std430, binding = {binding})")),
                "GLSL {}: {binding}",
                e.name
            );
        }
    }
}
