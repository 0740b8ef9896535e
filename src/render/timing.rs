//! Per-pass GPU times from timestamp queries: each pass writes a timestamp at its start and
//! end; after the frame the pairs are resolved, read back and scaled by the queue's period.

use std::cell::Cell;

use crate::error::Result;
use crate::gpu::{map_and_read, Gpu};

/// The passes that are timed, in the order of their query pairs: the occluders' depth
/// pass, the depth pyramid, the patch pass, the blade update, the blade cull and the draw;
/// then, with grass occlusion, the pyramid again, the late cull and the late draw; and the
/// generation of the tiles entering a streamed field. A pass that did not run in a frame
/// reads 0.
pub const PASSES: [&str; 10] = [
    "occluders",
    "pyramid",
    "patches",
    "update",
    "cull",
    "draw",
    "late pyramid",
    "late cull",
    "late draw",
    "tiles",
];
/// Indices into [`PASSES`].
pub const OCCLUDERS: usize = 0;
pub const PYRAMID: usize = 1;
pub const PATCHES: usize = 2;
pub const UPDATE: usize = 3;
pub const CULL: usize = 4;
pub const DRAW: usize = 5;
pub const LATE_PYRAMID: usize = 6;
pub const LATE_CULL: usize = 7;
pub const LATE_DRAW: usize = 8;
pub const TILES: usize = 9;

/// Timestamp query set and its read-back buffers.
pub struct GpuTimer {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    staging: wgpu::Buffer,
    period_ns: f32,
    /// Bit i: pass i was given timestamp writes since the last resolve.
    recorded: Cell<u32>,
    /// `recorded` at the last resolve: the passes whose times the staging buffer holds.
    resolved: Cell<u32>,
}

impl GpuTimer {
    /// `None` when the device has no timestamp queries.
    pub fn new(gpu: &Gpu) -> Option<Self> {
        if !gpu.timestamps {
            return None;
        }
        let count = (PASSES.len() * 2) as u32;
        let queries = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("sward.timestamps"),
            ty: wgpu::QueryType::Timestamp,
            count,
        });
        let size = count as u64 * 8;
        let resolve = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.timestamps.resolve"),
            size,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let staging = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.timestamps.staging"),
            size,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        Some(Self {
            queries,
            resolve,
            staging,
            period_ns: gpu.queue.get_timestamp_period(),
            recorded: Cell::new(0),
            resolved: Cell::new(0),
        })
    }

    /// Compute-pass timestamp writes for pass `index` of `PASSES`.
    pub fn compute(&self, index: usize) -> wgpu::ComputePassTimestampWrites<'_> {
        self.recorded.set(self.recorded.get() | 1 << index);
        wgpu::ComputePassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: Some(index as u32 * 2),
            end_of_pass_write_index: Some(index as u32 * 2 + 1),
        }
    }

    /// Render-pass timestamp writes for pass `index` of `PASSES`.
    pub fn render(&self, index: usize) -> wgpu::RenderPassTimestampWrites<'_> {
        self.recorded.set(self.recorded.get() | 1 << index);
        wgpu::RenderPassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: Some(index as u32 * 2),
            end_of_pass_write_index: Some(index as u32 * 2 + 1),
        }
    }

    /// Records the resolve and copy; call after the timed passes, before `finish`.
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        self.resolved.set(self.recorded.replace(0));
        let count = (PASSES.len() * 2) as u32;
        encoder.resolve_query_set(&self.queries, 0..count, &self.resolve, 0);
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.staging, 0, count as u64 * 8);
    }

    /// Milliseconds per pass of the last submitted frame (blocks until it is done); 0 for
    /// passes that did not run in it (their queries hold nothing of that frame).
    pub fn read_ms(&self, gpu: &Gpu) -> Result<[f64; PASSES.len()]> {
        let bytes = map_and_read(gpu, &self.staging)?;
        let stamps: Vec<u64> = bytemuck::pod_collect_to_vec(&bytes);
        let mut out = [0.0; PASSES.len()];
        let resolved = self.resolved.get();
        for (i, o) in out.iter_mut().enumerate() {
            if resolved & (1 << i) == 0 {
                continue;
            }
            let ticks = stamps[2 * i + 1].saturating_sub(stamps[2 * i]);
            *o = ticks as f64 * self.period_ns as f64 / 1e6;
        }
        Ok(out)
    }
}
