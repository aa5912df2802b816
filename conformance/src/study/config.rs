//! What a rendered-quality study renders ([`StudyConfig`]) and the frames at which it
//! is measured.

use super::scene::StudyScene;
use anyhow::Result;
use gpu_tracer::filter::FilterSettings;
use gpu_tracer::scene::TraceSettings;
use gpu_tracer::TileChoice;
use kernels::abi::SEED_MODE_FIXED;
use sampler_core::FrameLayout;

/// The frame at which the goals on single frames are checked ([`crate::study`], "Frame
/// numbering").
pub const GOAL_FRAME: u32 = 8;
/// Frame counts at which the accumulated RMSE is reported.
pub const ACCUMULATION_POINTS: [u32; 4] = [8, 32, 64, 128];
/// Frame counts whose accumulated mean image a run keeps (the report's pictures).
pub const ACCUMULATION_SNAPSHOTS: [u32; 2] = [8, 64];

/// What to render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StudyConfig {
    /// Image side in pixels (square frames).
    pub size: u32,
    /// Samples per pixel per frame.
    pub spp: u32,
    /// Frames per method.
    pub frames: u32,
    /// Samples per pixel of the reference (two halves of `ref_spp / 2`).
    pub ref_spp: u32,
    /// Block side of the sorting pass.
    pub block: u32,
    /// Dither tile.
    pub tile: TileChoice,
    /// Seed mode of the white / sort / permute / fixed-step runs
    /// (`SEED_MODE_FIXED` or `SEED_MODE_ADVANCE`).
    pub seed_mode: u32,
    /// Maximum path length in segments.
    pub max_depth: u32,
    /// The draw: salt of the initial white-noise seeds, and where the
    /// a-priori samplers' per-pixel data sits on the screen
    /// (`gpu_tracer::scene::sampler_origin_of_salt`; salt 1: as baked), so
    /// that two salts are two independent draws of every row. Only the
    /// renders read it: a [`Study`](super::Study) set up at one salt renders
    /// another once its `config.salt` is changed (`conformance study --draws`).
    pub salt: u32,
    /// Also measure every method after the real-time filters
    /// ([`STUDY_FILTERS`](super::filtered::STUDY_FILTERS)); on by default.
    pub filters: bool,
    /// The scene ([`StudyScene`]; the Cornell box by default).
    pub scene: StudyScene,
    /// A scene of the same room and camera whose albedo multiplies this scene's error
    /// on the insets ([`MethodRun::lf_modulated`](super::result::MethodRun::lf_modulated);
    /// `None` by default): the untextured twin's error modulated by the textured box's
    /// texture, to tell what the texture's modulation alone does to a blue error.
    pub modulate_by: Option<StudyScene>,
    /// Path regularisation of every row, white and the reference
    /// (`TraceSettings::glossy_regularization`, in `[0, 1]`; 0, the default:
    /// off). Above 0 the study also measures the bias against the unbiased
    /// reference ([`super::regularization`]).
    pub glossy_regularization: f32,
    /// Whether the studies' TAA clamps its history to the current frame's 3x3 colour
    /// box (`gpu_tracer::filter::FilterSettings::clamp`; on by default, what a
    /// renderer runs). Off, every chain with TAA (and its bias, the reference through
    /// the same chain) measures what the clamp costs a row.
    pub taa_clamp: bool,
}

impl StudyConfig {
    /// Defaults: 4x4 blocks, 64x64 tile, fixed seeds, depth 8, salt 1.
    pub fn new(size: u32, spp: u32, frames: u32, ref_spp: u32) -> Self {
        StudyConfig {
            size,
            spp,
            frames,
            ref_spp,
            block: 4,
            tile: TileChoice::Tile64,
            seed_mode: SEED_MODE_FIXED,
            max_depth: 8,
            salt: 1,
            filters: true,
            scene: StudyScene::Cornell,
            modulate_by: None,
            glossy_regularization: 0.0,
            taa_clamp: true,
        }
    }

    /// The settings of the studies' filter chains: the defaults, with
    /// [`StudyConfig::taa_clamp`].
    pub(crate) fn filter_settings(&self) -> FilterSettings {
        FilterSettings {
            clamp: self.taa_clamp,
            ..FilterSettings::default()
        }
    }

    pub(crate) fn settings(&self) -> TraceSettings {
        let mut s = TraceSettings::new(self.size, self.size);
        s.spp = self.spp;
        s.max_depth = self.max_depth;
        s.seed_mode = self.seed_mode;
        s.environment = self.scene.environment();
        s.glossy_regularization = self.glossy_regularization;
        s.sampler_origin = gpu_tracer::scene::sampler_origin_of_salt(self.salt);
        s
    }

    pub(crate) fn layout(&self) -> Result<FrameLayout> {
        Ok(FrameLayout::new(
            self.size,
            self.size,
            self.block,
            self.tile.side(),
        )?)
    }
}
