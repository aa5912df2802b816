//! The seed reprojection passes and the motion pass that feeds them, bit
//! for bit.

use gpu_tracer::gpu::Gpu;
use sampler_core::sequences::seed::hash_u32;
use sampler_core::*;

/// Backward motion fields for the reprojection conformance: random, and the
/// adversarial ones (all pixels to one source, NaN, a uniform shift, a
/// rotation, a zoom, infinities and huge values).
fn motion_fields(w: u32, h: u32, salt: u32) -> Vec<(&'static str, Vec<[f32; 2]>)> {
    let (cx, cy) = (w as f32 / 2.0, h as f32 / 2.0);
    let field =
        |f: &dyn Fn(u32, u32) -> [f32; 2]| -> Vec<[f32; 2]> { (0..w * h).map(|i| f(i % w, i / w)).collect() };
    let unit = |x: u32, y: u32, k: u32| hash_u32(x ^ (y << 12) ^ (k << 24) ^ salt) as f32 / u32::MAX as f32;
    vec![
        (
            "random",
            field(&|x, y| [unit(x, y, 1) * 12.0 - 6.0, unit(x, y, 2) * 12.0 - 6.0]),
        ),
        ("all to one source", field(&|x, y| [cx - x as f32, cy - y as f32])),
        ("NaN", field(&|_, _| [f32::NAN; 2])),
        ("uniform shift", field(&|_, _| [-2.25, 1.5])),
        (
            "rotation",
            field(&|x, y| {
                let (dx, dy) = (x as f32 + 0.5 - cx, y as f32 + 0.5 - cy);
                let (s, c) = 0.05f32.sin_cos();
                [c * dx - s * dy - dx, s * dx + c * dy - dy]
            }),
        ),
        (
            "zoom",
            field(&|x, y| [(x as f32 + 0.5 - cx) * -0.1, (y as f32 + 0.5 - cy) * -0.1]),
        ),
        (
            "infinities, huge values and NaN patches",
            field(&|x, y| match hash_u32(x * 31 + y * 977 + salt) % 5 {
                0 => [f32::INFINITY, 0.0],
                1 => [0.0, f32::NEG_INFINITY],
                2 => [1e30, -1e30],
                3 => [f32::NAN, 0.5],
                _ => [0.3, -0.7],
            }),
        ),
    ]
}

/// The GPU reprojection (six passes of `sampler_core::reprojection::passes`,
/// one atomic), in both forms (per chunk, per seed), against `sampler_core::reproject_frame`: identical seed
/// buffers on random and adversarial motion fields, frames with padding on
/// both axes and several chunks.
#[test]
fn reprojection_kernels_match_the_cpu_bit_for_bit() {
    use gpu_tracer::gpu::{PassForm, ReprojectPipelines, SeedReprojector};
    let Some(gpu) = Gpu::for_test("reprojection_kernels_match_the_cpu_bit_for_bit") else {
        return;
    };
    let pipelines = ReprojectPipelines::new(&gpu).expect("pipelines");
    for (k, &(w, h, block, tile)) in [(37u32, 23u32, 4u32, 16u32), (64, 64, 4, 64), (300, 130, 3, 64)]
        .iter()
        .enumerate()
    {
        let layout = FrameLayout::new(w, h, block, tile).unwrap();
        let seeds: Vec<u32> = (0..layout.seed_count() as u32)
            .map(|i| hash_u32(i ^ (k as u32) << 20))
            .collect();
        let seed_buffer = gpu.storage("seeds", &seeds);
        let mut reprojector = SeedReprojector::new(&gpu, &pipelines, layout, &seed_buffer).unwrap();
        for (name, motion) in motion_fields(w, h, k as u32) {
            let mut claims = vec![0; seeds.len()];
            let mut expected = vec![0; seeds.len()];
            let stats = reproject_frame(&layout, &motion, &seeds, &mut claims, &mut expected).unwrap();
            if name == "uniform shift" || name == "rotation" {
                assert!(stats.followed > stats.recycled, "{name}: {stats:?}");
                assert_ne!(expected, seeds, "{name} must move seeds");
            }
            reprojector.upload_motion(&gpu, &motion).unwrap();
            for form in [PassForm::PerGroup, PassForm::PerSeed] {
                reprojector.set_form(form);
                gpu.queue
                    .write_buffer(&seed_buffer, 0, bytemuck::cast_slice(&seeds));
                let mut encoder = gpu.device.create_command_encoder(&Default::default());
                reprojector.encode(&mut encoder, &pipelines, None);
                gpu.queue.submit([encoder.finish()]);
                let got: Vec<u32> = gpu.read(&seed_buffer, layout.seed_count()).unwrap();
                assert_eq!(got, expected, "{w}x{h}, {name}, {form:?}");
            }
        }
    }
}

/// The motion pass (`entry::motion_cs`) against the CPU's
/// `gpu_tracer::motion::seed_reprojection_motion` on the same G-buffers,
/// with every seed following, with slow pixels holding theirs, and with the
/// frame-wide rule of a frame that slides rigidly (the rigid-count pass's
/// atomic sum against `rigid_pixels`): the same vectors bit for bit,
/// `DISOCCLUDED` where the CPU marks a disocclusion.
#[test]
fn motion_kernel_matches_the_cpu() {
    use glam::{UVec2, UVec4, Vec2};
    use gpu_tracer::gpu::{TracePipelines, Tracer};
    use gpu_tracer::motion::{reprojection_motion, seed_reprojection_motion, write_visibility};
    use gpu_tracer::{cornell::cornell_box, SceneGpu, TraceSettings};
    use kernels::abi::{GBufferGpu, GBUFFER_HIT, GBUFFER_NO_HIT, GBUFFER_PREV_IN_FRONT};
    use kernels::pan_offset::FRAME_CLEARED_WORDS;
    let Some(gpu) = Gpu::for_test("motion_kernel_matches_the_cpu") else {
        return;
    };
    let (w, h) = (37u32, 23u32);
    let n = (w * h) as usize;
    let scene = SceneGpu::build(&cornell_box()).unwrap();
    let params = scene.trace_params(&TraceSettings::new(w, h), 0).unwrap();
    // G-buffers with four objects, misses, points behind the previous
    // camera, and depths around the 5% tolerance.
    let texel = |i: u32, salt: u32| {
        let r = |k: u32| hash_u32(i ^ (k << 16) ^ salt);
        let object = r(1) % 5;
        let hit = object < 4;
        let depth = 2.0 + (r(2) % 8) as f32 * 0.5;
        GBufferGpu {
            normal_depth: glam::Vec4::new(0.0, 0.0, 1.0, if hit { depth } else { 0.0 }),
            motion: glam::Vec4::new(
                (r(3) % 9) as f32 - 4.0 + (r(4) % 3) as f32 * 0.25,
                (r(5) % 7) as f32 - 3.0,
                depth * (0.93 + (r(6) % 15) as f32 * 0.01),
                0.0,
            ),
            ids: if hit {
                UVec4::new(
                    object,
                    0,
                    0,
                    GBUFFER_HIT | if r(7) % 9 == 0 { 0 } else { GBUFFER_PREV_IN_FRONT },
                )
            } else {
                UVec4::new(GBUFFER_NO_HIT, GBUFFER_NO_HIT, GBUFFER_NO_HIT, 0)
            },
            ..Default::default()
        }
    };
    let previous: Vec<GBufferGpu> = (0..n as u32).map(|i| texel(i, 11)).collect();
    let current: Vec<GBufferGpu> = (0..n as u32).map(|i| texel(i, 12)).collect();

    let pipelines = TracePipelines::new(&gpu).unwrap();
    let seeds = gpu.storage_zeroed::<u32>("seeds", n);
    let motion = gpu.storage_zeroed::<Vec2>("motion", n);
    let mut tracer = Tracer::new(
        &gpu,
        &pipelines,
        &scene,
        &params,
        &seeds,
        Tracer::color_buffer(&gpu, w, h),
    )
    .expect("tracer");
    tracer.enable_motion(&gpu, &pipelines, &motion);
    let mut vis = vec![UVec2::ZERO; n];
    write_visibility(&previous, &mut vis);
    // The same frame sliding rigidly: every pixel a hit moving (-1.25, 0.5)
    // px/frame, so the pixels off the border move rigidly (35 x 21 of 37 x 23).
    let sliding: Vec<GBufferGpu> = current
        .iter()
        .map(|g| {
            let mut g = *g;
            g.motion.x = -1.25;
            g.motion.y = 0.5;
            g.ids = UVec4::new(g.ids.x % 4, 0, 0, GBUFFER_HIT | GBUFFER_PREV_IN_FRONT);
            g
        })
        .collect();
    // The same at about 4 px/frame with parallax: each row 0.0625 px/frame
    // faster than the one above it, within the tolerance at that speed
    // (`kernels::motion::RIGID_WITHIN_PER_SPEED`), past the 0.05 floor.
    let parallax: Vec<GBufferGpu> = sliding
        .iter()
        .enumerate()
        .map(|(i, g)| {
            let mut g = *g;
            g.motion.x = -(4.0 + 0.0625 * (i as u32 / w) as f32);
            g
        })
        .collect();
    // An orbit's walls: the left half -1.25 px/frame, the right half -2.5;
    // rigid on both sides of the seam, but too far apart for one pan
    // offset (`kernels::pan_offset::moves_alike`).
    let turning: Vec<GBufferGpu> = sliding
        .iter()
        .enumerate()
        .map(|(i, g)| {
            let mut g = *g;
            g.motion.x = if i as u32 % w < w / 2 { -1.25 } else { -2.5 };
            g
        })
        .collect();
    assert_eq!(gpu_tracer::motion::rigid_pixels(&turning, w, h), 33 * 21);
    assert_eq!(gpu_tracer::motion::rigid_pixels(&current, w, h), 0);
    assert_eq!(gpu_tracer::motion::rigid_pixels(&sliding, w, h), 35 * 21);
    assert_eq!(gpu_tracer::motion::rigid_pixels(&parallax, w, h), 35 * 21);
    // (hold below, follow share, frame): every seed follows; the slow half of
    // the pixels hold; the same with a share no random frame reaches; a
    // sliding frame past its share (every seed follows whatever the speed)
    // and short of it (every seed holds); the frame with parallax the same.
    let cases = [
        (0.0f32, 0.0f32, &current),
        (2.5, 0.0, &current),
        (2.5, 0.3, &current),
        (100.0, 0.85, &sliding),
        (100.0, 0.87, &sliding),
        (100.0, 0.85, &parallax),
        (100.0, 0.87, &parallax),
        (100.0, 0.75, &turning),
    ];
    // The CPU's pan offset (`kernels::pan_offset`), advanced as the GPU's
    // pan-offset pass advances it at every call with a share above 0.
    let mut offset = [0u32; 2];
    let mut followed_frames = 0;
    for (hold_below, share, frame) in cases {
        let mut p = params;
        p.seed_hold_below = hold_below;
        p.seed_follow_share = share;
        tracer.set_params(&gpu, &p);
        let mut words = [0u32; FRAME_CLEARED_WORDS];
        for g in [&previous, frame] {
            gpu.queue
                .write_buffer(&tracer.gbuffer, 0, bytemuck::cast_slice(g));
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            tracer.encode_motion(&mut encoder, &pipelines, None);
            gpu.queue.submit([encoder.finish()]);
            if share > 0.0 {
                words = gpu_tracer::motion::frame_motion_words(g, w, h);
                let next = kernels::pan_offset::advance_offset(offset, &words, w * h, share);
                followed_frames += usize::from(next != offset);
                offset = next;
            }
        }
        let gpu_words = tracer.read_frame_motion(&gpu).unwrap();
        let case = format!("hold below {hold_below}, share {share}");
        if share > 0.0 {
            assert_eq!(
                gpu_words[..FRAME_CLEARED_WORDS],
                words,
                "{case}: rigid count and motion sums"
            );
        }
        assert_eq!(gpu_words[FRAME_CLEARED_WORDS..], offset, "{case}: pan offset");
        let got: Vec<Vec2> = gpu.read(&motion, n).unwrap();
        let expected = seed_reprojection_motion(frame, &vis, w, h, hold_below, share);
        for (i, (g, e)) in got.iter().zip(&expected).enumerate() {
            assert!(
                g.x.to_bits() == e[0].to_bits() && g.y.to_bits() == e[1].to_bits(),
                "{case}: pixel {i}: GPU {g:?}, CPU {e:?}"
            );
        }
        let plain = reprojection_motion(frame, &vis, w, h);
        let changed = expected.iter().zip(&plain).filter(|(e, p)| e != p).count();
        match (hold_below, share) {
            (0.0, _) => {
                assert_eq!(expected, plain);
                let gone = kernels::motion::DISOCCLUDED.to_array();
                let disoccluded = expected.iter().filter(|m| **m == gone).count();
                assert!(
                    disoccluded > n / 10 && disoccluded < n * 9 / 10,
                    "{disoccluded} of {n} NaN"
                );
            }
            (_, 0.85) => assert_eq!(changed, 0, "{case}: the sliding frame did not follow"),
            (_, 0.87) => assert!(expected.iter().all(|m| *m == [0.0, 0.0]), "{case}"),
            (_, 0.75) => assert_eq!(changed, 0, "{case}: the turning frame did not follow"),
            _ => assert!(
                changed > n / 10 && changed < n * 9 / 10,
                "{case}: {changed} of {n} held"
            ),
        }
    }
    // The sliding frames past their share moved the offset, once each; the
    // turning frame followed as a whole but left the offset where it was.
    assert_eq!(followed_frames, 2, "frames that advanced the pan offset");
}

/// A 24x20 job of 4 frames at depth 3 (no Russian roulette) with `sampler`,
/// `mode` and `tile`, salt 3.
fn pan_job(
    sampler: u32,
    mode: gpu_tracer::PermuteMode,
    tile: gpu_tracer::TileChoice,
) -> gpu_tracer::RenderJob {
    let mut settings = gpu_tracer::TraceSettings::new(24, 20);
    settings.max_depth = 3;
    settings.sampler = sampler;
    gpu_tracer::RenderJob {
        settings,
        frames: 4,
        mode,
        block: 4,
        tile,
        salt: 3,
    }
}

/// Camera speed of the pans, units a frame: about 0.9 px/frame at the
/// centre of the 24x20 frame.
const PAN_SPEED: f32 = 1.5;

/// A faster pan, about 1.8 px/frame at the centre: fast enough for the
/// frame-wide follow rule (pixels of at least 1 px/frame) and the pan offset.
const FAST_PAN_SPEED: f32 = 3.0;

/// The Cornell box with the camera panning `speed` units a frame.
fn pan_sequence(speed: f32) -> gpu_tracer::timeline::SceneSequence<'static> {
    use gpu_tracer::camera_path::{CameraPath, CameraPathKind};
    use gpu_tracer::timeline::{SceneSequence, Timeline};
    let timeline = Timeline {
        camera_path: Some(CameraPath {
            kind: CameraPathKind::Pan,
            speed,
        }),
        ..Timeline::still()
    };
    SceneSequence::new(&gpu_tracer::cornell::cornell_box(), timeline, 20).unwrap()
}

/// The frames of `job` on the Cornell box with the camera panning `speed`
/// units a frame ([`pan_sequence`]), on `gpu` or, with `None`, on the CPU
/// (`render_sequence_gpu`, `render_sequence_cpu`).
fn pan_frames(
    gpu: Option<&Gpu>,
    job: &gpu_tracer::RenderJob,
    options: gpu_tracer::render::SequenceOptions,
    speed: f32,
) -> Vec<Vec<glam::Vec4>> {
    use gpu_tracer::render::{render_sequence_cpu, render_sequence_gpu, FrameView};
    let mut sequence = pan_sequence(speed);
    let mut frames = Vec::new();
    let mut collect = |f: &FrameView<'_>| frames.push(f.color.to_vec());
    match gpu {
        Some(gpu) => {
            render_sequence_gpu(gpu, &mut sequence, job, options, |_| {}, Some(&mut collect)).unwrap()
        }
        None => render_sequence_cpu(&mut sequence, job, options, collect).unwrap(),
    };
    frames
}

/// A panning sequence on the GPU (the temporal permutation with
/// reprojection): with `reproject_hold_below` above every surface's speed
/// the frames equal those of no reprojection, bit for bit (the motion pass
/// wrote zero motion, so the reprojection is the identity); at 0 they
/// differ from them. The threshold reaches the GPU's motion pass through
/// `TraceParams::seed_hold_below`.
#[test]
fn slow_surfaces_keep_their_seeds_on_the_gpu() {
    use gpu_tracer::render::SequenceOptions;
    let Some(gpu) = Gpu::for_test("slow_surfaces_keep_their_seeds_on_the_gpu") else {
        return;
    };
    let job = pan_job(
        kernels::abi::SAMPLER_SEEDS,
        gpu_tracer::PermuteMode::Temporal,
        gpu_tracer::TileChoice::TEMPORAL,
    );
    let render = |reproject: bool, hold_below: f32| {
        let options = SequenceOptions {
            reproject,
            reproject_hold_below: hold_below,
            ..SequenceOptions::default()
        };
        pan_frames(Some(&gpu), &job, options, PAN_SPEED)
    };
    let still_seeds = render(false, 0.0);
    let followed = render(true, 0.0);
    assert_eq!(still_seeds.len(), 4);
    assert_ne!(followed[3], still_seeds[3], "reprojection moved no seed");
    assert!(render(true, 100.0) == still_seeds, "held seeds moved on the GPU");
}

/// ZSobol's homes on the GPU (`--mode hold --sampler zsobol`, a pan with
/// reprojection): the frames agree with the CPU's pixel for pixel up to
/// float rounding (so the GPU moves the homes and reads ZSobol's point at
/// them as the CPU does), and differ from those of homes left at their
/// pixels.
#[test]
fn zsobol_homes_follow_a_pan_on_the_gpu_as_on_the_cpu() {
    use gpu_tracer::render::SequenceOptions;
    let Some(gpu) = Gpu::for_test("zsobol_homes_follow_a_pan_on_the_gpu_as_on_the_cpu") else {
        return;
    };
    let job = pan_job(
        kernels::abi::SAMPLER_ZSOBOL,
        gpu_tracer::PermuteMode::Hold,
        gpu_tracer::TileChoice::Tile64,
    );
    let options = |reproject: bool| SequenceOptions {
        reproject,
        ..SequenceOptions::default()
    };
    let cpu_frames = pan_frames(None, &job, options(true), PAN_SPEED);
    let followed = pan_frames(Some(&gpu), &job, options(true), PAN_SPEED);
    assert_eq!(followed.len(), 4);
    let (frac, total) = crate::fraction_close(&cpu_frames, &followed);
    eprintln!(
        "zsobol homes: {:.2}% of {total} pixel-frames equal within 1e-3",
        100.0 * frac
    );
    assert_eq!(total, 24 * 20 * 4);
    assert!(frac > 0.95, "only {:.2}% of pixel-frames agree", 100.0 * frac);
    let still_homes = pan_frames(Some(&gpu), &job, options(false), PAN_SPEED);
    assert_ne!(followed[3], still_homes[3], "the homes did not move on the GPU");
}

/// The render defaults in a pan (`--mode temporal --sampler zsobol-jitter`,
/// reprojection with the frame-wide follow rule at a share of 0.1),
/// panning about 1.8 px/frame: the pan moves the frames rigidly enough
/// that they follow and the pan offset moves ZSobol's
/// points (checked on the CPU's G-buffers), and the GPU's frames agree
/// with the CPU's pixel for pixel up to float rounding (so the GPU advances
/// the offset and the trace reads it as the CPU does); without the offset
/// the frames differ, and agree again between the GPU and the CPU.
#[test]
fn zsobol_follows_a_pan_on_the_gpu_as_on_the_cpu() {
    use gpu_tracer::method_choice::DEFAULT_PERMUTE_SAMPLER;
    use gpu_tracer::render::SequenceOptions;
    use kernels::pan_offset::{advance_offset, offset_pixels};
    let Some(gpu) = Gpu::for_test("zsobol_follows_a_pan_on_the_gpu_as_on_the_cpu") else {
        return;
    };
    let job = pan_job(
        DEFAULT_PERMUTE_SAMPLER,
        gpu_tracer::PermuteMode::Temporal,
        gpu_tracer::TileChoice::TEMPORAL,
    );
    // A share this small frame reaches: at 24x20 the walls' parallax
    // between neighbouring pixels keeps most of them from moving rigidly.
    let share = 0.1;
    let options = SequenceOptions {
        reproject: true,
        reproject_follow_share: share,
        pan_offset: true,
        ..SequenceOptions::default()
    };
    // The offset the CPU's G-buffers give, frame by frame.
    let gbuffers = pan_gbuffers(&job, options, FAST_PAN_SPEED);
    let (w, h) = (job.settings.width, job.settings.height);
    let mut offset = [0u32; 2];
    for g in &gbuffers {
        let words = gpu_tracer::motion::frame_motion_words(g, w, h);
        offset = advance_offset(offset, &words, w * h, share);
    }
    let moved = [offset_pixels(offset[0]) as i32, offset_pixels(offset[1]) as i32];
    eprintln!("pan offset after {} frames: {moved:?} px", gbuffers.len());
    assert_ne!(moved, [0, 0], "the pan never moved ZSobol's points");
    let cpu_frames = pan_frames(None, &job, options, FAST_PAN_SPEED);
    let gpu_frames = pan_frames(Some(&gpu), &job, options, FAST_PAN_SPEED);
    let (frac, total) = crate::fraction_close(&cpu_frames, &gpu_frames);
    eprintln!(
        "defaults in a pan: {:.2}% of {total} pixel-frames equal within 1e-3",
        100.0 * frac
    );
    assert_eq!(total, 24 * 20 * 4);
    assert!(frac > 0.95, "only {:.2}% of pixel-frames agree", 100.0 * frac);
    // Without the pan offset ZSobol stays on the screen: other frames, and
    // the GPU (which then leaves the parameters' offset at 0) agrees.
    let screen = SequenceOptions {
        pan_offset: false,
        ..options
    };
    let cpu_screen = pan_frames(None, &job, screen, FAST_PAN_SPEED);
    assert_ne!(cpu_screen[3], cpu_frames[3], "the pan offset changed nothing");
    let gpu_screen = pan_frames(Some(&gpu), &job, screen, FAST_PAN_SPEED);
    let (frac, _) = crate::fraction_close(&cpu_screen, &gpu_screen);
    assert!(frac > 0.95, "without the offset only {:.2}% agree", 100.0 * frac);
}

/// The G-buffers of [`pan_frames`]' sequence at `speed`, rendered on the CPU.
fn pan_gbuffers(
    job: &gpu_tracer::RenderJob,
    options: gpu_tracer::render::SequenceOptions,
    speed: f32,
) -> Vec<Vec<kernels::abi::GBufferGpu>> {
    use gpu_tracer::render::{render_sequence_cpu, FrameView, SequenceOptions};
    let mut sequence = pan_sequence(speed);
    let mut gbuffers = Vec::new();
    let mut collect = |f: &FrameView<'_>| gbuffers.push(f.gbuffer.expect("G-buffer requested").to_vec());
    let options = SequenceOptions {
        gbuffer: true,
        ..options
    };
    render_sequence_cpu(&mut sequence, job, options, &mut collect).unwrap();
    gbuffers
}
