//! Motion vectors for the seed reprojection: the G-buffer's backward motion
//! with disoccluded pixels marked, in the form
//! `sampler_core::reproject_frame` takes.

use kernels::abi::{GBufferGpu, GBUFFER_HIT, GBUFFER_PREV_IN_FRONT};

/// Largest relative difference between a point's depth in the previous
/// camera and the previous frame's G-buffer depth at its previous pixel for
/// the point to count as visible there (the usual TAA depth test). 5%:
/// generous for the depth slopes of one pixel at grazing angles, far below
/// the jump at an occluding edge of a room-scale scene.
pub const DISOCCLUSION_DEPTH_TOLERANCE: f32 = 0.05;

/// Backward motion `[dx, dy]` per pixel (`width * height`, row-major) from
/// this frame's G-buffer, with NaN where the pixel's point was not visible
/// in the previous frame: behind the previous camera, outside the previous
/// frame, hidden by something nearer (depth test against `previous`, the
/// previous frame's G-buffer, with [`DISOCCLUSION_DEPTH_TOLERANCE`]), or on
/// another object than the previous pixel showed. Background pixels keep
/// their (camera-rotation) motion.
///
/// # Panics
/// If `current` or `previous` is not `width * height` long.
pub fn reprojection_motion(
    current: &[GBufferGpu],
    previous: &[GBufferGpu],
    width: u32,
    height: u32,
) -> Vec<[f32; 2]> {
    let n = width as usize * height as usize;
    assert!(
        current.len() == n && previous.len() == n,
        "G-buffers must be width * height"
    );
    current
        .iter()
        .enumerate()
        .map(|(i, g)| {
            let m = [g.motion.x, g.motion.y];
            if g.ids.w & GBUFFER_HIT == 0 {
                return m;
            }
            if g.ids.w & GBUFFER_PREV_IN_FRONT == 0 {
                return [f32::NAN; 2];
            }
            let (x, y) = (
                (i as u32 % width) as f32 + 0.5 + m[0],
                (i as u32 / width) as f32 + 0.5 + m[1],
            );
            if !(x >= 0.0 && y >= 0.0 && x < width as f32 && y < height as f32) {
                return [f32::NAN; 2];
            }
            let p = &previous[y as usize * width as usize + x as usize];
            let visible = p.ids.w & GBUFFER_HIT != 0
                && p.ids.x == g.ids.x
                && (p.normal_depth.w - g.motion.z).abs() <= DISOCCLUSION_DEPTH_TOLERANCE * g.motion.z;
            if visible {
                m
            } else {
                [f32::NAN; 2]
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{UVec4, Vec4};

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
        let m = reprojection_motion(&current, &previous, 3, 1);
        assert_eq!(m[0], [1.0, 0.0]);
        assert!(m[1][0].is_nan() && m[2][0].is_nan());
        // Depth within 5% on the same object: visible.
        let current = [
            texel(1, 10.0, [1.0, 0.0], 10.4),
            texel(1, 1.0, [0.0; 2], 1.0),
            texel(1, 1.0, [0.0; 2], 1.0),
        ];
        assert_eq!(reprojection_motion(&current, &previous, 3, 1)[0], [1.0, 0.0]);
    }
}
