//! The rows of the rendered-quality study: how the seeds (or random numbers) change
//! between frames.

/// How the seeds (or random numbers) change between frames.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// Fresh white-noise seeds every frame.
    White,
    /// [`Method::White`] from an independent draw of seeds
    /// ([`white_control_salt`]): equal to white in expectation, so its
    /// figures (white = 1) show how far from 1 one run reads by chance, per
    /// figure and region, in the same run as the other rows: the study's
    /// null row.
    WhiteControl,
    /// Sorting pass only (R2 walk), no retargeting.
    Sort,
    /// Sorting and retargeting with the aperiodic R2 walk: the method.
    Permute,
    /// [`Method::Permute`] with the position inside the pixel taken from the
    /// screen-space Sobol sampler (`--sampler screen-sobol-jitter`): the
    /// permutation for everything but the jitter.
    PermuteJitter,
    /// [`Method::Permute`] with the position inside the pixel from ZSobol
    /// (`--sampler zsobol-jitter`), whose frames continue one progressive net
    /// per pixel: a jitter blue in space and in time.
    PermuteZSobolJitter,
    /// Sorting and retargeting with the fixed integer step `floor(W * (a1, a2))`.
    FixedStep,
    /// Fresh white seeds plus a spatiotemporal blue-noise mask driving the first
    /// bounce's direction.
    Dither,
    /// [`Method::Dither`] with the filter-adapted mask
    /// (`sampler_core::defaults::filter_adapted_128`, EMA 0.1 x Gaussian 1.3435,
    /// issue 15) instead of STBN.
    DitherFilterAdapted,
    /// Fresh white seeds, the path's 2D decisions from the screen-space Sobol
    /// sampler with our optimised keys (`--sampler screen-sobol`, issue 6).
    ScreenSobol,
    /// Fresh white seeds, the path's 2D decisions from ZSobol (`--sampler zsobol`).
    ZSobol,
    /// Fresh white seeds, the path's 2D decisions from the spatiotemporal sampler
    /// (`--sampler spatiotemporal`, issue 29): each pixel continues one progressive
    /// Owen-scrambled Sobol sequence across frames, rotated by a blue-noise shift.
    Spatiotemporal,
    /// [`Method::Spatiotemporal`] continuing a Kronecker sequence across frames
    /// instead of Sobol (`--sampler spatiotemporal-kronecker`).
    SpatiotemporalKronecker,
    /// Sorting only, against the next slice of the STBN mask (blue in time),
    /// the seeds' streams fixed (`crate::study::temporal_sort`, CPU only).
    TemporalSort,
    /// [`Method::TemporalSort`] with the seeds' streams advancing every frame.
    TemporalSortAdvance,
    /// Sorting against STBN slice `t`, then an exact retarget table to slice
    /// `t + 1` (seeds cross block borders), fixed streams; CPU only.
    TemporalPermute,
    /// [`Method::TemporalPermute`] with the position inside the pixel from
    /// ZSobol, as [`Method::PermuteZSobolJitter`] (`--mode temporal --sampler
    /// zsobol-jitter`).
    TemporalPermuteJitter,
    /// [`Method::TemporalPermute`] with the position inside the pixel from
    /// the spatiotemporal sampler's Kronecker sequence (`PermuteMode::Temporal`
    /// with `SAMPLER_SPATIOTEMPORAL | SAMPLER_KRONECKER | SAMPLER_JITTER_ONLY`;
    /// no CLI name): a jitter whose every window of frames is evenly spread,
    /// the rest from the permuted seeds.
    TemporalPermuteKroneckerJitter,
    /// The feature-aware permutation (issue 14, `SequenceOptions::features` of the
    /// tracer's CPU loop): demodulated sort keys, blocks sorted in groups of one
    /// surface, retarget moves cut at edges, features from the G-buffer.
    FeaturePermute,
    /// [`Method::FeaturePermute`] with the pixel jitter from screen-space Sobol, as
    /// [`Method::PermuteJitter`].
    FeaturePermuteJitter,
    /// [`Method::FeaturePermute`] ranking the raw radiance luma
    /// (`gpu_tracer::feature_keys::FeatureKey::Raw`): what demodulation buys.
    FeaturePermuteRawKey,
    /// [`Method::FeaturePermute`] ranking the demodulated value minus its smoothed
    /// running mean (`FeatureKey::HistoryResidual`): the noise without the signal.
    FeaturePermuteHistoryKey,
    /// The feature-aware permutation against the temporal target
    /// (`--mode temporal --features on`): [`Method::FeaturePermute`]'s
    /// groups and cuts with [`Method::TemporalPermute`]'s slices and tables.
    FeatureTemporalPermute,
    /// [`Method::FeatureTemporalPermute`] with the pixel jitter from ZSobol,
    /// as [`Method::TemporalPermuteJitter`].
    FeatureTemporalPermuteJitter,
}

/// The salt of [`Method::WhiteControl`]'s seeds at the study's `salt`: the
/// salt with the leading 32 bits of `frac(sqrt 2)` flipped, a bijection that
/// keeps every control draw away from the consecutive salts of `--draws`
/// (and from the references' `0x5EED_xxxx` salts).
pub const fn white_control_salt(salt: u32) -> u32 {
    salt ^ 0x6A09_E667
}

impl Method {
    /// Every method, white first.
    pub const ALL: [Method; 24] = [
        Method::White,
        Method::WhiteControl,
        Method::Sort,
        Method::Permute,
        Method::PermuteJitter,
        Method::PermuteZSobolJitter,
        Method::FixedStep,
        Method::Dither,
        Method::DitherFilterAdapted,
        Method::ScreenSobol,
        Method::ZSobol,
        Method::Spatiotemporal,
        Method::SpatiotemporalKronecker,
        Method::TemporalSort,
        Method::TemporalSortAdvance,
        Method::TemporalPermute,
        Method::TemporalPermuteJitter,
        Method::TemporalPermuteKroneckerJitter,
        Method::FeaturePermute,
        Method::FeaturePermuteJitter,
        Method::FeaturePermuteRawKey,
        Method::FeaturePermuteHistoryKey,
        Method::FeatureTemporalPermute,
        Method::FeatureTemporalPermuteJitter,
    ];

    /// The rows of the report ([`crate::report`]): the baselines, the
    /// permutations and samplers a user chooses between, the render defaults
    /// ([`Method::TemporalPermuteJitter`]) and the sampler for a history
    /// ([`Method::SpatiotemporalKronecker`]), and the null row
    /// ([`Method::WhiteControl`]) that shows what chance reads in each column;
    /// the other rows (the sort-key variants, the temporal diagnostics)
    /// `conformance study` measures on request.
    pub const REPORT: [Method; 14] = [
        Method::White,
        Method::WhiteControl,
        Method::Sort,
        Method::Permute,
        Method::PermuteJitter,
        Method::FixedStep,
        Method::Dither,
        Method::DitherFilterAdapted,
        Method::ScreenSobol,
        Method::ZSobol,
        Method::FeaturePermute,
        Method::FeaturePermuteJitter,
        Method::TemporalPermuteJitter,
        Method::SpatiotemporalKronecker,
    ];

    /// The rows of issue 14's comparison (`conformance study` defaults).
    pub const FEATURE_ROWS: [Method; 5] = [
        Method::White,
        Method::Permute,
        Method::PermuteJitter,
        Method::FeaturePermute,
        Method::FeaturePermuteJitter,
    ];

    /// The trace settings' sampler of a permuting row: the a-priori sampler
    /// that takes its pixel jitter (`SAMPLER_JITTER_ONLY`) for the `-jitter`
    /// rows, else `SAMPLER_SEEDS` (every number from the permuted seeds).
    pub fn jitter_sampler(self) -> u32 {
        use kernels::abi::{
            SAMPLER_JITTER_ONLY, SAMPLER_KRONECKER, SAMPLER_SCREEN_SOBOL, SAMPLER_SEEDS,
            SAMPLER_SPATIOTEMPORAL, SAMPLER_ZSOBOL,
        };
        match self {
            Method::PermuteJitter | Method::FeaturePermuteJitter => {
                SAMPLER_SCREEN_SOBOL | SAMPLER_JITTER_ONLY
            }
            Method::PermuteZSobolJitter
            | Method::TemporalPermuteJitter
            | Method::FeatureTemporalPermuteJitter => SAMPLER_ZSOBOL | SAMPLER_JITTER_ONLY,
            Method::TemporalPermuteKroneckerJitter => {
                SAMPLER_SPATIOTEMPORAL | SAMPLER_KRONECKER | SAMPLER_JITTER_ONLY
            }
            _ => SAMPLER_SEEDS,
        }
    }

    /// The method called `name` ([`Method::name`]).
    pub fn from_name(name: &str) -> Option<Method> {
        Method::ALL.into_iter().find(|m| m.name() == name)
    }

    /// Whether the row is white noise ([`Method::White`], every figure's
    /// denominator, or [`Method::WhiteControl`], the null row): rows that a
    /// ranking of gains leaves out.
    pub fn is_white_noise(self) -> bool {
        matches!(self, Method::White | Method::WhiteControl)
    }

    /// Short name used in tables, files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Method::White => "white",
            Method::WhiteControl => "white-control",
            Method::Sort => "sort",
            Method::Permute => "permute",
            Method::PermuteJitter => "permute-jitter",
            Method::PermuteZSobolJitter => "permute-zsobol-jitter",
            Method::FixedStep => "fixed-step",
            Method::Dither => "bn-dither",
            Method::DitherFilterAdapted => "bn-dither-fa",
            Method::ScreenSobol => "screen-sobol",
            Method::ZSobol => "zsobol",
            Method::Spatiotemporal => "spatiotemporal",
            Method::SpatiotemporalKronecker => "spatiotemporal-kronecker",
            Method::TemporalSort => "temporal-sort",
            Method::TemporalSortAdvance => "temporal-sort-advance",
            Method::TemporalPermute => "temporal-permute",
            Method::TemporalPermuteJitter => "temporal-permute-jitter",
            Method::TemporalPermuteKroneckerJitter => "temporal-permute-kronecker-jitter",
            Method::FeaturePermute => "feature-permute",
            Method::FeaturePermuteJitter => "feature-permute-jitter",
            Method::FeaturePermuteRawKey => "feature-permute-raw-key",
            Method::FeaturePermuteHistoryKey => "feature-permute-history-key",
            Method::FeatureTemporalPermute => "feature-temporal-permute",
            Method::FeatureTemporalPermuteJitter => "feature-temporal-permute-jitter",
        }
    }

    /// One-line description.
    pub fn describe(self) -> &'static str {
        match self {
            Method::White => "fresh white-noise seeds every frame",
            Method::WhiteControl => {
                "fresh white-noise seeds every frame, an independent draw: the null row (reads 1 but for chance)"
            }
            Method::Sort => "sorting pass only (R2 walk), no retargeting",
            Method::Permute => "sorting + retargeting, aperiodic R2 offset walk",
            Method::PermuteJitter => "permute, with the pixel jitter from screen-space Sobol",
            Method::PermuteZSobolJitter => {
                "permute, with the pixel jitter from ZSobol (progressive over frames)"
            }
            Method::FixedStep => "sorting + retargeting, fixed integer step floor(W*(a1,a2))",
            Method::Dither => "white seeds + STBN mask on the first bounce direction",
            Method::DitherFilterAdapted => {
                "white seeds + the filter-adapted mask (EMA 0.1 x Gaussian) on the first bounce direction"
            }
            Method::ScreenSobol => "white seeds + screen-space Sobol (our keys) on every 2D decision",
            Method::ZSobol => "white seeds + ZSobol on every 2D decision",
            Method::Spatiotemporal => {
                "white seeds + one progressive Sobol sequence per pixel across frames, blue-noise shifts"
            }
            Method::SpatiotemporalKronecker => {
                "white seeds + one Kronecker sequence per pixel across frames, blue-noise shifts"
            }
            Method::TemporalSort => {
                "sorting pass only, against the next STBN slice (blue in time), fixed streams"
            }
            Method::TemporalSortAdvance => {
                "sorting pass only, against the next STBN slice (blue in time), streams advance every frame"
            }
            Method::TemporalPermute => {
                "sorting against STBN slice t + retarget table to slice t + 1 (blue in time), fixed streams"
            }
            Method::TemporalPermuteJitter => "temporal-permute, with the pixel jitter from ZSobol",
            Method::TemporalPermuteKroneckerJitter => {
                "temporal-permute, with the pixel jitter from the spatiotemporal Kronecker sequence"
            }
            Method::FeaturePermute => {
                "feature-aware permute: demodulated keys, groups of one surface, cut retarget moves"
            }
            Method::FeaturePermuteJitter => {
                "feature-aware permute, with the pixel jitter from screen-space Sobol"
            }
            Method::FeaturePermuteRawKey => {
                "feature-aware permute ranking the raw radiance (no demodulation)"
            }
            Method::FeaturePermuteHistoryKey => {
                "feature-aware permute ranking the demodulated value minus its smoothed running mean"
            }
            Method::FeatureTemporalPermute => {
                "feature-aware temporal-permute: groups of one surface and cut moves, STBN slices and tables"
            }
            Method::FeatureTemporalPermuteJitter => {
                "feature-aware temporal-permute, with the pixel jitter from ZSobol"
            }
        }
    }
}
