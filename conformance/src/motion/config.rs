//! What the motion study renders ([`MotionConfig`]).

use super::history::HistoryFetch;
use gpu_tracer::scene::TraceSettings;
use gpu_tracer::TileChoice;
use kernels::abi::SEED_MODE_FIXED;

/// What to render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionConfig {
    /// Image side in pixels (square frames), at least 32.
    pub size: u32,
    /// Frames per sequence and method (1 spp each).
    pub frames: u32,
    /// Samples per pixel of each pose's reference (two halves).
    pub ref_spp: u32,
    /// Maximum path length in segments.
    pub max_depth: u32,
    /// Block side of the sorting pass.
    pub block: u32,
    /// Dither tile.
    pub tile: TileChoice,
    /// The draw: salt of the initial white-noise seeds, and where the
    /// a-priori samplers' per-pixel data sits on the screen
    /// (`gpu_tracer::scene::sampler_origin_of_salt`; salt 1: as baked).
    pub salt: u32,
    /// Sway period in frames (a multiple of 4), `None` for
    /// [`sway_period`](super::case::sway_period) (`size / 4`).
    pub sway_period: Option<u32>,
    /// How the EMA's history reads its previous values (default: nearest pixel).
    pub history_fetch: HistoryFetch,
}

impl MotionConfig {
    /// Defaults: depth 8, 4x4 blocks, 64x64 tile, salt 1, sway period `size / 4`,
    /// nearest-pixel history fetch.
    pub fn new(size: u32, frames: u32, ref_spp: u32) -> Self {
        MotionConfig {
            size,
            frames,
            ref_spp,
            max_depth: 8,
            block: 4,
            tile: TileChoice::Tile64,
            salt: 1,
            sway_period: None,
            history_fetch: HistoryFetch::Nearest,
        }
    }

    pub(crate) fn settings(&self) -> TraceSettings {
        let mut s = TraceSettings::new(self.size, self.size);
        s.max_depth = self.max_depth;
        s.seed_mode = SEED_MODE_FIXED;
        s.sampler_origin = gpu_tracer::scene::sampler_origin_of_salt(self.salt);
        s
    }
}
