//! The permutation mode and sampler a render takes when its caller leaves one
//! or both out.
//!
//! The defaults are the combination measured best on the four study scenes
//! (Cornell box, glossy box, textured box, sun and sky; QUALITY.md, "The
//! defaults"): the temporally blue permutation ([`PermuteMode::Temporal`])
//! with ZSobol's pixel jitter ([`DEFAULT_PERMUTE_SAMPLER`]). Per frame it
//! keeps the permutation's flat walls and the a-priori jitter's silhouettes;
//! behind a history it keeps less of white noise's error than any other
//! permutation on every scene, where the published method (the R2 walk with
//! every number from the seeds) is white in time and 2-8% worse than white
//! on the whole image behind a history.

use crate::render::TileChoice;
use crate::scene::{TraceSettings, ZSOBOL_MAX_SPP};
use crate::PermuteMode;
use kernels::abi::{
    SAMPLER_JITTER_ONLY, SAMPLER_KIND_MASK, SAMPLER_KRONECKER, SAMPLER_SCREEN_SOBOL, SAMPLER_SEEDS,
    SAMPLER_SPATIOTEMPORAL, SAMPLER_ZSOBOL,
};

/// The sampler of the modes that permute seeds ([`PermuteMode::Sort`],
/// [`PermuteMode::Permute`], [`PermuteMode::Temporal`]) when none is named:
/// the position inside the pixel from ZSobol, whose frames are digital
/// shifts of one net (so a pixel's jitter is stratified in space and over
/// frames), every other number from the permuted seeds.
pub const DEFAULT_PERMUTE_SAMPLER: u32 = SAMPLER_ZSOBOL | SAMPLER_JITTER_ONLY;

/// The sampler of [`PermuteMode::Hold`] when none is named: the
/// spatiotemporal sampler with its Kronecker sequence in time, the row that
/// keeps least of white's error behind a history.
pub const DEFAULT_HOLD_SAMPLER: u32 = SAMPLER_SPATIOTEMPORAL | SAMPLER_KRONECKER;

/// Pixels per frame below which a pixel's seed stays where it is when seeds
/// are reprojected (`SequenceOptions::reproject_hold_below`) in
/// [`PermuteMode::Temporal`]: slower surfaces keep their seeds at their
/// pixels, faster ones carry them along. Measured for the defaults
/// (QUALITY.md, "Slow surfaces keep their seeds"): leaving seeds at their
/// pixels wins up to about 4 px/frame, following the surface from about 8,
/// and 6 per pixel beat 3 and 9.
pub const DEFAULT_REPROJECT_HOLD_BELOW: f32 = 6.0;

/// Share of a frame's pixels that must move rigidly
/// (`kernels::motion::moves_rigidly`) for every seed to follow its surface
/// in that frame, whatever its speed (`SequenceOptions::reproject_follow_share`)
/// in [`PermuteMode::Temporal`]. At 128x128 a camera pan moves 66-86% of
/// the Cornell box rigidly at 2 px/frame, an orbit about 27%, a moving block
/// 6%; below a pixel a frame nothing counts. Measured for the defaults
/// (QUALITY.md, "Pans follow"): with it the default is within 0.9% of the
/// better of reprojection on and off on the pans, orbits and block it was
/// chosen on, where the speed rule alone missed a pan at 2 px/frame by 2.7%.
/// Since the rigid tolerance grows with the speed
/// (`kernels::motion::RIGID_WITHIN_PER_SPEED`) pans at 3-5 px/frame count
/// as rigid too (0.71-0.76 of the pixels) and meet the criterion (at most
/// 1.8%, QUALITY.md "Pans follow at every speed"); a held-out orbit at
/// 3.6 px/frame misses by 4.0% through the speed rule's fast surfaces.
pub const DEFAULT_REPROJECT_FOLLOW_SHARE: f32 = 0.5;

/// [`DEFAULT_REPROJECT_HOLD_BELOW`] for the walk's modes
/// ([`PermuteMode::Permute`], [`PermuteMode::Sort`]): 4 px/frame, inside the
/// walk's own crossover (QUALITY.md, "Seeds in motion": leaving its seeds
/// wins at 2.4 px/frame, following them at 4.7). Not measured per pixel.
pub const WALK_REPROJECT_HOLD_BELOW: f32 = 4.0;

/// The speed below which seeds stay, per mode: [`DEFAULT_REPROJECT_HOLD_BELOW`]
/// for [`PermuteMode::Temporal`], [`WALK_REPROJECT_HOLD_BELOW`] for the walk's
/// modes, 0 for [`PermuteMode::Hold`], whose homes must follow every surface
/// (each point keeps its shift), and for [`PermuteMode::White`], which never
/// reprojects.
pub fn default_reproject_hold_below(mode: PermuteMode) -> f32 {
    match mode {
        PermuteMode::Temporal => DEFAULT_REPROJECT_HOLD_BELOW,
        PermuteMode::Sort | PermuteMode::Permute => WALK_REPROJECT_HOLD_BELOW,
        PermuteMode::Hold | PermuteMode::White => 0.0,
    }
}

/// What the frames are accumulated by, as far as the choice of defaults goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum History {
    /// Raw frames, or a history clamped to the current frame's neighbourhood
    /// (TAA as renderers run it): the defaults are the temporal permutation
    /// with ZSobol's jitter.
    Clamped,
    /// A history that keeps its past without clamping it (SVGF's temporal
    /// accumulation, a running mean): the defaults are [`PermuteMode::Hold`]
    /// with [`DEFAULT_HOLD_SAMPLER`]. Behind such a history a permutation's
    /// error stays in place from frame to frame and reads worse than white
    /// noise in flat regions, where the spatiotemporal sampler's sequences
    /// converge (QUALITY.md, "Without TAA's clamp").
    Unclamped,
}

/// The frame-wide follow rule per mode: [`DEFAULT_REPROJECT_FOLLOW_SHARE`]
/// for [`PermuteMode::Temporal`], 0 (off) for the others: the walk's modes
/// were not measured with it, and [`PermuteMode::Hold`] follows every
/// surface anyway.
pub fn default_reproject_follow_share(mode: PermuteMode) -> f32 {
    match mode {
        PermuteMode::Temporal => DEFAULT_REPROJECT_FOLLOW_SHARE,
        PermuteMode::Sort | PermuteMode::Permute | PermuteMode::Hold | PermuteMode::White => 0.0,
    }
}

/// A render's mode and sampler, named or chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MethodChoice {
    /// How seeds change between frames.
    pub mode: PermuteMode,
    /// The trace's sampler flags ([`TraceSettings::sampler`]).
    pub sampler: u32,
    /// Why the default sampler could not be taken and the seed stream was,
    /// when that happened (a line for the user); `None` otherwise.
    pub fallback: Option<&'static str>,
}

/// The mode when none is named: [`PermuteMode::Hold`] for the
/// spatiotemporal sampler (it draws every number itself),
/// [`PermuteMode::White`] for an a-priori sampler that draws every 2D
/// decision (`SAMPLER_SCREEN_SOBOL` or `SAMPLER_ZSOBOL` without
/// `SAMPLER_JITTER_ONLY`: the seeds would drive Russian roulette alone, as
/// the study's rows of those samplers have it), the walk's
/// [`PermuteMode::Permute`] when a tile other than the temporal target's
/// 64x64 one is asked for, [`PermuteMode::Hold`] (so the spatiotemporal
/// sampler) behind a [`History::Unclamped`] history when neither a sampler
/// nor a tile is named, else [`PermuteMode::Temporal`].
pub fn default_mode(sampler: Option<u32>, tile: Option<TileChoice>, history: History) -> PermuteMode {
    let kind = sampler.map(|s| s & SAMPLER_KIND_MASK);
    let jitter_only = sampler.is_some_and(|s| s & SAMPLER_JITTER_ONLY != 0);
    let unclamped_default = sampler.is_none() && tile.is_none() && history == History::Unclamped;
    if kind == Some(SAMPLER_SPATIOTEMPORAL) || unclamped_default {
        PermuteMode::Hold
    } else if matches!(kind, Some(SAMPLER_SCREEN_SOBOL | SAMPLER_ZSOBOL)) && !jitter_only {
        PermuteMode::White
    } else if tile.is_some_and(|t| t != TileChoice::TEMPORAL) {
        PermuteMode::Permute
    } else {
        PermuteMode::Temporal
    }
}

/// The sampler when none is named, for `mode` and the frame in `settings`
/// (its `sampler` field is ignored): the seed stream for
/// [`PermuteMode::White`] (the baseline stays white noise),
/// [`DEFAULT_HOLD_SAMPLER`] for [`PermuteMode::Hold`], and
/// [`DEFAULT_PERMUTE_SAMPLER`] for the modes that permute seeds, or the seed
/// stream with a reason where ZSobol cannot render the frame (more than
/// [`ZSOBOL_MAX_SPP`] spp or a side above 4096 pixels).
pub fn default_sampler(mode: PermuteMode, settings: &TraceSettings) -> (u32, Option<&'static str>) {
    match mode {
        PermuteMode::White => (SAMPLER_SEEDS, None),
        PermuteMode::Hold => (DEFAULT_HOLD_SAMPLER, None),
        PermuteMode::Sort | PermuteMode::Permute | PermuteMode::Temporal => {
            let side = settings.width.max(settings.height);
            if settings.spp <= ZSOBOL_MAX_SPP && side <= sampler_core::sequences::zsobol::ZSOBOL_TILE {
                (DEFAULT_PERMUTE_SAMPLER, None)
            } else {
                (
                    SAMPLER_SEEDS,
                    Some(
                        "the default pixel jitter (zsobol-jitter) takes at most 256 spp and 4096 pixels a side: \
                         every number comes from the seeds",
                    ),
                )
            }
        }
    }
}

/// The mode and sampler of a render whose caller named `mode` and `sampler`
/// or left them out (`None`): a named one is kept as it is (whether the two
/// go together is [`crate::RenderJob::validate`]'s to say), a missing one is
/// [`default_mode`] (which takes `history`) or [`default_sampler`] of the
/// other.
pub fn choose_method(
    mode: Option<PermuteMode>,
    sampler: Option<u32>,
    tile: Option<TileChoice>,
    history: History,
    settings: &TraceSettings,
) -> MethodChoice {
    let mode = mode.unwrap_or_else(|| default_mode(sampler, tile, history));
    let (sampler, fallback) = match sampler {
        Some(s) => (s, None),
        None => default_sampler(mode, settings),
    };
    MethodChoice {
        mode,
        sampler,
        fallback,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(width: u32, height: u32, spp: u32) -> TraceSettings {
        TraceSettings {
            spp,
            ..TraceSettings::new(width, height)
        }
    }

    #[test]
    fn nothing_named_is_the_temporal_permutation_with_zsobols_jitter() {
        let c = choose_method(None, None, None, History::Clamped, &frame(512, 512, 1));
        assert_eq!(c.mode, PermuteMode::Temporal);
        assert_eq!(c.sampler, SAMPLER_ZSOBOL | SAMPLER_JITTER_ONLY);
        assert_eq!(c.fallback, None);
    }

    #[test]
    fn a_named_mode_or_sampler_is_kept_and_the_other_follows_it() {
        let f = frame(256, 256, 4);
        let white = choose_method(Some(PermuteMode::White), None, None, History::Clamped, &f);
        assert_eq!((white.mode, white.sampler), (PermuteMode::White, SAMPLER_SEEDS));
        let walk = choose_method(Some(PermuteMode::Permute), None, None, History::Clamped, &f);
        assert_eq!(
            (walk.mode, walk.sampler),
            (PermuteMode::Permute, DEFAULT_PERMUTE_SAMPLER)
        );
        let hold = choose_method(Some(PermuteMode::Hold), None, None, History::Clamped, &f);
        assert_eq!(hold.sampler, DEFAULT_HOLD_SAMPLER);
        let seeds = choose_method(None, Some(SAMPLER_SEEDS), None, History::Clamped, &f);
        assert_eq!(
            (seeds.mode, seeds.sampler),
            (PermuteMode::Temporal, SAMPLER_SEEDS)
        );
        let st = choose_method(None, Some(SAMPLER_SPATIOTEMPORAL), None, History::Clamped, &f);
        assert_eq!(st.mode, PermuteMode::Hold);
        let sobol = choose_method(
            Some(PermuteMode::Sort),
            Some(SAMPLER_SCREEN_SOBOL),
            None,
            History::Clamped,
            &f,
        );
        assert_eq!(
            (sobol.mode, sobol.sampler),
            (PermuteMode::Sort, SAMPLER_SCREEN_SOBOL)
        );
    }

    #[test]
    fn a_sampler_that_draws_every_decision_renders_with_white_seeds() {
        let f = frame(64, 64, 1);
        for s in [SAMPLER_SCREEN_SOBOL, SAMPLER_ZSOBOL] {
            assert_eq!(
                choose_method(None, Some(s), None, History::Clamped, &f).mode,
                PermuteMode::White
            );
            let jitter = choose_method(None, Some(s | SAMPLER_JITTER_ONLY), None, History::Clamped, &f);
            assert_eq!(jitter.mode, PermuteMode::Temporal);
        }
    }

    #[test]
    fn an_unclamped_history_takes_the_spatiotemporal_sampler_unless_something_is_named() {
        let f = frame(256, 256, 1);
        let c = choose_method(None, None, None, History::Unclamped, &f);
        assert_eq!((c.mode, c.sampler), (PermuteMode::Hold, DEFAULT_HOLD_SAMPLER));
        let named = choose_method(Some(PermuteMode::Temporal), None, None, History::Unclamped, &f);
        assert_eq!(
            (named.mode, named.sampler),
            (PermuteMode::Temporal, DEFAULT_PERMUTE_SAMPLER)
        );
        let seeds = choose_method(None, Some(SAMPLER_SEEDS), None, History::Unclamped, &f);
        assert_eq!(seeds.mode, PermuteMode::Temporal);
        let walk = choose_method(None, None, Some(TileChoice::Tile128), History::Unclamped, &f);
        assert_eq!(walk.mode, PermuteMode::Permute);
    }

    #[test]
    fn seeds_stay_below_each_modes_crossover_and_homes_always_follow() {
        assert_eq!(default_reproject_hold_below(PermuteMode::Temporal), 6.0);
        assert_eq!(default_reproject_hold_below(PermuteMode::Permute), 4.0);
        assert_eq!(default_reproject_hold_below(PermuteMode::Sort), 4.0);
        assert_eq!(default_reproject_hold_below(PermuteMode::Hold), 0.0);
        assert_eq!(default_reproject_hold_below(PermuteMode::White), 0.0);
        assert_eq!(default_reproject_follow_share(PermuteMode::Temporal), 0.5);
        for m in [
            PermuteMode::Permute,
            PermuteMode::Sort,
            PermuteMode::Hold,
            PermuteMode::White,
        ] {
            assert_eq!(default_reproject_follow_share(m), 0.0, "{m:?}");
        }
    }

    #[test]
    fn the_128_tile_takes_the_walk_because_the_temporal_target_is_64() {
        let c = choose_method(
            None,
            None,
            Some(TileChoice::Tile128),
            History::Clamped,
            &frame(64, 64, 1),
        );
        assert_eq!(c.mode, PermuteMode::Permute);
        let c = choose_method(
            None,
            None,
            Some(TileChoice::Tile64),
            History::Clamped,
            &frame(64, 64, 1),
        );
        assert_eq!(c.mode, PermuteMode::Temporal);
    }

    #[test]
    fn frames_zsobol_cannot_render_fall_back_to_the_seeds_and_say_why() {
        for f in [
            frame(64, 64, ZSOBOL_MAX_SPP + 1),
            frame(4097, 8, 1),
            frame(8, 4097, 1),
        ] {
            let c = choose_method(None, None, None, History::Clamped, &f);
            assert_eq!(c.sampler, SAMPLER_SEEDS, "{f:?}");
            assert!(c.fallback.is_some_and(|why| why.contains("zsobol")), "{f:?}");
        }
        let edge = choose_method(
            None,
            None,
            None,
            History::Clamped,
            &frame(4096, 4096, ZSOBOL_MAX_SPP),
        );
        assert_eq!((edge.sampler, edge.fallback), (DEFAULT_PERMUTE_SAMPLER, None));
    }
}
