//! The temporally blue permutation on the GPU
//! ([`PermuteMode::Temporal`](super::PermuteMode::Temporal)): the sorting
//! and retargeting kernels of the walk's permutation, unchanged, with
//! frame `t`'s tile binding (the sort's gather pass) on slice `z = t mod D`
//! of the target and its table binding on table `z`, at tile offset 0.
//!
//! Every slice and every table is uploaded once, into one buffer each
//! (`D * W * W` words; 1 MiB each for the default 64x64x64 target). Each
//! slice and each table is then bound where it lies, one bind group per
//! `z` for each pass (binding ranges at `z * 4 W^2` bytes, a multiple of
//! every device's storage offset alignment for `W >= 8`): the frame picks
//! its bind groups as the walk's permutation picks its step's table, with
//! no copy and no upload per frame, and without overwriting the walk's tile
//! and table buffers, so the walk's modes keep working on the same
//! [`SeedPermuter`](super::SeedPermuter). (Copying slice and table into
//! the bound buffers with `copy_buffer_to_buffer` would also work; it
//! costs two copies a frame and makes those buffers mean different things
//! in different modes.)
//!
//! The kernels read the walk's offset `walk_offset(params.frame)`; these
//! bind groups bind their own frame parameters, those of frame 0 (offset
//! `(0, 0)`), written once, so the caller's `set_frame` does not matter.
//!
//! With the feature-aware permutation enabled too, the feature-aware
//! kernels get the same treatment ([`TemporalFeaturePasses`]): their tile
//! and table bindings on slice and table `z`, frame 0's parameters
//! (`sampler_core::permute_frame_features_temporal`).

use super::context::Gpu;
use super::GpuError;
use sampler_core::{FrameLayout, SliceTables};
use std::num::NonZeroU64;

/// The temporal target on the device and the bind groups of its passes.
#[derive(Debug)]
pub(super) struct TemporalPasses {
    /// Slices of the target (`D * W * W` ranks), bound a slice at a time.
    slices: wgpu::Buffer,
    /// Tables of the target (`D * W * W` packed offsets), bound a table at a time.
    tables: wgpu::Buffer,
    /// Frame 0's parameters (tile offset `(0, 0)`), written once.
    params: wgpu::Buffer,
    /// Bytes of one slice or table (`4 W^2`).
    entry_bytes: u64,
    /// Per slice `z`: the per-block sort against slice `z`.
    pub sort_bg: Vec<wgpu::BindGroup>,
    /// Per slice `z`: the per-seed sort's gather pass against slice `z` (its
    /// rank pass reads no tile: the permuter's serves every slice).
    pub gather_bg: Vec<wgpu::BindGroup>,
    /// Per slice `z`: the retarget pass with table `z` (slice `z` to `z + 1`).
    pub retarget_bg: Vec<wgpu::BindGroup>,
    /// Slices of the target (`D`), to pick `z = t mod D`.
    pub depth: u32,
    /// The feature-aware passes against the target, once both are enabled.
    pub features: Option<TemporalFeaturePasses>,
}

/// The feature-aware permutation's bind groups against the target
/// (`sampler_core::permute_frame_features_temporal`): per slice `z`, the
/// grouped sort against slice `z`, the links pass and the cut retarget with
/// table `z`, all with frame 0's parameters. The jump rounds between them
/// are the walk's (they read no tile, table or offset).
#[derive(Debug)]
pub(super) struct TemporalFeaturePasses {
    /// Per slice: `sort_features_cs` against slice `z`.
    pub sort_bg: Vec<wgpu::BindGroup>,
    /// Per slice: `sort_gather_features_cs` against slice `z` (the per-seed
    /// form's group and rank passes read no tile: the permuter's serve).
    pub gather_bg: Vec<wgpu::BindGroup>,
    /// Per slice: `record_link_cs` with table `z`.
    pub record_bg: Vec<wgpu::BindGroup>,
    /// Per slice: `retarget_features_cs` with table `z`.
    pub retarget_bg: Vec<wgpu::BindGroup>,
}

/// What the feature-aware temporal passes share with the permuter: the
/// feature-aware pipelines and buffers.
pub(super) struct FeatureParts<'a> {
    /// `sort_features_cs`.
    pub sort: &'a wgpu::ComputePipeline,
    /// `sort_gather_features_cs`.
    pub gather: &'a wgpu::ComputePipeline,
    /// Each visible pixel's surface group (`surface_group_cs`'s output).
    pub groups: &'a wgpu::Buffer,
    /// The seeds in the slots of their ranks (`sort_rank_features_cs`'s output).
    pub ranked: &'a wgpu::Buffer,
    /// `record_link_cs`.
    pub record: &'a wgpu::ComputePipeline,
    /// `retarget_features_cs`.
    pub retarget: &'a wgpu::ComputePipeline,
    /// Per-pixel sort keys.
    pub intensity: &'a wgpu::Buffer,
    /// Per-pixel surface features.
    pub features: &'a wgpu::Buffer,
    /// The feature thresholds.
    pub thresholds: &'a wgpu::Buffer,
    /// The retarget links (the jump rounds' first buffer).
    pub links: &'a wgpu::Buffer,
    /// The seed buffer (sort input, retarget output).
    pub seeds: &'a wgpu::Buffer,
    /// The sorted seeds (sort output, retarget input).
    pub scratch: &'a wgpu::Buffer,
}

/// What the temporal passes share with the
/// [`SeedPermuter`](super::SeedPermuter) they belong to: its buffers and
/// the walk's sorting and retargeting pipelines.
pub(super) struct PermuterParts<'a> {
    /// `sort_cs`.
    pub sort: &'a wgpu::ComputePipeline,
    /// `sort_gather_cs`.
    pub gather: &'a wgpu::ComputePipeline,
    /// `retarget_cs`.
    pub retarget: &'a wgpu::ComputePipeline,
    /// Per-pixel sort keys.
    pub intensity: &'a wgpu::Buffer,
    /// The seeds in the slots of their ranks (`sort_rank_cs`'s output).
    pub ranked: &'a wgpu::Buffer,
    /// The seed buffer (sort input, retarget output).
    pub seeds: &'a wgpu::Buffer,
    /// The sorted seeds (sort output, retarget input).
    pub scratch: &'a wgpu::Buffer,
}

impl TemporalPasses {
    /// Uploads `target` and builds the bind groups for `layout`.
    ///
    /// # Errors
    /// [`GpuError::Input`] if the target's tile differs from the layout's.
    pub fn new(
        gpu: &Gpu,
        layout: &FrameLayout,
        target: &SliceTables<'_>,
        buffers: PermuterParts<'_>,
    ) -> Result<Self, GpuError> {
        if target.tile() != layout.tile() {
            return Err(GpuError::Input(sampler_core::Error::TileSize {
                tile: target.tile(),
            }));
        }
        let slices = gpu.storage("temporal target slices", target.slices_packed());
        let tables = gpu.storage("temporal target tables", target.tables_packed());
        let params = gpu.uniform("frame params (frame 0)", &layout.params(0));
        let bytes = 4 * u64::from(target.tile()) * u64::from(target.tile());
        let align = u64::from(gpu.device.limits().min_storage_buffer_offset_alignment);
        if !bytes.is_multiple_of(align) {
            return Err(GpuError::Validation(format!(
                "a {0}x{0} slice ({bytes} bytes) cannot be bound at the device's storage offset alignment ({align} bytes)",
                target.tile()
            )));
        }
        let depth = target.depth();
        let sort_bg = per_slice(gpu, buffers.sort, depth, |z| {
            [
                whole(&params),
                whole(buffers.intensity),
                range(&slices, z, bytes),
                whole(buffers.seeds),
                whole(buffers.scratch),
            ]
        });
        let gather_bg = per_slice(gpu, buffers.gather, depth, |z| {
            [
                whole(&params),
                range(&slices, z, bytes),
                whole(buffers.ranked),
                whole(buffers.scratch),
            ]
        });
        let retarget_bg = per_slice(gpu, buffers.retarget, depth, |z| {
            [
                whole(&params),
                range(&tables, z, bytes),
                whole(buffers.scratch),
                whole(buffers.seeds),
            ]
        });
        Ok(TemporalPasses {
            slices,
            tables,
            params,
            entry_bytes: bytes,
            sort_bg,
            gather_bg,
            retarget_bg,
            depth,
            features: None,
        })
    }

    /// Builds the feature-aware passes' bind groups against the target
    /// ([`TemporalFeaturePasses`]).
    pub fn enable_features(&mut self, gpu: &Gpu, parts: FeatureParts<'_>) {
        let (bytes, depth) = (self.entry_bytes, self.depth);
        let params = whole(&self.params);
        let sort_bg = per_slice(gpu, parts.sort, depth, |z| {
            [
                params.clone(),
                whole(parts.intensity),
                whole(parts.features),
                whole(parts.thresholds),
                range(&self.slices, z, bytes),
                whole(parts.seeds),
                whole(parts.scratch),
            ]
        });
        let gather_bg = per_slice(gpu, parts.gather, depth, |z| {
            [
                params.clone(),
                range(&self.slices, z, bytes),
                whole(parts.groups),
                whole(parts.ranked),
                whole(parts.scratch),
            ]
        });
        let record_bg = per_slice(gpu, parts.record, depth, |z| {
            [
                params.clone(),
                range(&self.tables, z, bytes),
                whole(parts.features),
                whole(parts.thresholds),
                whole(parts.links),
            ]
        });
        let retarget_bg = per_slice(gpu, parts.retarget, depth, |z| {
            [
                params.clone(),
                range(&self.tables, z, bytes),
                whole(parts.links),
                whole(parts.features),
                whole(parts.thresholds),
                whole(parts.scratch),
                whole(parts.seeds),
            ]
        });
        self.features = Some(TemporalFeaturePasses {
            sort_bg,
            gather_bg,
            record_bg,
            retarget_bg,
        });
    }
}

/// One bind group of `pipeline` per slice `z` of `0..depth`, its bindings
/// `entries(z)`.
fn per_slice<'a, const N: usize>(
    gpu: &Gpu,
    pipeline: &wgpu::ComputePipeline,
    depth: u32,
    entries: impl Fn(u32) -> [wgpu::BufferBinding<'a>; N],
) -> Vec<wgpu::BindGroup> {
    (0..depth).map(|z| bind(gpu, pipeline, &entries(z))).collect()
}

/// Entry `z` of `buffer` when it holds entries of `bytes` bytes back to back.
fn range(buffer: &wgpu::Buffer, z: u32, bytes: u64) -> wgpu::BufferBinding<'_> {
    wgpu::BufferBinding {
        buffer,
        offset: u64::from(z) * bytes,
        size: NonZeroU64::new(bytes),
    }
}

/// All of `buffer`.
fn whole(buffer: &wgpu::Buffer) -> wgpu::BufferBinding<'_> {
    buffer.as_entire_buffer_binding()
}

/// A bind group of `pipeline`'s group 0 with `entries` at bindings 0, 1, ...
fn bind(gpu: &Gpu, pipeline: &wgpu::ComputePipeline, entries: &[wgpu::BufferBinding<'_>]) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry<'_>> = entries
        .iter()
        .enumerate()
        .map(|(i, b)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: wgpu::BindingResource::Buffer(b.clone()),
        })
        .collect();
    gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("temporal permutation"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    })
}
