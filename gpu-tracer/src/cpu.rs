//! The CPU renderer: the kernels' own per-pixel functions run with rayon.
//!
//! [`render_frame`] calls `kernels::trace_pixel` (through `trace_pixel_counted_variant`, the variant the GPU
//! runs for the scene) for every visible pixel, exactly as the GPU's `trace_cs` (or its smaller variants) does, so the two agree up to
//! floating-point differences between the host's and the device's math
//! libraries. Rows are distributed over the current rayon pool (use
//! `ThreadPool::install` to choose the thread count).

use crate::error::{Error, Result};
use crate::scene::{SceneGpu, TraceVariant};
use glam::{UVec2, Vec4};
use kernels::abi::{GBufferGpu, TraceParams, MAX_DEPTH_LIMIT, SAMPLER_SCREEN_SOBOL};
use kernels::trace::sampler_kind;
use kernels::{accumulate_pixel, gbuffer_pixel, trace_pixel_counted_variant, trace_variant};
use rayon::prelude::*;

/// Traces one frame: `color[y * width + x]` = mean radiance of the pixel's
/// `params.spp` samples, `(r, g, b, 1)`, with pixel `(x, y)` using seed
/// `seeds[y * padded_width + x]`. The screen-space Sobol sampler
/// (`params.sampler` is `SAMPLER_SCREEN_SOBOL`, with or without
/// `SAMPLER_JITTER_ONLY`) reads
/// `sampler_core::defaults::screen_sobol_keys()`, the keys the GPU tracer
/// binds; `params`' key-layout fields must describe them (as
/// [`SceneGpu::trace_params`] sets them).
///
/// # Errors
/// [`Error::FrameSize`] for a zero size or `padded_width < width`;
/// [`Error::InvalidParameter`] for `spp == 0`, `max_depth` outside
/// `1..=MAX_DEPTH_LIMIT`, or counts in `params` that do not match `scene`;
/// [`Error::BufferSize`] when `seeds` has fewer than `padded_width * height`
/// entries or `color` is not `width * height` long.
///
/// Returns the number of rays traced (camera, continuation and shadow rays).
///
/// Runs the trace kernel's variant the GPU runs for `scene`
/// ([`SceneGpu::trace_variant`]), as [`render_frame_variant`].
pub fn render_frame(
    scene: &SceneGpu,
    params: &TraceParams,
    seeds: &[u32],
    color: &mut [Vec4],
) -> Result<u64> {
    render_frame_variant(scene, params, seeds, color, scene.trace_variant())
}

/// [`render_frame`] with the trace kernel's `variant`
/// (`kernels::trace_variant`): [`TraceVariant::Full`] renders any scene,
/// the smaller variants the scenes that fit them, with the same colours
/// bit for bit.
///
/// # Errors
/// As [`render_frame`]; [`Error::UnfitTraceVariant`] for a variant on a
/// scene it cannot render ([`SceneGpu::fits_trace_variant`]).
pub fn render_frame_variant(
    scene: &SceneGpu,
    params: &TraceParams,
    seeds: &[u32],
    color: &mut [Vec4],
    variant: TraceVariant,
) -> Result<u64> {
    check_params(scene, params)?;
    if !scene.fits_trace_variant(variant) {
        return Err(Error::UnfitTraceVariant {
            variant: variant.name(),
        });
    }
    let trace = match variant {
        TraceVariant::Full => trace_pixel_counted_variant::<{ trace_variant::FULL }>,
        TraceVariant::Basic => trace_pixel_counted_variant::<{ trace_variant::BASIC }>,
        TraceVariant::Untextured => trace_pixel_counted_variant::<{ trace_variant::UNTEXTURED }>,
    };
    let (width, stride) = (params.width as usize, params.padded_width as usize);
    let pixels = width * params.height as usize;
    check_len("seed buffer", stride * params.height as usize, seeds.len(), true)?;
    check_len("frame colour buffer", pixels, color.len(), false)?;
    let keys = sampler_core::defaults::screen_sobol_keys();
    if [SAMPLER_SCREEN_SOBOL, kernels::abi::SAMPLER_SPATIOTEMPORAL].contains(&sampler_kind(params)) {
        let l = keys.layout();
        let fields = [
            ("key_side_log2", params.key_side_log2, l.side_log2),
            ("key_pairs", params.key_pairs, l.pairs),
            ("key_levels", params.key_levels, l.levels),
        ];
        for (name, value, want) in fields {
            if value != want {
                return Err(Error::InvalidParameter {
                    name,
                    value,
                    expected: "the layout of sampler_core::defaults::screen_sobol_keys()",
                });
            }
        }
    }
    // The spatiotemporal sampler's frame points, computed once for the frame
    // (the same numbers as without the table).
    let (params, table) = crate::sampler_data::with_frame_points(params);
    let params = &params;
    let with_points;
    let keys = if table.is_empty() {
        crate::sampler_data::sampler_buffer()
    } else {
        let mut buffer = crate::sampler_data::sampler_buffer().to_vec();
        let start = crate::sampler_data::point_table_offset();
        buffer[start..start + table.len()].copy_from_slice(&table);
        with_points = buffer;
        &with_points[..]
    };
    let rays = color
        .par_chunks_mut(width)
        .enumerate()
        .map(|(y, row)| {
            let mut rays = 0u64;
            for (x, out) in row.iter_mut().enumerate() {
                let (c, n) = trace(
                    params,
                    UVec2::new(x as u32, y as u32),
                    seeds[y * stride + x],
                    keys,
                    &scene.nodes,
                    &scene.triangles,
                    &scene.materials,
                    &scene.emitters,
                    &scene.attrs,
                    &scene.images,
                    &scene.environment,
                );
                *out = c;
                rays += n as u64;
            }
            rays
        })
        .sum();
    Ok(rays)
}

/// Computes the G-buffer of a frame: `gbuffer[y * width + x]` =
/// `kernels::gbuffer_pixel` of pixel `(x, y)` (what the GPU's `gbuffer_cs`
/// writes), with the cameras of `params` and the previous positions of
/// `scene` ([`SceneGpu::set_previous_positions`]).
///
/// # Errors
/// As [`render_frame`] for `params`; [`Error::BufferSize`] when `gbuffer`
/// is not `width * height` long.
pub fn gbuffer_frame(scene: &SceneGpu, params: &TraceParams, gbuffer: &mut [GBufferGpu]) -> Result<()> {
    check_params(scene, params)?;
    let width = params.width as usize;
    check_len("G-buffer", width * params.height as usize, gbuffer.len(), false)?;
    gbuffer.par_chunks_mut(width).enumerate().for_each(|(y, row)| {
        for (x, out) in row.iter_mut().enumerate() {
            *out = gbuffer_pixel(
                params,
                UVec2::new(x as u32, y as u32),
                &scene.nodes,
                &scene.triangles,
                &scene.materials,
                &scene.attrs,
                &scene.images,
                &scene.previous,
            );
        }
    });
    Ok(())
}

/// Folds frame `params.frame`'s colours into the accumulation buffer
/// (`kernels::accumulate_pixel` per pixel, as `accumulate_cs` does).
///
/// # Errors
/// [`Error::FrameSize`] for a zero size; [`Error::BufferSize`] when `color`
/// or `accum` is not `width * height` long.
pub fn accumulate_frame(params: &TraceParams, color: &[Vec4], accum: &mut [Vec4]) -> Result<()> {
    if params.width == 0 || params.height == 0 {
        return Err(Error::FrameSize {
            width: params.width,
            height: params.height,
            padded_width: params.padded_width,
        });
    }
    let pixels = params.width as usize * params.height as usize;
    check_len("frame colour buffer", pixels, color.len(), false)?;
    check_len("accumulation buffer", pixels, accum.len(), false)?;
    let frame = params.frame;
    accum
        .par_iter_mut()
        .zip(color.par_iter())
        .for_each(|(a, c)| *a = accumulate_pixel(*a, *c, frame));
    Ok(())
}

/// White-noise seeds for a `padded_width x padded_height` seed buffer
/// (`sampler_core::initial_seed` with `salt`), row-major: the seeds of
/// frame 0, and of every frame `t` in the `white` mode with salt
/// `sampler_core::frame_salt(salt, t)`.
pub fn white_seeds(padded_width: u32, padded_height: u32, salt: u32) -> Vec<u32> {
    (0..padded_height)
        .flat_map(|y| (0..padded_width).map(move |x| sampler_core::initial_seed(x, y, padded_width, salt)))
        .collect()
}

fn check_len(buffer: &'static str, expected: usize, actual: usize, at_least: bool) -> Result<()> {
    if actual == expected || (at_least && actual > expected) {
        Ok(())
    } else {
        Err(Error::BufferSize {
            buffer,
            expected,
            actual,
        })
    }
}

fn check_params(scene: &SceneGpu, p: &TraceParams) -> Result<()> {
    if p.width == 0 || p.height == 0 || p.padded_width < p.width {
        return Err(Error::FrameSize {
            width: p.width,
            height: p.height,
            padded_width: p.padded_width,
        });
    }
    let checks: [(&'static str, u32, bool, &'static str); 5] = [
        ("spp", p.spp, p.spp >= 1, ">= 1"),
        (
            "max_depth",
            p.max_depth,
            (1..=MAX_DEPTH_LIMIT).contains(&p.max_depth),
            "1..=64 (kernels::abi::MAX_DEPTH_LIMIT)",
        ),
        (
            "node_count",
            p.node_count,
            p.node_count as usize == scene.nodes.len(),
            "the scene's node count",
        ),
        (
            "triangle_count",
            p.triangle_count,
            p.triangle_count as usize == scene.triangles.len(),
            "the scene's triangle count",
        ),
        (
            "emitter_count",
            p.emitter_count,
            p.emitter_count <= scene.emitter_count,
            "at most the scene's emitter count",
        ),
    ];
    for (name, value, ok, expected) in checks {
        if !ok {
            return Err(Error::InvalidParameter {
                name,
                value,
                expected,
            });
        }
    }
    crate::scene::check_glossy_regularization(p.glossy_regularization)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cornell::{cornell_box, LIGHT_RECT, LIGHT_Y};
    use crate::scene::{Camera, Material, Scene, TraceSettings, Triangle};
    use glam::Vec3;
    use kernels::abi::SEED_MODE_ADVANCE;
    use kernels::camera::project_point;
    use kernels::trace_pixel;

    #[test]
    fn ray_count_is_bounded_by_the_path_layout() {
        let scene = SceneGpu::build(&cornell_box()).unwrap();
        let mut settings = TraceSettings::new(16, 16);
        settings.spp = 2;
        let params = scene.trace_params(&settings, 0).unwrap();
        let seeds = white_seeds(16, 16, 3);
        let mut color = vec![Vec4::ZERO; 256];
        let rays = render_frame(&scene, &params, &seeds, &mut color).unwrap();
        let paths = 256 * 2;
        // Every path traces its camera ray; each vertex adds at most a shadow
        // and a continuation ray.
        assert!(rays >= paths, "{rays} rays for {paths} paths");
        assert!(
            rays <= paths * (1 + 2 * params.max_depth as u64),
            "{rays} rays for {paths} paths"
        );
        // The Cornell box is closed but for the front: most paths bounce.
        assert!(rays > 3 * paths, "{rays} rays for {paths} paths");
    }

    /// Renders `frames` frames with fresh white seeds and returns the mean image.
    fn render_mean(scene: &SceneGpu, settings: &TraceSettings, frames: u32) -> Vec<Vec4> {
        let n = (settings.width * settings.height) as usize;
        let mut color = vec![Vec4::ZERO; n];
        let mut accum = vec![Vec4::ZERO; n];
        for t in 0..frames {
            let params = scene.trace_params(settings, t).expect("params");
            let seeds = white_seeds(settings.padded_width, settings.height, t);
            render_frame(scene, &params, &seeds, &mut color).expect("render");
            accumulate_frame(&params, &color, &mut accum).expect("accumulate");
        }
        accum
    }

    #[test]
    fn cornell_box_looks_like_a_cornell_box() {
        let scene = SceneGpu::build(&cornell_box()).expect("scene");
        let mut settings = TraceSettings::new(64, 64);
        settings.spp = 4;
        let img = render_mean(&scene, &settings, 16);
        assert!(img
            .iter()
            .all(|c| c.is_finite() && c.min_element() >= 0.0 && c.w == 16.0));
        let params = scene.trace_params(&settings, 0).expect("params");
        let at = |p: Vec3| {
            let r = project_point(&params, p).expect("visible");
            img[r.y as usize * 64 + r.x as usize].truncate()
        };
        let luma = |c: Vec3| sampler_core::luma(c);
        // The light is the brightest thing in the image, and shows its emission exactly.
        let light_centre = Vec3::new(
            (LIGHT_RECT[0].0 + LIGHT_RECT[1].0) / 2.0,
            LIGHT_Y,
            (LIGHT_RECT[0].1 + LIGHT_RECT[1].1) / 2.0,
        );
        // The light also reflects (albedo 0.78) light from the room back down: a little
        // more than its emission.
        let light = at(light_centre);
        let excess = light - crate::cornell::LIGHT_EMISSION;
        assert!(
            excess.min_element() >= 0.0 && excess.max_element() < 0.5,
            "{light}"
        );
        // Every pixel brighter than a third of the light's luma lies on the light's
        // rectangle (up to its one-pixel border).
        let lo = project_point(&params, Vec3::new(LIGHT_RECT[1].0, LIGHT_Y, LIGHT_RECT[0].1)).unwrap();
        let hi = project_point(&params, Vec3::new(LIGHT_RECT[0].0, LIGHT_Y, LIGHT_RECT[1].1)).unwrap();
        let mut bright = 0;
        for (i, c) in img.iter().enumerate() {
            if luma(c.truncate()) > luma(light) / 3.0 {
                let (x, y) = ((i % 64) as f32, (i / 64) as f32);
                let inside = x >= lo.x.min(hi.x) - 1.0
                    && x <= lo.x.max(hi.x) + 1.0
                    && y >= lo.y.min(hi.y) - 1.0
                    && y <= lo.y.max(hi.y) + 1.0;
                assert!(inside, "bright pixel ({x}, {y}) off the light ({lo}, {hi})");
                bright += 1;
            }
        }
        assert!(bright >= 4, "light covers {bright} pixels");
        // Red wall (left, x ~ 556) is red, green wall (right, x = 0) green.
        let red = at(Vec3::new(555.0, 300.0, 400.0));
        let green = at(Vec3::new(1.0, 300.0, 400.0));
        assert!(red.x > 3.0 * red.y && red.x > 3.0 * red.z, "red wall {red}");
        assert!(
            green.y > 1.5 * green.x && green.y > 1.5 * green.z,
            "green wall {green}"
        );
        // Colour bleeding: the white floor near the red wall is redder than near the green wall.
        let floor_red = mean_around(
            &img,
            64,
            project_point(&params, Vec3::new(500.0, 0.0, 300.0)).unwrap(),
        );
        let floor_green = mean_around(
            &img,
            64,
            project_point(&params, Vec3::new(56.0, 0.0, 300.0)).unwrap(),
        );
        let ratio = |c: Vec3| c.x / c.y;
        assert!(
            ratio(floor_red) > ratio(floor_green) * 1.1,
            "{floor_red} vs {floor_green}"
        );
        // Ceiling corners are lit only indirectly: darker than the directly lit floor.
        let floor_centre = at(Vec3::new(400.0, 0.0, 150.0));
        let ceiling = at(Vec3::new(20.0, 548.0, 540.0));
        assert!(luma(ceiling) < luma(floor_centre), "{ceiling} vs {floor_centre}");
        // Nothing else is as bright as the light: the walls are well below it.
        assert!(luma(floor_centre) < 0.2 * luma(light));
    }

    fn mean_around(img: &[Vec4], width: usize, p: glam::Vec2) -> Vec3 {
        let (cx, cy) = (p.x as i32, p.y as i32);
        let mut sum = Vec3::ZERO;
        let mut n = 0;
        for y in cy - 2..=cy + 2 {
            for x in cx - 2..=cx + 2 {
                sum += img[y as usize * width + x as usize].truncate();
                n += 1;
            }
        }
        sum / n as f32
    }

    /// A closed cube whose walls all have albedo `a` and emission `e`, seen
    /// from inside. Every point's radiance satisfies L = e + a L, so
    /// L = e / (1 - a) exactly, everywhere, for infinite path length; with
    /// paths of at most `D` segments it is e (1 - a^D) / (1 - a).
    fn furnace(a: f32, e: f32) -> SceneGpu {
        let mut triangles = Vec::new();
        let c = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
        let faces = [
            (
                [c(0., 0., 0.), c(1., 0., 0.), c(1., 1., 0.), c(0., 1., 0.)],
                Vec3::Z,
            ),
            (
                [c(0., 0., 1.), c(1., 0., 1.), c(1., 1., 1.), c(0., 1., 1.)],
                -Vec3::Z,
            ),
            (
                [c(0., 0., 0.), c(0., 1., 0.), c(0., 1., 1.), c(0., 0., 1.)],
                Vec3::X,
            ),
            (
                [c(1., 0., 0.), c(1., 1., 0.), c(1., 1., 1.), c(1., 0., 1.)],
                -Vec3::X,
            ),
            (
                [c(0., 0., 0.), c(1., 0., 0.), c(1., 0., 1.), c(0., 0., 1.)],
                Vec3::Y,
            ),
            (
                [c(0., 1., 0.), c(1., 1., 0.), c(1., 1., 1.), c(0., 1., 1.)],
                -Vec3::Y,
            ),
        ];
        for (q, inward) in faces {
            let flip = (q[1] - q[0]).cross(q[2] - q[0]).dot(inward) < 0.0;
            let q = if flip { [q[3], q[2], q[1], q[0]] } else { q };
            triangles.push(Triangle::new([q[0], q[1], q[2]], 0));
            triangles.push(Triangle::new([q[0], q[2], q[3]], 0));
        }
        let scene = Scene {
            lights: Vec::new(),
            environment_map: None,
            triangles,
            materials: vec![Material::new("furnace", Vec3::splat(a), Vec3::splat(e))],
            images: Vec::new(),
            camera: Camera {
                origin: Vec3::splat(0.5),
                target: Vec3::new(0.9, 0.6, 0.7),
                up: Vec3::Y,
                fov_y_degrees: 100.0,
            },
        };
        SceneGpu::build(&scene).expect("furnace")
    }

    #[test]
    fn furnace_converges_to_the_analytic_radiance() {
        // a = 0.5, e = 1: L = 2 with unbounded depth; max_depth 64 leaves a
        // bias of 2 * 0.5^64 (nothing). Russian roulette from vertex 3 keeps
        // it unbiased. Estimator variance is small, so a 32x32 x 8 spp x 4
        // frames mean (32768 paths) pins the mean to ~1e-3.
        let (a, e) = (0.5f32, 1.0f32);
        let scene = furnace(a, e);
        assert_eq!(scene.emitter_count, 12);
        let mut settings = TraceSettings::new(32, 32);
        settings.spp = 8;
        settings.max_depth = 64;
        let img = render_mean(&scene, &settings, 4);
        let n = img.len() as f64;
        let mean: f64 = img.iter().map(|c| c.x as f64).sum::<f64>() / n;
        let var: f64 = img.iter().map(|c| (c.x as f64 - mean).powi(2)).sum::<f64>() / (n - 1.0);
        let std_err = (var / n).sqrt();
        let expected = (e / (1.0 - a)) as f64;
        eprintln!("furnace: mean {mean} vs {expected} (standard error {std_err})");
        assert!(
            (mean - expected).abs() < 5.0 * std_err + 1e-4,
            "mean {mean} vs {expected} (standard error {std_err})"
        );
        // Grey in, grey out.
        assert!(img.iter().all(|c| c.x == c.y && c.y == c.z));

        // Bounded depth: exactly e (1 - a^D) / (1 - a) with D segments, no roulette.
        settings.max_depth = 3;
        settings.rr_depth = 64;
        let img = render_mean(&scene, &settings, 4);
        let mean: f64 = img.iter().map(|c| c.x as f64).sum::<f64>() / n;
        let expected = (e * (1.0 - a * a * a) / (1.0 - a)) as f64;
        assert!((mean - expected).abs() < 0.01, "depth 3: {mean} vs {expected}");
        // Depth 1: only direct emission, no noise at all.
        settings.max_depth = 1;
        let img = render_mean(&scene, &settings, 1);
        assert!(img.iter().all(|c| c.truncate() == Vec3::splat(e)));
    }

    #[test]
    fn next_event_estimation_and_bsdf_sampling_agree() {
        // Disabling NEE (emitter_count = 0 in the params) must give the same
        // expectation: each strategy alone is unbiased, and MIS never double
        // counts. Compare the mean image luma over independent frames, with a
        // tolerance of 4 combined standard errors.
        let scene = SceneGpu::build(&cornell_box()).expect("scene");
        let mut settings = TraceSettings::new(24, 24);
        settings.spp = 16;
        settings.max_depth = 4;
        settings.rr_depth = 64;
        let frames = 12;
        let mut stats = [(0.0f64, 0.0f64); 2];
        for (k, nee) in [true, false].into_iter().enumerate() {
            let mut params = scene.trace_params(&settings, 0).expect("params");
            if !nee {
                params.emitter_count = 0;
            }
            let totals: Vec<f64> = (0..frames)
                .map(|t| {
                    let seeds = white_seeds(24, 24, 1000 * k as u32 + t);
                    let mut color = vec![Vec4::ZERO; 24 * 24];
                    render_frame(&scene, &params, &seeds, &mut color).expect("render");
                    color
                        .iter()
                        .map(|c| sampler_core::luma(c.truncate()) as f64)
                        .sum::<f64>()
                })
                .collect();
            let n = frames as f64;
            let mean = totals.iter().sum::<f64>() / n;
            let var = totals.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
            stats[k] = (mean, (var / n).sqrt());
        }
        let [(a, sa), (b, sb)] = stats;
        let sigma = (sa * sa + sb * sb).sqrt();
        eprintln!("NEE+MIS {a} +- {sa} vs BSDF only {b} +- {sb}");
        assert!(
            (a - b).abs() < 4.0 * sigma,
            "NEE+MIS {a} +- {sa} vs BSDF only {b} +- {sb}"
        );
        // NEE is the lower-variance estimator in a scene with a small light.
        assert!(sa < sb);
    }

    #[test]
    fn seeds_define_the_image() {
        let scene = SceneGpu::build(&cornell_box()).expect("scene");
        let mut settings = TraceSettings::new(16, 8);
        settings.padded_width = 20;
        let seeds = white_seeds(20, 8, 3);
        let render = |frame: u32, settings: &TraceSettings, seeds: &[u32]| {
            let params = scene.trace_params(settings, frame).expect("params");
            let mut color = vec![Vec4::ZERO; 128];
            render_frame(&scene, &params, seeds, &mut color).expect("render");
            color
        };
        // Fixed mode: same seeds, same image, whatever the frame; advance mode: frames differ.
        assert_eq!(render(0, &settings, &seeds), render(5, &settings, &seeds));
        settings.seed_mode = SEED_MODE_ADVANCE;
        assert_eq!(render(0, &settings, &seeds), {
            let mut s = settings;
            s.seed_mode = 0;
            render(0, &s, &seeds)
        });
        assert_ne!(render(0, &settings, &seeds), render(1, &settings, &seeds));
        // A seed moved to another pixel carries its stream: pixel values differ
        // after swapping seeds between pixels.
        // (Pixel (8, 4) sees the back wall; seeds are indexed with the stride 20.)
        let mut swapped = seeds.clone();
        swapped.swap(4 * 20 + 8, 4 * 20 + 9);
        settings.seed_mode = 0;
        let (a, b) = (render(0, &settings, &seeds), render(0, &settings, &swapped));
        assert!(a[4 * 16 + 8].x > 0.0);
        assert_ne!(a[4 * 16 + 8], b[4 * 16 + 8]);
        assert_eq!(a[..4 * 16], b[..4 * 16]);
        // Rendering with one thread gives the same bits as with the pool.
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .expect("pool");
        let single = pool.install(|| render(0, &settings, &seeds));
        assert_eq!(single, render(0, &settings, &seeds));
    }

    #[test]
    fn apriori_samplers_use_the_default_keys() {
        use kernels::abi::{SAMPLER_JITTER_ONLY, SAMPLER_SEEDS, SAMPLER_SPATIOTEMPORAL, SAMPLER_ZSOBOL};
        let scene = SceneGpu::build(&cornell_box()).expect("scene");
        let keys = crate::sampler_data::sampler_buffer();
        let mut settings = TraceSettings::new(16, 12);
        settings.spp = 2;
        let seeds = white_seeds(16, 12, 3);
        let mut images = Vec::new();
        let samplers = [
            SAMPLER_SEEDS,
            SAMPLER_SCREEN_SOBOL,
            SAMPLER_ZSOBOL,
            SAMPLER_SCREEN_SOBOL | SAMPLER_JITTER_ONLY,
            SAMPLER_ZSOBOL | SAMPLER_JITTER_ONLY,
            SAMPLER_SPATIOTEMPORAL,
        ];
        for sampler in samplers {
            settings.sampler = sampler;
            let params = scene.trace_params(&settings, 2).expect("params");
            let mut color = vec![Vec4::ZERO; 16 * 12];
            render_frame(&scene, &params, &seeds, &mut color).expect("render");
            for (x, y) in [(0u32, 0u32), (7, 5), (15, 11)] {
                let want = trace_pixel(
                    &params,
                    glam::UVec2::new(x, y),
                    seeds[(y * 16 + x) as usize],
                    keys,
                    &scene.nodes,
                    &scene.triangles,
                    &scene.materials,
                    &scene.emitters,
                    &scene.attrs,
                    &scene.images,
                    &scene.environment,
                );
                assert_eq!(color[(y * 16 + x) as usize], want, "sampler {sampler} ({x}, {y})");
            }
            images.push(color);
        }
        for i in 0..images.len() {
            for j in 0..i {
                assert_ne!(
                    images[i], images[j],
                    "samplers {} and {}",
                    samplers[i], samplers[j]
                );
            }
        }
        // Parameters whose key layout is not the default keys' are refused.
        settings.sampler = SAMPLER_SCREEN_SOBOL;
        let bad = TraceParams {
            key_levels: 1,
            ..scene.trace_params(&settings, 0).expect("params")
        };
        let mut color = vec![Vec4::ZERO; 16 * 12];
        assert!(matches!(
            render_frame(&scene, &bad, &seeds, &mut color),
            Err(Error::InvalidParameter {
                name: "key_levels",
                ..
            })
        ));
    }

    #[test]
    fn pixel_value_is_the_mean_of_its_stream_samples() {
        // trace_pixel with spp samples = mean of trace_sample over stream
        // samples stream_sample(s), each starting at s * DIMS_PER_SAMPLE.
        use kernels::trace::{stream_sample, trace_sample};
        use sampler_core::RandomStream;
        let scene = SceneGpu::build(&cornell_box()).expect("scene");
        let mut settings = TraceSettings::new(16, 16);
        settings.spp = 3;
        settings.seed_mode = SEED_MODE_ADVANCE;
        let params = scene.trace_params(&settings, 7).expect("params");
        let pixel = glam::UVec2::new(8, 9);
        let seed = 0xDEAD_BEEF;
        let got = trace_pixel(
            &params,
            pixel,
            seed,
            &[],
            &scene.nodes,
            &scene.triangles,
            &scene.materials,
            &scene.emitters,
            &scene.attrs,
            &scene.images,
            &scene.environment,
        );
        let mut sum = Vec3::ZERO;
        for s in 0..3 {
            assert_eq!(stream_sample(&params, s), 7 * 3 + s);
            let stream = RandomStream::new(seed, stream_sample(&params, s), kernels::DIMS_PER_SAMPLE);
            assert_eq!(stream.index, (21 + s) * 386);
            sum += trace_sample(
                &params,
                pixel,
                stream,
                &scene.nodes,
                &scene.triangles,
                &scene.materials,
                &scene.emitters,
                &scene.attrs,
                &scene.images,
                &scene.environment,
            );
        }
        assert_eq!(got, (sum / 3.0).extend(1.0));
    }

    #[test]
    fn bad_buffers_and_params_are_errors() {
        let scene = SceneGpu::build(&cornell_box()).expect("scene");
        let params = scene.trace_params(&TraceSettings::new(8, 4), 0).expect("params");
        let mut color = vec![Vec4::ZERO; 32];
        let short = vec![0u32; 31];
        assert!(matches!(
            render_frame(&scene, &params, &short, &mut color),
            Err(Error::BufferSize {
                expected: 32,
                actual: 31,
                ..
            })
        ));
        let seeds = vec![0u32; 32];
        let mut small = vec![Vec4::ZERO; 31];
        assert!(render_frame(&scene, &params, &seeds, &mut small).is_err());
        let mut bad = params;
        bad.max_depth = 0;
        assert!(matches!(
            render_frame(&scene, &bad, &seeds, &mut color),
            Err(Error::InvalidParameter {
                name: "max_depth",
                ..
            })
        ));
        let mut bad = params;
        bad.node_count += 1;
        assert!(render_frame(&scene, &bad, &seeds, &mut color).is_err());
        let mut accum = vec![Vec4::ZERO; 30];
        assert!(accumulate_frame(&params, &color, &mut accum).is_err());
    }
}
