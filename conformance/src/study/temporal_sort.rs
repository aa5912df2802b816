//! A temporally blue sorting target for the seed permutation (issue 29, "a
//! temporally blue permutation"), CPU only: after frame `t` every block's
//! seeds are sorted so that their values rank like slice `t + 1` of a
//! spatiotemporal mask (STBN: blue in space and along time at every pixel),
//! read toroidally at an offset that moves once per cycle of the mask's slices
//! (`walk_offset(cycle)`). The sort targets the next slice directly, and
//! seeds never leave their block.
//!
//! [`render_temporal_permute`] adds what the walk's permutation has, and is
//! the tracer's `temporal` mode (`PermuteMode::Temporal`,
//! `sampler_core::permute_frame_temporal`): after sorting against slice
//! `t`, an exact radius-bounded retarget table between slices `t` and
//! `t + 1` (`sampler_core::defaults::temporal_target`, 64x64x64) moves seeds
//! across block borders, so a block's set of seeds changes over time (offset
//! 0, so the arrangement repeats every 64 frames).
//!
//! With fixed streams (`SEED_MODE_FIXED`) a block's values repeat every frame
//! and only their arrangement changes: each pixel takes, over frames, the
//! block's values in the order the mask's ranks give it, blue in time. With
//! advancing streams (`SEED_MODE_ADVANCE`) the values change every frame, so
//! the sort ranks on values that no longer hold. The study measures both
//! for the sort alone, and the temporal permutation with fixed streams.

use super::setup::Study;
use anyhow::Result;
use glam::Vec4;
use gpu_tracer::{cpu, PermuteMode, RenderJob, TileChoice};
use kernels::abi::{SEED_MODE_ADVANCE, SEED_MODE_FIXED};
use sampler_core::{sort_block_at_offset, walk_offset, FrameLayout, SpatiotemporalMask};

/// Side of the layout's tile for `mask`: its width, which must equal its height.
fn mask_side(mask: &SpatiotemporalMask<'_>) -> Result<u32> {
    anyhow::ensure!(
        mask.width() == mask.height(),
        "a temporal sorting target needs square slices, got {}x{}",
        mask.width(),
        mask.height()
    );
    Ok(mask.width())
}

/// Renders `study.config.frames` frames, sorting every block's seeds against
/// the next slice of `mask` after each (module docs), with the seeds' streams
/// fixed or advancing; calls `on_frame(t, colour)` for each frame.
///
/// # Errors
/// Rendering errors; a mask whose slices are not square.
pub fn render_temporal_sort(
    study: &Study,
    mask: SpatiotemporalMask<'_>,
    advance: bool,
    on_frame: &mut impl FnMut(u32, &[Vec4]),
) -> Result<()> {
    let mode = if advance {
        SEED_MODE_ADVANCE
    } else {
        SEED_MODE_FIXED
    };
    let (layout, settings, slices) = setup(study, &mask, mode)?;
    let depth = mask.depth();
    let params = layout.params(0);
    run_frames(study, &layout, &settings, on_frame, |t, color, seeds, next| {
        let target = t + 1;
        let offset = walk_offset(target / depth, params.tile_log2);
        let slice = &slices[(target % depth) as usize];
        next.copy_from_slice(seeds);
        for by in 0..params.blocks_y() {
            for bx in 0..params.blocks_x() {
                sort_block_at_offset(&params, offset, bx, by, color, slice, seeds, next);
            }
        }
    })
}

/// The frame loop of the temporal rows: white seeds from the study's salt,
/// then for every frame render, report, and let `step(t, colour, seeds,
/// next)` write the next frame's seeds.
fn run_frames(
    study: &Study,
    layout: &FrameLayout,
    settings: &gpu_tracer::TraceSettings,
    on_frame: &mut impl FnMut(u32, &[Vec4]),
    mut step: impl FnMut(u32, &[Vec4], &[u32], &mut [u32]),
) -> Result<()> {
    let c = &study.config;
    let mut seeds = cpu::white_seeds(layout.padded_width(), layout.padded_height(), c.salt);
    let mut next = seeds.clone();
    let mut color = vec![Vec4::ZERO; layout.pixel_count()];
    for t in 0..c.frames {
        let trace = study.scene.trace_params(settings, t)?;
        cpu::render_frame(&study.scene, &trace, &seeds, &mut color)?;
        on_frame(t, &color);
        step(t, &color, &seeds, &mut next);
        std::mem::swap(&mut seeds, &mut next);
    }
    Ok(())
}

/// The layout (tiles of the mask's side), trace settings (seed mode `seed_mode`)
/// and slice ranks of a temporal row.
fn setup(
    study: &Study,
    mask: &SpatiotemporalMask<'_>,
    seed_mode: u32,
) -> Result<(FrameLayout, gpu_tracer::TraceSettings, Vec<Vec<u32>>)> {
    let c = &study.config;
    let side = mask_side(mask)?;
    let layout = FrameLayout::new(c.size, c.size, c.block, side)?;
    let mut settings = c.settings();
    settings.seed_mode = seed_mode;
    settings.padded_width = layout.padded_width();
    Ok((layout, settings, slice_ranks(mask)))
}

/// The ranks of every slice of `mask`, slice-major.
fn slice_ranks(mask: &SpatiotemporalMask<'_>) -> Vec<Vec<u32>> {
    (0..mask.depth())
        .map(|z| sampler_core::bake::slice_ranks(mask, z))
        .collect()
}

/// Renders `study.config.frames` frames with fixed streams in the tracer's
/// temporal mode (128 tile, the default mask's slice tables): sorting every
/// block against slice `t mod 64` and retargeting to slice `t + 1` after
/// frame `t` (module docs); calls `on_frame(t, colour)` for each frame.
/// `sampler` is the trace settings' sampler (`kernels::abi::SAMPLER_SEEDS`,
/// or an a-priori sampler's jitter with `SAMPLER_JITTER_ONLY`).
///
/// # Errors
/// Rendering errors, a sampler the temporal mode refuses.
pub fn render_temporal_permute(
    study: &Study,
    sampler: u32,
    on_frame: &mut impl FnMut(u32, &[Vec4]),
) -> Result<()> {
    let c = &study.config;
    let mut settings = c.settings();
    settings.seed_mode = SEED_MODE_FIXED;
    settings.sampler = sampler;
    let job = RenderJob {
        settings,
        frames: c.frames,
        mode: PermuteMode::Temporal,
        block: c.block,
        tile: TileChoice::TEMPORAL,
        salt: c.salt,
    };
    gpu_tracer::render_cpu(&study.scene, &job, on_frame)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_stbn_mask_has_square_slices_of_a_tile_side() {
        let mask = sampler_core::defaults::stbn_128();
        assert_eq!(mask_side(&mask).unwrap(), 128);
        assert!(FrameLayout::new(100, 60, 4, 128).is_ok());
    }
}
