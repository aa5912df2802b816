//! Motion vectors for the seed reprojection on the CPU: the G-buffer's
//! backward motion with disoccluded pixels marked
//! `kernels::motion::DISOCCLUDED` (no source, like NaN), in the form
//! `sampler_core::reproject_frame` takes. Per pixel this is
//! `kernels::motion::reprojection_motion_pixel`, the code the GPU's motion
//! pass runs.

use glam::{UVec2, Vec2};
use kernels::abi::GBufferGpu;
use kernels::motion::{frame_follows, moves_rigidly, reprojection_motion_pixel, seed_motion, visibility};
use kernels::pan_offset::{
    pixel_contribution, region_word, sum_region, FRAME_CLEARED_WORDS, FRAME_RIGID, REGION_SAMPLED,
    REGION_SUM_X, REGION_SUM_Y,
};

pub use kernels::motion::DISOCCLUSION_DEPTH_TOLERANCE;

/// Writes the visibility of every texel of `gbuffer` (object id and linear
/// depth, `kernels::motion::visibility`) to `out`: what the next frame's
/// [`reprojection_motion`] needs of this frame, 8 bytes a pixel.
///
/// # Panics
/// If the lengths differ.
pub fn write_visibility(gbuffer: &[GBufferGpu], out: &mut [UVec2]) {
    assert_eq!(
        gbuffer.len(),
        out.len(),
        "visibility buffer must match the G-buffer"
    );
    for (o, g) in out.iter_mut().zip(gbuffer) {
        *o = visibility(g);
    }
}

/// Backward motion `[dx, dy]` per pixel (`width * height`, row-major) from
/// this frame's G-buffer, with `kernels::motion::DISOCCLUDED` where the pixel's point was not visible
/// in the previous frame: behind the previous camera, outside the previous
/// frame, hidden by something nearer (depth test against `previous`, the
/// previous frame's visibility from [`write_visibility`], with
/// [`DISOCCLUSION_DEPTH_TOLERANCE`]), or on another object than the
/// previous pixel showed. Background pixels keep their (camera-rotation)
/// motion.
///
/// # Panics
/// If `current` or `previous` is not `width * height` long.
pub fn reprojection_motion(
    current: &[GBufferGpu],
    previous: &[UVec2],
    width: u32,
    height: u32,
) -> Vec<[f32; 2]> {
    motion_per_pixel(current, previous, width, height, |_, m| m)
}

/// [`reprojection_motion`] as the seed reprojection takes it: zero where the
/// pixel's surface moved less than `hold_below` pixels since the previous
/// frame, so that its seed stays, unless at least `follow_share` of the
/// frame's pixels move rigidly (`kernels::motion::{moves_rigidly,
/// frame_follows, seed_motion}`, the code the GPU's rigid-count and motion
/// passes run). `hold_below` in pixels per frame, finite and `>= 0`; 0 gives
/// [`reprojection_motion`] exactly. `follow_share` in `[0, 1]`; 0: the
/// frame-wide rule is off.
///
/// # Panics
/// If `current` or `previous` is not `width * height` long.
pub fn seed_reprojection_motion(
    current: &[GBufferGpu],
    previous: &[UVec2],
    width: u32,
    height: u32,
    hold_below: f32,
    follow_share: f32,
) -> Vec<[f32; 2]> {
    let follows_all = follow_share > 0.0 && {
        let rigid = rigid_pixels(current, width, height);
        frame_follows(rigid, width.wrapping_mul(height), follow_share)
    };
    seed_motion_with(current, previous, width, height, hold_below, follows_all)
}

/// [`seed_reprojection_motion`] with the frame-wide rule already decided
/// (`follows_all`, from `kernels::motion::frame_follows` of the frame's
/// rigid count): for a caller that has counted the rigid pixels itself,
/// e.g. with [`frame_motion_words`].
///
/// # Panics
/// If `current` or `previous` is not `width * height` long.
pub fn seed_motion_with(
    current: &[GBufferGpu],
    previous: &[UVec2],
    width: u32,
    height: u32,
    hold_below: f32,
    follows_all: bool,
) -> Vec<[f32; 2]> {
    motion_per_pixel(current, previous, width, height, |g, m| {
        seed_motion(g, m, hold_below, follows_all)
    })
}

/// The frame-motion words the GPU's rigid-count pass sums
/// (`kernels::pan_offset`'s first `FRAME_CLEARED_WORDS`: the rigid count,
/// then each screen region's sampled count and motion sums; each pixel's
/// `pixel_contribution` added with wrapping), for `advance_offset`.
pub fn frame_motion_words(gbuffer: &[GBufferGpu], width: u32, height: u32) -> [u32; FRAME_CLEARED_WORDS] {
    let mut words = [0u32; FRAME_CLEARED_WORDS];
    for y in 0..height {
        for x in 0..width {
            let [rigid, sampled, mx, my] = pixel_contribution(gbuffer, x, y, width, height);
            words[FRAME_RIGID] = words[FRAME_RIGID].wrapping_add(rigid);
            if sampled != 0 {
                let r = sum_region(x, y, width, height);
                for (k, c) in [(REGION_SAMPLED, sampled), (REGION_SUM_X, mx), (REGION_SUM_Y, my)] {
                    let w = &mut words[region_word(r, k)];
                    *w = w.wrapping_add(c);
                }
            }
        }
    }
    words
}

/// How many pixels of the frame move rigidly
/// (`kernels::motion::moves_rigidly`; what the GPU's rigid-count pass sums).
///
/// # Panics
/// If `gbuffer` is not `width * height` long.
pub fn rigid_pixels(gbuffer: &[GBufferGpu], width: u32, height: u32) -> u32 {
    assert_eq!(
        gbuffer.len(),
        width as usize * height as usize,
        "G-buffer must be width * height"
    );
    (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .filter(|&(x, y)| moves_rigidly(gbuffer, x, y, width, height))
        .count() as u32
}

/// One pass over the pixels: `finish(texel, reprojection_motion_pixel(..))`.
fn motion_per_pixel(
    current: &[GBufferGpu],
    previous: &[UVec2],
    width: u32,
    height: u32,
    finish: impl Fn(&GBufferGpu, Vec2) -> Vec2,
) -> Vec<[f32; 2]> {
    let n = width as usize * height as usize;
    assert!(
        current.len() == n && previous.len() == n,
        "G-buffer and visibility must be width * height"
    );
    current
        .iter()
        .enumerate()
        .map(|(i, g)| {
            let (x, y) = (i as u32 % width, i as u32 / width);
            finish(g, reprojection_motion_pixel(g, x, y, width, height, previous)).to_array()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{UVec4, Vec4};
    use kernels::abi::{GBUFFER_HIT, GBUFFER_PREV_IN_FRONT};

    fn vis(g: &[GBufferGpu]) -> Vec<UVec2> {
        let mut v = vec![UVec2::ZERO; g.len()];
        write_visibility(g, &mut v);
        v
    }

    fn texel(object: u32, depth: f32, motion: [f32; 2], prev_depth: f32) -> GBufferGpu {
        GBufferGpu {
            normal_depth: Vec4::new(0.0, 0.0, 1.0, depth),
            motion: Vec4::new(motion[0], motion[1], prev_depth, 0.0),
            ids: UVec4::new(object, 0, 0, GBUFFER_HIT | GBUFFER_PREV_IN_FRONT),
            ..Default::default()
        }
    }

    #[test]
    fn occluded_and_off_screen_points_are_nan() {
        // 3x1 frame: previous frame showed object 1 at depth 10 everywhere,
        // except pixel 2 which showed object 2 (an occluder) at depth 4.
        let previous = [
            texel(1, 10.0, [0.0; 2], 10.0),
            texel(1, 10.0, [0.0; 2], 10.0),
            texel(2, 4.0, [0.0; 2], 4.0),
        ];
        let current = [
            texel(1, 10.0, [1.0, 0.0], 10.0), // was at pixel 1: visible
            texel(1, 10.0, [1.0, 0.0], 10.0), // was at pixel 2, hidden by the occluder
            texel(1, 10.0, [1.2, 0.0], 10.0), // was outside the frame
        ];
        let m = reprojection_motion(&current, &vis(&previous), 3, 1);
        assert_eq!(m[0], [1.0, 0.0]);
        let gone = kernels::motion::DISOCCLUDED.to_array();
        assert_eq!((m[1], m[2]), (gone, gone));
        // Depth within 5% on the same object: visible.
        let current = [
            texel(1, 10.0, [1.0, 0.0], 10.4),
            texel(1, 1.0, [0.0; 2], 1.0),
            texel(1, 1.0, [0.0; 2], 1.0),
        ];
        assert_eq!(
            reprojection_motion(&current, &vis(&previous), 3, 1)[0],
            [1.0, 0.0]
        );
    }

    #[test]
    fn slow_surfaces_hold_their_seeds_fast_and_disoccluded_ones_do_not() {
        let previous = [
            texel(1, 10.0, [0.0; 2], 10.0),
            texel(1, 10.0, [0.0; 2], 10.0),
            texel(2, 4.0, [0.0; 2], 4.0),
        ];
        let current = [
            texel(1, 10.0, [1.0, 0.0], 10.0),  // 1 px: follows at 0.5, holds at 2
            texel(1, 10.0, [1.0, 0.0], 10.0),  // disoccluded, 1 px: holds at 2
            texel(1, 10.0, [-2.5, 0.0], 10.0), // 2.5 px: follows at 2
        ];
        let vis = vis(&previous);
        let plain = reprojection_motion(&current, &vis, 3, 1);
        assert_eq!(seed_reprojection_motion(&current, &vis, 3, 1, 0.0, 0.0), plain);
        assert_eq!(seed_reprojection_motion(&current, &vis, 3, 1, 0.5, 0.0), plain);
        let held = seed_reprojection_motion(&current, &vis, 3, 1, 2.0, 0.0);
        assert_eq!(held, vec![[0.0, 0.0], [0.0, 0.0], plain[2]]);
        assert_eq!(plain[2], [-2.5, 0.0]);
        // No previous position (NaN motion): never held.
        let mut nan = current;
        nan[0].motion.x = f32::NAN;
        let m = seed_reprojection_motion(&nan, &vis, 3, 1, 100.0, 0.0);
        assert_eq!(m[0], kernels::motion::DISOCCLUDED.to_array());
    }

    /// A frame that slides rigidly (every surface 2 px/frame, the same
    /// everywhere) follows as a whole once its rigid pixels reach the share;
    /// one pixel's motion bent by more than `RIGID_WITHIN` takes it and its
    /// four neighbours out of the count.
    #[test]
    fn a_rigidly_sliding_frame_follows_as_a_whole_past_its_share() {
        let (w, h) = (6, 5);
        let mut current: Vec<_> = (0..w * h).map(|_| texel(1, 10.0, [-2.0, 0.0], 10.0)).collect();
        let vis = vis(&current);
        let plain = reprojection_motion(&current, &vis, w, h);
        // Rigid: the 4 x 3 pixels off the border, 12 of 30.
        assert_eq!(rigid_pixels(&current, w, h), 12);
        let held = seed_reprojection_motion(&current, &vis, w, h, 6.0, 0.0);
        assert!(held.iter().all(|m| *m == [0.0, 0.0]), "{held:?}");
        assert_eq!(seed_reprojection_motion(&current, &vis, w, h, 6.0, 0.4), plain);
        let not_enough = seed_reprojection_motion(&current, &vis, w, h, 6.0, 0.41);
        assert_eq!(not_enough, held);
        // Bend one interior pixel's motion: it and its 4 neighbours (all
        // interior) stop counting.
        current[2 * w as usize + 2].motion.y = 0.06;
        assert_eq!(rigid_pixels(&current, w, h), 7);
        // Too slow to count, however uniform.
        let slow: Vec<_> = (0..w * h).map(|_| texel(1, 10.0, [-0.9, 0.0], 10.0)).collect();
        assert_eq!(rigid_pixels(&slow, w, h), 0);
    }

    /// The tolerance grows with the speed (`RIGID_WITHIN_PER_SPEED`): the
    /// same bend that takes a 2 px/frame pixel out of the count leaves a
    /// 4 px/frame one in it, and a bend past 0.1 px/frame takes it out.
    #[test]
    fn the_rigid_tolerance_grows_with_the_speed() {
        let (w, h) = (6, 5);
        let frame = |speed: f32, bend: f32| {
            let mut f: Vec<_> = (0..w * h).map(|_| texel(1, 10.0, [-speed, 0.0], 10.0)).collect();
            f[2 * w as usize + 2].motion.y = bend;
            f
        };
        assert_eq!(rigid_pixels(&frame(2.0, 0.0625), w, h), 7);
        assert_eq!(rigid_pixels(&frame(4.0, 0.0625), w, h), 12);
        assert_eq!(rigid_pixels(&frame(4.0, 0.125), w, h), 7);
        // Up to 2 px/frame the floor holds: 0.05 counts at 1.5 px/frame.
        assert_eq!(rigid_pixels(&frame(1.5, 0.05), w, h), 12);
        assert_eq!(rigid_pixels(&frame(1.5, 0.0625), w, h), 7);
        // Proportional: 8 px/frame tolerates 0.2 px/frame but not 0.25.
        assert_eq!(rigid_pixels(&frame(8.0, 0.1875), w, h), 12);
        assert_eq!(rigid_pixels(&frame(8.0, 0.25), w, h), 7);
    }

    /// The pan offset (`kernels::pan_offset`): a 10x10 frame sliding
    /// (-1.25, 0.5) px/frame has 64 rigid pixels, 4 of them on the sum
    /// grid, one in each of 4 screen regions; the offset advances by their
    /// mean in 1/16 px when the frame follows, stays when it does not, and
    /// rounds to whole pixels.
    #[test]
    fn the_pan_offset_follows_frames_that_follow_as_a_whole() {
        use kernels::pan_offset::{advance_offset, fixed_motion, motion_spread, offset_pixels};
        let (w, h) = (10, 10);
        let sliding: Vec<_> = (0..w * h).map(|_| texel(1, 10.0, [-1.25, 0.5], 10.0)).collect();
        let words = frame_motion_words(&sliding, w, h);
        let (x, y) = (-20i32 as u32, 8u32);
        assert_eq!(words[FRAME_RIGID], 64);
        // Grid pixels (4, 4), (8, 4), (4, 8), (8, 8): regions (1, 1), (3, 1), (1, 3), (3, 3).
        for r in 0..16 {
            let expected = if [5, 7, 13, 15].contains(&r) {
                [1, x, y]
            } else {
                [0; 3]
            };
            let got = [REGION_SAMPLED, REGION_SUM_X, REGION_SUM_Y].map(|k| words[region_word(r, k)]);
            assert_eq!(got, expected, "region {r}");
        }
        assert_eq!(motion_spread(&words), [4, x, y, 0]);
        let mut offset = [0u32; 2];
        for frame in 1..=3u32 {
            offset = advance_offset(offset, &words, w * h, 0.5);
            assert_eq!(offset, [x.wrapping_mul(frame), y * frame]);
        }
        // -3.75 and 1.5 px round (halves up) to -4 and 2.
        assert_eq!(offset_pixels(offset[0]) as i32, -4);
        assert_eq!(offset_pixels(offset[1]), 2);
        assert_eq!(offset_pixels(-24i32 as u32) as i32, -1);
        assert_eq!(offset_pixels(-25i32 as u32) as i32, -2);
        // Short of the share, or with the rule off: no change.
        assert_eq!(advance_offset(offset, &words, w * h, 0.65), offset);
        assert_eq!(advance_offset(offset, &words, w * h, 0.0), offset);
        // A frame too slow to count: nothing sampled.
        let slow: Vec<_> = (0..w * h).map(|_| texel(1, 10.0, [-0.5, 0.0], 10.0)).collect();
        assert_eq!(frame_motion_words(&slow, w, h), [0; FRAME_CLEARED_WORDS]);
        assert_eq!(
            advance_offset(offset, &[0; FRAME_CLEARED_WORDS], w * h, 0.0),
            offset
        );
        // Fixed point: halves up, clamped at 64 px/frame, NaN as 0.
        assert_eq!(fixed_motion(16.5 / 16.0), 17);
        assert_eq!(fixed_motion(-16.5 / 16.0) as i32, -16);
        assert_eq!(fixed_motion(1000.0), 1024);
        assert_eq!(fixed_motion(-1000.0) as i32, -1024);
        assert_eq!(fixed_motion(f32::NAN), 0);
    }

    /// The offset moves only where the rigid pixels move alike
    /// (`kernels::pan_offset::moves_alike`): a 20x12 frame whose left half
    /// slides at `left` px/frame and right half at `right` (both with 0.5
    /// down) has rigid pixels in both halves, two grid columns in each; the
    /// regions' spread around the mean decides.
    #[test]
    fn the_pan_offset_leaves_frames_that_do_not_move_alike() {
        use kernels::pan_offset::{
            advance_offset, motion_spread, moves_alike, PAN_SPREAD_PERCENT, SPREAD_BITS,
        };
        let (w, h) = (20, 12);
        let frame = |left: f32, right: f32| -> Vec<GBufferGpu> {
            (0..w * h)
                .map(|i| texel(1, 10.0, [if i % w < 10 { left } else { right }, 0.5], 10.0))
                .collect()
        };
        // Parallax of a pan: -2 and -2.25 px/frame, means -32 and -36 in
        // 1/16 px around -34: spread 2 (32 in 1/256 px) against 14% of 34 + 8.
        let pan = frame_motion_words(&frame(-2.0, -2.25), w, h);
        assert_eq!(motion_spread(&pan), [8, -34i32 as u32, 8, 32]);
        assert!(moves_alike(motion_spread(&pan)));
        let moved = advance_offset([0, 0], &pan, w * h, 0.5);
        assert_eq!(moved, [-34i32 as u32, 8]);
        // An orbit's walls: -1.25 and -2.5 px/frame, means -20 and -40
        // around -30: spread 10 (160) against 14% of 30 + 8 = 5.3 (85).
        let turn = frame_motion_words(&frame(-1.25, -2.5), w, h);
        assert_eq!(motion_spread(&turn), [8, -30i32 as u32, 8, 160]);
        assert!(!moves_alike(motion_spread(&turn)));
        assert!(kernels::motion::frame_follows(turn[FRAME_RIGID], w * h, 0.5));
        assert_eq!(advance_offset(moved, &turn, w * h, 0.5), moved);
        // The boundary: a spread of exactly the percentage moves.
        // A spread of 1/16 of the mean's length in 1/256 px units.
        let at = PAN_SPREAD_PERCENT << SPREAD_BITS;
        assert!(moves_alike([1, 100, 0, at]));
        assert!(!moves_alike([1, 100, 0, at + 1]));
        // Uneven regions: one of 3 pixels 1/16 px off a mean of 0 gives
        // 1/3 of 16 in 1/256 px, floored: the remainders are kept.
        let mut words = [0u32; FRAME_CLEARED_WORDS];
        words[region_word(0, REGION_SAMPLED)] = 2;
        words[region_word(1, REGION_SAMPLED)] = 1;
        words[region_word(1, REGION_SUM_X)] = 1;
        assert_eq!(motion_spread(&words), [3, 0, 0, 5]);
        assert!(!moves_alike([0, 0, 0, 0]));
    }

    /// ZSobol is read at the pixel plus the pan offset rounded to whole
    /// pixels; the other samplers, and ZSobol's followed homes, ignore it.
    #[test]
    fn zsobol_reads_its_point_at_the_pan_offset() {
        use kernels::abi::{SAMPLER_FOLLOW_HOMES, SAMPLER_JITTER_ONLY, SAMPLER_SCREEN_SOBOL, SAMPLER_ZSOBOL};
        use kernels::numbers::sampler_position;
        let mut p = kernels::abi::TraceParams {
            sampler_offset_x: -40i32 as u32,
            sampler_offset_y: 24,
            ..Default::default()
        };
        let pixel = glam::UVec2::new(7, 3);
        for sampler in [SAMPLER_ZSOBOL, SAMPLER_ZSOBOL | SAMPLER_JITTER_ONLY] {
            p.sampler = sampler;
            let q = sampler_position(&p, pixel, 0);
            // -2.5 px rounds to -2, 1.5 to 2.
            assert_eq!((q.x as i32, q.y), (5, 5), "sampler {sampler:#x}");
        }
        p.sampler = SAMPLER_SCREEN_SOBOL;
        assert_eq!(sampler_position(&p, pixel, 0), pixel);
        p.sampler = SAMPLER_ZSOBOL | SAMPLER_FOLLOW_HOMES;
        let home = sampler_core::sequences::spatiotemporal::home_texel(0x0005_0009);
        assert_eq!(sampler_position(&p, pixel, 0x0005_0009), home);
    }
}
