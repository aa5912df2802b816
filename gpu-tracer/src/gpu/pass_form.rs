//! Which kernels run a pass that has two forms writing the same output.

use super::context::Gpu;

/// How a pass with two bit-identical forms is spread over invocations: the
/// sorting pass ([`SeedPermuter`](super::SeedPermuter): per block or per
/// seed) and the seed reprojection's take, list and recycle passes
/// ([`SeedReprojector`](super::SeedReprojector): per chunk or per seed). Both
/// forms write the same seeds, bit for bit; they differ in speed by device.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PassForm {
    /// One invocation walks a group of seeds (a sort block, `O(n^2)`
    /// comparisons in local arrays; a reprojection chunk of 256 seeds, in
    /// order): the least arithmetic, the fastest on a CPU rasteriser
    /// (lavapipe).
    PerGroup,
    /// One invocation per seed, each finding its place by counting within its
    /// group: more arithmetic, far more parallelism and no local arrays (which
    /// GPUs keep in scratch memory): the fastest on hardware GPUs.
    PerSeed,
}

impl PassForm {
    /// The faster form for `gpu`'s adapter: [`PerGroup`](Self::PerGroup) on a
    /// CPU (software) adapter, [`PerSeed`](Self::PerSeed) on any other.
    pub fn for_device(gpu: &Gpu) -> Self {
        if gpu.info.device_type == wgpu::DeviceType::Cpu {
            PassForm::PerGroup
        } else {
            PassForm::PerSeed
        }
    }
}
