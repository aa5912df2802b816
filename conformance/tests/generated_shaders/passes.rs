//! The generated passes run through wgpu (WGSL from source, GLSL compiled
//! by glslang) against `sampler_core` and `kernels` on the CPU, bit for bit.

use super::glslang::{compile_with_glslang, glslang, Front};
use super::{entry, read_generated};
use conformance::fixtures::{random_table, random_tile};
use glam::Vec4;
use gpu_tracer::gpu::Gpu;
use kernels::permute_entry::linear_dispatch;
use sampler_core::reprojection::passes::chunk_count;
use sampler_core::reprojection::seed_passes::COUNT_LANES;
use sampler_core::sequences::seed::hash_u32;
use sampler_core::*;
use shader_sources::{glsl_file, ENTRIES, WGSL_FILE};
use std::collections::BTreeMap;

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
    /// All pipelines from the one WGSL module, created from source.
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

/// `a` and `b` are both NaN, or equal, or finite and within the rounding
/// error of a sum of three products whose magnitudes add up to `scale`
/// (four roundings of at most `f32::EPSILON * scale` each).
fn within_rounding(a: f32, b: f32, scale: f32) -> bool {
    if a.is_nan() || b.is_nan() {
        return a.is_nan() && b.is_nan();
    }
    a == b || (a.is_finite() && b.is_finite() && (a - b).abs() <= 4.0 * f32::EPSILON * scale)
}

/// The feature-aware passes' own buffers in [`check_frame_loop`].
struct FeatureBuffers {
    features: wgpu::Buffer,
    thresholds: wgpu::Buffer,
    sorted: wgpu::Buffer,
    groups: wgpu::Buffer,
    sorted_per_seed: wgpu::Buffer,
    links: wgpu::Buffer,
    links_b: wgpu::Buffer,
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
///              intensity (the renderer's colour), sort (and sort_rank + sort_gather), retarget
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
        let ranked = gpu.storage_zeroed::<u32>("seeds (ranked)", n_seeds);
        let gathered = gpu.storage_zeroed::<u32>("seeds (sorted in two passes)", n_seeds);
        let colour = gpu.storage_zeroed::<Vec4>("colour", n_pixels);
        let intensity = gpu.storage_zeroed::<f32>("intensity", n_pixels);
        let motion_buf = gpu.storage_zeroed::<[f32; 2]>("motion", n_pixels);
        let claims = gpu.storage_zeroed::<u32>("claims", n_seeds);
        let counts = gpu.storage_zeroed::<u32>("chunk counts", 2 * chunks as usize);
        let free = gpu.storage_zeroed::<u32>("free", n_seeds);
        let flags = gpu.storage_zeroed::<u32>("reprojection flags", n_seeds);
        let reprojected = gpu.storage_zeroed::<u32>("seeds (reprojected per seed)", n_seeds);
        let features = conformance::fixtures::banded_features(w, h, 3, true, salt);
        let feature_bufs = FeatureBuffers {
            features: gpu.storage("features", &features),
            thresholds: gpu.storage("thresholds", &[FeatureThresholds::DEFAULT]),
            sorted: gpu.storage_zeroed::<u32>("feature-sorted seeds", n_seeds),
            groups: gpu.storage_zeroed::<u32>("surface groups", n_seeds),
            sorted_per_seed: gpu.storage_zeroed::<u32>("feature-sorted seeds (per seed)", n_seeds),
            links: gpu.storage_zeroed::<u32>("links", n_seeds),
            links_b: gpu.storage_zeroed::<u32>("links (jump)", n_seeds),
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
                // The per-seed form first, into its own output (the chunk
                // form below clears and claims again).
                let mut encoder = gpu.device.create_command_encoder(&Default::default());
                let per_seed: [(&str, &[&wgpu::Buffer], u32); 7] = [
                    ("clear_claims", &[&params, &claims], n_seeds as u32),
                    ("claim", &[&params, &motion_buf, &claims], n_pixels as u32),
                    (
                        "take_seed",
                        &[&params, &motion_buf, &claims, &seeds, &reprojected, &flags],
                        n_seeds as u32,
                    ),
                    ("count_flags", &[&params, &flags, &counts], chunks * COUNT_LANES),
                    ("scan", &[&params, &counts], 1),
                    (
                        "list_free_seed",
                        &[&params, &flags, &counts, &free],
                        n_seeds as u32,
                    ),
                    (
                        "recycle_seed",
                        &[&params, &flags, &counts, &free, &seeds, &reprojected],
                        n_seeds as u32,
                    ),
                ];
                for (pass, buffers, n) in per_seed {
                    passes.encode(gpu, &mut encoder, pass, buffers, n);
                }
                gpu.queue.submit([encoder.finish()]);
                let per_seed_out = gpu.read::<u32>(&reprojected, n_seeds).unwrap();
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
                assert_eq!(per_seed_out, cpu, "reprojection per seed, {what}");
            }

            // The renderer's frame, reduced to intensities by the GPU.
            let c = colours(n_pixels, salt ^ frame);
            gpu.queue.write_buffer(&colour, 0, bytemuck::cast_slice(&c));
            passes.run(gpu, "intensity", &[&params, &colour, &intensity], n_pixels as u32);
            let values: Vec<f32> = gpu.read(&intensity, n_pixels).unwrap();
            // Bit for bit up to what WGSL and Vulkan allow a compiler: any NaN
            // equals any NaN (hardware need not keep a NaN's payload; the sort's
            // key maps every NaN alike), and a finite value may differ by the
            // rounding of its products and sums, because a multiply and an add
            // may be fused (NVIDIA's compiler fuses luma's: 2 units in the last
            // place seen on an H100; lavapipe does not fuse). The passes after
            // this one are integer work on the values read back: exact.
            for (i, (&got, v)) in values.iter().zip(&c).enumerate() {
                let terms = [0.2126 * v.x, 0.7152 * v.y, 0.0722 * v.z];
                let scale: f32 = terms.iter().map(|t| t.abs()).sum();
                assert!(
                    within_rounding(got, luma(v.truncate()), scale),
                    "intensity of pixel {i}, {what}: {got:e} against the CPU's {:e}",
                    luma(v.truncate())
                );
            }

            // Sort (seeds -> scratch), retarget with this frame's table (scratch -> seeds).
            let p = layout.params(frame);
            let step = step_index(frame, p.tile_log2) as usize;
            // First the feature-aware passes from the same seeds, into their own buffers.
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            let fb = &feature_bufs;
            let steps: [(&str, &[&wgpu::Buffer], u32); 5] = [
                (
                    "surface_group",
                    &[&params, &fb.features, &fb.thresholds, &fb.groups],
                    p.seed_count(),
                ),
                (
                    "sort_rank_features",
                    &[&params, &intensity, &fb.groups, &seeds, &ranked],
                    p.seed_count(),
                ),
                (
                    "sort_gather_features",
                    &[&params, &tile_buf, &fb.groups, &ranked, &fb.sorted_per_seed],
                    p.seed_count(),
                ),
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
                    "record_link",
                    &[
                        &params,
                        &table_bufs[step],
                        &fb.features,
                        &fb.thresholds,
                        &fb.links,
                    ],
                    p.seed_count(),
                ),
            ];
            for (pass, buffers, n) in steps {
                passes.encode(gpu, &mut encoder, pass, buffers, n);
            }
            gpu.queue.submit([encoder.finish()]);
            // The links as recorded (read before the jump rounds rewrite them).
            let gpu_links = gpu.read::<u32>(&fb.links, n_seeds).unwrap();
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            for round in 0..features::permute::JUMP_ROUNDS {
                let (from, to) = if round % 2 == 0 {
                    (&fb.links, &fb.links_b)
                } else {
                    (&fb.links_b, &fb.links)
                };
                passes.encode(
                    gpu,
                    &mut encoder,
                    "jump_link",
                    &[&params, from, to],
                    p.seed_count(),
                );
            }
            passes.encode(
                gpu,
                &mut encoder,
                "retarget_features",
                &[
                    &params,
                    &table_bufs[step],
                    &fb.links,
                    &fb.features,
                    &fb.thresholds,
                    &fb.sorted,
                    &fb.out,
                ],
                p.seed_count(),
            );
            gpu.queue.submit([encoder.finish()]);
            // The per-pass intermediates are the reference form's: the fast
            // path behind `permute_frame_features` leaves its scratch buffers
            // unspecified (its output is checked against the same passes below).
            let (mut f_sorted, mut f_sources, mut f_next) =
                (vec![0; n_seeds], vec![0; n_seeds], vec![0; n_seeds]);
            features::permute::permute_frame_features_reference(
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
                gpu.read::<u32>(&fb.sorted_per_seed, n_seeds).unwrap(),
                f_sorted,
                "surface_group + sort_rank_features + sort_gather_features, {what}"
            );
            assert_eq!(gpu_links, f_sources, "record_link, {what}");
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

            // The two-pass sort (rank, gather) first, into its own buffers.
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            passes.encode(
                gpu,
                &mut encoder,
                "sort_rank",
                &[&params, &intensity, &seeds, &ranked],
                p.seed_count(),
            );
            passes.encode(
                gpu,
                &mut encoder,
                "sort_gather",
                &[&params, &tile_buf, &ranked, &gathered],
                p.seed_count(),
            );
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
                gpu.read::<u32>(&gathered, n_seeds).unwrap(),
                sorted,
                "sort_rank + sort_gather, {what}"
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
    use kernels::sampler_entry::{
        key_layout, screen_sobol_pair, spatiotemporal_pair, zsobol_pair, SamplerParams,
    };
    let keys = defaults::screen_sobol_keys();
    let key_buf = gpu.storage("keys", keys.keys());
    let tile = defaults::tile_64();
    let tile_buf = gpu.storage("shift tile", tile.values());
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

        // The spatiotemporal sampler reads the 64x64 tile (key_side_log2 = 6).
        let st_params = SamplerParams {
            key_side_log2: 6,
            ..params
        };
        let st_uniform = gpu.uniform("spatiotemporal params", &st_params);
        passes.run(
            gpu,
            "spatiotemporal",
            &[&st_uniform, &tile_buf, &samples],
            n as u32,
        );
        let cpu: Vec<[u32; 2]> = (0..n)
            .map(|i| {
                let v = spatiotemporal_pair(tile.values(), 6, spp, frame, pixel(i), sample_index, pair);
                [v.x.to_bits(), v.y.to_bits()]
            })
            .collect();
        assert_eq!(read_bits(&samples), cpu, "spatiotemporal, {what}");
        assert!(
            cpu.iter().any(|v| v != &cpu[0]),
            "{what}: constant spatiotemporal samples"
        );
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

#[test]
fn the_rounding_tolerance_scales_with_the_terms() {
    let two_up = f32::from_bits(1.0f32.to_bits() + 2);
    assert!(within_rounding(1.0, two_up, 1.0) && within_rounding(f32::NAN, -f32::NAN, 1.0));
    assert!(!within_rounding(1.0, 1.001, 1.0) && !within_rounding(1.0, f32::NAN, 1.0));
    assert!(!within_rounding(1.0, f32::INFINITY, 1.0) && within_rounding(f32::INFINITY, f32::INFINITY, 1.0));
    assert!(!within_rounding(0.0, 1e-6, 1.0) && within_rounding(0.0, 1e-6, 10.0));
}
