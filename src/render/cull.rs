//! The cull pass (`shaders/cull.wgsl`): resets the indirect arguments, then tests every
//! blade and appends the survivors to the visible list. Its counters can be read back.

use crate::error::Result;
use crate::gpu::{read_buffer, Gpu};
use crate::shaders;
use crate::sim::layout::{CullCounters, CullParams, WORKGROUP_SIZE};
use crate::sim::update::{compute_storage_entry, uniform_entry, BladeBuffers};

/// Cull pipelines, their uniforms and the indirect-argument buffer the draw reads.
pub struct CullPass {
    reset: wgpu::ComputePipeline,
    cull: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    params: wgpu::Buffer,
    /// `CullCounters`: draw_indexed_indirect arguments + per-test counters.
    pub args: wgpu::Buffer,
    count: u32,
}

impl CullPass {
    pub fn new(gpu: &Gpu, buffers: &BladeBuffers) -> Self {
        let device = &gpu.device;
        let module = shaders::module(device, "cull.wgsl");
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.cull.layout"),
            entries: &[
                uniform_entry(0, wgpu::ShaderStages::COMPUTE),
                compute_storage_entry(1, true),
                compute_storage_entry(2, true),
                compute_storage_entry(3, false),
                compute_storage_entry(4, false),
            ],
        });
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.cull.params"),
            size: std::mem::size_of::<CullParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let args = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.cull.indirect_args"),
            size: std::mem::size_of::<CullCounters>() as u64,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::INDIRECT
                | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sward.cull.bind_group"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: params.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: buffers.blades.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: buffers.patches.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: buffers.visible.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: args.as_entire_binding(),
                },
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sward.cull.pipeline_layout"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let make = |entry: &str, label: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(label),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        Self {
            reset: make("reset", "sward.cull.reset"),
            cull: make("main", "sward.cull.pipeline"),
            bind_group,
            params,
            args,
            count: buffers.count,
        }
    }

    /// Writes this frame's camera and thresholds.
    pub fn prepare(&self, queue: &wgpu::Queue, params: &CullParams) {
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(params));
    }

    /// Records the reset and the cull dispatch in one compute pass (the reset runs first:
    /// wgpu orders dispatches in a pass that write the same buffer).
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        timestamps: Option<wgpu::ComputePassTimestampWrites>,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("sward.cull"),
            timestamp_writes: timestamps,
        });
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.set_pipeline(&self.reset);
        pass.dispatch_workgroups(1, 1, 1);
        if self.count > 0 {
            pass.set_pipeline(&self.cull);
            pass.dispatch_workgroups(self.count.div_ceil(WORKGROUP_SIZE), 1, 1);
        }
    }

    /// Reads the counters of the last frame back (blocking).
    pub fn read_counters(&self, gpu: &Gpu) -> Result<CullCounters> {
        let bytes = read_buffer(gpu, &self.args, std::mem::size_of::<CullCounters>() as u64)?;
        Ok(bytemuck::pod_read_unaligned(&bytes))
    }

    /// Reads the visible blade indices of the last frame back (blocking).
    pub fn read_visible(&self, gpu: &Gpu, buffers: &BladeBuffers) -> Result<Vec<u32>> {
        let counters = self.read_counters(gpu)?;
        let n = counters.drawn() as u64;
        if n == 0 {
            return Ok(Vec::new());
        }
        let bytes = read_buffer(gpu, &buffers.visible, n * 4)?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }
}
