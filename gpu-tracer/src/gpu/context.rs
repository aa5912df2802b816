//! Adapter and device selection, the shader module, and buffer helpers.

use super::GpuError;
use bytemuck::Pod;
use std::sync::OnceLock;
use wgpu::util::DeviceExt;

/// The committed SPIR-V module of the `kernels` crate, built by rust-gpu
/// (`gpu-tracer/build-shaders.sh`; CI checks it is fresh).
pub const KERNELS_SPV: &[u8] = include_bytes!("../../shaders/kernels.spv");

/// Environment variable that, when set to `1`, turns a GPU test's skip (no
/// adapter) into a failure. CI sets it.
pub const REQUIRE_GPU_ENV: &str = "BLUENOISE_REQUIRE_GPU";

/// A wgpu device with the kernels module loaded.
#[derive(Debug)]
pub struct Gpu {
    /// The logical device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// Which adapter this is (name, backend, device type).
    pub info: wgpu::AdapterInfo,
    /// True when the device records GPU timestamps (pass timing).
    pub timestamps: bool,
    module: wgpu::ShaderModule,
}

impl Gpu {
    /// Opens the first Vulkan adapter (a real GPU is preferred; Mesa's
    /// lavapipe software rasteriser also qualifies) and loads the kernels.
    ///
    /// # Errors
    /// [`GpuError::NoAdapter`] where no adapter exists, [`GpuError::Device`]
    /// if the device cannot be created, [`GpuError::Validation`] if the
    /// shader module is rejected.
    pub fn new() -> Result<Self, GpuError> {
        Self::from_instance(wgpu::Instance::new(
            wgpu::InstanceDescriptor::new_without_display_handle().with_env(),
        ))
    }

    /// A device of wgpu's no-op backend: validates the kernels module,
    /// pipelines and bind groups (naga's SPIR-V front end, layouts) without
    /// any GPU; dispatches do nothing.
    ///
    /// # Errors
    /// As [`Gpu::new`].
    pub fn noop() -> Result<Self, GpuError> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        desc.backends = wgpu::Backends::NOOP;
        desc.backend_options.noop.enable = true;
        Self::from_instance(wgpu::Instance::new(desc))
    }

    /// Which adapter [`Gpu::new`] would open, without creating a device or
    /// loading the kernels (cheap: lets a caller skip a software adapter).
    ///
    /// # Errors
    /// [`GpuError::NoAdapter`] where no adapter exists.
    pub fn probe() -> Result<wgpu::AdapterInfo, GpuError> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle().with_env());
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            ..Default::default()
        }))
        .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        Ok(adapter.get_info())
    }

    fn from_instance(instance: wgpu::Instance) -> Result<Self, GpuError> {
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            ..Default::default()
        }))
        .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let info = adapter.get_info();
        let timestamps = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let mut required_features = wgpu::Features::empty();
        if timestamps {
            required_features |= wgpu::Features::TIMESTAMP_QUERY;
        }
        let adapter_limits = adapter.limits();
        let need = kernels::abi::MAX_STORAGE_BUFFERS_PER_STAGE;
        if adapter_limits.max_storage_buffers_per_shader_stage < need {
            return Err(GpuError::Device(format!(
                "adapter {} offers {} storage buffers per shader stage; the trace pass binds {need}",
                info.name, adapter_limits.max_storage_buffers_per_shader_stage
            )));
        }
        let required_limits = wgpu::Limits {
            max_storage_buffer_binding_size: adapter_limits.max_storage_buffer_binding_size,
            max_buffer_size: adapter_limits.max_buffer_size,
            max_storage_buffers_per_shader_stage: adapter_limits.max_storage_buffers_per_shader_stage.min(16),
            ..wgpu::Limits::downlevel_defaults()
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("gpu-tracer"),
            required_features,
            required_limits,
            ..Default::default()
        }))
        .map_err(|e| GpuError::Device(e.to_string()))?;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("kernels.spv"),
            source: wgpu::util::make_spirv(KERNELS_SPV),
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Validation(format!("kernels.spv: {e}")));
        }
        Ok(Gpu {
            device,
            queue,
            info,
            timestamps,
            module,
        })
    }

    /// Opens a GPU for a test, or explains why the test is skipped.
    ///
    /// Returns `None` (after printing the reason) where no adapter exists,
    /// unless [`REQUIRE_GPU_ENV`] is `1`, in which case it panics so CI fails.
    ///
    /// # Panics
    /// Also when an adapter exists but the device or the kernels module
    /// cannot be created: that is a bug, not a missing GPU.
    pub fn for_test(test: &str) -> Option<Self> {
        match Gpu::new() {
            Ok(gpu) => {
                eprintln!(
                    "{test}: running on {} ({:?}, {:?})",
                    gpu.info.name, gpu.info.backend, gpu.info.device_type
                );
                Some(gpu)
            }
            Err(e @ GpuError::NoAdapter(_)) => {
                if std::env::var(REQUIRE_GPU_ENV).as_deref() == Ok("1") {
                    panic!("{test}: no usable GPU adapter and {REQUIRE_GPU_ENV}=1: {e}");
                }
                eprintln!("SKIPPED {test}: {e}; set {REQUIRE_GPU_ENV}=1 to fail instead");
                None
            }
            // An adapter exists but the device or our kernels are broken: a real failure.
            Err(e) => panic!("{test}: {e}"),
        }
    }

    /// A one-line description of the adapter, e.g. `llvmpipe (Vulkan, Cpu)`.
    pub fn describe(&self) -> String {
        format!(
            "{} ({:?}, {:?})",
            self.info.name, self.info.backend, self.info.device_type
        )
    }

    /// Creates the compute pipeline of entry point `entry` with a layout
    /// reflected from the module.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if wgpu rejects it.
    pub fn pipeline(&self, entry: &str) -> Result<wgpu::ComputePipeline, GpuError> {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let pipeline = self
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: None,
                module: &self.module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            });
        match pollster::block_on(scope.pop()) {
            Some(e) => Err(GpuError::Validation(format!("pipeline {entry}: {e}"))),
            None => Ok(pipeline),
        }
    }

    /// A bind group layout and a pipeline layout of that one group:
    /// binding 0 a uniform buffer, bindings `1..=writable.len()` storage
    /// buffers, read-write where `writable[i - 1]`. For entry points that
    /// share bind groups ([`Gpu::bind_with`], [`Gpu::lazy_pipeline`]).
    pub fn buffer_layout(
        &self,
        label: &str,
        writable: &[bool],
    ) -> (wgpu::BindGroupLayout, wgpu::PipelineLayout) {
        let compute = wgpu::ShaderStages::COMPUTE;
        let buffer = |ty| wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        };
        let mut entries = vec![wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: compute,
            ty: buffer(wgpu::BufferBindingType::Uniform),
            count: None,
        }];
        entries.extend(
            writable
                .iter()
                .enumerate()
                .map(|(i, &w)| wgpu::BindGroupLayoutEntry {
                    binding: i as u32 + 1,
                    visibility: compute,
                    ty: buffer(wgpu::BufferBindingType::Storage { read_only: !w }),
                    count: None,
                }),
        );
        let group = self
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries: &entries,
            });
        let layout = self
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: &[Some(&group)],
                immediate_size: 0,
            });
        (group, layout)
    }

    /// A pipeline of entry point `entry` with the explicit `layout`
    /// ([`Gpu::buffer_layout`]), compiled on the first
    /// [`LazyPipeline::get`]: for kernels a run may not need (the full
    /// trace kernel takes seconds to compile on lavapipe).
    pub fn lazy_pipeline(&self, entry: &'static str, layout: &wgpu::PipelineLayout) -> LazyPipeline {
        LazyPipeline {
            entry,
            device: self.device.clone(),
            module: self.module.clone(),
            layout: layout.clone(),
            pipeline: OnceLock::new(),
        }
    }

    /// A bind group of `buffers` (binding `i` = `buffers[i]`, whole
    /// buffers) for the bind group layout `group`.
    pub fn bind_with(&self, group: &wgpu::BindGroupLayout, buffers: &[&wgpu::Buffer]) -> wgpu::BindGroup {
        let entries: Vec<wgpu::BindGroupEntry<'_>> = buffers
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: b.as_entire_binding(),
            })
            .collect();
        self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: group,
            entries: &entries,
        })
    }

    /// A storage buffer initialised with `data` (at least one element is
    /// allocated: wgpu refuses empty bindings). Usable as copy source and
    /// destination.
    pub fn storage<T: Pod>(&self, label: &str, data: &[T]) -> wgpu::Buffer {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let padded;
        let contents = if bytes.is_empty() {
            padded = [0u8; 16];
            &padded[..]
        } else {
            bytes
        };
        self.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        })
    }

    /// A zeroed storage buffer of `len` elements of `T` (at least one).
    pub fn storage_zeroed<T: Pod>(&self, label: &str, len: usize) -> wgpu::Buffer {
        self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: (len.max(1) * std::mem::size_of::<T>()) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    }

    /// A uniform buffer holding `value`, rewritable with `queue.write_buffer`.
    pub fn uniform<T: Pod>(&self, label: &str, value: &T) -> wgpu::Buffer {
        self.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytemuck::bytes_of(value),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        })
    }

    /// A bind group for `pipeline`'s group 0 with `buffers` at bindings
    /// `0..buffers.len()`, in order.
    pub fn bind(&self, pipeline: &wgpu::ComputePipeline, buffers: &[&wgpu::Buffer]) -> wgpu::BindGroup {
        self.bind_with(&pipeline.get_bind_group_layout(0), buffers)
    }

    /// Copies `len` elements of `buffer` back to the host (blocking).
    ///
    /// # Errors
    /// [`GpuError::Readback`] if mapping fails or the device is lost.
    pub fn read<T: Pod>(&self, buffer: &wgpu::Buffer, len: usize) -> Result<Vec<T>, GpuError> {
        let size = (len * std::mem::size_of::<T>()) as u64;
        if size == 0 {
            return Ok(Vec::new());
        }
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = self.device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, size);
        self.queue.submit([encoder.finish()]);
        let slice = staging.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        rx.recv()
            .map_err(|e| GpuError::Readback(e.to_string()))?
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        let view = slice
            .get_mapped_range()
            .map_err(|e| GpuError::Readback(format!("{e:?}")))?;
        let out = bytemuck::pod_collect_to_vec(&view);
        drop(view);
        staging.unmap();
        Ok(out)
    }

    /// Waits until all submitted work is done.
    ///
    /// # Errors
    /// [`GpuError::Readback`] if the device is lost.
    pub fn wait(&self) -> Result<(), GpuError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| GpuError::Readback(e.to_string()))
    }
}

/// Workgroups needed to cover `n` invocations with `size` per group.
pub fn groups(n: u32, size: u32) -> u32 {
    n.div_ceil(size)
}

/// A compute pipeline compiled on first use ([`Gpu::lazy_pipeline`]).
#[derive(Debug)]
pub struct LazyPipeline {
    entry: &'static str,
    device: wgpu::Device,
    module: wgpu::ShaderModule,
    layout: wgpu::PipelineLayout,
    pipeline: OnceLock<wgpu::ComputePipeline>,
}

impl LazyPipeline {
    /// The pipeline, compiled now if it has not been yet.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if wgpu rejects it (then the next call
    /// tries again).
    pub fn get(&self) -> Result<&wgpu::ComputePipeline, GpuError> {
        if let Some(p) = self.pipeline.get() {
            return Ok(p);
        }
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let pipeline = self
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(self.entry),
                layout: Some(&self.layout),
                module: &self.module,
                entry_point: Some(self.entry),
                compilation_options: Default::default(),
                cache: None,
            });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Validation(format!("pipeline {}: {e}", self.entry)));
        }
        Ok(self.pipeline.get_or_init(|| pipeline))
    }
}
