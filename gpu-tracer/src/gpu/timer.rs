//! GPU pass timing with timestamp queries.

use super::context::Gpu;
use super::GpuError;

/// Timestamps around `spans` compute passes: span `i` records its
/// beginning at query `2 i` and its end at `2 i + 1`.
#[derive(Debug)]
pub struct PassTimer {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    spans: u32,
}

impl PassTimer {
    /// A timer for `spans` passes, or `None` where the device has no
    /// timestamp queries.
    pub fn new(gpu: &Gpu, spans: u32) -> Option<Self> {
        if !gpu.timestamps {
            return None;
        }
        let count = 2 * spans;
        let queries = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("pass timer"),
            ty: wgpu::QueryType::Timestamp,
            count,
        });
        let resolve = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("pass timer resolve"),
            size: count as u64 * 8,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        Some(PassTimer {
            queries,
            resolve,
            spans,
        })
    }

    /// Timestamp writes for span `span` of a compute pass.
    pub fn writes(&self, span: u32) -> wgpu::ComputePassTimestampWrites<'_> {
        wgpu::ComputePassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: Some(2 * span),
            end_of_pass_write_index: Some(2 * span + 1),
        }
    }

    /// Encodes the resolution of every timestamp (after the timed passes).
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.resolve_query_set(&self.queries, 0..2 * self.spans, &self.resolve, 0);
    }

    /// Duration of each span in milliseconds (blocking read-back).
    ///
    /// # Errors
    /// [`GpuError::Readback`].
    pub fn read_ms(&self, gpu: &Gpu) -> Result<Vec<f64>, GpuError> {
        let ticks: Vec<u64> = gpu.read(&self.resolve, 2 * self.spans as usize)?;
        let period_ns = gpu.queue.get_timestamp_period() as f64;
        Ok(ticks
            .chunks(2)
            .map(|c| c[1].wrapping_sub(c[0]) as f64 * period_ns * 1e-6)
            .collect())
    }
}
