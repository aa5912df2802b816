//! The feature-aware permutation: sort what the seed controls, and never
//! move a seed to a surface it did not sample.
//!
//! The plain permutation ([`crate::permute_frame`]) assumes that a seed's
//! estimate survives a move inside its block and along the retarget
//! table's offsets. Across an edge (another object, a crease, a depth
//! jump) it does not. This module keeps every move on one surface, as
//! [`same_surface`] decides from per-pixel [`SurfaceFeature`]s:
//!
//! 1. **Groups inside a block** ([`block_groups`]): the connected components
//!    of the block's pixels under [`same_surface`]. Each group is sorted on
//!    its own ([`sort_block_grouped`]): its seeds, ordered by key, go onto its
//!    own positions, ordered by dither rank. A block with one group is
//!    sorted exactly as [`crate::sort_block`] sorts it.
//! 2. **Retargeting cut at edges** ([`retarget_features_pixel`]): the
//!    table's permutation `π` is a set of cycles; an edge `p -> π(p)` whose
//!    ends are not the same surface is **cut**. Cuts split each cycle into
//!    chains `s -> π(s) -> ... -> e` whose inner edges are all uncut. Every
//!    seed moves along its uncut edge as before; the seed at a chain's end
//!    `e` (whose edge is cut) goes to the chain's start `s` instead of
//!    crossing. A cycle without cuts is applied as it is; with cuts, each
//!    chain becomes a cycle of its own.
//! 3. **Isolated positions get a fresh seed** ([`refresh_isolated_seed`]): a
//!    chain of one position (its edges in and out of the table both cut)
//!    would keep its seed for ever, so the pixel repeated its estimate frame
//!    after frame (QUALITY.md: 12.9% of an edge pixel's frames brought back
//!    a seed it had had, against 4.2% for the plain permutation, and its
//!    running mean stopped converging). Its seed is replaced by a hash of
//!    itself instead, so its estimate changes as white noise's does.
//!
//! # Invariant (proof sketch)
//!
//! The output is a permutation of the input in which the seed of every
//! chain of one position is replaced by [`refresh_isolated_seed`] of itself
//! (a fresh 32-bit hash: it equals another seed of the buffer with
//! probability about `seeds / 2^32` per refreshed seed, and two pixels that
//! share a seed share only their random numbers). Each position `q` receives
//! exactly one seed: if the edge into `q` (from `π⁻¹(q)`) is uncut, the seed
//! of `π⁻¹(q)`; if it is cut, `q` starts exactly one chain, and the seed of
//! that chain's end (found by walking `π⁻¹` back from the end until a cut
//! edge, which exists because the end's own edge is cut and lies on the
//! same cycle). Every seed is sent once: along its uncut edge, or (its edge
//! cut) to its chain's start. No seed crosses a cut edge; a seed that jumps
//! to its chain's start reaches it along uncut edges only, so it stays on
//! the surface connected to it by same-surface steps.
//!
//! Padding positions (outside the visible frame) form a surface of their
//! own: an edge between padding and a visible pixel is cut, two padding
//! positions are never cut apart.
//!
//! # Cost
//!
//! One more `u32` scratch buffer (the table's inverse for the frame, built
//! by a scatter), and a walk per chain end whose total length is at most the
//! number of seeds on cut cycles (each chain is walked once).

use crate::error::{Buffer, Error};
pub use crate::features::isolated::refresh_isolated_seed;
use crate::features::step::FeatureStep;
use crate::features::surface::{edge_is_cut, same_surface, FeatureThresholds, SurfaceFeature};
use crate::permutation::dither::{tile_texel, DitherTile};
use crate::permutation::layout::{FrameLayout, FrameParams};
use crate::permutation::retarget::{retarget_destination, RetargetTables};
use crate::permutation::sort::{intensity_key, sort_block, Intensity, MAX_BLOCK_PIXELS};
use crate::sequences::walk::{step_index, walk_offset};
use glam::UVec2;

/// The groups of a block's `len` pixels: `groups[i]` is the smallest index
/// `j` of a pixel connected to pixel `i` by a chain of [`same_surface`]
/// pairs (so pixel `i` starts a group iff `groups[i] == i`). Block-local
/// indices are row-major inside the block, as the sorting pass lists them.
#[inline]
#[allow(clippy::needless_range_loop)]
pub fn block_groups(
    len: u32,
    features: &[SurfaceFeature; MAX_BLOCK_PIXELS],
    thresholds: &FeatureThresholds,
    groups: &mut [u32; MAX_BLOCK_PIXELS],
) {
    let n = if len as usize > MAX_BLOCK_PIXELS {
        MAX_BLOCK_PIXELS
    } else {
        len as usize
    };
    for i in 0..n {
        groups[i] = 0;
    }
    // Fast path: every pixel the same surface as the first makes one group
    // (the usual block, inside a surface): n - 1 tests instead of n^2 / 2.
    let mut one = true;
    for i in 1..n {
        if !same_surface(&features[i], &features[0], thresholds) {
            one = false;
        }
    }
    if one {
        return;
    }
    // Union-find with the smaller root winning, so roots are component minima.
    for i in 0..n {
        groups[i] = i as u32;
    }
    for i in 1..n {
        for j in 0..i {
            if same_surface(&features[i], &features[j], thresholds) {
                let a = find(groups, i as u32);
                let b = find(groups, j as u32);
                if a < b {
                    groups[b as usize] = a;
                } else if b < a {
                    groups[a as usize] = b;
                }
            }
        }
    }
    for i in 0..n {
        groups[i] = find(groups, i as u32);
    }
}

#[inline]
fn find(parent: &[u32; MAX_BLOCK_PIXELS], mut i: u32) -> u32 {
    while parent[i as usize] != i {
        i = parent[i as usize];
    }
    i
}

/// [`crate::sort_block`] inside groups: pixel `i` of group `groups[i]`
/// takes the position of the same rank among its group's positions, ranks
/// ordered by `(group, value, index)`. With every `groups[i]` equal this is
/// exactly [`crate::sort_block`].
#[allow(clippy::needless_range_loop)]
#[inline]
pub fn sort_block_grouped(
    len: u32,
    groups: &[u32; MAX_BLOCK_PIXELS],
    keys: &[u32; MAX_BLOCK_PIXELS],
    dither: &[u32; MAX_BLOCK_PIXELS],
    seeds: &[u32; MAX_BLOCK_PIXELS],
    out: &mut [u32; MAX_BLOCK_PIXELS],
) {
    let n = if len as usize > MAX_BLOCK_PIXELS {
        MAX_BLOCK_PIXELS
    } else {
        len as usize
    };
    let mut position_of_rank = [0u32; MAX_BLOCK_PIXELS];
    for j in 0..n {
        let (gj, dj) = (groups[j], dither[j]);
        let mut rank = 0usize;
        for i in 0..n {
            let (gi, di) = (groups[i], dither[i]);
            if gi < gj || (gi == gj && (di < dj || (di == dj && i < j))) {
                rank += 1;
            }
        }
        position_of_rank[rank] = j as u32;
    }
    for i in 0..n {
        let (gi, ki) = (groups[i], keys[i]);
        let mut rank = 0usize;
        for j in 0..n {
            let (gj, kj) = (groups[j], keys[j]);
            if gj < gi || (gj == gi && (kj < ki || (kj == ki && j < i))) {
                rank += 1;
            }
        }
        out[position_of_rank[rank] as usize] = seeds[i];
    }
}

/// The feature-aware sorting pass of block `(bx, by)` with tile offset
/// `offset`: as [`crate::sort_block_at_offset`], in groups
/// ([`block_groups`]) of `features` (`width * height`, row-major).
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn sort_block_features_at_offset<T: Intensity>(
    params: &FrameParams,
    offset: UVec2,
    bx: u32,
    by: u32,
    intensities: &[T],
    features: &[SurfaceFeature],
    thresholds: &FeatureThresholds,
    tile: &[u32],
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) {
    let x0 = bx * params.block;
    let y0 = by * params.block;
    let mut keys = [0u32; MAX_BLOCK_PIXELS];
    let mut dither = [0u32; MAX_BLOCK_PIXELS];
    let mut seeds = [0u32; MAX_BLOCK_PIXELS];
    let mut index = [0u32; MAX_BLOCK_PIXELS];
    let mut feats = [SurfaceFeature::default(); MAX_BLOCK_PIXELS];
    let mut len = 0usize;
    for dy in 0..params.block {
        for dx in 0..params.block {
            let x = x0 + dx;
            let y = y0 + dy;
            if x < params.padded_width && y < params.padded_height {
                let s = (y * params.padded_width + x) as usize;
                if x < params.width && y < params.height {
                    let v = (y * params.width + x) as usize;
                    keys[len] = intensity_key(intensities[v].intensity());
                    dither[len] = tile[tile_texel(UVec2::new(x, y), offset, params.tile_log2) as usize];
                    seeds[len] = seeds_in[s];
                    feats[len] = features[v];
                    index[len] = s as u32;
                    len += 1;
                } else {
                    seeds_out[s] = seeds_in[s];
                }
            }
        }
    }
    let mut groups = [0u32; MAX_BLOCK_PIXELS];
    block_groups(len as u32, &feats, thresholds, &mut groups);
    let mut one_group = true;
    #[allow(clippy::needless_range_loop)] // iterators over arrays do not compile for shaders
    for i in 0..len {
        if groups[i] != 0 {
            one_group = false;
        }
    }
    let mut out = [0u32; MAX_BLOCK_PIXELS];
    if one_group {
        // The same result, with the plain sort's cheaper comparisons.
        sort_block(len as u32, &keys, &dither, &seeds, &mut out);
    } else {
        sort_block_grouped(len as u32, &groups, &keys, &dither, &seeds, &mut out);
    }
    for i in 0..len {
        seeds_out[index[i] as usize] = out[i];
    }
}

/// The retarget destination of padded-buffer index `p` (`π(p)`) with tile
/// offset `offset` and packed table `table`.
#[inline]
pub fn retarget_index(params: &FrameParams, offset: UVec2, table: &[u32], p: u32) -> u32 {
    let pw = params.padded_width;
    let padded = UVec2::new(pw, params.padded_height);
    let d = retarget_destination(
        UVec2::new(p % pw, p / pw),
        offset,
        params.tile_log2,
        table,
        padded,
    );
    d.y * pw + d.x
}

/// First step of the feature-aware retarget, one per seed: records the
/// inverse of the table's permutation, `sources[π(p)] = p`.
#[inline]
pub fn record_source(params: &FrameParams, offset: UVec2, table: &[u32], p: u32, sources: &mut [u32]) {
    sources[retarget_index(params, offset, table, p) as usize] = p;
}

/// Second step, one per seed `p`: sends `seeds_in[p]` along its edge if it
/// is uncut, else to the start of its chain, refreshed if that start is `p`
/// itself (module docs). `sources` is the inverse from [`record_source`].
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn retarget_features_pixel(
    params: &FrameParams,
    offset: UVec2,
    table: &[u32],
    sources: &[u32],
    features: &[SurfaceFeature],
    thresholds: &FeatureThresholds,
    p: u32,
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) {
    let d = retarget_index(params, offset, table, p);
    if !edge_is_cut(params, features, thresholds, p, d) {
        seeds_out[d as usize] = seeds_in[p as usize];
        return;
    }
    // Walk back along uncut edges to the chain's start. Terminates: the
    // cut edge p -> d lies on this cycle.
    let mut q = p;
    loop {
        let r = sources[q as usize];
        if edge_is_cut(params, features, thresholds, r, q) {
            break;
        }
        q = r;
    }
    seeds_out[q as usize] = chain_start_seed(p, q, seeds_in[p as usize]);
}

/// The seed the start `q` of `p`'s chain receives from `p` (whose edge is
/// cut): `seed`, or [`refresh_isolated_seed`] of it when the chain is `p`
/// alone.
#[inline]
fn chain_start_seed(p: u32, q: u32, seed: u32) -> u32 {
    if q == p {
        refresh_isolated_seed(seed)
    } else {
        seed
    }
}

/// Flag bit of a link ([`record_link`]): set when the link's index is the
/// start of the chain (the seed index itself is in bits 0..31; a padded
/// seed buffer holds fewer than 2^31 seeds).
pub const LINK_START: u32 = 1 << 31;

/// Jump rounds ([`jump_link`]) the GPU runs between [`record_link`] and
/// [`retarget_features_linked`]. Any number gives the same output (the last
/// walk finishes what the rounds leave); each round halves the longest
/// walk and costs one pass over the links (4 bytes read in order, 4
/// gathered and 4 written per seed). The table's cycles wrap around the
/// padded frame: at 1280x720 with the default 64x64 tables the longest
/// cycle of a frame holds 68,820 to 120,780 seeds (frames 0 to 15), so a
/// chain on one large surface can be tens of thousands of seeds long (the
/// serial walk took 4.0 ms on an H100). Twelve rounds leave at most
/// `ceil(L / 4096)` steps for a chain of `L` seeds (30 for the longest
/// cycle), about where one more round costs as much as the steps it saves.
/// Even, so the links end in the buffer [`record_link`] wrote.
pub const JUMP_ROUNDS: u32 = 12;
const _: () = assert!(
    JUMP_ROUNDS.is_multiple_of(2),
    "the links must end where record_link wrote them"
);

/// First step of the linked feature-aware retarget, one per seed `p` (a
/// scatter into `links`, `seed_count`): the link of `d = π(p)`, which is
/// `d | LINK_START` if the edge `p -> d` is cut (`d` starts its chain),
/// else `p` (one step back along the chain). Identical to what
/// [`record_source`] and the walk of [`retarget_features_pixel`] read, in
/// one word.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn record_link(
    params: &FrameParams,
    offset: UVec2,
    table: &[u32],
    features: &[SurfaceFeature],
    thresholds: &FeatureThresholds,
    p: u32,
    links: &mut [u32],
) {
    let d = retarget_index(params, offset, table, p);
    links[d as usize] = if edge_is_cut(params, features, thresholds, p, d) {
        d | LINK_START
    } else {
        p
    };
}

/// One pointer-jumping round, one per seed `q`: a link that reaches its
/// chain's start stays; otherwise it becomes the link of the seed it points
/// to, so it points twice as far back (or to the start). Reads `links_in`,
/// writes `links_out[q]` (two buffers: every invocation reads the round's
/// input).
#[inline]
pub fn jump_link(q: u32, links_in: &[u32], links_out: &mut [u32]) {
    let v = links_in[q as usize];
    links_out[q as usize] = if v & LINK_START != 0 {
        v
    } else {
        links_in[v as usize]
    };
}

/// Last step, one per seed `p`: [`retarget_features_pixel`] with the walk
/// along `links` (after [`record_link`] and any number of [`jump_link`]
/// rounds): the same destination, in as many steps as the rounds left.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn retarget_features_linked(
    params: &FrameParams,
    offset: UVec2,
    table: &[u32],
    links: &[u32],
    features: &[SurfaceFeature],
    thresholds: &FeatureThresholds,
    p: u32,
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) {
    let d = retarget_index(params, offset, table, p);
    if !edge_is_cut(params, features, thresholds, p, d) {
        seeds_out[d as usize] = seeds_in[p as usize];
        return;
    }
    // Follow links to the chain's start; terminates as the walk of
    // `retarget_features_pixel` does (every link points back along the
    // chain, or is flagged at its start).
    let mut v = links[p as usize];
    while v & LINK_START == 0 {
        v = links[v as usize];
    }
    let q = v & !LINK_START;
    seeds_out[q as usize] = chain_start_seed(p, q, seeds_in[p as usize]);
}

/// The feature-aware permutation of a frame: grouped sort of `intensities`
/// (`width * height`, e.g. [`crate::features::surface::demodulated_luma`] values)
/// against `D_frame`, then the retarget of step `frame -> frame + 1` cut at
/// edges (module docs). `features` is the frame's [`SurfaceFeature`]
/// buffer (`width * height`); `sorted` and `sources` are scratch
/// (`seed_count` each; their contents afterwards are unspecified). Output:
/// a permutation of `seeds_in` but for the refreshed seeds of isolated
/// positions (module docs); with features that make every pixel one
/// surface, identical to [`crate::permute_frame`].
///
/// Where the plain CPU fast path applies (block side 2, 4 or 8 dividing a
/// tile of 16 to 128 texels) this runs a fast path (the plain fused
/// permutation, then a repair of split blocks and cut edges); elsewhere
/// [`permute_frame_features_reference`]. Both give identical output.
///
/// # Errors
/// [`Error::TileSize`] if the tile or tables do not match the layout;
/// [`Error::BufferSize`] for a buffer of the wrong length.
///
/// # Example
///
/// Two surfaces side by side: seeds are permuted, and none crosses from one to
/// the other.
///
/// ```
/// use sampler_core::{defaults, permute_frame_features, FeatureThresholds, FrameLayout, SurfaceFeature};
/// use glam::Vec3;
/// let layout = FrameLayout::new(64, 32, 4, 64)?;
/// let (tile, tables) = (defaults::tile_64(), defaults::tables_64());
/// let (w, n) = (layout.padded_width(), layout.seed_count());
/// let features: Vec<SurfaceFeature> = (0..64 * 32)
///     .map(|i| SurfaceFeature::new(if i % 64 < 30 { 0 } else { 1 }, 5.0, Vec3::Z))
///     .collect();
/// let image: Vec<f32> = (0..64 * 32).map(|i| (i * 7919 % 101) as f32).collect();
/// let seeds: Vec<u32> = (0..n as u32).collect(); // seed = its pixel index
/// let (mut sorted, mut sources, mut next) = (vec![0; n], vec![0; n], vec![0; n]);
/// let thresholds = FeatureThresholds::DEFAULT;
/// permute_frame_features(&layout, 0, &image, &features, &thresholds, &tile, &tables, &seeds,
///                        &mut sorted, &mut sources, &mut next)?;
/// // Each input seed moved once, except where a position's retarget edges are both
/// // cut: there a fresh seed (a hash, far above the seed count here).
/// let mut moved: Vec<u32> = next.iter().copied().filter(|&s| (s as usize) < n).collect();
/// let fresh = n - moved.len();
/// moved.sort();
/// moved.dedup();
/// assert_eq!(moved.len() + fresh, n);
/// assert!(fresh < n / 10, "{fresh} isolated positions"); // 209 of 4096 here, most beside the padding
/// for (p, &s) in next.iter().enumerate() {
///     let (x, y, sx, sy) = (p as u32 % w, p as u32 / w, s % w, s / w);
///     if x < 64 && y < 32 && sx < 64 && sy < 32 {
///         assert_eq!(x < 30, sx < 30, "seed {s} crossed the edge"); // stays on its surface
///     }
/// }
/// # Ok::<(), sampler_core::Error>(())
/// ```
#[allow(clippy::too_many_arguments)]
pub fn permute_frame_features<T: Intensity>(
    layout: &FrameLayout,
    frame: u32,
    intensities: &[T],
    features: &[SurfaceFeature],
    thresholds: &FeatureThresholds,
    tile: &DitherTile<'_>,
    tables: &RetargetTables<'_>,
    seeds_in: &[u32],
    sorted: &mut [u32],
    sources: &mut [u32],
    seeds_out: &mut [u32],
) -> Result<(), Error> {
    check_feature_tiles(layout, tile, tables)?;
    check_feature_buffers(
        layout,
        intensities,
        features,
        seeds_in,
        sorted,
        sources,
        seeds_out,
    )?;
    FeatureStep::of_walk(layout, frame, intensities, features, thresholds, tile, tables)
        .run(seeds_in, sorted, sources, seeds_out);
    Ok(())
}

impl<'a, T: Intensity> FeatureStep<'a, T> {
    /// The walk's step after frame `frame`: its tile and the table of its
    /// step.
    fn of_walk(
        layout: &FrameLayout,
        frame: u32,
        intensities: &'a [T],
        features: &'a [SurfaceFeature],
        thresholds: &'a FeatureThresholds,
        tile: &'a DitherTile<'_>,
        tables: &'a RetargetTables<'_>,
    ) -> Self {
        let params = layout.params(frame);
        FeatureStep {
            params,
            intensities,
            features,
            thresholds,
            tile: tile.values(),
            table: tables.table(step_index(frame, params.tile_log2)),
        }
    }

    /// Runs the step on checked seed buffers (`sorted` and `sources` are
    /// scratch): the CPU fast path where it applies, else
    /// [`reference`](Self::reference); identical output.
    pub(crate) fn run(
        &self,
        seeds_in: &[u32],
        sorted: &mut [u32],
        sources: &mut [u32],
        seeds_out: &mut [u32],
    ) {
        if crate::features::cpu::applies(&self.params) {
            crate::features::cpu::permute_features_fast(self, seeds_in, sorted, sources, seeds_out);
        } else {
            self.reference(seeds_in, sorted, sources, seeds_out);
        }
    }

    /// The reference passes, as the GPU kernels run them (less the jump
    /// rounds, which do not change the output): the grouped sort of every
    /// block into `sorted`, the links into `sources`, the cut retarget into
    /// `seeds_out`.
    pub(crate) fn reference(
        &self,
        seeds_in: &[u32],
        sorted: &mut [u32],
        sources: &mut [u32],
        seeds_out: &mut [u32],
    ) {
        let (params, table) = (&self.params, self.table.packed());
        let (features, thresholds) = (self.features, self.thresholds);
        let offset = walk_offset(params.frame, params.tile_log2);
        for by in 0..params.blocks_y() {
            for bx in 0..params.blocks_x() {
                sort_block_features_at_offset(
                    params,
                    offset,
                    bx,
                    by,
                    self.intensities,
                    features,
                    thresholds,
                    self.tile,
                    seeds_in,
                    sorted,
                );
            }
        }
        for p in 0..params.seed_count() {
            record_link(params, offset, table, features, thresholds, p, sources);
        }
        for p in 0..params.seed_count() {
            retarget_features_linked(
                params, offset, table, sources, features, thresholds, p, sorted, seeds_out,
            );
        }
    }
}

/// The reference form of [`permute_frame_features`]: [`sort_block_features_at_offset`]
/// for every block into `sorted`, [`record_link`] for every seed into
/// `sources` (the table's inverse and the cut bits, as links), then
/// [`retarget_features_linked`] for every seed, as the GPU kernels run them
/// (less the [`jump_link`] rounds, which do not change the output).
/// Identical output to [`permute_frame_features`], which takes a faster
/// path on the CPU where it can, and to the serial walk of
/// [`retarget_features_pixel`] after [`record_source`]; afterwards `sorted`
/// holds the sorted seeds and `sources` the links of [`record_link`].
///
/// # Errors
/// As [`permute_frame_features`].
#[allow(clippy::too_many_arguments)]
pub fn permute_frame_features_reference<T: Intensity>(
    layout: &FrameLayout,
    frame: u32,
    intensities: &[T],
    features: &[SurfaceFeature],
    thresholds: &FeatureThresholds,
    tile: &DitherTile<'_>,
    tables: &RetargetTables<'_>,
    seeds_in: &[u32],
    sorted: &mut [u32],
    sources: &mut [u32],
    seeds_out: &mut [u32],
) -> Result<(), Error> {
    check_feature_tiles(layout, tile, tables)?;
    check_feature_buffers(
        layout,
        intensities,
        features,
        seeds_in,
        sorted,
        sources,
        seeds_out,
    )?;
    FeatureStep::of_walk(layout, frame, intensities, features, thresholds, tile, tables)
        .reference(seeds_in, sorted, sources, seeds_out);
    Ok(())
}

/// The tile checks of [`permute_frame_features`]: tile and tables of the
/// layout's side.
fn check_feature_tiles(
    layout: &FrameLayout,
    tile: &DitherTile<'_>,
    tables: &RetargetTables<'_>,
) -> Result<(), Error> {
    if tile.tile() != layout.tile() || tables.tile() != layout.tile() {
        return Err(Error::TileSize { tile: tile.tile() });
    }
    Ok(())
}

/// The buffer checks of the feature-aware permutations: intensities and
/// features of the frame's pixels, seed buffers of its padded size.
pub(crate) fn check_feature_buffers<T>(
    layout: &FrameLayout,
    intensities: &[T],
    features: &[SurfaceFeature],
    seeds_in: &[u32],
    sorted: &[u32],
    sources: &[u32],
    seeds_out: &[u32],
) -> Result<(), Error> {
    layout.check_intensity_buffer(intensities.len())?;
    if features.len() != layout.pixel_count() {
        return Err(Error::BufferSize {
            buffer: Buffer::Features,
            expected: layout.pixel_count(),
            actual: features.len(),
        });
    }
    layout.check_seed_buffer(Buffer::SeedsIn, seeds_in.len())?;
    layout.check_seed_buffer(Buffer::SeedsOut, seeds_out.len())?;
    layout.check_seed_buffer(Buffer::Scratch, sorted.len())?;
    layout.check_seed_buffer(Buffer::Scratch, sources.len())?;
    Ok(())
}

#[cfg(test)]
#[path = "permute_tests.rs"]
mod tests;
