//! The isotropic Trowbridge-Reitz (GGX) microfacet model: the normal
//! distribution `D`, Smith's masking `G1` and height-correlated
//! masking-shadowing `G2`, and sampling of the visible normals.
//!
//! # Conventions
//!
//! - Vectors are in the local shading frame, `z` along the macro-surface
//!   normal (`crate::sampling::Frame`), unit length, and point away from the
//!   surface: `wo` towards the viewer, `wi` towards the light, `h` the
//!   microfacet normal (for a reflection, the half vector
//!   `normalize(wo + wi)`).
//! - `alpha` is the GGX width, `roughness^2` for glTF's perceptual roughness
//!   ([`alpha_from_roughness`]), in `[`[`ALPHA_MIN`]`, 1]`.
//! - Densities are per steradian: `D` over microfacet normals (so that
//!   `int D(h) h.z dh = 1` over the hemisphere), [`reflected_pdf`] over `wi`.
//!
//! The formulas are those of Heitz 2014 ("Understanding the Masking-Shadowing
//! Function in Microfacet-Based BRDFs", JCGT 3(2)), rearranged so that no
//! term divides by a cosine: every function here is finite at grazing angles,
//! including `cos = 0`.

use core::f32::consts::{PI, TAU};
use glam::{Vec2, Vec3};

/// Smallest GGX `alpha` [`alpha_from_roughness`] returns (perceptual roughness
/// ~0.032). Keeps the peak of `D`, `1 / (pi alpha^2)` ~ 3.2e5 per steradian,
/// and the sample weights well inside f32, and the lobe (~1e-3 rad wide)
/// four orders of magnitude wider than the f32 rounding of a reflected
/// direction (~1e-7 rad), so evaluation and sampling still agree; smoother
/// surfaces render as this near-mirror. A choice, not a measurement.
pub const ALPHA_MIN: f32 = 1e-3;

/// GGX `alpha` of glTF's perceptual `roughness`: `roughness^2` (glTF 2.0,
/// appendix B, "Metal BRDF and Dielectric BRDF": `specular_brdf(roughness^2)`),
/// `roughness` clamped to `[0, 1]`
/// first and the result to at least [`ALPHA_MIN`]. Result in
/// `[ALPHA_MIN, 1]`; a NaN roughness gives `ALPHA_MIN`.
#[inline]
pub fn alpha_from_roughness(roughness: f32) -> f32 {
    // Not `f32::clamp`: it asserts `min <= max`, a panic path in shaders, and
    // passes NaN through; `max` then `min` maps NaN to 0.
    #[allow(clippy::manual_clamp)]
    let r = roughness.max(0.0).min(1.0);
    (r * r).max(ALPHA_MIN)
}

/// Normal distribution `D(h)` per steradian of microfacet normal:
/// `alpha^2 / (pi ((h.z)^2 (alpha^2 - 1) + 1)^2)` for `h.z > 0`, else 0.
///
/// Evaluated as `1 / (pi alpha^2 t^2)` with `t = (h.x^2 + h.y^2) / alpha^2 +
/// h.z^2`, which keeps its precision near the peak for small `alpha` (the
/// textbook form subtracts two numbers near 1). For unit `h` and `alpha <=
/// 1`, `t >= 1`, so the result is at most `1 / (pi alpha^2)`.
#[inline]
pub fn distribution(h: Vec3, alpha: f32) -> f32 {
    if h.z <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let t = (h.x * h.x + h.y * h.y) / a2 + h.z * h.z;
    1.0 / (PI * a2 * t * t)
}

/// `|w.z| (1 + 2 Lambda(w)) = sqrt(w.z^2 + alpha^2 (w.x^2 + w.y^2))`, the
/// common factor of the masking terms; `>= alpha |sin theta|`, so positive for
/// any unit `w` but the normal itself when `alpha` is 0.
#[inline]
fn masking_root(w: Vec3, alpha: f32) -> f32 {
    libm::sqrtf(w.z * w.z + alpha * alpha * (w.x * w.x + w.y * w.y))
}

/// Smith's auxiliary function `Lambda(w) = (sqrt(1 + alpha^2 tan^2) - 1) / 2`,
/// `>= 0`, for a direction at any side of the surface (it depends on `|w.z|`).
/// At the horizon (`w.z = 0`) Lambda is infinite: returns `f32::MAX`.
/// The kernels use the equivalent [`masking`] and [`masking_shadowing`],
/// which need no such special value.
#[inline]
pub fn lambda(w: Vec3, alpha: f32) -> f32 {
    let c = libm::fabsf(w.z);
    if c <= 0.0 {
        return f32::MAX;
    }
    0.5 * (masking_root(w, alpha) / c - 1.0)
}

/// Smith's masking `G1(w) = 1 / (1 + Lambda(w))`, in `[0, 1]`: the fraction
/// of the microfacets facing `w` that are visible from `w`. Evaluated as
/// `2 |w.z| / (|w.z| + sqrt(w.z^2 + alpha^2 (w.x^2 + w.y^2)))`: 0 at the
/// horizon, 1 along the normal.
#[inline]
pub fn masking(w: Vec3, alpha: f32) -> f32 {
    let c = libm::fabsf(w.z);
    let denom = c + masking_root(w, alpha);
    if denom <= 0.0 {
        return 0.0;
    }
    2.0 * c / denom
}

/// Height-correlated Smith masking-shadowing `G2(wo, wi) = 1 / (1 +
/// Lambda(wo) + Lambda(wi))` (Heitz 2014, eq. 99), in `[0, 1]`, for a
/// reflection (`wo`, `wi` on the same side). Evaluated as
/// `2 |co| |ci| / (|co| r_i + |ci| r_o)` with `r = sqrt(c^2 + alpha^2 s^2)`;
/// 0 when either direction is at the horizon.
#[inline]
pub fn masking_shadowing(wo: Vec3, wi: Vec3, alpha: f32) -> f32 {
    let (co, ci) = (libm::fabsf(wo.z), libm::fabsf(wi.z));
    let denom = co * masking_root(wi, alpha) + ci * masking_root(wo, alpha);
    if denom <= 0.0 {
        return 0.0;
    }
    2.0 * co * ci / denom
}

/// The visibility function `V = G2(wo, wi) / (4 |wo.z| |wi.z|)` of the glTF
/// specification (appendix B, "Specular BRDF", which uses this
/// height-correlated `G2`), so that the specular BRDF is `F D V`:
/// `0.5 / (|co| r_i + |ci| r_o)` with `r = sqrt(c^2 + alpha^2 s^2)` (the
/// specification's `sqrt(alpha^2 + (1 - alpha^2) c^2)` for unit vectors).
/// `>= 0`; finite when one direction is at the horizon (`0.5 / (alpha |ci|)`
/// when `wo` is), 0 when both are.
#[inline]
pub fn visibility(wo: Vec3, wi: Vec3, alpha: f32) -> f32 {
    let (co, ci) = (libm::fabsf(wo.z), libm::fabsf(wi.z));
    let denom = co * masking_root(wi, alpha) + ci * masking_root(wo, alpha);
    if denom <= 0.0 {
        return 0.0;
    }
    0.5 / denom
}

/// Mirror direction of `wo` about the unit normal `h`: `2 (wo . h) h - wo`.
#[inline]
pub fn reflect(wo: Vec3, h: Vec3) -> Vec3 {
    2.0 * wo.dot(h) * h - wo
}

/// A microfacet normal distributed as the normals visible from `wo`,
/// density [`visible_normal_pdf`], from `u` in `[0, 1)^2`: Dupuy & Benyoub
/// 2023, "Sampling Visible GGX Normals with Spherical Caps" (listing 3,
/// isotropic). `wo.z > 0` required (callers reject `wo` below the horizon).
///
/// The result is unit with `h.z >= 0` and `wo . h >= 0` (up to rounding).
/// `u.x` picks the azimuth; `u.y` the height on the spherical cap.
#[inline]
pub fn sample_visible_normal(wo: Vec3, alpha: f32, u: Vec2) -> Vec3 {
    // Stretch wo into the configuration of alpha = 1 (a hemisphere).
    let v = Vec3::new(wo.x * alpha, wo.y * alpha, wo.z).normalize();
    // Uniform point on the spherical cap z in (-v.z, 1].
    let phi = TAU * u.x;
    let z = (1.0 - u.y) * (1.0 + v.z) - v.z;
    let sin_theta = libm::sqrtf((1.0 - z * z).max(0.0));
    let (s, c) = libm::sincosf(phi);
    let h_std = Vec3::new(sin_theta * c, sin_theta * s, z) + v;
    // Unstretch. h_std.z >= 0; it is the zero vector only for a cap point
    // exactly opposite v, which u in [0, 1)^2 cannot reach but rounding
    // might: fall back to the normal.
    let h = Vec3::new(h_std.x * alpha, h_std.y * alpha, h_std.z);
    let len2 = h.length_squared();
    if len2 <= 0.0 {
        return Vec3::Z;
    }
    h * (1.0 / libm::sqrtf(len2))
}

/// Density per steradian of [`sample_visible_normal`]: the distribution of
/// visible normals `D_wo(h) = G1(wo) max(0, wo . h) D(h) / wo.z` (Heitz
/// 2018, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4),
/// eq. 3). 0 for `wo.z <= 0` or `h` facing away from `wo`.
#[inline]
pub fn visible_normal_pdf(wo: Vec3, h: Vec3, alpha: f32) -> f32 {
    let wo_h = wo.dot(h);
    if wo.z <= 0.0 || wo_h <= 0.0 {
        return 0.0;
    }
    // G1(wo) / wo.z = 2 / (wo.z + r_o): finite at grazing wo.
    2.0 * wo_h * distribution(h, alpha) / (wo.z + masking_root(wo, alpha))
}

/// Density per steradian of `wi = reflect(wo, h)` for `h` drawn by
/// [`sample_visible_normal`]: `D_wo(h) / (4 wo . h)` with `h =
/// normalize(wo + wi)`, which simplifies to `D(h) / (2 (wo.z + r_o))`,
/// `r_o = sqrt(wo.z^2 + alpha^2 (wo.x^2 + wo.y^2))`.
///
/// This is the density over the whole sphere: the reflected direction falls
/// below the horizon (`wi.z <= 0`) with the probability that light leaves the
/// single-scattering model there, and `reflected_pdf` is not 0 for such `wi`;
/// a BRDF that treats those as lost (as
/// [`super::metallic_roughness::MetallicRoughness::pdf`] does) cuts it at
/// the horizon. 0 for `wo.z <= 0`, for `wi = -wo`, or `h` below the surface.
#[inline]
pub fn reflected_pdf(wo: Vec3, wi: Vec3, alpha: f32) -> f32 {
    let sum = wo + wi;
    let len2 = sum.length_squared();
    if wo.z <= 0.0 || len2 <= 0.0 {
        return 0.0;
    }
    let h = sum * (1.0 / libm::sqrtf(len2));
    if wo.dot(h) <= 0.0 {
        return 0.0;
    }
    0.5 * distribution(h, alpha) / (wo.z + masking_root(wo, alpha))
}

#[cfg(test)]
mod tests {
    use super::*;
    use sampler_core::random_f32;

    const ALPHAS: [f32; 5] = [ALPHA_MIN, 0.01, 0.09, 0.36, 1.0];

    /// Unit direction at polar angle `theta`, azimuth `phi`.
    fn dir(theta: f32, phi: f32) -> Vec3 {
        Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos())
    }

    /// Midpoint rule over `theta` in `[0, theta_max]`, `phi` in `[0, 2 pi)`,
    /// weighted by the solid angle `sin theta dtheta dphi`; f64 sums.
    fn sphere_integral(theta_max: f64, nt: u32, np: u32, f: impl Fn(Vec3) -> f64) -> f64 {
        let (dt, dp) = (theta_max / nt as f64, core::f64::consts::TAU / np as f64);
        let mut sum = 0.0;
        for i in 0..nt {
            let t = (i as f64 + 0.5) * dt;
            let mut ring = 0.0;
            for j in 0..np {
                ring += f(dir(t as f32, ((j as f64 + 0.5) * dp) as f32));
            }
            sum += ring * t.sin();
        }
        sum * dt * dp
    }

    #[test]
    fn alpha_is_roughness_squared_clamped() {
        assert_eq!(alpha_from_roughness(0.5), 0.25);
        assert_eq!(alpha_from_roughness(1.0), 1.0);
        assert_eq!(alpha_from_roughness(2.0), 1.0);
        assert_eq!(alpha_from_roughness(0.0), ALPHA_MIN);
        assert_eq!(alpha_from_roughness(-1.0), ALPHA_MIN);
        assert_eq!(alpha_from_roughness(f32::NAN), ALPHA_MIN);
    }

    #[test]
    fn distribution_is_normalised_and_matches_the_textbook_form() {
        // int D(h) cos(theta_h) dh = 1 over the hemisphere (projected area).
        for alpha in [0.09f32, 0.36, 1.0] {
            let n = (2000.0 / alpha.sqrt()) as u32;
            let total = sphere_integral(core::f64::consts::FRAC_PI_2, n, 64, |h| {
                distribution(h, alpha) as f64 * h.z as f64
            });
            println!("int D cos dh, alpha {alpha}: {total:.6}");
            assert!((total - 1.0).abs() < 1e-3, "alpha {alpha}: {total}");
        }
        for alpha in ALPHAS {
            for i in 0..100 {
                let h = dir(1.5 * random_f32(1, i), TAU * random_f32(2, i));
                let a2 = alpha as f64 * alpha as f64;
                let c2 = (h.z as f64).powi(2);
                let textbook = a2 / (core::f64::consts::PI * (c2 * (a2 - 1.0) + 1.0).powi(2));
                let d = distribution(h, alpha) as f64;
                assert!(
                    (d - textbook).abs() <= 2e-4 * textbook,
                    "alpha {alpha}: {d} vs {textbook}"
                );
            }
            assert_eq!(distribution(Vec3::new(1.0, 0.0, -0.0), alpha), 0.0);
            assert_eq!(distribution(-Vec3::Z, alpha), 0.0);
        }
    }

    #[test]
    fn masking_forms_agree_with_lambda() {
        for alpha in ALPHAS {
            for i in 0..200 {
                let wo = dir(1.57 * random_f32(3, i), TAU * random_f32(4, i));
                let wi = dir(1.57 * random_f32(5, i), TAU * random_f32(6, i));
                let (lo, li) = (lambda(wo, alpha), lambda(wi, alpha));
                assert!(lo >= 0.0 && li >= 0.0);
                let g1 = masking(wo, alpha);
                assert!((g1 - 1.0 / (1.0 + lo)).abs() < 1e-5, "G1 at {wo}");
                let g2 = masking_shadowing(wo, wi, alpha);
                assert!((g2 - 1.0 / (1.0 + lo + li)).abs() < 1e-5, "G2 at {wo} {wi}");
                assert!(g2 <= g1.min(masking(wi, alpha)) + 1e-6, "G2 <= G1 each side");
                let v = visibility(wo, wi, alpha);
                let expected = g2 / (4.0 * wo.z * wi.z);
                assert!((v - expected).abs() <= 1e-4 * expected, "V at {wo} {wi}");
                // The specification's V_GGX form for unit vectors.
                let a2 = alpha * alpha;
                let spec = 0.5
                    / (wo.z * (wi.z * wi.z * (1.0 - a2) + a2).sqrt()
                        + wi.z * (wo.z * wo.z * (1.0 - a2) + a2).sqrt());
                assert!((v - spec).abs() <= 1e-4 * spec, "V_GGX at {wo} {wi}");
            }
        }
    }

    #[test]
    fn grazing_and_degenerate_directions_are_finite() {
        let horizon = Vec3::X;
        let up = Vec3::Z;
        for alpha in ALPHAS {
            assert_eq!(masking(horizon, alpha), 0.0);
            assert_eq!(masking(up, alpha), 1.0);
            assert_eq!(lambda(horizon, alpha), f32::MAX);
            assert_eq!(lambda(up, alpha), 0.0);
            assert_eq!(masking_shadowing(horizon, up, alpha), 0.0);
            assert_eq!(visibility(horizon, horizon, alpha), 0.0);
            let v = visibility(horizon, up, alpha);
            assert!(v.is_finite() && (v - 0.5 / alpha).abs() <= 1e-5 * v, "{v}");
            assert_eq!(reflected_pdf(horizon, up, alpha), 0.0, "wo at the horizon");
            assert_eq!(reflected_pdf(up, -up, alpha), 0.0, "wi = -wo");
            let grazing = Vec3::new(1.0, 0.0, 1e-6).normalize();
            for u in [Vec2::ZERO, Vec2::splat(0.5), Vec2::splat(1.0 - f32::EPSILON)] {
                let h = sample_visible_normal(grazing, alpha, u);
                assert!(
                    h.is_finite() && (h.length() - 1.0).abs() < 1e-5 && h.z >= 0.0,
                    "{h}"
                );
                let p = reflected_pdf(grazing, reflect(grazing, h), alpha);
                assert!(p.is_finite() && p >= 0.0, "{p}");
            }
        }
    }

    #[test]
    fn visible_normals_are_visible_and_normalised() {
        for alpha in [0.09f32, 0.36, 1.0] {
            for cos_o in [0.1f32, 0.5, 0.95] {
                let wo = Vec3::new((1.0 - cos_o * cos_o).sqrt(), 0.0, cos_o);
                // int D_wo(h) dh = 1 over the hemisphere (Heitz 2018, eq. 2).
                let total = sphere_integral(core::f64::consts::FRAC_PI_2, 1500, 1024, |h| {
                    visible_normal_pdf(wo, h, alpha) as f64
                });
                println!("int D_wo dh, alpha {alpha} cos_o {cos_o}: {total:.6}");
                assert!((total - 1.0).abs() < 2e-3, "alpha {alpha} cos {cos_o}: {total}");
                // The reflected density covers the sphere, horizon cut included.
                let total = sphere_integral(core::f64::consts::PI, 3000, 1024, |wi| {
                    reflected_pdf(wo, wi, alpha) as f64
                });
                println!("int reflected_pdf dwi over the sphere, alpha {alpha} cos_o {cos_o}: {total:.6}");
                assert!(
                    (total - 1.0).abs() < 2e-3,
                    "reflected, alpha {alpha} cos {cos_o}: {total}"
                );
                for i in 0..1000 {
                    let u = Vec2::new(random_f32(7, 2 * i), random_f32(7, 2 * i + 1));
                    let h = sample_visible_normal(wo, alpha, u);
                    assert!(
                        (h.length() - 1.0).abs() < 1e-5 && h.z >= 0.0 && wo.dot(h) >= -1e-6,
                        "{h}"
                    );
                    let wi = reflect(wo, h);
                    let via_h = visible_normal_pdf(wo, h, alpha) / (4.0 * wo.dot(h));
                    let p = reflected_pdf(wo, wi, alpha);
                    assert!((p - via_h).abs() <= 1e-3 * via_h, "{p} vs {via_h}");
                }
            }
        }
    }
}
