//! Temporal accumulation: the running mean of the frames rendered so far.
//!
//! The trace pass writes each frame's own colour (`width * height` Vec4,
//! `(r, g, b, 1)`): that buffer is also the intensity image the sorting pass
//! ranks (by the luma of `rgb`, `sampler_core::Intensity for Vec4`). The
//! accumulation buffer holds, per pixel, the mean of frames `0..=t` in `rgb`
//! and the number of frames `t + 1` in `w` (exact as `f32` up to 2^24 frames).

use glam::Vec4;

/// Pixel of the accumulation buffer after adding frame `frame` (0-based):
/// `previous` holds the mean of frames `0..frame` (ignored when `frame` is
/// 0), `color` is the new frame's colour. Returns the mean of frames
/// `0..=frame` in `xyz` and `frame + 1` in `w`.
///
/// Incremental form `m + (c - m) / (t + 1)`, which never sums large totals.
/// Identical on the host and the GPU (same f32 operations).
#[inline]
pub fn accumulate_pixel(previous: Vec4, color: Vec4, frame: u32) -> Vec4 {
    let count = frame.wrapping_add(1) as f32;
    if frame == 0 {
        return color.truncate().extend(1.0);
    }
    let mean = previous.truncate();
    (mean + (color.truncate() - mean) / count).extend(count)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn running_mean_matches_the_plain_mean() {
        let frames: Vec<Vec4> = (0..100)
            .map(|i| Vec4::new(i as f32, (i * i) as f32 * 0.01, 1.0 / (i + 1) as f32, 1.0))
            .collect();
        let mut acc = Vec4::new(f32::NAN, 7.0, 7.0, 7.0); // garbage before frame 0 is ignored
        for (t, c) in frames.iter().enumerate() {
            acc = accumulate_pixel(acc, *c, t as u32);
            let n = t + 1;
            let mean = frames[..n].iter().fold(Vec4::ZERO, |a, b| a + *b) / n as f32;
            assert!(
                (acc.truncate() - mean.truncate()).abs().max_element() < 1e-4 * (1.0 + mean.max_element())
            );
            assert_eq!(acc.w, n as f32);
        }
    }
}
