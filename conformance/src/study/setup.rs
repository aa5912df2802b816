//! A study's fixed inputs: the scene, the reference, the flat insets (checked
//! geometrically) and the regions of the still camera's frame-0 G-buffer.

use super::config::StudyConfig;
use super::insets::{check_inset, inset_layout, max_gradient, Inset};
use super::reference::Reference;
use super::regularization::RegularizationEffect;
use crate::metrics::regions::{classify_regions, Region};
use crate::metrics::surfaces::glossy_first_hits;
use anyhow::{ensure, Result};
use gpu_tracer::cpu;
use gpu_tracer::scene::SceneGpu;
use kernels::abi::GBufferGpu;
use std::path::Path;

/// The scene, reference and insets of one configuration.
#[derive(Debug)]
pub struct Study {
    /// The configuration.
    pub config: StudyConfig,
    /// The scene's buffers ([`StudyConfig::scene`]).
    pub scene: SceneGpu,
    /// The reference.
    pub reference: Reference,
    /// The flat insets, checked geometrically.
    pub insets: Vec<Inset>,
    /// The region of every pixel ([`crate::metrics::regions`]), from the frame-0 G-buffer.
    pub regions: Vec<Region>,
    /// The frame-0 G-buffer (centre rays; the camera does not move).
    pub gbuffer: Vec<GBufferGpu>,
    /// Per pixel, whether its first hit is glossy ([`crate::metrics::surfaces`]).
    pub glossy: Vec<bool>,
    /// With [`StudyConfig::modulate_by`]: per pixel, the albedo luma of that scene's
    /// primary hit over this scene's (1 where this scene's is below
    /// `sampler_core::features::surface::ALBEDO_FLOOR`).
    pub modulation: Option<Vec<f32>>,
    /// With [`StudyConfig::glossy_regularization`] above 0: its bias and its
    /// effect on white's noise, from the unbiased reference beside the
    /// regularised one ([`RegularizationEffect`]).
    pub regularization: Option<RegularizationEffect>,
}

/// The luma of `g`'s albedo, or `None` below
/// `sampler_core::features::surface::ALBEDO_FLOOR` (emitters, the sky, black
/// surfaces: nothing to divide by).
pub(crate) fn albedo_luma(g: &GBufferGpu) -> Option<f32> {
    let a = sampler_core::luma(g.albedo.truncate());
    (a >= sampler_core::features::surface::ALBEDO_FLOOR).then_some(a)
}

/// Per pixel, `luma(albedo of over) / luma(albedo of under)` (1 where `under`'s is
/// below `ALBEDO_FLOOR`).
fn albedo_ratio(over: &[GBufferGpu], under: &[GBufferGpu]) -> Vec<f32> {
    over.iter()
        .zip(under)
        .map(|(o, u)| albedo_luma(u).map_or(1.0, |a| sampler_core::luma(o.albedo.truncate()) / a))
        .collect()
}

impl Study {
    /// Builds the scene, renders or loads the reference and places the insets.
    ///
    /// # Errors
    /// Bad settings, or an inset that does not lie on its surface.
    pub fn new(
        config: StudyConfig,
        cache_dir: Option<&Path>,
        progress: impl FnMut(u32, u32),
    ) -> Result<Study> {
        ensure!(config.frames >= 1, "at least one frame");
        ensure!(config.size >= 32, "the insets need an image of at least 32x32");
        config.layout()?;
        let scene = SceneGpu::build(&config.scene.load()?)?;
        let reference = Reference::get(&scene, &config, cache_dir, progress)?;
        let unbiased = if config.glossy_regularization > 0.0 {
            let unbiased_config = StudyConfig {
                glossy_regularization: 0.0,
                ..config
            };
            Some(Reference::get(&scene, &unbiased_config, cache_dir, |_, _| {})?)
        } else {
            None
        };
        let mut insets = inset_layout(config.scene, config.size);
        let params = scene.trace_params(&config.settings(), 0)?;
        for inset in &mut insets {
            check_inset(&scene, &params, inset)?;
            inset.max_gradient = max_gradient(&reference.luma, config.size, inset);
        }
        let mut gbuffer = vec![GBufferGpu::default(); (config.size * config.size) as usize];
        cpu::gbuffer_frame(&scene, &params, &mut gbuffer)?;
        let regions = classify_regions(&gbuffer, config.size, config.size);
        let glossy = glossy_first_hits(&scene.materials, &gbuffer);
        let regularization = match &unbiased {
            Some(unbiased) => Some(RegularizationEffect::measure(
                config.glossy_regularization,
                &reference,
                unbiased,
                &regions,
            )?),
            None => None,
        };
        let modulation = match config.modulate_by {
            Some(other) => {
                ensure!(
                    other.camera_matches(config.scene),
                    "modulate_by: {} is not the room of {} seen by its camera (a scene and itself, or the \
                     textured box and its untextured twin)",
                    other.name(),
                    config.scene.name()
                );
                let other_scene = SceneGpu::build(&other.load()?)?;
                let other_params = other_scene.trace_params(&config.settings(), 0)?;
                let mut other_gbuffer = vec![GBufferGpu::default(); gbuffer.len()];
                cpu::gbuffer_frame(&other_scene, &other_params, &mut other_gbuffer)?;
                Some(albedo_ratio(&other_gbuffer, &gbuffer))
            }
            None => None,
        };
        Ok(Study {
            config,
            scene,
            reference,
            insets,
            regions,
            gbuffer,
            glossy,
            modulation,
            regularization,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

    #[test]
    fn albedo_ratio_is_one_over_dark_surfaces() {
        let at = |v: f32| GBufferGpu {
            albedo: Vec4::new(v, v, v, 0.0),
            ..GBufferGpu::default()
        };
        let over = [at(0.8), at(0.1), at(0.5)];
        let under = [at(0.4), at(0.4), at(0.0)];
        let r = albedo_ratio(&over, &under);
        assert!((r[0] - 2.0).abs() < 1e-5, "{r:?}");
        assert!((r[1] - 0.25).abs() < 1e-5, "{r:?}");
        // Black under (an emitter, the sky): left alone.
        assert_eq!(r[2], 1.0);
    }
}
