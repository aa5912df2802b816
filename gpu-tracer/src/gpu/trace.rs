//! The path-tracing, G-buffer and accumulation passes on the GPU.

use super::context::{groups, Gpu, LazyPipeline};
use super::timer::PassTimer;
use super::GpuError;
use crate::scene::{SceneGpu, TraceVariant};
use glam::{UVec2, Vec4};
use kernels::abi::{
    GBufferGpu, TraceParams, ACCUMULATE_ENTRY, FEATURES_ENTRY, GBUFFER_ENTRY, GBUFFER_UNTEXTURED_ENTRY,
    MOTION_ENTRY, PAN_OFFSET_ENTRY, RIGID_COUNT_ENTRY, TRACE_BASIC_ENTRY, TRACE_ENTRY,
    TRACE_UNTEXTURED_ENTRY, TRACE_WORKGROUP,
};
use kernels::pan_offset::{FRAME_CLEARED_WORDS, FRAME_MOTION_WORDS, FRAME_OFFSET_X, FRAME_OFFSET_Y};

// The pan offset's two words are copied as one block into the parameters:
// adjacent in both, at offsets a buffer copy may use (multiples of 4).
const _: () = assert!(FRAME_OFFSET_Y == FRAME_OFFSET_X + 1);
const _: () = assert!(
    std::mem::offset_of!(TraceParams, sampler_offset_y)
        == std::mem::offset_of!(TraceParams, sampler_offset_x) + 4
);
const _: () = assert!(std::mem::offset_of!(TraceParams, sampler_offset_x) % 4 == 0);

/// The trace, G-buffer and accumulate pipelines, created once per device.
/// The trace kernel's variants (`kernels::trace_variant`) share one
/// bind group layout and are compiled on first use: a run of plain scenes
/// never pays for the full kernel's compilation (seconds on lavapipe).
#[derive(Debug)]
pub struct TracePipelines {
    /// Bind group layout of both trace variants (the bindings of
    /// `kernels::abi::TRACE_ENTRY`).
    trace_group: wgpu::BindGroupLayout,
    trace: LazyPipeline,
    trace_basic: LazyPipeline,
    trace_untextured: LazyPipeline,
    /// Bind group layout of both G-buffer variants.
    gbuffer_group: wgpu::BindGroupLayout,
    gbuffer: LazyPipeline,
    gbuffer_untextured: LazyPipeline,
    motion: wgpu::ComputePipeline,
    rigid_count: wgpu::ComputePipeline,
    pan_offset: wgpu::ComputePipeline,
    features: wgpu::ComputePipeline,
    accumulate: wgpu::ComputePipeline,
}

impl TracePipelines {
    /// Creates the pipelines from the kernels module (the trace variants
    /// when first asked for, [`TracePipelines::trace`]).
    ///
    /// # Errors
    /// [`GpuError::Validation`] if wgpu rejects one.
    pub fn new(gpu: &Gpu) -> Result<Self, GpuError> {
        // Bindings 1-10 (kernels::abi): only the colour (6) is written.
        let mut writable = [false; 10];
        writable[5] = true;
        let (trace_group, layout) = gpu.buffer_layout("trace", &writable);
        // G-buffer bindings 1-7: only the G-buffer (7) is written.
        let (gbuffer_group, gbuffer_layout) =
            gpu.buffer_layout("g-buffer", &[false, false, false, false, false, false, true]);
        Ok(TracePipelines {
            trace_group,
            trace: gpu.lazy_pipeline(TRACE_ENTRY, &layout),
            trace_basic: gpu.lazy_pipeline(TRACE_BASIC_ENTRY, &layout),
            trace_untextured: gpu.lazy_pipeline(TRACE_UNTEXTURED_ENTRY, &layout),
            gbuffer_group,
            gbuffer: gpu.lazy_pipeline(GBUFFER_ENTRY, &gbuffer_layout),
            gbuffer_untextured: gpu.lazy_pipeline(GBUFFER_UNTEXTURED_ENTRY, &gbuffer_layout),
            motion: gpu.pipeline(MOTION_ENTRY)?,
            rigid_count: gpu.pipeline(RIGID_COUNT_ENTRY)?,
            pan_offset: gpu.pipeline(PAN_OFFSET_ENTRY)?,
            features: gpu.pipeline(FEATURES_ENTRY)?,
            accumulate: gpu.pipeline(ACCUMULATE_ENTRY)?,
        })
    }

    /// The trace pipeline of `variant`, compiled now if it has not been.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if wgpu rejects it.
    pub fn trace(&self, variant: TraceVariant) -> Result<&wgpu::ComputePipeline, GpuError> {
        match variant {
            TraceVariant::Full => self.trace.get(),
            TraceVariant::Basic => self.trace_basic.get(),
            TraceVariant::Untextured => self.trace_untextured.get(),
        }
    }

    /// The G-buffer pipeline for scenes of trace `variant`: without texture
    /// lookups unless `variant` is [`TraceVariant::Full`]; compiled now if
    /// it has not been.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if wgpu rejects it.
    pub fn gbuffer(&self, variant: TraceVariant) -> Result<&wgpu::ComputePipeline, GpuError> {
        match variant {
            TraceVariant::Full => self.gbuffer.get(),
            TraceVariant::Basic | TraceVariant::Untextured => self.gbuffer_untextured.get(),
        }
    }
}

/// The scene's buffers on the device.
#[derive(Debug)]
struct SceneBuffers {
    nodes: wgpu::Buffer,
    triangles: wgpu::Buffer,
    materials: wgpu::Buffer,
    emitters: wgpu::Buffer,
    attrs: wgpu::Buffer,
    images: wgpu::Buffer,
    previous: wgpu::Buffer,
    /// The environment map's table and texels (binding 10 of the trace pass).
    environment: wgpu::Buffer,
    /// Element counts, to tell whether an update fits the buffers.
    counts: [usize; 8],
}

impl SceneBuffers {
    fn counts(scene: &SceneGpu) -> [usize; 8] {
        [
            scene.nodes.len(),
            scene.triangles.len(),
            scene.materials.len(),
            scene.emitters.len(),
            scene.attrs.len(),
            scene.images.len(),
            scene.previous.len(),
            scene.environment.len(),
        ]
    }

    fn upload(gpu: &Gpu, scene: &SceneGpu) -> Self {
        SceneBuffers {
            nodes: gpu.storage("bvh nodes", &scene.nodes),
            triangles: gpu.storage("triangles", &scene.triangles),
            materials: gpu.storage("materials", &scene.materials),
            emitters: gpu.storage("emitters", &scene.emitters),
            attrs: gpu.storage("triangle attributes", &scene.attrs),
            images: gpu.storage("images", &scene.images),
            previous: gpu.storage("previous positions", &scene.previous),
            environment: gpu.storage("environment map", &scene.environment),
            counts: Self::counts(scene),
        }
    }

    /// Rewrites, in place (same counts), the buffers a new pose changes:
    /// BVH, triangles, their attributes (leaf order), emitters and previous
    /// positions. Materials, images and the environment map stay: a pose never changes them
    /// ([`SceneGpu::set_positions`]).
    fn write_pose(&self, gpu: &Gpu, scene: &SceneGpu) {
        let q = &gpu.queue;
        q.write_buffer(&self.nodes, 0, bytemuck::cast_slice(&scene.nodes));
        q.write_buffer(&self.triangles, 0, bytemuck::cast_slice(&scene.triangles));
        q.write_buffer(&self.emitters, 0, bytemuck::cast_slice(&scene.emitters));
        q.write_buffer(&self.attrs, 0, bytemuck::cast_slice(&scene.attrs));
        q.write_buffer(&self.previous, 0, bytemuck::cast_slice(&scene.previous));
    }
}

/// A scene uploaded to the device with its frame buffers: the colour of the
/// current frame, the running mean (`width * height` `Vec4` each) and the
/// G-buffer (`width * height` [`GBufferGpu`]).
#[derive(Debug)]
pub struct Tracer {
    width: u32,
    height: u32,
    params: wgpu::Buffer,
    scene: SceneBuffers,
    seeds: wgpu::Buffer,
    keys: wgpu::Buffer,
    /// Colour of the last traced frame (`w` = 1), `width * height`.
    pub color: wgpu::Buffer,
    /// Running mean of all accumulated frames, `width * height`.
    pub accum: wgpu::Buffer,
    /// G-buffer of the last [`Tracer::encode_gbuffer`], `width * height`
    /// [`GBufferGpu`]; stays on the device for the passes that read it.
    pub gbuffer: wgpu::Buffer,
    trace_bg: wgpu::BindGroup,
    gbuffer_bg: wgpu::BindGroup,
    accumulate_bg: wgpu::BindGroup,
    motion: Option<MotionPass>,
    features_bg: Option<wgpu::BindGroup>,
    /// Which trace kernel [`Tracer::encode_trace`] runs.
    variant: TraceVariant,
    /// Whether [`Tracer::encode_motion`] runs the rigid-count pass: the
    /// parameters last set have a `seed_follow_share` above 0 (at 0 the
    /// motion pass does not read the count).
    count_rigid: bool,
    /// Whether [`Tracer::encode_motion`] copies the pan offset into the
    /// parameters ([`Tracer::set_pan_offset`]).
    pan_offset: bool,
}

/// The motion pass's ping-pong visibility buffers (`width * height`
/// `UVec2`, `kernels::motion::visibility`) and a bind group per direction:
/// frame `t` reads `visibility[(t + 1) % 2]` and writes `visibility[t % 2]`;
/// and the frame-motion buffer (`kernels::pan_offset`: the rigid-count
/// pass's count and sums, the pan offset) with the count's bind group.
#[derive(Debug)]
struct MotionPass {
    bind_groups: [wgpu::BindGroup; 2],
    frame: wgpu::Buffer,
    rigid_bg: wgpu::BindGroup,
    offset_bg: wgpu::BindGroup,
    /// Which bind group the next [`Tracer::encode_motion`] uses.
    next: usize,
}

impl Tracer {
    /// Uploads `scene` and the screen-space Sobol keys
    /// (`sampler_core::defaults::screen_sobol_keys()`, binding 7, read by
    /// the screen-sobol sampler; [`crate::SceneGpu::trace_params`] writes
    /// their layout into the parameters) and allocates the accumulation
    /// buffer and the G-buffer for `params`' size. `seeds` is the seed
    /// buffer the trace pass reads (`params.padded_width` wide); `color`
    /// (from [`Tracer::color_buffer`]) receives each frame. Runs the trace
    /// kernel variant the scene fits ([`SceneGpu::trace_variant`]),
    /// compiling it if `pipelines` has not yet.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if the trace pipeline does not compile.
    pub fn new(
        gpu: &Gpu,
        pipelines: &TracePipelines,
        scene: &SceneGpu,
        params: &TraceParams,
        seeds: &wgpu::Buffer,
        color: wgpu::Buffer,
    ) -> Result<Self, GpuError> {
        let n = (params.width * params.height) as usize;
        let (params, table) = crate::sampler_data::with_frame_points(params);
        let params_buf = gpu.uniform("trace params", &params);
        let keys = gpu.storage(
            "a-priori sampler keys, shift tile and frame points",
            crate::sampler_data::sampler_buffer(),
        );
        write_frame_points(gpu, &keys, &table);
        let accum = gpu.storage_zeroed::<Vec4>("accumulation", n);
        let gbuffer = gpu.storage_zeroed::<GBufferGpu>("g-buffer", n);
        let variant = scene.trace_variant();
        pipelines.trace(variant)?;
        pipelines.gbuffer(variant)?;
        let scene = SceneBuffers::upload(gpu, scene);
        let (trace_bg, gbuffer_bg) = Self::scene_bind_groups(
            gpu,
            pipelines,
            &params_buf,
            &scene,
            seeds,
            &color,
            &keys,
            &gbuffer,
        );
        let accumulate_bg = gpu.bind(&pipelines.accumulate, &[&params_buf, &color, &accum]);
        Ok(Tracer {
            width: params.width,
            height: params.height,
            params: params_buf,
            scene,
            seeds: seeds.clone(),
            keys,
            color,
            accum,
            gbuffer,
            trace_bg,
            gbuffer_bg,
            accumulate_bg,
            motion: None,
            features_bg: None,
            variant,
            count_rigid: params.seed_follow_share > 0.0,
            pan_offset: true,
        })
    }

    /// Sets up the feature pass ([`encode_features`](Self::encode_features))
    /// to write each frame's surface features into `features` (`width *
    /// height` `SurfaceFeature`, e.g. `SeedPermuter::features`) and its
    /// demodulated sort keys into `intensity` (`width * height` `f32`).
    pub fn enable_features(
        &mut self,
        gpu: &Gpu,
        pipelines: &TracePipelines,
        features: &wgpu::Buffer,
        intensity: &wgpu::Buffer,
    ) {
        self.features_bg = Some(gpu.bind(
            &pipelines.features,
            &[&self.params, &self.gbuffer, &self.color, features, intensity],
        ));
    }

    /// Encodes the feature pass (after this frame's G-buffer and trace).
    ///
    /// # Panics
    /// Without [`enable_features`](Self::enable_features) first.
    pub fn encode_features(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipelines: &TracePipelines,
        timer: Option<(&PassTimer, u32)>,
    ) {
        let bg = self
            .features_bg
            .as_ref()
            .expect("enable_features before encode_features");
        self.encode(encoder, &pipelines.features, bg, timer);
    }

    /// Sets up the motion pass ([`encode_motion`](Self::encode_motion)) to
    /// write the reprojection motion of every frame into `motion`
    /// (`width * height` `Vec2`, e.g. `SeedReprojector::motion`).
    pub fn enable_motion(&mut self, gpu: &Gpu, pipelines: &TracePipelines, motion: &wgpu::Buffer) {
        let n = (self.width * self.height) as usize;
        let vis = [
            gpu.storage_zeroed::<UVec2>("visibility (even frames)", n),
            gpu.storage_zeroed::<UVec2>("visibility (odd frames)", n),
        ];
        let frame = gpu.storage_zeroed::<u32>("frame motion", FRAME_MOTION_WORDS);
        let bind = |read: usize, write: usize| {
            gpu.bind(
                &pipelines.motion,
                &[
                    &self.params,
                    &self.gbuffer,
                    &vis[read],
                    &vis[write],
                    motion,
                    &frame,
                ],
            )
        };
        let rigid_bg = gpu.bind(&pipelines.rigid_count, &[&self.params, &self.gbuffer, &frame]);
        let offset_bg = gpu.bind(&pipelines.pan_offset, &[&self.params, &frame]);
        self.motion = Some(MotionPass {
            bind_groups: [bind(1, 0), bind(0, 1)],
            rigid_bg,
            offset_bg,
            frame,
            next: 0,
        });
    }

    /// Whether the trace reads ZSobol at the pan offset the pan-offset pass
    /// advances (`kernels::pan_offset`; on from [`Tracer::new`]): with
    /// `false` [`Tracer::encode_motion`] leaves the parameters' offset as
    /// [`Tracer::set_params`] wrote it (0 from the scene's parameters), so
    /// ZSobol stays on the screen; the offset in the frame-motion buffer
    /// advances either way.
    pub fn set_pan_offset(&mut self, on: bool) {
        self.pan_offset = on;
    }

    /// Encodes the motion pass (after [`encode_gbuffer`](Self::encode_gbuffer)
    /// of the same frame): the motion vectors of this frame against the
    /// previous one's visibility, with disoccluded pixels
    /// `kernels::motion::DISOCCLUDED`
    /// (`kernels::motion::reprojection_motion_pixel`), and this frame's
    /// visibility for the next. Before it, when the parameters last set
    /// have a `TraceParams::seed_follow_share` above 0, the count and sums
    /// cleared, the rigid-count pass (five G-buffer texels a pixel) and the
    /// one-invocation pass that advances the pan offset from its words
    /// (`kernels::pan_offset`); the motion pass then reads the count (the
    /// frame-wide rule). After them, unless
    /// [`Tracer::set_pan_offset`] turned it off, the pan offset is copied
    /// into the parameters' `sampler_offset_x` and `sampler_offset_y`,
    /// where the trace reads it: call [`Tracer::set_params`] before this,
    /// not between it and the trace.
    /// Call once per frame; the first call's motion is meaningless (no
    /// previous frame). `timer` times the passes together.
    ///
    /// # Panics
    /// Without [`enable_motion`](Self::enable_motion) first.
    pub fn encode_motion(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        pipelines: &TracePipelines,
        timer: Option<(&PassTimer, u32)>,
    ) {
        let pass = self.motion.as_mut().expect("enable_motion before encode_motion");
        let i = pass.next;
        pass.next = 1 - i;
        let motion = self.motion.as_ref().expect("checked above");
        if self.count_rigid {
            let cleared = (FRAME_CLEARED_WORDS * std::mem::size_of::<u32>()) as u64;
            encoder.clear_buffer(&motion.frame, 0, Some(cleared));
        }
        // One compute pass, so that `timer` times every dispatch; wgpu
        // orders the pan offset's and the motion dispatch's reads of the
        // count after the count's atomic writes (one usage scope per
        // dispatch).
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("rigid count + pan offset + motion"),
            timestamp_writes: timer.map(|(t, span)| t.writes(span)),
        });
        let (gx, gy) = (
            groups(self.width, TRACE_WORKGROUP.0),
            groups(self.height, TRACE_WORKGROUP.1),
        );
        if self.count_rigid {
            pass.set_pipeline(&pipelines.rigid_count);
            pass.set_bind_group(0, &motion.rigid_bg, &[]);
            pass.dispatch_workgroups(gx, gy, 1);
            pass.set_pipeline(&pipelines.pan_offset);
            pass.set_bind_group(0, &motion.offset_bg, &[]);
            pass.dispatch_workgroups(1, 1, 1);
        }
        pass.set_pipeline(&pipelines.motion);
        pass.set_bind_group(0, &motion.bind_groups[i], &[]);
        pass.dispatch_workgroups(gx, gy, 1);
        drop(pass);
        if !self.pan_offset {
            return;
        }
        // The pan offset (two words) into the parameters, for the trace.
        let word = std::mem::size_of::<u32>() as u64;
        encoder.copy_buffer_to_buffer(
            &motion.frame,
            FRAME_OFFSET_X as u64 * word,
            &self.params,
            std::mem::offset_of!(TraceParams, sampler_offset_x) as u64,
            2 * word,
        );
    }

    /// Reads the frame-motion buffer back (`kernels::pan_offset`'s
    /// `FRAME_MOTION_WORDS` words: the last frame's rigid count and sums,
    /// the pan offset). For tests and diagnostics.
    ///
    /// # Panics
    /// Without [`enable_motion`](Self::enable_motion) first.
    ///
    /// # Errors
    /// [`GpuError`] if the read-back fails.
    pub fn read_frame_motion(&self, gpu: &Gpu) -> Result<Vec<u32>, GpuError> {
        let motion = self
            .motion
            .as_ref()
            .expect("enable_motion before read_frame_motion");
        gpu.read(&motion.frame, FRAME_MOTION_WORDS)
    }

    #[allow(clippy::too_many_arguments)]
    fn scene_bind_groups(
        gpu: &Gpu,
        pipelines: &TracePipelines,
        params: &wgpu::Buffer,
        s: &SceneBuffers,
        seeds: &wgpu::Buffer,
        color: &wgpu::Buffer,
        keys: &wgpu::Buffer,
        gbuffer: &wgpu::Buffer,
    ) -> (wgpu::BindGroup, wgpu::BindGroup) {
        let trace = gpu.bind_with(
            &pipelines.trace_group,
            &[
                params,
                &s.nodes,
                &s.triangles,
                &s.materials,
                &s.emitters,
                seeds,
                color,
                keys,
                &s.attrs,
                &s.images,
                &s.environment,
            ],
        );
        let gbuf = gpu.bind_with(
            &pipelines.gbuffer_group,
            &[
                params,
                &s.nodes,
                &s.triangles,
                &s.materials,
                &s.attrs,
                &s.images,
                &s.previous,
                gbuffer,
            ],
        );
        (trace, gbuf)
    }

    /// Uploads a new pose of the scene [`Tracer::new`] was given (a moving
    /// scene's next frame from [`SceneGpu::set_positions`], with its
    /// previous positions; materials and images are those of the first
    /// upload): rewrites the geometry buffers where the sizes match, else
    /// uploads every buffer anew and rebuilds the bind groups.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if the trace variant the new pose needs
    /// does not compile.
    pub fn update_scene(
        &mut self,
        gpu: &Gpu,
        pipelines: &TracePipelines,
        scene: &SceneGpu,
    ) -> Result<(), GpuError> {
        self.variant = scene.trace_variant();
        pipelines.trace(self.variant)?;
        pipelines.gbuffer(self.variant)?;
        if SceneBuffers::counts(scene) == self.scene.counts {
            self.scene.write_pose(gpu, scene);
            return Ok(());
        }
        self.scene = SceneBuffers::upload(gpu, scene);
        let (trace_bg, gbuffer_bg) = Self::scene_bind_groups(
            gpu,
            pipelines,
            &self.params,
            &self.scene,
            &self.seeds,
            &self.color,
            &self.keys,
            &self.gbuffer,
        );
        self.trace_bg = trace_bg;
        self.gbuffer_bg = gbuffer_bg;
        Ok(())
    }

    /// The trace kernel [`Tracer::encode_trace`] runs: the scene's
    /// [`SceneGpu::trace_variant`] unless [`Tracer::set_variant`] chose.
    pub fn variant(&self) -> TraceVariant {
        self.variant
    }

    /// Runs the trace pass with `variant` from now on (until the next
    /// [`Tracer::update_scene`]): [`TraceVariant::Full`] always renders
    /// correctly (slower on lavapipe, for comparisons); the smaller ones
    /// only a scene that fits them.
    ///
    /// # Errors
    /// [`GpuError::Unsupported`] for a variant on a scene
    /// [`SceneGpu::fits_trace_variant`] refuses (it would render wrongly);
    /// [`GpuError::Validation`] if the variant's pipeline does not compile.
    pub fn set_variant(
        &mut self,
        pipelines: &TracePipelines,
        scene: &SceneGpu,
        variant: TraceVariant,
    ) -> Result<(), GpuError> {
        if !scene.fits_trace_variant(variant) {
            return Err(GpuError::Unsupported(
                crate::error::Error::UnfitTraceVariant {
                    variant: variant.name(),
                }
                .to_string(),
            ));
        }
        pipelines.trace(variant)?;
        pipelines.gbuffer(variant)?;
        self.variant = variant;
        Ok(())
    }

    /// A frame colour buffer for a `width x height` frame, to pass to
    /// [`Tracer::new`] (and to the permutation's intensity pass).
    pub fn color_buffer(gpu: &Gpu, width: u32, height: u32) -> wgpu::Buffer {
        gpu.storage_zeroed::<Vec4>("frame colour", (width * height) as usize)
    }

    /// Writes the parameters of the next submission (frame index, cameras),
    /// and with the spatiotemporal sampler the frame's point table
    /// (`crate::sampler_data::with_frame_points`: `point_samples` is set
    /// here, whatever `params` says).
    pub fn set_params(&mut self, gpu: &Gpu, params: &TraceParams) {
        self.count_rigid = params.seed_follow_share > 0.0;
        let (params, table) = crate::sampler_data::with_frame_points(params);
        write_frame_points(gpu, &self.keys, &table);
        gpu.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
    }

    /// Encodes the trace pass (optionally timed as `timer` span `span`).
    ///
    /// # Panics
    /// If `pipelines` cannot compile the trace variant that compiled when
    /// this tracer was made (a different device or module).
    pub fn encode_trace(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipelines: &TracePipelines,
        timer: Option<(&PassTimer, u32)>,
    ) {
        // Compiled by `new`, `update_scene` or `set_variant` on these or
        // other pipelines of the same module: a failure here would be a
        // shader that compiled once and no longer does.
        let pipeline = pipelines
            .trace(self.variant)
            .unwrap_or_else(|e| panic!("the trace pipeline compiled before: {e}"));
        self.encode(encoder, pipeline, &self.trace_bg, timer);
    }

    /// Encodes the G-buffer pass (optionally timed as `timer` span `span`):
    /// fills [`Tracer::gbuffer`] for the current parameters, without
    /// texture lookups unless the tracer's variant is the full one
    /// ([`TracePipelines::gbuffer`]).
    ///
    /// # Panics
    /// As [`Tracer::encode_trace`].
    pub fn encode_gbuffer(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipelines: &TracePipelines,
        timer: Option<(&PassTimer, u32)>,
    ) {
        let pipeline = pipelines
            .gbuffer(self.variant)
            .unwrap_or_else(|e| panic!("the G-buffer pipeline compiled before: {e}"));
        self.encode(encoder, pipeline, &self.gbuffer_bg, timer);
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

    /// Reads the G-buffer back (blocking).
    ///
    /// # Errors
    /// [`GpuError::Readback`].
    pub fn read_gbuffer(&self, gpu: &Gpu) -> Result<Vec<GBufferGpu>, GpuError> {
        gpu.read(&self.gbuffer, (self.width * self.height) as usize)
    }
}

/// Stores a frame point table (`crate::sampler_data::with_frame_points`) at
/// its place in the sampler buffer; nothing for an empty table.
fn write_frame_points(gpu: &Gpu, keys: &wgpu::Buffer, table: &[u32]) {
    if !table.is_empty() {
        let offset = (crate::sampler_data::point_table_offset() * 4) as u64;
        gpu.queue.write_buffer(keys, offset, bytemuck::cast_slice(table));
    }
}
