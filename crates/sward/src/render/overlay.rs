//! The wind overlay (`--wind-overlay`): a second render pass over the finished frame that
//! shows the fluid velocity (colour layer + arrow glyphs) and the AGC guide arrows.

use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use super::draw::read_storage;
use super::mesh::{terrain_mesh, TerrainVertex};
use crate::field::HeightField;
use crate::gpu::Gpu;
use crate::shaders;
use crate::sim::update::uniform_entry;
use crate::sim::wind_layout::{ArrowGpu, MAX_ARROWS};

/// Glyphs per side of the arrow lattice.
pub const GLYPHS: u32 = 32;
/// Air speed (m/s) that maps to full colour and full glyph length.
pub const FULL_SPEED: f32 = 3.0;

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
struct OverlayUniforms {
    grid: [f32; 4],
    info: [u32; 4],
    extra: [f32; 4],
}

const _: () = assert!(std::mem::size_of::<OverlayUniforms>() == 48);

/// Pipelines and buffers of the overlay.
pub struct OverlayPass {
    field: wgpu::RenderPipeline,
    glyph: wgpu::RenderPipeline,
    guide: wgpu::RenderPipeline,
    group: wgpu::BindGroup,
    uniforms: wgpu::Buffer,
    arrows: wgpu::Buffer,
    arrow_count: u32,
    /// The strongest guide's strength (the arrows' colour scale).
    max_strength: f32,
    terrain_vertices: wgpu::Buffer,
    terrain_indices: wgpu::Buffer,
    terrain_count: u32,
    grid: [f32; 4],
    resolution: u32,
    terrain_size: f32,
}

impl OverlayPass {
    /// `samples`: the 3D passes' sample count (it draws into their multisampled colour).
    /// `velocity` is the solver's grid (`resolution`², corner `origin`, cell `cell_size`).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        gpu: &Gpu,
        format: wgpu::TextureFormat,
        samples: u32,
        frame: &wgpu::Buffer,
        velocity: &wgpu::Buffer,
        resolution: u32,
        origin: [f32; 2],
        cell_size: f32,
        terrain: &HeightField,
    ) -> Self {
        let device = &gpu.device;
        let module = shaders::module(device, "overlay.wgsl");
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.overlay.layout"),
            entries: &[
                uniform_entry(0, vf),
                uniform_entry(1, vf),
                read_storage(2, vf),
                read_storage(3, vf),
                read_storage(4, vf),
            ],
        });
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.overlay.uniforms"),
            size: std::mem::size_of::<OverlayUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let arrows = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.overlay.arrows"),
            size: (MAX_ARROWS * std::mem::size_of::<ArrowGpu>()) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let heights = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("sward.overlay.heights"),
            contents: bytemuck::cast_slice(&terrain.heights),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sward.overlay.group"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: frame.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: uniforms.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: velocity.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: arrows.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: heights.as_entire_binding(),
                },
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sward.overlay.pipeline_layout"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let terrain_attrs = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];
        let terrain_buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<TerrainVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &terrain_attrs,
        })];
        let make =
            |label: &str, vs: &str, buffers: &[Option<wgpu::VertexBufferLayout>], fs: &str| {
                device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some(label),
                    layout: Some(&pipeline_layout),
                    vertex: wgpu::VertexState {
                        module: &module,
                        entry_point: Some(vs),
                        compilation_options: Default::default(),
                        buffers,
                    },
                    primitive: wgpu::PrimitiveState::default(),
                    depth_stencil: None,
                    multisample: wgpu::MultisampleState {
                        count: samples,
                        ..Default::default()
                    },
                    fragment: Some(wgpu::FragmentState {
                        module: &module,
                        entry_point: Some(fs),
                        compilation_options: Default::default(),
                        targets: &[Some(wgpu::ColorTargetState {
                            format,
                            blend: Some(wgpu::BlendState::ALPHA_BLENDING),
                            write_mask: wgpu::ColorWrites::ALL,
                        })],
                    }),
                    multiview_mask: None,
                    cache: None,
                })
            };
        let (tv, ti) = terrain_mesh(terrain);
        Self {
            field: make(
                "sward.overlay.field",
                "vs_field",
                &terrain_buffers,
                "fs_field",
            ),
            glyph: make("sward.overlay.glyph", "vs_glyph", &[], "fs_line"),
            guide: make("sward.overlay.guide", "vs_guide", &[], "fs_line"),
            group,
            uniforms,
            arrows,
            arrow_count: 0,
            max_strength: 1e-3,
            terrain_vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("sward.overlay.terrain_vertices"),
                contents: bytemuck::cast_slice::<TerrainVertex, u8>(&tv),
                usage: wgpu::BufferUsages::VERTEX,
            }),
            terrain_indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("sward.overlay.terrain_indices"),
                contents: bytemuck::cast_slice(&ti),
                usage: wgpu::BufferUsages::INDEX,
            }),
            terrain_count: ti.len() as u32,
            grid: [origin[0], origin[1], cell_size, FULL_SPEED],
            resolution,
            terrain_size: terrain.size,
        }
    }

    /// Uploads the guide arrows to draw (all of them, at full strength).
    pub fn prepare(&mut self, queue: &wgpu::Queue, arrows: &[ArrowGpu]) {
        let n = arrows.len().min(MAX_ARROWS);
        if n > 0 {
            queue.write_buffer(&self.arrows, 0, bytemuck::cast_slice(&arrows[..n]));
        }
        self.arrow_count = n as u32;
        self.max_strength = arrows.iter().map(|a| a.strength).fold(1e-3, f32::max);
        self.write_uniforms(queue);
    }

    /// Moves the velocity layer with a grid that follows the camera (its corner now).
    pub fn move_grid(&mut self, queue: &wgpu::Queue, origin: [f32; 2]) {
        if [self.grid[0], self.grid[1]] != origin {
            self.grid[0] = origin[0];
            self.grid[1] = origin[1];
            self.write_uniforms(queue);
        }
    }

    fn write_uniforms(&self, queue: &wgpu::Queue) {
        let u = OverlayUniforms {
            grid: self.grid,
            info: [self.resolution, GLYPHS, self.arrow_count, 0],
            extra: [self.terrain_size, 0.03, 0.05, self.max_strength],
        };
        queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&u));
    }

    /// Draws the overlay over `color` (loads, never clears).
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        color: &wgpu::TextureView,
        q: crate::gpu::queries::PassQueries,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("sward.overlay"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: color,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: q.render_writes(),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        q.begin(&mut pass);
        pass.set_bind_group(0, &self.group, &[]);
        pass.set_pipeline(&self.field);
        pass.set_vertex_buffer(0, self.terrain_vertices.slice(..));
        pass.set_index_buffer(self.terrain_indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.terrain_count, 0, 0..1);
        pass.set_pipeline(&self.glyph);
        pass.draw(0..9, 0..GLYPHS * GLYPHS);
        if self.arrow_count > 0 {
            pass.set_pipeline(&self.guide);
            pass.draw(0..9, 0..self.arrow_count);
        }
        q.end(&mut pass);
    }
}
