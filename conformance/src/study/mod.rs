//! The rendered-quality study with a still camera: end-to-end quality of the seed
//! permutation on rendered frames (issue 5, part 2).
//!
//! Entry points: [`Study::new`] (scene, reference, insets and regions of a
//! [`StudyConfig`]), [`Study::run`] (renders and measures each [`Method`]) and the
//! [`StudyResult`] it returns (relative figures, [`StudyResult::markdown`],
//! [`StudyResult::summary`]).
//!
//! - [`scene`]: the scenes a study can use ([`StudyScene`]).
//! - [`method`]: the rows ([`Method`]).
//! - [`config`]: what to render ([`StudyConfig`]) and the frames measured ([`GOAL_FRAME`]).
//! - [`reference`](mod@reference): the high-sample reference images and their cache.
//! - [`insets`]: the flat insets and the checks that they see their surface.
//! - [`setup`]: the fixed inputs of one configuration ([`Study`]).
//! - [`walks`]: the frame loops `gpu_tracer::render_cpu` does not cover (fixed step,
//!   blue-noise dither).
//! - [`feature_diagnostics`]: what the feature-aware permutation treats differently.
//! - [`filtered`]: each method's error after the real-time filters.
//! - [`history`]: each method's error after an exponential history alone (EMA, no
//!   clamp) and after the EMA then a Gaussian blur.
//! - [`result`]: the measured study and every figure read off it.
//! - [`draws`]: one study over several draws (salts): each headline figure's mean and
//!   range.
//! - [`uncertainty`]: how far one run's accumulated figures can be trusted.
//! - [`surfaces`]: the interior's history on glossy and on diffuse first hits.
//! - `meter`: [`Study::run`] and the per-frame measurement.
//!
//! Each module uses only those listed above it.
//!
//! The Cornell box (static camera) is rendered on the CPU for several frames with each
//! [`Method`]; every frame is compared with a high-sample reference on luma
//! (Rec. 709, `sampler_core::luma`):
//!
//! - `error_t = luma(frame_t) - luma(reference)`, per pixel;
//! - (a) low-frequency power ratio ([`low_frequency_ratio`](crate::low_frequency_ratio))
//!   of `error_t` on the flat [`Inset`]s, averaged over the insets;
//! - (b) RMS of `error_t` after a toroidal Gaussian blur of sigma 1 and 2 (a stand-in
//!   for a denoiser), whole image;
//! - (c) RMS of the temporally accumulated image (mean of frames `0..n`) minus the
//!   reference, whole image, for every `n`.
//!
//! - (d) per region ([`crate::metrics::regions`]: emitter zone, edges, interior, from
//!   the frame-0 G-buffer of the still camera): the sigma-1 blurred error's squared sum
//!   ([`StudyResult::pooled_region`]) and the accumulated error's.
//!
//! Figures are made relative to the [`Method::White`] run of the same configuration
//! (white = 1) by [`StudyResult::relative`]. All runs start from the same white-noise
//! seeds (salt [`StudyConfig::salt`]), so frame 0 is identical for every method except
//! the dither baseline.
//!
//! # Frame numbering
//!
//! Frame `t` (from 0) is rendered with the seeds after `t` permutation passes: frame 0
//! is the white-noise start. "By frame 8" in the goals means `t = 8`.
//!
//! # Reference noise
//!
//! The reference is the mean of two independent halves (`ref_spp / 2` samples each).
//! Its own noise adds to every squared error: `E[(acc - ref)^2] = var(acc) + var(ref)`.
//! `var(ref)` is estimated per image as `mean((A - B)^2) / 4` (A, B the halves' luma)
//! and [`MethodRun::acc_rmse_corrected`] subtracts it; without the correction every
//! accumulated ratio is pulled towards 1. Both are reported.
//!
//! # Flat insets
//!
//! Three square regions picked on the Cornell box where the reference is smooth: the
//! back wall right of the tall block, the red (left) and the green (right) wall. The
//! floor is not used: with this camera the only floor area tall enough for a
//! `size / 8` square lies next to the tall block, across its shadow edge (relative
//! reference gradient 0.9-1.4 per pixel, against 0.06-0.12 on the walls). They are
//! placed by fractions of the image size and
//! checked geometrically: [`Study::new`] casts the centre ray of every inset pixel and
//! fails unless all of them hit the intended surface (back wall: `z >= 559`, floor:
//! `y <= 0.5`, red / green wall: their material). [`Inset::max_gradient`] reports how
//! flat the reference is inside each.
//!
//! # The fixed-step comparison
//!
//! [`Method::FixedStep`] is the permutation with the dither tile moved by the fixed
//! integer step `floor(W * (a1, a2))` ((48, 36) for W = 64) every frame instead of the
//! aperiodic R2 walk: offset `o_t = t * step mod W`, sorted against `tile[(p + o_t) mod W]`
//! and retargeted with the table baked for that step (table 0, since the step is the
//! walk's base step). The frame loop is [`permute_with_offset`], which with the R2
//! walk's offsets reproduces `sampler_core::permute_frame` exactly (tested).
//!
//! # The feature-aware rows (issue 14)
//!
//! [`Method::FeaturePermute`] and [`Method::FeaturePermuteJitter`] render through the
//! tracer's own loop (`gpu_tracer::render::render_sequence_cpu` with
//! `SequenceOptions::features` on a still sequence): each frame's G-buffer gives the
//! `SurfaceFeature`s and the demodulated keys of `sampler_core::permute_frame_features`.
//! [`StudyResult::features`] says how much of the frame they treat differently from the
//! plain permutation, and [`MethodRun::seed_repeats`] (from a mirror of the seeds,
//! checked against frame 1) how often a pixel gets a seed it already had.
//!
//! [`Method::FeaturePermuteRawKey`] and [`Method::FeaturePermuteHistoryKey`] are the same
//! loop with another sort key (`gpu_tracer::feature_keys::FeatureKey`); they are not in
//! [`Method::REPORT`] and are measured by `conformance study --methods ...`.
//!
//! # Scenes
//!
//! [`StudyConfig::scene`] picks the Cornell box (default), the checker-textured glTF
//! Cornell box and its untextured twin, the glossy Cornell box, or the outdoor
//! `sun-sky` scene ([`StudyScene`]). The four rooms share the camera and the insets;
//! `sun-sky` has its own camera, its constant sky ([`StudyScene::environment`]) and
//! insets (sunlit ground, ground in the sphere's umbra, the wall's shaded face); all
//! share the region definition. [`MethodRun::lf_demodulated`] measures the
//! insets' error with the albedo divided out, which separates the texture's share of a
//! textured inset's error from the irradiance noise the seeds arrange.
//!
//! # The blue-noise-dither baseline
//!
//! [`Method::Dither`]: fresh white-noise seeds every frame (as [`Method::White`]) and
//! `kernels::abi::SEED_MODE_BLUE_NOISE_DITHER`: the first vertex's BSDF direction is
//! drawn from the default 128x128x64 spatiotemporal blue-noise mask
//! (`sampler_core::defaults::stbn_128`), `(mask(x, y, t mod 64), mask(x + 64, y + 64,
//! t mod 64))`, through `kernels::dither::trace_pixel_dithered`. CPU only: the GPU
//! entry point has no mask binding.

pub mod config;
pub mod draws;
pub mod feature_diagnostics;
pub mod filtered;
pub mod history;
pub mod insets;
mod meter;
pub mod method;
pub mod reference;
pub mod regularization;
pub mod result;
pub mod scene;
pub mod setup;
pub mod surfaces;
pub mod temporal_sort;
pub mod uncertainty;
pub mod walks;

pub use config::{StudyConfig, ACCUMULATION_POINTS, ACCUMULATION_SNAPSHOTS, GOAL_FRAME};
pub use draws::{draws_markdown, pooled_with_null, DrawFigure, Spread, DRAW_FIGURES};
pub use feature_diagnostics::FeatureDiagnostics;
pub use history::{HistoryErrors, EMA_ALPHA, EMA_FROM};
pub use insets::{crop, Inset, Surface};
pub use method::{white_control_salt, Method};
pub use reference::{default_cache_dir, Reference};
pub use regularization::RegularizationEffect;
pub use result::{HistoryMetric, MethodRun, Metric, Snapshot, StudyResult, TEMPORAL_MEANS};
pub use scene::StudyScene;
pub use setup::Study;
pub use temporal_sort::{render_temporal_permute, render_temporal_sort};
pub use walks::{permute_with_offset, render_dither, render_walk, Walk};
