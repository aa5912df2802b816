//! The real-time filters on the GPU: the passes of `kernels::filter_entry`
//! over device-resident buffers, the same per-pixel functions and order as
//! [`crate::filter::FrameFilter`] on the CPU.

use super::context::Gpu;
use super::timer::PassTimer;
use super::GpuError;
use crate::filter::{FilterChain, FilterSettings};
use glam::{Vec2, Vec4};
use kernels::abi::GBufferGpu;
use kernels::filter_entry::{
    ATROUS_ENTRY, DEMODULATE_ENTRY, GAUSS_ENTRY, REMODULATE_ENTRY, TAA_ENTRY, VARIANCE_ENTRY,
};
use kernels::filters::atrous::ATROUS_ITERATIONS;
use kernels::filters::{FilterParams, FILTER_CLAMP, FILTER_HISTORY_VALID};

/// The six compute pipelines of the filters, created once per device.
#[derive(Debug)]
pub struct FilterPipelines {
    demodulate: wgpu::ComputePipeline,
    remodulate: wgpu::ComputePipeline,
    taa: wgpu::ComputePipeline,
    gauss: wgpu::ComputePipeline,
    variance: wgpu::ComputePipeline,
    atrous: wgpu::ComputePipeline,
}

impl FilterPipelines {
    /// Creates the pipelines from the kernels module.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if wgpu rejects one.
    pub fn new(gpu: &Gpu) -> Result<Self, GpuError> {
        Ok(FilterPipelines {
            demodulate: gpu.pipeline(DEMODULATE_ENTRY)?,
            remodulate: gpu.pipeline(REMODULATE_ENTRY)?,
            taa: gpu.pipeline(TAA_ENTRY)?,
            gauss: gpu.pipeline(GAUSS_ENTRY)?,
            variance: gpu.pipeline(VARIANCE_ENTRY)?,
            atrous: gpu.pipeline(ATROUS_ENTRY)?,
        })
    }
}

/// Which pipeline a step runs.
#[derive(Clone, Copy, Debug)]
enum Stage {
    Demodulate,
    Remodulate,
    Taa,
    Gauss,
    Variance,
    Atrous,
}

/// A filter chain on the device with its buffers and history.
///
/// Per frame: fill [`color`](Self::color), [`gbuffer`](Self::gbuffer) and
/// [`motion`](Self::motion) (by copies from the renderer's own buffers, or
/// [`upload`](Self::upload)), [`encode`](Self::encode), and read
/// [`output`](Self::output) (`width * height` `Vec4`, `w` = 1).
#[derive(Debug)]
pub struct FrameFilterGpu {
    chain: FilterChain,
    settings: FilterSettings,
    width: u32,
    height: u32,
    /// Input colour, linear RGB in `xyz`, `width * height` `Vec4`.
    pub color: wgpu::Buffer,
    /// Input G-buffer, `width * height` [`GBufferGpu`].
    pub gbuffer: wgpu::Buffer,
    /// Input backward motion, `width * height` `Vec2` (disoccluded pixels far
    /// outside the frame; zeros for a still camera).
    pub motion: wgpu::Buffer,
    output: wgpu::Buffer,
    taa_out: wgpu::Buffer,
    history: wgpu::Buffer,
    taa_params: wgpu::Buffer,
    steps: Vec<(Stage, wgpu::BindGroup)>,
    has_history: bool,
}

impl FrameFilterGpu {
    /// Allocates the buffers (about `16 * 6` bytes per pixel plus the
    /// G-buffer) and wires the passes of `chain`.
    ///
    /// # Errors
    /// [`GpuError::Filter`] for a zero size or a setting out of range.
    pub fn new(
        gpu: &Gpu,
        pipelines: &FilterPipelines,
        chain: FilterChain,
        settings: FilterSettings,
        width: u32,
        height: u32,
    ) -> Result<Self, GpuError> {
        if width == 0 || height == 0 {
            return Err(GpuError::Filter(crate::error::Error::FrameSize {
                width,
                height,
                padded_width: width,
            }));
        }
        settings.check().map_err(GpuError::Filter)?;
        let n = width as usize * height as usize;
        let base = FilterParams {
            width,
            height,
            ..Default::default()
        };
        let color = gpu.storage_zeroed::<Vec4>("filter colour", n);
        let gbuffer = gpu.storage_zeroed::<GBufferGpu>("filter G-buffer", n);
        let motion = gpu.storage_zeroed::<Vec2>("filter motion", n);
        let output = gpu.storage_zeroed::<Vec4>("filtered", n);
        let a = gpu.storage_zeroed::<Vec4>("filter ping", n);
        let b = gpu.storage_zeroed::<Vec4>("filter pong", n);
        let taa_out = gpu.storage_zeroed::<Vec4>("taa output", n);
        let history = gpu.storage_zeroed::<Vec4>("taa history", n);
        let params = gpu.uniform("filter params", &base);
        let taa_params = gpu.uniform("taa params", &taa_uniform(base, settings, false));
        let p = pipelines;
        let mut steps = Vec::new();
        match chain {
            FilterChain::None => {}
            FilterChain::Gauss => {
                for (axis, src, dst) in [(0u32, &color, &a), (1, &a, &output)] {
                    let u = gpu.uniform(
                        "gauss params",
                        &FilterParams {
                            weight: settings.sigma,
                            step: axis,
                            ..base
                        },
                    );
                    steps.push((Stage::Gauss, gpu.bind(&p.gauss, &[&u, src, dst])));
                }
            }
            _ => {
                steps.push((
                    Stage::Demodulate,
                    gpu.bind(&p.demodulate, &[&params, &color, &gbuffer, &a]),
                ));
                // `cur` holds the chain's current result.
                let mut cur = &a;
                if chain.temporal() {
                    steps.push((
                        Stage::Taa,
                        gpu.bind(&p.taa, &[&taa_params, &a, &history, &motion, &taa_out]),
                    ));
                    cur = &taa_out;
                }
                if chain.atrous() {
                    let (mut src, mut dst) = (&b, &a);
                    steps.push((
                        Stage::Variance,
                        gpu.bind(&p.variance, &[&params, cur, &gbuffer, src]),
                    ));
                    for it in 0..ATROUS_ITERATIONS {
                        let u = gpu.uniform(
                            "atrous params",
                            &FilterParams {
                                step: 1 << it,
                                ..base
                            },
                        );
                        steps.push((Stage::Atrous, gpu.bind(&p.atrous, &[&u, src, &gbuffer, dst])));
                        std::mem::swap(&mut src, &mut dst);
                    }
                    cur = src;
                }
                steps.push((
                    Stage::Remodulate,
                    gpu.bind(&p.remodulate, &[&params, cur, &gbuffer, &output]),
                ));
            }
        }
        Ok(FrameFilterGpu {
            chain,
            settings,
            width,
            height,
            color,
            gbuffer,
            motion,
            output,
            taa_out,
            history,
            taa_params,
            steps,
            has_history: false,
        })
    }

    /// The chain.
    pub fn chain(&self) -> FilterChain {
        self.chain
    }

    /// The filtered frame of the last [`encode`](Self::encode).
    pub fn output(&self) -> &wgpu::Buffer {
        if self.chain == FilterChain::None {
            &self.color
        } else {
            &self.output
        }
    }

    /// Forgets the history (a camera cut).
    pub fn reset(&mut self) {
        self.has_history = false;
    }

    /// Writes the inputs from the host.
    ///
    /// # Errors
    /// [`GpuError::Filter`] when a buffer is not `width * height` long.
    pub fn upload(
        &self,
        gpu: &Gpu,
        color: &[Vec4],
        gbuffer: &[GBufferGpu],
        motion: &[Vec2],
    ) -> Result<(), GpuError> {
        let n = self.width as usize * self.height as usize;
        crate::filter::check_inputs(n, color, gbuffer, motion).map_err(GpuError::Filter)?;
        gpu.queue
            .write_buffer(&self.color, 0, bytemuck::cast_slice(color));
        gpu.queue
            .write_buffer(&self.gbuffer, 0, bytemuck::cast_slice(gbuffer));
        gpu.queue
            .write_buffer(&self.motion, 0, bytemuck::cast_slice(motion));
        Ok(())
    }

    /// Encodes the chain's passes for the next frame (and the history copy),
    /// after writing this frame's TAA uniform. `timer` (if any, with its span
    /// index) times the passes as one span (not the history copy).
    pub fn encode(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        pipelines: &FilterPipelines,
        timer: Option<(&PassTimer, u32)>,
    ) {
        let base = FilterParams {
            width: self.width,
            height: self.height,
            ..Default::default()
        };
        let taa = taa_uniform(base, self.settings, self.has_history);
        gpu.queue
            .write_buffer(&self.taa_params, 0, bytemuck::bytes_of(&taa));
        if !self.steps.is_empty() {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("real-time filter"),
                timestamp_writes: timer.map(|(t, span)| t.writes(span)),
            });
            let (x, y) = kernels::permute_entry::linear_dispatch(self.width * self.height);
            for (stage, bind_group) in &self.steps {
                pass.set_pipeline(match stage {
                    Stage::Demodulate => &pipelines.demodulate,
                    Stage::Remodulate => &pipelines.remodulate,
                    Stage::Taa => &pipelines.taa,
                    Stage::Gauss => &pipelines.gauss,
                    Stage::Variance => &pipelines.variance,
                    Stage::Atrous => &pipelines.atrous,
                });
                pass.set_bind_group(0, bind_group, &[]);
                pass.dispatch_workgroups(x, y, 1);
            }
        }
        if self.chain.temporal() {
            let bytes = self.width as u64 * self.height as u64 * 16;
            encoder.copy_buffer_to_buffer(&self.taa_out, 0, &self.history, 0, bytes);
            self.has_history = true;
        }
    }

    /// Reads the filtered frame back (blocking).
    ///
    /// # Errors
    /// [`GpuError::Readback`].
    pub fn read_output(&self, gpu: &Gpu) -> Result<Vec<Vec4>, GpuError> {
        gpu.read(self.output(), self.width as usize * self.height as usize)
    }
}

/// The TAA pass's uniform: alpha, clamping, and whether the history holds a
/// frame.
fn taa_uniform(base: FilterParams, settings: FilterSettings, has_history: bool) -> FilterParams {
    FilterParams {
        weight: settings.alpha,
        flags: if has_history { FILTER_HISTORY_VALID } else { 0 }
            | if settings.clamp { FILTER_CLAMP } else { 0 },
        ..base
    }
}
