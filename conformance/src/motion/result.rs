//! A measured sequence ([`CaseResult`]: one [`MotionRun`] per method) and the figures
//! read off it, relative to white and to the still sequence.

use super::case::MotionCase;
use super::config::MotionConfig;
use super::method::MotionMethod;
use crate::metrics::regions::Region;
use crate::study::insets::Inset;
use crate::study::GOAL_FRAME;

/// First frame of the pooled EMA figures: the history (alpha 0.1) has then reached
/// `1 - 0.9^16 = 81%` of its weight.
pub const EMA_FROM: u32 = 16;

/// What the pose pass measured about a sequence (method independent).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SequenceStats {
    /// Mean length of the backward motion vector at the image centre over frames
    /// `1..`, pixels per frame (0 for a still sequence).
    pub centre_speed: f64,
    /// Mean length of the backward motion vector over the pixels that have a previous
    /// position, mean over frames `1..`, pixels per frame.
    pub mean_speed: f64,
    /// Mean over frames `1..` of the fraction of pixels whose seed followed its point
    /// (`ReprojectStats::followed / pixels`).
    pub followed: f64,
    /// Same for recycled seeds (disoccluded, off screen, or lost claims).
    pub recycled: f64,
    /// Mean fraction of pixels that keep the seed of their own pixel after the
    /// reprojection (the reprojection is the identity there).
    pub stayed: f64,
    /// Mean over frames `1..` of the fraction of neighbours (horizontal and vertical) whose homes,
    /// carried from frame 0 by every frame's reprojection (what `--mode hold` reads
    /// ZSobol's and the spatiotemporal sampler's points at), are still neighbours in
    /// the same order: 1 for a still camera or a whole-pixel pan.
    pub homes_in_order: f64,
    /// Mean over frames `1..` of the fraction of pixels that move rigidly
    /// (`gpu_tracer::motion::rigid_pixels`: the count the frame-wide follow rule reads).
    pub rigid_share: f64,
    /// Fraction of frames `1..` in which every seed follows its surface under the
    /// default follow share (`kernels::motion::frame_follows` with
    /// `gpu_tracer::method_choice::DEFAULT_REPROJECT_FOLLOW_SHARE`).
    pub frames_following: f64,
    /// Fraction of frames `1..` that follow as a whole and whose rigid pixels
    /// move alike, so that the pan offset moves (`kernels::pan_offset::
    /// advance_offset` with the default follow share).
    pub frames_moving_offset: f64,
    /// Mean, over the frames `1..` with sampled rigid pixels, of their
    /// screen regions' spread around the mean motion relative to its length
    /// (`kernels::pan_offset::motion_spread` over the L1 speed; the pan
    /// offset moves at most `PAN_SPREAD_PERCENT` / 100).
    pub rigid_spread: f64,
    /// Frames `1..` with sampled rigid pixels (for [`Self::rigid_spread`]'s mean).
    pub frames_sampled: f64,
    /// Mean fraction of pixels whose history is reset (frames `1..`).
    pub history_resets: f64,
    /// Mean share of the image of each region ([`Region::ALL`] order).
    pub region_share: [f64; 3],
    /// Distinct poses (references) of the sequence.
    pub poses: usize,
}

/// Index of a whole-image or region figure in the per-frame sums.
pub(super) const WHOLE: usize = 0;
pub(super) fn slot(r: Region) -> usize {
    1 + r as usize
}

/// Per-frame sums of one method.
#[derive(Clone, Debug)]
pub struct MotionRun {
    /// The method.
    pub method: MotionMethod,
    /// Per frame, per inset ([`CaseResult::insets`] order): the error's low-frequency
    /// ratio (white noise = 1).
    pub lf: Vec<Vec<f64>>,
    /// Per frame: sum of squared blurred (sigma 1) error over the whole image and each
    /// region (`[whole, emitter, edges, interior]`).
    pub blur: Vec<[f64; 4]>,
    /// Per frame: sum of squared history error minus the reference's noise variance,
    /// whole image and interior; then the same for the history of the per-frame
    /// error (the noise part: [`Figure::EmaNoise`]), whole image and interior.
    pub ema: Vec<[f64; 4]>,
    /// Per frame: sum of squared error after the real-time filter
    /// (`taa+atrous` of `gpu_tracer::filter`, reprojected by the motion vectors,
    /// reset at disocclusions), whole image and interior.
    pub filtered: Vec<[f64; 2]>,
}

/// One of the study's figures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Figure {
    /// Inset low-frequency power, mean over frames of the ratio to white.
    LowFrequency,
    /// Blurred RMSE, whole image (`None`) or one region.
    Blur(Option<Region>),
    /// History RMSE (reference noise removed), whole image or interior.
    Ema {
        /// Interior only.
        interior: bool,
    },
    /// History RMSE of the per-frame error (each frame minus its own pose's
    /// reference, blended by the same reprojected history), whole image or
    /// interior: the history's error without its resampling lag (nearest-pixel
    /// fetches drift up to half a pixel off the surface, the same for every
    /// method). What a sampler can change; equal to [`Figure::Ema`] with a still
    /// camera.
    EmaNoise {
        /// Interior only.
        interior: bool,
    },
    /// RMSE after the real-time filter (TAA + a-trous), whole image or interior,
    /// over frames from [`EMA_FROM`].
    Filtered {
        /// Interior only.
        interior: bool,
    },
}

/// A measured sequence: every method's run.
#[derive(Debug)]
pub struct CaseResult {
    /// The case.
    pub case: MotionCase,
    /// What moves.
    pub description: String,
    /// The configuration.
    pub config: MotionConfig,
    /// Method-independent measurements.
    pub stats: SequenceStats,
    /// The insets at frame 0 (the LF series' order).
    pub insets: Vec<Inset>,
    /// Which insets are this sequence's own (its LF figure); the still sequence also
    /// measures the moving sequences' smaller insets for [`Self::versus_static`].
    pub own_insets: Vec<bool>,
    /// One run per method, in the order requested.
    pub runs: Vec<MotionRun>,
}

impl CaseResult {
    /// The run of `method`, if measured.
    pub fn run(&self, method: MotionMethod) -> Option<&MotionRun> {
        self.runs.iter().find(|r| r.method == method)
    }

    /// `figure` of `method` relative to white's ([`crate::motion`], "Figures"). `None`
    /// when a run is missing or no frame is pooled.
    pub fn relative(&self, method: MotionMethod, figure: Figure) -> Option<f64> {
        let own: Vec<usize> = (0..self.insets.len()).filter(|&i| self.own_insets[i]).collect();
        self.relative_on(method, figure, &own)
    }

    /// [`Self::relative`], with the LF figure over the insets `insets` (indices into
    /// [`Self::insets`]).
    fn relative_on(&self, method: MotionMethod, figure: Figure, insets: &[usize]) -> Option<f64> {
        let m = self.run(method)?;
        let w = self.run(MotionMethod::White)?;
        let frames = m.lf.len().min(w.lf.len());
        let from = (GOAL_FRAME as usize).min(frames.saturating_sub(1));
        match figure {
            Figure::LowFrequency => {
                if insets.is_empty() {
                    return None;
                }
                let mean = |v: &[f64]| insets.iter().map(|&i| v[i]).sum::<f64>() / insets.len() as f64;
                let v: Vec<f64> = (from..frames).map(|t| mean(&m.lf[t]) / mean(&w.lf[t])).collect();
                (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
            }
            Figure::Blur(region) => {
                let k = region.map_or(WHOLE, slot);
                let sum = |r: &MotionRun| (from..frames).map(|t| r.blur[t][k]).sum::<f64>();
                ratio(sum(m), sum(w))
            }
            Figure::Ema { interior } | Figure::EmaNoise { interior } => {
                let from = (EMA_FROM as usize).min(frames.saturating_sub(1));
                let k = usize::from(interior)
                    + if matches!(figure, Figure::EmaNoise { .. }) {
                        2
                    } else {
                        0
                    };
                let sum = |r: &MotionRun| (from..frames).map(|t| r.ema[t][k]).sum::<f64>();
                ratio(sum(m).max(0.0), sum(w))
            }
            Figure::Filtered { interior } => {
                let from = (EMA_FROM as usize).min(frames.saturating_sub(1));
                let k = usize::from(interior);
                let sum = |r: &MotionRun| {
                    (from..r.filtered.len().min(frames))
                        .map(|t| r.filtered[t][k])
                        .sum::<f64>()
                };
                ratio(sum(m), sum(w))
            }
        }
    }

    /// `figure` of `method` here divided by the same method's figure in `still` (both
    /// relative to white). The LF figure of `still` is taken on the insets of the same
    /// name and side as this sequence's (the still sequence measures every case's
    /// insets: [`run_study`](super::sequence::run_study)).
    pub fn versus_static(&self, still: &CaseResult, method: MotionMethod, figure: Figure) -> Option<f64> {
        let same: Vec<usize> = self
            .insets
            .iter()
            .zip(&self.own_insets)
            .filter(|(_, own)| **own)
            .filter_map(|(i, _)| {
                still
                    .insets
                    .iter()
                    .position(|s| s.name == i.name && s.side == i.side)
            })
            .collect();
        Some(self.relative(method, figure)? / still.relative_on(method, figure, &same)?)
    }
}

fn ratio(a: f64, b: f64) -> Option<f64> {
    (b > 0.0 && a.is_finite()).then(|| (a / b).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::tables::markdown;
    use crate::study::insets::inset_layout;

    #[test]
    fn figures_pool_over_frames_relative_to_white() {
        let run = |method, lf: f64, blur: f64| MotionRun {
            method,
            lf: vec![vec![lf]; 20],
            blur: vec![[blur, blur, 0.0, 0.0]; 20],
            ema: vec![[blur, 0.0, blur, 0.0]; 20],
            filtered: vec![[blur, blur]; 20],
        };
        let r = CaseResult {
            case: MotionCase::Still,
            description: String::new(),
            config: MotionConfig::new(32, 20, 4),
            stats: SequenceStats::default(),
            insets: inset_layout(crate::study::StudyScene::Cornell, 32)[..1].to_vec(),
            own_insets: vec![true],
            runs: vec![
                run(MotionMethod::White, 2.0, 4.0),
                run(MotionMethod::Permute, 1.0, 1.0),
            ],
        };
        assert_eq!(
            r.relative(MotionMethod::Permute, Figure::Filtered { interior: true }),
            Some(0.5)
        );
        assert_eq!(r.relative(MotionMethod::Permute, Figure::LowFrequency), Some(0.5));
        assert_eq!(r.relative(MotionMethod::Permute, Figure::Blur(None)), Some(0.5));
        assert_eq!(
            r.relative(MotionMethod::Permute, Figure::Ema { interior: false }),
            Some(0.5)
        );
        assert_eq!(
            r.relative(MotionMethod::Permute, Figure::Blur(Some(Region::Edge))),
            None
        );
        assert_eq!(
            r.versus_static(&r, MotionMethod::Permute, Figure::LowFrequency),
            Some(1.0)
        );
        assert!(markdown(&[r]).contains("| still | permute, no reprojection | 0.500 | 0.500 |"));
    }
}
