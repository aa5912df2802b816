//! The rendered-quality study in motion (issue 13, part 4): the seed permutation with
//! and without the bijective seed reprojection (`sampler_core::reproject_frame`) on
//! moving Cornell-box sequences, against a reference rendered at every frame's pose.
//!
//! Entry points: [`run_study`] (every case and method, the still sequence first) and
//! [`markdown`] (its tables); [`MotionSequence::new`] and [`MotionSequence::run`] pose
//! and measure one sequence ([`CaseResult`]).
//!
//! - [`case`]: the moving sequences ([`MotionCase`]) as timelines.
//! - [`history`]: the reprojecting exponential history (the "EMA" figure).
//! - [`config`]: what to render ([`MotionConfig`]).
//! - [`method`]: the rows ([`MotionMethod`]).
//! - [`insets`]: the flat insets following their surface ([`fit_insets`]).
//! - [`result`]: a measured sequence and its figures ([`CaseResult`], [`Figure`]).
//! - [`tables`]: the markdown tables.
//! - [`draws`]: the study over several draws (salts): each figure's mean and range, and
//!   the rows' paired differences.
//! - [`sequence`]: the posed sequences and the runs over them.
//!
//! Each module uses only those listed above it, the still study ([`crate::study`]:
//! reference, insets, the filtered error) and [`crate::metrics`].
//!
//! Sequences ([`case`]): the camera swaying on an orbit at about 0.5 and
//! 2 px/frame at the image centre, on request the camera sliding sideways (a pan, no
//! turn; `conformance motion --pan-speeds`), the short block rising and sinking, and the still
//! camera (the static figures every moving figure is compared with, measured by the
//! same code). Every method renders through `gpu_tracer::render::render_sequence_cpu`
//! (per frame: G-buffer, reprojection, trace, sort + retarget), 1 spp, starting from
//! the same white seeds ([`MotionConfig::salt`]).
//!
//! # Rows ([`MotionMethod`])
//! white (fresh seeds), permute without reprojection, permute with reprojection,
//! permute-jitter (`SAMPLER_SCREEN_SOBOL | SAMPLER_JITTER_ONLY`) with reprojection,
//! feature-aware permute with reprojection (`SequenceOptions::features`, issue 14:
//! demodulated keys, blocks sorted in groups of one surface, retarget moves cut at
//! edges), screen-sobol (white seeds, every 2D decision from the screen-space sampler),
//! and the later rows of [`MotionMethod::ALL`]: the a-priori samplers, and the render
//! defaults (temporal permutation with ZSobol's jitter) without reprojection, with it,
//! feature-aware, and with it only for surfaces faster than
//! `gpu_tracer::method_choice::DEFAULT_REPROJECT_HOLD_BELOW` (the default).
//!
//! # Per-frame reference
//! Every frame is compared with a reference of the same pose
//! ([`crate::study::reference::Reference::get_named`], two halves of `ref_spp / 2` samples),
//! cached in [`crate::study::reference::default_cache_dir`] under a name holding
//! [`crate::study::reference::pose_key`] (renderer, camera, scene, settings). The sway repeats its
//! poses, so a sequence renders only its distinct poses.
//!
//! # Figures (all relative to white's run of the same sequence: white = 1)
//! Error `e_t = luma(frame_t) - luma(reference_t)`; figures pooled over frames
//! `t >= GOAL_FRAME` (8) like the static study's "LF mean 8.." and "blur s1 rms":
//! - **LF**: low-frequency power (`|f| <= 1/8`) of `e_t` on the three flat insets of the
//!   static study ([`crate::study::insets`]), mean over insets, divided by white's at the same
//!   frame, mean over frames. The insets follow their surface: each is placed at frame 0
//!   and moved every frame so that the world point under its centre stays under its
//!   centre (rounded to whole pixels); every pixel's centre ray is checked against the
//!   inset's surface in every frame and the study fails if one misses it.
//! - **blur**: RMS of `e_t` after a toroidal Gaussian blur of sigma 1, over frames, as
//!   `sqrt(sum_t sum_p b^2 / same for white)`, for the whole image and per region
//!   ([`crate::metrics::regions`]: emitter zone, edges, interior as issue 14 defines
//!   them; from each frame's G-buffer).
//! - **EMA**: RMSE of a reprojecting exponential history ([`history`], alpha
//!   0.1, reset on disocclusion, previous values read at the nearest pixel or bilinearly:
//!   [`MotionConfig::history_fetch`]) against the frame's reference, over frames
//!   `t >= EMA_FROM` (16, once the history has settled), whole image and interior, with
//!   the reference's own noise subtracted (per pixel, from its halves).
//!
//! [`CaseResult::versus_static`] divides a moving sequence's figure by the same method's
//! figure on the still sequence: the goals of issue 13 ("within 1.1x of static at 0.5
//! px/frame, 1.25x at 2 px/frame") read off directly.
//!
//! # Diagnostics ([`SequenceStats`])
//! Measured image-centre speed, the fractions of pixels whose seed followed its point,
//! was recycled (`sampler_core::ReprojectStats`) or stayed in its pixel, the share of
//! neighbours whose homes (carried from frame 0, as `--mode hold` carries them) are still
//! neighbours, the share of pixels that move rigidly and of frames in which every seed
//! follows under the default follow share (the render defaults' frame-wide rule), history
//! resets, and the regions' shares of the image.

pub mod case;
pub mod config;
pub mod draws;
pub mod history;
pub mod insets;
pub mod method;
pub mod result;
pub mod sequence;
pub mod tables;

pub use case::MotionCase;
pub use config::MotionConfig;
pub use draws::draws_markdown;
pub use history::HistoryFetch;
pub use insets::{fit_insets, InsetAnchor, MIN_INSET_SIDE};
pub use method::MotionMethod;
pub use result::{CaseResult, Figure, MotionRun, SequenceStats, EMA_FROM};
pub use sequence::{run_study, MotionSequence};
pub use tables::markdown;
