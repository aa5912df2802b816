//! A separable Gaussian blur, one axis per pass: the simple stand-in
//! denoiser of the STBN and FAST papers' error figures.
//!
//! `out(p) = sum_d g(d) src(p + d e) / sum_d g(d)`, `g(d) = exp(-d^2 / (2
//! sigma^2))`, `d` in `-r..=r` with `r = min(ceil(3 sigma),`
//! [`MAX_GAUSS_RADIUS`]`)`, `e` the pass's axis; taps beyond the frame read
//! the edge pixel (clamp to edge), so a constant image stays constant.

use super::{index, FilterParams};
use glam::Vec4;

/// Largest radius in pixels (a sigma above 4 pixels is truncated at 12
/// pixels, 3 sigma for sigma 4).
pub const MAX_GAUSS_RADIUS: u32 = 12;

/// One Gaussian pass at pixel `(x, y)`: `params.weight` is sigma in pixels
/// (`> 0`), `params.step` the axis (0 = x, 1 = y). `w` of the output is
/// filtered too.
#[inline]
pub fn gauss_pass_pixel(params: &FilterParams, x: u32, y: u32, src: &[Vec4]) -> Vec4 {
    let sigma = params.weight;
    let radius = libm::ceilf(3.0 * sigma).clamp(0.0, MAX_GAUSS_RADIUS as f32) as i32;
    let inv = -1.0 / (2.0 * sigma * sigma);
    let (last_x, last_y) = (params.width as i32 - 1, params.height as i32 - 1);
    let mut sum = Vec4::ZERO;
    let mut total = 0.0;
    let mut d = -radius;
    while d <= radius {
        let g = libm::expf((d * d) as f32 * inv);
        let (qx, qy) = if params.step == 0 {
            ((x as i32 + d).clamp(0, last_x), y as i32)
        } else {
            (x as i32, (y as i32 + d).clamp(0, last_y))
        };
        sum += src[index(qx as u32, qy as u32, params.width)] * g;
        total += g;
        d += 1;
    }
    sum / total
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_stays_constant_and_an_impulse_spreads_symmetrically() {
        let (w, h) = (9u32, 5u32);
        let p = |step| FilterParams {
            width: w,
            height: h,
            weight: 1.0,
            step,
            ..Default::default()
        };
        let flat = vec![Vec4::splat(0.5); (w * h) as usize];
        for step in [0, 1] {
            let v = gauss_pass_pixel(&p(step), 0, 4, &flat);
            assert!((v - Vec4::splat(0.5)).abs().max_element() < 1e-6);
        }
        let mut impulse = vec![Vec4::ZERO; (w * h) as usize];
        impulse[(2 * w + 4) as usize] = Vec4::ONE;
        let row: Vec<f32> = (0..w)
            .map(|x| gauss_pass_pixel(&p(0), x, 2, &impulse).x)
            .collect();
        let sum: f32 = row.iter().sum();
        assert!((sum - 1.0).abs() < 1e-5, "{row:?}");
        assert!((row[3] - row[5]).abs() < 1e-7 && row[4] > row[3] && row[3] > row[2]);
        // g(1) / g(0) = exp(-1/2) for sigma 1.
        assert!((row[3] / row[4] - libm::expf(-0.5)).abs() < 1e-6);
        // The other axis does not touch this row's neighbours.
        assert_eq!(gauss_pass_pixel(&p(1), 3, 2, &impulse).x, 0.0);
    }
}
