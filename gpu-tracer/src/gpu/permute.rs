//! The seed permutation on the GPU: intensity, sorting, retargeting and seed
//! initialisation passes over device-resident buffers, no read-back between
//! frames.

use super::context::Gpu;
use super::dispatch::{encode_pass, Dispatch};
use super::pass_form::PassForm;
use super::temporal::{FeatureParts, PermuterParts, TemporalPasses};
use super::timer::PassTimer;
use super::GpuError;
use kernels::permute_entry::{
    INTENSITY_ENTRY, JUMP_LINK_ENTRY, RECORD_LINK_ENTRY, RETARGET_ENTRY, RETARGET_FEATURES_ENTRY,
    SEED_INIT_ENTRY, SORT_ENTRY, SORT_FEATURES_ENTRY, SORT_GATHER_ENTRY, SORT_GATHER_FEATURES_ENTRY,
    SORT_RANK_ENTRY, SORT_RANK_FEATURES_ENTRY, SURFACE_GROUP_ENTRY,
};
use sampler_core::features::permute::JUMP_ROUNDS;
use sampler_core::{
    step_index, DitherTile, FeatureThresholds, FrameLayout, FrameParams, RetargetTables, SliceTables,
    SurfaceFeature, STEP_COUNT,
};

/// How seeds change between frames.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PermuteMode {
    /// Fresh white-noise seeds every frame (the baseline): frame `t` is
    /// salted `sampler_core::frame_salt(salt, t)`.
    White,
    /// Sorting pass only: seeds ranked like the frame's dither tile.
    Sort,
    /// Sorting then retargeting (Heitz & Belcour 2019).
    Permute,
    /// Nothing between frames: the buffer is written once and kept (moved
    /// along the motion with reprojection). Only for the spatiotemporal
    /// sampler and ZSobol on every decision, whose buffer then holds the
    /// pixels' homes (`kernels::abi::SAMPLER_FOLLOW_HOMES`), not seeds: they
    /// draw their numbers from per-pixel data read at the home and advance
    /// their own sequence every frame.
    Hold,
    /// The temporally blue permutation (`sampler_core::permute_frame_temporal`):
    /// after frame `t`, the sorting pass ranks against slice `t mod D` of a
    /// spatiotemporal mask and the retargeting pass moves seeds to slice
    /// `t + 1` with the exact table between them, both at tile offset 0.
    /// Needs [`SeedPermuter::enable_temporal`]; the tile side is the mask's
    /// (64 for the default one). With [`SeedPermuter::enable_features`] too,
    /// the feature-aware passes against the same slice and table
    /// (`sampler_core::permute_frame_features_temporal`); seed reprojection
    /// moves the seeds before the trace as in [`Permute`](Self::Permute).
    Temporal,
}

/// The compute pipelines of the permutation (plain and feature-aware), created once per device.
#[derive(Debug)]
pub struct PermutePipelines {
    intensity: wgpu::ComputePipeline,
    sort: wgpu::ComputePipeline,
    sort_rank: wgpu::ComputePipeline,
    sort_gather: wgpu::ComputePipeline,
    retarget: wgpu::ComputePipeline,
    seed_init: wgpu::ComputePipeline,
    sort_features: wgpu::ComputePipeline,
    surface_group: wgpu::ComputePipeline,
    sort_rank_features: wgpu::ComputePipeline,
    sort_gather_features: wgpu::ComputePipeline,
    record_link: wgpu::ComputePipeline,
    jump_link: wgpu::ComputePipeline,
    retarget_features: wgpu::ComputePipeline,
}

impl PermutePipelines {
    /// Creates the pipelines from the kernels module.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if wgpu rejects one.
    pub fn new(gpu: &Gpu) -> Result<Self, GpuError> {
        Ok(PermutePipelines {
            intensity: gpu.pipeline(INTENSITY_ENTRY)?,
            sort: gpu.pipeline(SORT_ENTRY)?,
            sort_rank: gpu.pipeline(SORT_RANK_ENTRY)?,
            sort_gather: gpu.pipeline(SORT_GATHER_ENTRY)?,
            retarget: gpu.pipeline(RETARGET_ENTRY)?,
            seed_init: gpu.pipeline(SEED_INIT_ENTRY)?,
            sort_features: gpu.pipeline(SORT_FEATURES_ENTRY)?,
            surface_group: gpu.pipeline(SURFACE_GROUP_ENTRY)?,
            sort_rank_features: gpu.pipeline(SORT_RANK_FEATURES_ENTRY)?,
            sort_gather_features: gpu.pipeline(SORT_GATHER_FEATURES_ENTRY)?,
            record_link: gpu.pipeline(RECORD_LINK_ENTRY)?,
            jump_link: gpu.pipeline(JUMP_LINK_ENTRY)?,
            retarget_features: gpu.pipeline(RETARGET_FEATURES_ENTRY)?,
        })
    }
}

/// Device buffers and bind groups of the permutation for one frame layout.
///
/// Seeds live in [`seeds`](Self::seeds) (`padded_width * padded_height`
/// `u32`s, the buffer the tracer reads); the passes use a second buffer as
/// the sort output and retarget back into `seeds`. The sort runs in the
/// [`PassForm`] chosen for the device ([`set_sort_form`](Self::set_sort_form)
/// changes it); the per-seed form ranks into a third buffer first.
#[derive(Debug)]
pub struct SeedPermuter {
    layout: FrameLayout,
    params: wgpu::Buffer,
    /// The seed buffer the tracer reads (padded, row-major).
    pub seeds: wgpu::Buffer,
    scratch: wgpu::Buffer,
    /// Seeds in the slots of their intensity ranks (the two-pass sort's
    /// middle buffer, `seed_count` `u32`).
    ranked: wgpu::Buffer,
    /// Per-pixel sort keys (luma of the colour buffer), `width * height` f32.
    pub intensity: wgpu::Buffer,
    intensity_bg: wgpu::BindGroup,
    sort_bg: wgpu::BindGroup,
    rank_bg: wgpu::BindGroup,
    gather_bg: wgpu::BindGroup,
    retarget_bg: Vec<wgpu::BindGroup>,
    seed_init_bg: wgpu::BindGroup,
    tile: wgpu::Buffer,
    tables: Vec<wgpu::Buffer>,
    features: Option<FeaturePasses>,
    temporal: Option<TemporalPasses>,
    sort_form: PassForm,
}

/// The buffers and bind groups of the feature-aware passes
/// ([`SeedPermuter::enable_features`]).
#[derive(Debug)]
struct FeaturePasses {
    features: wgpu::Buffer,
    thresholds: wgpu::Buffer,
    /// The links of the cut retarget (the jump rounds' first buffer).
    links: wgpu::Buffer,
    /// Each visible pixel's surface group in its block (the per-seed sort's).
    groups: wgpu::Buffer,
    /// The per-block grouped sort.
    sort_bg: wgpu::BindGroup,
    /// The per-seed grouped sort: groups, rank, gather.
    group_bg: wgpu::BindGroup,
    rank_bg: wgpu::BindGroup,
    gather_bg: wgpu::BindGroup,
    /// Per retarget table: the links pass and the cut retarget.
    record_bg: Vec<wgpu::BindGroup>,
    /// The jump rounds: `links -> links_b`, then `links_b -> links`.
    jump_bg: [wgpu::BindGroup; 2],
    retarget_bg: Vec<wgpu::BindGroup>,
}

impl SeedPermuter {
    /// Uploads the tile and tables and wires the passes to `color` (the
    /// tracer's `width * height` `Vec4` frame colour buffer). Device memory:
    /// three `u32` per padded seed (seeds, sorted, ranked), one `f32` per
    /// pixel (intensity), the tile and its four tables (`5 * 4 W^2` bytes);
    /// [`enable_features`](Self::enable_features) adds three `u32` per seed
    /// (links twice, groups) and 16 bytes per pixel (features).
    ///
    /// # Errors
    /// [`GpuError::Input`] if the tile or tables do not match the layout.
    pub fn new(
        gpu: &Gpu,
        pipelines: &PermutePipelines,
        layout: FrameLayout,
        tile: &DitherTile<'_>,
        tables: &RetargetTables<'_>,
        color: &wgpu::Buffer,
    ) -> Result<Self, GpuError> {
        if tile.tile() != layout.tile() || tables.tile() != layout.tile() {
            return Err(GpuError::Input(sampler_core::Error::TileSize {
                tile: tile.tile(),
            }));
        }
        let params = gpu.uniform("frame params", &layout.params(0));
        let seeds = gpu.storage_zeroed::<u32>("seeds", layout.seed_count());
        let scratch = gpu.storage_zeroed::<u32>("seeds (sorted)", layout.seed_count());
        let ranked = gpu.storage_zeroed::<u32>("seeds (ranked)", layout.seed_count());
        let intensity = gpu.storage_zeroed::<f32>("intensity", layout.pixel_count());
        let tile_buf = gpu.storage("dither tile", tile.values());
        let table_bufs: Vec<wgpu::Buffer> = (0..STEP_COUNT as u32)
            .map(|i| gpu.storage("retarget table", tables.table(i).packed()))
            .collect();
        let intensity_bg = gpu.bind(&pipelines.intensity, &[&params, color, &intensity]);
        let sort_bg = gpu.bind(
            &pipelines.sort,
            &[&params, &intensity, &tile_buf, &seeds, &scratch],
        );
        let rank_bg = gpu.bind(&pipelines.sort_rank, &[&params, &intensity, &seeds, &ranked]);
        let gather_bg = gpu.bind(&pipelines.sort_gather, &[&params, &tile_buf, &ranked, &scratch]);
        let retarget_bg = table_bufs
            .iter()
            .map(|t| gpu.bind(&pipelines.retarget, &[&params, t, &scratch, &seeds]))
            .collect();
        let seed_init_bg = gpu.bind(&pipelines.seed_init, &[&params, &seeds]);
        Ok(SeedPermuter {
            layout,
            params,
            seeds,
            scratch,
            ranked,
            intensity,
            intensity_bg,
            sort_bg,
            rank_bg,
            gather_bg,
            retarget_bg,
            seed_init_bg,
            tile: tile_buf,
            tables: table_bufs,
            features: None,
            temporal: None,
            sort_form: PassForm::for_device(gpu),
        })
    }

    /// Switches [`PermuteMode::Permute`] to the feature-aware permutation
    /// (`sampler_core::permute_frame_features` with `thresholds`): its sort
    /// keys are read from [`intensity`](Self::intensity) and its features
    /// from [`features`](Self::features) (`width * height`
    /// `SurfaceFeature`), which the caller fills each frame (the tracer's
    /// feature pass, or [`upload_features`](Self::upload_features)).
    pub fn enable_features(
        &mut self,
        gpu: &Gpu,
        pipelines: &PermutePipelines,
        thresholds: &FeatureThresholds,
    ) {
        let features = gpu.storage_zeroed::<SurfaceFeature>("surface features", self.layout.pixel_count());
        let thresholds = gpu.storage("feature thresholds", std::slice::from_ref(thresholds));
        let links = gpu.storage_zeroed::<u32>("retarget links", self.layout.seed_count());
        let links_b = gpu.storage_zeroed::<u32>("retarget links (jump)", self.layout.seed_count());
        let groups = gpu.storage_zeroed::<u32>("surface groups", self.layout.seed_count());
        let group_bg = gpu.bind(
            &pipelines.surface_group,
            &[&self.params, &features, &thresholds, &groups],
        );
        let rank_bg = gpu.bind(
            &pipelines.sort_rank_features,
            &[&self.params, &self.intensity, &groups, &self.seeds, &self.ranked],
        );
        let gather_bg = gpu.bind(
            &pipelines.sort_gather_features,
            &[&self.params, &self.tile, &groups, &self.ranked, &self.scratch],
        );
        let sort_bg = gpu.bind(
            &pipelines.sort_features,
            &[
                &self.params,
                &self.intensity,
                &features,
                &thresholds,
                &self.tile,
                &self.seeds,
                &self.scratch,
            ],
        );
        let record_bg = self
            .tables
            .iter()
            .map(|t| {
                gpu.bind(
                    &pipelines.record_link,
                    &[&self.params, t, &features, &thresholds, &links],
                )
            })
            .collect();
        let jump_bg = [
            gpu.bind(&pipelines.jump_link, &[&self.params, &links, &links_b]),
            gpu.bind(&pipelines.jump_link, &[&self.params, &links_b, &links]),
        ];
        let retarget_bg = self
            .tables
            .iter()
            .map(|t| {
                gpu.bind(
                    &pipelines.retarget_features,
                    &[
                        &self.params,
                        t,
                        &links,
                        &features,
                        &thresholds,
                        &self.scratch,
                        &self.seeds,
                    ],
                )
            })
            .collect();
        self.features = Some(FeaturePasses {
            features,
            thresholds,
            links,
            groups,
            sort_bg,
            group_bg,
            rank_bg,
            gather_bg,
            record_bg,
            jump_bg,
            retarget_bg,
        });
        self.wire_temporal_features(gpu, pipelines);
    }

    /// With both the feature-aware permutation and the temporal mode
    /// enabled, builds the feature-aware passes against the temporal target.
    fn wire_temporal_features(&mut self, gpu: &Gpu, pipelines: &PermutePipelines) {
        if let (Some(f), Some(t)) = (&self.features, &mut self.temporal) {
            let parts = FeatureParts {
                sort: &pipelines.sort_features,
                gather: &pipelines.sort_gather_features,
                groups: &f.groups,
                ranked: &self.ranked,
                record: &pipelines.record_link,
                retarget: &pipelines.retarget_features,
                intensity: &self.intensity,
                features: &f.features,
                thresholds: &f.thresholds,
                links: &f.links,
                seeds: &self.seeds,
                scratch: &self.scratch,
            };
            t.enable_features(gpu, parts);
        }
    }

    /// Enables [`PermuteMode::Temporal`] with `target` (its slices and
    /// tables uploaded once; module `temporal` of `gpu` says how they are
    /// bound).
    ///
    /// # Errors
    /// [`GpuError::Input`] if the target's tile differs from the layout's;
    /// [`GpuError::Validation`] if a slice cannot be bound at the device's
    /// storage offset alignment (tiles below 8x8).
    pub fn enable_temporal(
        &mut self,
        gpu: &Gpu,
        pipelines: &PermutePipelines,
        target: &SliceTables<'_>,
    ) -> Result<(), GpuError> {
        let buffers = PermuterParts {
            sort: &pipelines.sort,
            gather: &pipelines.sort_gather,
            intensity: &self.intensity,
            retarget: &pipelines.retarget,
            ranked: &self.ranked,
            seeds: &self.seeds,
            scratch: &self.scratch,
        };
        self.temporal = Some(TemporalPasses::new(gpu, &self.layout, target, buffers)?);
        self.wire_temporal_features(gpu, pipelines);
        Ok(())
    }

    /// The surface-feature buffer of the feature-aware permutation, if
    /// [`enable_features`](Self::enable_features) was called.
    pub fn features(&self) -> Option<&wgpu::Buffer> {
        self.features.as_ref().map(|f| &f.features)
    }

    /// Replaces the surface features with `features` (`width * height`).
    ///
    /// # Errors
    /// [`GpuError::Input`] for a wrong length; [`GpuError::Validation`]
    /// without [`enable_features`](Self::enable_features).
    pub fn upload_features(&self, gpu: &Gpu, features: &[SurfaceFeature]) -> Result<(), GpuError> {
        let f = self
            .features
            .as_ref()
            .ok_or_else(|| GpuError::Validation("upload_features needs enable_features first".into()))?;
        if features.len() != self.layout.pixel_count() {
            return Err(GpuError::Input(sampler_core::Error::BufferSize {
                buffer: sampler_core::Buffer::Features,
                expected: self.layout.pixel_count(),
                actual: features.len(),
            }));
        }
        gpu.queue
            .write_buffer(&f.features, 0, bytemuck::cast_slice(features));
        Ok(())
    }

    /// The frame layout.
    pub fn layout(&self) -> &FrameLayout {
        &self.layout
    }

    /// Writes the frame parameters of frame `frame` (takes effect at the next
    /// submission; call once per submission).
    pub fn set_frame(&self, gpu: &Gpu, frame: u32) {
        gpu.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&self.layout.params(frame)));
    }

    /// Encodes white-noise seeds with salt `frame` (as set by
    /// [`set_frame`](Self::set_frame)) into [`seeds`](Self::seeds).
    pub fn encode_seed_init(&self, encoder: &mut wgpu::CommandEncoder, pipelines: &PermutePipelines) {
        let init = [(
            &pipelines.seed_init,
            &self.seed_init_bg,
            self.layout.seed_count() as u32,
        )];
        encode_pass(encoder, "seed init", &init, None);
    }

    /// Encodes the colour -> intensity pass.
    pub fn encode_intensity(&self, encoder: &mut wgpu::CommandEncoder, pipelines: &PermutePipelines) {
        let intensity = [(
            &pipelines.intensity,
            &self.intensity_bg,
            self.layout.pixel_count() as u32,
        )];
        encode_pass(encoder, "intensity", &intensity, None);
    }

    /// Encodes the passes that turn frame `frame`'s seeds and intensities into
    /// frame `frame + 1`'s seeds, for `mode`. [`set_frame`](Self::set_frame)
    /// must have been called with `frame` for this submission, except in
    /// [`PermuteMode::White`], which needs the next frame's salt
    /// (`sampler_core::frame_salt(salt, frame + 1)`).
    /// `timer` (if any, with its first span index) records the sort pass as
    /// that span and the retarget pass as the next.
    /// [`PermuteMode::Temporal`] ignores the frame parameters (its passes
    /// bind frame 0's) and uses slice and table `frame mod D`.
    ///
    /// # Panics
    /// With [`PermuteMode::Temporal`] if
    /// [`enable_temporal`](Self::enable_temporal) was not called.
    pub fn encode_step(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipelines: &PermutePipelines,
        frame: u32,
        mode: PermuteMode,
        timer: Option<(&PassTimer, u32)>,
    ) {
        let params: FrameParams = self.layout.params(frame);
        match mode {
            PermuteMode::White => self.encode_seed_init(encoder, pipelines),
            PermuteMode::Hold => {}
            PermuteMode::Permute if self.features.is_some() => {
                let f = self.features.as_ref().expect("checked");
                let step = step_index(frame, params.tile_log2) as usize;
                self.encode_feature_sort(encoder, pipelines, f, [&f.sort_bg, &f.gather_bg], timer);
                let groups = [&f.record_bg[step], &f.retarget_bg[step]];
                encode_feature_retarget(encoder, pipelines, &params, groups, &f.jump_bg, timer);
            }
            PermuteMode::Temporal if self.features.is_some() => {
                let f = self.features.as_ref().expect("checked");
                let passes = self
                    .temporal
                    .as_ref()
                    .and_then(|t| t.features.as_ref().map(|tf| (t.depth, tf)));
                let (depth, tf) = passes.expect("PermuteMode::Temporal needs SeedPermuter::enable_temporal");
                let z = (frame % depth) as usize;
                self.encode_feature_sort(encoder, pipelines, f, [&tf.sort_bg[z], &tf.gather_bg[z]], timer);
                let groups = [&tf.record_bg[z], &tf.retarget_bg[z]];
                encode_feature_retarget(encoder, pipelines, &params, groups, &f.jump_bg, timer);
            }
            PermuteMode::Temporal => {
                let passes = self
                    .temporal
                    .as_ref()
                    .expect("PermuteMode::Temporal needs SeedPermuter::enable_temporal");
                let z = (frame % passes.depth) as usize;
                let groups = [&passes.sort_bg[z], &passes.gather_bg[z]];
                self.encode_plain_sort(encoder, pipelines, self.sort_form, groups, timer);
                self.encode_retarget(encoder, pipelines, &passes.retarget_bg[z], timer);
            }
            PermuteMode::Sort | PermuteMode::Permute => {
                self.encode_walk_sort(encoder, pipelines, self.sort_form, timer);
                if mode == PermuteMode::Permute {
                    let step = step_index(frame, params.tile_log2) as usize;
                    self.encode_retarget(encoder, pipelines, &self.retarget_bg[step], timer);
                } else {
                    let bytes = (params.seed_count() as u64) * 4;
                    encoder.copy_buffer_to_buffer(&self.scratch, 0, &self.seeds, 0, bytes);
                }
            }
        }
    }

    /// Encodes the plain retarget with `table_group` (the walk's table of the
    /// step or a temporal table), from the sorted buffer into
    /// [`seeds`](Self::seeds), timed as span `span + 1` of `timer` (the sort
    /// before it is span `span`).
    fn encode_retarget(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipelines: &PermutePipelines,
        table_group: &wgpu::BindGroup,
        timer: Option<(&PassTimer, u32)>,
    ) {
        let retarget = [(&pipelines.retarget, table_group, self.layout.seed_count() as u32)];
        encode_pass(
            encoder,
            "retarget",
            &retarget,
            timer.map(|(t, span)| (t, span + 1)),
        );
    }

    /// The form the sorting pass runs in (at creation,
    /// [`PassForm::for_device`]).
    pub fn sort_form(&self) -> PassForm {
        self.sort_form
    }

    /// Runs the sorting pass in `form` from now on (the same seeds either way).
    pub fn set_sort_form(&mut self, form: PassForm) {
        self.sort_form = form;
    }

    /// Encodes the walk's sorting pass of frame `frame` (as set by
    /// [`set_frame`](Self::set_frame)) in `form`, from [`seeds`](Self::seeds)
    /// into the sorted buffer ([`read_sorted`](Self::read_sorted)), timed as
    /// span `span` of `timer`: what [`encode_step`](Self::encode_step) runs
    /// before the retarget in [`PermuteMode::Sort`] and
    /// [`PermuteMode::Permute`], for tests and for timing one form against
    /// the other.
    pub fn encode_walk_sort(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipelines: &PermutePipelines,
        form: PassForm,
        timer: Option<(&PassTimer, u32)>,
    ) {
        self.encode_plain_sort(encoder, pipelines, form, [&self.sort_bg, &self.gather_bg], timer);
    }

    /// Encodes a sorting pass in `form`, in one compute pass labelled
    /// `label` timed as span `span` of `timer`: `per_block` (the per-block
    /// kernel and its bind group, one invocation per block) or `per_seed`
    /// (the per-seed passes in order, one invocation per seed each).
    fn encode_sort(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        label: &str,
        form: PassForm,
        per_block: (&wgpu::ComputePipeline, &wgpu::BindGroup),
        per_seed: &[(&wgpu::ComputePipeline, &wgpu::BindGroup)],
        timer: Option<(&PassTimer, u32)>,
    ) {
        let dispatches: Vec<Dispatch<'_>> = match form {
            PassForm::PerGroup => {
                let params = self.layout.params(0);
                vec![(per_block.0, per_block.1, params.blocks_x() * params.blocks_y())]
            }
            PassForm::PerSeed => {
                let n = self.layout.seed_count() as u32;
                per_seed.iter().map(|&(p, bg)| (p, bg, n)).collect()
            }
        };
        encode_pass(encoder, label, &dispatches, timer);
    }

    /// Encodes the plain sorting pass in `form` with `tile_groups` (the
    /// per-block kernel's and the gather pass's bind groups: the walk's tile
    /// or a temporal slice; the rank pass reads no tile).
    fn encode_plain_sort(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipelines: &PermutePipelines,
        form: PassForm,
        tile_groups: [&wgpu::BindGroup; 2],
        timer: Option<(&PassTimer, u32)>,
    ) {
        let [block, gather] = tile_groups;
        let per_seed = [
            (&pipelines.sort_rank, &self.rank_bg),
            (&pipelines.sort_gather, gather),
        ];
        self.encode_sort(encoder, "sort", form, (&pipelines.sort, block), &per_seed, timer);
    }

    /// Encodes the feature-aware sorting pass of `f` in the permuter's form
    /// with `tile_groups` (as [`encode_plain_sort`](Self::encode_plain_sort)'s;
    /// the group and rank passes read no tile).
    fn encode_feature_sort(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipelines: &PermutePipelines,
        f: &FeaturePasses,
        tile_groups: [&wgpu::BindGroup; 2],
        timer: Option<(&PassTimer, u32)>,
    ) {
        let [block, gather] = tile_groups;
        let per_seed = [
            (&pipelines.surface_group, &f.group_bg),
            (&pipelines.sort_rank_features, &f.rank_bg),
            (&pipelines.sort_gather_features, gather),
        ];
        let per_block = (&pipelines.sort_features, block);
        self.encode_sort(
            encoder,
            "feature-aware sort",
            self.sort_form,
            per_block,
            &per_seed,
            timer,
        );
    }

    /// Replaces the seed buffer with `seeds` (`padded_width * padded_height`).
    ///
    /// # Errors
    /// [`GpuError::Input`] for a wrong length.
    pub fn upload_seeds(&self, gpu: &Gpu, seeds: &[u32]) -> Result<(), GpuError> {
        self.layout
            .check_seed_buffer(sampler_core::Buffer::SeedsIn, seeds.len())?;
        gpu.queue
            .write_buffer(&self.seeds, 0, bytemuck::cast_slice(seeds));
        Ok(())
    }

    /// Replaces the intensity buffer with `values` (`width * height`).
    ///
    /// # Errors
    /// [`GpuError::Input`] for a wrong length.
    pub fn upload_intensity(&self, gpu: &Gpu, values: &[f32]) -> Result<(), GpuError> {
        self.layout.check_intensity_buffer(values.len())?;
        gpu.queue
            .write_buffer(&self.intensity, 0, bytemuck::cast_slice(values));
        Ok(())
    }

    /// Reads the seed buffer back (blocking).
    ///
    /// # Errors
    /// [`GpuError::Readback`].
    pub fn read_seeds(&self, gpu: &Gpu) -> Result<Vec<u32>, GpuError> {
        gpu.read(&self.seeds, self.layout.seed_count())
    }

    /// The sort pass's output buffer (`seed_count` `u32`).
    pub fn sorted(&self) -> &wgpu::Buffer {
        &self.scratch
    }

    /// Reads the sort pass's output buffer back (blocking).
    ///
    /// # Errors
    /// [`GpuError::Readback`].
    pub fn read_sorted(&self, gpu: &Gpu) -> Result<Vec<u32>, GpuError> {
        gpu.read(&self.scratch, self.layout.seed_count())
    }
}

/// Encodes the feature-aware permutation's retarget with `groups` (the
/// links pass's and the cut retarget's bind groups) and `jump` (the jump
/// rounds' two): the links, the jump rounds and the cut retarget in one
/// compute pass (wgpu orders the dispatches and puts barriers between them),
/// timed as span `span + 1` of `timer` (the sort before it is span `span`).
fn encode_feature_retarget(
    encoder: &mut wgpu::CommandEncoder,
    pipelines: &PermutePipelines,
    params: &FrameParams,
    groups: [&wgpu::BindGroup; 2],
    jump: &[wgpu::BindGroup; 2],
    timer: Option<(&PassTimer, u32)>,
) {
    let [record, retarget] = groups;
    let n = params.seed_count();
    let mut dispatches: Vec<Dispatch<'_>> = vec![(&pipelines.record_link, record, n)];
    for round in 0..JUMP_ROUNDS {
        dispatches.push((&pipelines.jump_link, &jump[(round % 2) as usize], n));
    }
    dispatches.push((&pipelines.retarget_features, retarget, n));
    let timer = timer.map(|(t, span)| (t, span + 1));
    encode_pass(encoder, "feature-aware retarget", &dispatches, timer);
}
