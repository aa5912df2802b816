//! A study's fixed inputs: the scene, the reference, the flat insets (checked
//! geometrically) and the regions of the still camera's frame-0 G-buffer.

use super::config::StudyConfig;
use super::insets::{check_inset, inset_layout, max_gradient, Inset};
use super::reference::Reference;
use crate::metrics::regions::{classify_regions, Region};
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
        let mut insets = inset_layout(config.scene, config.size);
        let params = scene.trace_params(&config.settings(), 0)?;
        for inset in &mut insets {
            check_inset(&scene, &params, inset)?;
            inset.max_gradient = max_gradient(&reference.luma, config.size, inset);
        }
        let mut gbuffer = vec![GBufferGpu::default(); (config.size * config.size) as usize];
        cpu::gbuffer_frame(&scene, &params, &mut gbuffer)?;
        let regions = classify_regions(&gbuffer, config.size, config.size);
        Ok(Study {
            config,
            scene,
            reference,
            insets,
            regions,
            gbuffer,
        })
    }
}
