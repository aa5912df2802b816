//! What the feature-aware permutation treats differently from the plain one, and how
//! often a permuting row gives a pixel a seed it already had.
//!
//! [`FeatureDiagnostics`] (from `Study::feature_diagnostics`) and the seed mirror
//! `SeedTracker`.

use super::method::Method;
use super::setup::Study;
use crate::metrics::regions::Region;
use anyhow::{ensure, Result};
use glam::Vec4;
use gpu_tracer::cpu;
use kernels::surface_features::surface_feature;
use sampler_core::features::permute::{block_groups, retarget_index};
use sampler_core::features::surface::edge_is_cut;
use sampler_core::{
    step_index, walk_offset, FeatureThresholds, FrameLayout, SurfaceFeature, MAX_BLOCK_PIXELS,
};

/// How much of the frame the feature-aware permutation treats differently from the
/// plain one, from the still camera's G-buffer with `FeatureThresholds::DEFAULT`
/// (the features do not change between frames; the retarget table and tile offset do).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FeatureDiagnostics {
    /// Fraction of sorting blocks (with a visible pixel) holding more than one group.
    pub split_blocks: f64,
    /// Fraction of visible pixels in such blocks.
    pub pixels_in_split_blocks: f64,
    /// Mean number of groups of a split block.
    pub groups_per_split_block: f64,
    /// Fraction of retarget moves (`p -> table(p)`, all seeds, mean over the study's
    /// frames) that are cut (not [`sampler_core::same_surface`], or padding / visible).
    pub cut_moves: f64,
    /// Fraction of retarget moves that stay in place (the table's fixed points).
    pub fixed_moves: f64,
    /// Per region ([`Region::ALL`] order): fraction of its pixels in split blocks.
    pub split_by_region: [f64; 3],
    /// Per region: fraction of the moves out of its pixels that are cut (mean over
    /// frames).
    pub cut_by_region: [f64; 3],
    /// Surface ids whose visible pixels have more than one albedo (where the
    /// demodulated key can order a group's pixels differently from the raw key; with
    /// none, demodulation only rescales each group's keys and the sort is the same).
    pub ids_with_varying_albedo: usize,
}

impl Study {
    /// The feature diagnostics of this frame (see [`FeatureDiagnostics`]).
    ///
    /// # Errors
    /// Bad layout.
    pub fn feature_diagnostics(&self) -> Result<FeatureDiagnostics> {
        let layout = self.config.layout()?;
        let features: Vec<SurfaceFeature> = self.gbuffer.iter().map(surface_feature).collect();
        let thresholds = FeatureThresholds::DEFAULT;
        let params = layout.params(0);
        let mut d = FeatureDiagnostics::default();
        let (mut blocks, mut split, mut groups_total, mut split_pixels) = (0u64, 0u64, 0u64, 0u64);
        for by in 0..params.blocks_y() {
            for bx in 0..params.blocks_x() {
                let mut feats = [SurfaceFeature::default(); MAX_BLOCK_PIXELS];
                let mut len = 0usize;
                for y in by * params.block..((by + 1) * params.block).min(params.height) {
                    for x in bx * params.block..((bx + 1) * params.block).min(params.width) {
                        feats[len] = features[(y * params.width + x) as usize];
                        len += 1;
                    }
                }
                if len == 0 {
                    continue;
                }
                blocks += 1;
                let mut groups = [0u32; MAX_BLOCK_PIXELS];
                block_groups(len as u32, &feats, &thresholds, &mut groups);
                let count = (0..len).filter(|&i| groups[i] == i as u32).count() as u64;
                if count > 1 {
                    split += 1;
                    groups_total += count;
                    split_pixels += len as u64;
                    for y in by * params.block..((by + 1) * params.block).min(params.height) {
                        for x in bx * params.block..((bx + 1) * params.block).min(params.width) {
                            let r = self.regions[(y * params.width + x) as usize] as usize;
                            d.split_by_region[r] += 1.0;
                        }
                    }
                }
            }
        }
        d.split_blocks = split as f64 / blocks.max(1) as f64;
        d.pixels_in_split_blocks = split_pixels as f64 / params.pixel_count() as f64;
        d.groups_per_split_block = groups_total as f64 / split.max(1) as f64;
        let (_, tables) = self.config.tile.load();
        let region_pixels =
            Region::ALL.map(|r| self.regions.iter().filter(|&&x| x == r).count().max(1) as f64);
        for (v, n) in d.split_by_region.iter_mut().zip(region_pixels) {
            *v /= n;
        }
        let (mut cut, mut fixed, mut moves) = (0u64, 0u64, 0u64);
        for t in 0..self.config.frames {
            let params = layout.params(t);
            let offset = walk_offset(t, params.tile_log2);
            let table = tables.table(step_index(t, params.tile_log2)).packed();
            for p in 0..params.seed_count() {
                let q = retarget_index(&params, offset, table, p);
                moves += 1;
                fixed += u64::from(q == p);
                let is_cut = edge_is_cut(&params, &features, &thresholds, p, q);
                cut += u64::from(is_cut);
                let (x, y) = (p % params.padded_width, p / params.padded_width);
                if is_cut && x < params.width && y < params.height {
                    d.cut_by_region[self.regions[(y * params.width + x) as usize] as usize] += 1.0;
                }
            }
        }
        for (v, n) in d.cut_by_region.iter_mut().zip(region_pixels) {
            *v /= n * f64::from(self.config.frames);
        }
        let mut albedo: std::collections::HashMap<u32, Vec<[u32; 3]>> = std::collections::HashMap::new();
        for g in self
            .gbuffer
            .iter()
            .filter(|g| g.ids.w & kernels::abi::GBUFFER_HIT != 0)
        {
            let a = [g.albedo.x.to_bits(), g.albedo.y.to_bits(), g.albedo.z.to_bits()];
            let seen = albedo.entry(g.ids.x).or_default();
            if !seen.contains(&a) {
                seen.push(a);
            }
        }
        d.ids_with_varying_albedo = albedo.values().filter(|v| v.len() > 1).count();
        d.cut_moves = cut as f64 / moves.max(1) as f64;
        d.fixed_moves = fixed as f64 / moves.max(1) as f64;
        Ok(d)
    }
}

/// Mirrors the seeds of a permuting row from its frames (the same library calls as the
/// tracer's CPU loop) and records every visible pixel's seed per frame
/// ([`MethodRun::seed_repeats`](super::result::MethodRun::seed_repeats)). Frame 1 is
/// re-traced from the mirrored seeds and must match the renderer's frame bit for bit.
pub(crate) struct SeedTracker {
    method: Method,
    layout: FrameLayout,
    seeds: Vec<u32>,
    next: Vec<u32>,
    sorted: Vec<u32>,
    sources: Vec<u32>,
    features: Vec<SurfaceFeature>,
    /// `history[pixel * frames + t]`.
    history: Vec<u32>,
    frames: usize,
}

impl SeedTracker {
    pub(crate) fn new(study: &Study, method: Method) -> Result<Option<SeedTracker>> {
        if !matches!(
            method,
            Method::Permute | Method::PermuteJitter | Method::FeaturePermute | Method::FeaturePermuteJitter
        ) {
            return Ok(None);
        }
        let c = &study.config;
        let layout = c.layout()?;
        let seeds = cpu::white_seeds(layout.padded_width(), layout.padded_height(), c.salt);
        let n = seeds.len();
        Ok(Some(SeedTracker {
            method,
            layout,
            next: vec![0; n],
            sorted: vec![0; n],
            sources: vec![0; n],
            seeds,
            features: study.gbuffer.iter().map(surface_feature).collect(),
            history: vec![0; (c.size * c.size * c.frames) as usize],
            frames: c.frames as usize,
        }))
    }

    pub(crate) fn frame(&mut self, study: &Study, t: u32, color: &[Vec4]) -> Result<()> {
        let (w, pw) = (self.layout.width() as usize, self.layout.padded_width() as usize);
        for (i, _) in color.iter().enumerate() {
            self.history[i * self.frames + t as usize] = self.seeds[(i / w) * pw + i % w];
        }
        if t == 1 {
            let mut settings = study.config.settings();
            settings.padded_width = self.layout.padded_width();
            settings.sampler = self.method.jitter_sampler();
            let params = study.scene.trace_params(&settings, t)?;
            let mut check = vec![Vec4::ZERO; color.len()];
            cpu::render_frame(&study.scene, &params, &self.seeds, &mut check)?;
            ensure!(
                check == color,
                "{}: the mirrored seeds do not reproduce frame 1",
                self.method.name()
            );
        }
        let (tile, tables) = study.config.tile.load();
        if matches!(self.method, Method::FeaturePermute | Method::FeaturePermuteJitter) {
            let keys: Vec<f32> = color
                .iter()
                .zip(&study.gbuffer)
                .map(|(c, g)| kernels::surface_features::demodulated_intensity(*c, g))
                .collect();
            sampler_core::permute_frame_features(
                &self.layout,
                t,
                &keys,
                &self.features,
                &FeatureThresholds::DEFAULT,
                &tile,
                &tables,
                &self.seeds,
                &mut self.sorted,
                &mut self.sources,
                &mut self.next,
            )?;
        } else {
            sampler_core::permute_frame(
                &self.layout,
                t,
                color,
                &tile,
                &tables,
                &self.seeds,
                &mut self.next,
            )?;
        }
        std::mem::swap(&mut self.seeds, &mut self.next);
        Ok(())
    }

    /// Per region, the fraction of (pixel, frame) pairs with a seed seen before.
    pub(crate) fn repeats(&self, regions: &[Region]) -> [f64; 3] {
        let (mut rep, mut all) = ([0u64; 3], [0u64; 3]);
        for (i, r) in regions.iter().enumerate() {
            let mut v = self.history[i * self.frames..(i + 1) * self.frames].to_vec();
            v.sort_unstable();
            v.dedup();
            rep[*r as usize] += (self.frames - v.len()) as u64;
            all[*r as usize] += self.frames as u64;
        }
        [0, 1, 2].map(|k| rep[k] as f64 / all[k].max(1) as f64)
    }
}
