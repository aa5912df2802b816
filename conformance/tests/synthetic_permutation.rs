//! The permutation on a synthetic, perfectly homogeneous image, where a
//! seed's value does not depend on the pixel it lands on (the method's ideal
//! case; algorithm.md's simulation reports error LF 0.06 of white by frame 8
//! with the R2 walk). Separates the sampler-core machinery from the
//! renderer: if this reaches low LF power, the passes are right and the
//! rendered gap comes from how much a seed's value changes when it moves.

use conformance::{low_frequency_ratio, Grid, SpectrumAnalyzer};
use sampler_core::{defaults, initial_seed, permute_frame, random_f32, sort_frame, FrameLayout};

const SIZE: u32 = 128;

/// Pixel value of a seed: a 2D integrand (the fraction of a disk covered by
/// the seed's point), identical at every pixel.
fn value(seed: u32) -> f32 {
    let (x, y) = (random_f32(seed, 0), random_f32(seed, 1));
    let d2 = (x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5);
    if d2 < 0.16 {
        1.0
    } else {
        0.0
    }
}

fn lf_of(seeds: &[u32], layout: &FrameLayout, analyzer: &mut SpectrumAnalyzer) -> f64 {
    let pw = layout.padded_width() as usize;
    let g = Grid::from_fn(SIZE as usize, SIZE as usize, |x, y| value(seeds[y * pw + x])).unwrap();
    low_frequency_ratio(&analyzer.power_spectrum(&g))
}

/// Mean error LF power over frames 8..16, with retargeting or sorting only.
fn run(retarget: bool) -> (f64, Vec<f64>) {
    let layout = FrameLayout::new(SIZE, SIZE, 4, 64).unwrap();
    let (tile, tables) = (defaults::tile_64(), defaults::tables_64());
    let pw = layout.padded_width();
    let mut seeds: Vec<u32> = (0..layout.seed_count() as u32)
        .map(|i| initial_seed(i % pw, i / pw, pw, 7))
        .collect();
    let mut next = vec![0u32; seeds.len()];
    let mut analyzer = SpectrumAnalyzer::new();
    let white = lf_of(&seeds, &layout, &mut analyzer);
    let mut lf = Vec::new();
    for t in 0..16u32 {
        let image: Vec<f32> = (0..SIZE * SIZE)
            .map(|i| value(seeds[((i / SIZE) * pw + i % SIZE) as usize]))
            .collect();
        if retarget {
            permute_frame(&layout, t, &image, &tile, &tables, &seeds, &mut next).unwrap();
        } else {
            sort_frame(&layout, t, &image, &tile, &seeds, &mut next).unwrap();
        }
        std::mem::swap(&mut seeds, &mut next);
        lf.push(lf_of(&seeds, &layout, &mut analyzer));
    }
    assert!(white > 0.7 && white < 1.3, "white LF {white}");
    let late = lf[7..].iter().sum::<f64>() / lf[7..].len() as f64 / white;
    (late, lf)
}

#[test]
fn homogeneous_image_error_becomes_blue() {
    let (late, lf) = run(true);
    eprintln!(
        "sort + retarget, LF by frame: {:?}",
        lf.iter().map(|v| format!("{v:.3}")).collect::<Vec<_>>()
    );
    eprintln!("sort + retarget, mean LF frames 8..16 (white = 1): {late:.3}");
    assert!(late < 0.15, "a homogeneous image must turn blue: LF {late:.3}");
}

#[test]
fn retargeting_is_what_lets_the_improvement_accumulate() {
    let (permute, _) = run(true);
    let (sort_only, lf) = run(false);
    eprintln!(
        "sort only, LF by frame: {:?}",
        lf.iter().map(|v| format!("{v:.3}")).collect::<Vec<_>>()
    );
    eprintln!("mean LF frames 8..16: sort only {sort_only:.3}, sort + retarget {permute:.3}");
    assert!(
        sort_only > 3.0 * permute,
        "sort only {sort_only:.3} vs permute {permute:.3}"
    );
}
