//! Statistical and end-to-end checks of `sampler_core::distributions`,
//! through the public API.
//!
//! Piecewise-constant distributions: the inverse CDF is monotone and
//! continuous, the pdf is normalised and matches the weights, sampled cells
//! pass a chi-square test, zero weights fall back to uniform, one non-zero
//! cell takes every sample.
//!
//! Environment maps: the pdf returned is the pdf of the direction returned,
//! the texels drawn follow their weights (chi-square), and
//! importance-sampled integrals agree with uniform sphere sampling and with
//! the exact texel sums.
//!
//! Random numbers come from the crate's counter-based hash (`random_f32`),
//! so every run draws the same samples and the statistical tolerances (5
//! standard errors, chi-square at p ~ 1e-6) cannot flake.

use glam::{UVec2, Vec2, Vec3};
use sampler_core::distributions::environment::{direction_to_uv, luminance, texel_weight, MIN_SIN_THETA};
use sampler_core::{random_f32, Distribution1d, Distribution2d, EnvironmentMap};
use std::f64::consts::PI;

/// Random weights in `[0, 1)`, about a quarter of them 0.
fn random_weights(n: u32, seed: u32) -> Vec<f32> {
    (0..n)
        .map(|i| {
            let w = random_f32(seed, 2 * i);
            if random_f32(seed, 2 * i + 1) < 0.25 {
                0.0
            } else {
                w
            }
        })
        .collect()
}

fn build_2d(width: u32, height: u32, weights: &[f32]) -> Vec<f32> {
    let mut table = vec![0.0; Distribution2d::table_len(width, height)];
    Distribution2d::build(width, height, weights, &mut table).unwrap();
    table
}

/// The cell of `[0, 1)` split in `n` that contains `x`.
fn cell_of(x: f32, n: u32) -> u32 {
    ((x * n as f32) as u32).min(n - 1)
}

/// The inverse CDF is non-decreasing, and continuous with slope
/// `1 / pdf` where every weight is positive.
#[test]
fn sampling_is_monotone_and_continuous() {
    let weights: Vec<f32> = (0..13).map(|i| 0.2 + random_f32(5, i)).collect();
    let mut table = vec![0.0; 14];
    let d = Distribution1d::build(&weights, &mut table).unwrap();
    let min_pdf = (0..13)
        .map(|i| d.pdf((i as f32 + 0.5) / 13.0))
        .fold(f32::MAX, f32::min);
    let steps = 100_000;
    let mut last = d.sample(0.0).x;
    for k in 1..steps {
        let x = d.sample(k as f32 / steps as f32).x;
        assert!(x >= last, "not monotone at step {k}");
        assert!(
            x - last <= 1.01 / (steps as f32 * min_pdf) + 1e-6,
            "jump at step {k}"
        );
        last = x;
    }
    // With empty cells it is still monotone; it jumps over them.
    let mut table = [0.0; 5];
    let d = Distribution1d::build(&[1.0, 0.0, 0.0, 1.0], &mut table).unwrap();
    assert_eq!(d.sample(0.499_999_97).index, 0);
    assert_eq!(d.sample(0.5).x, 0.75);
}

/// The pdf is normalised, and cell masses are the weights' shares.
#[test]
fn pdf_integrates_to_one_and_matches_weights() {
    let (width, height) = (9, 4);
    let weights = random_weights(36, 7);
    let table = build_2d(width, height, &weights);
    let d = Distribution2d::new(width, height, &table).unwrap();
    let sum: f64 = weights.iter().map(|&w| w as f64).sum();
    assert!((d.integral() as f64 - sum / 36.0).abs() < 1e-6);
    let mut total = 0.0f64;
    for y in 0..height {
        for x in 0..width {
            let p = Vec2::new((x as f32 + 0.5) / width as f32, (y as f32 + 0.5) / height as f32);
            let mass = d.pdf(p) as f64 / 36.0;
            let want = weights[(y * width + x) as usize] as f64 / sum;
            assert!((mass - want).abs() < 1e-6, "cell ({x}, {y}): {mass} vs {want}");
            total += mass;
        }
    }
    assert!((total - 1.0).abs() < 1e-5);
}

/// Chi-square upper quantile with `dof` degrees of freedom at z standard
/// deviations (Wilson-Hilferty).
fn chi_square_quantile(dof: f64, z: f64) -> f64 {
    let a = 2.0 / (9.0 * dof);
    dof * (1.0 - a + z * a.sqrt()).powi(3)
}

/// Sampled cells follow the weights: chi-square at p ~ 1e-6 on a 7x5 map
/// with empty cells, which the same counts fail against weights off by
/// 10% in one cell.
#[test]
fn sampled_cells_pass_chi_square() {
    let (width, height) = (7, 5);
    let weights = random_weights(35, 11);
    let table = build_2d(width, height, &weights);
    let d = Distribution2d::new(width, height, &table).unwrap();
    let samples = 200_000u32;
    let mut counts = [0u32; 35];
    for i in 0..samples {
        let s = d.sample(Vec2::new(random_f32(12, 2 * i), random_f32(12, 2 * i + 1)));
        counts[(s.cell.y * width + s.cell.x) as usize] += 1;
    }
    let statistic = |weights: &[f32]| {
        let sum: f64 = weights.iter().map(|&w| w as f64).sum();
        let mut chi2 = 0.0;
        for (c, &w) in counts.iter().zip(weights) {
            if w == 0.0 {
                assert_eq!(*c, 0);
                continue;
            }
            let e = samples as f64 * w as f64 / sum;
            chi2 += (*c as f64 - e).powi(2) / e;
        }
        chi2
    };
    let dof = weights.iter().filter(|&&w| w > 0.0).count() as f64 - 1.0;
    let limit = chi_square_quantile(dof, 4.75);
    let chi2 = statistic(&weights);
    assert!(chi2 < limit, "chi2 {chi2} over {limit} ({dof} dof)");
    let mut wrong = weights.clone();
    let i = wrong.iter().position(|&w| w > 0.5).unwrap();
    wrong[i] *= 1.1;
    assert!(statistic(&wrong) > limit);
}

/// All-zero weights sample uniformly with pdf 1 and integral 0; a zero
/// row in a non-zero map is never sampled.
#[test]
fn zero_weights_fall_back_to_uniform() {
    let table = build_2d(4, 3, &[0.0; 12]);
    let d = Distribution2d::new(4, 3, &table).unwrap();
    assert_eq!(d.integral(), 0.0);
    for i in 0..1000 {
        let u = Vec2::new(random_f32(9, 2 * i), random_f32(9, 2 * i + 1));
        let s = d.sample(u);
        assert!((s.point - u).abs().max_element() < 1e-6, "{u} -> {}", s.point);
        // 1 up to the rounding of the thirds in the uniform marginal.
        assert!((s.pdf - 1.0).abs() < 1e-6 && d.pdf(u) == s.pdf, "{}", s.pdf);
    }
    let mut t1 = [0.0; 4];
    let d1 = Distribution1d::build(&[0.0; 3], &mut t1).unwrap();
    assert_eq!(
        (d1.sample(0.5).x, d1.sample(0.5).pdf, d1.integral()),
        (0.5, 1.0, 0.0)
    );

    let mut weights = [1.0f32; 12];
    weights[4..8].fill(0.0);
    let table = build_2d(4, 3, &weights);
    let d = Distribution2d::new(4, 3, &table).unwrap();
    for i in 0..1000 {
        let s = d.sample(Vec2::new(random_f32(10, 2 * i), random_f32(10, 2 * i + 1)));
        assert_ne!(s.cell.y, 1);
        assert_eq!(s.pdf, 1.5);
    }
    assert_eq!(d.pdf(Vec2::new(0.3, 0.5)), 0.0);
}

/// One non-zero cell takes every sample, with pdf `width * height`.
#[test]
fn one_bright_cell_takes_every_sample() {
    let (width, height) = (9, 7);
    let mut weights = vec![0.0f32; 63];
    weights[(4 * width + 6) as usize] = 3.5;
    let table = build_2d(width, height, &weights);
    let d = Distribution2d::new(width, height, &table).unwrap();
    assert!((d.integral() - 3.5 / 63.0).abs() < 1e-7);
    for i in 0..5000 {
        let s = d.sample(Vec2::new(random_f32(13, 2 * i), random_f32(13, 2 * i + 1)));
        assert_eq!(s.cell, UVec2::new(6, 4));
        assert_eq!((cell_of(s.point.x, width), cell_of(s.point.y, height)), (6, 4));
        assert_eq!(s.pdf, 63.0);
    }
    // Its corners: u = 0 and u -> 1 land on the cell's edges.
    assert_eq!(d.sample(Vec2::ZERO).point, Vec2::new(6.0 / 9.0, 4.0 / 7.0));
    let top = d.sample(Vec2::ONE).point;
    assert!((top - Vec2::new(7.0 / 9.0, 5.0 / 7.0)).abs().max_element() < 1e-6);
}

/// A `width x height` map of linear RGB texels with its sampling table.
struct TestMap {
    width: u32,
    height: u32,
    rgb: Vec<[f32; 3]>,
    table: Vec<f32>,
}

impl TestMap {
    fn new(width: u32, height: u32, rgb: Vec<[f32; 3]>) -> Self {
        let mut table = vec![0.0; EnvironmentMap::table_len(width, height)];
        EnvironmentMap::build(width, height, &rgb, &mut table).unwrap();
        TestMap {
            width,
            height,
            rgb,
            table,
        }
    }

    fn map(&self, rotation_turns: f32) -> EnvironmentMap<'_> {
        EnvironmentMap::new(self.width, self.height, &self.table)
            .unwrap()
            .with_rotation_turns(rotation_turns)
    }

    /// The texel containing map coordinates `uv` (clamped to the map).
    fn texel_of(&self, uv: Vec2) -> UVec2 {
        let x = ((uv.x * self.width as f32) as u32).min(self.width - 1);
        let y = ((uv.y * self.height as f32) as u32).min(self.height - 1);
        UVec2::new(x, y)
    }

    fn luminance_at(&self, texel: UVec2) -> f64 {
        luminance(Vec3::from_array(
            self.rgb[(texel.y * self.width + texel.x) as usize],
        )) as f64
    }

    /// Luminance seen in direction `dir` (texel-constant radiance).
    fn radiance(&self, dir: Vec3, rotation_turns: f32) -> f64 {
        self.luminance_at(self.texel_of(direction_to_uv(dir, rotation_turns)))
    }

    /// Exact `∫ Y(omega) max(cos(theta), 0)^power d omega` over the sphere
    /// (power 0) or the upper hemisphere (power 1, `height` even), in f64.
    fn exact_integral(&self, cosine: bool) -> f64 {
        let (w, h) = (self.width as f64, self.height as f64);
        let mut total = 0.0;
        for y in 0..self.height {
            let (top, bottom) = (PI * y as f64 / h, PI * (y + 1) as f64 / h);
            let factor = if cosine {
                if 2 * y >= self.height {
                    continue;
                }
                // ∫ cos sin d theta = (sin^2(bottom) - sin^2(top)) / 2, times 2 pi / w.
                PI / w * (bottom.sin().powi(2) - top.sin().powi(2))
            } else {
                2.0 * PI / w * (top.cos() - bottom.cos())
            };
            for x in 0..self.width {
                total += self.luminance_at(UVec2::new(x, y)) * factor;
            }
        }
        total
    }
}

/// Random texels: channels in `[0, 2)`, about a fifth of the texels black.
fn random_rgb(count: u32, seed: u32) -> Vec<[f32; 3]> {
    (0..count)
        .map(|i| {
            if random_f32(seed, 4 * i + 3) < 0.2 {
                [0.0; 3]
            } else {
                [0, 1, 2].map(|c| 2.0 * random_f32(seed, 4 * i + c))
            }
        })
        .collect()
}

/// A sky: a vertical gradient, a small bright sun, black ground below the
/// horizon's first rows (32x16, so the equator is a row edge).
fn sun_map() -> TestMap {
    let (width, height) = (32u32, 16u32);
    let mut rgb = Vec::new();
    for y in 0..height {
        for x in 0..width {
            let v = (y as f32 + 0.5) / height as f32;
            rgb.push(if y >= 11 {
                [0.0; 3]
            } else if (x, y) == (20, 5) || (x, y) == (21, 5) {
                [900.0, 800.0, 600.0]
            } else {
                [0.2 + v, 0.3 + v, 0.9 + 0.2 * (x as f32 / width as f32)]
            });
        }
    }
    TestMap::new(width, height, rgb)
}

fn u2(seed: u32, i: u32) -> Vec2 {
    Vec2::new(random_f32(seed, 2 * i), random_f32(seed, 2 * i + 1))
}

/// Uniform direction on the sphere (pdf `1 / (4 pi)`).
fn uniform_sphere(u: Vec2) -> Vec3 {
    let y = 1.0 - 2.0 * u.y;
    let r = (1.0 - y * y).max(0.0).sqrt();
    let phi = std::f32::consts::TAU * u.x;
    Vec3::new(r * phi.cos(), y, r * phi.sin())
}

/// Mean and standard error of `n` values.
fn mean_and_error(n: u32, mut f: impl FnMut(u32) -> f64) -> (f64, f64) {
    let (mut sum, mut squares) = (0.0, 0.0);
    for i in 0..n {
        let v = f(i);
        sum += v;
        squares += v * v;
    }
    let mean = sum / n as f64;
    let variance = (squares / n as f64 - mean * mean).max(0.0);
    (mean, (variance / n as f64).sqrt())
}

/// Distance in texels from map coordinates `uv` to the nearest texel edge.
fn edge_distance(uv: Vec2, width: u32, height: u32) -> f32 {
    let d = |x: f32, n: u32| {
        let s = x * n as f32;
        (s - s.round()).abs()
    };
    d(uv.x, width).min(d(uv.y, height))
}

/// The pdf returned with a direction is `pdf(direction)`, under a rotation,
/// on an odd-sized map with black texels; the texel and map coordinates
/// returned are those of the direction.
#[test]
fn environment_sample_and_pdf_agree() {
    let (width, height) = (13, 7);
    let test = TestMap::new(width, height, random_rgb(width * height, 1));
    for rotation in [0.0, 0.37, -1.2] {
        let map = test.map(rotation);
        let mut moved = 0;
        for i in 0..50_000 {
            let s = map.sample(u2(2, i));
            let (dir, pdf) = map.sample_direction(u2(2, i));
            assert_eq!((dir, pdf), (s.direction, s.pdf));
            assert!((dir.length() - 1.0).abs() < 1e-6);
            assert!(test.luminance_at(s.texel) > 0.0, "drew black texel {}", s.texel);
            let uv = direction_to_uv(dir, rotation);
            if test.texel_of(uv) != s.texel {
                moved += 1;
                assert!(edge_distance(uv, width, height) < 1e-3, "{} vs {}", uv, s.uv);
                continue;
            }
            assert!((uv - s.uv).abs().max_element() < 1e-5, "{uv} vs {}", s.uv);
            let again = map.pdf(dir);
            if (dir.x * dir.x + dir.z * dir.z).sqrt() < MIN_SIN_THETA {
                assert_eq!((pdf, again), (0.0, 0.0));
                continue;
            }
            assert!(pdf > 0.0 && pdf.is_finite(), "sample {i}: {s:?}");
            assert!((again - pdf).abs() <= 1e-5 * pdf, "sample {i}: {pdf} vs {again}");
        }
        assert!(moved < 50, "{moved} directions changed texel");
    }
}

/// Drawn texels follow luminance x sin(theta) (chi-square, p ~ 1e-6); the
/// same counts fail against luminance alone, so the test sees the
/// `sin(theta)` factor.
#[test]
fn sampled_texels_follow_the_weights() {
    let (width, height) = (9, 6);
    let test = TestMap::new(width, height, random_rgb(width * height, 3));
    let map = test.map(0.21);
    let samples = 300_000;
    let mut counts = vec![0u32; (width * height) as usize];
    for i in 0..samples {
        let s = map.sample(u2(4, i));
        counts[(s.texel.y * width + s.texel.x) as usize] += 1;
    }
    let chi2 = |weight: &dyn Fn(u32, u32) -> f64| {
        let total: f64 = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .map(|(x, y)| weight(x, y))
            .sum();
        let mut chi2 = 0.0;
        for y in 0..height {
            for x in 0..width {
                let c = counts[(y * width + x) as usize] as f64;
                let e = samples as f64 * weight(x, y) / total;
                if e == 0.0 {
                    assert_eq!(c, 0.0, "texel ({x}, {y}) has no weight");
                } else {
                    chi2 += (c - e) * (c - e) / e;
                }
            }
        }
        chi2
    };
    let rgb = |x: u32, y: u32| Vec3::from_array(test.rgb[(y * width + x) as usize]);
    let dof = test
        .rgb
        .iter()
        .filter(|c| luminance(Vec3::from_array(**c)) > 0.0)
        .count() as f64
        - 1.0;
    let limit = chi_square_quantile(dof, 4.75);
    let statistic = chi2(&|x, y| texel_weight(rgb(x, y), y, height) as f64);
    assert!(statistic < limit, "chi2 {statistic} over {limit} ({dof} dof)");
    let without_sin = chi2(&|x, y| luminance(rgb(x, y)) as f64);
    assert!(
        without_sin > 10.0 * limit,
        "chi2 without sin(theta) {without_sin}"
    );
}

/// ∫ L d omega over the sphere and ∫ L cos(theta) d omega over the upper
/// hemisphere: the importance-sampled estimates equal the exact texel sums
/// and uniform sphere sampling's estimates within 5 standard errors, with a
/// much smaller error than uniform sampling on a map with a sun.
#[test]
fn estimates_match_exact_integrals_and_uniform_sampling() {
    let test = sun_map();
    let rotation = 0.13;
    let map = test.map(rotation);
    let n = 200_000;
    for cosine in [false, true] {
        let weight = |dir: Vec3| if cosine { dir.y.max(0.0) as f64 } else { 1.0 };
        let exact = test.exact_integral(cosine);
        let (is, is_error) = mean_and_error(n, |i| {
            let (dir, pdf) = map.sample_direction(u2(5, i));
            if pdf == 0.0 {
                return 0.0;
            }
            test.radiance(dir, rotation) * weight(dir) / pdf as f64
        });
        let (uniform, uniform_error) = mean_and_error(n, |i| {
            let dir = uniform_sphere(u2(6, i));
            4.0 * PI * test.radiance(dir, rotation) * weight(dir)
        });
        let name = if cosine { "hemisphere cosine" } else { "sphere" };
        assert!(
            (is - exact).abs() < 5.0 * is_error + 1e-4 * exact,
            "{name}: IS {is} +- {is_error} vs {exact}"
        );
        assert!(
            (uniform - exact).abs() < 5.0 * uniform_error,
            "{name}: uniform {uniform} +- {uniform_error} vs {exact}"
        );
        let both = (is_error.powi(2) + uniform_error.powi(2)).sqrt();
        assert!((is - uniform).abs() < 5.0 * both, "{name}: {is} vs {uniform}");
        assert!(
            is_error * 5.0 < uniform_error,
            "{name}: IS error {is_error}, uniform {uniform_error}"
        );
    }
    // The sphere integral is also what the table says.
    let exact = test.exact_integral(false);
    assert!((map.luminance_integral() as f64 / exact - 1.0).abs() < 1e-5);
}

/// The pdf per steradian integrates to 1 over the sphere (midpoint rule on
/// a grid that refines every texel, so no grid cell straddles a texel edge).
#[test]
fn pdf_integrates_to_one_over_the_sphere() {
    let (width, height) = (7, 5);
    let test = TestMap::new(width, height, random_rgb(width * height, 7));
    let map = test.map(0.0);
    let (nu, nv) = (width * 60, height * 120);
    let mut total = 0.0f64;
    for j in 0..nv {
        let theta = PI * (j as f64 + 0.5) / nv as f64;
        for i in 0..nu {
            let phi = 2.0 * PI * (i as f64 + 0.5) / nu as f64;
            let dir = Vec3::new(
                (-theta.sin() * phi.sin()) as f32,
                theta.cos() as f32,
                (theta.sin() * phi.cos()) as f32,
            );
            total += map.pdf(dir) as f64 * theta.sin() * (PI / nv as f64) * (2.0 * PI / nu as f64);
        }
    }
    assert!((total - 1.0).abs() < 1e-4, "{total}");
}

/// A map with one non-black texel: every sample lands in it, with a finite
/// pdf that matches `pdf(dir)`, and the estimate of its integral is exact up
/// to the `sin(theta)` variation inside the texel.
#[test]
fn one_bright_texel_takes_every_sample() {
    let (width, height) = (11, 9);
    let mut rgb = vec![[0.0f32; 3]; 99];
    let bright = UVec2::new(7, 2);
    rgb[(bright.y * width + bright.x) as usize] = [4.0, 2.0, 1.0];
    let test = TestMap::new(width, height, rgb);
    let map = test.map(0.6);
    let (estimate, error) = mean_and_error(20_000, |i| {
        let s = map.sample(u2(8, i));
        assert_eq!(s.texel, bright);
        assert_eq!(test.texel_of(s.uv), bright);
        assert!(s.pdf > 0.0 && s.pdf.is_finite());
        if edge_distance(direction_to_uv(s.direction, 0.6), width, height) > 1e-3 {
            assert!((map.pdf(s.direction) / s.pdf - 1.0).abs() < 1e-5);
        }
        test.luminance_at(bright) / s.pdf as f64
    });
    let exact = test.exact_integral(false);
    assert!(
        (estimate - exact).abs() < 5.0 * error + 1e-5 * exact,
        "{estimate} +- {error} vs {exact}"
    );
    // Everywhere else the pdf is 0.
    assert_eq!(map.pdf(Vec3::NEG_Z), 0.0);
}

/// An all-black map samples (u, v) uniformly: pdf `1 / (2 pi^2 sin(theta))`,
/// luminance integral 0, no NaN.
#[test]
fn all_black_map_is_uniform_in_uv() {
    let (width, height) = (6, 5);
    let test = TestMap::new(width, height, vec![[0.0; 3]; 30]);
    let map = test.map(0.0);
    assert_eq!(map.luminance_integral(), 0.0);
    for i in 0..10_000 {
        let u = u2(9, i);
        let s = map.sample(u);
        assert!((s.uv - u).abs().max_element() < 1e-6);
        let sin_theta = (PI * s.uv.y as f64).sin();
        if sin_theta < MIN_SIN_THETA as f64 {
            assert_eq!(s.pdf, 0.0);
            continue;
        }
        let want = 1.0 / (2.0 * PI * PI * sin_theta);
        assert!((s.pdf as f64 / want - 1.0).abs() < 1e-5, "{} vs {want}", s.pdf);
        assert!((map.pdf(s.direction) as f64 / want - 1.0).abs() < 1e-5);
    }
}
