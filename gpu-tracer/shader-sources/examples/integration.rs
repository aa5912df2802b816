//! How a renderer uses the seed permutation, to copy from:
//! `cargo run -p shader-sources --example integration [-- --cpu] [--out DIR]`.
//!
//! The "renderer" is one WGSL compute shader that estimates a procedural
//! image (a disc over a gradient) with one random sample per pixel, drawn
//! from the pixel's seed. After each frame the seeds are permuted (intensity,
//! sort, retarget: the generated WGSL of `sampler-core/shaders/wgsl/`), so the
//! next frame's error is distributed as blue noise. Without a GPU adapter
//! (or with `--cpu`) the same loop runs on the CPU with
//! `sampler_core::permute_frame`: the renderer is integer arithmetic, so both
//! paths write the same frames, bit for bit. Frames are 8-bit PGM images in
//! `DIR` (default `target/integration`); each line printed gives a frame's
//! error after a 3x3 box blur (white noise in frame 0, blue after).

use sampler_core::{defaults, initial_seed, permute_frame, step_index, FrameLayout, STEP_COUNT};
use wgpu::util::DeviceExt;

/// The renderer. A seed alone picks the sample (not mixed with the frame
/// index: the permutation relies on a seed giving a similar value next frame).
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
// Brightness of pixel (x, y) in 24-bit fixed point: 0.25 inside a disc of
// radius 0.3 * width, else a gradient (x + 0.5) / width.
fn truth(x: u32, y: u32) -> u32 {
    let dx = i32(2u * x + 1u) - i32(params.width);
    let dy = i32(2u * y + 1u) - i32(params.height);
    let r = i32(params.width) * 3 / 5;
    if (dx * dx + dy * dy < r * r) { return 1u << 22u; }
    return ((2u * x + 1u) << 23u) / params.width;
}
@compute @workgroup_size(8, 8)
fn render(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= params.width || id.y >= params.height) { return; }
    let seed = seeds[id.y * params.padded_width + id.x];     // seed buffers are padded
    let v = select(0.0, 1.0, (hash(seed) >> 8u) < truth(id.x, id.y)); // 1-spp estimate
    colour[id.y * params.width + id.x] = vec4<f32>(v, v, v, 1.0);
}
"#;

/// The generated permutation passes (one module, every entry point).
const PASSES_WGSL: &str = include_str!("../../../sampler-core/shaders/wgsl/seed_permutation.wgsl");
const WIDTH: u32 = 256;
const HEIGHT: u32 = 160;
const FRAMES: u32 = 8;

fn main() {
    // Headless machines: Mesa's window-system layer prints "error: XDG_RUNTIME_DIR is
    // invalid" when the variable is missing; a private directory keeps it quiet.
    if std::env::var_os("XDG_RUNTIME_DIR").is_none() {
        let dir = std::env::temp_dir().join("bluenoise-runtime-example");
        if std::fs::create_dir_all(&dir).is_ok() {
            std::env::set_var("XDG_RUNTIME_DIR", dir);
        }
    }
    let args: Vec<String> = std::env::args().collect();
    let out = match args.iter().position(|a| a == "--out") {
        Some(i) => std::path::PathBuf::from(args.get(i + 1).expect("--out DIR")),
        None => shader_sources::workspace_root().join("target/integration"),
    };
    std::fs::create_dir_all(&out).expect("output directory");
    let layout = FrameLayout::new(WIDTH, HEIGHT, 4, 64).unwrap(); // 4x4 sort blocks, 64x64 tile
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle().with_env());
    let adapter = match args.iter().any(|a| a == "--cpu") {
        true => None,
        false => pollster::block_on(instance.request_adapter(&Default::default())).ok(),
    };
    let frames = match adapter {
        Some(adapter) => {
            let info = adapter.get_info();
            println!(
                "device: {} ({:?}, {:?})",
                info.name, info.backend, info.device_type
            );
            gpu_frames(&adapter, &layout)
        }
        None => {
            println!("device: CPU fallback (sampler_core::permute_frame)");
            cpu_frames(&layout)
        }
    };
    for (t, frame) in frames.iter().enumerate() {
        let mut pgm = format!("P5 {WIDTH} {HEIGHT} 255\n").into_bytes();
        pgm.extend(frame.iter().map(|c| (c[0] * 255.0) as u8));
        let path = out.join(format!("frame_{t:02}.pgm"));
        std::fs::write(&path, pgm).expect("write frame");
        println!(
            "frame {t}: blurred error {:.4} -> {}",
            blurred_error(frame),
            path.display()
        );
    }
}

/// The CPU path: the renderer in Rust, then `permute_frame` between frames.
fn cpu_frames(layout: &FrameLayout) -> Vec<Vec<[f32; 4]>> {
    let (tile, tables) = (defaults::tile_64(), defaults::tables_64());
    let pw = layout.padded_width();
    let mut seeds: Vec<u32> = (0..layout.seed_count() as u32)
        .map(|i| initial_seed(i % pw, i / pw, pw, 0))
        .collect();
    let mut next = vec![0; layout.seed_count()];
    let mut frames = Vec::new();
    for t in 0..FRAMES {
        let image: Vec<[f32; 4]> = (0..WIDTH * HEIGHT)
            .map(|i| {
                let (x, y) = (i % WIDTH, i / WIDTH);
                let v = (hash(seeds[(y * pw + x) as usize]) >> 8 < truth(x, y)) as u32 as f32;
                [v, v, v, 1.0]
            })
            .collect();
        permute_frame(layout, t, &image, &tile, &tables, &seeds, &mut next).unwrap();
        std::mem::swap(&mut seeds, &mut next);
        frames.push(image);
    }
    frames
}

/// The GPU path: per frame, render, then intensity -> sort -> retarget.
fn gpu_frames(adapter: &wgpu::Adapter, layout: &FrameLayout) -> Vec<Vec<[f32; 4]>> {
    let (device, queue) = pollster::block_on(adapter.request_device(&Default::default())).expect("device");
    let module = |code: &str| {
        let source = wgpu::ShaderSource::Wgsl(code.into());
        device.create_shader_module(wgpu::ShaderModuleDescriptor { label: None, source })
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
    let [seed_init, intensity, sort, retarget] = ["seed_init", "intensity", "sort", "retarget"]
        .map(|pass| pipeline(&passes, &format!("permute_entry_{pass}_cs")));

    let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
    let with_data = |contents: &[u8], usage| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: None,
            contents,
            usage,
        })
    };
    let empty = |bytes: usize, usage| with_data(&vec![0; bytes], usage);
    let uniform = wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST;
    let params = with_data(bytemuck::bytes_of(&layout.params(0)), uniform);
    let (tile, tables) = (defaults::tile_64(), defaults::tables_64());
    let tile = with_data(bytemuck::cast_slice(tile.values()), usage);
    let tables: Vec<_> = (0..STEP_COUNT as u32)
        .map(|i| with_data(bytemuck::cast_slice(tables.table(i).packed()), usage))
        .collect();
    let seeds = empty(4 * layout.seed_count(), usage);
    let sorted = empty(4 * layout.seed_count(), usage);
    let colour = empty(16 * layout.pixel_count(), usage);
    let intensities = empty(4 * layout.pixel_count(), usage);
    let read = wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST;
    let readback = empty(16 * layout.pixel_count(), read);

    // One dispatch of `p` with `buffers` at bindings 0, 1, ... over `groups`.
    let dispatch = |encoder: &mut wgpu::CommandEncoder,
                    p: &wgpu::ComputePipeline,
                    buffers: &[&wgpu::Buffer],
                    groups: (u32, u32)| {
        let entries: Vec<_> = (0..buffers.len())
            .map(|i| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: buffers[i].as_entire_binding(),
            })
            .collect();
        let layout = p.get_bind_group_layout(0);
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &layout,
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
    let mut frames = Vec::new();
    for t in 0..FRAMES {
        let p = layout.params(t);
        queue.write_buffer(&params, 0, bytemuck::bytes_of(&p));
        let mut encoder = device.create_command_encoder(&Default::default());
        if t == 0 {
            // White-noise seeds to start from (`params.frame`, 0 here, is the salt).
            dispatch(&mut encoder, &seed_init, &[&params, &seeds], linear(n_seeds));
        }
        let blocks = p.blocks_x() * p.blocks_y();
        let table = &tables[step_index(t, p.tile_log2) as usize]; // this frame's step of the walk
        let frame: [(&wgpu::ComputePipeline, &[&wgpu::Buffer], (u32, u32)); 4] = [
            // 1. The renderer's frame, with the current seeds.
            (
                &render,
                &[&params, &seeds, &colour],
                (WIDTH.div_ceil(8), HEIGHT.div_ceil(8)),
            ),
            // 2. Between frames: luma, sort (seeds -> sorted), retarget (sorted -> seeds).
            (&intensity, &[&params, &colour, &intensities], linear(n_pixels)),
            (
                &sort,
                &[&params, &intensities, &tile, &seeds, &sorted],
                linear(blocks),
            ),
            (&retarget, &[&params, table, &sorted, &seeds], linear(n_seeds)),
        ];
        for (pipeline, buffers, groups) in frame {
            dispatch(&mut encoder, pipeline, buffers, groups);
        }
        encoder.copy_buffer_to_buffer(&colour, 0, &readback, 0, readback.size());
        queue.submit([encoder.finish()]);
        readback
            .slice(..)
            .map_async(wgpu::MapMode::Read, |r| r.expect("map"));
        device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
        frames.push(bytemuck::pod_collect_to_vec(
            &readback.slice(..).get_mapped_range().unwrap(),
        ));
        readback.unmap();
    }
    frames
}

/// The renderer's `hash` and `truth`, in Rust for the CPU path.
fn hash(x: u32) -> u32 {
    let mut h = x;
    h ^= h >> 16;
    h = h.wrapping_mul(0x7feb352d);
    h ^= h >> 15;
    h = h.wrapping_mul(0x846ca68b);
    h ^ (h >> 16)
}
fn truth(x: u32, y: u32) -> u32 {
    let (dx, dy, r) = (
        (2 * x + 1) as i32 - WIDTH as i32,
        (2 * y + 1) as i32 - HEIGHT as i32,
        WIDTH as i32 * 3 / 5,
    );
    if dx * dx + dy * dy < r * r {
        1 << 22
    } else {
        ((2 * x + 1) << 23) / WIDTH
    }
}

/// RMS over the image of the error (estimate minus truth) averaged over 3x3
/// pixels: roughly what the eye sees. Blue-noise error mostly cancels in the
/// average; white noise (frame 0) does not.
fn blurred_error(frame: &[[f32; 4]]) -> f32 {
    let error = |x: u32, y: u32| frame[(y * WIDTH + x) as usize][0] - truth(x, y) as f32 / (1 << 24) as f32;
    let mut sum = 0.0;
    for y in 1..HEIGHT - 1 {
        for x in 1..WIDTH - 1 {
            let e: f32 = (0..9).map(|k| error(x + k % 3 - 1, y + k / 3 - 1)).sum();
            sum += (e / 9.0).powi(2);
        }
    }
    (sum / ((WIDTH - 2) * (HEIGHT - 2)) as f32).sqrt()
}
