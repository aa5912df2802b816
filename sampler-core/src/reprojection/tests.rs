//! Tests of [`reproject_frame`] as a whole and of each of its paths
//! against the first version, kept here as `reproject_reference`.

use crate::error::{Buffer, Error};
use crate::permutation::layout::{FrameLayout, FrameParams};
use crate::reprojection::ring::RING_WORDS;
use crate::reprojection::sweep::{fused_body, reproject_fused, FUSED_SPAN};
use crate::reprojection::two_sweeps::{assign_by_pixels, assign_by_sources, claim_all};
use crate::reprojection::*;

fn layout(w: u32, h: u32) -> FrameLayout {
    FrameLayout::new(w, h, 4, 16).unwrap()
}

fn run(l: &FrameLayout, motion: &[[f32; 2]]) -> alloc_free::Out {
    let n = l.seed_count();
    let mut out = alloc_free::Out::new(n);
    let seeds = alloc_free::Out::iota(n);
    let mut claims = alloc_free::Out::new(n);
    out.stats = reproject_frame(
        l,
        motion,
        seeds.as_slice(),
        claims.as_mut_slice(),
        out.as_mut_slice(),
    )
    .unwrap();
    out
}

/// Fixed-capacity buffers: this crate is `no_std` without `alloc` in tests too.
mod alloc_free {
    pub const CAP: usize = 64 * 64;
    pub struct Out {
        pub data: [u32; CAP],
        pub len: usize,
        pub stats: super::ReprojectStats,
    }
    impl Out {
        pub fn new(len: usize) -> Self {
            assert!(len <= CAP);
            Out {
                data: [0; CAP],
                len,
                stats: Default::default(),
            }
        }
        pub fn iota(len: usize) -> Self {
            let mut o = Self::new(len);
            for (i, v) in o.data[..len].iter_mut().enumerate() {
                *v = i as u32 * 7 + 3;
            }
            o
        }
        pub fn as_slice(&self) -> &[u32] {
            &self.data[..self.len]
        }
        pub fn as_mut_slice(&mut self) -> &mut [u32] {
            &mut self.data[..self.len]
        }
    }
}

fn is_permutation(out: &[u32]) -> bool {
    let mut seen = [false; alloc_free::CAP];
    out.iter().all(|&s| {
        let i = ((s - 3) / 7) as usize;
        (s - 3) % 7 == 0 && i < out.len() && !core::mem::replace(&mut seen[i], true)
    })
}

#[test]
fn zero_motion_is_the_identity() {
    let l = layout(20, 13);
    let motion = [[0.0f32; 2]; 20 * 13];
    let out = run(&l, &motion);
    assert_eq!(out.as_slice(), alloc_free::Out::iota(l.seed_count()).as_slice());
    assert_eq!(
        out.stats,
        ReprojectStats {
            followed: 260,
            recycled: 0
        }
    );
}

#[test]
fn a_uniform_shift_moves_seeds_and_recycles_the_uncovered_edge() {
    let l = layout(20, 13);
    // The picture moved 2 px right: every pixel's point was 2 px to its left.
    let motion = [[-2.0f32, 0.0]; 20 * 13];
    let out = run(&l, &motion);
    let seeds = alloc_free::Out::iota(l.seed_count());
    let pw = l.padded_width() as usize;
    for y in 0..13 {
        for x in 2..20 {
            assert_eq!(out.as_slice()[y * pw + x], seeds.as_slice()[y * pw + x - 2]);
        }
    }
    assert_eq!(
        out.stats,
        ReprojectStats {
            followed: 18 * 13,
            recycled: 2 * 13
        }
    );
    assert!(is_permutation(out.as_slice()));
}

#[test]
fn adversarial_fields_stay_permutations() {
    let l = layout(23, 17);
    let n = 23 * 17;
    let mut motion = [[0.0f32; 2]; 23 * 17];
    let fields: [fn(u32, u32) -> [f32; 2]; 6] = [
        |x, y| [11.0 - x as f32, 8.0 - y as f32], // all to one source
        |_, _| [f32::NAN, f32::NAN],              // nothing valid
        |x, y| [(y as f32 - 8.0) * 0.3, -(x as f32 - 11.0) * 0.3], // rotation
        |x, y| [(x as f32 - 11.0) * -0.5, (y as f32 - 8.0) * -0.5], // zoom
        |x, _| [if x % 3 == 0 { f32::INFINITY } else { 0.4 }, -0.6],
        |x, y| [1e30 * (x as f32 - y as f32), 0.0],
    ];
    for field in fields {
        for (i, m) in motion.iter_mut().enumerate().take(n) {
            *m = field(i as u32 % 23, i as u32 / 23);
        }
        let out = run(&l, &motion);
        assert!(is_permutation(out.as_slice()));
        assert_eq!(out.stats.followed + out.stats.recycled, n as u32);
    }
}

#[test]
fn bad_buffers_are_errors() {
    let l = layout(8, 8);
    let n = l.seed_count();
    let seeds = alloc_free::Out::iota(n);
    let mut out = alloc_free::Out::new(n);
    let mut claims = alloc_free::Out::new(n);
    let motion = [[0.0f32; 2]; 63];
    assert!(matches!(
        reproject_frame(
            &l,
            &motion,
            seeds.as_slice(),
            claims.as_mut_slice(),
            out.as_mut_slice()
        ),
        Err(Error::BufferSize {
            buffer: Buffer::Motion,
            expected: 64,
            actual: 63
        })
    ));
}

/// The first version of [`reproject_frame`] (two sweeps over the motion
/// vectors, `take_if_won` per pixel), kept verbatim as the reference the
/// fast forms must equal bit for bit. Its keys are [`claim_at`]'s, so it
/// follows the quantisation wherever that changes.
fn reproject_reference(
    layout: &FrameLayout,
    motion: &[[f32; 2]],
    seeds_in: &[u32],
    claims: &mut [u32],
    seeds_out: &mut [u32],
) -> Result<ReprojectStats, Error> {
    let n = layout.seed_count();
    if n > MAX_REPROJECT_SEEDS {
        return Err(Error::FrameSize {
            width: layout.width(),
            height: layout.height(),
        });
    }
    layout.check_seed_buffer(Buffer::SeedsIn, seeds_in.len())?;
    layout.check_seed_buffer(Buffer::SeedsOut, seeds_out.len())?;
    layout.check_seed_buffer(Buffer::Claims, claims.len())?;
    if motion.len() != layout.pixel_count() {
        return Err(Error::BufferSize {
            buffer: Buffer::Motion,
            expected: layout.pixel_count(),
            actual: motion.len(),
        });
    }
    let params = layout.params(0);
    let bits = index_bits(params.padded_width * params.padded_height);
    let (w, h) = (params.width as usize, params.height as usize);
    let pw = params.padded_width as usize;
    // Claim: visible pixels take the minimum key per source; padding claims itself.
    claims.fill(CLAIM_NONE);
    for (y, row) in claims.chunks_exact_mut(pw).enumerate() {
        if y >= h {
            for (x, c) in row.iter_mut().enumerate() {
                *c = (y * pw + x) as u32;
            }
        } else {
            for (x, c) in row.iter_mut().enumerate().skip(w) {
                *c = (y * pw + x) as u32;
            }
        }
    }
    for y in 0..h {
        for x in 0..w {
            let (source, key) = claim_at(&params, bits, x as u32, y as u32, motion[y * w + x]);
            if source != CLAIM_NONE && key < claims[source as usize] {
                claims[source as usize] = key;
            }
        }
    }
    // Winners take their source's seed; the k-th pixel without a seed (in
    // buffer order) takes the k-th unclaimed source's seed. There are exactly
    // as many of each (module docs).
    let mut stats = ReprojectStats::default();
    let mut free = claims
        .iter()
        .enumerate()
        .filter(|(_, &c)| c == CLAIM_NONE)
        .map(|(q, _)| q);
    for (y, row) in seeds_out.chunks_exact_mut(pw).enumerate() {
        for (x, out) in row.iter_mut().enumerate() {
            if x >= w || y >= h {
                *out = seeds_in[y * pw + x]; // padding always wins its own seed
                continue;
            }
            let (source, key) = claim_at(&params, bits, x as u32, y as u32, motion[y * w + x]);
            if let Some(seed) = take_if_won(claims, seeds_in, source, key) {
                *out = seed;
                stats.followed += 1;
            } else {
                let q = free
                    .next()
                    .expect("as many unclaimed sources as pixels without a seed");
                *out = seeds_in[q];
                stats.recycled += 1;
            }
        }
    }
    Ok(stats)
}

/// A motion field for the comparison with the reference: `kind` picks
/// it, `(w, h)` the visible size, `i` the pixel's index.
fn field(kind: usize, x: u32, y: u32, w: u32, h: u32) -> [f32; 2] {
    let (xf, yf, cx, cy) = (x as f32, y as f32, w as f32 * 0.5, h as f32 * 0.5);
    // Small LCG over the pixel index and the field: random-ish fields.
    let mut z = u64::from(y * w + x + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ kind as u64;
    let mut rnd = || {
        z = z
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (z >> 40) as f32 / (1u64 << 24) as f32 // [0, 1)
    };
    match kind {
        0 => [0.0, 0.0],
        1 => [-2.0, 0.0],
        2 => [-0.7, 0.1],
        3 => [1.3, -2.6],
        4 => [-0.5, -0.5], // exactly on pixel corners: distance 0.5, the largest key
        5 => [0.0, 3.0],   // vertical: pixels at the top wait for sources at the bottom
        6 => [0.25, -5.5],
        7 => [(yf - cy) * 0.3, -(xf - cx) * 0.3],  // rotation
        8 => [(xf - cx) * -0.5, (yf - cy) * -0.5], // zoom in
        9 => [(xf - cx) * 0.7, (yf - cy) * 0.4],   // zoom out
        10 => [cx - xf, cy - yf],                  // all to one source
        11 if (x / 4 + y / 3).is_multiple_of(3) => [f32::NAN, f32::NAN], // disoccluded patches
        11 => [-0.7, 0.4],
        12 if x.is_multiple_of(3) => [f32::INFINITY, 0.0],
        12 => [0.4, -0.6],
        13 => [1e30 * (xf - yf), f32::NEG_INFINITY * (xf - 3.0)],
        14 => [rnd() * 6.0 - 3.0, rnd() * 6.0 - 3.0],
        15 if rnd() < 0.2 => [f32::NAN, 0.0],
        15 => [rnd() * 80.0 - 40.0, rnd() * 80.0 - 40.0],
        16 => [rnd() * 3.0 - 1.5, (rnd() * 4.0).floor() - 2.0],
        // Everything disoccluded but the last pixel, which lands exactly
        // on the first pixel's corner (the largest key when there is no
        // padding; it equalled CLAIM_NONE, and duplicated a seed, before
        // the distance levels stopped one short), with and without a
        // rival claim.
        17 | 18 if x == w - 1 && y == h - 1 => [0.5 - w as f32, 0.5 - h as f32],
        18 if x == 0 && y == 0 => [0.0, 0.0],
        _ => [f32::NAN, f32::NAN],
    }
}

const FIELDS: usize = 19;

type Fused = fn(
    &FrameParams,
    &[[f32; 2]],
    &[u32],
    &mut [u32],
    &mut [u32],
    usize,
    &mut [u64],
) -> Option<ReprojectStats>;

#[test]
fn every_path_equals_the_first_version() {
    // Padding on both axes or none, widths not a multiple of the batch,
    // 2^bits buffers without padding (16 x 16, 64 x 64), fewer than 256 seeds.
    let sizes = [
        (23, 17, 16),
        (1, 1, 16),
        (37, 5, 16),
        (16, 16, 16),
        (48, 48, 16),
        (64, 64, 16),
        (5, 3, 2),
        (20, 13, 4),
    ];
    let mut motion = [[0.0f32; 2]; alloc_free::CAP];
    let mut ring = [0u64; RING_WORDS];
    let (mut fused_runs, mut ring_runs) = (0, 0);
    for (w, h, tile) in sizes {
        let l = FrameLayout::new(w, h, 2, tile).unwrap();
        let params = l.params(0);
        let (n, pixels) = (l.seed_count(), l.pixel_count());
        let seeds = alloc_free::Out::iota(n);
        for kind in 0..FIELDS {
            for (i, m) in motion[..pixels].iter_mut().enumerate() {
                *m = field(kind, i as u32 % w, i as u32 / w, w, h);
            }
            let motion = &motion[..pixels];
            let mut expected = alloc_free::Out::new(n);
            let mut claims = alloc_free::Out::new(n);
            expected.stats = reproject_reference(
                &l,
                motion,
                seeds.as_slice(),
                claims.as_mut_slice(),
                expected.as_mut_slice(),
            )
            .unwrap();
            let check = |out: &alloc_free::Out, stats: ReprojectStats, path: &str| {
                assert_eq!(
                    out.as_slice(),
                    expected.as_slice(),
                    "{path}, {w}x{h}, field {kind}"
                );
                assert_eq!(stats, expected.stats, "{path}, {w}x{h}, field {kind}");
            };
            // Scratch starts as garbage: nothing may rely on its contents.
            let fresh = || {
                let mut c = alloc_free::Out::new(n);
                c.as_mut_slice().fill(0x5a5a_5a5a);
                (c, alloc_free::Out::new(n))
            };

            let (mut claims, mut out) = fresh();
            let stats = reproject_frame(
                &l,
                motion,
                seeds.as_slice(),
                claims.as_mut_slice(),
                out.as_mut_slice(),
            );
            check(&out, stats.unwrap(), "reproject_frame");

            let (mut claims, mut out) = fresh();
            let span = claim_all(&params, motion, claims.as_mut_slice());
            let stats = assign_by_pixels(
                &params,
                motion,
                seeds.as_slice(),
                claims.as_slice(),
                out.as_mut_slice(),
            );
            check(&out, stats, "assign_by_pixels");

            // The smallest ring that fits, so its marks wrap around.
            let words = ((2 * span + 1) * params.padded_width as usize)
                .div_ceil(64)
                .next_power_of_two();
            if words <= RING_WORDS {
                let (mut claims, mut out) = fresh();
                claim_all(&params, motion, claims.as_mut_slice());
                ring.fill(0);
                let stats = assign_by_sources(
                    &params,
                    seeds.as_slice(),
                    claims.as_slice(),
                    out.as_mut_slice(),
                    span,
                    &mut ring[..words],
                );
                check(&out, stats, "assign_by_sources");
                ring_runs += 1;
            }

            for span in [0, 1, 2, 5, FUSED_SPAN] {
                let words = ((2 * span + 1) * params.padded_width as usize)
                    .div_ceil(64)
                    .next_power_of_two();
                // The dispatching form (AVX2 where the CPU has it) and the
                // portable body.
                let forms: [(&str, Fused); 2] =
                    [("reproject_fused", reproject_fused), ("fused_body", fused_body)];
                for (path, form) in forms {
                    let (mut claims, mut out) = fresh();
                    ring.fill(0);
                    let fused = form(
                        &params,
                        motion,
                        seeds.as_slice(),
                        claims.as_mut_slice(),
                        out.as_mut_slice(),
                        span,
                        &mut ring[..words],
                    );
                    if let Some(stats) = fused {
                        check(&out, stats, path);
                        fused_runs += 1;
                    }
                }
            }
        }
    }
    // Both fast forms ran on most cases (the fused one gives up on far claims).
    assert!(ring_runs > sizes.len() * FIELDS * 3 / 4, "{ring_runs}");
    assert!(fused_runs > sizes.len() * FIELDS * 4, "{fused_runs}");
}

#[test]
fn points_on_pixel_corners_give_permutations_in_2k_buffers() {
    // 16 x 16 and 64 x 64 without padding: 2^8 and 2^12 seeds, so the last
    // pixel's index is all ones and a point on a pixel corner (squared
    // distance 0.5) gives the largest key. That key used to equal
    // `CLAIM_NONE`, and with a pixel left without a seed the last pixel's
    // source was handed out twice.
    type Corner = fn(u32, u32, u32, u32) -> [f32; 2];
    let corners: [Corner; 8] = [
        |_, _, _, _| [0.5, 0.5],
        |_, _, _, _| [-0.5, -0.5],
        |_, _, _, _| [0.5, -0.5],
        |_, _, _, _| [-0.5, 0.5],
        |x, y, w, h| field(17, x, y, w, h),
        |x, y, w, h| field(18, x, y, w, h),
        // Every pixel on some corner, of some pixel up to 3 away.
        |x, y, _, _| [((x * 7 + y) % 7) as f32 - 3.5, ((x + y * 5) % 6) as f32 - 2.5],
        // Everything disoccluded but the last pixel, on its own corner,
        // and the first pixel, which then lacks a seed.
        |x, y, w, h| {
            if x == w - 1 && y == h - 1 {
                [-0.5, -0.5]
            } else {
                [f32::NAN, f32::NAN]
            }
        },
    ];
    for (w, h) in [(16, 16), (64, 64)] {
        let l = layout(w, h);
        let n = (w * h) as usize;
        assert_eq!(l.seed_count(), n, "no padding");
        let seeds = alloc_free::Out::iota(n);
        let mut motion = [[0.0f32; 2]; alloc_free::CAP];
        for (c, corner) in corners.iter().enumerate() {
            for (i, m) in motion[..n].iter_mut().enumerate() {
                *m = corner(i as u32 % w, i as u32 / w, w, h);
            }
            let out = run(&l, &motion[..n]);
            assert!(is_permutation(out.as_slice()), "{w}x{h}, field {c}");
            assert_eq!(out.stats.followed + out.stats.recycled, n as u32);
            let mut expected = alloc_free::Out::new(n);
            let mut claims = alloc_free::Out::new(n);
            let stats = reproject_reference(
                &l,
                &motion[..n],
                seeds.as_slice(),
                claims.as_mut_slice(),
                expected.as_mut_slice(),
            );
            assert_eq!(out.as_slice(), expected.as_slice(), "{w}x{h}, field {c}");
            assert_eq!(out.stats, stats.unwrap(), "{w}x{h}, field {c}");
            let followed = match c {
                0 => (w - 1) * (h - 1), // each pixel claims its lower right neighbour
                1 => w * h,             // each pixel claims itself: the identity
                4 | 7 => 1,             // only the last pixel has a source
                _ => out.stats.followed,
            };
            assert_eq!(out.stats.followed, followed, "{w}x{h}, field {c}");
        }
    }
}
