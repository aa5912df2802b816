//! Motion vectors for the seed reprojection on the CPU: the G-buffer's
//! backward motion with disoccluded pixels marked
//! `kernels::motion::DISOCCLUDED` (no source, like NaN), in the form
//! `sampler_core::reproject_frame` takes. Per pixel this is
//! `kernels::motion::reprojection_motion_pixel`, the code the GPU's motion
//! pass runs.

use glam::{UVec2, Vec2};
use kernels::abi::GBufferGpu;
use kernels::motion::{reprojection_motion_pixel, seed_motion, visibility};

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
/// frame (`kernels::motion::seed_motion`, the code the GPU's motion pass
/// runs), so that its seed stays. `hold_below` in pixels per frame, finite
/// and `>= 0`; 0 gives [`reprojection_motion`] exactly.
///
/// # Panics
/// If `current` or `previous` is not `width * height` long.
pub fn seed_reprojection_motion(
    current: &[GBufferGpu],
    previous: &[UVec2],
    width: u32,
    height: u32,
    hold_below: f32,
) -> Vec<[f32; 2]> {
    motion_per_pixel(current, previous, width, height, |g, m| {
        seed_motion(g, m, hold_below)
    })
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
        assert_eq!(seed_reprojection_motion(&current, &vis, 3, 1, 0.0), plain);
        assert_eq!(seed_reprojection_motion(&current, &vis, 3, 1, 0.5), plain);
        let held = seed_reprojection_motion(&current, &vis, 3, 1, 2.0);
        assert_eq!(held, vec![[0.0, 0.0], [0.0, 0.0], plain[2]]);
        assert_eq!(plain[2], [-2.5, 0.0]);
        // No previous position (NaN motion): never held.
        let mut nan = current;
        nan[0].motion.x = f32::NAN;
        let m = seed_reprojection_motion(&nan, &vis, 3, 1, 100.0);
        assert_eq!(m[0], kernels::motion::DISOCCLUDED.to_array());
    }
}
