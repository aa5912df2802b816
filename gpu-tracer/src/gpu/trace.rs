//! The path-tracing and accumulation passes on the GPU.

use super::context::{groups, Gpu};
use super::timer::PassTimer;
use super::GpuError;
use crate::scene::SceneGpu;
use glam::Vec4;
use kernels::abi::{TraceParams, ACCUMULATE_ENTRY, TRACE_ENTRY, TRACE_WORKGROUP};

/// The trace and accumulate pipelines, created once per device.
#[derive(Debug)]
pub struct TracePipelines {
    trace: wgpu::ComputePipeline,
    accumulate: wgpu::ComputePipeline,
}

impl TracePipelines {
    /// Creates both pipelines from the kernels module.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if wgpu rejects one.
    pub fn new(gpu: &Gpu) -> Result<Self, GpuError> {
        Ok(TracePipelines {
            trace: gpu.pipeline(TRACE_ENTRY)?,
            accumulate: gpu.pipeline(ACCUMULATE_ENTRY)?,
        })
    }
}

/// A scene uploaded to the device with its frame buffers: the colour of the
/// current frame and the running mean, `width * height` `Vec4` each.
#[derive(Debug)]
pub struct Tracer {
    width: u32,
    height: u32,
    params: wgpu::Buffer,
    /// Colour of the last traced frame (`w` = 1), `width * height`.
    pub color: wgpu::Buffer,
    /// Running mean of all accumulated frames, `width * height`.
    pub accum: wgpu::Buffer,
    trace_bg: wgpu::BindGroup,
    accumulate_bg: wgpu::BindGroup,
}

impl Tracer {
    /// Uploads `scene` and the screen-space Sobol keys
    /// (`sampler_core::defaults::screen_sobol_keys()`, binding 7, read by
    /// the screen-sobol sampler; [`crate::SceneGpu::trace_params`] writes
    /// their layout into the parameters) and allocates the accumulation
    /// buffer for `params`' size. `seeds` is the seed buffer the trace pass reads
    /// (`params.padded_width` wide); `color` (from [`Tracer::color_buffer`])
    /// receives each frame.
    pub fn new(
        gpu: &Gpu,
        pipelines: &TracePipelines,
        scene: &SceneGpu,
        params: &TraceParams,
        seeds: &wgpu::Buffer,
        color: wgpu::Buffer,
    ) -> Self {
        let n = (params.width * params.height) as usize;
        let params_buf = gpu.uniform("trace params", params);
        let nodes = gpu.storage("bvh nodes", &scene.nodes);
        let triangles = gpu.storage("triangles", &scene.triangles);
        let materials = gpu.storage("materials", &scene.materials);
        let emitters = gpu.storage("emitters", &scene.emitters);
        let keys = gpu.storage(
            "screen-space sobol keys",
            sampler_core::defaults::screen_sobol_keys().keys(),
        );
        let accum = gpu.storage_zeroed::<Vec4>("accumulation", n);
        let trace_bg = gpu.bind(
            &pipelines.trace,
            &[
                &params_buf,
                &nodes,
                &triangles,
                &materials,
                &emitters,
                seeds,
                &color,
                &keys,
            ],
        );
        let accumulate_bg = gpu.bind(&pipelines.accumulate, &[&params_buf, &color, &accum]);
        Tracer {
            width: params.width,
            height: params.height,
            params: params_buf,
            color,
            accum,
            trace_bg,
            accumulate_bg,
        }
    }

    /// A frame colour buffer for a `width x height` frame, to pass to
    /// [`Tracer::new`] (and to the permutation's intensity pass).
    pub fn color_buffer(gpu: &Gpu, width: u32, height: u32) -> wgpu::Buffer {
        gpu.storage_zeroed::<Vec4>("frame colour", (width * height) as usize)
    }

    /// Writes the parameters of the next submission (frame index etc.).
    pub fn set_params(&self, gpu: &Gpu, params: &TraceParams) {
        gpu.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(params));
    }

    /// Encodes the trace pass (optionally timed as `timer` span `span`).
    pub fn encode_trace(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipelines: &TracePipelines,
        timer: Option<(&PassTimer, u32)>,
    ) {
        self.encode(encoder, &pipelines.trace, &self.trace_bg, timer);
    }

    /// Encodes the accumulation of the current colour into the running mean.
    pub fn encode_accumulate(&self, encoder: &mut wgpu::CommandEncoder, pipelines: &TracePipelines) {
        self.encode(encoder, &pipelines.accumulate, &self.accumulate_bg, None);
    }

    fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipeline: &wgpu::ComputePipeline,
        bind_group: &wgpu::BindGroup,
        timer: Option<(&PassTimer, u32)>,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: None,
            timestamp_writes: timer.map(|(t, span)| t.writes(span)),
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.dispatch_workgroups(
            groups(self.width, TRACE_WORKGROUP.0),
            groups(self.height, TRACE_WORKGROUP.1),
            1,
        );
    }

    /// Reads the last frame's colour back (blocking).
    ///
    /// # Errors
    /// [`GpuError::Readback`].
    pub fn read_color(&self, gpu: &Gpu) -> Result<Vec<Vec4>, GpuError> {
        gpu.read(&self.color, (self.width * self.height) as usize)
    }

    /// Reads the running mean back (blocking).
    ///
    /// # Errors
    /// [`GpuError::Readback`].
    pub fn read_accum(&self, gpu: &Gpu) -> Result<Vec<Vec4>, GpuError> {
        gpu.read(&self.accum, (self.width * self.height) as usize)
    }
}
