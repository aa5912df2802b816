//! A reprojecting exponential history: the temporal accumulation a real-time renderer
//! (TAA, the temporal pass of SVGF) runs before its spatial filter, as the "accumulated
//! error" of the motion study ([`crate::motion`]).
//!
//! `h_t(p) = alpha * x_t(p) + (1 - alpha) * h_{t-1}(q)`, where `q` is the pixel that
//! contains `p`'s previous position `p + 0.5 + m(p)` (`m` the backward motion vector of
//! `gpu_tracer::motion::reprojection_motion`). The history is **reset**
//! (`h_t(p) = x_t(p)`) where the motion is NaN (disocclusion: the point was hidden, off
//! screen or on another object in the previous frame) and in frame 0.
//!
//! The previous history is read at the nearest pixel, not bilinearly: a bilinear fetch
//! blurs the history a little more every frame (the usual TAA softening), which lowers
//! every method's error by a filter that is not part of the comparison and adds the same
//! bias at every edge. No neighbourhood clamp either: the figure is the error of the
//! plain average that the seeds' temporal distribution feeds. With a still camera it is
//! the ordinary exponential moving average.

/// The history weight of the study: 0.1, the usual TAA blend factor (quality.md, "What
/// the viewer sees").
pub const HISTORY_ALPHA: f32 = 0.1;

/// The history of a `width x height` frame (module docs).
#[derive(Clone, Debug)]
pub struct ReprojectedHistory {
    width: u32,
    height: u32,
    alpha: f32,
    value: Vec<f32>,
    scratch: Vec<f32>,
    started: bool,
}

impl ReprojectedHistory {
    /// An empty history (the first [`Self::update`] resets every pixel) with blend
    /// factor `alpha` in `(0, 1]`.
    ///
    /// # Panics
    /// If `alpha` is not in `(0, 1]`.
    pub fn new(width: u32, height: u32, alpha: f32) -> Self {
        assert!(alpha > 0.0 && alpha <= 1.0, "alpha must be in (0, 1]");
        let n = width as usize * height as usize;
        ReprojectedHistory {
            width,
            height,
            alpha,
            value: vec![0.0; n],
            scratch: vec![0.0; n],
            started: false,
        }
    }

    /// Blends `frame` (`width * height`, row-major) into the history reprojected by
    /// `motion` (backward motion in pixels per pixel; NaN or a previous position
    /// outside the frame = reset) and returns the new history and the number of reset
    /// pixels.
    ///
    /// # Panics
    /// If a buffer is not `width * height` long.
    pub fn update(&mut self, frame: &[f32], motion: &[[f32; 2]]) -> (&[f32], usize) {
        let (w, h) = (self.width as usize, self.height as usize);
        assert!(
            frame.len() == w * h && motion.len() == w * h,
            "buffers must be width * height"
        );
        let mut resets = 0;
        for (i, (out, (&x, m))) in self.scratch.iter_mut().zip(frame.iter().zip(motion)).enumerate() {
            let px = (i % w) as f32 + 0.5 + m[0];
            let py = (i / w) as f32 + 0.5 + m[1];
            // False for NaN.
            let inside = px >= 0.0 && py >= 0.0 && px < w as f32 && py < h as f32;
            *out = if self.started && inside {
                let q = (py as usize).min(h - 1) * w + (px as usize).min(w - 1);
                self.alpha * x + (1.0 - self.alpha) * self.value[q]
            } else {
                resets += 1;
                x
            };
        }
        std::mem::swap(&mut self.value, &mut self.scratch);
        self.started = true;
        (&self.value, resets)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn still_history_is_the_ema_and_motion_moves_it() {
        let mut hist = ReprojectedHistory::new(3, 1, 0.5);
        let still = [[0.0f32; 2]; 3];
        assert_eq!(hist.update(&[1.0, 2.0, 3.0], &still).0, &[1.0, 2.0, 3.0]);
        assert_eq!(hist.update(&[3.0, 2.0, 1.0], &still).0, &[2.0, 2.0, 2.0]);
        // Everything moved one pixel right: pixel x reads x - 1; pixel 0 came from
        // outside (reset), pixel 2 is disoccluded (NaN).
        let shift = [[-1.0, 0.0], [-1.0, 0.0], [f32::NAN, 0.0]];
        let (v, resets) = hist.update(&[0.0, 0.0, 4.0], &shift);
        assert_eq!(v, &[0.0, 1.0, 4.0]);
        assert_eq!(resets, 2);
    }
}
