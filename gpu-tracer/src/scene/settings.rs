//! Settings of the trace pass ([`TraceSettings`]) and the [`TraceParams`]
//! they make with a scene's buffers ([`SceneGpu::trace_params`]).

use super::buffers::SceneGpu;
use crate::error::{Error, Result};
use kernels::abi::{
    TraceParams, MAX_DEPTH_LIMIT, SAMPLER_JITTER_ONLY, SAMPLER_KIND_MASK, SAMPLER_SCREEN_SOBOL,
    SAMPLER_ZSOBOL, SEED_MODE_ADVANCE,
};

/// Settings of the trace pass that do not depend on the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraceSettings {
    /// Visible width in pixels, `>= 1`.
    pub width: u32,
    /// Visible height in pixels, `>= 1`.
    pub height: u32,
    /// Seed-buffer stride in seeds, `>= width` (the padded width of
    /// `sampler_core::FrameLayout`).
    pub padded_width: u32,
    /// Samples per pixel per frame, `>= 1`.
    pub spp: u32,
    /// Maximum path length in segments, `1..=MAX_DEPTH_LIMIT`.
    pub max_depth: u32,
    /// First path vertex subject to Russian roulette (see
    /// [`TraceParams::rr_depth`]).
    pub rr_depth: u32,
    /// [`kernels::abi::SEED_MODE_FIXED`] or [`SEED_MODE_ADVANCE`].
    pub seed_mode: u32,
    /// Source of the path's 2D decisions (jitter, light samples, BSDF
    /// directions): [`kernels::abi::SAMPLER_SEEDS`]
    /// (the seed stream), [`SAMPLER_SCREEN_SOBOL`] (at most
    /// [`screen_sobol_max_spp`] spp) or [`SAMPLER_ZSOBOL`] (at most
    /// [`ZSOBOL_MAX_SPP`] spp, width and height at most
    /// `sampler_core::sequences::zsobol::ZSOBOL_TILE`); either a-priori sampler may be
    /// ORed with [`SAMPLER_JITTER_ONLY`] (only the position inside the pixel
    /// from the sampler, the rest from the seeds: for the seed permutation;
    /// also the spatiotemporal sampler, with or without its Kronecker
    /// sequence).
    /// See [`TraceParams::sampler`].
    pub sampler: u32,
    /// Radiance of a constant environment (sky), linear RGB, each channel
    /// finite and `>= 0`; zero (the default): none. See
    /// [`TraceParams::environment`].
    pub environment: glam::Vec3,
    /// Path regularisation strength, in `[0, 1]` (NaN refused): glossy
    /// surfaces met after rough ones are made at least this times as rough
    /// (`kernels::regularization`; biased). 0 (the default): off, unbiased.
    /// See [`TraceParams::glossy_regularization`].
    pub glossy_regularization: f32,
    /// Where the a-priori samplers' per-pixel data sits on the screen, in
    /// pixels (x, y; any values, read wrapping): pixel `p` reads the keys,
    /// shifts or ZSobol point of `p + origin`. One draw of the samplers'
    /// placement, for decorrelating two renders that should not share a
    /// pattern (two eyes, two studies of one method); every origin has the
    /// same quality in expectation. `[0, 0]` (the default): the samplers as
    /// baked. See [`TraceParams::sampler_origin_x`] and
    /// [`sampler_origin_of_salt`].
    pub sampler_origin: [u32; 2],
}

/// The samplers' origin ([`TraceSettings::sampler_origin`]) of draw `salt`:
/// point `salt - 1` (wrapping) of the R2 sequence started at 0, in 1/4096
/// (the top 12 bits of `sampler_core::sequences::r2::r2_q32(salt - 1, 0)`),
/// so salt 1 is the samplers as baked (`[0, 0]`) and consecutive salts sit
/// far apart on the 64-pixel tiles and on ZSobol's 4096-pixel period. The
/// studies' `--salt` picks it together with the white seeds.
pub fn sampler_origin_of_salt(salt: u32) -> [u32; 2] {
    let [x, y] = sampler_core::sequences::r2::r2_q32(salt.wrapping_sub(1), 0);
    [x >> 20, y >> 20]
}

/// Largest spp per frame of [`SAMPLER_ZSOBOL`]: `2^ZSOBOL_MAX_LOG2_SPP` = 256.
pub const ZSOBOL_MAX_SPP: u32 = 1 << sampler_core::sequences::zsobol::ZSOBOL_MAX_LOG2_SPP;

/// Largest spp per frame of [`SAMPLER_SCREEN_SOBOL`] with the default keys
/// (`sampler_core::defaults::screen_sobol_keys()`): the spp its last key
/// level is optimised for, `2^(levels - 1)` (16).
pub fn screen_sobol_max_spp() -> u32 {
    1 << (sampler_core::defaults::screen_sobol_keys().layout().levels - 1)
}

/// [`Error::InvalidSetting`] unless `strength` is a path regularisation
/// strength in `[0, 1]` (NaN refused): the one check of
/// [`TraceSettings::glossy_regularization`] and of the CPU renderer's
/// parameters.
pub(crate) fn check_glossy_regularization(strength: f32) -> Result<()> {
    if (0.0..=1.0).contains(&strength) {
        Ok(())
    } else {
        Err(Error::InvalidSetting {
            name: "glossy_regularization",
            value: strength,
            expected: "a strength in [0, 1] (0: off)",
        })
    }
}

impl TraceSettings {
    /// Settings for a `width x height` frame with an unpadded seed buffer,
    /// 1 spp, max depth 8, Russian roulette from vertex 3 and
    /// [`kernels::abi::SEED_MODE_FIXED`].
    pub fn new(width: u32, height: u32) -> Self {
        TraceSettings {
            width,
            height,
            padded_width: width,
            spp: 1,
            max_depth: 8,
            rr_depth: 3,
            seed_mode: kernels::abi::SEED_MODE_FIXED,
            sampler: kernels::abi::SAMPLER_SEEDS,
            environment: glam::Vec3::ZERO,
            glossy_regularization: 0.0,
            sampler_origin: [0, 0],
        }
    }
}

impl SceneGpu {
    /// The [`TraceParams`] of frame `frame` with these settings.
    ///
    /// # Errors
    /// [`Error::FrameSize`] for a zero size or `padded_width < width`;
    /// [`Error::InvalidParameter`] for `spp == 0`, `max_depth` outside
    /// `1..=MAX_DEPTH_LIMIT`, an unknown `seed_mode` or `sampler`, or a
    /// sampler that does not support the settings (spp above
    /// [`screen_sobol_max_spp`] for screen-space Sobol; spp above
    /// [`ZSOBOL_MAX_SPP`] or a side above 4096 for ZSobol).
    ///
    /// The key-layout fields are those of
    /// `sampler_core::defaults::screen_sobol_keys()`, the keys the CPU
    /// renderer and the GPU tracer use.
    pub fn trace_params(&self, settings: &TraceSettings, frame: u32) -> Result<TraceParams> {
        let s = settings;
        if s.width == 0 || s.height == 0 || s.padded_width < s.width {
            return Err(Error::FrameSize {
                width: s.width,
                height: s.height,
                padded_width: s.padded_width,
            });
        }
        if s.spp == 0 {
            return Err(Error::InvalidParameter {
                name: "spp",
                value: s.spp,
                expected: ">= 1",
            });
        }
        if s.max_depth == 0 || s.max_depth > MAX_DEPTH_LIMIT {
            return Err(Error::InvalidParameter {
                name: "max_depth",
                value: s.max_depth,
                expected: "1..=64 (kernels::abi::MAX_DEPTH_LIMIT)",
            });
        }
        for value in s.environment.to_array() {
            // NaN is in no range: refused with the negatives and infinities.
            if !(0.0..=f32::MAX).contains(&value) {
                return Err(Error::InvalidSetting {
                    name: "environment",
                    value,
                    expected: "a finite radiance >= 0 in every channel",
                });
            }
        }
        check_glossy_regularization(s.glossy_regularization)?;
        if self.environment_map.width > 0 && s.environment != glam::Vec3::ZERO {
            return Err(Error::InvalidSetting {
                name: "environment",
                value: s.environment.max_element(),
                expected: "0 when the scene has an environment map (a constant sky and a map are exclusive)",
            });
        }
        if s.seed_mode > SEED_MODE_ADVANCE {
            return Err(Error::InvalidParameter {
                name: "seed_mode",
                value: s.seed_mode,
                expected: "0 (fixed) or 1 (advance by frame)",
            });
        }
        let zsobol_tile = sampler_core::sequences::zsobol::ZSOBOL_TILE;
        let (kind, flags) = (s.sampler & SAMPLER_KIND_MASK, s.sampler & !SAMPLER_KIND_MASK);
        let sampler_checks: [(&'static str, u32, bool, &'static str); 4] = [
            (
                "sampler",
                s.sampler,
                sampler_flags_valid(kind, flags),
                "0 (seeds), 1 (screen-sobol), 2 (zsobol) or 3 (spatiotemporal), the last three optionally ORed \
                 with 256 (jitter only), zsobol and spatiotemporal also with 512 (homes), spatiotemporal also \
                 with 1024 (Kronecker sequence), alone or with 512 or 256",
            ),
            (
                "spp",
                s.spp,
                kind != SAMPLER_SCREEN_SOBOL || s.spp <= screen_sobol_max_spp(),
                "at most 16 with the screen-sobol sampler (its keys are optimised for 1, 2, 4, 8 and 16 spp)",
            ),
            (
                "spp",
                s.spp,
                kind != SAMPLER_ZSOBOL || s.spp <= ZSOBOL_MAX_SPP,
                "at most 256 with the zsobol sampler (its sample index is 32 bits)",
            ),
            (
                "width or height",
                s.width.max(s.height),
                kind != SAMPLER_ZSOBOL || s.width.max(s.height) <= zsobol_tile,
                "at most 4096 with the zsobol sampler (its pixel order repeats every 4096 pixels)",
            ),
        ];
        for (name, value, ok, expected) in sampler_checks {
            if !ok {
                return Err(Error::InvalidParameter {
                    name,
                    value,
                    expected,
                });
            }
        }
        let key_layout = sampler_core::defaults::screen_sobol_keys().layout();
        let c = &self.camera;
        Ok(TraceParams {
            width: s.width,
            height: s.height,
            padded_width: s.padded_width,
            spp: s.spp,
            max_depth: s.max_depth,
            frame,
            triangle_count: self.triangles.len() as u32,
            emitter_count: self.emitter_count,
            seed_mode: s.seed_mode,
            node_count: self.nodes.len() as u32,
            rr_depth: s.rr_depth,
            tan_half_fov_y: c.tan_half_fov_y,
            camera_origin: c.origin.extend(0.0),
            camera_forward: c.forward.extend(0.0),
            camera_right: c.right.extend(0.0),
            camera_up: c.up.extend(0.0),
            sampler: s.sampler,
            key_side_log2: key_layout.side_log2,
            key_pairs: key_layout.pairs,
            key_levels: key_layout.levels,
            prev_camera_origin: self.prev_camera.origin.extend(0.0),
            prev_camera_forward: self.prev_camera.forward.extend(0.0),
            prev_camera_right: self.prev_camera.right.extend(0.0),
            prev_camera_up: self.prev_camera.up.extend(0.0),
            prev_tan_half_fov_y: self.prev_camera.tan_half_fov_y,
            image_count: self.image_count,
            point_samples: 0,
            seed_hold_below: 0.0,
            environment: s.environment.extend(self.environment_select_pdf()),
            environment_map: self.environment_map,
            glossy_regularization: s.glossy_regularization,
            seed_follow_share: 0.0,
            sampler_offset_x: 0,
            sampler_offset_y: 0,
            sampler_origin_x: s.sampler_origin[0],
            sampler_origin_y: s.sampler_origin[1],
            pad0: 0,
            pad1: 0,
        })
    }
}

/// Whether sampler `kind` ([`SAMPLER_KIND_MASK`] bits of
/// [`TraceSettings::sampler`]) takes `flags` (the other bits): the seed
/// stream none; screen-space Sobol the jitter-only flag; ZSobol the
/// jitter-only flag or homes, not both; the spatiotemporal sampler its
/// Kronecker sequence with either the jitter-only flag or homes, not both.
fn sampler_flags_valid(kind: u32, flags: u32) -> bool {
    use kernels::abi::{SAMPLER_FOLLOW_HOMES, SAMPLER_KRONECKER, SAMPLER_SEEDS, SAMPLER_SPATIOTEMPORAL};
    let jitter_or_homes = |f: u32| f == 0 || f == SAMPLER_JITTER_ONLY || f == SAMPLER_FOLLOW_HOMES;
    match kind {
        SAMPLER_SEEDS => flags == 0,
        SAMPLER_SCREEN_SOBOL => flags & !SAMPLER_JITTER_ONLY == 0,
        SAMPLER_ZSOBOL => jitter_or_homes(flags),
        SAMPLER_SPATIOTEMPORAL => jitter_or_homes(flags & !SAMPLER_KRONECKER),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::buffers::tests::quad_scene;
    use glam::Vec3;

    /// Salt 1 is the samplers as baked; the first 16 salts give 16
    /// different origins on the 64-pixel tiles, and the settings carry the
    /// origin into the parameters.
    #[test]
    fn salts_draw_the_samplers_origin() {
        assert_eq!(sampler_origin_of_salt(1), [0, 0]);
        assert_eq!(sampler_origin_of_salt(2), [0xC13F_A9A9 >> 20, 0x91E1_0DA6 >> 20]);
        let mut on_tile: Vec<[u32; 2]> = (1..=16)
            .map(|salt| sampler_origin_of_salt(salt).map(|c| c % 64))
            .collect();
        on_tile.sort();
        on_tile.dedup();
        assert_eq!(on_tile.len(), 16);
        for salt in [0, 7, u32::MAX] {
            assert!(sampler_origin_of_salt(salt).iter().all(|&c| c < 4096));
        }
        let gpu = SceneGpu::build(&quad_scene(Vec3::ONE)).expect("valid");
        let s = TraceSettings {
            sampler_origin: sampler_origin_of_salt(3),
            ..TraceSettings::new(16, 8)
        };
        let p = gpu.trace_params(&s, 0).expect("valid");
        assert_eq!(
            [p.sampler_origin_x, p.sampler_origin_y],
            sampler_origin_of_salt(3)
        );
    }

    #[test]
    fn trace_params_validation() {
        let gpu = SceneGpu::build(&quad_scene(Vec3::ONE)).expect("valid");
        let ok = TraceSettings::new(16, 8);
        let p = gpu.trace_params(&ok, 5).expect("valid");
        assert_eq!(
            (p.width, p.height, p.padded_width, p.frame, p.emitter_count),
            (16, 8, 16, 5, 2)
        );
        assert_eq!(p.node_count as usize, gpu.nodes.len());
        let bad = [
            TraceSettings { width: 0, ..ok },
            TraceSettings {
                padded_width: 15,
                ..ok
            },
            TraceSettings { spp: 0, ..ok },
            TraceSettings { max_depth: 0, ..ok },
            TraceSettings { max_depth: 65, ..ok },
            TraceSettings { seed_mode: 2, ..ok },
            TraceSettings { sampler: 4, ..ok },
            TraceSettings {
                environment: Vec3::new(1.0, f32::NAN, 0.0),
                ..ok
            },
            TraceSettings {
                environment: Vec3::new(-0.5, 1.0, 1.0),
                ..ok
            },
            TraceSettings {
                environment: Vec3::new(f32::INFINITY, 1.0, 1.0),
                ..ok
            },
            TraceSettings {
                glossy_regularization: f32::NAN,
                ..ok
            },
            TraceSettings {
                glossy_regularization: -0.1,
                ..ok
            },
            TraceSettings {
                glossy_regularization: 1.5,
                ..ok
            },
            TraceSettings {
                sampler: SAMPLER_JITTER_ONLY,
                ..ok
            },
            // Homes: ZSobol on every decision and the spatiotemporal sampler only.
            TraceSettings {
                sampler: SAMPLER_ZSOBOL | SAMPLER_JITTER_ONLY | 1 << 9,
                ..ok
            },
            TraceSettings {
                sampler: SAMPLER_SCREEN_SOBOL | 1 << 9,
                ..ok
            },
            // The Kronecker jitter reads the seeds for the rest: no homes with it.
            TraceSettings {
                sampler: kernels::abi::SAMPLER_SPATIOTEMPORAL
                    | kernels::abi::SAMPLER_KRONECKER
                    | SAMPLER_JITTER_ONLY
                    | 1 << 9,
                ..ok
            },
            TraceSettings {
                sampler: SAMPLER_SCREEN_SOBOL,
                spp: 17,
                ..ok
            },
            TraceSettings {
                sampler: SAMPLER_SCREEN_SOBOL | SAMPLER_JITTER_ONLY,
                spp: 17,
                ..ok
            },
            TraceSettings {
                sampler: SAMPLER_ZSOBOL,
                spp: 257,
                ..ok
            },
            TraceSettings {
                sampler: SAMPLER_ZSOBOL | SAMPLER_JITTER_ONLY,
                width: 4097,
                padded_width: 4097,
                ..ok
            },
            TraceSettings {
                sampler: SAMPLER_ZSOBOL,
                width: 4097,
                padded_width: 4097,
                ..ok
            },
        ];
        for s in bad {
            assert!(gpu.trace_params(&s, 0).is_err(), "{s:?}");
        }
        for strength in [0.0, 0.5, 1.0] {
            let s = TraceSettings {
                glossy_regularization: strength,
                ..ok
            };
            assert_eq!(
                gpu.trace_params(&s, 0).expect("valid").glossy_regularization,
                strength
            );
        }
        for (sampler, spp) in [
            (SAMPLER_SCREEN_SOBOL, 16),
            (SAMPLER_ZSOBOL, 256),
            (SAMPLER_SCREEN_SOBOL | SAMPLER_JITTER_ONLY, 16),
            (SAMPLER_ZSOBOL | SAMPLER_JITTER_ONLY, 256),
            (SAMPLER_ZSOBOL | 1 << 9, 256),
            (kernels::abi::SAMPLER_SPATIOTEMPORAL, 4096),
        ] {
            let p = gpu
                .trace_params(&TraceSettings { sampler, spp, ..ok }, 0)
                .expect("supported");
            let layout = sampler_core::defaults::screen_sobol_keys().layout();
            assert_eq!(
                (p.sampler, p.key_side_log2, p.key_pairs, p.key_levels),
                (sampler, layout.side_log2, layout.pairs, layout.levels)
            );
        }
    }
}
