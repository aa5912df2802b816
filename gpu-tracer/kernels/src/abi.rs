//! Every `#[repr(C)]` structure shared between the host and the kernels, and
//! the names of the entry points.
//!
//! All structures are [`bytemuck::Pod`], contain only `f32`, `u32`, `Vec4`
//! and `UVec4` fields and have no padding, so their host layout equals the
//! Vulkan block layout (std140 for the uniform, std430 for storage buffers).
//! Sizes are checked at compile time.
//!
//! # Suffixes
//!
//! Types ending in `Gpu` are the buffer forms of a friendlier host type in
//! the `gpu-tracer` crate (`Triangle` / `TriangleGpu`, ...).
//!
//! # Bindings
//!
//! | entry point | binding | kind | contents |
//! |---|---|---|---|
//! | [`TRACE_ENTRY`], [`TRACE_UNTEXTURED_ENTRY`], [`TRACE_BASIC_ENTRY`] | 0 | uniform | [`TraceParams`] |
//! | | 1 | storage, read | `[BvhNodeGpu]`, root at index 0 |
//! | | 2 | storage, read | `[TriangleGpu]`, in BVH leaf order |
//! | | 3 | storage, read | `[MaterialGpu]` |
//! | | 4 | storage, read | `[EmitterGpu]` (at least one entry: pad with [`EmitterGpu::NONE`]) |
//! | | 5 | storage, read | seeds `[u32]`, `padded_width * padded_height` |
//! | | 6 | storage, write | frame colour `[Vec4]`, `width * height` |
//! | | 7 | storage, read | screen-space Sobol keys `[u32]` laid out as [`TraceParams::key_side_log2`], [`TraceParams::key_pairs`], [`TraceParams::key_levels`] say (`sampler_core::sequences::screen_sobol`; the host binds `sampler_core::defaults::screen_sobol_keys()`), then the `STEP_COUNT` shift-pair tiles of the [`SPATIOTEMPORAL_TILE_LOG2`]-sided shift tile of [`SAMPLER_SPATIOTEMPORAL`] and its jitter pair's net shifts (the host appends `sampler_core::sequences::spatiotemporal::write_shift_pair_tiles` of `sampler_core::defaults::tile_64()`'s ranks, `shift_pair_tiles_len` words: both coordinates of a pair's shift in one word), then the `2 * KRONECKER_PAIRS` generator words of [`SAMPLER_KRONECKER`] (`sampler_core::sequences::kronecker::KRONECKER_GENERATORS`), then the frame's point table of [`SAMPLER_SPATIOTEMPORAL`] ([`TraceParams::point_samples`]); read only with [`SAMPLER_SCREEN_SOBOL`] (with or without [`SAMPLER_JITTER_ONLY`]) and [`SAMPLER_SPATIOTEMPORAL`], at least one element |
//! | | 8 | storage, read | `[TriangleAttrGpu]` (112 bytes each: texture coordinates, ids, tangent, vertex normals), parallel to binding 2 |
//! | | 9 | storage, read | images `[u32]` (layout in [`IMAGE_HEADER_WORDS`]), at least one element |
//! | | 10 | storage, read | environment map `[f32]`: sampling table then texels ([`crate::environment::environment_texel`]), at least one element |
//! | [`GBUFFER_ENTRY`], [`GBUFFER_UNTEXTURED_ENTRY`] | 0 | uniform | [`TraceParams`] (current and previous camera) |
//! | | 1 | storage, read | `[BvhNodeGpu]` |
//! | | 2 | storage, read | `[TriangleGpu]` |
//! | | 3 | storage, read | `[MaterialGpu]` |
//! | | 4 | storage, read | `[TriangleAttrGpu]` |
//! | | 5 | storage, read | images `[u32]` |
//! | | 6 | storage, read | previous-frame positions `[TriangleGpu]`, parallel to binding 2 (`w` unused) |
//! | | 7 | storage, write | G-buffer `[GBufferGpu]`, `width * height` |
//! | [`MOTION_ENTRY`] | 0 | uniform | [`TraceParams`] |
//! | | 1 | storage, read | G-buffer `[GBufferGpu]` of this frame |
//! | | 2 | storage, read | previous frame's visibility `[UVec2]` (`crate::motion::visibility`), `width * height` |
//! | | 3 | storage, write | this frame's visibility `[UVec2]`, `width * height` |
//! | | 4 | storage, write | reprojection motion `[Vec2]` (pixels; `crate::motion::DISOCCLUDED` where disoccluded), `width * height` |
//! | | 5 | storage, read | frame motion `[u32]`, `crate::pan_offset::FRAME_MOTION_WORDS`: reads [`RIGID_COUNT_ENTRY`]'s rigid count |
//! | [`RIGID_COUNT_ENTRY`] | 0 | uniform | [`TraceParams`] |
//! | | 1 | storage, read | G-buffer `[GBufferGpu]` of this frame |
//! | | 2 | storage, read-write | frame motion `[u32]` (`crate::pan_offset` has the layout): rigid count and motion sums, atomic; the host clears them |
//! | [`PAN_OFFSET_ENTRY`] | 0 | uniform | [`TraceParams`] |
//! | | 1 | storage, read-write | frame motion `[u32]`: reads [`RIGID_COUNT_ENTRY`]'s words, advances the pan offset (`crate::pan_offset::advance_offset`) |
//! | [`FEATURES_ENTRY`] | 0 | uniform | [`TraceParams`] |
//! | | 1 | storage, read | G-buffer `[GBufferGpu]` of this frame |
//! | | 2 | storage, read | frame colour `[Vec4]` |
//! | | 3 | storage, write | `[sampler_core::SurfaceFeature]`, `width * height` |
//! | | 4 | storage, write | demodulated sort keys `[f32]`, `width * height` |
//! | [`ACCUMULATE_ENTRY`] | 0 | uniform | [`TraceParams`] |
//! | | 1 | storage, read | frame colour `[Vec4]`, `width * height` |
//! | | 2 | storage, read-write | accumulation `[Vec4]`, `width * height` |
//!
//! The three entry points run on 8 x 8 workgroups ([`TRACE_WORKGROUP`]) over the
//! visible frame: dispatch `ceil(width / 8) x ceil(height / 8) x 1`. The
//! trace pass binds 10 storage buffers: the host requests a
//! `max_storage_buffers_per_shader_stage` of at least that
//! ([`MAX_STORAGE_BUFFERS_PER_STAGE`]).
//! wgpu refuses empty buffers, so every storage buffer holds at least one
//! element; the counts in [`TraceParams`] say how many are meaningful.

use glam::{UVec4, Vec2, Vec4};

/// Name of the path-tracing entry point (rust-gpu qualifies it with its module path) (one invocation per visible pixel).
pub const TRACE_ENTRY: &str = "entry::trace_cs";
/// Name of the basic variant of [`TRACE_ENTRY`] (`crate::trace_variant`):
/// the same bindings, for scenes without textures, cut-outs, vertex
/// normals, glossy materials, punctual lights or environment maps.
pub const TRACE_BASIC_ENTRY: &str = "entry::trace_basic_cs";
/// Name of the untextured variant of [`TRACE_ENTRY`]
/// (`crate::trace_variant`): the same bindings, for scenes without
/// textures, normal maps or cut-outs.
pub const TRACE_UNTEXTURED_ENTRY: &str = "entry::trace_untextured_cs";
/// Name of the accumulation entry point (one invocation per visible pixel).
pub const ACCUMULATE_ENTRY: &str = "entry::accumulate_cs";
/// Name of the G-buffer entry point (one invocation per visible pixel):
/// primary visibility through the pixel centre, motion vectors.
pub const GBUFFER_ENTRY: &str = "entry::gbuffer_cs";
/// Name of the G-buffer entry point without texture lookups or cut-outs
/// (`crate::gbuffer::gbuffer_pixel_variant`): the same bindings as
/// [`GBUFFER_ENTRY`], for scenes the untextured or basic trace kernel
/// renders.
pub const GBUFFER_UNTEXTURED_ENTRY: &str = "entry::gbuffer_untextured_cs";
/// Name of the motion entry point (one invocation per visible pixel): the
/// seed reprojection's motion vectors from the G-buffer
/// (`crate::motion::reprojection_motion_pixel`).
pub const MOTION_ENTRY: &str = "entry::motion_cs";
/// Name of the rigid-count entry point (one invocation per visible pixel):
/// counts the pixels that move rigidly (`crate::motion::moves_rigidly`) for
/// the motion pass's frame-wide rule.
pub const RIGID_COUNT_ENTRY: &str = "entry::rigid_count_cs";
/// Name of the pan-offset entry point (one invocation for the frame): advances
/// the pan offset from the rigid-count pass's words
/// (`crate::pan_offset::advance_offset`).
pub const PAN_OFFSET_ENTRY: &str = "entry::pan_offset_cs";
/// Name of the feature entry point (one invocation per visible pixel): the
/// feature-aware permutation's inputs from the G-buffer and the colour
/// (`crate::surface_features`).
pub const FEATURES_ENTRY: &str = "entry::features_cs";
/// Storage buffers the widest entry point ([`TRACE_ENTRY`]) binds.
pub const MAX_STORAGE_BUFFERS_PER_STAGE: u32 = 10;

/// [`MaterialGpu::textures`]: no texture.
pub const TEXTURE_NONE: u32 = u32::MAX;
/// Sampler flags of [`MaterialGpu::textures`]: wrap mode along `u` in bits
/// 0-1, along `v` in bits 2-3 ([`WRAP_REPEAT`], [`WRAP_CLAMP`],
/// [`WRAP_MIRROR`]), filter in bit 4 ([`FILTER_BILINEAR`] or nearest),
/// [`TEXEL_LINEAR`] in bit 5, [`UV_TRANSFORM`] in bit 6.
pub const WRAP_REPEAT: u32 = 0;
/// Clamp to the edge texel.
pub const WRAP_CLAMP: u32 = 1;
/// Mirrored repeat.
pub const WRAP_MIRROR: u32 = 2;
/// Bit 4 of the sampler flags: bilinear filtering (clear: nearest texel).
pub const FILTER_BILINEAR: u32 = 1 << 4;
/// Images buffer layout: image `i`'s header is words `4 i .. 4 i + 4` =
/// `(first texel word, width, height, mip levels)` (levels `>= 1`, 0 reads
/// as 1; the levels after the first follow the image's texels, each half
/// the size of the one before: `crate::texture_filter`); texels follow all headers, one
/// `u32` each, row-major from the top row, `r | g << 8 | b << 16 | a << 24`
/// with sRGB-encoded colour and linear alpha (read by alpha cut-outs).
pub const IMAGE_HEADER_WORDS: u32 = 4;

/// [`GBufferGpu::ids`]`.x` of a pixel whose centre ray hits nothing.
pub const GBUFFER_NO_HIT: u32 = u32::MAX;
/// [`GBufferGpu::ids`]`.w` flag: the centre ray hit a triangle.
pub const GBUFFER_HIT: u32 = 1;
/// [`GBufferGpu::ids`]`.w` flag: the hit point was in front of the previous
/// frame's camera (its previous raster position and depth are meaningful).
pub const GBUFFER_PREV_IN_FRONT: u32 = 2;
/// [`GBufferGpu::ids`]`.w` flag: the hit surface emits towards the camera.
pub const GBUFFER_EMITTER: u32 = 4;
/// Workgroup size `(x, y)` of [`TRACE_ENTRY`] and [`ACCUMULATE_ENTRY`],
/// in pixels; must match the `#[spirv(compute(threads(8, 8)))]` attributes.
pub const TRACE_WORKGROUP: (u32, u32) = (8, 8);

/// Largest supported [`TraceParams::max_depth`]: the random-number layout
/// reserves dimensions for this many path vertices
/// (see [`crate::trace::DIMS_PER_SAMPLE`]). 64 bounces are far beyond what a
/// diffuse scene needs after Russian roulette.
pub const MAX_DEPTH_LIMIT: u32 = 64;

/// [`TraceParams::seed_mode`]: the pixel's seed alone defines its random
/// stream; sample `s` of every frame uses stream sample `s`. This is what the
/// public implementations of the permutation method do.
pub const SEED_MODE_FIXED: u32 = 0;
/// [`TraceParams::seed_mode`]: the stream is advanced by the frame index;
/// sample `s` of frame `t` uses stream sample `t * spp + s` (wrapping).
pub const SEED_MODE_ADVANCE: u32 = 1;
/// [`TraceParams::seed_mode`]: blue-noise-dither baseline. Streams as in
/// [`SEED_MODE_FIXED`], but `crate::dither::trace_pixel_dithered` replaces the
/// two numbers of the first vertex's BSDF direction by a caller-supplied
/// spatiotemporal blue-noise mask value (Cranley-Patterson rotated per
/// sample). Only the CPU path supplies the mask (the `conformance` crate's
/// quality study); [`TRACE_ENTRY`] has no mask binding and renders this mode
/// exactly like [`SEED_MODE_FIXED`].
pub const SEED_MODE_BLUE_NOISE_DITHER: u32 = 2;

/// [`TraceParams::sampler`]: every number of a path comes from the pixel's
/// seed stream (`crate::trace` module docs). The default.
pub const SAMPLER_SEEDS: u32 = 0;
/// [`TraceParams::sampler`]: the path's 2D decisions (pixel jitter, each
/// vertex's light sample and BSDF direction; `crate::trace` module docs)
/// come from the screen-space Sobol sampler with optimised keys
/// (`sampler_core::sequences::screen_sobol`, key binding 7), one dimension pair each;
/// sample `s` of frame `t` reads sample index `s` of the keys at
/// `pixel + o_t` (the R2 walk offset of frame `t`, `sampler_core::walk_offset`,
/// wrapping on the key tile), with the key tile of level `ceil(log2 spp)`
/// (optimised for that spp; the host allows `spp <= 2^(key_levels - 1)`).
/// Russian roulette still reads the seed stream.
pub const SAMPLER_SCREEN_SOBOL: u32 = 1;
/// [`TraceParams::sampler`]: the path's 2D decisions come from the
/// Morton-ordered ZSobol sampler (`sampler_core::sequences::zsobol`), one dimension pair
/// each, with `2^ceil(log2 spp)` samples per pixel; sample `s` of frame `t`
/// is sample `s` of one fixed randomisation XORed with point `t` of a
/// (0, 2)-sequence (`sampler_core::zsobol_frame_sample_u32`: every frame
/// stratified as ZSobol is, a pixel's frames one progressive net; see
/// `crate::numbers::apriori_pair`). The host allows `spp <= 256` and frames at
/// most 4096 pixels wide and high (ZSobol's tile). Russian roulette still
/// reads the seed stream.
pub const SAMPLER_ZSOBOL: u32 = 2;
/// [`TraceParams::sampler`]: the path's 2D decisions come from the
/// spatiotemporal sampler (`sampler_core::sequences::spatiotemporal`), one
/// dimension pair each: every pixel continues one progressive
/// Owen-scrambled Sobol sequence across frames (index `frame * spp + s`),
/// rotated by a per-pixel shift read from the dither tile that follows the
/// screen-space Sobol keys in binding 7 (at `ScreenSobolLayout::key_count()`
/// of the keys' layout, side `2^`[`SPATIOTEMPORAL_TILE_LOG2`]; the pixel
/// jitter's shift from the net tile after it,
/// `sampler_core::sequences::spatiotemporal::net_shift_u32`). Any spp.
/// Russian roulette reads the sampler too (`crate::numbers::pair_roulette`):
/// with this sampler no number of a path comes from the seed.
pub const SAMPLER_SPATIOTEMPORAL: u32 = 3;
/// `log2` of the side of [`SAMPLER_SPATIOTEMPORAL`]'s shift tile (64x64).
pub const SPATIOTEMPORAL_TILE_LOG2: u32 = 6;
/// Flag of [`TraceParams::sampler`], ORed with [`SAMPLER_SCREEN_SOBOL`] or
/// [`SAMPLER_ZSOBOL`]: only the position inside the pixel (sampler pair 0)
/// comes from the a-priori sampler; every other number comes from the seed
/// stream, so the seed permutation still drives the path. Meant for the
/// permutation: a seed's estimate survives its move to a neighbouring pixel
/// on smooth regions (the jitter moves the first hit by less than a pixel),
/// while along silhouettes, where the estimate depends on little but the
/// jitter and the permutation cannot help, the sampler stratifies the
/// jitter along rows and columns (QUALITY.md, "Permutation with a-priori
/// jitter").
pub const SAMPLER_JITTER_ONLY: u32 = 1 << 8;
/// Flag of [`TraceParams::sampler`], ORed with [`SAMPLER_SPATIOTEMPORAL`] or
/// [`SAMPLER_ZSOBOL`]: the seed buffer (binding 4) holds each pixel's
/// **home** (`sampler_core::sequences::spatiotemporal::home_of_pixel`), not a
/// seed, and the pixel reads its per-pixel sampler data (the spatiotemporal
/// shift, ZSobol's point) where the home says instead of at its own position.
/// The host starts the homes at the pixels and, when things move, moves them
/// like seeds with the seed reprojection, so the pixels that follow a surface
/// keep its sequence over frames. Numbers still read from the seed stream
/// (ZSobol's Russian roulette) then come from the home's stream, which the
/// host advances by frame (`seed_mode` 1). Ignored with the other samplers.
pub const SAMPLER_FOLLOW_HOMES: u32 = 1 << 9;
/// Flag of [`TraceParams::sampler`], ORed with [`SAMPLER_SPATIOTEMPORAL`]:
/// every pixel continues the Kronecker sequence `frac(n g_k)` of
/// `sampler_core::sequences::kronecker` (its generators read from binding 7
/// after the shift tile) instead of the Owen-scrambled Sobol sequence; the
/// shifts and everything else are unchanged. Ignored with the other samplers.
pub const SAMPLER_KRONECKER: u32 = 1 << 10;
/// The bits of [`TraceParams::sampler`] that name the sampler
/// ([`SAMPLER_SEEDS`], [`SAMPLER_SCREEN_SOBOL`], [`SAMPLER_ZSOBOL`] or
/// [`SAMPLER_SPATIOTEMPORAL`]); the
/// rest are flags ([`SAMPLER_JITTER_ONLY`], [`SAMPLER_FOLLOW_HOMES`],
/// [`SAMPLER_KRONECKER`]).
pub const SAMPLER_KIND_MASK: u32 = 0xFF;
/// Whether the sampler named by the kind bits of `sampler` (a
/// [`TraceParams::sampler`] value) reads its per-pixel data at a home with
/// [`SAMPLER_FOLLOW_HOMES`]: [`SAMPLER_SPATIOTEMPORAL`] (its shift) and
/// [`SAMPLER_ZSOBOL`] (its point). The one list of them, for the kernels and
/// the host's checks alike.
#[inline]
pub const fn sampler_reads_homes(sampler: u32) -> bool {
    let kind = sampler & SAMPLER_KIND_MASK;
    kind == SAMPLER_SPATIOTEMPORAL || kind == SAMPLER_ZSOBOL
}

/// Per-frame parameters of the trace, G-buffer and accumulate passes
/// (uniform buffer, 256 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct TraceParams {
    /// Visible width in pixels, `>= 1`.
    pub width: u32,
    /// Visible height in pixels, `>= 1`.
    pub height: u32,
    /// Seed-buffer row stride in seeds (`>= width`): pixel `(x, y)` reads
    /// `seeds[y * padded_width + x]`. Identical to
    /// `sampler_core::FrameParams::padded_width`.
    pub padded_width: u32,
    /// Samples per pixel per frame, `>= 1`; the frame colour is their mean.
    pub spp: u32,
    /// Maximum path length in segments (camera segment included), in
    /// `1..=MAX_DEPTH_LIMIT`; 1 shows only directly visible emitters. Larger
    /// values are clamped to [`MAX_DEPTH_LIMIT`].
    pub max_depth: u32,
    /// Index `t` of the frame being rendered, from 0. For the accumulate pass:
    /// the frame being added, so the mean afterwards covers `t + 1` frames.
    pub frame: u32,
    /// Number of meaningful entries of the triangle buffer.
    pub triangle_count: u32,
    /// Number of meaningful entries of the emitter buffer; 0 disables
    /// next-event estimation (emitters are then only found by BSDF sampling).
    pub emitter_count: u32,
    /// [`SEED_MODE_FIXED`], [`SEED_MODE_ADVANCE`] or
    /// [`SEED_MODE_BLUE_NOISE_DITHER`]; any other value behaves like
    /// [`SEED_MODE_FIXED`].
    pub seed_mode: u32,
    /// Number of entries of the node buffer (>= 1; node 0 is the root).
    pub node_count: u32,
    /// Path vertex index from which Russian roulette applies: vertex `d`
    /// (0 = first hit from the camera) is subject to it when `d >= rr_depth`.
    /// 3 by default; `MAX_DEPTH_LIMIT` or more disables it.
    pub rr_depth: u32,
    /// `tan(fov_y / 2)` of the pinhole camera, `> 0` (vertical field of view).
    pub tan_half_fov_y: f32,
    /// Camera position in world units; `w` = 0.
    pub camera_origin: Vec4,
    /// Unit viewing direction; `w` = 0.
    pub camera_forward: Vec4,
    /// Unit vector to the right of the image, orthogonal to `forward`; `w` = 0.
    pub camera_right: Vec4,
    /// Unit vector to the top of the image, orthogonal to both; `w` = 0.
    pub camera_up: Vec4,
    /// Source of the path's 2D decisions: [`SAMPLER_SEEDS`],
    /// [`SAMPLER_SCREEN_SOBOL`], [`SAMPLER_ZSOBOL`] or
    /// [`SAMPLER_SPATIOTEMPORAL`], the last three optionally ORed with
    /// [`SAMPLER_JITTER_ONLY`], the spatiotemporal one also with
    /// [`SAMPLER_FOLLOW_HOMES`]; any other value behaves like
    /// [`SAMPLER_SEEDS`]. [`Self::seed_mode`] still drives the seed stream
    /// (Russian roulette except with the spatiotemporal sampler, and
    /// everything the sampler does not).
    pub sampler: u32,
    /// `sampler_core::ScreenSobolLayout::side_log2` of the key buffer
    /// (binding 7): `log2` of the key tile side. Read only with
    /// [`SAMPLER_SCREEN_SOBOL`].
    pub key_side_log2: u32,
    /// `ScreenSobolLayout::pairs` of the key buffer (`>= 1`).
    pub key_pairs: u32,
    /// `ScreenSobolLayout::levels` of the key buffer (`>= 1`; level `j` is
    /// optimised for `2^j` spp).
    pub key_levels: u32,
    /// The previous frame's camera position (for motion vectors; equal to
    /// [`Self::camera_origin`] for frame 0 or a still camera); `w` = 0.
    pub prev_camera_origin: Vec4,
    /// The previous frame's unit viewing direction; `w` = 0.
    pub prev_camera_forward: Vec4,
    /// The previous frame's unit right vector; `w` = 0.
    pub prev_camera_right: Vec4,
    /// The previous frame's unit up vector; `w` = 0.
    pub prev_camera_up: Vec4,
    /// The previous frame's `tan(fov_y / 2)`, `> 0`.
    pub prev_tan_half_fov_y: f32,
    /// Number of images in the images buffer (headers), `>= 0`.
    pub image_count: u32,
    /// [`SAMPLER_SPATIOTEMPORAL`]: the number of samples `s` (from 0) whose
    /// sequence points for [`Self::frame`] the host stored in binding 7 after
    /// the shift tile (`crate::numbers::point_table_start`, slots as
    /// `crate::numbers::point_slot` says); the kernel computes the points of
    /// later samples itself. 0: no table (always correct, slower). A table of
    /// another frame than [`Self::frame`] gives wrong numbers: the host writes
    /// both together.
    pub point_samples: u32,
    /// Pixels per frame below which the motion pass ([`MOTION_ENTRY`])
    /// writes zero motion, so that the seed reprojection leaves the pixel's
    /// seed where it is (`crate::motion::seed_motion`); finite, `>= 0`;
    /// 0: every seed follows its surface. Read by the motion pass only.
    pub seed_hold_below: f32,
    /// Radiance of the constant environment, linear RGB in `xyz` (each
    /// finite and `>= 0`; zero: no environment): what every ray that leaves
    /// the scene sees, in every direction, when [`Self::environment_map`] is
    /// empty ([`crate::environment`]); zero with a map. `w`: the probability
    /// that next-event estimation picks the environment map's entry of the
    /// emitter list ([`EMITTER_ENVIRONMENT`]), for the MIS weight of BSDF
    /// samples that escape; 0 when there is none.
    pub environment: Vec4,
    /// The environment map's size and rotation (`width` 0: no map; then
    /// binding 10 holds one unused element). Its table and texels are
    /// binding 10 ([`crate::environment::environment_texel`] has the layout).
    pub environment_map: sampler_core::EnvironmentParams,
    /// Path regularisation strength ([`crate::regularization`]), finite, in
    /// `[0, 1]`: a glossy surface's roughness is raised to at least this times
    /// the roughest lobe that continued the path before it. 0 (the default):
    /// off, every path unbiased and as it was bit for bit.
    pub glossy_regularization: f32,
    /// Share of the frame's pixels, in `[0, 1]`, that must move rigidly
    /// (`crate::motion::moves_rigidly`, counted by [`RIGID_COUNT_ENTRY`])
    /// for every seed to follow its surface whatever
    /// [`Self::seed_hold_below`] says (`crate::motion::frame_follows`);
    /// 0: never, and the motion pass does not read the count. Read by the
    /// motion pass only.
    pub seed_follow_share: f32,
    /// ZSobol's screen offset, x (`crate::pan_offset`): `i32` bits in
    /// `crate::pan_offset::OFFSET_UNITS` per pixel; the trace reads ZSobol's
    /// point of pixel `p + round(offset)` ([`SAMPLER_ZSOBOL`] without
    /// [`SAMPLER_FOLLOW_HOMES`]). 0 from the host; with the motion pass on,
    /// the GPU copies the frame-motion buffer's accumulated offset here
    /// after it (the CPU renderer writes its own).
    pub sampler_offset_x: u32,
    /// ZSobol's screen offset, y; as [`Self::sampler_offset_x`].
    pub sampler_offset_y: u32,
    /// Where the a-priori samplers' per-pixel data sits on the screen, x
    /// (`crate::numbers::sampler_position`): the pixel (or home) `p` reads
    /// the keys of [`SAMPLER_SCREEN_SOBOL`], the shifts of
    /// [`SAMPLER_SPATIOTEMPORAL`] or ZSobol's point of `p + origin`
    /// (wrapping adds, so any `u32` is valid; the data repeats every 4096
    /// pixels or less, a divisor of `2^32`). One draw of the samplers'
    /// placement: two origins give two independent-looking renders with the
    /// same quality in expectation. 0 (the default) everywhere else.
    pub sampler_origin_x: u32,
    /// The samplers' origin, y; as [`Self::sampler_origin_x`].
    pub sampler_origin_y: u32,
    /// Padding to std140's 16-byte size; 0.
    pub pad0: u32,
    /// Padding to std140's 16-byte size; 0.
    pub pad1: u32,
}

/// One node of the BVH2 built by obvhs 0.4 (`Bvh2Node`), 48 bytes.
///
/// Inner node: `info.x == 0`, children at `info.y` and `info.y + 1`.
/// Leaf: `info.x >= 1` triangles at `triangles[info.y .. info.y + info.x]`
/// (the host reorders triangles by obvhs' `primitive_indices`, so leaves
/// index the triangle buffer directly).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct BvhNodeGpu {
    /// Box minimum corner (world units); `w` = 0.
    pub min: Vec4,
    /// Box maximum corner (world units); `w` = 0.
    pub max: Vec4,
    /// `x` = primitive count (0 for inner nodes), `y` = first child node or
    /// first triangle, `z`, `w` = 0 (obvhs' unused meta words).
    pub info: UVec4,
}

/// One triangle, 48 bytes. Vertices in world units, counter-clockwise seen
/// from the front: the geometric normal `(v1 - v0) x (v2 - v0)` points to the
/// front. Emission leaves the front side only; diffuse reflection is
/// two-sided.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct TriangleGpu {
    /// First vertex in `xyz`; `w` = material index as an exact integer-valued
    /// `f32` (indices up to 2^24).
    pub v0: Vec4,
    /// Second vertex in `xyz`; `w` = probability that next-event estimation
    /// picks this triangle (its [`EmitterGpu::pdf`]), 0 when it is not in the
    /// emitter list. Needed to weight emitters hit by BSDF sampling (MIS).
    pub v1: Vec4,
    /// Third vertex in `xyz`; `w` = [`CUT_OUT`] when the material can cut
    /// holes (alpha test at every candidate hit), 0 otherwise.
    pub v2: Vec4,
}

/// [`MaterialGpu::model`]`.x`: a Lambertian material (albedo `a`, BRDF
/// `a / pi`, two-sided). [`MaterialGpu::pbr`] and the metallic-roughness
/// texture are not read. The zero value, so a zeroed material is Lambertian.
pub const MODEL_LAMBERT: u32 = 0;
/// [`MaterialGpu::model`]`.x`: the glTF 2.0 metallic-roughness BRDF
/// (`crate::bsdf::MetallicRoughness`) with base colour = the albedo after
/// the base colour texture, metallic and roughness from [`MaterialGpu::pbr`]
/// times the metallic-roughness texture; two-sided like the Lambertian
/// model (the shading normal faces the outgoing direction).
pub const MODEL_METALLIC_ROUGHNESS: u32 = 1;
/// Flag of a texture's sampler flags (bit 5): the texels hold linear data,
/// not sRGB-encoded colour (glTF's metallic-roughness texture); each 8-bit
/// channel `c` reads as `c / 255`.
pub const TEXEL_LINEAR: u32 = 1 << 5;

/// Flag of a texture's sampler flags (bit 6): the texture coordinates go
/// through the texture's [`UvTransformGpu`] (in [`MaterialGpu`]) before the
/// lookup (glTF `KHR_texture_transform`). Clear: the coordinates are used as
/// they are (bit for bit, no arithmetic).
pub const UV_TRANSFORM: u32 = 1 << 6;

/// An affine map of texture coordinates, 32 bytes: `uv' = (u . (uv, 1),
/// v . (uv, 1))` with the dot products over `xyz`, i.e. the first two rows
/// of glTF `KHR_texture_transform`'s 3x3 matrix `translation * rotation *
/// scale` (the host computes them). Read only when the texture's sampler
/// flags carry [`UV_TRANSFORM`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct UvTransformGpu {
    /// First row `(m00, m01, m02)`: `u' = m00 u + m01 v + m02`; `w` = 0.
    pub u: Vec4,
    /// Second row `(m10, m11, m12)`: `v' = m10 u + m11 v + m12`; `w` = 0.
    pub v: Vec4,
}

impl UvTransformGpu {
    /// The identity map.
    pub const IDENTITY: UvTransformGpu = UvTransformGpu {
        u: Vec4::new(1.0, 0.0, 0.0, 0.0),
        v: Vec4::new(0.0, 1.0, 0.0, 0.0),
    };

    /// `uv` mapped: `(u . (uv, 1), v . (uv, 1))`, evaluated as
    /// `m0 * u + m1 * v + m2` per row (the same f32 operations on the CPU
    /// and the GPU).
    #[inline]
    pub fn apply(&self, uv: Vec2) -> Vec2 {
        Vec2::new(
            self.u.x * uv.x + self.u.y * uv.y + self.u.z,
            self.v.x * uv.x + self.v.y * uv.y + self.v.z,
        )
    }
}

/// [`TriangleGpu::v2`]`.w` of a triangle whose material can cut holes
/// ([`MaterialGpu::alpha`]`.x > 0`, glTF `alphaMode` `MASK`): the
/// traversals (`crate::bvh`) test the base colour alpha at each candidate
/// hit and skip it in a hole. Any other value (0) is opaque: no test, no
/// cost.
pub const CUT_OUT: f32 = 1.0;

/// A possibly emissive, possibly textured, possibly cut-out, possibly
/// normal-mapped material, 240 bytes: Lambertian or glTF metallic-roughness
/// ([`Self::model`]), each texture with its own coordinate transform.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct MaterialGpu {
    /// Lambertian albedo, or the metallic-roughness model's base colour, in
    /// linear RGB, each channel in `[0, 1]`; `w` = 0. Multiplied by the base
    /// colour texture when there is one.
    pub albedo: Vec4,
    /// Emitted radiance in linear RGB (arbitrary radiometric units,
    /// `>= 0`), from the front side; `w` = 0. Multiplied by the emission
    /// texture when there is one.
    pub emission: Vec4,
    /// `x`: image index of the base colour texture or [`TEXTURE_NONE`];
    /// `y`: its sampler flags ([`WRAP_REPEAT`] ...); `z`, `w`: the same for
    /// the emission texture.
    pub textures: UVec4,
    /// Factors. `x`, `y`, read only with [`MODEL_METALLIC_ROUGHNESS`]: `x`
    /// = glTF `metallicFactor`, `y` = `roughnessFactor` (perceptual; GGX
    /// `alpha = roughness^2`), both in `[0, 1]` (the host refuses anything
    /// else). `z`, read only with a normal texture ([`Self::normal`], any
    /// model): the normal texture's `scale` (multiplies the tangent-plane
    /// components of the texel's normal; finite, 1 by default in glTF).
    /// `w` = 0.
    pub pbr: Vec4,
    /// `x`: [`MODEL_LAMBERT`] or [`MODEL_METALLIC_ROUGHNESS`] (any other
    /// value shades as Lambertian); `y`: image index of the
    /// metallic-roughness texture or [`TEXTURE_NONE`] (glTF
    /// `metallicRoughnessTexture`: blue = metallic, green = roughness, each
    /// multiplying its factor); `z`: its sampler flags (with
    /// [`TEXEL_LINEAR`]); `w` = 0.
    pub model: UVec4,
    /// Alpha cut-out (glTF `alphaMode` `MASK`): `x` = `alphaCutoff`, finite
    /// and `>= 0` (0: opaque, nothing is cut); `y` = the base colour
    /// factor's alpha in `[0, 1]`; `z`, `w` = 0. A point whose base colour
    /// alpha (`y` times the base colour texture's alpha, linear) is below
    /// `x` is a hole. Read only for triangles flagged [`CUT_OUT`].
    pub alpha: Vec4,
    /// Coordinate transform of the base colour texture (read with
    /// [`UV_TRANSFORM`] in its flags, `textures.y`).
    pub base_color_uv: UvTransformGpu,
    /// Coordinate transform of the emission texture (read with
    /// [`UV_TRANSFORM`] in `textures.w`).
    pub emission_uv: UvTransformGpu,
    /// Coordinate transform of the metallic-roughness texture (read with
    /// [`UV_TRANSFORM`] in `model.z`).
    pub metal_rough_uv: UvTransformGpu,
    /// Normal map (glTF `normalTexture`, `crate::normal_map`): `x` = image
    /// index or [`TEXTURE_NONE`] (no normal map: the surface shades with its
    /// geometric normal, bit for bit as without this field); `y` = its
    /// sampler flags (read with [`TEXEL_LINEAR`] whether set or not: the
    /// texels are data); `z`, `w` = 0. Its scale is `pbr.z`.
    pub normal: UVec4,
    /// Coordinate transform of the normal texture (read with
    /// [`UV_TRANSFORM`] in `normal.y`).
    pub normal_uv: UvTransformGpu,
}

impl MaterialGpu {
    /// An untextured Lambertian material.
    pub const fn untextured(albedo: Vec4, emission: Vec4) -> Self {
        MaterialGpu {
            albedo,
            emission,
            textures: UVec4::new(TEXTURE_NONE, 0, TEXTURE_NONE, 0),
            pbr: Vec4::ZERO,
            model: UVec4::new(MODEL_LAMBERT, TEXTURE_NONE, 0, 0),
            alpha: Vec4::ZERO,
            base_color_uv: UvTransformGpu::IDENTITY,
            emission_uv: UvTransformGpu::IDENTITY,
            metal_rough_uv: UvTransformGpu::IDENTITY,
            normal: UVec4::new(TEXTURE_NONE, 0, 0, 0),
            normal_uv: UvTransformGpu::IDENTITY,
        }
    }

    /// An untextured metallic-roughness material: base colour `albedo`
    /// (linear RGB in `[0, 1]`, `w` = 0), `metallic` and `roughness` in
    /// `[0, 1]`, no emission.
    pub const fn metallic_roughness(albedo: Vec4, metallic: f32, roughness: f32) -> Self {
        MaterialGpu {
            albedo,
            emission: Vec4::ZERO,
            textures: UVec4::new(TEXTURE_NONE, 0, TEXTURE_NONE, 0),
            pbr: Vec4::new(metallic, roughness, 0.0, 0.0),
            model: UVec4::new(MODEL_METALLIC_ROUGHNESS, TEXTURE_NONE, 0, 0),
            alpha: Vec4::ZERO,
            base_color_uv: UvTransformGpu::IDENTITY,
            emission_uv: UvTransformGpu::IDENTITY,
            metal_rough_uv: UvTransformGpu::IDENTITY,
            normal: UVec4::new(TEXTURE_NONE, 0, 0, 0),
            normal_uv: UvTransformGpu::IDENTITY,
        }
    }
}

/// Per-triangle attributes the BVH traversal does not need, 112 bytes,
/// parallel to the triangle buffer (BVH leaf order).
///
/// Layout: texture coordinates (32 bytes), ids (16), the normal map's
/// tangent (16), then the three vertex normals (48), each field a 16-byte
/// `Vec4`/`UVec4` (std430 without padding).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct TriangleAttrGpu {
    /// Texture coordinates of vertices 0 (`xy`) and 1 (`zw`).
    pub uv01: Vec4,
    /// Texture coordinates of vertex 2 (`xy`); `zw` = 0.
    pub uv2: Vec4,
    /// `x`: object id (below [`GBUFFER_NO_HIT`]); `y`: index of the triangle
    /// in the host's scene order (before BVH reordering); `z`, `w` = 0.
    pub ids: UVec4,
    /// The tangent frame of the normal map (read only for materials with a
    /// normal texture, [`MaterialGpu::normal`]): `x`, `y` = the tangent as a
    /// combination `x (v1 - v0) + y (v2 - v0)` of the triangle's edges (any
    /// length; the kernel projects it onto the plane and normalises it, so
    /// it follows the triangle when animation moves its vertices); `z` =
    /// bitangent sign (glTF `TANGENT.w`: the bitangent is `z * (n x t)`
    /// with `n` the front normal; negative means -1, anything else +1);
    /// `w` = 0. All zero (the default): any tangent, sign +1
    /// (`crate::normal_map::tangent_frame`).
    pub tangent: Vec4,
    /// Shading normal of vertex 0 (`crate::vertex_normal`): `xyz` = unit
    /// vector in world space (the file's `NORMAL` / OBJ `vn` after the
    /// node's inverse-transpose transform), pointing to the side the
    /// authored normals point to (any side: the kernel orients the blend to
    /// the triangle's front); `w` = 0. All three normals zero (the default):
    /// the triangle has no vertex normals and shades with its flat
    /// geometric normal, bit for bit as before vertex normals existed. The
    /// host writes either three unit normals or three zeros.
    pub normal0: Vec4,
    /// Shading normal of vertex 1, as [`Self::normal0`].
    pub normal1: Vec4,
    /// Shading normal of vertex 2, as [`Self::normal0`].
    pub normal2: Vec4,
}

/// One pixel of the G-buffer, 64 bytes: what the ray through the pixel
/// centre sees first. Without a hit every field is 0 except
/// `ids = (GBUFFER_NO_HIT, GBUFFER_NO_HIT, GBUFFER_NO_HIT, 0)` and
/// `motion.xy` (the motion of the direction, as for a point at infinity).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GBufferGpu {
    /// `xyz`: unit geometric normal in world space, facing the camera (not
    /// the normal map's shading normal: the feature-aware permutation wants
    /// the surface's orientation, and normal maps would add texture detail
    /// to it); `w`: linear
    /// depth, the hit point's distance along the camera's forward axis in
    /// world units, `> 0`.
    pub normal_depth: Vec4,
    /// `rgb`: albedo at the hit in linear RGB (material albedo x base colour
    /// texture), each in `[0, 1]`; `w`: 0.
    pub albedo: Vec4,
    /// `xy`: backward motion in pixels: where the hit point was in the
    /// previous frame's raster, minus this pixel's centre `(x + 0.5, y +
    /// 0.5)` (raster `x` right, `y` down); includes camera and object
    /// motion; 0 for a still scene; only meaningful with
    /// [`GBUFFER_PREV_IN_FRONT`]. `z`: the hit point's linear depth in the
    /// previous camera (compare with the previous G-buffer's depth to detect
    /// disocclusion). `w`: 0.
    pub motion: Vec4,
    /// `x`: object id, `y`: material index, `z`: triangle index in the host's
    /// scene order, `w`: flags ([`GBUFFER_HIT`], [`GBUFFER_PREV_IN_FRONT`],
    /// [`GBUFFER_EMITTER`]).
    pub ids: UVec4,
}

/// [`EmitterGpu::kind`]: an emissive triangle ([`EmitterGpu::triangle`]),
/// sampled by a uniform point on its area. The zero value.
pub const EMITTER_TRIANGLE: u32 = 0;
/// [`EmitterGpu::kind`]: a point light (glTF `KHR_lights_punctual` `point`):
/// intensity in candela at [`EmitterGpu::position`], the same in every
/// direction. A delta light: found by next-event estimation only.
pub const EMITTER_POINT: u32 = 1;
/// [`EmitterGpu::kind`]: a spot light (`KHR_lights_punctual` `spot`): a
/// point light whose intensity is scaled by the extension's smooth cone
/// falloff around [`EmitterGpu::direction`] (`crate::lights::spot_falloff`).
pub const EMITTER_SPOT: u32 = 2;
/// [`EmitterGpu::kind`]: a directional light (`KHR_lights_punctual`
/// `directional`): illuminance in lux from infinitely far away, travelling
/// along [`EmitterGpu::direction`]; with a non-zero angular radius
/// ([`EmitterGpu::shape`]`.x`) a sun disk of uniform radiance. Found by
/// next-event estimation only (rays that escape see the environment, not
/// the disk).
pub const EMITTER_DIRECTIONAL: u32 = 3;
/// [`EmitterGpu::kind`]: the environment map ([`TraceParams::environment_map`],
/// binding 10), sampled in proportion to luminance times solid angle and
/// combined with BSDF sampling by MIS. At most one entry.
pub const EMITTER_ENVIRONMENT: u32 = 4;

/// One entry of the emitter list for next-event estimation, 80 bytes: an
/// emissive triangle or a punctual light ([`EMITTER_TRIANGLE`],
/// [`EMITTER_POINT`], [`EMITTER_SPOT`], [`EMITTER_DIRECTIONAL`]).
///
/// Emitters are picked with probability proportional to their power by a
/// binary search over `cdf` (the host's `gpu_tracer::scene` documents the
/// power of each kind). Photometric units are the renderer's radiance
/// unit: an emissive surface of radiance 1 and a point light of 1 cd at 1
/// unit of distance give the same irradiance scale (1 lux = 1 unit of
/// irradiance).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct EmitterGpu {
    /// What the entry is: one of the `EMITTER_*` constants.
    pub kind: u32,
    /// [`EMITTER_TRIANGLE`]: index into the triangle buffer (BVH leaf
    /// order); 0 for the other kinds.
    pub triangle: u32,
    /// Inclusive cumulative selection probability: the sum of `pdf` over this
    /// entry and all before it, in `(0, 1]`; the last entry holds exactly 1.
    pub cdf: f32,
    /// Probability of picking this entry, in `(0, 1]`.
    pub pdf: f32,
    /// Point and spot lights: `xyz` = position in world units, `w` = range
    /// in world units beyond which the light has no effect, windowed as the
    /// extension recommends (`crate::lights::range_window`); `w` = 0 for an
    /// unbounded light. Zero for the other kinds.
    pub position: Vec4,
    /// Spot lights: `xyz` = unit axis of the cone, the direction the light
    /// shines along (the node's `-z`). Directional lights: `xyz` = unit
    /// direction the light travels (from the light into the scene). `w` = 0.
    pub direction: Vec4,
    /// `xyz` = linear RGB intensity: candela for point and spot lights
    /// (colour times intensity), lux (illuminance on a surface facing the
    /// light) for directional lights; zero for triangles. `w` = triangle
    /// area in square world units as the host computed it for the selection
    /// probability (the kernels recompute the area from the vertices, the
    /// same f32 operations on both sides of the MIS weight), 0 for the other
    /// kinds.
    pub intensity: Vec4,
    /// Spot lights: `x` = cosine of the outer cone angle, `y` = `1 /
    /// max(1e-3, cos inner - cos outer)` (the extension's angle scale).
    /// Directional lights: `x` = `1 - cos(angular radius)`, in `[0, 1)`, 0
    /// for a delta light (the glTF directional light), computed in f64 on
    /// the host so that small radii keep their precision. `z`, `w` = 0.
    pub shape: Vec4,
}

impl EmitterGpu {
    /// Padding entry for an emitter buffer of a scene without emitters
    /// (never read while `emitter_count == 0`).
    pub const NONE: EmitterGpu = EmitterGpu {
        kind: EMITTER_TRIANGLE,
        triangle: 0,
        cdf: 1.0,
        pdf: 0.0,
        position: Vec4::ZERO,
        direction: Vec4::ZERO,
        intensity: Vec4::ZERO,
        shape: Vec4::ZERO,
    };

    /// Triangle area in square world units as the host computed it (the
    /// selection power of an [`EMITTER_TRIANGLE`]); 0 for the other kinds.
    pub fn area(&self) -> f32 {
        self.intensity.w
    }
}

const _: () = assert!(core::mem::size_of::<TraceParams>() == 272);
const _: () = assert!(core::mem::size_of::<TriangleAttrGpu>() == 112);
const _: () = assert!(core::mem::size_of::<GBufferGpu>() == 64);
const _: () = assert!(core::mem::size_of::<BvhNodeGpu>() == 48);
const _: () = assert!(core::mem::size_of::<TriangleGpu>() == 48);
const _: () = assert!(core::mem::size_of::<UvTransformGpu>() == 32);
const _: () = assert!(core::mem::size_of::<MaterialGpu>() == 240);
const _: () = assert!(core::mem::size_of::<EmitterGpu>() == 80);
