//! The generated shader sources in `sampler-core/shaders/` (written by
//! `cargo run -p shader-sources` from the committed rust-gpu SPIR-V):
//!
//! - they are fresh: generating them again in memory gives the committed
//!   bytes (so CI fails on stale files);
//! - the **WGSL** module, created through wgpu from WGSL source, runs every
//!   pass (seed init, intensity, sort, retarget, the feature-aware sort,
//!   record-source and retarget, and the six reprojection passes) and
//!   matches `sampler_core` on the CPU bit for bit over chained frames,
//!   several surfaces with creases and background, and adversarial motion;
//! - the a-priori samplers' entry points (screen-space Sobol, ZSobol) give
//!   every pixel's pair bit for bit as `kernels::sampler_entry` on the CPU;
//! - the **GLSL** files, compiled by `glslangValidator` to SPIR-V and loaded
//!   through wgpu, do the same;
//! - the **HLSL** files compile with glslang's HLSL front end to SPIR-V (not
//!   run: naga's SPIR-V front end rejects glslang's HLSL output);
//! - the **HLSL** and **MSL** files are also checked statically (no MSL
//!   compiler or naga HLSL/MSL front end exists here): generated header,
//!   every entry point declared with 64-wide workgroups, the atomic minimum
//!   of `claim_cs` present, nothing of the path tracer.
//!
//! GPU tests need an adapter (Mesa's lavapipe counts) and the GLSL test
//! `glslangValidator` (Debian `glslang-tools`). Without them the test prints
//! `SKIPPED` with the reason; `BLUENOISE_REQUIRE_GPU=1` (set in CI) turns
//! that into a failure.

use conformance::fixtures::{random_table, random_tile};
use glam::Vec4;
use gpu_tracer::gpu::{Gpu, REQUIRE_GPU_ENV};
use kernels::permute_entry::linear_dispatch;
use sampler_core::reproject_passes::chunk_count;
use sampler_core::seed::hash_u32;
use sampler_core::*;
use shader_sources::{
    generate_from_workspace, glsl_file, hlsl_file, msl_file, stale_files, workspace_root, Entry, COMMAND,
    ENTRIES, OUTPUT_DIR, WGSL_FILE,
};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::process::Command;

fn shaders_dir() -> PathBuf {
    workspace_root().join(OUTPUT_DIR)
}

fn read_generated(path: &str) -> String {
    let full = shaders_dir().join(path);
    std::fs::read_to_string(&full).unwrap_or_else(|e| panic!("{}: {e}; run `{COMMAND}`", full.display()))
}

fn entry(pass: &str) -> &'static Entry {
    ENTRIES
        .iter()
        .find(|e| e.pass() == pass)
        .unwrap_or_else(|| panic!("no entry point for pass {pass}"))
}

#[test]
fn committed_sources_are_fresh() {
    let files = generate_from_workspace(&workspace_root()).expect("generate");
    let problems = stale_files(&shaders_dir(), &files);
    assert!(
        problems.is_empty(),
        "{OUTPUT_DIR} is stale; run `{COMMAND}`:\n{}",
        problems.join("\n")
    );
}

/// The compute pipelines of the ten passes, keyed by [`Entry::pass`], from
/// one module (WGSL) or one module per entry point (GLSL).
struct Passes {
    pipelines: BTreeMap<&'static str, wgpu::ComputePipeline>,
}

/// Creates a shader module inside a validation error scope: a rejected
/// module fails the test with wgpu's message.
fn module(gpu: &Gpu, label: &str, source: wgpu::ShaderSource<'_>) -> wgpu::ShaderModule {
    let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let module = gpu.device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source,
    });
    if let Some(e) = pollster::block_on(scope.pop()) {
        panic!("{label}: {e}");
    }
    module
}

fn pipeline(gpu: &Gpu, module: &wgpu::ShaderModule, label: &str, entry_point: &str) -> wgpu::ComputePipeline {
    let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let pipeline = gpu
        .device
        .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(label),
            layout: None,
            module,
            entry_point: Some(entry_point),
            compilation_options: Default::default(),
            cache: None,
        });
    if let Some(e) = pollster::block_on(scope.pop()) {
        panic!("pipeline {label}: {e}");
    }
    pipeline
}

impl Passes {
    /// All fifteen pipelines from the one WGSL module, created from source.
    fn from_wgsl(gpu: &Gpu) -> Self {
        let text = read_generated(WGSL_FILE);
        let module = module(gpu, WGSL_FILE, wgpu::ShaderSource::Wgsl(text.into()));
        Passes {
            pipelines: ENTRIES
                .iter()
                .map(|e| (e.pass(), pipeline(gpu, &module, e.name, e.name)))
                .collect(),
        }
    }

    /// Each GLSL file compiled by `glslangValidator` to SPIR-V and loaded
    /// through wgpu's SPIR-V front end (entry point `main`).
    fn from_glsl(gpu: &Gpu, spirv: &BTreeMap<&'static str, Vec<u8>>) -> Self {
        Passes {
            pipelines: ENTRIES
                .iter()
                .map(|e| {
                    let path = glsl_file(e);
                    let module = module(gpu, &path, wgpu::util::make_spirv(&spirv[e.name]));
                    (e.pass(), pipeline(gpu, &module, &path, "main"))
                })
                .collect(),
        }
    }

    /// Encodes pass `pass` over `n` invocations (`linear_dispatch`) with
    /// `buffers` at bindings `0..` of group 0.
    fn encode(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        pass: &str,
        buffers: &[&wgpu::Buffer],
        n: u32,
    ) {
        assert_eq!(buffers.len(), entry(pass).bindings.len(), "{pass}: bindings");
        let pipeline = &self.pipelines[pass];
        let bind_group = gpu.bind(pipeline, buffers);
        let mut cpass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(pass),
            timestamp_writes: None,
        });
        cpass.set_pipeline(pipeline);
        cpass.set_bind_group(0, &bind_group, &[]);
        let (x, y) = linear_dispatch(n);
        cpass.dispatch_workgroups(x, y, 1);
    }

    fn run(&self, gpu: &Gpu, pass: &str, buffers: &[&wgpu::Buffer], n: u32) {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        self.encode(gpu, &mut encoder, pass, buffers, n);
        gpu.queue.submit([encoder.finish()]);
    }
}

/// Intensities with NaN, infinities, signed zeros and many ties (as
/// `gpu_vs_cpu`), as colours whose luma is computed by the intensity pass.
fn colours(n: usize, salt: u32) -> Vec<Vec4> {
    (0..n as u32)
        .map(|i| {
            let h = hash_u32(i ^ hash_u32(salt));
            let v = match h % 16 {
                0 => f32::NAN,
                1 => f32::INFINITY,
                2 => f32::NEG_INFINITY,
                3 => -0.0,
                4..=8 => (h >> 8) as f32 % 4.0,
                _ => random_f32(h, 1) * 3.0,
            };
            let g = random_f32(h, 2);
            Vec4::new(v, g, v * 0.5, 1.0)
        })
        .collect()
}

/// Backward motion fields (pixels): random, a rotation, NaN and infinity
/// patches, everything to one source, a uniform shift.
fn motion(w: u32, h: u32, kind: u32, salt: u32) -> Vec<[f32; 2]> {
    let (cx, cy) = (w as f32 / 2.0, h as f32 / 2.0);
    let unit = |x: u32, y: u32, k: u32| hash_u32(x ^ (y << 12) ^ (k << 24) ^ salt) as f32 / u32::MAX as f32;
    (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            match kind % 5 {
                0 => [unit(x, y, 1) * 12.0 - 6.0, unit(x, y, 2) * 12.0 - 6.0],
                1 => {
                    let (dx, dy) = (x as f32 + 0.5 - cx, y as f32 + 0.5 - cy);
                    let (s, c) = 0.05f32.sin_cos();
                    [c * dx - s * dy - dx, s * dx + c * dy - dy]
                }
                2 => match hash_u32(x * 31 + y * 977 + salt) % 5 {
                    0 => [f32::INFINITY, 0.0],
                    1 => [0.0, f32::NEG_INFINITY],
                    2 => [1e30, -1e30],
                    3 => [f32::NAN, 0.5],
                    _ => [0.3, -0.7],
                },
                3 => [cx - x as f32, cy - y as f32],
                _ => [-2.25, 1.5],
            }
        })
        .collect()
}

/// Frame sizes (with padding on both axes and several reprojection chunks),
/// block and tile sides, first frame index.
const CASES: &[(u32, u32, u32, u32, u32)] = &[
    (1, 1, 2, 4, 0),
    (17, 13, 3, 8, 5),
    (97, 61, 4, 64, 12345),
    (131, 67, 5, 16, 77),
    (33, 129, 7, 32, u32::MAX - 1),
];

/// The feature-aware passes' own buffers in [`check_frame_loop`].
struct FeatureBuffers {
    features: wgpu::Buffer,
    thresholds: wgpu::Buffer,
    sorted: wgpu::Buffer,
    sources: wgpu::Buffer,
    out: wgpu::Buffer,
}

/// Frames chained per case: frame 0 initialises the seeds.
const FRAMES: u32 = 3;

/// Runs the README's frame loop with `passes` and on the CPU side by side,
/// comparing every pass's output bit for bit:
///
/// ```text
/// first frame: seed_init
/// each frame:  [clear_claims, claim, take, scan, list_free, recycle] (after the first)
///              intensity (the renderer's colour), sort, retarget
/// ```
fn check_frame_loop(gpu: &Gpu, passes: &Passes, language: &str) {
    for (k, &(w, h, block, tile_side, first)) in CASES.iter().enumerate() {
        let salt = k as u32 * 7919;
        let layout = FrameLayout::new(w, h, block, tile_side).unwrap();
        let tile_values = random_tile(tile_side, salt, k % 2 == 0);
        let tile = DitherTile::new(tile_side, &tile_values).unwrap();
        let packed: Vec<Vec<u32>> = (0..4)
            .map(|i| random_table(tile_side, salt + i, 5 * tile_side * tile_side))
            .collect();
        let tables =
            RetargetTables::new(tile_side, [&packed[0], &packed[1], &packed[2], &packed[3]]).unwrap();
        let (n_seeds, n_pixels) = (layout.seed_count(), layout.pixel_count());
        let chunks = chunk_count(&layout.params(0));

        let params = gpu.uniform("params", &layout.params(first));
        let tile_buf = gpu.storage("tile", tile.values());
        let table_bufs: Vec<wgpu::Buffer> = (0..STEP_COUNT as u32)
            .map(|i| gpu.storage("table", tables.table(i).packed()))
            .collect();
        let seeds = gpu.storage_zeroed::<u32>("seeds", n_seeds);
        let scratch = gpu.storage_zeroed::<u32>("seeds (sorted / reprojected)", n_seeds);
        let colour = gpu.storage_zeroed::<Vec4>("colour", n_pixels);
        let intensity = gpu.storage_zeroed::<f32>("intensity", n_pixels);
        let motion_buf = gpu.storage_zeroed::<[f32; 2]>("motion", n_pixels);
        let claims = gpu.storage_zeroed::<u32>("claims", n_seeds);
        let counts = gpu.storage_zeroed::<u32>("chunk counts", 2 * chunks as usize);
        let free = gpu.storage_zeroed::<u32>("free", n_seeds);
        let features = conformance::fixtures::banded_features(w, h, 3, true, salt);
        let feature_bufs = FeatureBuffers {
            features: gpu.storage("features", &features),
            thresholds: gpu.storage("thresholds", &[FeatureThresholds::DEFAULT]),
            sorted: gpu.storage_zeroed::<u32>("feature-sorted seeds", n_seeds),
            sources: gpu.storage_zeroed::<u32>("sources", n_seeds),
            out: gpu.storage_zeroed::<u32>("feature-permuted seeds", n_seeds),
        };

        // Frame 0: white-noise seeds, salt = params.frame.
        passes.run(gpu, "seed_init", &[&params, &seeds], n_seeds as u32);
        let pw = layout.padded_width();
        let mut cpu: Vec<u32> = (0..n_seeds as u32)
            .map(|i| initial_seed(i % pw, i / pw, pw, first))
            .collect();
        assert_eq!(
            gpu.read::<u32>(&seeds, n_seeds).unwrap(),
            cpu,
            "{language} seed_init, case {k}"
        );

        for t in 0..FRAMES {
            let frame = first.wrapping_add(t);
            let what = format!("{language}, case {k} ({w}x{h}), frame {frame}");
            gpu.queue
                .write_buffer(&params, 0, bytemuck::bytes_of(&layout.params(frame)));
            if t > 0 {
                // The camera moved: reproject the seeds along the motion.
                let m = motion(w, h, k as u32 + t, salt + t);
                gpu.queue.write_buffer(&motion_buf, 0, bytemuck::cast_slice(&m));
                let mut encoder = gpu.device.create_command_encoder(&Default::default());
                let steps: [(&str, &[&wgpu::Buffer], u32); 6] = [
                    ("clear_claims", &[&params, &claims], n_seeds as u32),
                    ("claim", &[&params, &motion_buf, &claims], n_pixels as u32),
                    (
                        "take",
                        &[&params, &motion_buf, &claims, &seeds, &scratch, &counts],
                        chunks,
                    ),
                    ("scan", &[&params, &counts], 1),
                    ("list_free", &[&params, &claims, &counts, &free], chunks),
                    (
                        "recycle",
                        &[&params, &motion_buf, &claims, &counts, &free, &seeds, &scratch],
                        chunks,
                    ),
                ];
                for (pass, buffers, n) in steps {
                    passes.encode(gpu, &mut encoder, pass, buffers, n);
                }
                encoder.copy_buffer_to_buffer(&scratch, 0, &seeds, 0, n_seeds as u64 * 4);
                gpu.queue.submit([encoder.finish()]);
                let mut cpu_claims = vec![0; n_seeds];
                let mut next = vec![0; n_seeds];
                reproject_frame(&layout, &m, &cpu, &mut cpu_claims, &mut next).unwrap();
                cpu = next;
                assert_eq!(
                    gpu.read::<u32>(&seeds, n_seeds).unwrap(),
                    cpu,
                    "reprojection, {what}"
                );
            }

            // The renderer's frame, reduced to intensities by the GPU.
            let c = colours(n_pixels, salt ^ frame);
            gpu.queue.write_buffer(&colour, 0, bytemuck::cast_slice(&c));
            passes.run(gpu, "intensity", &[&params, &colour, &intensity], n_pixels as u32);
            let values: Vec<f32> = gpu.read(&intensity, n_pixels).unwrap();
            // Bit for bit, except that any NaN equals any NaN (hardware need not
            // keep a NaN's payload; the sort's key maps every NaN alike).
            let canonical = |v: f32| {
                if v.is_nan() {
                    f32::NAN.to_bits()
                } else {
                    v.to_bits()
                }
            };
            let expected: Vec<u32> = c.iter().map(|v| canonical(luma(v.truncate()))).collect();
            let got: Vec<u32> = values.iter().map(|&v| canonical(v)).collect();
            assert_eq!(got, expected, "intensity, {what}");

            // Sort (seeds -> scratch), retarget with this frame's table (scratch -> seeds).
            let p = layout.params(frame);
            let step = step_index(frame, p.tile_log2) as usize;
            // First the feature-aware passes from the same seeds, into their own buffers.
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            let fb = &feature_bufs;
            let steps: [(&str, &[&wgpu::Buffer], u32); 3] = [
                (
                    "sort_features",
                    &[
                        &params,
                        &intensity,
                        &fb.features,
                        &fb.thresholds,
                        &tile_buf,
                        &seeds,
                        &fb.sorted,
                    ],
                    p.blocks_x() * p.blocks_y(),
                ),
                (
                    "record_source",
                    &[&params, &table_bufs[step], &fb.sources],
                    p.seed_count(),
                ),
                (
                    "retarget_features",
                    &[
                        &params,
                        &table_bufs[step],
                        &fb.sources,
                        &fb.features,
                        &fb.thresholds,
                        &fb.sorted,
                        &fb.out,
                    ],
                    p.seed_count(),
                ),
            ];
            for (pass, buffers, n) in steps {
                passes.encode(gpu, &mut encoder, pass, buffers, n);
            }
            gpu.queue.submit([encoder.finish()]);
            // The per-pass intermediates are the reference form's: the fast
            // path behind `permute_frame_features` leaves its scratch buffers
            // unspecified (its output is checked against the same passes below).
            let (mut f_sorted, mut f_sources, mut f_next) =
                (vec![0; n_seeds], vec![0; n_seeds], vec![0; n_seeds]);
            feature_permute::permute_frame_features_reference(
                &layout,
                frame,
                &values,
                &features,
                &FeatureThresholds::DEFAULT,
                &tile,
                &tables,
                &cpu,
                &mut f_sorted,
                &mut f_sources,
                &mut f_next,
            )
            .unwrap();
            assert_eq!(
                gpu.read::<u32>(&fb.sorted, n_seeds).unwrap(),
                f_sorted,
                "sort_features, {what}"
            );
            assert_eq!(
                gpu.read::<u32>(&fb.sources, n_seeds).unwrap(),
                f_sources,
                "record_source, {what}"
            );
            assert_eq!(
                gpu.read::<u32>(&fb.out, n_seeds).unwrap(),
                f_next,
                "retarget_features, {what}"
            );
            let (mut scratch_a, mut scratch_b, mut fast_next) =
                (vec![0; n_seeds], vec![0; n_seeds], vec![0; n_seeds]);
            permute_frame_features(
                &layout,
                frame,
                &values,
                &features,
                &FeatureThresholds::DEFAULT,
                &tile,
                &tables,
                &cpu,
                &mut scratch_a,
                &mut scratch_b,
                &mut fast_next,
            )
            .unwrap();
            assert_eq!(fast_next, f_next, "CPU fast path against the passes, {what}");

            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            passes.encode(
                gpu,
                &mut encoder,
                "sort",
                &[&params, &intensity, &tile_buf, &seeds, &scratch],
                p.blocks_x() * p.blocks_y(),
            );
            passes.encode(
                gpu,
                &mut encoder,
                "retarget",
                &[&params, &table_bufs[step], &scratch, &seeds],
                p.seed_count(),
            );
            gpu.queue.submit([encoder.finish()]);
            let mut sorted = vec![0; n_seeds];
            sort_frame(&layout, frame, &values, &tile, &cpu, &mut sorted).unwrap();
            let mut next = vec![0; n_seeds];
            permute_frame(&layout, frame, &values, &tile, &tables, &cpu, &mut next).unwrap();
            assert_eq!(
                gpu.read::<u32>(&scratch, n_seeds).unwrap(),
                sorted,
                "sort, {what}"
            );
            assert_eq!(
                gpu.read::<u32>(&seeds, n_seeds).unwrap(),
                next,
                "sort + retarget, {what}"
            );
            if n_pixels > 1 {
                assert_ne!(next, cpu, "{what} must move seeds");
            }
            cpu = next;
        }
    }
}

/// The a-priori samplers' entry points against `kernels::sampler_entry`'s
/// functions on the CPU (which the tracer uses too): every pixel's pair,
/// bit for bit, for several sample indices, pairs, spp and frames, with the
/// default screen-space Sobol keys.
fn check_samplers(gpu: &Gpu, passes: &Passes, language: &str) {
    use glam::{UVec2, Vec2};
    use kernels::sampler_entry::{key_layout, screen_sobol_pair, zsobol_pair, SamplerParams};
    let keys = defaults::screen_sobol_keys();
    let key_buf = gpu.storage("keys", keys.keys());
    for (width, height, spp, sample_index, pair, frame) in [
        (37u32, 23u32, 1u32, 0u32, 0u32, 0u32),
        (64, 9, 4, 3, 1, 17),
        (130, 5, 16, 15, 5, 12345),
        (7, 3, 300, 299, 2, 3),
    ] {
        let layout = keys.layout();
        let params = SamplerParams {
            width,
            height,
            spp,
            sample_index,
            pair,
            frame,
            key_side_log2: layout.side_log2,
            key_pairs: layout.pairs,
            key_levels: layout.levels,
            ..Default::default()
        };
        let n = (width * height) as usize;
        let uniform = gpu.uniform("sampler params", &params);
        let samples = gpu.storage_zeroed::<Vec2>("samples", n);
        let pixel = |i: usize| UVec2::new(i as u32 % width, i as u32 / width);
        // The GPU's pairs as bits (bit for bit, NaN payloads included).
        let read_bits = |buffer: &wgpu::Buffer| -> Vec<[u32; 2]> {
            let v: Vec<Vec2> = gpu.read(buffer, n).unwrap();
            v.iter().map(|v| [v.x.to_bits(), v.y.to_bits()]).collect()
        };
        let what = format!(
            "{language}: {width}x{height}, spp {spp}, sample {sample_index}, pair {pair}, frame {frame}"
        );

        passes.run(gpu, "screen_sobol", &[&uniform, &key_buf, &samples], n as u32);
        let cpu: Vec<[u32; 2]> = (0..n)
            .map(|i| {
                let v = screen_sobol_pair(
                    keys.keys(),
                    key_layout(&params),
                    spp,
                    frame,
                    pixel(i),
                    sample_index,
                    pair,
                );
                [v.x.to_bits(), v.y.to_bits()]
            })
            .collect();
        assert_eq!(read_bits(&samples), cpu, "screen_sobol, {what}");

        passes.run(gpu, "zsobol", &[&uniform, &samples], n as u32);
        let cpu: Vec<[u32; 2]> = (0..n)
            .map(|i| {
                let v = zsobol_pair(spp, frame, pixel(i), sample_index, pair);
                [v.x.to_bits(), v.y.to_bits()]
            })
            .collect();
        assert_eq!(read_bits(&samples), cpu, "zsobol, {what}");
        assert!(cpu.iter().any(|v| v != &cpu[0]), "{what}: constant samples");
    }
}

#[test]
fn wgsl_passes_match_the_cpu_bit_for_bit() {
    let test = "wgsl_passes_match_the_cpu_bit_for_bit";
    let Some(gpu) = Gpu::for_test(test) else {
        return;
    };
    let passes = Passes::from_wgsl(&gpu);
    check_frame_loop(&gpu, &passes, "WGSL");
    check_samplers(&gpu, &passes, "WGSL");
}

/// `glslangValidator` on PATH, or why not (a skip, or a failure in CI).
fn glslang() -> Option<&'static str> {
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
enum Front {
    Glsl,
    /// glslang's HLSL front end (`-D`), entry point named as in the file.
    Hlsl,
}

/// glslang's HLSL front end rejects the zero-cast of an array that naga
/// writes and DXC accepts (`uint local[4][32] = (uint[4][32])0;`): spell it
/// as a (nested) initialiser list of zeros. Nothing else is touched.
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
        out.push_str(&rest[..open]);
        out.push_str(&zeros(&dims));
        out.push(';');
        rest = &rest[at + 4..];
    }
    out.push_str(rest);
    out
}

/// Compiles every generated GLSL or HLSL file to SPIR-V for Vulkan 1.1.
fn compile_with_glslang(tool: &str, front: Front) -> BTreeMap<&'static str, Vec<u8>> {
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

#[test]
fn glsl_passes_match_the_cpu_bit_for_bit() {
    let test = "glsl_passes_match_the_cpu_bit_for_bit";
    let Some(tool) = glslang() else {
        return;
    };
    let spirv = compile_with_glslang(tool, Front::Glsl);
    let Some(gpu) = Gpu::for_test(test) else {
        return;
    };
    let passes = Passes::from_glsl(&gpu, &spirv);
    check_frame_loop(&gpu, &passes, "GLSL");
    check_samplers(&gpu, &passes, "GLSL");
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
}

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
            let leaked = f.text.match_indices(tracer).any(|(at, _)| {
                let before = &f.text[..at];
                !(before.ends_with("retarget_") || before.ends_with("sort_"))
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
            "screen_sobol" | "zsobol" => "SamplerParamsBlock",
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
