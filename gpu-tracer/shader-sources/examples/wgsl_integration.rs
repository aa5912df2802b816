//! A renderer that is not written with rust-gpu using the generated WGSL
//! passes (`sampler-core/shaders/wgsl/seed_permutation.wgsl`) between
//! frames: `cargo run -p shader-sources --example wgsl_integration`.
//!
//! The "renderer" is one WGSL compute shader that estimates a procedural
//! image (a disc over a gradient) with one random sample per pixel, drawn
//! from the pixel's seed. After each frame the seeds are permuted (intensity,
//! sort, retarget) so the next frame's error is distributed as blue noise.
//! Frames are written as PGM images to `target/wgsl_integration/`.

use sampler_core::{defaults, step_index, FrameLayout, FrameParams, STEP_COUNT};
use wgpu::util::DeviceExt;

/// The renderer: one sample per pixel from its seed, alone (not mixed with
/// the frame index: the permutation relies on a seed giving a similar value
/// next frame).
const RENDER_WGSL: &str = r#"
struct FrameParams { width: u32, height: u32, padded_width: u32, padded_height: u32,
                     block: u32, tile_log2: u32, frame: u32, reserved: u32 }
@group(0) @binding(0) var<uniform> params: FrameParams;
@group(0) @binding(1) var<storage, read> seeds: array<u32>;
@group(0) @binding(2) var<storage, read_write> colour: array<vec4<f32>>;

fn hash(x: u32) -> u32 {
    var h = x;
    h ^= h >> 16u; h *= 0x7feb352du; h ^= h >> 15u; h *= 0x846ca68bu; h ^= h >> 16u;
    return h;
}

@compute @workgroup_size(8, 8)
fn render(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= params.width || id.y >= params.height) { return; }
    let seed = seeds[id.y * params.padded_width + id.x];     // seed buffers are padded
    let size = vec2<f32>(f32(params.width), f32(params.height));
    let uv = (vec2<f32>(id.xy) + 0.5) / size;
    let truth = select(uv.x, 0.25, distance(uv, vec2(0.5)) < 0.3);
    let u = f32(hash(seed) >> 8u) / 16777216.0;               // one sample in [0, 1)
    let v = select(0.0, 1.0, u < truth);                     // 1-spp estimate of `truth`
    colour[id.y * params.width + id.x] = vec4<f32>(v, v, v, 1.0);
}
"#;

/// The generated permutation passes (all ten entry points in one module).
const PASSES_WGSL: &str = include_str!("../../../sampler-core/shaders/wgsl/seed_permutation.wgsl");

const WIDTH: u32 = 256;
const HEIGHT: u32 = 160;
const FRAMES: u32 = 8;

fn main() {
    // --- Device: any adapter; lavapipe (Mesa's CPU Vulkan) works.
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle().with_env());
    let adapter = pollster::block_on(instance.request_adapter(&Default::default())).expect("no GPU adapter");
    let info = adapter.get_info();
    println!(
        "device: {} ({:?}, {:?})",
        info.name, info.backend, info.device_type
    );
    let (device, queue) = pollster::block_on(adapter.request_device(&Default::default())).expect("device");

    // --- Pipelines: ours, and the generated passes by their entry-point names.
    let module = |code: &str| {
        device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: None,
            source: wgpu::ShaderSource::Wgsl(code.into()),
        })
    };
    let (ours, passes) = (module(RENDER_WGSL), module(PASSES_WGSL));
    let pipeline = |m: &wgpu::ShaderModule, entry: &str| {
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: None, // reflected: group 0, bindings as in sampler-core/shaders/README.md
            module: m,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        })
    };
    let render = pipeline(&ours, "render");
    let seed_init = pipeline(&passes, "permute_entry_seed_init_cs");
    let intensity = pipeline(&passes, "permute_entry_intensity_cs");
    let sort = pipeline(&passes, "permute_entry_sort_cs");
    let retarget = pipeline(&passes, "permute_entry_retarget_cs");

    // --- Buffers. Seeds cover the frame padded to the tile (64), 4x4 sort blocks.
    let layout = FrameLayout::new(WIDTH, HEIGHT, 4, 64).unwrap();
    let (tile, tables) = (defaults::tile_64(), defaults::tables_64());
    let storage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
    let with_data = |contents: &[u8], usage| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: None,
            contents,
            usage,
        })
    };
    let empty = |bytes: usize| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size: bytes as u64,
            usage: storage,
            mapped_at_creation: false,
        })
    };
    let params = with_data(
        bytemuck::bytes_of(&layout.params(0)),
        wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
    );
    let tile_buf = with_data(bytemuck::cast_slice(tile.values()), storage);
    let table_bufs: Vec<wgpu::Buffer> = (0..STEP_COUNT as u32)
        .map(|i| with_data(bytemuck::cast_slice(tables.table(i).packed()), storage))
        .collect();
    let (seeds, sorted) = (empty(4 * layout.seed_count()), empty(4 * layout.seed_count()));
    let colour = empty(16 * layout.pixel_count());
    let intensities = empty(4 * layout.pixel_count());
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: 16 * layout.pixel_count() as u64,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });

    // One dispatch of `pipeline` with `buffers` at bindings 0.., over `groups`.
    let dispatch = |encoder: &mut wgpu::CommandEncoder,
                    p: &wgpu::ComputePipeline,
                    buffers: &[&wgpu::Buffer],
                    groups: (u32, u32)| {
        let entries: Vec<wgpu::BindGroupEntry> = buffers
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: b.as_entire_binding(),
            })
            .collect();
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &p.get_bind_group_layout(0),
            entries: &entries,
        });
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(p);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups(groups.0, groups.1, 1);
    };
    // The generated passes are linear: `n` invocations in 64-wide groups.
    let linear = kernels::permute_entry::linear_dispatch;
    let (n_seeds, n_pixels) = (layout.seed_count() as u32, layout.pixel_count() as u32);

    let out_dir = shader_sources::workspace_root().join("target/wgsl_integration");
    std::fs::create_dir_all(&out_dir).unwrap();
    for frame in 0..FRAMES {
        let p: FrameParams = layout.params(frame);
        queue.write_buffer(&params, 0, bytemuck::bytes_of(&p));
        let mut encoder = device.create_command_encoder(&Default::default());
        if frame == 0 {
            // White-noise seeds to start from (`params.frame` is the salt).
            dispatch(&mut encoder, &seed_init, &[&params, &seeds], linear(n_seeds));
        }
        // 1. The renderer's frame, with the current seeds.
        dispatch(
            &mut encoder,
            &render,
            &[&params, &seeds, &colour],
            (WIDTH.div_ceil(8), HEIGHT.div_ceil(8)),
        );
        // 2. Between frames: intensities, sort (seeds -> sorted), retarget (sorted -> seeds),
        //    with the retarget table of this frame's step.
        dispatch(
            &mut encoder,
            &intensity,
            &[&params, &colour, &intensities],
            linear(n_pixels),
        );
        let blocks = p.blocks_x() * p.blocks_y();
        dispatch(
            &mut encoder,
            &sort,
            &[&params, &intensities, &tile_buf, &seeds, &sorted],
            linear(blocks),
        );
        let table = &table_bufs[step_index(frame, p.tile_log2) as usize];
        dispatch(
            &mut encoder,
            &retarget,
            &[&params, table, &sorted, &seeds],
            linear(n_seeds),
        );
        encoder.copy_buffer_to_buffer(&colour, 0, &readback, 0, readback.size());
        queue.submit([encoder.finish()]);

        // Write the frame as an 8-bit PGM.
        readback
            .slice(..)
            .map_async(wgpu::MapMode::Read, |r| r.expect("map"));
        device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
        let pixels: Vec<[f32; 4]> =
            bytemuck::pod_collect_to_vec(&readback.slice(..).get_mapped_range().unwrap());
        readback.unmap();
        let mut pgm = format!("P5 {WIDTH} {HEIGHT} 255\n").into_bytes();
        pgm.extend(pixels.iter().map(|c| (c[0] * 255.0) as u8));
        let path = out_dir.join(format!("frame_{frame:02}.pgm"));
        std::fs::write(&path, pgm).unwrap();
        println!(
            "frame {frame}: blurred error {:.4} -> {}",
            blurred_error(&pixels),
            path.display()
        );
    }
}

/// RMS over the image of the error (estimate minus the shader's `truth`)
/// averaged over 3x3 pixels: what the eye sees. Blue-noise error (frames
/// after the first) mostly cancels in the average; white noise (frame 0)
/// does not.
fn blurred_error(pixels: &[[f32; 4]]) -> f32 {
    let (w, h) = (WIDTH as i32, HEIGHT as i32);
    let error = |x: i32, y: i32| {
        let (u, v) = ((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
        let truth = if ((u - 0.5).powi(2) + (v - 0.5).powi(2)).sqrt() < 0.3 {
            0.25
        } else {
            u
        };
        pixels[(y * w + x) as usize][0] - truth
    };
    let mut sum = 0.0;
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let e: f32 = (-1..=1)
                .flat_map(|dy| (-1..=1).map(move |dx| (dx, dy)))
                .map(|(dx, dy)| error(x + dx, y + dy))
                .sum();
            sum += (e / 9.0).powi(2);
        }
    }
    (sum / ((w - 2) * (h - 2)) as f32).sqrt()
}
