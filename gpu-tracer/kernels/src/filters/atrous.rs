//! SVGF's spatial stage (Schied et al. 2017): an edge-avoiding a-trous
//! wavelet filter, five iterations of a 5x5 B-spline kernel whose taps are
//! `2^i` pixels apart, each tap weighted by how much its surface and
//! luminance agree with the centre's:
//!
//! - depth: `w_z = exp(-|z_p - z_q| / (SIGMA_Z |grad z(p) . (p - q)| + eps))`,
//!   the depth difference against what the centre's depth slope predicts;
//! - normal: `w_n = max(0, n_p . n_q)^SIGMA_N`;
//! - luminance: `w_l = exp(-|l_p - l_q| / (SIGMA_L sqrt(var_p) + eps))`.
//!
//! The colour's `w` carries the luminance variance: [`variance_pixel`]
//! estimates it from the 3x3 neighbourhood before the first iteration, and
//! every iteration propagates it (`sum w^2 var / (sum w)^2`), so later
//! iterations stop at smaller luminance differences. Pixels without a
//! primary hit and pixels that see an emitter are passed through and never
//! used as taps: an emitter's radiance is not noise to be shared with its
//! surroundings, and a 3x3 variance that straddles a light's silhouette is
//! so large that the luminance test would let the light bleed into the
//! surfaces around it ([`filtered_surface`]). So are the pixels beside an
//! emitter (one of their 3x3 neighbours sees it; `w` =
//! [`BESIDE_EMITTER`]): their samples see the light over part of the pixel,
//! so their values are the light's silhouette, not noise around a smooth
//! illumination, and averaging them with the surface beyond blurs the
//! silhouette (on the Cornell box that blur was 0.89 of white noise's
//! filtered error with no noise at all: `QUALITY.md`, "The filter passes
//! the lights' silhouettes through"); the temporal filter alone smooths
//! them.

use super::{index, FilterParams};
use crate::abi::{GBufferGpu, GBUFFER_EMITTER, GBUFFER_HIT};
use glam::{Vec3, Vec4};
use sampler_core::permutation::sort::luma;

/// Number of a-trous iterations (steps 1, 2, 4, 8, 16 pixels), as in SVGF.
pub const ATROUS_ITERATIONS: u32 = 5;
/// Depth sensitivity `sigma_z` (SVGF's value).
pub const SIGMA_Z: f32 = 1.0;
/// Normal exponent `sigma_n` (SVGF's value).
pub const SIGMA_N: u32 = 128;
/// Luminance sensitivity `sigma_l`, in standard deviations (SVGF's value).
pub const SIGMA_L: f32 = 4.0;

/// The `w` [`variance_pixel`] gives a filtered surface with an emitter among
/// its 3x3 neighbours (a light's silhouette): [`atrous_pixel`] passes such a
/// pixel through and never uses it as a tap (module docs). A variance is
/// never negative, so the value cannot be taken for one.
pub const BESIDE_EMITTER: f32 = -1.0;

/// The B-spline weight of a tap `k` steps from the centre, `|k| <= 2`:
/// 3/8, 1/4, 1/16 (a function, not a constant array: naga rejects the
/// array type rust-gpu emits for a constant indexed at run time).
#[inline]
fn bspline(k: i32) -> f32 {
    match k {
        0 => 0.375,
        -1 | 1 => 0.25,
        _ => 0.0625,
    }
}

/// The colour of pixel `(x, y)` with `w` set to the variance of the luma
/// over its 3x3 neighbourhood (pixels in the frame that are
/// [`filtered_surface`]s; 0 if there is none), or to [`BESIDE_EMITTER`] if
/// one of those neighbours (in the frame) sees an emitter.
#[inline]
pub fn variance_pixel(params: &FilterParams, x: u32, y: u32, color: &[Vec4], gbuffer: &[GBufferGpu]) -> Vec4 {
    let (w, h) = (params.width, params.height);
    let c = color[index(x, y, w)];
    let (mut n, mut sum, mut sum2) = (0.0f32, 0.0f32, 0.0f32);
    let mut beside_emitter = 0u32;
    let mut dy = 0;
    while dy < 3 {
        let mut dx = 0;
        while dx < 3 {
            let (qx, qy) = ((x + dx).wrapping_sub(1), (y + dy).wrapping_sub(1));
            if qx < w && qy < h {
                let gq = &gbuffer[index(qx, qy, w)];
                if filtered_surface(gq) {
                    let l = luma(color[index(qx, qy, w)].truncate());
                    n += 1.0;
                    sum += l;
                    sum2 += l * l;
                }
                if gq.ids.w & GBUFFER_EMITTER != 0 {
                    beside_emitter = 1;
                }
            }
            dx += 1;
        }
        dy += 1;
    }
    if beside_emitter == 1 {
        return c.truncate().extend(BESIDE_EMITTER);
    }
    let var = if n > 0.0 {
        let mean = sum / n;
        (sum2 / n - mean * mean).max(0.0)
    } else {
        0.0
    };
    c.truncate().extend(var)
}

/// One a-trous iteration at pixel `(x, y)`: `params.step` is the tap
/// distance in pixels (`2^iteration`); `src` colours with the luma variance
/// in `w` ([`variance_pixel`] for the first iteration, the previous
/// iteration's output after).
#[inline]
pub fn atrous_pixel(params: &FilterParams, x: u32, y: u32, src: &[Vec4], gbuffer: &[GBufferGpu]) -> Vec4 {
    let (w, h) = (params.width, params.height);
    let centre = src[index(x, y, w)];
    let g = &gbuffer[index(x, y, w)];
    if !filtered_surface(g) || centre.w == BESIDE_EMITTER {
        return centre;
    }
    let n_p = g.normal_depth.truncate();
    let z_p = g.normal_depth.w;
    let (gx, gy) = depth_gradient(gbuffer, w, h, x, y);
    let l_p = luma(centre.truncate());
    let l_scale = SIGMA_L * libm::sqrtf(centre.w.max(0.0)) + 1e-10;
    let step = params.step as i32;
    let mut sum = Vec3::ZERO;
    let mut sum_var = 0.0f32;
    let mut total = 0.0f32;
    let mut j = -2i32;
    while j <= 2 {
        let mut i = -2i32;
        while i <= 2 {
            let qx = x as i32 + i * step;
            let qy = y as i32 + j * step;
            if qx >= 0 && qy >= 0 && qx < w as i32 && qy < h as i32 {
                let q = index(qx as u32, qy as u32, w);
                let gq = &gbuffer[q];
                let c = src[q];
                if filtered_surface(gq) && c.w != BESIDE_EMITTER {
                    let expected = libm::fabsf(gx * (i * step) as f32 + gy * (j * step) as f32);
                    let w_z = -libm::fabsf(z_p - gq.normal_depth.w) / (SIGMA_Z * expected + 1e-4);
                    let w_l = -libm::fabsf(l_p - luma(c.truncate())) / l_scale;
                    let w_n = pow_normal(n_p.dot(gq.normal_depth.truncate()).max(0.0));
                    let k = bspline(i) * bspline(j);
                    let weight = k * w_n * libm::expf(w_z + w_l);
                    sum += c.truncate() * weight;
                    sum_var += weight * weight * c.w;
                    total += weight;
                }
            }
            i += 1;
        }
        j += 1;
    }
    // The centre tap has weight (3/8)^2 > 0, so `total > 0`.
    (sum / total).extend(sum_var / (total * total))
}

/// Whether the filter smooths texel `g` and uses it as a tap: a primary hit
/// that is not an emitter.
#[inline]
pub fn filtered_surface(g: &GBufferGpu) -> bool {
    g.ids.w & (GBUFFER_HIT | GBUFFER_EMITTER) == GBUFFER_HIT
}

/// `d^SIGMA_N` for `d` in `[0, 1]` by seven squarings (`2^7 = 128`).
#[inline]
fn pow_normal(d: f32) -> f32 {
    let mut v = d;
    let mut k = 0;
    while k < 7 {
        v *= v;
        k += 1;
    }
    v
}

/// Linear depth change per pixel at `(x, y)` along x and y: central
/// differences of the neighbours with a hit (one-sided at edges and beside
/// background; 0 where neither neighbour has one). Plain functions, no
/// closures: a closure capturing a buffer becomes a struct holding a
/// pointer, which naga rejects.
#[inline]
fn depth_gradient(gbuffer: &[GBufferGpu], w: u32, h: u32, x: u32, y: u32) -> (f32, f32) {
    let z = gbuffer[index(x, y, w)].normal_depth.w;
    let left = if x > 0 {
        depth_at(gbuffer, index(x - 1, y, w))
    } else {
        f32::MAX
    };
    let right = if x + 1 < w {
        depth_at(gbuffer, index(x + 1, y, w))
    } else {
        f32::MAX
    };
    let up = if y > 0 {
        depth_at(gbuffer, index(x, y - 1, w))
    } else {
        f32::MAX
    };
    let down = if y + 1 < h {
        depth_at(gbuffer, index(x, y + 1, w))
    } else {
        f32::MAX
    };
    (slope(z, left, right), slope(z, up, down))
}

/// The linear depth of texel `i`, or `f32::MAX` without a hit.
#[inline]
fn depth_at(gbuffer: &[GBufferGpu], i: usize) -> f32 {
    let g = &gbuffer[i];
    if g.ids.w & GBUFFER_HIT != 0 {
        g.normal_depth.w
    } else {
        f32::MAX
    }
}

/// Depth change per pixel at a texel of depth `z` between its neighbours
/// before (`a`) and after (`b`); `f32::MAX` marks a neighbour without a hit.
#[inline]
fn slope(z: f32, a: f32, b: f32) -> f32 {
    if a != f32::MAX && b != f32::MAX {
        0.5 * (b - a)
    } else if b != f32::MAX {
        b - z
    } else if a != f32::MAX {
        z - a
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::UVec4;

    fn surface(normal: Vec3, depth: f32, id: u32) -> GBufferGpu {
        GBufferGpu {
            normal_depth: normal.extend(depth),
            ids: UVec4::new(id, 0, 0, GBUFFER_HIT),
            ..Default::default()
        }
    }

    fn params(w: u32, h: u32, step: u32) -> FilterParams {
        FilterParams {
            width: w,
            height: h,
            step,
            ..Default::default()
        }
    }

    #[test]
    fn smooths_noise_on_one_plane_and_keeps_a_crease() {
        let (w, h) = (16u32, 8u32);
        // Left half faces +z, right half +x: a crease at x = 8. Depth is a
        // plane sloping along x.
        let gbuffer: Vec<GBufferGpu> = (0..w * h)
            .map(|i| {
                let x = i % w;
                let n = if x < 8 { Vec3::Z } else { Vec3::X };
                surface(n, 2.0 + 0.1 * x as f32, u32::from(x >= 8))
            })
            .collect();
        // Checkerboard noise around 1.0 on the left, 0.2 on the right.
        let color: Vec<Vec4> = (0..w * h)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                let base = if x < 8 { 1.0 } else { 0.2 };
                let n = if (x + y) % 2 == 0 { 0.05 } else { -0.05 };
                Vec4::splat(base + n)
            })
            .collect();
        let p = params(w, h, 1);
        let var: Vec<Vec4> = (0..w * h)
            .map(|i| variance_pixel(&p, i % w, i / w, &color, &gbuffer))
            .collect();
        assert!(var[(3 * w + 3) as usize].w > 0.0);
        let mut src = var;
        for it in 0..ATROUS_ITERATIONS {
            let p = params(w, h, 1 << it);
            src = (0..w * h)
                .map(|i| atrous_pixel(&p, i % w, i / w, &src, &gbuffer))
                .collect();
        }
        let rms = |lo: u32, hi: u32, base: f32| -> f32 {
            let mut s = 0.0;
            let mut n = 0.0;
            for y in 0..h {
                for x in lo..hi {
                    s += (src[(y * w + x) as usize].x - base).powi(2);
                    n += 1.0;
                }
            }
            (s / n).sqrt()
        };
        // Noise (0.05) mostly gone inside each half; the crease not blurred.
        assert!(rms(1, 7, 1.0) < 0.02, "left {}", rms(1, 7, 1.0));
        assert!(rms(9, 15, 0.2) < 0.02, "right {}", rms(9, 15, 0.2));
        assert!(rms(7, 8, 1.0) < 0.05 && rms(8, 9, 0.2) < 0.05, "crease blurred");
        // Variance shrinks with the iterations.
        assert!(src[(3 * w + 3) as usize].w < 0.0025 / 4.0);
    }

    #[test]
    fn background_and_emitters_pass_through_and_are_never_taps() {
        let (w, h) = (5u32, 5u32);
        let mut gbuffer = vec![surface(Vec3::Z, 1.0, 0); 25];
        gbuffer[12] = GBufferGpu::default();
        let mut color = vec![Vec4::new(1.0, 1.0, 1.0, 0.0); 25];
        color[12] = Vec4::new(50.0, 50.0, 50.0, 0.0);
        let p = params(w, h, 1);
        assert_eq!(atrous_pixel(&p, 2, 2, &color, &gbuffer), color[12]);
        let v = atrous_pixel(&p, 1, 2, &color, &gbuffer);
        assert!((v.x - 1.0).abs() < 1e-6, "{v}");
        // An emitter likewise: kept as it is, and not bled into its neighbours.
        gbuffer[12] = surface(Vec3::Z, 1.0, 0);
        gbuffer[12].ids.w |= crate::abi::GBUFFER_EMITTER;
        assert_eq!(atrous_pixel(&p, 2, 2, &color, &gbuffer), color[12]);
        let v = atrous_pixel(&p, 1, 2, &color, &gbuffer);
        assert!((v.x - 1.0).abs() < 1e-6, "{v}");
        // Its neighbours are the light's silhouette: marked, passed through
        // and never taps; a pixel two away is filtered as usual.
        assert_eq!(variance_pixel(&p, 1, 2, &color, &gbuffer).w, BESIDE_EMITTER);
        assert_eq!(variance_pixel(&p, 0, 2, &color, &gbuffer).w, 0.0);
        let mut marked: Vec<Vec4> = (0..25)
            .map(|i| variance_pixel(&p, i % 5, i / 5, &color, &gbuffer))
            .collect();
        marked[11] = Vec4::new(9.0, 9.0, 9.0, BESIDE_EMITTER);
        assert_eq!(atrous_pixel(&p, 1, 2, &marked, &gbuffer), marked[11]);
        let v = atrous_pixel(&p, 0, 2, &marked, &gbuffer);
        assert!((v.x - 1.0).abs() < 1e-6, "a marked pixel was used as a tap: {v}");
    }

    #[test]
    fn pow_normal_is_the_128th_power() {
        for d in [0.0f32, 0.5, 0.99, 1.0] {
            assert!((pow_normal(d) - d.powi(128)).abs() < 1e-6);
        }
    }
}
