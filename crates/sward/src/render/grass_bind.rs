//! The grass draw's bind groups: the frame, the blades, the visible lists, the cull
//! uniforms, the level, the cull's counts, and for the blade models the update's uniforms,
//! the wind grid (CWD-Sim's blades bend in the vertex shader) and the Verlet states (the
//! thesis's blades are cubic), the blade states (η, for the trail colour view) and the sun
//! along each blade (the deferred shading's). Rebuilt when the wind grid or the Verlet
//! states change.

use super::draw::read_storage;
use crate::sim::update::{compute_storage_entry, uniform_entry, whole, BladeBuffers};

/// What the grass groups bind besides the model's buffers, kept to rebuild them.
pub struct GrassBindings {
    /// The grass bind group's layout (bindings 0 to 11), shared by the grass pipelines and
    /// the deferred shading's compute passes.
    pub layout: wgpu::BindGroupLayout,
    frame: wgpu::Buffer,
    blades: wgpu::Buffer,
    states: wgpu::Buffer,
    visible: wgpu::Buffer,
    /// The sun along each blade (`BladeBuffers::sun`), for the deferred shading.
    sun: wgpu::Buffer,
    cull_params: wgpu::Buffer,
    cull_output: wgpu::Buffer,
    /// The field's species and clumps (`FieldTraits`).
    traits: wgpu::Buffer,
    /// Per group: its level uniform and the region of the visible list it binds (offset,
    /// size; `None`: to the end).
    levels: Vec<(wgpu::Buffer, u64, Option<u64>)>,
}

/// The buffers the blade models add to the grass draw.
#[derive(Clone, Copy)]
pub struct ModelBuffers<'a> {
    /// The update's `SimParams` (the model, CWD-Sim's parameters, the wind's).
    pub sim_params: &'a wgpu::Buffer,
    /// The wind solver's velocity grid (`vec2` per cell, m/s), for CWD-Sim's vertex bend.
    pub wind_grid: &'a wgpu::Buffer,
    /// The Verlet blades' states (`VerletState` per blade), for the cubic blade model.
    pub verlet: &'a wgpu::Buffer,
}

impl GrassBindings {
    /// Creates the layout and keeps the sources: the frame uniforms, the blade buffers, the
    /// cull's uniforms and counts, one level uniform and visible-list region per group, and
    /// the field's traits (uploaded here).
    pub fn new(
        device: &wgpu::Device,
        frame: &wgpu::Buffer,
        buffers: &BladeBuffers,
        cull_params: &wgpu::Buffer,
        cull_output: &wgpu::Buffer,
        levels: Vec<(wgpu::Buffer, u64, Option<u64>)>,
        traits: &crate::field::clumps::FieldTraits,
    ) -> Self {
        // The deferred shading's compute passes bind the same group (`render::deferred`).
        let compute = wgpu::ShaderStages::COMPUTE;
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT | compute;
        let vertex = wgpu::ShaderStages::VERTEX | compute;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.draw.grass_layout"),
            entries: &[
                read_storage(0, vf),
                read_storage(1, vertex),
                read_storage(2, vertex),
                uniform_entry(3, vertex),
                uniform_entry(4, vertex),
                read_storage(5, vertex),
                uniform_entry(6, vertex),
                read_storage(7, vertex),
                read_storage(8, vertex),
                read_storage(9, vertex),
                uniform_entry(10, vf),
                // The sun along the drawn blades: written and read by the deferred
                // shading's compute passes only.
                compute_storage_entry(11, false),
            ],
        });
        let traits = wgpu::util::DeviceExt::create_buffer_init(
            device,
            &wgpu::util::BufferInitDescriptor {
                label: Some("sward.draw.field_traits"),
                contents: bytemuck::bytes_of(traits),
                usage: wgpu::BufferUsages::UNIFORM,
            },
        );
        Self {
            layout,
            traits,
            frame: frame.clone(),
            blades: buffers.blades.clone(),
            states: buffers.states.clone(),
            visible: buffers.visible.clone(),
            sun: buffers.sun.clone(),
            cull_params: cull_params.clone(),
            cull_output: cull_output.clone(),
            levels,
        }
    }

    /// One group per level (or one for all with multi-draw).
    pub fn groups(&self, device: &wgpu::Device, model: ModelBuffers) -> Vec<wgpu::BindGroup> {
        self.levels
            .iter()
            .map(|(level, offset, size)| {
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("sward.draw.grass_group"),
                    layout: &self.layout,
                    entries: &[
                        whole(0, &self.frame),
                        whole(1, &self.blades),
                        wgpu::BindGroupEntry {
                            binding: 2,
                            resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                                buffer: &self.visible,
                                offset: *offset,
                                size: size.and_then(wgpu::BufferSize::new),
                            }),
                        },
                        whole(3, &self.cull_params),
                        whole(4, level),
                        whole(5, &self.cull_output),
                        whole(6, model.sim_params),
                        whole(7, model.wind_grid),
                        whole(8, model.verlet),
                        whole(9, &self.states),
                        whole(10, &self.traits),
                        whole(11, &self.sun),
                    ],
                })
            })
            .collect()
    }
}
