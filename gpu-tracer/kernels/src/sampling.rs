//! Warps from the unit square to the directions and points the path tracer
//! samples, with their densities.
//!
//! Every warp takes numbers in `[0, 1)` and is deterministic, so the same
//! stream gives the same path on the host and on the GPU.

use core::f32::consts::{FRAC_1_PI, TAU};
use glam::{Vec2, Vec3};

/// An orthonormal basis `(tangent, bitangent, normal)`, right-handed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// First tangent, unit length, orthogonal to `normal`.
    pub tangent: Vec3,
    /// Second tangent, `normal x tangent`.
    pub bitangent: Vec3,
    /// The unit normal the frame was built around.
    pub normal: Vec3,
}

impl Frame {
    /// Basis around the unit vector `normal`, without branches on its
    /// direction other than the sign of `z` (Duff et al. 2017, "Building an
    /// Orthonormal Basis, Revisited", JCGT 6(1)).
    #[inline]
    pub fn from_normal(normal: Vec3) -> Self {
        let sign = libm::copysignf(1.0, normal.z);
        let a = -1.0 / (sign + normal.z);
        let b = normal.x * normal.y * a;
        let tangent = Vec3::new(1.0 + sign * normal.x * normal.x * a, sign * b, -sign * normal.x);
        let bitangent = Vec3::new(b, sign + normal.y * normal.y * a, -normal.y);
        Frame {
            tangent,
            bitangent,
            normal,
        }
    }

    /// World vector of local coordinates `(x, y, z)` (z along the normal).
    #[inline]
    pub fn to_world(&self, local: Vec3) -> Vec3 {
        self.tangent * local.x + self.bitangent * local.y + self.normal * local.z
    }
}

/// Uniform direction in the cone of half-angle `theta_max` around `+z`,
/// from `u` in `[0, 1)^2`, given `one_minus_cos_max = 1 - cos(theta_max)`
/// in `(0, 2]` (passed instead of the angle so that small cones keep their
/// precision). Density per solid angle: `1 / (2 pi one_minus_cos_max)`.
///
/// `cos theta = 1 - u.x * one_minus_cos_max`, `phi = 2 pi u.y`; `sin theta`
/// from `(1 - cos)(1 + cos)`, exact for small angles.
#[inline]
pub fn sample_uniform_cone(u: Vec2, one_minus_cos_max: f32) -> Vec3 {
    let one_minus_cos = u.x * one_minus_cos_max;
    let cos_theta = 1.0 - one_minus_cos;
    let sin_theta = libm::sqrtf((one_minus_cos * (2.0 - one_minus_cos)).max(0.0));
    let phi = TAU * u.y;
    Vec3::new(
        sin_theta * libm::cosf(phi),
        sin_theta * libm::sinf(phi),
        cos_theta,
    )
}

/// Cosine-weighted direction on the hemisphere around `+z`, from `u` in
/// `[0, 1)^2`. Density per solid angle: [`cosine_hemisphere_pdf`]`(z)`.
///
/// Polar map of the disk (`r = sqrt(u.x)`, `phi = 2 pi u.y`) projected up.
/// `z >= 0`; `z` can be 0 only for `u.x` rounding to 1.
#[inline]
pub fn sample_cosine_hemisphere(u: Vec2) -> Vec3 {
    let r = libm::sqrtf(u.x);
    let phi = TAU * u.y;
    let z = libm::sqrtf((1.0 - u.x).max(0.0));
    Vec3::new(r * libm::cosf(phi), r * libm::sinf(phi), z)
}

/// Density per steradian of [`sample_cosine_hemisphere`] for a direction at
/// `cos_theta` from the axis: `cos_theta / pi` (0 below the horizon).
#[inline]
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta.max(0.0) * FRAC_1_PI
}

/// Barycentrics `(b1, b2)` (weights of the second and third vertex) of a
/// point uniformly distributed over a triangle, from `u` in `[0, 1)^2`
/// (square-root parametrisation; density `1 / area` per unit area).
#[inline]
pub fn sample_triangle_barycentrics(u: Vec2) -> Vec2 {
    let su = libm::sqrtf(u.x);
    Vec2::new(su * (1.0 - u.y), su * u.y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use sampler_core::random_f32;

    fn u2(i: u32) -> Vec2 {
        Vec2::new(random_f32(7, 2 * i), random_f32(7, 2 * i + 1))
    }

    #[test]
    fn frame_is_orthonormal() {
        for i in 0..1000 {
            let u = u2(i);
            // Uniform sphere directions, including near -z where naive formulas break.
            let z = 1.0 - 2.0 * u.x;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let n = Vec3::new(r * (TAU * u.y).cos(), r * (TAU * u.y).sin(), z).normalize();
            let f = Frame::from_normal(n);
            for (a, b) in [
                (f.tangent, f.bitangent),
                (f.tangent, f.normal),
                (f.bitangent, f.normal),
            ] {
                assert!(a.dot(b).abs() < 1e-5, "{n}");
            }
            for v in [f.tangent, f.bitangent] {
                assert!((v.length() - 1.0).abs() < 1e-5, "{n}");
            }
            assert!(
                (f.tangent.cross(f.bitangent) - n).length() < 1e-5,
                "right-handed at {n}"
            );
        }
        let down = Frame::from_normal(-Vec3::Z);
        assert!((down.to_world(Vec3::Z) + Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn cosine_sampling_has_the_right_moments() {
        // For p = cos/pi: E[z] = 2/3, E[z^2] = 1/2, E[x] = E[y] = 0.
        let n = 200_000;
        let (mut sz, mut sz2, mut sx, mut sy) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for i in 0..n {
            let d = sample_cosine_hemisphere(u2(i));
            assert!((d.length() - 1.0).abs() < 1e-5 && d.z >= 0.0);
            sz += d.z as f64;
            sz2 += (d.z * d.z) as f64;
            sx += d.x as f64;
            sy += d.y as f64;
        }
        let n = n as f64;
        // Standard errors are about 0.0005; allow ~8 sigma.
        assert!((sz / n - 2.0 / 3.0).abs() < 0.004, "E[z] = {}", sz / n);
        assert!((sz2 / n - 0.5).abs() < 0.004, "E[z^2] = {}", sz2 / n);
        assert!((sx / n).abs() < 0.004 && (sy / n).abs() < 0.004);
        // The pdf integrates to 1 over the hemisphere: int cos/pi dw = 1.
        assert!((cosine_hemisphere_pdf(1.0) - FRAC_1_PI).abs() < 1e-7);
        assert_eq!(cosine_hemisphere_pdf(-0.5), 0.0);
    }

    #[test]
    fn triangle_points_are_uniform() {
        // Uniform over the triangle (0,0),(1,0),(0,1) in (b1, b2): mean (1/3, 1/3),
        // and a quarter of the points fall in each of the 4 midpoint sub-triangles.
        let n = 100_000;
        let mut mean = Vec2::ZERO;
        let mut corner = [0u32; 3];
        for i in 0..n {
            let b = sample_triangle_barycentrics(u2(i));
            assert!(b.x >= 0.0 && b.y >= 0.0 && b.x + b.y <= 1.0 + 1e-6);
            mean += b;
            let b0 = 1.0 - b.x - b.y;
            for (k, w) in [b0, b.x, b.y].into_iter().enumerate() {
                if w > 0.5 {
                    corner[k] += 1;
                }
            }
        }
        mean /= n as f32;
        assert!((mean - Vec2::splat(1.0 / 3.0)).length() < 0.005, "{mean}");
        for c in corner {
            let frac = c as f64 / n as f64;
            assert!((frac - 0.25).abs() < 0.01, "{frac}");
        }
    }

    #[test]
    fn cone_sampling_is_uniform_in_the_cone() {
        // Uniform in the cone: cos theta uniform on [cos_max, 1], so E[z] is
        // the midpoint; phi uniform, so E[x] = E[y] = 0; no direction leaves it.
        for one_minus_cos_max in [1e-4f32, 0.05, 1.0] {
            let n = 50_000;
            let cos_max = 1.0 - one_minus_cos_max as f64;
            let (mut sz, mut sx) = (0.0f64, 0.0f64);
            for i in 0..n {
                let d = sample_uniform_cone(u2(i), one_minus_cos_max);
                assert!((d.length() - 1.0).abs() < 1e-5, "{d}");
                assert!(d.z as f64 >= cos_max - 1e-6, "{d} outside {one_minus_cos_max}");
                sz += d.z as f64;
                sx += d.x as f64;
            }
            let mid = 0.5 * (1.0 + cos_max);
            let tol = 0.01 * one_minus_cos_max as f64 + 1e-6;
            assert!(
                (sz / n as f64 - mid).abs() < tol,
                "E[z] = {} for {one_minus_cos_max}",
                sz / n as f64
            );
            let sin_max = (1.0 - cos_max * cos_max).sqrt();
            assert!((sx / n as f64).abs() < 0.02 * sin_max + 1e-6);
        }
    }
}
