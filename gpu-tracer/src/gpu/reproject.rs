//! The seed reprojection on the GPU: the six passes of
//! `sampler_core::reprojection::passes` (or, per seed, those of
//! `sampler_core::reprojection::seed_passes`) over device-resident buffers,
//! bit for bit what `sampler_core::reproject_frame` computes on the CPU.

use super::context::Gpu;
use super::dispatch::{encode_pass, Dispatch};
use super::pass_form::PassForm;
use super::timer::PassTimer;
use super::GpuError;
use glam::Vec2;
use kernels::reproject_entry::{
    CLAIM_ENTRY, CLEAR_CLAIMS_ENTRY, COUNT_FLAGS_ENTRY, LIST_FREE_ENTRY, LIST_FREE_SEED_ENTRY, RECYCLE_ENTRY,
    RECYCLE_SEED_ENTRY, SCAN_ENTRY, TAKE_ENTRY, TAKE_SEED_ENTRY,
};
use sampler_core::reprojection::passes::chunk_count;
use sampler_core::reprojection::seed_passes::COUNT_LANES;
use sampler_core::reprojection::MAX_REPROJECT_SEEDS;
use sampler_core::{Buffer, FrameLayout};

/// The compute pipelines of the reprojection (both forms), created once per device.
#[derive(Debug)]
pub struct ReprojectPipelines {
    clear: wgpu::ComputePipeline,
    claim: wgpu::ComputePipeline,
    take: wgpu::ComputePipeline,
    scan: wgpu::ComputePipeline,
    list_free: wgpu::ComputePipeline,
    recycle: wgpu::ComputePipeline,
    take_seed: wgpu::ComputePipeline,
    count_flags: wgpu::ComputePipeline,
    list_free_seed: wgpu::ComputePipeline,
    recycle_seed: wgpu::ComputePipeline,
}

impl ReprojectPipelines {
    /// Creates the pipelines from the kernels module.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if wgpu rejects one.
    pub fn new(gpu: &Gpu) -> Result<Self, GpuError> {
        Ok(ReprojectPipelines {
            clear: gpu.pipeline(CLEAR_CLAIMS_ENTRY)?,
            claim: gpu.pipeline(CLAIM_ENTRY)?,
            take: gpu.pipeline(TAKE_ENTRY)?,
            scan: gpu.pipeline(SCAN_ENTRY)?,
            list_free: gpu.pipeline(LIST_FREE_ENTRY)?,
            recycle: gpu.pipeline(RECYCLE_ENTRY)?,
            take_seed: gpu.pipeline(TAKE_SEED_ENTRY)?,
            count_flags: gpu.pipeline(COUNT_FLAGS_ENTRY)?,
            list_free_seed: gpu.pipeline(LIST_FREE_SEED_ENTRY)?,
            recycle_seed: gpu.pipeline(RECYCLE_SEED_ENTRY)?,
        })
    }
}

/// Device buffers and bind groups of the reprojection of one seed buffer.
///
/// [`encode`](Self::encode) moves the seeds of `seeds` (the buffer given to
/// [`new`](Self::new), `padded_width * padded_height` `u32`, laid out for
/// the previous frame's screen) along [`motion`](Self::motion) and leaves
/// the result in `seeds` again (through a scratch buffer and one copy), in
/// the [`PassForm`] chosen for the device ([`set_form`](Self::set_form)
/// changes it).
#[derive(Debug)]
pub struct SeedReprojector {
    layout: FrameLayout,
    /// Backward motion per visible pixel, `width * height` `Vec2` (pixels,
    /// raster `y` down; NaN, or anything placing the previous position outside
    /// the frame, for a disoccluded pixel): written by the
    /// tracer's motion pass or uploaded with
    /// [`upload_motion`](Self::upload_motion).
    pub motion: wgpu::Buffer,
    seeds: wgpu::Buffer,
    out: wgpu::Buffer,
    clear_bg: wgpu::BindGroup,
    claim_bg: wgpu::BindGroup,
    take_bg: wgpu::BindGroup,
    scan_bg: wgpu::BindGroup,
    list_free_bg: wgpu::BindGroup,
    recycle_bg: wgpu::BindGroup,
    take_seed_bg: wgpu::BindGroup,
    count_flags_bg: wgpu::BindGroup,
    list_free_seed_bg: wgpu::BindGroup,
    recycle_seed_bg: wgpu::BindGroup,
    form: PassForm,
}

impl SeedReprojector {
    /// Allocates the scratch buffers (claims, chunk counts, free list,
    /// flags, output: about `16 * seed_count` bytes, plus `8 * width * height`
    /// of motion) and wires the passes to `seeds`.
    ///
    /// # Errors
    /// [`GpuError::Input`] when the padded frame has more than
    /// `MAX_REPROJECT_SEEDS` seeds.
    pub fn new(
        gpu: &Gpu,
        pipelines: &ReprojectPipelines,
        layout: FrameLayout,
        seeds: &wgpu::Buffer,
    ) -> Result<Self, GpuError> {
        if layout.seed_count() > MAX_REPROJECT_SEEDS {
            return Err(GpuError::Input(sampler_core::Error::FrameSize {
                width: layout.width(),
                height: layout.height(),
            }));
        }
        let frame = layout.params(0);
        let params = gpu.uniform("reproject params", &frame);
        let motion = gpu.storage_zeroed::<Vec2>("motion", layout.pixel_count());
        let claims = gpu.storage_zeroed::<u32>("claims", layout.seed_count());
        let counts = gpu.storage_zeroed::<u32>("chunk counts", 2 * chunk_count(&frame) as usize);
        let free = gpu.storage_zeroed::<u32>("free sources", layout.seed_count());
        let out = gpu.storage_zeroed::<u32>("seeds (reprojected)", layout.seed_count());
        let flags = gpu.storage_zeroed::<u32>("reprojection flags", layout.seed_count());
        Ok(SeedReprojector {
            layout,
            clear_bg: gpu.bind(&pipelines.clear, &[&params, &claims]),
            claim_bg: gpu.bind(&pipelines.claim, &[&params, &motion, &claims]),
            take_bg: gpu.bind(
                &pipelines.take,
                &[&params, &motion, &claims, seeds, &out, &counts],
            ),
            scan_bg: gpu.bind(&pipelines.scan, &[&params, &counts]),
            list_free_bg: gpu.bind(&pipelines.list_free, &[&params, &claims, &counts, &free]),
            recycle_bg: gpu.bind(
                &pipelines.recycle,
                &[&params, &motion, &claims, &counts, &free, seeds, &out],
            ),
            take_seed_bg: gpu.bind(
                &pipelines.take_seed,
                &[&params, &motion, &claims, seeds, &out, &flags],
            ),
            count_flags_bg: gpu.bind(&pipelines.count_flags, &[&params, &flags, &counts]),
            list_free_seed_bg: gpu.bind(&pipelines.list_free_seed, &[&params, &flags, &counts, &free]),
            recycle_seed_bg: gpu.bind(
                &pipelines.recycle_seed,
                &[&params, &flags, &counts, &free, seeds, &out],
            ),
            form: PassForm::for_device(gpu),
            motion,
            seeds: seeds.clone(),
            out,
        })
    }

    /// The frame layout.
    pub fn layout(&self) -> &FrameLayout {
        &self.layout
    }

    /// The form the take, list and recycle passes run in (at creation,
    /// [`PassForm::for_device`]).
    pub fn form(&self) -> PassForm {
        self.form
    }

    /// Runs the take, list and recycle passes in `form` from now on (the
    /// same seeds either way).
    pub fn set_form(&mut self, form: PassForm) {
        self.form = form;
    }

    /// Encodes the passes (six per chunk, or seven with the per-seed form's
    /// count pass) and the copy back into the seed buffer. `timer` (if any,
    /// with its span index) times the passes as one span (the copy back is
    /// not timed).
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipelines: &ReprojectPipelines,
        timer: Option<(&PassTimer, u32)>,
    ) {
        let steps: Vec<Dispatch<'_>> = self.passes(pipelines).into_iter().map(|(_, d)| d).collect();
        encode_pass(encoder, "seed reprojection", &steps, timer);
        self.encode_copy_back(encoder);
    }

    /// Encodes what [`encode`](Self::encode) encodes, each pass in its own
    /// compute pass timed as span `first + k` of `timer` (`k` in pass order),
    /// and returns the passes' names in that order: which pass costs what.
    pub fn encode_each_timed(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipelines: &ReprojectPipelines,
        timer: &PassTimer,
        first: u32,
    ) -> Vec<&'static str> {
        let passes = self.passes(pipelines);
        for (k, (name, dispatch)) in passes.iter().enumerate() {
            encode_pass(encoder, name, &[*dispatch], Some((timer, first + k as u32)));
        }
        self.encode_copy_back(encoder);
        passes.into_iter().map(|(name, _)| name).collect()
    }

    /// The output back into the seed buffer.
    fn encode_copy_back(&self, encoder: &mut wgpu::CommandEncoder) {
        let bytes = self.layout.seed_count() as u64 * 4;
        encoder.copy_buffer_to_buffer(&self.out, 0, &self.seeds, 0, bytes);
    }

    /// The passes of the current form, named, in dispatch order.
    fn passes<'a>(&'a self, pipelines: &'a ReprojectPipelines) -> Vec<(&'static str, Dispatch<'a>)> {
        let p = self.layout.params(0);
        let chunks = chunk_count(&p);
        let n = p.seed_count();
        match self.form {
            PassForm::PerGroup => vec![
                ("clear", (&pipelines.clear, &self.clear_bg, n)),
                ("claim", (&pipelines.claim, &self.claim_bg, p.pixel_count())),
                ("take", (&pipelines.take, &self.take_bg, chunks)),
                ("scan", (&pipelines.scan, &self.scan_bg, 1)),
                ("list free", (&pipelines.list_free, &self.list_free_bg, chunks)),
                ("recycle", (&pipelines.recycle, &self.recycle_bg, chunks)),
            ],
            PassForm::PerSeed => vec![
                ("clear", (&pipelines.clear, &self.clear_bg, n)),
                ("claim", (&pipelines.claim, &self.claim_bg, p.pixel_count())),
                ("take", (&pipelines.take_seed, &self.take_seed_bg, n)),
                (
                    "count",
                    (&pipelines.count_flags, &self.count_flags_bg, chunks * COUNT_LANES),
                ),
                ("scan", (&pipelines.scan, &self.scan_bg, 1)),
                (
                    "list free",
                    (&pipelines.list_free_seed, &self.list_free_seed_bg, n),
                ),
                ("recycle", (&pipelines.recycle_seed, &self.recycle_seed_bg, n)),
            ],
        }
    }

    /// Replaces the motion buffer with `motion` (`width * height`, pixels,
    /// NaN or any out-of-frame motion for disoccluded pixels, as `sampler_core::reproject_frame` takes
    /// it).
    ///
    /// # Errors
    /// [`GpuError::Input`] for a wrong length.
    pub fn upload_motion(&self, gpu: &Gpu, motion: &[[f32; 2]]) -> Result<(), GpuError> {
        if motion.len() != self.layout.pixel_count() {
            return Err(GpuError::Input(sampler_core::Error::BufferSize {
                buffer: Buffer::Motion,
                expected: self.layout.pixel_count(),
                actual: motion.len(),
            }));
        }
        gpu.queue
            .write_buffer(&self.motion, 0, bytemuck::cast_slice(motion));
        Ok(())
    }

    /// Reads the motion buffer back (blocking), as `[dx, dy]` pairs.
    ///
    /// # Errors
    /// [`GpuError::Readback`].
    pub fn read_motion(&self, gpu: &Gpu) -> Result<Vec<[f32; 2]>, GpuError> {
        let v: Vec<Vec2> = gpu.read(&self.motion, self.layout.pixel_count())?;
        Ok(v.into_iter().map(|m| m.to_array()).collect())
    }
}
