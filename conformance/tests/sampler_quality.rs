//! Issue 6, item 4: the a-priori samplers as tracer modes (`--sampler
//! screen-sobol|zsobol`) on rendered frames, at a CI size.
//!
//! The Cornell box at 64x64, 1 and 4 spp per frame, white-noise seeds (a
//! fresh salt every frame, `PermuteMode::White`), against a 512-spp CPU
//! reference (two independent 256-spp halves). Per sampler and spp, over
//! `FRAMES` frames (each frame compared on its own, not accumulated):
//! - **blurred RMSE**: RMS of the luma error blurred by a Gaussian of sigma 1
//!   pixel (`conformance::GaussianBlur`, toroidal);
//! - **RMSE**: RMS of the luma error itself;
//!
//! both with the reference's own noise removed (its variance, estimated from
//! the halves, subtracted from the mean squared error), mean squared errors
//! averaged over the frames, then relative to the seed stream's (`seeds`,
//! white noise) at the same spp. Issue 6's goals: blurred <= 0.8 and
//! unblurred <= 1.05 of white's, for both samplers at 1 and 4 spp.
//!
//! The a-priori samplers drive every 2D decision of the path (pixel jitter,
//! each vertex's light sample and BSDF direction; `kernels::trace` docs);
//! only Russian roulette still reads the white seeds. At 1 spp about 97% of
//! the squared error sits in the ~50 pixels along the light's silhouette
//! (emission about 30x the walls' radiance), lines one pixel wide that only
//! the jitter pair drives: a 2D blue-noise pattern seen through such a line
//! is only slightly anticorrelated (blurred 0.89-0.93 of white). Both
//! samplers therefore also stratify samples along rows and columns of
//! pixels: the screen-space Sobol keys are trained with line terms
//! (`sampler_core::bake` keys docs) and ZSobol places its low six index
//! digits at 1 spp so each row of every aligned square up to 64x64 has its
//! `y` coordinates in as many different intervals as it has pixels, and
//! each column its `x` coordinates (`sampler_core::sequences::zsobol`). Both goals are
//! met at 1 and 4 spp.

use conformance::{GaussianBlur, Grid};
use glam::Vec4;
use gpu_tracer::cornell::cornell_box;
use gpu_tracer::cpu::{render_frame, white_seeds};
use gpu_tracer::{render_cpu, PermuteMode, RenderJob, SceneGpu, TileChoice, TraceSettings};
use kernels::abi::{SAMPLER_SCREEN_SOBOL, SAMPLER_SEEDS, SAMPLER_ZSOBOL};
use std::sync::OnceLock;

const SIZE: u32 = 64;
const REF_SPP: u32 = 512;
const FRAMES: u32 = 64;
const SAMPLERS: [(u32, &str); 3] = [
    (SAMPLER_SEEDS, "seeds (white)"),
    (SAMPLER_SCREEN_SOBOL, "screen-sobol"),
    (SAMPLER_ZSOBOL, "zsobol"),
];
const BLUR_GOAL: f64 = 0.8;
const RMSE_GOAL: f64 = 1.05;

fn luma(c: &Vec4) -> f32 {
    sampler_core::luma(c.truncate())
}

struct Reference {
    luma: Vec<f32>,
    /// Per-pixel variance of the reference's luma, image mean.
    var: f64,
    /// The same, after the sigma-1 blur (`var * sum g^2`: the reference's
    /// noise is white).
    var_blurred: f64,
}

fn scene() -> &'static SceneGpu {
    static SCENE: OnceLock<SceneGpu> = OnceLock::new();
    SCENE.get_or_init(|| SceneGpu::build(&cornell_box()).expect("scene"))
}

fn blur() -> GaussianBlur {
    GaussianBlur::new(1.0).expect("sigma 1")
}

fn reference() -> &'static Reference {
    static REF: OnceLock<Reference> = OnceLock::new();
    REF.get_or_init(|| {
        let start = std::time::Instant::now();
        let scene = scene();
        let mut settings = TraceSettings::new(SIZE, SIZE);
        settings.spp = REF_SPP / 2;
        let params = scene.trace_params(&settings, 0).expect("params");
        let n = (SIZE * SIZE) as usize;
        let half = |salt: u32| {
            let mut color = vec![Vec4::ZERO; n];
            render_frame(scene, &params, &white_seeds(SIZE, SIZE, salt), &mut color).expect("render");
            color
        };
        let (a, b) = (half(0xA5A5_0001), half(0x5A5A_0002));
        let mean_luma: Vec<f32> = a.iter().zip(&b).map(|(x, y)| luma(&((*x + *y) * 0.5))).collect();
        // (A - B) / 2 has the variance of the mean of the halves.
        let var = a
            .iter()
            .zip(&b)
            .map(|(x, y)| {
                let d = (luma(x) - luma(y)) as f64;
                d * d / 4.0
            })
            .sum::<f64>()
            / n as f64;
        let var_blurred = var * blur().sum_of_squares_2d();
        println!(
            "reference: {SIZE}x{SIZE} at {REF_SPP} spp in {:.1} s, noise variance {var:.3e} (blurred {var_blurred:.3e})",
            start.elapsed().as_secs_f64()
        );
        Reference {
            luma: mean_luma,
            var,
            var_blurred,
        }
    })
}

/// Measured errors of one sampler at one spp.
struct Errors {
    /// Mean squared luma error, reference noise removed.
    mse: f64,
    /// The same after the sigma-1 blur.
    mse_blurred: f64,
}

/// Errors of `FRAMES` frames of `sampler` at `spp`. Every sampler uses the
/// same seeds (salt 17), so frame `t` differs between samplers only through
/// the numbers the sampler drives.
fn errors(sampler: u32, spp: u32) -> Errors {
    let reference = reference();
    let blur = blur();
    let mut settings = TraceSettings::new(SIZE, SIZE);
    settings.spp = spp;
    settings.sampler = sampler;
    let job = RenderJob {
        settings,
        frames: FRAMES,
        mode: PermuteMode::White,
        block: 4,
        tile: TileChoice::Tile64,
        salt: 17,
    };
    let n = (SIZE * SIZE) as usize;
    let (mut mse, mut mse_blurred) = (0.0f64, 0.0f64);
    let mut per_frame = Vec::new();
    render_cpu(scene(), &job, |_, color| {
        let err: Vec<f32> = color
            .iter()
            .zip(&reference.luma)
            .map(|(c, r)| luma(c) - r)
            .collect();
        let e = Grid::new(SIZE as usize, SIZE as usize, err).expect("grid");
        let blurred = blur.apply(&e);
        let sq = |g: &Grid| g.data().iter().map(|&v| (v as f64) * (v as f64)).sum::<f64>() / n as f64;
        let (a, b) = (sq(&e), sq(&blurred));
        per_frame.push(b.sqrt());
        mse += a;
        mse_blurred += b;
    })
    .expect("render");
    println!(
        "  sampler {sampler} at {spp} spp: blurred RMSE per frame {:?}",
        per_frame
            .iter()
            .map(|v| (v * 1e4).round() / 1e4)
            .collect::<Vec<_>>()
    );
    Errors {
        mse: (mse / FRAMES as f64 - reference.var).max(0.0),
        mse_blurred: (mse_blurred / FRAMES as f64 - reference.var_blurred).max(0.0),
    }
}

/// (RMSE, blurred RMSE) of each sampler relative to white's at `spp`.
fn relative(spp: u32) -> Vec<(&'static str, f64, f64)> {
    let start = std::time::Instant::now();
    let abs: Vec<Errors> = SAMPLERS.iter().map(|&(s, _)| errors(s, spp)).collect();
    let (white, white_blur) = (abs[0].mse, abs[0].mse_blurred);
    println!(
        "{spp} spp, {FRAMES} frames of {SIZE}x{SIZE} per sampler ({:.1} s):",
        start.elapsed().as_secs_f64()
    );
    let mut out = Vec::new();
    for (&(_, name), e) in SAMPLERS.iter().zip(&abs) {
        let (mse, mse_blur) = (e.mse, e.mse_blurred);
        let (r, rb) = ((mse / white).sqrt(), (mse_blur / white_blur).sqrt());
        println!(
            "  {name:14} RMSE {:.5} ({r:.3} of white), blurred RMSE {:.5} ({rb:.3} of white)",
            mse.sqrt(),
            mse_blur.sqrt()
        );
        out.push((name, r, rb));
    }
    out
}

/// Per spp: rows `(sampler name, RMSE, blurred RMSE)` relative to white.
type Figures = Vec<(u32, Vec<(&'static str, f64, f64)>)>;

/// The measured figures of both spp levels, computed once.
fn figures() -> &'static Figures {
    static FIGURES: OnceLock<Figures> = OnceLock::new();
    FIGURES.get_or_init(|| [1u32, 4].iter().map(|&spp| (spp, relative(spp))).collect())
}

/// Goal rows at the spp levels `spps` that exceed `goal` in column
/// `blurred` (false: RMSE, true: blurred RMSE), described with the amount
/// they miss by.
fn missed(spps: &[u32], blurred: bool, goal: f64) -> Vec<String> {
    let mut out = Vec::new();
    for (spp, rows) in figures().iter().filter(|(spp, _)| spps.contains(spp)) {
        for &(name, r, rb) in &rows[1..] {
            let (v, what) = if blurred {
                (rb, "blurred RMSE")
            } else {
                (r, "RMSE")
            };
            if v > goal {
                out.push(format!(
                    "{name} at {spp} spp: {what} {v:.3} of white (goal <= {goal}, missed by {:.3})",
                    v - goal
                ));
            }
        }
    }
    out
}

/// Issue 6: the unblurred RMSE of each a-priori sampler is no worse than
/// white's (<= 1.05) at 1 and 4 spp.
#[test]
fn apriori_samplers_rmse_is_no_worse_than_white() {
    let missed = missed(&[1, 4], false, RMSE_GOAL);
    assert!(missed.is_empty(), "issue 6 goal missed:\n{}", missed.join("\n"));
}

/// Issue 6: the blurred (sigma 1) RMSE of each a-priori sampler is clearly
/// below white's (<= 0.8) at 4 spp.
#[test]
fn apriori_samplers_blurred_rmse_is_below_white_at_4_spp() {
    let missed = missed(&[4], true, BLUR_GOAL);
    assert!(missed.is_empty(), "issue 6 goal missed:\n{}", missed.join("\n"));
}

/// Issue 6: the same at 1 spp, where the light's silhouette carries almost
/// all of the error (module docs): met since the samplers stratify samples
/// along rows and columns of pixels.
#[test]
fn apriori_samplers_blurred_rmse_is_below_white_at_1_spp() {
    let missed = missed(&[1], true, BLUR_GOAL);
    assert!(missed.is_empty(), "issue 6 goal missed:\n{}", missed.join("\n"));
}
