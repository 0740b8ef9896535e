//! The GPU side of [`crate::sim::carry`]: the carried blades' rest copies and the objects'
//! motions in storage buffers, and the compute pass (`shaders/carry.wgsl`) that puts the
//! carried blades where their objects are now, recorded before the patch pass.

use wgpu::util::DeviceExt;

use super::carry::{CarriedBlade, CarryObject};
use super::update::{compute_storage_entry, BladeBuffers};
use crate::error::Result;
use crate::gpu::Gpu;
use crate::shaders;

/// The compute pass (`shaders/carry.wgsl`) that moves the carried blades to where their
/// objects are this step, with its rest-copy and object-motion buffers.
pub struct CarryPass {
    pipeline: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    objects: wgpu::Buffer,
    /// Carried blades (invocations).
    count: u32,
    /// Workgroups along x and y (a 2D dispatch stays under the per-dimension limit).
    groups: (u32, u32),
}

impl CarryPass {
    /// Uploads the rest copies of `carried` (checked against the adapter's limits first)
    /// for `objects` moving objects.
    pub fn new(
        gpu: &Gpu,
        buffers: &BladeBuffers,
        carried: &[CarriedBlade],
        objects: usize,
    ) -> Result<Self> {
        let bytes = std::mem::size_of_val(carried) as u64;
        gpu.check_storage("the carried blades' rest copies", bytes)?;
        let device = &gpu.device;
        let rest = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("sward.carry.rest"),
            contents: bytemuck::cast_slice(carried),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let objects = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.carry.objects"),
            size: (objects.max(1) * std::mem::size_of::<CarryObject>()) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.carry.layout"),
            entries: &[
                compute_storage_entry(0, false),
                compute_storage_entry(1, false),
                compute_storage_entry(2, true),
                compute_storage_entry(3, true),
            ],
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sward.carry.bind_group"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: buffers.blades.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: buffers.states.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: rest.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: objects.as_entire_binding(),
                },
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sward.carry.pipeline_layout"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let module = shaders::module(device, "carry.wgsl");
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("sward.carry.pipeline"),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        let count = carried.len() as u32;
        let total = count.div_ceil(64);
        let max = device.limits().max_compute_workgroups_per_dimension.max(1);
        let x = total.clamp(1, max);
        let groups = (x, total.div_ceil(x).max(1));
        Ok(Self {
            pipeline,
            bind_group,
            objects,
            count,
            groups,
        })
    }

    /// This step's motions, one per carried object, in `Carried::objects` order.
    pub fn prepare(&self, queue: &wgpu::Queue, motions: &[CarryObject]) {
        if !motions.is_empty() {
            queue.write_buffer(&self.objects, 0, bytemuck::cast_slice(motions));
        }
    }

    /// Records the carry dispatch (64 blades per workgroup) into `encoder`; records nothing
    /// when there are no carried blades.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder) {
        if self.count == 0 {
            return;
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("sward.carry"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.dispatch_workgroups(self.groups.0, self.groups.1, 1);
    }
}
