//! The GPU side of [`crate::sim::propagation`]: the force field per cell and the passes of
//! `shaders/propagate.wgsl` (init, one dispatch per generation, apply), recorded right after
//! the blade update, which splats its collision pushes into the update's output buffer.

use wgpu::util::DeviceExt;

use super::layout::PatchDispatch;
use super::propagation::{cells_per_side, MAX_GENERATIONS};
use super::update::{compute_storage_entry, uniform_entry, whole, BladeBuffers};
use crate::error::Result;
use crate::gpu::Gpu;
use crate::scene::Propagation;
use crate::shaders;

/// Bytes of the update's output before the splat: the reset counter and padding.
pub const SPLAT_OFFSET: u64 = 16;

/// Bytes of the update's output for a grid of `n` cells per side.
pub fn update_out_bytes(n: u32) -> u64 {
    SPLAT_OFFSET + 12 * (n as u64 * n as u64).max(1)
}

/// The propagation's compute passes (`shaders/propagate.wgsl`: init, one dispatch per
/// generation, apply) and the force-field buffer they work on.
pub struct PropagationPass {
    init: wgpu::ComputePipeline,
    generation: wgpu::ComputePipeline,
    /// The apply over each update list (`UPDATE_LIST` 0 and 1).
    apply: [wgpu::ComputePipeline; 2],
    /// One bind group per generation (each binds its generation's uniform).
    groups: Vec<wgpu::BindGroup>,
    /// Cells per side the buffers were made for.
    pub n: u32,
    update_out: wgpu::Buffer,
    dispatch: wgpu::Buffer,
    /// The force field, one `vec4<f32>` per cell: EF.x, EF.z, the generation (-1: not
    /// reached), unused (as [`crate::sim::propagation::Field`]); STORAGE | COPY_SRC.
    pub field: wgpu::Buffer,
}

impl PropagationPass {
    /// The field for `propagation`'s grid over `buffers` (whose update output must hold its
    /// splat: [`BladeBuffers::ensure_splat`]); `params` is the update's uniform buffer.
    pub fn new(
        gpu: &Gpu,
        buffers: &BladeBuffers,
        params: &wgpu::Buffer,
        propagation: &Propagation,
    ) -> Result<Self> {
        let n = cells_per_side(propagation);
        let cells = n as u64 * n as u64;
        gpu.check_storage("the propagation grid", cells * 16)?;
        let device = &gpu.device;
        let field = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.propagation.field"),
            size: cells.max(1) * 16,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.propagation.layout"),
            entries: &[
                uniform_entry(0, wgpu::ShaderStages::COMPUTE),
                compute_storage_entry(1, false),
                compute_storage_entry(2, false),
                uniform_entry(3, wgpu::ShaderStages::COMPUTE),
                compute_storage_entry(4, false),
                compute_storage_entry(5, false),
                compute_storage_entry(6, true),
            ],
        });
        let groups = (0..=MAX_GENERATIONS)
            .map(|g| {
                let step = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("sward.propagation.generation"),
                    contents: bytemuck::cast_slice(&[g, 0u32, 0, 0]),
                    usage: wgpu::BufferUsages::UNIFORM,
                });
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("sward.propagation.bind_group"),
                    layout: &layout,
                    entries: &[
                        whole(0, params),
                        whole(1, &buffers.resets),
                        whole(2, &field),
                        whole(3, &step),
                        whole(4, &buffers.blades),
                        whole(5, &buffers.states),
                        whole(6, &buffers.patch_lists),
                    ],
                })
            })
            .collect();
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sward.propagation.pipeline_layout"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let module = shaders::module(device, "propagate.wgsl");
        // `list`: the update list the apply walks (`UPDATE_LIST` in `update_slot.wgsl`).
        let pipeline = |entry: &str, list: u32| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(&format!("sward.propagation.{entry}{}", ["", "_free"][list as usize])),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: &[("UPDATE_LIST", f64::from(list))],
                    ..Default::default()
                },
                cache: None,
            })
        };
        Ok(Self {
            init: pipeline("init", 0),
            generation: pipeline("generation", 0),
            apply: [pipeline("apply", 0), pipeline("apply", 1)],
            groups,
            n,
            update_out: buffers.resets.clone(),
            dispatch: buffers.dispatch.clone(),
            field,
        })
    }

    /// Clears the splat before the update adds this step's pushes.
    pub fn clear(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.clear_buffer(&self.update_out, SPLAT_OFFSET, None);
    }

    /// Records init, `generations` generations and (for Jahrmann's blades) the apply.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, generations: u32, apply: bool) {
        let cells = self.n * self.n;
        let workgroups = cells.div_ceil(64);
        let gx = workgroups.min(65535);
        let gy = workgroups.div_ceil(gx);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("sward.propagation"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.init);
        pass.set_bind_group(0, &self.groups[0], &[]);
        pass.dispatch_workgroups(gx, gy, 1);
        pass.set_pipeline(&self.generation);
        for g in 1..=generations.min(MAX_GENERATIONS) {
            pass.set_bind_group(0, &self.groups[g as usize], &[]);
            pass.dispatch_workgroups(gx, gy, 1);
        }
        if apply {
            // Over both update lists: the patches with a collider near and the others.
            pass.set_bind_group(0, &self.groups[0], &[]);
            for (pipeline, offset) in self.apply.iter().zip(PatchDispatch::UPDATE_OFFSETS) {
                pass.set_pipeline(pipeline);
                pass.dispatch_workgroups_indirect(&self.dispatch, offset);
            }
        }
    }
}
