//! The scene's mesh objects (`objects`, issue 14): one vertex and index buffer per object
//! (positions and area-weighted normals from [`crate::mesh`]), a uniform with its model
//! matrix and colour, drawn lit in the colour pass and depth-only in the occluder pass, so
//! that an object hides the grass behind it from the depth pyramid like the terrain does.

use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use super::pipelines::{pipeline, PipelineSpec};
use crate::mesh::Mesh;
use crate::scene::MeshObject;
use crate::sim::update::uniform_entry;

/// `MeshObject` in `mesh.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
struct ObjectUniforms {
    model: [[f32; 4]; 4],
    normal: [[f32; 4]; 4],
    color: [f32; 4],
}

const _: () = assert!(std::mem::size_of::<ObjectUniforms>() == 144);

/// One object on the GPU.
struct GpuObject {
    uniform: wgpu::Buffer,
    color: [f32; 4],
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    group: wgpu::BindGroup,
}

/// The objects' buffers and their two pipelines (colour and depth-only).
pub struct ObjectsPass {
    objects: Vec<GpuObject>,
    layout: wgpu::BindGroupLayout,
    format: wgpu::TextureFormat,
    samples: u32,
    colour: wgpu::RenderPipeline,
    depth: wgpu::RenderPipeline,
    /// Into the sun's shadow cascades.
    shadow: wgpu::RenderPipeline,
}

const VERTEX_ATTRIBUTES: [wgpu::VertexAttribute; 2] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];

/// The uniforms of an object placed by `model`.
fn uniforms_of(model: glam::Mat4, color: [f32; 4]) -> ObjectUniforms {
    let normal = glam::Mat4::from_mat3(glam::Mat3::from_mat4(model).inverse().transpose());
    ObjectUniforms {
        model: model.to_cols_array_2d(),
        normal: normal.to_cols_array_2d(),
        color,
    }
}

fn vertex_layout() -> [Option<wgpu::VertexBufferLayout<'static>>; 1] {
    [Some(wgpu::VertexBufferLayout {
        array_stride: 24,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &VERTEX_ATTRIBUTES,
    })]
}

impl ObjectsPass {
    /// Uploads `meshes` (the session's, checked against the adapter) placed by `objects`;
    /// `frame` is the draw pass's frame uniform.
    pub fn new(
        device: &wgpu::Device,
        objects: &[MeshObject],
        meshes: &[Mesh],
        frame: &wgpu::Buffer,
        format: wgpu::TextureFormat,
        samples: u32,
    ) -> Self {
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.objects.layout"),
            entries: &[uniform_entry(0, vf), uniform_entry(1, vf)],
        });
        let gpu_objects = objects
            .iter()
            .zip(meshes)
            .enumerate()
            .map(|(i, (object, mesh))| {
                let vertices: Vec<[f32; 6]> = mesh
                    .positions
                    .iter()
                    .zip(&mesh.normals)
                    .map(|(p, n)| [p[0], p[1], p[2], n[0], n[1], n[2]])
                    .collect();
                let c = object.color;
                let color = [c.0, c.1, c.2, 1.0];
                let uniforms = uniforms_of(object.transform(), color);
                // COPY_DST: a moving object's transform is rewritten every frame.
                let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(&format!("sward.objects.{i}.uniforms")),
                    contents: bytemuck::bytes_of(&uniforms),
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                });
                GpuObject {
                    color,
                    vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: Some(&format!("sward.objects.{i}.vertices")),
                        contents: bytemuck::cast_slice(&vertices),
                        // STORAGE: an animated object's skinning pass writes its pose here;
                        // COPY_SRC: its twin test reads it back.
                        usage: wgpu::BufferUsages::VERTEX
                            | wgpu::BufferUsages::STORAGE
                            | wgpu::BufferUsages::COPY_SRC,
                    }),
                    indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: Some(&format!("sward.objects.{i}.indices")),
                        contents: bytemuck::cast_slice(&mesh.indices),
                        usage: wgpu::BufferUsages::INDEX,
                    }),
                    index_count: mesh.indices.len() as u32,
                    uniform: uniform.clone(),
                    group: device.create_bind_group(&wgpu::BindGroupDescriptor {
                        label: Some(&format!("sward.objects.{i}.group")),
                        layout: &layout,
                        entries: &[
                            wgpu::BindGroupEntry {
                                binding: 0,
                                resource: frame.as_entire_binding(),
                            },
                            wgpu::BindGroupEntry {
                                binding: 1,
                                resource: uniform.as_entire_binding(),
                            },
                        ],
                    }),
                }
            })
            .collect();
        let (colour, depth) = Self::pipelines(device, &layout, format, samples);
        let buffers = vertex_layout();
        let shadow = super::pipelines::shadow_pipeline(
            device,
            "sward.objects.shadow",
            ("mesh.wgsl", "vs_main"),
            &layout,
            &buffers,
            &[],
        );
        Self {
            objects: gpu_objects,
            layout,
            format,
            samples,
            colour,
            depth,
            shadow,
        }
    }

    fn pipelines(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        format: wgpu::TextureFormat,
        samples: u32,
    ) -> (wgpu::RenderPipeline, wgpu::RenderPipeline) {
        let buffers = vertex_layout();
        let spec = |label, depth_only| PipelineSpec {
            label,
            shader: "mesh.wgsl",
            vertex: "vs_main",
            layout,
            buffers: &buffers,
            depth_write: true,
            // Meshes may be open or wound either way: draw both sides.
            cull_back: false,
            lines: false,
            depth_only,
            constants: &[],
        };
        (
            pipeline(device, format, samples, spec("sward.objects.colour", false)),
            pipeline(device, format, samples, spec("sward.objects.depth", true)),
        )
    }

    /// Places object i by `models[i]` from the next frame on (moving objects).
    pub fn set_transforms(&self, queue: &wgpu::Queue, models: &[glam::Mat4]) {
        for (object, model) in self.objects.iter().zip(models) {
            let uniforms = uniforms_of(*model, object.color);
            queue.write_buffer(&object.uniform, 0, bytemuck::bytes_of(&uniforms));
        }
    }

    /// Rebuilds the colour and depth pipelines for targets of `samples` MSAA samples; does
    /// nothing when the count is unchanged.
    pub fn set_samples(&mut self, device: &wgpu::Device, samples: u32) {
        if samples != self.samples {
            self.samples = samples;
            (self.colour, self.depth) = Self::pipelines(device, &self.layout, self.format, samples);
        }
    }

    /// Object `i`'s vertex buffer (position, normal: six floats a vertex).
    pub fn vertex_buffer(&self, i: usize) -> Option<&wgpu::Buffer> {
        self.objects.get(i).map(|o| &o.vertices)
    }

    /// Whether the scene has no mesh objects to draw.
    pub fn is_empty(&self) -> bool {
        self.objects.is_empty()
    }

    /// Draws every object into a shadow cascade (the frame buffer holds its view).
    pub fn draw_shadow(&self, pass: &mut wgpu::RenderPass<'_>) {
        if self.objects.is_empty() {
            return;
        }
        pass.set_pipeline(&self.shadow);
        for o in &self.objects {
            pass.set_bind_group(0, &o.group, &[]);
            pass.set_vertex_buffer(0, o.vertices.slice(..));
            pass.set_index_buffer(o.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..o.index_count, 0, 0..1);
        }
    }

    /// Draws every object lit (`depth_only` false) or into the depth only.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, depth_only: bool) {
        if self.objects.is_empty() {
            return;
        }
        pass.set_pipeline(if depth_only {
            &self.depth
        } else {
            &self.colour
        });
        for o in &self.objects {
            pass.set_bind_group(0, &o.group, &[]);
            pass.set_vertex_buffer(0, o.vertices.slice(..));
            pass.set_index_buffer(o.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..o.index_count, 0, 0..1);
        }
    }
}
