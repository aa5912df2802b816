//! Temporal accumulation: an exponential history reprojected by the motion
//! vectors (TAA; the temporal stage of SVGF).
//!
//! `out(p) = alpha * c(p) + (1 - alpha) * clamp(h(p + 0.5 + m(p)))`, where
//! `c` is the current frame, `h` the previous output read bilinearly at the
//! pixel's previous raster position (`m`: backward motion in pixels, as in
//! [`crate::motion::reprojection_motion_pixel`]), and `clamp` limits the
//! history to the box of the current 3x3 neighbourhood's colours (optional,
//! [`FILTER_CLAMP`]). The history **resets** (`out = c`) where the previous
//! position is outside the frame (which includes
//! [`DISOCCLUDED`](crate::motion::DISOCCLUDED) and NaN motion) and when
//! [`FILTER_HISTORY_VALID`] is clear (the first frame).

use super::{index, FilterParams, FILTER_CLAMP, FILTER_HISTORY_VALID};
use glam::{Vec2, Vec4};

/// The TAA output of pixel `(x, y)`: `current` and `history` are
/// `width * height` colours (`xyz` filtered, `w` carried from `current`),
/// `motion` the backward motion per pixel. `params.weight` is alpha.
#[inline]
pub fn taa_pixel(
    params: &FilterParams,
    x: u32,
    y: u32,
    current: &[Vec4],
    history: &[Vec4],
    motion: &[Vec2],
) -> Vec4 {
    let (w, h) = (params.width, params.height);
    let c = current[index(x, y, w)];
    if params.flags & FILTER_HISTORY_VALID == 0 {
        return c;
    }
    let m = motion[index(x, y, w)];
    let px = x as f32 + 0.5 + m.x;
    let py = y as f32 + 0.5 + m.y;
    // False for NaN and for the far-off disocclusion marker.
    if !(px >= 0.0 && py >= 0.0 && px < w as f32 && py < h as f32) {
        return c;
    }
    let mut past = bilinear(history, w, h, px - 0.5, py - 0.5);
    if params.flags & FILTER_CLAMP != 0 {
        let (lo, hi) = neighbourhood_box(current, w, h, x, y);
        past = past.clamp(lo, hi);
    }
    let alpha = params.weight;
    (c * alpha + past * (1.0 - alpha)).truncate().extend(c.w)
}

/// `buffer` (`w x h`) at continuous position `(fx, fy)` in pixel-centre
/// coordinates (pixel `(i, j)` at `(i, j)`), bilinear, edges clamped.
#[inline]
fn bilinear(buffer: &[Vec4], w: u32, h: u32, fx: f32, fy: f32) -> Vec4 {
    let fx = fx.max(0.0);
    let fy = fy.max(0.0);
    let x0 = (fx as u32).min(w - 1);
    let y0 = (fy as u32).min(h - 1);
    let x1 = (x0 + 1).min(w - 1);
    let y1 = (y0 + 1).min(h - 1);
    let tx = (fx - x0 as f32).clamp(0.0, 1.0);
    let ty = (fy - y0 as f32).clamp(0.0, 1.0);
    let top = buffer[index(x0, y0, w)] * (1.0 - tx) + buffer[index(x1, y0, w)] * tx;
    let bottom = buffer[index(x0, y1, w)] * (1.0 - tx) + buffer[index(x1, y1, w)] * tx;
    top * (1.0 - ty) + bottom * ty
}

/// Per-channel minimum and maximum of `current` over the 3x3 pixels around
/// `(x, y)` that lie in the frame.
#[inline]
fn neighbourhood_box(current: &[Vec4], w: u32, h: u32, x: u32, y: u32) -> (Vec4, Vec4) {
    let c = current[index(x, y, w)];
    let (mut lo, mut hi) = (c, c);
    let mut dy = 0;
    while dy < 3 {
        let mut dx = 0;
        while dx < 3 {
            let (qx, qy) = ((x + dx).wrapping_sub(1), (y + dy).wrapping_sub(1));
            if qx < w && qy < h {
                let q = current[index(qx, qy, w)];
                lo = lo.min(q);
                hi = hi.max(q);
            }
            dx += 1;
        }
        dy += 1;
    }
    (lo, hi)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::DISOCCLUDED;

    fn params(flags: u32) -> FilterParams {
        FilterParams {
            width: 4,
            height: 3,
            weight: 0.25,
            flags,
            ..Default::default()
        }
    }

    fn ramp() -> [Vec4; 12] {
        core::array::from_fn(|i| Vec4::new(i as f32, 2.0 * i as f32, 1.0, 9.0))
    }

    #[test]
    fn first_frame_and_disocclusion_reset_to_the_current_frame() {
        let current = ramp();
        let history = [Vec4::splat(100.0); 12];
        let still = [Vec2::ZERO; 12];
        assert_eq!(
            taa_pixel(&params(0), 1, 1, &current, &history, &still),
            current[5]
        );
        let gone = [DISOCCLUDED; 12];
        let p = params(FILTER_HISTORY_VALID);
        assert_eq!(taa_pixel(&p, 1, 1, &current, &history, &gone), current[5]);
        let nan = [Vec2::splat(f32::NAN); 12];
        assert_eq!(taa_pixel(&p, 1, 1, &current, &history, &nan), current[5]);
        // Off the right edge.
        let off = [Vec2::new(3.0, 0.0); 12];
        assert_eq!(taa_pixel(&p, 1, 1, &current, &history, &off), current[5]);
    }

    #[test]
    fn still_blend_and_half_pixel_shift_read_the_right_history() {
        let current = [Vec4::new(1.0, 1.0, 1.0, 5.0); 12];
        let history = ramp();
        let p = params(FILTER_HISTORY_VALID);
        let still = [Vec2::ZERO; 12];
        let out = taa_pixel(&p, 2, 1, &current, &history, &still);
        let expect = 0.25 * 1.0 + 0.75 * history[6].x;
        assert!((out.x - expect).abs() < 1e-6, "{out}");
        assert_eq!(out.w, 5.0, "w comes from the current frame");
        // Half a pixel to the left: the mean of pixels 5 and 6.
        let half = [Vec2::new(-0.5, 0.0); 12];
        let out = taa_pixel(&p, 2, 1, &current, &history, &half);
        let expect = 0.25 + 0.75 * 0.5 * (history[5].x + history[6].x);
        assert!((out.x - expect).abs() < 1e-5, "{out}");
    }

    #[test]
    fn clamp_limits_the_history_to_the_neighbourhood() {
        let current = ramp();
        let history = [Vec4::splat(1000.0); 12];
        let still = [Vec2::ZERO; 12];
        let p = params(FILTER_HISTORY_VALID | FILTER_CLAMP);
        // Pixel (0, 0): neighbours 0, 1, 4, 5; the box's top is pixel 5.
        let out = taa_pixel(&p, 0, 0, &current, &history, &still);
        let expect = 0.25 * current[0].x + 0.75 * current[5].x;
        assert!((out.x - expect).abs() < 1e-5, "{out}");
    }
}
