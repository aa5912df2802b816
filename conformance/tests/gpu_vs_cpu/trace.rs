//! The path tracer: traced frames (statistically, and pixel for pixel
//! with the same seeds), the G-buffer of a textured moving scene, and the
//! feature pass.

use glam::Vec4;
use gpu_tracer::gpu::{Gpu, PermuteMode};
use sampler_core::sequences::seed::hash_u32;
use sampler_core::*;

/// Per-pixel running sums over frames: mean and variance of the luma.
struct PixelStats {
    sum: Vec<f64>,
    sum_sq: Vec<f64>,
    frames: u32,
}

impl PixelStats {
    fn new(n: usize) -> Self {
        PixelStats {
            sum: vec![0.0; n],
            sum_sq: vec![0.0; n],
            frames: 0,
        }
    }
    fn add(&mut self, color: &[Vec4]) {
        for (i, c) in color.iter().enumerate() {
            let v = luma(c.truncate()) as f64;
            self.sum[i] += v;
            self.sum_sq[i] += v * v;
        }
        self.frames += 1;
    }
    fn mean(&self, i: usize) -> f64 {
        self.sum[i] / self.frames as f64
    }
    /// Variance of the mean of pixel `i` (sample variance / frames).
    fn var_of_mean(&self, i: usize) -> f64 {
        let n = self.frames as f64;
        let m = self.mean(i);
        ((self.sum_sq[i] / n - m * m).max(0.0) * n / (n - 1.0)) / n
    }
}

#[test]
fn path_traced_frames_agree_statistically_with_the_cpu_renderer() {
    let Some(gpu) = Gpu::for_test("path_traced_frames_agree_statistically_with_the_cpu_renderer") else {
        return;
    };
    let scene = gpu_tracer::SceneGpu::build(&gpu_tracer::cornell::cornell_box()).unwrap();
    compare_trace_statistics(&gpu, &scene, kernels::abi::SAMPLER_SEEDS, "seeds");
}

/// The glossy Cornell box (metallic-roughness spheres: GGX sampling, the
/// reused lobe number, MIS with `eval` and `pdf`): per-pixel means agree
/// statistically with the CPU renderer, and with the same seeds the frames
/// agree pixel for pixel up to float rounding, so the GPU runs the same
/// BSDF code on the same numbers; with path regularisation too (the
/// roughness floor and the continuing lobe's roughness), and with ZSobol's
/// jitter (sharp first hits read vertex 0's pairs from ZSobol).
#[test]
fn glossy_frames_agree_with_the_cpu_renderer() {
    let Some(gpu) = Gpu::for_test("glossy_frames_agree_with_the_cpu_renderer") else {
        return;
    };
    let scene = gpu_tracer::SceneGpu::build(&gpu_tracer::cornell::cornell_glossy()).unwrap();
    compare_trace_statistics(&gpu, &scene, kernels::abi::SAMPLER_SEEDS, "glossy seeds");
    use kernels::abi::{SAMPLER_JITTER_ONLY, SAMPLER_SEEDS, SAMPLER_ZSOBOL};
    for (sampler, strength, mode, name) in [
        (SAMPLER_SEEDS, 0.0, PermuteMode::White, "glossy seeds"),
        (
            SAMPLER_SEEDS,
            0.7,
            PermuteMode::White,
            "glossy seeds, regularised 0.7",
        ),
        // Jitter only: at the spheres (sharp first hits) vertex 0's pairs
        // come from ZSobol too, the rest from the permuted seeds.
        (
            SAMPLER_ZSOBOL | SAMPLER_JITTER_ONLY,
            0.0,
            PermuteMode::Permute,
            "glossy zsobol-jitter",
        ),
    ] {
        compare_same_seeds_with(&gpu, &scene, sampler, strength, mode, name);
    }
}

/// `scene` with an 8x8 bilinear, repeating normal map of varied tilts
/// (scale 0.8) on every material, and planar texture coordinates `((x + z)
/// / 140, (y + z) / 140)` on every triangle (none is degenerate for the
/// axis-aligned walls of a Cornell box).
fn with_normal_maps(mut scene: gpu_tracer::scene::Scene) -> gpu_tracer::scene::Scene {
    use gpu_tracer::scene::{Filter, Image, NormalTexture, TextureRef, Wrap};
    let image = scene.images.len() as u32;
    scene.images.push(Image {
        name: "bumps".into(),
        width: 8,
        height: 8,
        texels: (0..64)
            .map(|i| {
                let (x, y) = ((i % 8) as f32, (i / 8) as f32);
                let r = 128.0 + 110.0 * (x * 0.9).sin();
                let g = 128.0 + 110.0 * (y * 1.3 + x).cos();
                [r as u8, g as u8, 230, 255]
            })
            .collect(),
    });
    let texture = TextureRef {
        image,
        wrap_u: Wrap::Repeat,
        wrap_v: Wrap::Repeat,
        filter: Filter::Bilinear,
        transform: None,
    };
    for m in &mut scene.materials {
        m.normal_texture = Some(NormalTexture { texture, scale: 0.8 });
    }
    for t in &mut scene.triangles {
        t.uvs = t.vertices.map(|p| glam::Vec2::new(p.x + p.z, p.y + p.z) / 140.0);
    }
    scene
}

/// Punctual lights (point, spot, a directional sun with a disk) and an
/// environment map on the GPU against the CPU: the outdoor scene (with and
/// without a sky map), the Cornell box with a point and a spot light
/// beside its area light (selection by power across kinds), the glossy
/// Cornell box with normal maps under a point light, and the smooth-normal
/// sphere fixture, plain and normal-mapped.
/// Per-pixel means agree statistically, and with the same seeds the frames
/// agree pixel for pixel up to float rounding.
#[test]
fn lit_frames_agree_with_the_cpu_renderer() {
    use gpu_tracer::scene::{Light, LightKind};
    let Some(gpu) = Gpu::for_test("lit_frames_agree_with_the_cpu_renderer") else {
        return;
    };
    let mut room = gpu_tracer::cornell::cornell_box();
    room.lights
        .push(Light::point("bulb", glam::Vec3::new(400.0, 400.0, 200.0), 4.0e4));
    room.lights.push(Light {
        name: "spot".into(),
        kind: LightKind::Spot {
            inner_cone_angle: 0.2,
            outer_cone_angle: 0.5,
        },
        position: glam::Vec3::new(150.0, 500.0, 300.0),
        direction: glam::Vec3::new(0.2, -1.0, 0.1),
        color: glam::Vec3::new(1.0, 0.8, 0.6),
        intensity: 8.0e4,
        range: None,
    });
    // The outdoor scene under a sky map with a bright spot instead of its
    // constant sky: the map's importance sampling and MIS weights.
    let mut mapped = gpu_tracer::outdoor::sun_and_sky();
    let (w, h) = (64u32, 32u32);
    mapped.environment_map = Some(gpu_tracer::scene::EnvironmentMap {
        name: "spot sky".into(),
        width: w,
        height: h,
        texels: (0..w * h)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                let spot = if (x as i32 - 20).abs() < 3 && (y as i32 - 9).abs() < 2 {
                    50.0
                } else {
                    0.0
                };
                [0.3 + spot, 0.35 + spot, 0.45 * (1.0 - y as f32 / h as f32)]
            })
            .collect(),
        rotation_degrees: 75.0,
    });
    // The glossy Cornell box with normal maps on every material (Lambertian
    // and metallic-roughness shading in a tilted frame) and a point light.
    let mut bumpy = with_normal_maps(gpu_tracer::cornell::cornell_glossy());
    bumpy
        .lights
        .push(Light::point("bulb", glam::Vec3::new(400.0, 400.0, 200.0), 4.0e4));
    // The smooth sphere (vertex normals, under its directional light),
    // framed close so that it covers most pixels, plain and normal-mapped
    // (the tangent frame around the smooth normal).
    let mut sphere = gpu_tracer::gltf::load_gltf(
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../gpu-tracer/tests/data/gltf/smooth_sphere.gltf"
        ),
        None,
    )
    .unwrap()
    .scene;
    assert!(sphere.triangles.iter().all(|t| t.normals.is_some()));
    sphere.camera = gpu_tracer::scene::Camera {
        origin: glam::Vec3::new(0.0, 0.0, 2.2),
        target: glam::Vec3::ZERO,
        up: glam::Vec3::Y,
        fov_y_degrees: 60.0,
    };
    let mut bumpy_sphere = with_normal_maps(sphere.clone());
    for t in &mut bumpy_sphere.triangles {
        t.uvs = t.vertices.map(|p| glam::Vec2::new(p.x + p.z, p.y + p.z) * 2.0);
    }
    // Per-pixel statistics (64 frames a side) for the two scenes that hold
    // every new light kind between them; the same-seed comparison, which
    // already pins the GPU to the CPU's arithmetic, for all of them.
    for (scene, name, statistics) in [
        (gpu_tracer::outdoor::sun_and_sky(), "sun-sky", false),
        (room, "cornell + point + spot", true),
        (mapped, "sun-sky under a sky map", true),
        (bumpy, "glossy cornell, normal-mapped, + point", false),
        (sphere, "smooth sphere", false),
        (bumpy_sphere, "smooth sphere, normal-mapped", false),
    ] {
        let scene = gpu_tracer::SceneGpu::build(&scene).unwrap();
        if statistics {
            compare_trace_statistics(&gpu, &scene, kernels::abi::SAMPLER_SEEDS, name);
        }
        compare_same_seeds(
            &gpu,
            &scene,
            kernels::abi::SAMPLER_SEEDS,
            PermuteMode::White,
            name,
        );
    }
}

/// `--sampler screen-sobol` and `--sampler zsobol` on the GPU against the
/// CPU: per-pixel means agree statistically (independent seeds), and with
/// the same seeds the frames agree pixel for pixel up to float differences,
/// which only holds if the GPU reads the same a-priori numbers (keys at
/// binding 7, key layout and sample indices) as the CPU.
#[test]
fn apriori_samplers_agree_with_the_cpu_renderer() {
    use gpu_tracer::{cornell::cornell_box, SceneGpu};
    let Some(gpu) = Gpu::for_test("apriori_samplers_agree_with_the_cpu_renderer") else {
        return;
    };
    let scene = SceneGpu::build(&cornell_box()).unwrap();
    use kernels::abi::{
        SAMPLER_JITTER_ONLY, SAMPLER_KRONECKER, SAMPLER_SCREEN_SOBOL, SAMPLER_SPATIOTEMPORAL, SAMPLER_ZSOBOL,
    };
    for (sampler, name, mode) in [
        (SAMPLER_SCREEN_SOBOL, "screen-sobol", PermuteMode::White),
        (SAMPLER_ZSOBOL, "zsobol", PermuteMode::White),
        (SAMPLER_SPATIOTEMPORAL, "spatiotemporal", PermuteMode::White),
        // The Kronecker sequence: generators read from the sampler buffer.
        (
            SAMPLER_SPATIOTEMPORAL | SAMPLER_KRONECKER,
            "spatiotemporal-kronecker",
            PermuteMode::White,
        ),
        // Homes in the seed buffer (written by the host, read through the flag).
        (SAMPLER_SPATIOTEMPORAL, "spatiotemporal-hold", PermuteMode::Hold),
        // Jitter only: the seeds drive the rest, so permute them as the GPU would.
        (
            SAMPLER_SCREEN_SOBOL | SAMPLER_JITTER_ONLY,
            "screen-sobol-jitter",
            PermuteMode::Permute,
        ),
        (
            SAMPLER_ZSOBOL | SAMPLER_JITTER_ONLY,
            "zsobol-jitter",
            PermuteMode::Permute,
        ),
        // The Kronecker sequence's jitter (its net shifts) with the seeds.
        (
            SAMPLER_SPATIOTEMPORAL | SAMPLER_KRONECKER | SAMPLER_JITTER_ONLY,
            "spatiotemporal-kronecker-jitter",
            PermuteMode::Temporal,
        ),
    ] {
        compare_trace_statistics(&gpu, &scene, sampler, name);
        compare_same_seeds(&gpu, &scene, sampler, mode, name);
    }
}

/// Same seeds (and `sampler`, at a samplers' origin other than 0) on both
/// sides: only float rounding differs, so at least 95% of pixel-frames agree
/// within 1e-3 (relative).
fn compare_same_seeds(gpu: &Gpu, scene: &gpu_tracer::SceneGpu, sampler: u32, mode: PermuteMode, name: &str) {
    compare_same_seeds_with(gpu, scene, sampler, 0.0, mode, name)
}

/// [`compare_same_seeds`] with path regularisation of `glossy_regularization`.
fn compare_same_seeds_with(
    gpu: &Gpu,
    scene: &gpu_tracer::SceneGpu,
    sampler: u32,
    glossy_regularization: f32,
    mode: PermuteMode,
    name: &str,
) {
    use gpu_tracer::{render_cpu, render_gpu, RenderJob, TileChoice, TraceSettings};
    {
        let (w, h, frames) = (24u32, 20u32, 8u32);
        let mut settings = TraceSettings::new(w, h);
        settings.spp = 4;
        settings.sampler = sampler;
        settings.glossy_regularization = glossy_regularization;
        // A draw of the samplers' placement other than the baked one, so the
        // origin's adds are compared too (`TraceSettings::sampler_origin`).
        settings.sampler_origin = [37, 4090];
        let job = RenderJob {
            settings,
            frames,
            mode,
            block: 4,
            tile: TileChoice::Tile64,
            salt: 5,
        };
        let mut cpu_frames = Vec::new();
        render_cpu(scene, &job, |_, c| cpu_frames.push(c.to_vec())).unwrap();
        let mut gpu_frames = Vec::new();
        let mut collect = |_t: u32, c: &[Vec4]| gpu_frames.push(c.to_vec());
        render_gpu(gpu, scene, &job, |_| {}, Some(&mut collect)).unwrap();
        let (frac, total) = crate::fraction_close(&cpu_frames, &gpu_frames);
        eprintln!(
            "{name}: same seeds, {:.2}% of {total} pixel-frames equal within 1e-3",
            100.0 * frac
        );
        assert_eq!(total, (w * h * frames) as usize);
        assert!(
            frac > 0.95,
            "{name}: only {:.2}% of pixel-frames agree",
            100.0 * frac
        );
    }
}

/// Per-pixel means of 64 white-mode frames on the CPU and the GPU, from
/// different salts, with the path's 2D decisions from `sampler`: the
/// differences must look like noise (mean z^2 near 1 or below). With an
/// a-priori sampler both sides share those numbers (they depend only on
/// pixel and frame), which correlates the estimates and makes the test
/// conservative, never stricter.
fn compare_trace_statistics(gpu: &Gpu, scene: &gpu_tracer::SceneGpu, sampler: u32, name: &str) {
    use gpu_tracer::{render_cpu, render_gpu, RenderJob, TileChoice, TraceSettings};
    let (w, h, frames) = (24u32, 20u32, 64u32);
    let mut settings = TraceSettings::new(w, h);
    settings.spp = 2;
    settings.sampler = sampler;
    // White noise on both sides, from different salts: independent estimates
    // of the same per-pixel expectation.
    let job = |salt| RenderJob {
        settings,
        frames,
        mode: PermuteMode::White,
        block: 4,
        tile: TileChoice::Tile64,
        salt,
    };
    let n = (w * h) as usize;
    let mut cpu = PixelStats::new(n);
    render_cpu(scene, &job(1), |_, c| cpu.add(c)).unwrap();
    let mut gpu_stats = PixelStats::new(n);
    let mut collect = |_t: u32, c: &[Vec4]| gpu_stats.add(c);
    let out = render_gpu(gpu, scene, &job(1_000_003), |_| {}, Some(&mut collect)).unwrap();
    assert_eq!(out.last.len(), n);
    // z-score of the difference of means per pixel; pixels with no variance
    // on either side (background, light) must agree to float precision.
    let (mut z2_sum, mut within4, mut counted) = (0.0f64, 0usize, 0usize);
    for i in 0..n {
        let var = cpu.var_of_mean(i) + gpu_stats.var_of_mean(i);
        let d = gpu_stats.mean(i) - cpu.mean(i);
        if var < 1e-12 {
            assert!(
                d.abs() <= 1e-4 * (1.0 + cpu.mean(i).abs()),
                "pixel {i}: {} vs {}",
                gpu_stats.mean(i),
                cpu.mean(i)
            );
            continue;
        }
        let z = d / var.sqrt();
        z2_sum += z * z;
        counted += 1;
        if z.abs() <= 4.0 {
            within4 += 1;
        }
    }
    let mean_z2 = z2_sum / counted as f64;
    let frac4 = within4 as f64 / counted as f64;
    eprintln!(
        "{name}: {counted} pixels compared: mean z^2 {mean_z2:.3} (expected ~1), {:.2}% within 4 sigma",
        100.0 * frac4
    );
    // Heavy-tailed path-tracing noise inflates sample variances little at 128
    // samples per pixel; a biased kernel would push mean z^2 far above 1.
    assert!(counted > n / 2, "{name}: too few pixels with variance: {counted}");
    assert!(
        mean_z2 < 1.6,
        "{name}: mean z^2 {mean_z2:.3}: GPU and CPU disagree"
    );
    assert!(
        frac4 > 0.99,
        "only {:.2}% of pixels within 4 sigma",
        100.0 * frac4
    );
    // And the image means agree within 4 sigma (pixels are independent in
    // white mode, so the variances add).
    let total = |s: &PixelStats| (0..n).map(|i| s.mean(i)).sum::<f64>() / n as f64;
    let (tc, tg) = (total(&cpu), total(&gpu_stats));
    let sigma = ((0..n)
        .map(|i| cpu.var_of_mean(i) + gpu_stats.var_of_mean(i))
        .sum::<f64>())
    .sqrt()
        / n as f64;
    eprintln!("{name}: image means {tc:.4} (CPU) vs {tg:.4} (GPU), sigma {sigma:.4}");
    assert!(
        (tc - tg).abs() < 4.0 * sigma,
        "{name}: image means {tc:.4} (CPU) vs {tg:.4} (GPU), sigma {sigma:.4}"
    );
}

/// A textured, moving scene: a checker-textured floor (nearest, repeat), a
/// wall with a bilinear clamp texture, a light whose emission is textured,
/// and a block that moved since the previous frame under a camera that
/// moved too. The G-buffer's integer parts (ids, flags) agree bit for bit
/// between the GPU's `gbuffer_cs` and the CPU's `gbuffer_frame`, its float
/// parts within 1e-4 (relative), and the traced colour with the same seeds
/// within 1e-3 on at least 95% of the pixels (texture decoding uses `pow`,
/// whose last bits differ between the host's libm and the device).
#[test]
fn textured_moving_scene_and_gbuffer_agree_with_the_cpu() {
    use glam::{Vec2, Vec3};
    use gpu_tracer::cpu::{gbuffer_frame, render_frame, white_seeds};
    use gpu_tracer::gpu::{TracePipelines, Tracer};
    use gpu_tracer::scene::{Camera, Filter, Image, Material, Scene, TextureRef, Triangle, Wrap};
    use gpu_tracer::{SceneGpu, TraceSettings};
    use kernels::abi::{GBUFFER_HIT, GBUFFER_PREV_IN_FRONT};
    let Some(gpu) = Gpu::for_test("textured_moving_scene_and_gbuffer_agree_with_the_cpu") else {
        return;
    };
    let checker = Image {
        name: "checker".into(),
        width: 4,
        height: 4,
        texels: (0..16)
            .map(|i| {
                if (i % 4 + i / 4) % 2 == 0 {
                    [250, 240, 230, 255]
                } else {
                    [20, 40, 90, 255]
                }
            })
            .collect(),
    };
    let gradient = Image {
        name: "gradient".into(),
        width: 3,
        height: 2,
        texels: vec![
            [255, 0, 0, 255],
            [0, 255, 0, 255],
            [0, 0, 255, 255],
            [9, 99, 199, 255],
            [128; 4],
            [255; 4],
        ],
    };
    let tex = |image, wrap, filter| TextureRef {
        image,
        wrap_u: wrap,
        wrap_v: wrap,
        filter,
        transform: None,
    };
    let quad = |c: [Vec3; 4], uv: f32, material: u32, object: u32| {
        let uvs = [
            Vec2::ZERO,
            Vec2::new(uv, 0.0),
            Vec2::new(uv, uv),
            Vec2::new(0.0, uv),
        ];
        [
            Triangle {
                vertices: [c[0], c[1], c[2]],
                uvs: [uvs[0], uvs[1], uvs[2]],
                material,
                object,
                tangent: None,
                normals: None,
            },
            Triangle {
                vertices: [c[0], c[2], c[3]],
                uvs: [uvs[0], uvs[2], uvs[3]],
                material,
                object,
                tangent: None,
                normals: None,
            },
        ]
    };
    let v = Vec3::new;
    let mut triangles = Vec::new();
    triangles.extend(quad(
        [v(-2., 0., -2.), v(-2., 0., 2.), v(2., 0., 2.), v(2., 0., -2.)],
        3.0,
        0,
        0,
    ));
    triangles.extend(quad(
        [v(-2., 0., -2.), v(2., 0., -2.), v(2., 2., -2.), v(-2., 2., -2.)],
        1.5,
        1,
        1,
    ));
    triangles.extend(quad(
        [
            v(-0.5, 1.9, -0.5),
            v(0.5, 1.9, -0.5),
            v(0.5, 1.9, 0.5),
            v(-0.5, 1.9, 0.5),
        ],
        1.0,
        2,
        2,
    ));
    let block_first = triangles.len();
    triangles.extend(quad(
        [
            v(-0.3, 0.0, 0.2),
            v(0.3, 0.0, 0.2),
            v(0.3, 0.6, 0.2),
            v(-0.3, 0.6, 0.2),
        ],
        1.0,
        3,
        3,
    ));
    let mut light = Material::new("light", Vec3::ZERO, Vec3::splat(6.0));
    light.emission_texture = Some(tex(1, Wrap::Repeat, Filter::Nearest));
    let mut floor = Material::new("floor", Vec3::ONE, Vec3::ZERO);
    floor.base_color_texture = Some(tex(0, Wrap::Repeat, Filter::Nearest));
    let mut wall = Material::new("wall", Vec3::splat(0.9), Vec3::ZERO);
    wall.base_color_texture = Some(tex(1, Wrap::Clamp, Filter::Bilinear));
    let camera = |x: f32| Camera {
        origin: v(x, 1.0, 3.5),
        target: v(0.0, 0.6, 0.0),
        up: Vec3::Y,
        fov_y_degrees: 55.0,
    };
    let scene = Scene {
        lights: Vec::new(),
        environment_map: None,
        triangles,
        materials: vec![
            floor,
            wall,
            light,
            Material::new("block", Vec3::splat(0.6), Vec3::ZERO),
        ],
        images: vec![checker, gradient],
        camera: camera(0.0),
    };
    // The block moved by +0.1 in x since the previous frame; the camera by 0.05.
    let mut gpu_scene = SceneGpu::build(&scene).unwrap();
    let previous: Vec<[Vec3; 3]> = scene.triangles.iter().map(|t| t.vertices).collect();
    let mut now = previous.clone();
    for t in &mut now[block_first..] {
        for p in t.iter_mut() {
            p.x += 0.1;
        }
    }
    gpu_scene.set_positions(&now).unwrap();
    gpu_scene.set_previous_positions(&previous).unwrap();
    gpu_scene.set_cameras(&camera(0.05), &camera(0.0)).unwrap();

    let (w, h) = (40u32, 32u32);
    let mut settings = TraceSettings::new(w, h);
    settings.spp = 2;
    settings.max_depth = 4;
    let params = gpu_scene.trace_params(&settings, 1).unwrap();
    let seeds = white_seeds(w, h, 9);
    let n = (w * h) as usize;
    let mut cpu_gbuffer = vec![Default::default(); n];
    gbuffer_frame(&gpu_scene, &params, &mut cpu_gbuffer).unwrap();
    let mut cpu_color = vec![Vec4::ZERO; n];
    render_frame(&gpu_scene, &params, &seeds, &mut cpu_color).unwrap();

    let pipelines = TracePipelines::new(&gpu).unwrap();
    let seed_buffer = gpu.storage("seeds", &seeds);
    let color = Tracer::color_buffer(&gpu, w, h);
    let tracer = Tracer::new(&gpu, &pipelines, &gpu_scene, &params, &seed_buffer, color).expect("tracer");
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    tracer.encode_gbuffer(&mut encoder, &pipelines, None);
    tracer.encode_trace(&mut encoder, &pipelines, None);
    gpu.queue.submit([encoder.finish()]);
    let gpu_gbuffer = tracer.read_gbuffer(&gpu).unwrap();
    let gpu_color = tracer.read_color(&gpu).unwrap();

    let close = |a: Vec4, b: Vec4| (a - b).abs().max_element() <= 1e-4 * (1.0 + a.abs().max_element());
    let mut moving_block = 0;
    for (i, (c, g)) in cpu_gbuffer.iter().zip(&gpu_gbuffer).enumerate() {
        assert_eq!(c.ids, g.ids, "pixel {i}: ids");
        assert!(
            close(c.normal_depth, g.normal_depth),
            "pixel {i}: {:?} vs {:?}",
            c,
            g
        );
        assert!(close(c.albedo, g.albedo), "pixel {i}: {:?} vs {:?}", c, g);
        assert!(close(c.motion, g.motion), "pixel {i}: {:?} vs {:?}", c, g);
        if c.ids.x == 3 {
            assert_eq!(c.ids.w, GBUFFER_HIT | GBUFFER_PREV_IN_FRONT);
            moving_block += 1;
        }
    }
    // The block is visible, and its motion differs from the wall's behind it.
    assert!(moving_block > 10, "block covers {moving_block} pixels");
    let agree = cpu_color
        .iter()
        .zip(&gpu_color)
        .filter(|(p, q)| (**p - **q).abs().max_element() <= 1e-3 * (1.0 + p.abs().max_element()))
        .count();
    eprintln!(
        "textured moving scene: {agree} of {n} pixels within 1e-3; G-buffer ids identical on {}",
        gpu.describe()
    );
    assert!(
        agree as f64 >= 0.95 * n as f64,
        "only {agree} of {n} pixels agree"
    );
    // The textures show: the floor's albedo takes both checker colours.
    let floor_albedos: std::collections::BTreeSet<u32> = cpu_gbuffer
        .iter()
        .filter(|g| g.ids.x == 0)
        .map(|g| (g.albedo.x * 100.0) as u32)
        .collect();
    assert!(floor_albedos.len() >= 2, "{floor_albedos:?}");
}

/// The tracer's feature pass (`entry::features_cs`) against the CPU's
/// `kernels::surface_features` on the same G-buffer and colour: identical
/// ids and depths, normals within the encoding's precision and sort keys
/// within 1e-6 relative (a shader's division need not round like the
/// host's).
#[test]
fn feature_pass_matches_the_cpu() {
    use glam::{UVec4, Vec3};
    use gpu_tracer::gpu::{TracePipelines, Tracer};
    use gpu_tracer::{cornell::cornell_box, SceneGpu, TraceSettings};
    use kernels::abi::{GBufferGpu, GBUFFER_HIT, GBUFFER_NO_HIT};
    use kernels::surface_features::{demodulated_intensity, surface_feature};
    use sampler_core::features::surface::decode_normal;
    let Some(gpu) = Gpu::for_test("feature_pass_matches_the_cpu") else {
        return;
    };
    let (w, h) = (29u32, 17u32);
    let n = (w * h) as usize;
    let scene = SceneGpu::build(&cornell_box()).unwrap();
    let params = scene.trace_params(&TraceSettings::new(w, h), 0).unwrap();
    let unit = |i: u32, k: u32| hash_u32(i ^ (k << 20)) as f32 / u32::MAX as f32;
    let gbuffer: Vec<GBufferGpu> = (0..n as u32)
        .map(|i| {
            if i % 7 == 0 {
                return GBufferGpu {
                    ids: UVec4::new(GBUFFER_NO_HIT, GBUFFER_NO_HIT, GBUFFER_NO_HIT, 0),
                    ..Default::default()
                };
            }
            let normal = Vec3::new(unit(i, 1) - 0.5, unit(i, 2) - 0.5, unit(i, 3) - 0.5).normalize();
            GBufferGpu {
                normal_depth: normal.extend(1.0 + 9.0 * unit(i, 4)),
                albedo: Vec4::new(unit(i, 5), unit(i, 6), unit(i, 7) * 0.01, 0.0),
                ids: UVec4::new(i % 5, 0, 0, GBUFFER_HIT),
                ..Default::default()
            }
        })
        .collect();
    let color: Vec<Vec4> = (0..n as u32)
        .map(|i| Vec4::new(unit(i, 8) * 3.0, unit(i, 9), unit(i, 10), 1.0))
        .collect();

    let pipelines = TracePipelines::new(&gpu).unwrap();
    let seeds = gpu.storage_zeroed::<u32>("seeds", n);
    let features = gpu.storage_zeroed::<SurfaceFeature>("features", n);
    let keys = gpu.storage_zeroed::<f32>("keys", n);
    let mut tracer = Tracer::new(
        &gpu,
        &pipelines,
        &scene,
        &params,
        &seeds,
        Tracer::color_buffer(&gpu, w, h),
    )
    .expect("tracer");
    tracer.enable_features(&gpu, &pipelines, &features, &keys);
    gpu.queue
        .write_buffer(&tracer.gbuffer, 0, bytemuck::cast_slice(&gbuffer));
    gpu.queue
        .write_buffer(&tracer.color, 0, bytemuck::cast_slice(&color));
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    tracer.encode_features(&mut encoder, &pipelines, None);
    gpu.queue.submit([encoder.finish()]);
    let got_features: Vec<SurfaceFeature> = gpu.read(&features, n).unwrap();
    let got_keys: Vec<f32> = gpu.read(&keys, n).unwrap();

    let mut demodulated = 0;
    for i in 0..n {
        let (f, k) = (
            surface_feature(&gbuffer[i]),
            demodulated_intensity(color[i], &gbuffer[i]),
        );
        let g = got_features[i];
        assert_eq!((g.id, g.depth.to_bits()), (f.id, f.depth.to_bits()), "pixel {i}");
        if f.id != NO_SURFACE {
            assert!(
                decode_normal(g.normal).dot(decode_normal(f.normal)) > 0.999_99,
                "pixel {i}: normal {:x} vs {:x}",
                g.normal,
                f.normal
            );
        }
        assert!(
            (got_keys[i] - k).abs() <= 1e-6 * k.abs(),
            "pixel {i}: key {} vs {k}",
            got_keys[i]
        );
        if k != luma(color[i].truncate()) {
            demodulated += 1;
        }
    }
    assert!(demodulated > n / 2, "only {demodulated} of {n} keys demodulated");
}
