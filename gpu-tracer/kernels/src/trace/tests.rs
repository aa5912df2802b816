//! Tests of the path tracer ([`super`]).

use super::*;
use crate::abi::{
    SAMPLER_JITTER_ONLY, SAMPLER_SCREEN_SOBOL, SAMPLER_SEEDS, SAMPLER_ZSOBOL, SEED_MODE_ADVANCE,
};
use glam::Vec2;
use sampler_core::sequences::screen_sobol::ScreenSobolLayout;

#[test]
fn stream_sample_modes() {
    let mut p = TraceParams {
        spp: 4,
        frame: 3,
        ..Default::default()
    };
    assert_eq!(stream_sample(&p, 2), 2);
    p.seed_mode = SEED_MODE_ADVANCE;
    assert_eq!(stream_sample(&p, 2), 14);
    p.seed_mode = 7;
    assert_eq!(stream_sample(&p, 2), 2);
}

/// A diffuse floor (y = 0, albedo 0.5) under an emitter covering the
/// half-plane x > 0 at y = 1 (facing down, emission 1), seen from above
/// the floor at x = 0; no emitter list, so light arrives only through
/// vertex 0's BSDF direction: each sample is 0 or 0.5.
struct HalfLit {
    nodes: [BvhNodeGpu; 1],
    triangles: [TriangleGpu; 2],
    materials: [MaterialGpu; 2],
    emitters: [EmitterGpu; 1],
    attrs: [TriangleAttrGpu; 2],
}

fn half_lit() -> HalfLit {
    let floor = TriangleGpu {
        v0: Vec4::new(-100.0, 0.0, -100.0, 0.0),
        v1: Vec4::new(-100.0, 0.0, 200.0, 0.0),
        v2: Vec4::new(200.0, 0.0, -100.0, 0.0),
    };
    let light = TriangleGpu {
        v0: Vec4::new(0.0, 1.0, -100.0, 1.0),
        v1: Vec4::new(100.0, 1.0, 0.0, 0.0),
        v2: Vec4::new(0.0, 1.0, 100.0, 0.0),
    };
    HalfLit {
        nodes: [BvhNodeGpu {
            min: Vec4::new(-100.0, 0.0, -100.0, 0.0),
            max: Vec4::new(200.0, 1.0, 200.0, 0.0),
            info: glam::UVec4::new(2, 0, 0, 0),
        }],
        triangles: [floor, light],
        materials: [
            MaterialGpu::untextured(Vec4::new(0.5, 0.5, 0.5, 0.0), Vec4::ZERO),
            MaterialGpu::untextured(Vec4::ZERO, Vec4::new(1.0, 1.0, 1.0, 0.0)),
        ],
        emitters: [EmitterGpu::NONE],
        attrs: [TriangleAttrGpu::default(); 2],
    }
}

fn half_lit_params(sampler: u32, spp: u32, frame: u32) -> TraceParams {
    TraceParams {
        width: 16,
        height: 16,
        padded_width: 16,
        spp,
        max_depth: 2,
        frame,
        triangle_count: 2,
        node_count: 1,
        rr_depth: 3,
        tan_half_fov_y: 0.2,
        camera_origin: Vec4::new(0.0, 0.5, 0.0, 0.0),
        camera_forward: Vec4::new(0.0, -1.0, 0.0, 0.0),
        camera_right: Vec4::X,
        camera_up: Vec4::Z,
        sampler,
        key_side_log2: 2,
        key_pairs: 1,
        key_levels: 3,
        ..Default::default()
    }
}

fn test_keys() -> [u32; 48] {
    core::array::from_fn(|i| sampler_core::sequences::seed::hash_u32(i as u32 ^ 0x5bd1_e995))
}

fn render(
    scene: &HalfLit,
    params: &TraceParams,
    keys: &[u32],
    seed_of: impl Fn(u32, u32) -> u32,
) -> [f32; 256] {
    core::array::from_fn(|i| {
        let (x, y) = (i as u32 % 16, i as u32 / 16);
        trace_pixel(
            params,
            UVec2::new(x, y),
            seed_of(x, y),
            keys,
            &scene.nodes,
            &scene.triangles,
            &scene.materials,
            &scene.emitters,
            &scene.attrs,
            &[0],
            &[0.0],
        )
        .x
    })
}

/// With an a-priori sampler every decision of these paths (depth 2, no
/// Russian roulette) comes from the sampler: the image does not depend
/// on the seeds, differs from the seed stream's, and equals the mean of
/// `spp` samples built from `PathNumbers::new`.
#[test]
fn apriori_samplers_drive_every_pair() {
    let scene = half_lit();
    let keys = test_keys();
    let seed_of = |x: u32, y: u32| sampler_core::initial_seed(x, y, 16, 7);
    let other_seed_of = |x: u32, y: u32| sampler_core::initial_seed(x, y, 16, 8);
    for spp in [1u32, 4] {
        let seeds_img = render(&scene, &half_lit_params(SAMPLER_SEEDS, spp, 3), &keys, seed_of);
        assert_ne!(
            seeds_img,
            render(
                &scene,
                &half_lit_params(SAMPLER_SEEDS, spp, 3),
                &keys,
                other_seed_of
            ),
            "the seed stream depends on the seeds"
        );
        for sampler in [SAMPLER_SCREEN_SOBOL, SAMPLER_ZSOBOL] {
            let params = half_lit_params(sampler, spp, 3);
            let img = render(&scene, &params, &keys, seed_of);
            assert_eq!(
                img,
                render(&scene, &params, &keys, other_seed_of),
                "sampler {sampler}"
            );
            let differing = img.iter().zip(&seeds_img).filter(|(a, b)| a != b).count();
            assert!(
                differing > 16,
                "sampler {sampler} spp {spp}: only {differing} pixels differ"
            );
            for (x, y) in [(0u32, 0u32), (5, 9), (15, 15)] {
                let pixel = UVec2::new(x, y);
                let mut sum = Vec3::ZERO;
                for s in 0..spp {
                    let numbers = PathNumbers::new(&params, pixel, seed_of(x, y), s);
                    assert_eq!(
                        numbers.jitter(&params, &keys),
                        apriori_pair(&params, &keys, pixel, s, 0)
                    );
                    assert_eq!(
                        numbers.bsdf(&params, &keys, 1),
                        apriori_pair(&params, &keys, pixel, s, pair_bsdf(1))
                    );
                    sum += trace_sample_with::<{ crate::trace_variant::FULL }>(
                        &params,
                        &keys,
                        numbers,
                        &scene.nodes,
                        &scene.triangles,
                        &scene.materials,
                        &scene.emitters,
                        &scene.attrs,
                        &[0],
                        &[0.0],
                        &mut 0,
                    );
                }
                assert_eq!(
                    img[(y * 16 + x) as usize],
                    (sum / spp as f32).x,
                    "pixel ({x}, {y})"
                );
            }
        }
        // Unknown sampler values fall back to the seed stream.
        assert_eq!(
            render(&scene, &half_lit_params(9, spp, 3), &keys, seed_of),
            seeds_img
        );
    }
}

/// With [`SAMPLER_JITTER_ONLY`] the jitter is the sampler's pair 0 (not
/// the stream's) and every other pair the seed stream's: the image
/// depends on the seeds and differs from the full sampler's.
#[test]
fn jitter_only_takes_pair_zero_from_the_sampler() {
    let scene = half_lit();
    let keys = test_keys();
    let seed_of = |x: u32, y: u32| sampler_core::initial_seed(x, y, 16, 7);
    let other_seed_of = |x: u32, y: u32| sampler_core::initial_seed(x, y, 16, 8);
    for sampler in [SAMPLER_SCREEN_SOBOL, SAMPLER_ZSOBOL] {
        let params = half_lit_params(sampler | SAMPLER_JITTER_ONLY, 1, 3);
        let full = half_lit_params(sampler, 1, 3);
        let seeds = half_lit_params(SAMPLER_SEEDS, 1, 3);
        for (x, y) in [(0u32, 0u32), (5, 9), (15, 15)] {
            let pixel = UVec2::new(x, y);
            let numbers = PathNumbers::new(&params, pixel, seed_of(x, y), 0);
            let stream = PathNumbers::new(&seeds, pixel, seed_of(x, y), 0);
            assert_eq!(
                numbers.jitter(&params, &keys),
                apriori_pair(&full, &keys, pixel, 0, PAIR_JITTER)
            );
            assert_ne!(numbers.jitter(&params, &keys), stream.jitter(&seeds, &keys));
            assert_stream_pairs((&numbers, &params), (&stream, &seeds), &keys, 0..3);
        }
        let img = render(&scene, &params, &keys, seed_of);
        assert_ne!(
            img,
            render(&scene, &params, &keys, other_seed_of),
            "sampler {sampler}"
        );
        assert_ne!(img, render(&scene, &full, &keys, seed_of), "sampler {sampler}");
    }
    // Screen-space Sobol reads the key buffer: other keys, other image.
    let params = half_lit_params(SAMPLER_SCREEN_SOBOL, 1, 0);
    let other: [u32; 48] = core::array::from_fn(|i| keys[(i + 1) % 48]);
    assert_ne!(
        render(&scene, &params, &keys, seed_of),
        render(&scene, &params, &other, seed_of)
    );
}

/// `numbers` (under its parameters) reads the same light and BSDF pairs as
/// the seed-stream `stream` at every vertex of `depths`.
fn assert_stream_pairs(
    (numbers, params): (&PathNumbers, &TraceParams),
    (stream, seeds): (&PathNumbers, &TraceParams),
    keys: &[u32],
    depths: core::ops::Range<u32>,
) {
    for depth in depths {
        assert_eq!(
            numbers.light(params, keys, depth),
            stream.light(seeds, keys, depth)
        );
        assert_eq!(numbers.bsdf(params, keys, depth), stream.bsdf(seeds, keys, depth));
    }
}

/// At a sharp first hit, the jitter-only scope takes vertex 0's light and
/// BSDF pairs from the sampler too, and nothing else; without one the
/// stream's pairs stay; the full scope is not affected.
#[test]
fn a_sharp_first_hit_takes_vertex_zeros_pairs_from_the_sampler() {
    let keys = test_keys();
    for sampler in [SAMPLER_SCREEN_SOBOL, SAMPLER_ZSOBOL] {
        let params = half_lit_params(sampler | SAMPLER_JITTER_ONLY, 1, 3);
        let full = half_lit_params(sampler, 1, 3);
        let seeds = half_lit_params(SAMPLER_SEEDS, 1, 3);
        let pixel = UVec2::new(5, 9);
        let seed = sampler_core::initial_seed(5, 9, 16, 7);
        let stream = PathNumbers::new(&seeds, pixel, seed, 0);
        let mut numbers = PathNumbers::new(&params, pixel, seed, 0);
        // A later vertex cannot mark the first hit.
        numbers.set_sharp_first_hit(1, 1);
        assert_eq!(numbers.light(&params, &keys, 0), stream.light(&seeds, &keys, 0));
        assert_eq!(numbers.bsdf(&params, &keys, 0), stream.bsdf(&seeds, &keys, 0));
        numbers.set_sharp_first_hit(0, 1);
        assert_eq!(
            numbers.light(&params, &keys, 0),
            apriori_pair(&full, &keys, pixel, 0, pair_light(0))
        );
        assert_eq!(
            numbers.bsdf(&params, &keys, 0),
            apriori_pair(&full, &keys, pixel, 0, pair_bsdf(0))
        );
        assert_ne!(numbers.bsdf(&params, &keys, 0), stream.bsdf(&seeds, &keys, 0));
        assert_stream_pairs((&numbers, &params), (&stream, &seeds), &keys, 1..3);
        assert_eq!(
            numbers.roulette(&params, &keys, 3),
            stream.roulette(&seeds, &keys, 3)
        );
        numbers.set_sharp_first_hit(0, 0);
        assert_eq!(numbers.bsdf(&params, &keys, 0), stream.bsdf(&seeds, &keys, 0));
        // The full scope reads the sampler either way.
        let mut all = PathNumbers::new(&full, pixel, seed, 0);
        let before = all.bsdf(&full, &keys, 2);
        all.set_sharp_first_hit(0, 1);
        assert_eq!(all.bsdf(&full, &keys, 2), before);
    }
}

/// Degenerate key layouts never panic: a 1x1 key tile (`key_side_log2`
/// 0) with any frame reads key 0 for every pixel.
#[test]
fn screen_sobol_with_a_one_texel_tile_does_not_overflow() {
    let keys = [0x1234_5678u32; 3];
    let p = TraceParams {
        key_side_log2: 0,
        frame: 0xFFFF_FFF0,
        ..half_lit_params(SAMPLER_SCREEN_SOBOL, 1, 0)
    };
    let a = apriori_pair(&p, &keys, UVec2::new(u32::MAX, 7), 0, 0);
    assert_eq!(a, apriori_pair(&p, &keys, UVec2::new(0, 0), 0, 0));
    assert!((0.0..1.0).contains(&a.x) && (0.0..1.0).contains(&a.y));
}

/// With `SAMPLER_FOLLOW_HOMES` the spatiotemporal sampler and ZSobol read
/// their per-pixel data at the home the seed-buffer entry names, so a
/// pixel's jitter is the home pixel's; without the flag, and for the other
/// samplers, at the pixel itself.
#[test]
fn homes_move_the_zsobol_and_spatiotemporal_points() {
    use crate::abi::{sampler_reads_homes, SAMPLER_FOLLOW_HOMES, SAMPLER_SPATIOTEMPORAL};
    use sampler_core::sequences::spatiotemporal::home_of_pixel;
    let keys = test_keys();
    let (pixel, home) = (UVec2::new(5, 9), UVec2::new(12, 3));
    let seed = home_of_pixel(home.x, home.y);
    for sampler in [
        SAMPLER_SEEDS,
        SAMPLER_SCREEN_SOBOL,
        SAMPLER_ZSOBOL,
        SAMPLER_SPATIOTEMPORAL,
    ] {
        let plain = half_lit_params(sampler, 1, 6);
        let homes = TraceParams {
            sampler: sampler | SAMPLER_FOLLOW_HOMES,
            ..plain
        };
        let follows = sampler == SAMPLER_ZSOBOL || sampler == SAMPLER_SPATIOTEMPORAL;
        assert_eq!(sampler_position(&plain, pixel, seed), pixel, "sampler {sampler}");
        let want = if follows { home } else { pixel };
        assert_eq!(sampler_position(&homes, pixel, seed), want, "sampler {sampler}");
        assert_eq!(sampler_reads_homes(sampler), follows, "sampler {sampler}");
        if follows {
            let jitter = PathNumbers::new(&homes, pixel, seed, 0).jitter(&homes, &keys);
            assert_eq!(jitter, apriori_pair(&plain, &keys, home, 0, PAIR_JITTER));
            // (The test keys hold no spatiotemporal shift tile worth telling apart.)
            if sampler == SAMPLER_ZSOBOL {
                assert_ne!(jitter, apriori_pair(&plain, &keys, pixel, 0, PAIR_JITTER));
            }
        }
    }
}

/// The pair layout: jitter 0, then light and BSDF of each vertex.
#[test]
fn apriori_pair_layout() {
    assert_eq!(PAIR_JITTER, 0);
    assert_eq!(
        (pair_light(0), pair_bsdf(0), pair_light(1), pair_bsdf(1)),
        (1, 2, 3, 4)
    );
}

/// `apriori_pair` returns the sampler-core samplers' values for the
/// documented indices, for optimised and padded pairs.
#[test]
fn apriori_pair_matches_sampler_core() {
    let keys = test_keys();
    let layout = ScreenSobolLayout::new(4, 1, 3).unwrap();
    for (spp, frame, s) in [(1u32, 0u32, 0u32), (2, 5, 1), (4, 2, 3), (3, 1, 2)] {
        for pixel in [UVec2::new(0, 0), UVec2::new(6, 3), UVec2::new(1023, 77)] {
            for pair in [0u32, 1, 5] {
                let p = TraceParams {
                    frame,
                    ..half_lit_params(SAMPLER_SCREEN_SOBOL, spp, 0)
                };
                let d = 2 * pair;
                let at = pixel + sampler_core::walk_offset(frame, p.key_side_log2);
                let want = Vec2::new(
                    sampler_core::sequences::screen_sobol::screen_sobol_sample(&keys, layout, spp, at, s, d),
                    sampler_core::sequences::screen_sobol::screen_sobol_sample(
                        &keys,
                        layout,
                        spp,
                        at,
                        s,
                        d + 1,
                    ),
                );
                assert_eq!(apriori_pair(&p, &keys, pixel, s, pair), want);
                let p = TraceParams {
                    sampler: SAMPLER_ZSOBOL,
                    ..p
                };
                let log2 = 32 - (spp - 1).leading_zeros();
                let q = |d| {
                    sampler_core::sequences::r2::q32_to_f32(sampler_core::zsobol_frame_sample_u32(
                        pixel, s, d, log2, frame,
                    ))
                };
                let want = Vec2::new(q(d), q(d + 1));
                assert_eq!(apriori_pair(&p, &keys, pixel, s, pair), want);
            }
        }
    }
}

/// Screen-space Sobol: frame `t` reads the key tile shifted by the R2
/// walk offset `o_t`, and a pixel's samples of one frame (here 4 spp,
/// key level 2) form a (0, 2, 2)-net: one point in each elementary
/// interval of area 1/4.
#[test]
fn screen_sobol_frames_shift_the_keys_and_keep_the_net() {
    let keys = test_keys();
    let params = |frame: u32| half_lit_params(SAMPLER_SCREEN_SOBOL, 4, frame);
    for t in [1u32, 2, 7] {
        let o = sampler_core::walk_offset(t, params(t).key_side_log2);
        assert_ne!(o, UVec2::ZERO);
        for pixel in [UVec2::new(0, 0), UVec2::new(3, 1)] {
            for s in 0..4 {
                assert_eq!(
                    apriori_pair(&params(t), &keys, pixel, s, 1),
                    apriori_pair(&params(0), &keys, pixel + o, s, 1)
                );
            }
        }
    }
    for pixel in [UVec2::new(0, 0), UVec2::new(3, 1), UVec2::new(2, 2)] {
        let pts: [Vec2; 4] = core::array::from_fn(|s| apriori_pair(&params(5), &keys, pixel, s as u32, 0));
        for (nx, ny) in [(4.0f32, 1.0f32), (2.0, 2.0), (1.0, 4.0)] {
            let mut cells: [u32; 4] = pts.map(|p| (p.x * nx) as u32 * ny as u32 + (p.y * ny) as u32);
            cells.sort_unstable();
            assert_eq!(cells, [0, 1, 2, 3], "pixel {pixel} {pts:?}");
        }
    }
}

/// The samplers' origin moves where every a-priori sampler reads its
/// per-pixel data, homes and ZSobol's pan offset included, by wrapping
/// adds: a pixel's numbers under origin `o` are those of pixel `p + o`
/// under origin 0.
#[test]
fn the_origin_moves_every_samplers_data() {
    use crate::abi::{SAMPLER_FOLLOW_HOMES, SAMPLER_KRONECKER, SAMPLER_SPATIOTEMPORAL};
    use sampler_core::sequences::spatiotemporal::home_of_pixel;
    let keys = test_keys();
    let (pixel, home) = (UVec2::new(5, 9), UVec2::new(12, 3));
    let origin = UVec2::new(4093, 70);
    let moved = |p: UVec2| UVec2::new(p.x.wrapping_add(origin.x), p.y.wrapping_add(origin.y));
    for (sampler, at) in [
        (SAMPLER_SCREEN_SOBOL, pixel),
        (SAMPLER_ZSOBOL, pixel),
        (SAMPLER_SPATIOTEMPORAL, pixel),
        (SAMPLER_SPATIOTEMPORAL | SAMPLER_KRONECKER, pixel),
        (SAMPLER_ZSOBOL | SAMPLER_FOLLOW_HOMES, home),
        (SAMPLER_SPATIOTEMPORAL | SAMPLER_FOLLOW_HOMES, home),
    ] {
        let plain = half_lit_params(sampler, 1, 6);
        let drawn = TraceParams {
            sampler_origin_x: origin.x,
            sampler_origin_y: origin.y,
            ..plain
        };
        let seed = home_of_pixel(home.x, home.y);
        assert_eq!(sampler_position(&plain, pixel, seed), at, "sampler {sampler}");
        assert_eq!(
            sampler_position(&drawn, pixel, seed),
            moved(at),
            "sampler {sampler}"
        );
        let jitter = PathNumbers::new(&drawn, pixel, seed, 0).jitter(&drawn, &keys);
        assert_eq!(
            jitter,
            apriori_pair(&plain, &keys, moved(at), 0, PAIR_JITTER),
            "sampler {sampler}"
        );
    }
    // With ZSobol's pan offset both add.
    let panned = TraceParams {
        sampler_offset_x: -40i32 as u32,
        sampler_offset_y: 24,
        sampler_origin_x: origin.x,
        sampler_origin_y: origin.y,
        ..half_lit_params(SAMPLER_ZSOBOL, 1, 6)
    };
    let no_origin = TraceParams {
        sampler_origin_x: 0,
        sampler_origin_y: 0,
        ..panned
    };
    assert_eq!(
        sampler_position(&panned, pixel, 0),
        moved(sampler_position(&no_origin, pixel, 0))
    );
}
