//! Where the rendered gap of issue 5 comes from: the seed permutation on the
//! Cornell box's real per-seed estimates, with the spatial variation of the
//! integrand switched off or on (QUALITY.md, "Where the rendered gap comes
//! from"). Ignored by default (about 20 s in release); run with
//!
//! ```text
//! cargo test --release -p conformance --test rendered_diagnostics -- --ignored --nocapture
//! ```
//!
//! - **fixed pixel**: every pixel renders the same pixel (the back-wall
//!   inset's centre) with its own seed, so a seed's estimate does not depend
//!   on where the permutation moves it: the method's homogeneous ideal, on
//!   the renderer's real distribution of estimates;
//! - **real pixels**: the ordinary frame.
//!
//! Both permute with the default 64x64 tile and tables and are measured on
//! the study's three flat insets (128x128 layout) by the low-frequency power
//! of the error (against the study's 256-spp reference; for the fixed pixel,
//! that pixel's reference value), mean over frames 8..32, relative to fresh
//! white seeds.

use conformance::study::{default_cache_dir, Study, StudyConfig};
use conformance::{low_frequency_ratio, Grid, SpectrumAnalyzer};
use glam::{UVec2, Vec4};
use gpu_tracer::cpu::white_seeds;
use sampler_core::{defaults, luma, permute_frame, FrameLayout};

const SIZE: u32 = 128;
const FRAMES: u32 = 32;

#[derive(Clone, Copy, PartialEq)]
enum Seeds {
    /// Fresh white seeds every frame.
    White,
    /// The permutation (sort + retarget, R2 walk).
    Permuted,
}

/// Mean inset LF power of the error over frames 8..FRAMES.
fn inset_lf(study: &Study, seeds_kind: Seeds, fixed: bool) -> f64 {
    let layout = FrameLayout::new(SIZE, SIZE, 4, 64).unwrap();
    let (tile, tables) = (defaults::tile_64(), defaults::tables_64());
    let pw = layout.padded_width();
    let mut settings = gpu_tracer::TraceSettings::new(SIZE, SIZE);
    settings.max_depth = study.config.max_depth;
    settings.padded_width = pw;
    let (scene, reference) = (&study.scene, &study.reference.luma);
    let back = &study.insets[0];
    let mut seeds = white_seeds(pw, layout.padded_height(), 99);
    let mut next = vec![0u32; seeds.len()];
    let mut analyzer = SpectrumAnalyzer::new();
    let centre = UVec2::new(back.x0 + back.side / 2, back.y0 + back.side / 2);
    let n = (SIZE * SIZE) as usize;
    let (mut sum, mut count) = (0.0, 0);
    for t in 0..FRAMES {
        if seeds_kind == Seeds::White {
            seeds = white_seeds(pw, layout.padded_height(), 1000 + t);
        }
        let params = scene.trace_params(&settings, t).unwrap();
        let color: Vec<Vec4> = (0..n as u32)
            .map(|i| {
                let (x, y) = (i % SIZE, i / SIZE);
                let pixel = if fixed { centre } else { UVec2::new(x, y) };
                kernels::trace_pixel(
                    &params,
                    pixel,
                    seeds[(y * pw + x) as usize],
                    &[],
                    &scene.nodes,
                    &scene.triangles,
                    &scene.materials,
                    &scene.emitters,
                    &scene.attrs,
                    &scene.images,
                    &scene.environment,
                )
            })
            .collect();
        if t >= 8 {
            for inset in &study.insets {
                let (x0, y0, side) = (inset.x0 as usize, inset.y0 as usize, inset.side as usize);
                let g = Grid::from_fn(side, side, |x, y| {
                    let i = (y0 + y) * SIZE as usize + x0 + x;
                    let r = if fixed {
                        reference[centre.y as usize * SIZE as usize + centre.x as usize]
                    } else {
                        reference[i]
                    };
                    luma(color[i].truncate()) - r
                })
                .unwrap();
                sum += low_frequency_ratio(&analyzer.power_spectrum(&g));
                count += 1;
            }
        }
        permute_frame(&layout, t, &color, &tile, &tables, &seeds, &mut next).unwrap();
        std::mem::swap(&mut seeds, &mut next);
    }
    sum / count as f64
}

#[test]
#[ignore = "diagnostic, about 20 s in release: run with --ignored"]
fn the_gap_comes_from_the_integrand_changing_between_pixels() {
    for depth in [2u32, 8] {
        let mut config = StudyConfig::new(SIZE, 1, FRAMES, 256);
        config.max_depth = depth;
        let study = Study::new(config, Some(&default_cache_dir()), |_, _| {}).unwrap();
        assert_eq!(study.insets[0].name, "back wall");
        let mut rel = [0.0f64; 2];
        for (k, fixed) in [true, false].into_iter().enumerate() {
            let white = inset_lf(&study, Seeds::White, fixed);
            let permuted = inset_lf(&study, Seeds::Permuted, fixed);
            rel[k] = permuted / white;
            println!(
                "depth {depth}, {}: permuted inset LF {:.3} of white's",
                if fixed { "fixed pixel" } else { "real pixels" },
                rel[k]
            );
        }
        // The machinery works on the renderer's own estimates...
        assert!(rel[0] < 0.25, "depth {depth}: fixed-pixel LF {:.3}", rel[0]);
        // ...and moving seeds between pixels is what costs.
        assert!(rel[1] > rel[0] + 0.1, "depth {depth}: {rel:?}");
    }
}
