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
//! The previous history is read at the nearest pixel by default ([`HistoryFetch`]): a
//! bilinear fetch blurs the history a little more every frame (the usual TAA softening),
//! which lowers every method's error by a filter that is not part of the comparison and
//! adds the same bias at every edge. [`HistoryFetch::Bilinear`] is that fetch, for the
//! question whether a history that resamples at sub-pixel precision keeps what a
//! sampler's temporal order buys (`QUALITY.md`, "Blue in time"). No neighbourhood clamp
//! either way: the figure is the error of the plain average that the seeds' temporal
//! distribution feeds. With a still camera both fetches are the ordinary exponential
//! moving average.

/// The history weight of the study: 0.1, the usual TAA blend factor (quality.md, "What
/// the viewer sees").
pub const HISTORY_ALPHA: f32 = 0.1;

/// How the history reads its previous value at a pixel's previous position (module
/// docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum HistoryFetch {
    /// The pixel that contains the previous position (no resampling blur).
    #[default]
    Nearest,
    /// Bilinear between the four pixel centres around the previous position (edge
    /// pixels clamped), as TAA implementations read their history.
    Bilinear,
}

/// The history of a `width x height` frame (module docs).
#[derive(Clone, Debug)]
pub struct ReprojectedHistory {
    width: u32,
    height: u32,
    alpha: f32,
    fetch: HistoryFetch,
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
            fetch: HistoryFetch::Nearest,
            value: vec![0.0; n],
            scratch: vec![0.0; n],
            started: false,
        }
    }

    /// The same history reading its previous values with `fetch`.
    pub fn with_fetch(self, fetch: HistoryFetch) -> Self {
        ReprojectedHistory { fetch, ..self }
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
                self.alpha * x + (1.0 - self.alpha) * fetch_at(&self.value, w, h, self.fetch, px, py)
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

/// The history `value` (`w x h`, row-major) at position `(px, py)` in pixels (pixel
/// `(x, y)` covers `[x, x + 1) x [y, y + 1)`), inside the frame, read with `fetch`.
fn fetch_at(value: &[f32], w: usize, h: usize, fetch: HistoryFetch, px: f32, py: f32) -> f32 {
    let at = |x: usize, y: usize| value[y * w + x];
    match fetch {
        HistoryFetch::Nearest => at((px as usize).min(w - 1), (py as usize).min(h - 1)),
        HistoryFetch::Bilinear => {
            // Relative to pixel centres; outside the outer centres the edge pixel's
            // value (clamped).
            let (u, v) = ((px - 0.5).max(0.0), (py - 0.5).max(0.0));
            let (x0, y0) = ((u as usize).min(w - 1), (v as usize).min(h - 1));
            let (x1, y1) = ((x0 + 1).min(w - 1), (y0 + 1).min(h - 1));
            let (fx, fy) = ((u - x0 as f32).clamp(0.0, 1.0), (v - y0 as f32).clamp(0.0, 1.0));
            let top = at(x0, y0) + fx * (at(x1, y0) - at(x0, y0));
            let bottom = at(x0, y1) + fx * (at(x1, y1) - at(x0, y1));
            top + fy * (bottom - top)
        }
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

    #[test]
    fn bilinear_fetch_reads_between_pixel_centres() {
        let mut hist = ReprojectedHistory::new(4, 2, 0.5).with_fetch(HistoryFetch::Bilinear);
        let still = [[0.0f32; 2]; 8];
        let first = [0.0, 4.0, 8.0, 12.0, 2.0, 6.0, 10.0, 14.0];
        // Still: the plain EMA, as the nearest fetch.
        assert_eq!(hist.update(&first, &still).0, &first);
        // A quarter pixel right and a half pixel down: pixel (1, 0)'s previous
        // position (1.75, 1.0) lies between centres (1.5, 0.5), (2.5, 0.5), (1.5,
        // 1.5) and (2.5, 1.5): 4 + 0.25 * 4 + 0.5 * 2 = 6 blended with 0 at 0.5.
        let shift = [[0.25f32, 0.5]; 8];
        let zeros = [0.0f32; 8];
        let v = hist.update(&zeros, &shift).0.to_vec();
        assert_eq!(v[1], 3.0);
        // Pixel (3, 0) at (3.75, 1.0) reads past the last column of centres: the edge
        // column, 12 + 0.5 * (14 - 12) = 13; pixel (3, 1) at (3.75, 2.0) left the frame
        // (reset to its new value).
        assert_eq!(v[3], 6.5);
        assert_eq!(v[7], 0.0);
        // Where the two fetches differ: a quarter pixel right and down.
        let mut nearest = ReprojectedHistory::new(4, 2, 0.5);
        nearest.update(&first, &still);
        let n = nearest.update(&zeros, &[[0.25f32, 0.25]; 8]).0.to_vec();
        let mut bilinear = ReprojectedHistory::new(4, 2, 0.5).with_fetch(HistoryFetch::Bilinear);
        bilinear.update(&first, &still);
        let b = bilinear.update(&zeros, &[[0.25f32, 0.25]; 8]).0.to_vec();
        // Pixel (1, 0) at (1.75, 0.75): nearest reads (1, 0) = 4; bilinear 4 + 0.25 * 4
        // + 0.25 * 2 = 5.5.
        assert_eq!(n[1], 2.0);
        assert_eq!(b[1], 2.75);
    }
}
