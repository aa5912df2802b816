//! Which device renders: `--device auto` takes a hardware GPU adapter when
//! one exists and the CPU renderer otherwise (a software rasteriser such as
//! lavapipe is far slower than the native CPU renderer); `gpu` takes any
//! adapter; `cpu` none.

use crate::args::DeviceArg;
use anyhow::{Context, Result};
use gpu_tracer::gpu::{Gpu, GpuError};

/// The GPU to render on, or `None` for the CPU renderer; says on stderr why
/// `auto` fell back to the CPU.
///
/// # Errors
/// `--device gpu` without a usable adapter.
pub(crate) fn open_device(device: DeviceArg) -> Result<Option<Gpu>> {
    Ok(match device {
        DeviceArg::Cpu => None,
        DeviceArg::Gpu => Some(Gpu::new().context("--device gpu was requested")?),
        DeviceArg::Auto => match Gpu::probe().and_then(|info| {
            if info.device_type == wgpu::DeviceType::Cpu {
                Ok(Err(info))
            } else {
                Gpu::new().map(Ok)
            }
        }) {
            Ok(Err(info)) => {
                eprintln!(
                    "notice: the only GPU adapter is a software rasteriser ({} ({:?}, {:?})); the \
                     native CPU renderer is much faster, so it renders (--device gpu forces the adapter)",
                    info.name, info.backend, info.device_type
                );
                None
            }
            Ok(Ok(gpu)) => Some(gpu),
            Err(GpuError::NoAdapter(reason)) => {
                eprintln!("notice: no GPU adapter ({reason}); rendering on the CPU");
                None
            }
            Err(e) => {
                eprintln!("warning: the GPU could not be used ({e}); rendering on the CPU");
                None
            }
        },
    })
}
