//! The frame loops of the static study that `gpu_tracer::render_cpu` does not cover:
//! the permutation with an explicit tile offset (the fixed-step comparison) and the
//! blue-noise-dither baseline (see [`crate::study`], "The fixed-step comparison"
//! and "The blue-noise-dither baseline").

use super::setup::Study;
use anyhow::Result;
use glam::{UVec2, Vec2, Vec4};
use gpu_tracer::cpu;
use kernels::abi::{TraceParams, SEED_MODE_BLUE_NOISE_DITHER, SEED_MODE_FIXED};
use rayon::prelude::*;
use sampler_core::{
    retarget_pixel_at_offset, sort_block_at_offset, walk_offset, DitherTile, FrameLayout, Intensity,
    RetargetTable, SpatiotemporalMask,
};

/// Offset sequence of the dither tile.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Walk {
    /// The aperiodic R2 walk (`sampler_core::walk_offset`), table per step.
    R2,
    /// `o_t = t * base_step mod W`, always table 0.
    FixedStep,
}

impl Walk {
    /// Offset of frame `t` and the index of the retarget table for the step after it.
    pub fn offset_and_table(self, t: u32, tile_log2: u32) -> (UVec2, u32) {
        match self {
            Walk::R2 => (walk_offset(t, tile_log2), sampler_core::step_index(t, tile_log2)),
            Walk::FixedStep => {
                let mask = (1u32 << tile_log2) - 1;
                let step = sampler_core::sequences::walk::base_step(tile_log2);
                (
                    UVec2::new(t.wrapping_mul(step.x) & mask, t.wrapping_mul(step.y) & mask),
                    0,
                )
            }
        }
    }
}

/// One permutation step with an explicit tile offset: sorting pass against
/// `tile[(p + offset) mod W]` in every block, then the retargeting scatter with `table`
/// read at `(p + offset) mod W`. Same conventions and tie-breaking as
/// `sampler_core::permute_frame`: `sampler_core::sort_block_at_offset` per block,
/// then `sampler_core::retarget_pixel_at_offset` per seed.
///
/// # Panics
/// If a buffer does not match `layout`.
pub fn permute_with_offset<T: Intensity>(
    layout: &FrameLayout,
    offset: UVec2,
    intensities: &[T],
    tile: &DitherTile<'_>,
    table: RetargetTable<'_>,
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) {
    let p = layout.params(0);
    assert_eq!(seeds_in.len(), layout.seed_count());
    assert_eq!(seeds_out.len(), layout.seed_count());
    assert_eq!(intensities.len(), layout.pixel_count());
    let mut sorted = seeds_in.to_vec();
    for by in 0..p.blocks_y() {
        for bx in 0..p.blocks_x() {
            sort_block_at_offset(
                &p,
                offset,
                bx,
                by,
                intensities,
                tile.values(),
                seeds_in,
                &mut sorted,
            );
        }
    }
    for i in 0..p.seed_count() {
        retarget_pixel_at_offset(&p, offset, i, table.packed(), &sorted, seeds_out);
    }
}

/// Renders `study.config.frames` frames permuting with `walk` (CPU), calling
/// `on_frame(t, colour)` for each.
///
/// # Errors
/// Rendering errors.
pub fn render_walk(study: &Study, walk: Walk, on_frame: &mut impl FnMut(u32, &[Vec4])) -> Result<()> {
    let c = &study.config;
    let layout = c.layout()?;
    let (tile, tables) = c.tile.load();
    let mut settings = c.settings();
    settings.padded_width = layout.padded_width();
    let mut seeds = cpu::white_seeds(layout.padded_width(), layout.padded_height(), c.salt);
    let mut next = vec![0u32; seeds.len()];
    let mut color = vec![Vec4::ZERO; layout.pixel_count()];
    for t in 0..c.frames {
        let params = study.scene.trace_params(&settings, t)?;
        cpu::render_frame(&study.scene, &params, &seeds, &mut color)?;
        on_frame(t, &color);
        let (offset, table) = walk.offset_and_table(t, tile.tile_log2());
        permute_with_offset(
            &layout,
            offset,
            &color,
            &tile,
            tables.table(table),
            &seeds,
            &mut next,
        );
        std::mem::swap(&mut seeds, &mut next);
    }
    Ok(())
}

/// The blue-noise-dither baseline (module docs) with `mask` (128x128x64: the
/// STBN default or the filter-adapted one), CPU only.
///
/// # Errors
/// Rendering errors.
pub fn render_dither(
    study: &Study,
    mask: SpatiotemporalMask<'_>,
    on_frame: &mut impl FnMut(u32, &[Vec4]),
) -> Result<()> {
    let c = &study.config;
    let mut settings = c.settings();
    settings.seed_mode = SEED_MODE_FIXED;
    let layout = c.layout()?;
    settings.padded_width = layout.padded_width();
    let (w, pw) = (c.size, layout.padded_width());
    let mut color = vec![Vec4::ZERO; layout.pixel_count()];
    let scene = &study.scene;
    for t in 0..c.frames {
        // The host's settings only accept the modes the GPU implements; the dither mode
        // is set on the kernel parameters directly.
        let params = TraceParams {
            seed_mode: SEED_MODE_BLUE_NOISE_DITHER,
            ..scene.trace_params(&settings, t)?
        };
        // The same seeds as the white run's frame t (`sampler_core::frame_salt`).
        let seeds = cpu::white_seeds(pw, layout.padded_height(), sampler_core::frame_salt(c.salt, t));
        let z = t % mask.depth();
        color.par_chunks_mut(w as usize).enumerate().for_each(|(y, row)| {
            let y = y as u32;
            for (x, out) in row.iter_mut().enumerate() {
                let x = x as u32;
                let dither = Vec2::new(mask.value(x, y, z), mask.value(x + 64, y + 64, z));
                *out = kernels::dither::trace_pixel_dithered(
                    &params,
                    UVec2::new(x, y),
                    seeds[(y * pw + x) as usize],
                    dither,
                    &scene.nodes,
                    &scene.triangles,
                    &scene.materials,
                    &scene.emitters,
                    &scene.attrs,
                    &scene.images,
                    &scene.environment,
                );
            }
        });
        on_frame(t, &color);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use gpu_tracer::TileChoice;

    #[test]
    fn fixed_step_repeats_every_16_frames_and_r2_does_not() {
        let fixed: Vec<UVec2> = (0..40)
            .map(|t| Walk::FixedStep.offset_and_table(t, 6).0)
            .collect();
        assert_eq!(fixed[1], UVec2::new(48, 36));
        assert_eq!(fixed[16], UVec2::ZERO);
        assert_eq!(fixed[17], fixed[1]);
        let distinct: std::collections::HashSet<_> = fixed.iter().collect();
        assert_eq!(distinct.len(), 16);
        let r2: std::collections::HashSet<_> = (0..64).map(|t| Walk::R2.offset_and_table(t, 6).0).collect();
        assert!(r2.len() > 60, "{}", r2.len());
    }

    #[test]
    fn permute_with_r2_offsets_equals_permute_frame() {
        let layout = FrameLayout::new(70, 45, 4, 64).unwrap();
        let (tile, tables) = TileChoice::Tile64.load();
        let image: Vec<f32> = (0..layout.pixel_count())
            .map(|i| sampler_core::random_f32(i as u32, 99))
            .collect();
        let seeds: Vec<u32> = (0..layout.seed_count() as u32).map(|i| i * 7 + 3).collect();
        for t in [0u32, 1, 5, 17, 63] {
            let mut want = vec![0; seeds.len()];
            sampler_core::permute_frame(&layout, t, &image, &tile, &tables, &seeds, &mut want).unwrap();
            let (o, k) = Walk::R2.offset_and_table(t, 6);
            let mut got = vec![0; seeds.len()];
            permute_with_offset(&layout, o, &image, &tile, tables.table(k), &seeds, &mut got);
            assert_eq!(got, want, "frame {t}");
        }
    }
}
