//! Statistical checks of `kernels::bsdf`: the GGX albedo two ways, the
//! sampler's density against its histogram (chi-square), the density's
//! normalisation, and white furnaces of the glTF metallic-roughness BRDF.
//!
//! Every estimate is compared with a deterministic quadrature of the same
//! integral. Quadratures use the midpoint rule on a grid in `(theta, phi)`
//! over the upper hemisphere, weighted by `sin theta` (solid angle), summed in
//! f64; `wo` lies in the `xz` plane, so integrands are even in `phi` and the
//! grid covers `phi` in `[0, pi]`, doubled. Random numbers come from
//! `sampler_core::random_f32` (white, hashed from a seed and an index), so
//! every run draws the same samples. Run with `--nocapture` for the tables.

use core::f64::consts::{FRAC_PI_2, PI};
use glam::{Vec2, Vec3};
use kernels::bsdf::ggx::{
    alpha_from_roughness, distribution, masking, masking_shadowing, reflect, reflected_pdf,
    sample_visible_normal, visibility,
};
use kernels::bsdf::{BsdfSample, MetallicRoughness};
use sampler_core::random_f32;

/// Roughness and `cos(theta_o)` grid of the albedo tables.
const ROUGHNESS: [f32; 4] = [0.1, 0.3, 0.6, 1.0];
const COS_O: [f32; 3] = [0.2, 0.5, 0.9];

/// Quadrature grid: `theta` steps over `[0, pi/2]`, `phi` steps over
/// `[0, pi]`. Steps of ~1.5e-3 rad in `theta` and ~7.7e-4 in `phi` resolve the
/// narrowest lobe integrated (roughness 0.1, alpha 0.01, whose reflected lobe
/// is ~3e-3 rad wide across the plane of incidence at `cos_o = 0.2`) with
/// several steps per width; doubling both moved no quadrature in the tables
/// by more than 1e-6 relative (checked when the grid was chosen).
const THETA_STEPS: u32 = 1024;
const PHI_STEPS: u32 = 4096;

/// Samples per Monte Carlo estimate.
const SAMPLES: u32 = 1 << 18;

/// `wo` at `cos_o` from the normal, in the `xz` plane.
fn wo_at(cos_o: f32) -> Vec3 {
    Vec3::new((1.0 - cos_o * cos_o).max(0.0).sqrt(), 0.0, cos_o)
}

/// Unit direction at polar angle `theta`, azimuth `phi`.
fn dir(theta: f64, phi: f64) -> Vec3 {
    Vec3::new(
        (theta.sin() * phi.cos()) as f32,
        (theta.sin() * phi.sin()) as f32,
        theta.cos() as f32,
    )
}

/// `int f(wi) dwi` over the upper hemisphere for an integrand even in `phi`
/// (module doc).
fn hemisphere_integral(f: impl Fn(Vec3) -> f64) -> f64 {
    let (dt, dp) = (FRAC_PI_2 / THETA_STEPS as f64, PI / PHI_STEPS as f64);
    let mut sum = 0.0;
    for i in 0..THETA_STEPS {
        let theta = (i as f64 + 0.5) * dt;
        let mut ring = 0.0;
        for j in 0..PHI_STEPS {
            ring += f(dir(theta, (j as f64 + 0.5) * dp));
        }
        sum += ring * theta.sin();
    }
    2.0 * sum * dt * dp
}

/// Mean and standard error of `SAMPLES` values of `f(i)`.
fn monte_carlo(f: impl Fn(u32) -> f64) -> (f64, f64) {
    let (mut s, mut s2) = (0.0, 0.0);
    for i in 0..SAMPLES {
        let x = f(i);
        s += x;
        s2 += x * x;
    }
    let n = SAMPLES as f64;
    let mean = s / n;
    (mean, ((s2 / n - mean * mean).max(0.0) / n).sqrt())
}

/// The three numbers of sample `i` of stream `seed`: `u` and `u_lobe`.
fn numbers(seed: u32, i: u32) -> (Vec2, f32) {
    let u = Vec2::new(random_f32(seed, 3 * i), random_f32(seed, 3 * i + 1));
    (u, random_f32(seed, 3 * i + 2))
}

/// GGX directional albedo with `F = 1`, `E(wo) = int D G2 / (4 co ci) ci
/// dwi`, by quadrature.
fn ggx_albedo_quadrature(wo: Vec3, alpha: f32) -> f64 {
    hemisphere_integral(|wi| {
        let h = (wo + wi).normalize();
        (distribution(h, alpha) * visibility(wo, wi, alpha) * wi.z) as f64
    })
}

#[test]
fn ggx_albedo_importance_sampled_equals_quadrature() {
    println!(
        "GGX directional albedo, F = 1 (importance sampling with VNDF, {SAMPLES} samples / quadrature):"
    );
    println!("| roughness | cos_o | VNDF estimate | std. error | quadrature | rel. diff |");
    println!("|---|---|---|---|---|---|");
    for roughness in ROUGHNESS {
        let alpha = alpha_from_roughness(roughness);
        for cos_o in COS_O {
            let wo = wo_at(cos_o);
            let quadrature = ggx_albedo_quadrature(wo, alpha);
            // f cos / pdf with the sampler's own density (not the closed form
            // G2 / G1): the estimate is right only if the density is the
            // sampler's.
            let (estimate, error) = monte_carlo(|i| {
                let (u, _) = numbers(1, i);
                let wi = reflect(wo, sample_visible_normal(wo, alpha, u));
                if wi.z <= 0.0 {
                    return 0.0;
                }
                let h = (wo + wi).normalize();
                let f = distribution(h, alpha) * visibility(wo, wi, alpha);
                let w = (f * wi.z / reflected_pdf(wo, wi, alpha)) as f64;
                // The same weight in closed form (Heitz 2018, eq. 19).
                let closed = (masking_shadowing(wo, wi, alpha) / masking(wo, alpha)) as f64;
                assert!((w - closed).abs() <= 1e-3 * closed.max(1e-6), "{w} vs {closed}");
                w
            });
            let rel = (estimate - quadrature) / quadrature;
            println!("| {roughness} | {cos_o} | {estimate:.5} | {error:.5} | {quadrature:.5} | {rel:+.2e} |");
            assert!(
                rel.abs() < 0.01,
                "roughness {roughness}, cos_o {cos_o}: {estimate} vs {quadrature}"
            );
            assert!(
                quadrature <= 1.0 + 1e-4,
                "single scattering never gains energy: {quadrature}"
            );
            if roughness == 0.1 && cos_o == 0.9 {
                assert!(
                    quadrature > 0.995,
                    "a smooth lobe near the normal keeps its energy: {quadrature}"
                );
            }
        }
    }
}

/// `int pdf(wo, wi) dwi` over the upper hemisphere plus the fraction of
/// failed samples is 1: the sampler's directions below the horizon are
/// exactly the density's missing mass.
#[test]
fn density_integrates_to_one_with_the_lost_reflections() {
    println!("int pdf over the hemisphere + fraction of failed samples ({SAMPLES} samples):");
    println!("| metallic | roughness | cos_o | int pdf | failed | sum |");
    println!("|---|---|---|---|---|---|");
    for metallic in [0.0f32, 1.0] {
        for roughness in ROUGHNESS {
            let m = MetallicRoughness::new(Vec3::new(0.8, 0.6, 0.3), metallic, roughness);
            for cos_o in COS_O {
                let wo = wo_at(cos_o);
                let integral = hemisphere_integral(|wi| m.pdf(wo, wi) as f64);
                let (failed, error) = monte_carlo(|i| {
                    let (u, u_lobe) = numbers(2, i);
                    (m.sample(wo, u, u_lobe) == BsdfSample::NONE) as u32 as f64
                });
                let sum = integral + failed;
                println!("| {metallic} | {roughness} | {cos_o} | {integral:.5} | {failed:.5} | {sum:.5} |");
                assert!(integral <= 1.0 + 1e-3, "{integral}");
                assert!(
                    (sum - 1.0).abs() <= 5.0 * error + 1e-3,
                    "{m:?} cos_o {cos_o}: {sum}"
                );
            }
        }
    }
}

/// Upper tail `P(X >= x)` of a chi-square variable with `dof` degrees of
/// freedom, by the Wilson-Hilferty normal approximation of `(X / dof)^(1/3)`
/// (Wilson & Hilferty 1931; close enough for a pass/fail threshold at the
/// hundreds of degrees of freedom used here).
fn chi_square_p_value(x: f64, dof: f64) -> f64 {
    let v = 2.0 / (9.0 * dof);
    let z = ((x / dof).cbrt() - (1.0 - v)) / v.sqrt();
    0.5 * libm::erfc(z / core::f64::consts::SQRT_2)
}

const COS_BINS: usize = 16;
const PHI_BINS: usize = 32;
/// Midpoint sub-cells per bin side for the expected counts.
const SUB: usize = 32;

/// Cell of `wi` (upper hemisphere) in the `(cos theta, phi)` histogram.
fn cell(wi: Vec3) -> usize {
    let c = ((wi.z * COS_BINS as f32) as usize).min(COS_BINS - 1);
    let phi = (wi.y as f64)
        .atan2(wi.x as f64)
        .rem_euclid(core::f64::consts::TAU);
    let p = ((phi / core::f64::consts::TAU * PHI_BINS as f64) as usize).min(PHI_BINS - 1);
    c * PHI_BINS + p
}

/// Pearson's chi-square of the sampler's directions against its density, on
/// `COS_BINS x PHI_BINS` cells equal in `(cos theta, phi)` (so the density
/// integrates over a cell by a midpoint rule in those coordinates, `dw = dcos
/// dphi`) plus one cell for the failed samples; cells expecting fewer than 5
/// samples are pooled (Mitsuba's `ChiSquareTest` does the same). Returns
/// `(chi2, dof)`.
fn chi_square(m: &MetallicRoughness, wo: Vec3, seed: u32) -> (f64, usize) {
    let n = SAMPLES as f64;
    let mut expected = vec![0.0f64; COS_BINS * PHI_BINS + 1];
    let (dc, dp) = (
        1.0 / (COS_BINS * SUB) as f64,
        core::f64::consts::TAU / (PHI_BINS * SUB) as f64,
    );
    for i in 0..COS_BINS * SUB {
        let cos = (i as f64 + 0.5) * dc;
        let sin = (1.0 - cos * cos).sqrt();
        for j in 0..PHI_BINS * SUB {
            let phi = (j as f64 + 0.5) * dp;
            let wi = Vec3::new((sin * phi.cos()) as f32, (sin * phi.sin()) as f32, cos as f32);
            expected[(i / SUB) * PHI_BINS + j / SUB] += m.pdf(wo, wi) as f64 * dc * dp * n;
        }
    }
    let inside: f64 = expected.iter().sum();
    expected[COS_BINS * PHI_BINS] = (n - inside).max(0.0);
    let mut observed = vec![0u64; expected.len()];
    for i in 0..SAMPLES {
        let (u, u_lobe) = numbers(seed, i);
        let s = m.sample(wo, u, u_lobe);
        if s.pdf > 0.0 {
            observed[cell(s.wi)] += 1;
        } else {
            observed[COS_BINS * PHI_BINS] += 1;
        }
    }
    let (mut chi2, mut cells) = (0.0, 0);
    let (mut pooled_e, mut pooled_o) = (0.0, 0.0);
    for (&e, &o) in expected.iter().zip(&observed) {
        if e < 5.0 {
            pooled_e += e;
            pooled_o += o as f64;
        } else {
            chi2 += (o as f64 - e).powi(2) / e;
            cells += 1;
        }
    }
    if pooled_e >= 5.0 {
        chi2 += (pooled_o - pooled_e).powi(2) / pooled_e;
        cells += 1;
    } else {
        assert!(
            pooled_o <= 20.0,
            "{pooled_o} samples where {pooled_e} were expected"
        );
    }
    (chi2, cells - 1)
}

#[test]
fn sampled_directions_follow_the_density() {
    let configs: Vec<(f32, f32, f32)> = [0.2f32, 0.5, 1.0]
        .iter()
        .flat_map(|&r| [0.0f32, 0.5, 1.0].map(move |m| (r, m)))
        .flat_map(|(r, m)| [0.3f32, 0.8].map(move |c| (r, m, c)))
        .collect();
    // Bonferroni: 1% for the whole family.
    let significance = 0.01 / configs.len() as f64;
    println!("chi-square of {SAMPLES} sampled directions against the density ({COS_BINS} x {PHI_BINS} cells + failed):");
    println!("| roughness | metallic | cos_o | chi2 | dof | p |");
    println!("|---|---|---|---|---|---|");
    for (k, &(roughness, metallic, cos_o)) in configs.iter().enumerate() {
        let m = MetallicRoughness::new(Vec3::new(0.8, 0.6, 0.3), metallic, roughness);
        let (chi2, dof) = chi_square(&m, wo_at(cos_o), 100 + k as u32);
        let p = chi_square_p_value(chi2, dof as f64);
        println!("| {roughness} | {metallic} | {cos_o} | {chi2:.1} | {dof} | {p:.3} |");
        assert!(dof >= 10, "too few cells to test: {dof}");
        assert!(
            p > significance,
            "{m:?} cos_o {cos_o}: chi2 {chi2} with {dof} dof, p = {p}"
        );
    }
}

#[test]
fn metal_white_furnace_equals_the_ggx_albedo() {
    // Base colour 1, metallic 1: F = 1, the material is the GGX lobe alone.
    println!(
        "white furnace, metallic 1, base colour 1 (mean sample weight, {SAMPLES} samples / quadrature):"
    );
    println!("| roughness | cos_o | mean weight | std. error | quadrature |");
    println!("|---|---|---|---|---|");
    for roughness in ROUGHNESS {
        let m = MetallicRoughness::new(Vec3::ONE, 1.0, roughness);
        for cos_o in COS_O {
            let wo = wo_at(cos_o);
            let quadrature = hemisphere_integral(|wi| (m.eval(wo, wi).x * wi.z) as f64);
            let ggx = ggx_albedo_quadrature(wo, m.alpha());
            assert!((quadrature - ggx).abs() <= 1e-5, "{quadrature} vs GGX {ggx}");
            let (mean, error) = monte_carlo(|i| {
                let (u, u_lobe) = numbers(3, i);
                let s = m.sample(wo, u, u_lobe);
                assert!(s.weight.x == s.weight.y && s.weight.y == s.weight.z);
                s.weight.x as f64
            });
            println!("| {roughness} | {cos_o} | {mean:.5} | {error:.5} | {quadrature:.5} |");
            assert!(
                (mean - quadrature).abs() <= 5.0 * error + 1e-3 * quadrature,
                "{mean} vs {quadrature}"
            );
            assert!(quadrature <= 1.0 + 1e-4);
        }
    }
}

/// Base colour 1, metallic 0. The specification's Fresnel mix weights the
/// diffuse lobe by `1 - F(|wo . h|)`, about 0.96 for most `wi`, while the
/// specular lobe reflects up to `F(wo.z)`: the sum exceeds 1 at grazing `wo`
/// and low roughness (1.30 at roughness 0.1, `cos_o` 0.2), as the
/// specification warns (appendix B, "Coupling Diffuse and Specular
/// Reflection": `fresnel_mix` "breaks ... energy conservation"). The test pins what
/// the model does: the sampler's mean weight equals the quadrature; no gain
/// near the normal (`cos_o = 0.9`) or at roughness 1; and everywhere at most
/// `0.96 + E_ggx(wo)`, the bound the model's two terms obey.
#[test]
fn dielectric_white_furnace_gains_only_at_grazing() {
    println!(
        "white furnace, metallic 0, base colour 1 (mean sample weight, {SAMPLES} samples / quadrature):"
    );
    println!("| roughness | cos_o | mean weight | std. error | quadrature |");
    println!("|---|---|---|---|---|");
    for roughness in ROUGHNESS {
        let m = MetallicRoughness::new(Vec3::ONE, 0.0, roughness);
        for cos_o in COS_O {
            let wo = wo_at(cos_o);
            let quadrature = hemisphere_integral(|wi| (m.eval(wo, wi).x * wi.z) as f64);
            let (mean, error) = monte_carlo(|i| {
                let (u, u_lobe) = numbers(4, i);
                m.sample(wo, u, u_lobe).weight.x as f64
            });
            println!("| {roughness} | {cos_o} | {mean:.5} | {error:.5} | {quadrature:.5} |");
            assert!(
                (mean - quadrature).abs() <= 5.0 * error + 1e-3 * quadrature,
                "{mean} vs {quadrature}"
            );
            if cos_o >= 0.9 || roughness == 1.0 {
                assert!(
                    quadrature <= 1.0 + 1e-3,
                    "roughness {roughness}, cos_o {cos_o}: {quadrature}"
                );
            }
            let bound = 0.96 + ggx_albedo_quadrature(wo, m.alpha());
            assert!(quadrature <= bound + 1e-4, "{quadrature} above {bound}");
        }
    }
}
