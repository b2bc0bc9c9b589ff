//! GPU-side phase times from timestamp queries, where the adapter has them.
//!
//! The wall-clock times (submit to fence) include submitting the work and
//! waiting for the fence. Timestamps the GPU writes at the start of a
//! phase's first pass and at the end of its last pass give the GPU's own
//! time for the phase.

use crate::error::RenderError;
use crate::gpu::Gpu;
use crate::passes::readback::Readback;

/// First query slot of the shadow phase (start, end).
pub(crate) const SHADOW_PHASE: u32 = 0;
/// First query slot of the main phase (start, end).
pub(crate) const MAIN_PHASE: u32 = 2;
const SLOTS: u32 = 4;
const BYTES: u32 = SLOTS * wgpu::QUERY_SIZE;

pub(crate) struct PhaseTimer {
    set: wgpu::QuerySet,
    resolved: wgpu::Buffer,
    /// Nanoseconds per timestamp tick.
    period_ns: f64,
}

impl PhaseTimer {
    /// `None` when the device was opened without timestamp queries.
    pub(crate) fn new(gpu: &Gpu) -> Option<PhaseTimer> {
        if !gpu.summary.timestamps {
            return None;
        }
        let device = &gpu.device;
        let set =
            device.create_query_set(&wgpu::QuerySetDescriptor { label: Some("phase times"), ty: wgpu::QueryType::Timestamp, count: SLOTS });
        let resolved = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("phase times"),
            size: BYTES as u64,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        Some(PhaseTimer { set, resolved, period_ns: gpu.queue.get_timestamp_period() as f64 })
    }

    /// The timestamp writes of pass `index` of the `count` passes of the
    /// phase whose slots start at `phase`: the first pass writes the start,
    /// the last the end.
    pub(crate) fn writes(&self, phase: u32, index: usize, count: usize) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        let (first, last) = (index == 0, index + 1 == count);
        (first || last).then_some(wgpu::RenderPassTimestampWrites {
            query_set: &self.set,
            beginning_of_pass_write_index: first.then_some(phase),
            end_of_pass_write_index: last.then_some(phase + 1),
        })
    }

    /// The shadow and main phases' GPU times in milliseconds, once their
    /// work has been submitted; `None` for a phase whose end timestamp is
    /// not after its start (a phase with no pass, or a driver that does not
    /// count).
    pub(crate) fn read(&self, gpu: &Gpu) -> Result<[Option<f64>; 2], RenderError> {
        let mut enc = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("phase times") });
        enc.resolve_query_set(&self.set, 0..SLOTS, &self.resolved, 0);
        let mut rb = Readback::default();
        let slot = rb.add_buffer(&gpu.device, &mut enc, &self.resolved, BYTES);
        gpu.queue.submit([enc.finish()]);
        let ticks: Vec<u64> = bytemuck::pod_collect_to_vec(&rb.finish(gpu)?[slot]);
        let ms = |phase: usize| {
            let (start, end) = (ticks[phase], ticks[phase + 1]);
            (end > start).then(|| (end - start) as f64 * self.period_ns * 1e-6)
        };
        Ok([ms(SHADOW_PHASE as usize), ms(MAIN_PHASE as usize)])
    }
}
