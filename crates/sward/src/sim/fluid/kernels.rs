//! The plumbing of the wind solver's compute kernels: bind group layouts from a list of
//! (binding, use) slots, pipelines per entry point, bind groups from buffer lists, and the
//! timestamp queries of the timed passes.

use crate::gpu::Gpu;
use crate::shaders;
use crate::sim::update::{compute_storage_entry, uniform_entry};

/// How a binding of a fluid kernel is used.
#[derive(Clone, Copy)]
pub(super) enum Slot {
    Uniform,
    Read,
    Write,
}

/// One compute entry point: its layout and pipeline.
pub(super) struct Kernel {
    pub layout: wgpu::BindGroupLayout,
    pub pipeline: wgpu::ComputePipeline,
    /// The binding numbers of the layout, in the order `bind` takes its buffers.
    bindings: Vec<u32>,
}

impl Kernel {
    /// Entry point `entry` of `fluid_{file}.wgsl` with consecutive bindings 0, 1, ….
    pub fn new(
        device: &wgpu::Device,
        module: &wgpu::ShaderModule,
        name: &str,
        entry: &str,
        slots: &[Slot],
    ) -> Self {
        let numbered: Vec<_> = slots
            .iter()
            .enumerate()
            .map(|(i, s)| (i as u32, *s))
            .collect();
        Self::with_bindings(device, module, name, entry, &numbered)
    }

    /// Entry point `entry` with the given binding numbers (a module whose entry points use
    /// different subsets of its globals).
    pub fn with_bindings(
        device: &wgpu::Device,
        module: &wgpu::ShaderModule,
        name: &str,
        entry: &str,
        slots: &[(u32, Slot)],
    ) -> Self {
        Self::specialised(device, module, name, entry, slots, &[])
    }

    /// [`Kernel::with_bindings`] with the module's pipeline-overridable constants set
    /// (`override` in WGSL): a constant condition is folded when the pipeline is compiled,
    /// where llvmpipe runs both sides of a branch on a uniform.
    pub fn specialised(
        device: &wgpu::Device,
        module: &wgpu::ShaderModule,
        name: &str,
        entry: &str,
        slots: &[(u32, Slot)],
        constants: &[(&str, f64)],
    ) -> Self {
        let entries: Vec<_> = slots
            .iter()
            .map(|&(binding, slot)| match slot {
                Slot::Uniform => uniform_entry(binding, wgpu::ShaderStages::COMPUTE),
                Slot::Read => compute_storage_entry(binding, true),
                Slot::Write => compute_storage_entry(binding, false),
            })
            .collect();
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(&format!("sward.fluid.{name}.layout")),
            entries: &entries,
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(&format!("sward.fluid.{name}.pipeline_layout")),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(&format!("sward.fluid.{name}.pipeline")),
            layout: Some(&pipeline_layout),
            module,
            entry_point: Some(entry),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants,
                ..Default::default()
            },
            cache: None,
        });
        Self {
            layout,
            pipeline,
            bindings: slots.iter().map(|(b, _)| *b).collect(),
        }
    }

    /// A bind group of `buffers`, one per slot, in slot order.
    ///
    /// # Panics
    /// If the buffer count differs from the slot count (a wiring defect of the solver).
    pub fn bind(
        &self,
        device: &wgpu::Device,
        label: &str,
        buffers: &[&wgpu::Buffer],
    ) -> wgpu::BindGroup {
        assert_eq!(
            buffers.len(),
            self.bindings.len(),
            "bind group {label}: one buffer per slot"
        );
        let entries: Vec<_> = self
            .bindings
            .iter()
            .zip(buffers)
            .map(|(&binding, b)| wgpu::BindGroupEntry {
                binding,
                resource: b.as_entire_binding(),
            })
            .collect();
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(&format!("sward.fluid.{label}.bind_group")),
            layout: &self.layout,
            entries: &entries,
        })
    }
}

/// The module of `fluid_{name}.wgsl`.
pub(super) fn module(device: &wgpu::Device, name: &str) -> wgpu::ShaderModule {
    shaders::module(device, &format!("fluid_{name}.wgsl"))
}

/// Timestamp queries of the fluid passes and their read-back buffers.
pub(super) struct FluidTimer {
    pub queries: wgpu::QuerySet,
    pub resolve: wgpu::Buffer,
    pub staging: wgpu::Buffer,
    pub period_ns: f32,
    pub count: u32,
}

impl FluidTimer {
    /// Two queries (begin, end) per pass; `None` without timestamp queries.
    pub fn new(gpu: &Gpu, passes: usize) -> Option<Self> {
        if !gpu.timestamps {
            return None;
        }
        let count = passes as u32 * 2;
        let size = count as u64 * 8;
        Some(Self {
            queries: gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("sward.fluid.timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count,
            }),
            resolve: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("sward.fluid.timestamps.resolve"),
                size,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            staging: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("sward.fluid.timestamps.staging"),
                size,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            }),
            period_ns: gpu.queue.get_timestamp_period(),
            count,
        })
    }
}
