//! Frame-level passes: what a renderer calls once per frame.
//!
//! ```text
//! frame 0: seeds = initial seeds (white noise)
//! loop t:  image_t = render(seeds)
//!          seeds   = permute_frame(t, image_t, seeds)   // sort with D_t, retarget t -> t+1
//! ```
//!
//! The per-block and per-pixel functions ([`sort_block_in_frame`],
//! [`retarget_pixel`]) are what the GPU kernels call, one invocation per
//! block or per seed; the frame functions here loop over them (or over an
//! equivalent faster CPU path that is tested to give identical output).

use crate::error::{Buffer, Error};
use crate::permutation::dither::{tile_texel, DitherTile};
use crate::permutation::layout::{FrameLayout, FrameParams};
use crate::permutation::retarget::{retarget_destination, RetargetTable, RetargetTables};
use crate::permutation::sort::{intensity_key, sort_block, Intensity, MAX_BLOCK_PIXELS};
use crate::sequences::walk::{step_index, walk_offset};
use glam::UVec2;

/// Sorts block `(bx, by)` of the frame described by `params`, reading
/// `seeds_in` and writing the same block's seeds into `seeds_out`.
/// Shader-callable; one invocation per block, blocks are disjoint.
///
/// `intensities`: `width * height` visible values; `tile`: `W * W` dither
/// values; seed buffers: `padded_width * padded_height`. Pixels of the block
/// outside the visible frame keep their seeds.
///
/// # Example
///
/// What a GPU kernel runs, one invocation per block, here as a CPU loop; it
/// equals [`sort_frame`]:
///
/// ```
/// use sampler_core::{defaults, sort_block_in_frame, sort_frame, FrameLayout};
/// let layout = FrameLayout::new(20, 12, 4, 64)?;
/// let tile = defaults::tile_64();
/// let params = layout.params(7); // frame 7
/// let image: Vec<f32> = (0..20 * 12).map(|i| (i * 13 % 7) as f32).collect();
/// let seeds: Vec<u32> = (0..layout.seed_count() as u32).collect();
/// let mut out = vec![0; seeds.len()];
/// for by in 0..params.blocks_y() {
///     for bx in 0..params.blocks_x() {
///         sort_block_in_frame(&params, bx, by, &image, tile.values(), &seeds, &mut out);
///     }
/// }
/// let mut expected = vec![0; seeds.len()];
/// sort_frame(&layout, 7, &image, &tile, &seeds, &mut expected)?;
/// assert_eq!(out, expected);
/// # Ok::<(), sampler_core::Error>(())
/// ```
#[inline]
pub fn sort_block_in_frame<T: Intensity>(
    params: &FrameParams,
    bx: u32,
    by: u32,
    intensities: &[T],
    tile: &[u32],
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) {
    let offset = walk_offset(params.frame, params.tile_log2);
    sort_block_at_offset(params, offset, bx, by, intensities, tile, seeds_in, seeds_out);
}

/// [`sort_block_in_frame`] with an explicit tile offset (each component in
/// `0..W`) instead of the walk's `o_frame`: for renderers with their own
/// offset schedule, and for studying other walks. `params.frame` is ignored.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn sort_block_at_offset<T: Intensity>(
    params: &FrameParams,
    offset: UVec2,
    bx: u32,
    by: u32,
    intensities: &[T],
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
    let mut len = 0usize;
    for dy in 0..params.block {
        for dx in 0..params.block {
            let x = x0 + dx;
            let y = y0 + dy;
            if x < params.padded_width && y < params.padded_height {
                let s = (y * params.padded_width + x) as usize;
                if x < params.width && y < params.height {
                    keys[len] = intensity_key(intensities[(y * params.width + x) as usize].intensity());
                    dither[len] = tile[tile_texel(UVec2::new(x, y), offset, params.tile_log2) as usize];
                    seeds[len] = seeds_in[s];
                    index[len] = s as u32;
                    len += 1;
                } else {
                    seeds_out[s] = seeds_in[s];
                }
            }
        }
    }
    let mut out = [0u32; MAX_BLOCK_PIXELS];
    sort_block(len as u32, &keys, &dither, &seeds, &mut out);
    for i in 0..len {
        seeds_out[index[i] as usize] = out[i];
    }
}

/// Moves the seed at padded-buffer index `seed_index` to its retargeted
/// place. Shader-callable; one invocation per seed; the scatter is a
/// bijection, so invocations never write the same element.
///
/// # Example
///
/// What a GPU kernel runs, one invocation per seed, here as a CPU loop; it
/// equals [`retarget_frame`]:
///
/// ```
/// use sampler_core::{defaults, retarget_frame, retarget_pixel, step_index, FrameLayout};
/// let layout = FrameLayout::new(20, 12, 4, 64)?;
/// let tables = defaults::tables_64();
/// let params = layout.params(7);
/// let table = tables.table(step_index(7, params.tile_log2));
/// let seeds: Vec<u32> = (0..layout.seed_count() as u32).collect();
/// let mut out = vec![0; seeds.len()];
/// for i in 0..params.seed_count() {
///     retarget_pixel(&params, i, table.packed(), &seeds, &mut out);
/// }
/// let mut expected = vec![0; seeds.len()];
/// retarget_frame(&layout, 7, &tables, &seeds, &mut expected)?;
/// assert_eq!(out, expected);
/// # Ok::<(), sampler_core::Error>(())
/// ```
#[inline]
pub fn retarget_pixel(
    params: &FrameParams,
    seed_index: u32,
    table: &[u32],
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) {
    let offset = walk_offset(params.frame, params.tile_log2);
    retarget_pixel_at_offset(params, offset, seed_index, table, seeds_in, seeds_out);
}

/// [`retarget_pixel`] with an explicit tile offset (each component in
/// `0..W`) instead of the walk's `o_frame`; `table` must be the one baked
/// for the step to the next offset. `params.frame` is ignored.
#[inline]
pub fn retarget_pixel_at_offset(
    params: &FrameParams,
    offset: UVec2,
    seed_index: u32,
    table: &[u32],
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) {
    let p = UVec2::new(seed_index % params.padded_width, seed_index / params.padded_width);
    let padded = UVec2::new(params.padded_width, params.padded_height);
    let d = retarget_destination(p, offset, params.tile_log2, table, padded);
    seeds_out[(d.y * params.padded_width + d.x) as usize] = seeds_in[seed_index as usize];
}

pub(crate) fn check_common<T>(
    layout: &FrameLayout,
    tile: &DitherTile<'_>,
    intensities: &[T],
    seeds_in: &[u32],
    seeds_out: &[u32],
) -> Result<(), Error> {
    if tile.tile() != layout.tile() {
        return Err(Error::TileSize { tile: tile.tile() });
    }
    layout.check_intensity_buffer(intensities.len())?;
    check_seeds(layout, seeds_in, seeds_out)
}

fn check_seeds(layout: &FrameLayout, seeds_in: &[u32], seeds_out: &[u32]) -> Result<(), Error> {
    layout.check_seed_buffer(Buffer::SeedsIn, seeds_in.len())?;
    layout.check_seed_buffer(Buffer::SeedsOut, seeds_out.len())
}

/// Sorting pass over a whole frame: `seeds_out` = `seeds_in` permuted inside
/// each block so the ranks of frame `frame`'s intensities follow `D_frame`.
///
/// # Errors
/// [`Error::BufferSize`] for a buffer of the wrong length,
/// [`Error::TileSize`] if the tile's side differs from the layout's.
///
/// # Example
///
/// The two passes of [`permute_frame`], one after the
/// other (as a GPU runs them):
///
/// ```
/// use sampler_core::{defaults, permute_frame, retarget_frame, sort_frame, FrameLayout};
/// let layout = FrameLayout::new(40, 24, 4, 64)?;
/// let (tile, tables) = (defaults::tile_64(), defaults::tables_64());
/// let n = layout.seed_count();
/// let image: Vec<f32> = (0..40 * 24).map(|i| (i * 31 % 17) as f32).collect();
/// let seeds: Vec<u32> = (0..n as u32).map(|i| i.wrapping_mul(2654435761)).collect();
/// let (mut sorted, mut next) = (vec![0; n], vec![0; n]);
/// sort_frame(&layout, 3, &image, &tile, &seeds, &mut sorted)?;
/// retarget_frame(&layout, 3, &tables, &sorted, &mut next)?;
/// let mut fused = vec![0; n];
/// permute_frame(&layout, 3, &image, &tile, &tables, &seeds, &mut fused)?;
/// assert_eq!(next, fused);
/// # Ok::<(), sampler_core::Error>(())
/// ```
pub fn sort_frame<T: Intensity>(
    layout: &FrameLayout,
    frame: u32,
    intensities: &[T],
    tile: &DitherTile<'_>,
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) -> Result<(), Error> {
    check_common(layout, tile, intensities, seeds_in, seeds_out)?;
    let params = layout.params(frame);
    for by in 0..params.blocks_y() {
        for bx in 0..params.blocks_x() {
            sort_block_in_frame(&params, bx, by, intensities, tile.values(), seeds_in, seeds_out);
        }
    }
    Ok(())
}

/// Retargeting pass over a whole frame: scatters `seeds_in` (ranked like
/// `D_frame`) with the table of step `frame -> frame + 1`.
///
/// # Errors
/// [`Error::BufferSize`] for a seed buffer of the wrong length,
/// [`Error::TileSize`] if the tables' tile differs from the layout's.
pub fn retarget_frame(
    layout: &FrameLayout,
    frame: u32,
    tables: &RetargetTables<'_>,
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) -> Result<(), Error> {
    if tables.tile() != layout.tile() {
        return Err(Error::TileSize { tile: tables.tile() });
    }
    check_seeds(layout, seeds_in, seeds_out)?;
    let params = layout.params(frame);
    let table = tables.table(step_index(frame, params.tile_log2));
    for i in 0..params.seed_count() {
        retarget_pixel(&params, i, table.packed(), seeds_in, seeds_out);
    }
    Ok(())
}

/// The per-frame entry: sorting then retargeting, fused in one pass with no
/// allocation. `seeds_in` rendered frame `frame` (whose pixel values are
/// `intensities`); `seeds_out` receives the seeds to render frame
/// `frame + 1` with. Output is identical to [`sort_frame`] followed by
/// [`retarget_frame`].
///
/// # Errors
/// [`Error::BufferSize`] for a buffer of the wrong length,
/// [`Error::TileSize`] if the tile or tables do not match the layout.
///
/// ```
/// use sampler_core::*;
/// let layout = FrameLayout::new(5, 3, 2, 4)?;          // 5x3 frame, 2x2 blocks, 4x4 tile
/// let tile: Vec<u32> = (0..16).map(|i| (i * 7) % 16).collect();
/// let identity = [IDENTITY_PACKED; 16];
/// let tables = RetargetTables::new(4, [&identity; 4])?;
/// let seeds: Vec<u32> = (0..layout.seed_count() as u32).collect();
/// let image: Vec<f32> = (0..15).map(|i| (i % 4) as f32).collect();
/// let mut next = vec![0; layout.seed_count()];
/// permute_frame(&layout, 0, &image, &DitherTile::new(4, &tile)?, &tables, &seeds, &mut next)?;
/// let mut sorted = next.clone();
/// sorted.sort();
/// assert_eq!(sorted, seeds); // a permutation: no seed lost or duplicated
/// # Ok::<(), sampler_core::Error>(())
/// ```
pub fn permute_frame<T: Intensity>(
    layout: &FrameLayout,
    frame: u32,
    intensities: &[T],
    tile: &DitherTile<'_>,
    tables: &RetargetTables<'_>,
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) -> Result<(), Error> {
    permute_frame_with(
        layout,
        frame,
        intensities,
        tile,
        tables,
        seeds_in,
        seeds_out,
        true,
    )
}

/// [`permute_frame`] without the run-time choice of a wider instruction set
/// (the build's baseline only): identical output, for benchmarks and tests
/// that compare the two.
#[doc(hidden)]
pub fn permute_frame_baseline_isa<T: Intensity>(
    layout: &FrameLayout,
    frame: u32,
    intensities: &[T],
    tile: &DitherTile<'_>,
    tables: &RetargetTables<'_>,
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) -> Result<(), Error> {
    permute_frame_with(
        layout,
        frame,
        intensities,
        tile,
        tables,
        seeds_in,
        seeds_out,
        false,
    )
}

#[allow(clippy::too_many_arguments)]
fn permute_frame_with<T: Intensity>(
    layout: &FrameLayout,
    frame: u32,
    intensities: &[T],
    tile: &DitherTile<'_>,
    tables: &RetargetTables<'_>,
    seeds_in: &[u32],
    seeds_out: &mut [u32],
    dispatch: bool,
) -> Result<(), Error> {
    check_common(layout, tile, intensities, seeds_in, seeds_out)?;
    if tables.tile() != layout.tile() {
        return Err(Error::TileSize { tile: tables.tile() });
    }
    let params = layout.params(frame);
    let table = tables.table(step_index(frame, params.tile_log2));
    permute_checked(
        &params,
        intensities,
        tile.values(),
        table,
        seeds_in,
        seeds_out,
        dispatch,
    );
    Ok(())
}

/// Sorting + retargeting of the whole frame `params` (tile offset
/// `walk_offset(params.frame)`) with `table`, buffers already checked: the
/// CPU fast path where it applies (with the run-time instruction set when
/// `dispatch`), else [`permute_block`] per block. Identical output either way.
pub(crate) fn permute_checked<T: Intensity>(
    params: &FrameParams,
    intensities: &[T],
    tile: &[u32],
    table: RetargetTable<'_>,
    seeds_in: &[u32],
    seeds_out: &mut [u32],
    dispatch: bool,
) {
    let cached = crate::permutation::cpu::applies(params);
    if cached && dispatch {
        crate::permutation::cpu::permute_blocks_cached(params, intensities, tile, table, seeds_in, seeds_out);
    } else if cached {
        crate::permutation::cpu::permute_blocks_portable(
            params,
            intensities,
            tile,
            table,
            seeds_in,
            seeds_out,
        );
    } else {
        permute_blocks(params, intensities, tile, table, seeds_in, seeds_out);
    }
}

/// The general CPU path of [`permute_frame`] (any block and tile size; see
/// `permute_cpu` for the faster common case): [`permute_block`] per block.
fn permute_blocks<T: Intensity>(
    params: &FrameParams,
    intensities: &[T],
    tile: &[u32],
    table: RetargetTable<'_>,
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) {
    for by in 0..params.blocks_y() {
        for bx in 0..params.blocks_x() {
            permute_block(
                params,
                bx,
                by,
                intensities,
                tile,
                table.packed(),
                seeds_in,
                seeds_out,
            );
        }
    }
}

/// Sorting + retargeting of one block, fused: the reference sort
/// ([`sort_block`]) of its visible pixels, then every seed of the block
/// (padding included) goes straight to its retargeted place. The general CPU
/// path of [`permute_frame`], and the fast path's clipped edge blocks.
#[allow(clippy::too_many_arguments)]
pub(crate) fn permute_block<T: Intensity>(
    params: &FrameParams,
    bx: u32,
    by: u32,
    intensities: &[T],
    tile: &[u32],
    packed: &[u32],
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) {
    let offset = walk_offset(params.frame, params.tile_log2);
    let padded = UVec2::new(params.padded_width, params.padded_height);
    let mut keys = [0u32; MAX_BLOCK_PIXELS];
    let mut dither = [0u32; MAX_BLOCK_PIXELS];
    let mut seeds = [0u32; MAX_BLOCK_PIXELS];
    let mut pos = [UVec2::ZERO; MAX_BLOCK_PIXELS];
    let mut len = 0usize;
    let mut sorted = [0u32; MAX_BLOCK_PIXELS];
    let (x0, y0) = (bx * params.block, by * params.block);
    for y in y0..(y0 + params.block).min(params.padded_height) {
        for x in x0..(x0 + params.block).min(params.padded_width) {
            let p = UVec2::new(x, y);
            let s = seeds_in[(y * params.padded_width + x) as usize];
            if x < params.width && y < params.height {
                keys[len] = intensity_key(intensities[(y * params.width + x) as usize].intensity());
                dither[len] = tile[tile_texel(p, offset, params.tile_log2) as usize];
                seeds[len] = s;
                pos[len] = p;
                len += 1;
            } else {
                let d = retarget_destination(p, offset, params.tile_log2, packed, padded);
                seeds_out[(d.y * params.padded_width + d.x) as usize] = s;
            }
        }
    }
    sort_block(len as u32, &keys, &dither, &seeds, &mut sorted);
    for i in 0..len {
        let d = retarget_destination(pos[i], offset, params.tile_log2, packed, padded);
        seeds_out[(d.y * params.padded_width + d.x) as usize] = sorted[i];
    }
}
