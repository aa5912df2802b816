//! The rows of the motion study: which seeds and sampler each uses, as a render job.

use super::config::MotionConfig;
use gpu_tracer::render::SequenceOptions;
use gpu_tracer::{PermuteMode, RenderJob};

/// Which seeds and sampler a row uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MotionMethod {
    /// Fresh white-noise seeds every frame.
    White,
    /// [`MotionMethod::White`] from an independent draw of seeds
    /// ([`crate::study::white_control_salt`]): the null row, equal to white
    /// in expectation, whose figures show how far from 1 (and its in motion /
    /// still ratios how far from 1) one run reads by chance.
    WhiteControl,
    /// The permutation, seeds left at their pixels when things move.
    Permute,
    /// The permutation with the seeds reprojected along the motion vectors.
    PermuteReproject,
    /// The permutation with the pixel jitter from screen-space Sobol, reprojected.
    PermuteJitterReproject,
    /// The feature-aware permutation (issue 14), reprojected.
    FeaturePermuteReproject,
    /// White seeds and screen-space Sobol on every 2D decision.
    ScreenSobol,
    /// The spatiotemporal sampler on every decision (issue 29): one progressive
    /// sequence per pixel across frames, its shift read at the screen pixel.
    Spatiotemporal,
    /// The spatiotemporal sampler with its homes moved along the motion
    /// (hold mode with reprojection): each surface point keeps its shift.
    SpatiotemporalFollow,
    /// [`MotionMethod::SpatiotemporalFollow`] with the Kronecker sequence in
    /// time (`--sampler spatiotemporal-kronecker`).
    SpatiotemporalKroneckerFollow,
    /// White seeds and ZSobol on every 2D decision (`--sampler zsobol`): its
    /// frames digital shifts of one net, each pixel's point fixed on the screen.
    ZSobol,
    /// ZSobol on every 2D decision with its homes moved along the motion
    /// (`--mode hold --sampler zsobol` with reprojection): each surface point
    /// keeps its pixel's point of the net, so a history that follows the
    /// surface reads one pixel's sequence of frames.
    ZSobolFollow,
    /// The temporal permutation (`--mode temporal`, the 64 tile) with ZSobol's
    /// jitter (`--sampler zsobol-jitter`), seeds left at their pixels when
    /// things move: the render defaults with `--reproject off`.
    TemporalPermuteJitter,
    /// [`MotionMethod::TemporalPermuteJitter`] with every seed reprojected.
    TemporalPermuteJitterReproject,
    /// [`MotionMethod::TemporalPermuteJitterReproject`] with the
    /// feature-aware permutation (`--mode temporal --features on`).
    FeatureTemporalPermuteJitterReproject,
    /// [`MotionMethod::TemporalPermuteJitterReproject`] with the seeds of
    /// pixels slower than `gpu_tracer::method_choice::DEFAULT_REPROJECT_HOLD_BELOW`
    /// left at their pixels (`SequenceOptions::reproject_hold_below`), except
    /// in frames that move rigidly
    /// (`gpu_tracer::method_choice::DEFAULT_REPROJECT_FOLLOW_SHARE`): the
    /// render defaults when something moves (with the pan offset:
    /// ZSobol's points follow the frames that follow as a whole).
    TemporalPermuteJitterReprojectFast,
    /// [`MotionMethod::TemporalPermuteJitterReprojectFast`] without the pan
    /// offset (`SequenceOptions::pan_offset` off, `--pan-offset off`):
    /// ZSobol's points stay on the screen.
    TemporalPermuteJitterReprojectFastScreen,
}

impl MotionMethod {
    /// Every row, white first.
    pub const ALL: [MotionMethod; 17] = [
        MotionMethod::White,
        MotionMethod::WhiteControl,
        MotionMethod::Permute,
        MotionMethod::PermuteReproject,
        MotionMethod::PermuteJitterReproject,
        MotionMethod::FeaturePermuteReproject,
        MotionMethod::ScreenSobol,
        MotionMethod::Spatiotemporal,
        MotionMethod::SpatiotemporalFollow,
        MotionMethod::SpatiotemporalKroneckerFollow,
        MotionMethod::ZSobol,
        MotionMethod::ZSobolFollow,
        MotionMethod::TemporalPermuteJitter,
        MotionMethod::TemporalPermuteJitterReproject,
        MotionMethod::FeatureTemporalPermuteJitterReproject,
        MotionMethod::TemporalPermuteJitterReprojectFast,
        MotionMethod::TemporalPermuteJitterReprojectFastScreen,
    ];

    /// Short name on the command line (`conformance motion --methods`): the
    /// study's method names ([`crate::study::Method::name`]) where a row is one
    /// of them, with `-reproject` where the seeds follow the motion.
    pub fn key(self) -> &'static str {
        match self {
            MotionMethod::White => "white",
            MotionMethod::WhiteControl => "white-control",
            MotionMethod::Permute => "permute",
            MotionMethod::PermuteReproject => "permute-reproject",
            MotionMethod::PermuteJitterReproject => "permute-jitter-reproject",
            MotionMethod::FeaturePermuteReproject => "feature-permute-reproject",
            MotionMethod::ScreenSobol => "screen-sobol",
            MotionMethod::Spatiotemporal => "spatiotemporal",
            MotionMethod::SpatiotemporalFollow => "spatiotemporal-follow",
            MotionMethod::SpatiotemporalKroneckerFollow => "spatiotemporal-kronecker-follow",
            MotionMethod::ZSobol => "zsobol",
            MotionMethod::ZSobolFollow => "zsobol-follow",
            MotionMethod::TemporalPermuteJitter => "temporal-permute-jitter",
            MotionMethod::TemporalPermuteJitterReproject => "temporal-permute-jitter-reproject",
            MotionMethod::FeatureTemporalPermuteJitterReproject => {
                "feature-temporal-permute-jitter-reproject"
            }
            MotionMethod::TemporalPermuteJitterReprojectFast => "temporal-permute-jitter-reproject-fast",
            MotionMethod::TemporalPermuteJitterReprojectFastScreen => {
                "temporal-permute-jitter-reproject-fast-screen"
            }
        }
    }

    /// The rows named by `keys` ([`MotionMethod::key`]), white first (every
    /// figure is relative to it) and each row once, in the order given;
    /// every row ([`MotionMethod::ALL`]) when `keys` is empty. An unknown key
    /// is an error that lists the known ones.
    pub fn rows_named<S: AsRef<str>>(keys: &[S]) -> anyhow::Result<Vec<MotionMethod>> {
        if keys.is_empty() {
            return Ok(MotionMethod::ALL.to_vec());
        }
        let mut rows = vec![MotionMethod::White];
        for key in keys {
            let key = key.as_ref();
            let row = MotionMethod::ALL
                .into_iter()
                .find(|m| m.key() == key)
                .ok_or_else(|| {
                    let known: Vec<&str> = MotionMethod::ALL.iter().map(|m| m.key()).collect();
                    anyhow::anyhow!("unknown motion row {key:?} (known: {})", known.join(", "))
                })?;
            if !rows.contains(&row) {
                rows.push(row);
            }
        }
        Ok(rows)
    }

    /// Name used in tables.
    pub fn name(self) -> &'static str {
        match self {
            MotionMethod::White => "white",
            MotionMethod::WhiteControl => "white, another draw (the null row)",
            MotionMethod::Permute => "permute, no reprojection",
            MotionMethod::PermuteReproject => "permute + reprojection",
            MotionMethod::PermuteJitterReproject => "permute-jitter + reprojection",
            MotionMethod::FeaturePermuteReproject => "feature-aware permute + reprojection",
            MotionMethod::ScreenSobol => "screen-sobol",
            MotionMethod::Spatiotemporal => "spatiotemporal, shifts at the pixels",
            MotionMethod::SpatiotemporalFollow => "spatiotemporal, shifts follow (hold + reprojection)",
            MotionMethod::SpatiotemporalKroneckerFollow => "spatiotemporal-kronecker, shifts follow",
            MotionMethod::ZSobol => "zsobol",
            MotionMethod::ZSobolFollow => "zsobol, points follow (hold + reprojection)",
            MotionMethod::TemporalPermuteJitter => "temporal-permute + zsobol jitter, no reprojection",
            MotionMethod::TemporalPermuteJitterReproject => "temporal-permute + zsobol jitter + reprojection",
            MotionMethod::FeatureTemporalPermuteJitterReproject => {
                "feature-aware temporal-permute + zsobol jitter + reprojection"
            }
            MotionMethod::TemporalPermuteJitterReprojectFast => {
                "temporal-permute + zsobol jitter + reprojection of fast surfaces and rigid frames (the default)"
            }
            MotionMethod::TemporalPermuteJitterReprojectFastScreen => {
                "temporal-permute + zsobol jitter + reprojection of fast surfaces and rigid frames, zsobol on the screen"
            }
        }
    }

    /// The render job and sequence options of this row.
    pub(super) fn job(self, config: &MotionConfig) -> (RenderJob, SequenceOptions) {
        let mut settings = config.settings();
        settings.spp = 1;
        let features = matches!(
            self,
            MotionMethod::FeaturePermuteReproject | MotionMethod::FeatureTemporalPermuteJitterReproject
        );
        let (mode, reproject) = match self {
            MotionMethod::White | MotionMethod::WhiteControl => (PermuteMode::White, false),
            MotionMethod::FeaturePermuteReproject => (PermuteMode::Permute, true),
            MotionMethod::Permute => (PermuteMode::Permute, false),
            MotionMethod::PermuteReproject => (PermuteMode::Permute, true),
            MotionMethod::PermuteJitterReproject => {
                settings.sampler = kernels::abi::SAMPLER_SCREEN_SOBOL | kernels::abi::SAMPLER_JITTER_ONLY;
                (PermuteMode::Permute, true)
            }
            MotionMethod::ScreenSobol => {
                settings.sampler = kernels::abi::SAMPLER_SCREEN_SOBOL;
                (PermuteMode::White, false)
            }
            MotionMethod::Spatiotemporal => {
                settings.sampler = kernels::abi::SAMPLER_SPATIOTEMPORAL;
                (PermuteMode::White, false)
            }
            MotionMethod::SpatiotemporalFollow => {
                settings.sampler = kernels::abi::SAMPLER_SPATIOTEMPORAL;
                (PermuteMode::Hold, true)
            }
            MotionMethod::SpatiotemporalKroneckerFollow => {
                settings.sampler = kernels::abi::SAMPLER_SPATIOTEMPORAL | kernels::abi::SAMPLER_KRONECKER;
                (PermuteMode::Hold, true)
            }
            MotionMethod::ZSobol => {
                settings.sampler = kernels::abi::SAMPLER_ZSOBOL;
                (PermuteMode::White, false)
            }
            MotionMethod::ZSobolFollow => {
                settings.sampler = kernels::abi::SAMPLER_ZSOBOL;
                (PermuteMode::Hold, true)
            }
            MotionMethod::TemporalPermuteJitter => {
                settings.sampler = kernels::abi::SAMPLER_ZSOBOL | kernels::abi::SAMPLER_JITTER_ONLY;
                (PermuteMode::Temporal, false)
            }
            MotionMethod::TemporalPermuteJitterReproject
            | MotionMethod::FeatureTemporalPermuteJitterReproject
            | MotionMethod::TemporalPermuteJitterReprojectFast
            | MotionMethod::TemporalPermuteJitterReprojectFastScreen => {
                settings.sampler = kernels::abi::SAMPLER_ZSOBOL | kernels::abi::SAMPLER_JITTER_ONLY;
                (PermuteMode::Temporal, true)
            }
        };
        let tile = if mode == PermuteMode::Temporal {
            gpu_tracer::TileChoice::TEMPORAL
        } else {
            config.tile
        };
        let job = RenderJob {
            settings,
            frames: config.frames,
            mode,
            block: config.block,
            tile,
            salt: match self {
                MotionMethod::WhiteControl => crate::study::white_control_salt(config.salt),
                _ => config.salt,
            },
        };
        let fast = matches!(
            self,
            MotionMethod::TemporalPermuteJitterReprojectFast
                | MotionMethod::TemporalPermuteJitterReprojectFastScreen
        );
        let (hold_below, follow_share) = if fast {
            (
                gpu_tracer::method_choice::DEFAULT_REPROJECT_HOLD_BELOW,
                gpu_tracer::method_choice::DEFAULT_REPROJECT_FOLLOW_SHARE,
            )
        } else {
            (0.0, 0.0)
        };
        let options = SequenceOptions {
            gbuffer: false,
            reproject,
            reproject_hold_below: hold_below,
            reproject_follow_share: follow_share,
            pan_offset: self == MotionMethod::TemporalPermuteJitterReprojectFast,
            features,
            ..SequenceOptions::default()
        };
        (job, options)
    }
}

#[cfg(test)]
mod tests {
    use super::MotionMethod;
    use std::collections::HashSet;

    #[test]
    fn every_row_has_its_own_key() {
        let keys: HashSet<&str> = MotionMethod::ALL.iter().map(|m| m.key()).collect();
        assert_eq!(keys.len(), MotionMethod::ALL.len());
        for m in MotionMethod::ALL {
            assert_eq!(MotionMethod::rows_named(&[m.key()]).unwrap().last(), Some(&m));
        }
    }

    #[test]
    fn the_null_row_draws_other_seeds_and_nothing_else() {
        let config = super::MotionConfig::new(32, 8, 4);
        let (white, white_options) = MotionMethod::White.job(&config);
        let (control, control_options) = MotionMethod::WhiteControl.job(&config);
        assert_ne!(control.salt, white.salt);
        assert_eq!(control.salt, crate::study::white_control_salt(white.salt));
        assert_eq!(control.mode, white.mode);
        assert_eq!(control.settings.sampler, white.settings.sampler);
        assert_eq!(control_options.reproject, white_options.reproject);
    }

    #[test]
    fn named_rows_start_with_white_and_appear_once() {
        let rows = MotionMethod::rows_named(&["zsobol", "permute-reproject", "zsobol", "white"]).unwrap();
        assert_eq!(
            rows,
            [
                MotionMethod::White,
                MotionMethod::ZSobol,
                MotionMethod::PermuteReproject
            ]
        );
        let none: [&str; 0] = [];
        assert_eq!(MotionMethod::rows_named(&none).unwrap(), MotionMethod::ALL);
    }

    #[test]
    fn an_unknown_row_lists_the_known_keys() {
        let err = MotionMethod::rows_named(&["zsobol", "permute+reproject"])
            .unwrap_err()
            .to_string();
        assert!(err.contains("\"permute+reproject\""), "{err}");
        assert!(err.contains("temporal-permute-jitter-reproject-fast"), "{err}");
    }
}
