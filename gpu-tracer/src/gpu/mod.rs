//! The wgpu side of the tracer: device, kernels module, and one struct per
//! group of GPU passes.

mod context;
mod dispatch;
mod filter;
mod headless;
mod pass_form;
mod permute;
mod reproject;
mod temporal;
mod timer;
mod trace;

pub use context::{groups, Gpu, LazyPipeline, KERNELS_SPV, REQUIRE_GPU_ENV};
pub use filter::{FilterPipelines, FrameFilterGpu};
pub use headless::{prepare_headless_environment, RUNTIME_DIR_ENV};
pub use pass_form::PassForm;
pub use permute::{PermuteMode, PermutePipelines, SeedPermuter};
pub use reproject::{ReprojectPipelines, SeedReprojector};
pub use timer::PassTimer;
pub use trace::{TracePipelines, Tracer};

use std::fmt;

/// What can go wrong on the GPU side.
#[derive(Debug)]
#[non_exhaustive]
pub enum GpuError {
    /// No adapter: no GPU and no software Vulkan driver (install Mesa's
    /// `mesa-vulkan-drivers` for lavapipe), or none matched.
    NoAdapter(String),
    /// The adapter refused to create a device.
    Device(String),
    /// wgpu rejected the shader module, a pipeline or a bind group.
    Validation(String),
    /// Mapping a buffer back to the host failed or the device was lost.
    Readback(String),
    /// Input that does not fit the frame layout.
    Input(sampler_core::Error),
    /// A filter setting or buffer that does not fit ([`crate::filter`]).
    Filter(crate::error::Error),
    /// A kernel asked for a scene it cannot render
    /// ([`Tracer::set_variant`]).
    Unsupported(String),
}

impl fmt::Display for GpuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GpuError::NoAdapter(e) => write!(f, "no GPU adapter: {e}"),
            GpuError::Device(e) => write!(f, "cannot create a GPU device: {e}"),
            GpuError::Validation(e) => write!(f, "GPU validation error: {e}"),
            GpuError::Readback(e) => write!(f, "GPU read-back failed: {e}"),
            GpuError::Input(e) => write!(f, "bad input: {e}"),
            GpuError::Filter(e) => write!(f, "bad filter input: {e}"),
            GpuError::Unsupported(e) => write!(f, "unsupported: {e}"),
        }
    }
}

impl std::error::Error for GpuError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            GpuError::Input(e) => Some(e),
            GpuError::Filter(e) => Some(e),
            _ => None,
        }
    }
}

impl From<sampler_core::Error> for GpuError {
    fn from(e: sampler_core::Error) -> Self {
        GpuError::Input(e)
    }
}
