//! Encoding linear dispatches (`kernels::permute_entry::linear_dispatch`) in
//! compute passes: what every pass of the permutation and the reprojection
//! does.

use super::timer::PassTimer;
use kernels::permute_entry::linear_dispatch;

/// One dispatch: the pipeline, its bind group (group 0) and the number of
/// invocations (one per seed, pixel, block or chunk, as the kernel says).
pub(super) type Dispatch<'a> = (&'a wgpu::ComputePipeline, &'a wgpu::BindGroup, u32);

/// Encodes `dispatches` in order in one compute pass labelled `label`, timed
/// as span `span` of `timer` if given. wgpu orders the dispatches of a pass and
/// puts the barriers their storage buffers need between them.
pub(super) fn encode_pass(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    dispatches: &[Dispatch<'_>],
    timer: Option<(&PassTimer, u32)>,
) {
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some(label),
        timestamp_writes: timer.map(|(t, span)| t.writes(span)),
    });
    for &(pipeline, bind_group, n) in dispatches {
        let (x, y) = linear_dispatch(n);
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.dispatch_workgroups(x, y, 1);
    }
}
