//! Where a path sample's numbers come from: the pixel's seed stream (the
//! layout the seed permutation relies on) or an a-priori screen-space
//! sampler, behind one [`PathNumbers`] the integrator ([`crate::trace`])
//! reads.
//!
//! # Seed-stream layout
//!
//! Sample `s` of a pixel reads the seed's stream at indices
//! `[s * DIMS_PER_SAMPLE, (s + 1) * DIMS_PER_SAMPLE)`
//! (`sampler_core::RandomStream::new(seed, s, DIMS_PER_SAMPLE)`):
//!
//! | dimension | use |
//! |---|---|
//! | 0, 1 | position inside the pixel |
//! | `2 + 6 d + 0` | vertex `d`: reserved (unused) |
//! | `2 + 6 d + 1, 2` | vertex `d`: which emitter and the point on it |
//! | `2 + 6 d + 3, 4` | vertex `d`: BSDF lobe (first number, reused) and direction |
//! | `2 + 6 d + 5` | vertex `d`: Russian roulette |
//!
//! Every vertex draws its six numbers whether or not it uses them, so a
//! dimension always drives the same decision: that is what lets the seed
//! permutation correlate pixels' estimates. The light pair picks the emitter
//! with its first number and reuses that number, rescaled to `[0, 1)` within
//! the emitter's probability interval, for the point
//! ([`crate::trace::select_emitter_reusing`]): one 2D pair covers all the emitters, so a
//! stratified or blue-noise pair stays so over the whole light. The BSDF
//! pair does the same for a metallic-roughness material's lobe choice
//! ([`crate::shading::reuse_lobe_number`]); a Lambertian vertex reads it as
//! the direction only. The stream
//! sample `s` is the sample index within the frame in
//! [`SEED_MODE_FIXED`](crate::abi::SEED_MODE_FIXED) and `frame * spp + s` in
//! [`SEED_MODE_ADVANCE`] (see [`stream_sample`]).
//!
//!
//! [`TraceParams::sampler`] chooses where a path sample's 2D decisions come
//! from in [`crate::trace::trace_pixel`]:
//! - [`SAMPLER_SEEDS`](crate::abi::SAMPLER_SEEDS): the seed stream (table
//!   above);
//! - [`SAMPLER_SCREEN_SOBOL`] or [`SAMPLER_ZSOBOL`]: the a-priori sampler's
//!   dimension pairs ([`apriori_pair`]), in path order:
//!
//! | sampler pair | use |
//! |---|---|
//! | 0 ([`PAIR_JITTER`]) | position inside the pixel |
//! | `1 + 2 d` ([`pair_light`]) | vertex `d`: emitter and point on it |
//! | `2 + 2 d` ([`pair_bsdf`]) | vertex `d`: BSDF direction |
//! | `1 + 2 MAX_DEPTH_LIMIT + d` ([`pair_roulette`]) | vertex `d`: Russian roulette ([`SAMPLER_SPATIOTEMPORAL`] only) |
//!
//! The first pairs are the ones the screen-space Sobol keys are optimised
//! for (jitter, vertex 0's light, vertex 0's BSDF, vertex 1's light with the
//! default 4 pairs); later pairs are valid, unoptimised Owen-scrambled
//! sequences. Russian roulette still reads the seed stream (except with
//! [`SAMPLER_SPATIOTEMPORAL`], whose every decision is its own), so `seed_mode`
//! and the seed permutation keep applying to it. The a-priori pairs are the
//! same for every seed: they depend only on the pixel, the frame and the
//! sample.
//!
//! With [`SAMPLER_JITTER_ONLY`] set, only pair 0 (the position inside the
//! pixel) comes from the sampler and everything else from the seed stream:
//! the seed permutation with a stratified jitter. At a **sharp first hit**
//! (a glossy surface seen from the camera,
//! [`crate::shading::Shading::is_sharp`]) vertex 0's light and BSDF pairs
//! come from the sampler too ([`PathNumbers::set_sharp_first_hit`]): there a
//! seed's value does not predict its next one (the reflection moves with the
//! sample), so the permutation gains nothing from the seed while the
//! sampler's pairs, one net over frames per pixel with ZSobol, are blue in
//! time (`QUALITY.md`, "Sharp first hits"). Lambertian and rough surfaces
//! keep the seed's pairs, so scenes without sharp glossy surfaces render as
//! before, bit for bit.

use crate::abi::{
    sampler_reads_homes, TraceParams, MAX_DEPTH_LIMIT, SAMPLER_FOLLOW_HOMES, SAMPLER_JITTER_ONLY,
    SAMPLER_KIND_MASK, SAMPLER_KRONECKER, SAMPLER_SCREEN_SOBOL, SAMPLER_SPATIOTEMPORAL, SAMPLER_ZSOBOL,
    SEED_MODE_ADVANCE, SPATIOTEMPORAL_TILE_LOG2,
};
use crate::pan_offset::offset_pixels;
use crate::sampler_entry::{screen_sobol_pair, zsobol_pair};
use glam::{UVec2, Vec2};
use sampler_core::sequences::kronecker::{kronecker_point_at, KRONECKER_PAIRS};
use sampler_core::sequences::r2::q32_to_f32;
use sampler_core::sequences::screen_sobol::ScreenSobolLayout;
use sampler_core::sequences::spatiotemporal::{
    home_texel, shift_pair_tiles_len, spatiotemporal_index, spatiotemporal_point_u32,
    spatiotemporal_shift_packed, SEQUENCE_KRONECKER, SEQUENCE_SOBOL, SPATIOTEMPORAL_SEED,
};
use sampler_core::RandomStream;

/// Stream dimensions used before the first vertex (pixel jitter).
pub const DIMS_CAMERA: u32 = 2;
/// Stream dimensions used at every path vertex (see the module docs).
pub const DIMS_PER_VERTEX: u32 = 6;
/// Stream dimensions reserved per sample: `DIMS_CAMERA + DIMS_PER_VERTEX *
/// MAX_DEPTH_LIMIT` = 386, whatever `max_depth` is, so a dimension's meaning
/// does not depend on the depth setting.
pub const DIMS_PER_SAMPLE: u32 = DIMS_CAMERA + DIMS_PER_VERTEX * MAX_DEPTH_LIMIT;

/// Stream sample used by sample `s` of frame `params.frame`: `s` in
/// [`crate::abi::SEED_MODE_FIXED`] (and for unknown modes),
/// `frame * spp + s` (wrapping) in [`SEED_MODE_ADVANCE`].
#[inline]
pub fn stream_sample(params: &TraceParams, s: u32) -> u32 {
    if params.seed_mode == SEED_MODE_ADVANCE {
        params.frame.wrapping_mul(params.spp).wrapping_add(s)
    } else {
        s
    }
}

/// [`PathNumbers`] scope: every 2D decision from the seed stream.
pub const APRIORI_NONE: u32 = 0;
/// [`PathNumbers`] scope: every 2D decision from the a-priori sampler.
pub const APRIORI_ALL: u32 = 1;
/// [`PathNumbers`] scope: the jitter pair from the a-priori sampler, the
/// rest from the seed stream ([`SAMPLER_JITTER_ONLY`]).
pub const APRIORI_JITTER: u32 = 2;

/// The sampler named by `params.sampler` without its flags:
/// [`SAMPLER_SCREEN_SOBOL`], [`SAMPLER_ZSOBOL`], or anything else for the
/// seed stream.
#[inline]
pub fn sampler_kind(params: &TraceParams) -> u32 {
    params.sampler & SAMPLER_KIND_MASK
}

/// Which of the path's 2D decisions the a-priori sampler drives:
/// [`APRIORI_NONE`], [`APRIORI_ALL`] or [`APRIORI_JITTER`].
#[inline]
pub fn apriori_scope(params: &TraceParams) -> u32 {
    let kind = sampler_kind(params);
    if kind != SAMPLER_SCREEN_SOBOL && kind != SAMPLER_ZSOBOL && kind != SAMPLER_SPATIOTEMPORAL {
        APRIORI_NONE
    } else if params.sampler & SAMPLER_JITTER_ONLY != 0 {
        APRIORI_JITTER
    } else {
        APRIORI_ALL
    }
}

/// A-priori sampler pair of the position inside the pixel.
pub const PAIR_JITTER: u32 = 0;

/// A-priori sampler pair of vertex `depth`'s next-event estimation (emitter
/// and point on it): `1 + 2 depth`.
#[inline]
pub fn pair_light(depth: u32) -> u32 {
    1 + 2 * depth
}

/// A-priori sampler pair of vertex `depth`'s BSDF direction: `2 + 2 depth`.
#[inline]
pub fn pair_bsdf(depth: u32) -> u32 {
    2 + 2 * depth
}

/// A-priori sampler pair of vertex `depth`'s Russian roulette (its first
/// coordinate; [`SAMPLER_SPATIOTEMPORAL`] only): `1 + 2 MAX_DEPTH_LIMIT + depth`,
/// after every light and BSDF pair of the longest path.
#[inline]
pub fn pair_roulette(depth: u32) -> u32 {
    1 + 2 * MAX_DEPTH_LIMIT + depth
}

/// Slots per sample of [`SAMPLER_SPATIOTEMPORAL`]'s frame point table at
/// `max_depth` (clamped to [`MAX_DEPTH_LIMIT`]): `1 + 3 max_depth`, one per
/// pair a path of that depth can draw (jitter, light and BSDF per vertex,
/// Russian roulette per vertex).
#[inline]
pub fn point_slots(max_depth: u32) -> u32 {
    1 + 3 * max_depth.min(MAX_DEPTH_LIMIT)
}

/// Slot of sampler pair `pair` in the frame point table at `max_depth`
/// (clamped to [`MAX_DEPTH_LIMIT`]): pairs `0..=2 max_depth` (jitter, then
/// light and BSDF per vertex) keep their number, the roulette pairs
/// [`pair_roulette`]`(d)`, `d < max_depth`, follow them at `1 + 2 max_depth +
/// d`; any other pair has no slot (`u32::MAX`). Inverse of
/// [`point_slot_pair`].
#[inline]
pub fn point_slot(pair: u32, max_depth: u32) -> u32 {
    let max_depth = max_depth.min(MAX_DEPTH_LIMIT);
    if pair <= 2 * max_depth {
        pair
    } else if pair >= pair_roulette(0) && pair < pair_roulette(max_depth) {
        1 + 2 * max_depth + (pair - pair_roulette(0))
    } else {
        u32::MAX
    }
}

/// The sampler pair stored in `slot` of the frame point table at
/// `max_depth` (`slot < point_slots(max_depth)`): inverse of [`point_slot`].
#[inline]
pub fn point_slot_pair(slot: u32, max_depth: u32) -> u32 {
    let max_depth = max_depth.min(MAX_DEPTH_LIMIT);
    if slot <= 2 * max_depth {
        slot
    } else {
        pair_roulette(slot - 1 - 2 * max_depth)
    }
}

/// Index in binding 7 of the Kronecker generators
/// (`sampler_core::sequences::kronecker::KRONECKER_GENERATORS`, read with
/// [`SAMPLER_KRONECKER`]): after the screen-space Sobol keys (`key_count`
/// words) and the `STEP_COUNT` shift-pair tiles and the jitter pair's net
/// shifts of the `2^SPATIOTEMPORAL_TILE_LOG2`-sided shift tile
/// (`sampler_core::sequences::spatiotemporal::write_shift_pair_tiles`,
/// [`shift_pair_tiles_len`] words).
#[inline]
pub fn generators_start(key_count: usize) -> usize {
    key_count + shift_pair_tiles_len(SPATIOTEMPORAL_TILE_LOG2)
}

/// Index in binding 7 of the frame point table: after the generators
/// ([`generators_start`], `2 * KRONECKER_PAIRS` words).
#[inline]
pub fn point_table_start(key_count: usize) -> usize {
    generators_start(key_count) + 2 * KRONECKER_PAIRS as usize
}

/// The sequence [`SAMPLER_SPATIOTEMPORAL`] continues under `params`:
/// `SEQUENCE_KRONECKER` with [`SAMPLER_KRONECKER`], else `SEQUENCE_SOBOL`
/// (`sampler_core::sequences::spatiotemporal`).
#[inline]
pub fn spatiotemporal_sequence(params: &TraceParams) -> u32 {
    if params.sampler & SAMPLER_KRONECKER != 0 {
        SEQUENCE_KRONECKER
    } else {
        SEQUENCE_SOBOL
    }
}

/// [`SAMPLER_SPATIOTEMPORAL`]'s unshifted point of `pair` for sample `s`:
/// read from the frame point table when `s < params.point_samples` and the
/// pair has a slot inside `keys`, else computed
/// (`sampler_core::sequences::spatiotemporal::spatiotemporal_point_u32`;
/// the table holds the same words).
#[inline]
fn spatiotemporal_point(params: &TraceParams, keys: &[u32], key_count: usize, s: u32, pair: u32) -> [u32; 2] {
    let slot = point_slot(pair, params.max_depth);
    if s < params.point_samples && slot != u32::MAX {
        let slots = point_slots(params.max_depth) as usize;
        let i = point_table_start(key_count) + 2 * (s as usize * slots + slot as usize);
        if i + 1 < keys.len() {
            return [keys[i], keys[i + 1]];
        }
    }
    let index = spatiotemporal_index(params.frame, params.spp.max(1), s);
    if spatiotemporal_sequence(params) == SEQUENCE_KRONECKER {
        kronecker_point_at(keys, generators_start(key_count), index, pair)
    } else {
        spatiotemporal_point_u32(index, pair, SPATIOTEMPORAL_SEED)
    }
}

/// Pair `pair` (dimensions `2 pair`, `2 pair + 1`) of sample `s` of `pixel`
/// in frame `params.frame` from the a-priori sampler `params.sampler`
/// (flags ignored, see [`sampler_kind`]), each
/// coordinate in `[0, 1)` (24 bits):
/// - [`SAMPLER_SCREEN_SOBOL`]: sample index `s` with the keys of `keys`
///   laid out as `params.key_side_log2 / key_pairs / key_levels`, level
///   `ceil(log2 spp)` (`sampler_core::sequences::screen_sobol::screen_sobol_pair_u32`),
///   read at `pixel + o_t` where `o_t = sampler_core::walk_offset(frame,
///   key_side_log2)` is the R2 walk that also moves the dither tile. The
///   keys are optimised for the first `2^level` indices only, so every frame
///   uses exactly those (a sequence continued across frames loses the
///   blue-noise error after frame 0); the toroidal shift gives each pixel
///   other keys every frame, so the accumulated mean converges as Monte
///   Carlo over per-frame stratified estimates.
/// - [`SAMPLER_ZSOBOL`]: sample `s` with `2^ceil(log2 spp)` samples per pixel
///   (at most 256) in frame `params.frame`. ZSobol's index is
///   `morton(pixel) * 2^log2_spp + s`: the blue-noise property needs
///   `log2_spp` to be exactly the frame's spp (a larger one would spread a
///   frame's samples over unrelated strata), so frames do not continue the
///   index; each frame is the same point set XORed with point `frame` of a
///   (0, 2)-sequence instead (`sampler_core::zsobol_frame_sample_u32`), which
///   keeps every frame's stratification and makes a pixel's frames one
///   progressive net: its mean converges faster than independent frames'.
/// - [`SAMPLER_SPATIOTEMPORAL`]: index `frame * spp + s` of the shared
///   progressive sequence (Owen-scrambled Sobol, or the Kronecker sequence
///   with [`SAMPLER_KRONECKER`], [`spatiotemporal_sequence`]), rotated by the
///   pixel's shift read, both coordinates in one load, from the shift-pair
///   tiles stored after the keys (the jitter pair's from the net tile after
///   them, ZSobol's one-sample points: jointly stratified over neighbours)
///   (`sampler_core::sequences::spatiotemporal::spatiotemporal_shift_packed`:
///   bit for bit the two reads of the rank tile; the
///   point from the frame table after the tiles when
///   [`TraceParams::point_samples`] covers `s`, see [`point_slot`]): one
///   sequence per pixel across frames, so its mean converges like the
///   sequence's and its error is anti-correlated from frame to frame.
/// - any other value: `Vec2::ZERO` (unused).
#[inline]
pub fn apriori_pair(params: &TraceParams, keys: &[u32], pixel: UVec2, s: u32, pair: u32) -> Vec2 {
    let spp = params.spp.max(1);
    let kind = sampler_kind(params);
    let layout = ScreenSobolLayout {
        side_log2: params.key_side_log2,
        pairs: params.key_pairs.max(1),
        levels: params.key_levels.max(1),
        pad: 0,
    };
    if kind == SAMPLER_SCREEN_SOBOL {
        screen_sobol_pair(keys, layout, spp, params.frame, pixel, s, pair)
    } else if kind == SAMPLER_ZSOBOL {
        zsobol_pair(spp, params.frame, pixel, s, pair)
    } else if kind == SAMPLER_SPATIOTEMPORAL {
        let shift =
            spatiotemporal_shift_packed(keys, layout.key_count(), SPATIOTEMPORAL_TILE_LOG2, pixel, pair);
        let p = spatiotemporal_point(params, keys, layout.key_count(), s, pair);
        Vec2::new(
            q32_to_f32(p[0].wrapping_add(shift[0])),
            q32_to_f32(p[1].wrapping_add(shift[1])),
        )
    } else {
        Vec2::ZERO
    }
}

/// Where one path sample's numbers come from (module docs): the seed
/// stream, the a-priori sampler of `params.sampler`, or the dither override
/// of vertex 0's BSDF pair. Plain data; the parameters and the key buffer
/// are passed to the methods, and must be the ones it was made with.
#[derive(Clone, Copy, Debug)]
pub struct PathNumbers {
    /// The seed's stream at the sample's first dimension.
    stream: RandomStream,
    /// The pixel being rendered.
    pub(crate) pixel: UVec2,
    /// Where the a-priori sampler reads its per-pixel data: [`Self::pixel`],
    /// or the home the seed holds with [`SAMPLER_FOLLOW_HOMES`]
    /// ([`SAMPLER_SPATIOTEMPORAL`] and [`SAMPLER_ZSOBOL`]; see
    /// [`sampler_position`]).
    sampler_pixel: UVec2,
    /// Sample index `s` within the frame.
    sample: u32,
    /// Which 2D decisions come from [`apriori_pair`]: [`APRIORI_NONE`],
    /// [`APRIORI_ALL`] or [`APRIORI_JITTER`] (the rest from the stream).
    apriori: u32,
    /// Vertex 0's BSDF pair when [`Self::first_bsdf_set`] is 1.
    first_bsdf: Vec2,
    /// 1: use [`Self::first_bsdf`]; 0: the sampler's or stream's pair.
    first_bsdf_set: u32,
    /// 1: the path's first hit is sharp, and with [`APRIORI_JITTER`] vertex
    /// 0's light and BSDF pairs come from the a-priori sampler too (module
    /// docs); 0: not (the start).
    sharp_first_hit: u32,
}

impl PathNumbers {
    /// Sample `s` of `pixel` with seed `seed` under `params` (its
    /// `seed_mode` and `sampler`).
    #[inline]
    pub fn new(params: &TraceParams, pixel: UVec2, seed: u32, s: u32) -> Self {
        let stream = RandomStream::new(seed, stream_sample(params, s), DIMS_PER_SAMPLE);
        PathNumbers {
            sample: s,
            apriori: apriori_scope(params),
            sampler_pixel: sampler_position(params, pixel, seed),
            ..Self::from_stream(stream, pixel)
        }
    }

    /// Every number from `stream` (positioned at the sample's first
    /// dimension).
    #[inline]
    pub fn from_stream(stream: RandomStream, pixel: UVec2) -> Self {
        PathNumbers {
            stream,
            pixel,
            sampler_pixel: pixel,
            sample: 0,
            apriori: APRIORI_NONE,
            first_bsdf: Vec2::ZERO,
            first_bsdf_set: 0,
            sharp_first_hit: 0,
        }
    }

    /// Records whether the path's first hit is sharp (module docs): call it
    /// at every vertex with `sharp` = 1 for a sharp surface at vertex 0, 0
    /// otherwise, before reading that vertex's pairs (a plain store, so that
    /// no `PathNumbers` value is chosen between branches in a shader).
    #[inline]
    pub fn set_sharp_first_hit(&mut self, depth: u32, sharp: u32) {
        if depth == 0 {
            self.sharp_first_hit = sharp;
        }
    }

    /// The same numbers with vertex 0's BSDF pair replaced by `u` (each
    /// coordinate in `[0, 1)`).
    #[inline]
    pub fn with_first_bsdf(self, u: Vec2) -> Self {
        PathNumbers {
            first_bsdf: u,
            first_bsdf_set: 1,
            ..self
        }
    }

    /// Stream dimensions `dim`, `dim + 1` after the sample's first.
    #[inline]
    fn stream_pair(&self, dim: u32) -> Vec2 {
        let mut d = RandomStream {
            seed: self.stream.seed,
            index: self.stream.index.wrapping_add(dim),
        };
        d.next_vec2()
    }

    /// Sampler pair `pair` if the a-priori sampler drives it, else stream
    /// dimensions `dim`, `dim + 1`.
    #[inline]
    fn pair(&self, params: &TraceParams, keys: &[u32], pair: u32, dim: u32) -> Vec2 {
        let first_vertex = pair == pair_light(0) || pair == pair_bsdf(0);
        let jitter_scope = pair == PAIR_JITTER || (self.sharp_first_hit == 1 && first_vertex);
        if self.apriori == APRIORI_ALL || (self.apriori == APRIORI_JITTER && jitter_scope) {
            apriori_pair(params, keys, self.sampler_pixel, self.sample, pair)
        } else {
            self.stream_pair(dim)
        }
    }

    /// Position inside the pixel, each coordinate in `[0, 1)`.
    #[inline]
    pub fn jitter(&self, params: &TraceParams, keys: &[u32]) -> Vec2 {
        self.pair(params, keys, PAIR_JITTER, 0)
    }

    /// Vertex `depth`'s next-event pair (emitter and point).
    #[inline]
    pub fn light(&self, params: &TraceParams, keys: &[u32], depth: u32) -> Vec2 {
        self.pair(params, keys, pair_light(depth), vertex_dim(depth) + 1)
    }

    /// Vertex `depth`'s BSDF pair.
    #[inline]
    pub fn bsdf(&self, params: &TraceParams, keys: &[u32], depth: u32) -> Vec2 {
        if depth == 0 && self.first_bsdf_set == 1 {
            self.first_bsdf
        } else {
            self.pair(params, keys, pair_bsdf(depth), vertex_dim(depth) + 3)
        }
    }

    /// Vertex `depth`'s Russian-roulette number: coordinate 0 of sampler pair
    /// [`pair_roulette`] when [`SAMPLER_SPATIOTEMPORAL`] drives every decision
    /// (so that the decision to continue a path is stratified over frames
    /// too), else the seed stream (the other samplers keep their numbers).
    #[inline]
    pub fn roulette(&self, params: &TraceParams, keys: &[u32], depth: u32) -> f32 {
        if self.apriori == APRIORI_ALL && sampler_kind(params) == SAMPLER_SPATIOTEMPORAL {
            apriori_pair(
                params,
                keys,
                self.sampler_pixel,
                self.sample,
                pair_roulette(depth),
            )
            .x
        } else {
            self.stream_pair(vertex_dim(depth) + 5).x
        }
    }
}

/// The position the a-priori sampler reads its per-pixel data at for
/// `pixel` whose seed-buffer entry is `seed`: with [`SAMPLER_SPATIOTEMPORAL`]
/// or [`SAMPLER_ZSOBOL`] and [`SAMPLER_FOLLOW_HOMES`], the position the home
/// `seed` holds names (`sampler_core::sequences::spatiotemporal::home_texel`:
/// the spatiotemporal shift, or ZSobol's point of that pixel); with
/// [`SAMPLER_ZSOBOL`] otherwise `pixel` plus the pan offset rounded to
/// whole pixels ([`TraceParams::sampler_offset_x`], `crate::pan_offset`; 0
/// unless frames follow as a whole); otherwise `pixel`. Every case then
/// plus the samplers' origin ([`TraceParams::sampler_origin_x`], wrapping:
/// every table the position reads repeats every 4096 pixels or less, a
/// divisor of `2^32`, so the adds are exact).
#[inline]
pub fn sampler_position(params: &TraceParams, pixel: UVec2, seed: u32) -> UVec2 {
    let at = if sampler_reads_homes(params.sampler) && params.sampler & SAMPLER_FOLLOW_HOMES != 0 {
        home_texel(seed)
    } else if params.sampler & SAMPLER_KIND_MASK == SAMPLER_ZSOBOL {
        UVec2::new(
            pixel.x.wrapping_add(offset_pixels(params.sampler_offset_x)),
            pixel.y.wrapping_add(offset_pixels(params.sampler_offset_y)),
        )
    } else {
        pixel
    };
    UVec2::new(
        at.x.wrapping_add(params.sampler_origin_x),
        at.y.wrapping_add(params.sampler_origin_y),
    )
}

/// First stream dimension of vertex `depth`: `DIMS_CAMERA + DIMS_PER_VERTEX * depth`.
#[inline]
fn vertex_dim(depth: u32) -> u32 {
    DIMS_CAMERA.wrapping_add(DIMS_PER_VERTEX.wrapping_mul(depth))
}
