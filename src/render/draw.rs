//! The draw pass: sky, terrain, colliders and the grass (one indexed indirect draw per level
//! of detail, whose instance counts — batches of `DRAW_BATCH` blades — the cull pass wrote;
//! one multi-draw where the adapter has first-instance support), depth tested, into any colour view. Before it, a depth-only
//! pass of the opaque objects (terrain, colliders) feeds the occlusion test's pyramid.

use wgpu::util::DeviceExt;

use super::camera::CameraView;
use super::grass_bind::{GrassBindings, ModelBuffers};
use super::mesh::{sphere_mesh, LodMeshes};

use super::terrain::TerrainPass;
use crate::field::{DensityMap, HeightField};
use crate::gpu::queries::PassQueries;
use crate::gpu::Gpu;
use crate::shaders;
use crate::sim::layout::{FrameUniforms, LOD_LEVELS};
use crate::sim::update::{uniform_entry, BladeBuffers};

/// Depth format of every pass.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

struct Mesh {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    count: u32,
}

/// Pipelines and buffers of the draw pass.
/// Which of the uploaded collider spheres are drawn: all `count` but the `hidden` range
/// (the spheres packed into mesh objects, which the mesh itself shows).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SphereDraw {
    pub count: u32,
    pub hidden: std::ops::Range<u32>,
}

impl SphereDraw {
    /// The instance ranges to draw.
    pub fn drawn(&self) -> [std::ops::Range<u32>; 2] {
        let start = self.hidden.start.min(self.count);
        let end = self.hidden.end.clamp(start, self.count);
        [0..start, end..self.count]
    }

    pub fn any_drawn(&self) -> bool {
        self.drawn().iter().any(|r| !r.is_empty())
    }
}

pub struct DrawPass {
    frame: wgpu::Buffer,
    frame_group: wgpu::BindGroup,
    /// One group per level (each binds its region of the visible list), or one for all
    /// levels with multi-draw.
    grass_groups: Vec<wgpu::BindGroup>,
    spheres_group: wgpu::BindGroup,
    /// Kept to rebuild the pipelines for another sample count.
    frame_layout: wgpu::BindGroupLayout,
    /// The grass groups' layout and sources, kept to rebind the blade models' buffers.
    grass: GrassBindings,
    spheres_layout: wgpu::BindGroupLayout,
    format: wgpu::TextureFormat,
    pipelines: Pipelines,
    /// The clipmap terrain's buffers and bind group.
    terrain_pass: TerrainPass,
    sphere_mesh: Mesh,
    /// A coarse sphere for the occluder pass: its vertices lie on the sphere, so it is
    /// inside it and occludes no more than the sphere does (and the colour pass's finer
    /// sphere, in front of it, still passes the depth test).
    occluder_sphere: Mesh,
    blade_indices: wgpu::Buffer,
    /// The scene's mesh objects (`objects`).
    pub objects: Option<super::objects::ObjectsPass>,
}

/// Value of `draw_level.x` that makes the grass shader take the level from the instance.
const LEVEL_FROM_INSTANCE: u32 = u32::MAX;

pub(crate) fn read_storage(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: true },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

pub(super) struct PipelineSpec<'a> {
    pub label: &'a str,
    pub shader: &'a str,
    /// The vertex entry point (the grass's lit passes shade the sun's shadow per vertex).
    pub vertex: &'a str,
    pub layout: &'a wgpu::BindGroupLayout,
    pub buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    pub depth_write: bool,
    pub cull_back: bool,
    pub lines: bool,
    /// Without colour output (the occluder depth pass).
    pub depth_only: bool,
}

pub(super) fn pipeline(
    device: &wgpu::Device,
    format: wgpu::TextureFormat,
    samples: u32,
    spec: PipelineSpec,
) -> wgpu::RenderPipeline {
    let module = shaders::module(device, spec.shader);
    // Lit passes read the sun, the sky and the shadow map at group 1.
    let light = super::light::layout(device);
    let groups: &[Option<&wgpu::BindGroupLayout>] = if spec.depth_only {
        &[Some(spec.layout)]
    } else {
        &[Some(spec.layout), Some(&light)]
    };
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(&format!("{}.layout", spec.label)),
        bind_group_layouts: groups,
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(spec.label),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some(spec.vertex),
            compilation_options: Default::default(),
            buffers: spec.buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::TriangleList,
            front_face: wgpu::FrontFace::Ccw,
            cull_mode: if spec.cull_back {
                Some(wgpu::Face::Back)
            } else {
                None
            },
            polygon_mode: if spec.lines {
                wgpu::PolygonMode::Line
            } else {
                wgpu::PolygonMode::Fill
            },
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(spec.depth_write),
            // LessEqual: the opaque objects pass again over their own depth from the
            // occluder pass (their clip position is @invariant), and the sky (no depth
            // writes) passes only where nothing was drawn: it sits at depth 1, the cleared
            // value.
            depth_compare: Some(wgpu::CompareFunction::LessEqual),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        // Every pass of the frame's 3D targets has their sample count (`render.msaa`).
        multisample: wgpu::MultisampleState {
            count: samples,
            ..Default::default()
        },
        fragment: (!spec.depth_only).then_some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs_main"),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// A shadow caster's pipeline: `entry` of `shader` into a single-sample depth map, both
/// sides drawn, with a slope-scaled depth bias against acne on surfaces at grazing sun.
pub(super) fn shadow_pipeline(
    device: &wgpu::Device,
    label: &str,
    (shader, entry): (&str, &str),
    layout: &wgpu::BindGroupLayout,
    buffers: &[Option<wgpu::VertexBufferLayout>],
) -> wgpu::RenderPipeline {
    let module = shaders::module(device, shader);
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(&format!("{label}.layout")),
        bind_group_layouts: &[Some(layout)],
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(&pipeline_layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::TriangleList,
            cull_mode: None,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::LessEqual),
            stencil: Default::default(),
            bias: wgpu::DepthBiasState {
                constant: 2,
                slope_scale: 1.5,
                clamp: 0.0,
            },
        }),
        multisample: Default::default(),
        fragment: None,
        multiview_mask: None,
        cache: None,
    })
}

/// The render pipelines of the draw pass, for one colour format and sample count.
struct Pipelines {
    samples: u32,
    sky: wgpu::RenderPipeline,
    terrain: wgpu::RenderPipeline,
    spheres: wgpu::RenderPipeline,
    /// Depth-only terrain and colliders (the occluder pass).
    terrain_depth: wgpu::RenderPipeline,
    spheres_depth: wgpu::RenderPipeline,
    grass: wgpu::RenderPipeline,
    /// The sun's shadow casters: terrain, colliders and the grass (coarsest level).
    shadow_terrain: wgpu::RenderPipeline,
    shadow_spheres: wgpu::RenderPipeline,
    shadow_grass: wgpu::RenderPipeline,
    /// The grass as lines, when the device has `POLYGON_MODE_LINE`.
    grass_lines: Option<wgpu::RenderPipeline>,
}

impl Pipelines {
    /// `layouts`: frame, terrain, spheres and grass bind group layouts.
    fn new(
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        samples: u32,
        layouts: [&wgpu::BindGroupLayout; 4],
    ) -> Self {
        let [frame_layout, terrain_layout, spheres_layout, grass_layout] = layouts;
        let sphere_attrs = wgpu::vertex_attr_array![0 => Float32x3];
        let sphere_buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: 12,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &sphere_attrs,
        })];
        let sky = pipeline(
            device,
            format,
            samples,
            PipelineSpec {
                label: "sward.draw.sky",
                shader: "sky.wgsl",
                vertex: "vs_main",
                layout: frame_layout,
                buffers: &[],
                depth_write: false,
                cull_back: false,
                lines: false,
                depth_only: false,
            },
        );
        let terrain_pipeline = pipeline(
            device,
            format,
            samples,
            PipelineSpec {
                label: "sward.draw.terrain",
                shader: "terrain.wgsl",
                vertex: "vs_main",
                layout: terrain_layout,
                buffers: &[],
                depth_write: true,
                cull_back: false,
                lines: false,
                depth_only: false,
            },
        );
        let spheres = pipeline(
            device,
            format,
            samples,
            PipelineSpec {
                label: "sward.draw.spheres",
                shader: "spheres.wgsl",
                vertex: "vs_main",
                layout: spheres_layout,
                buffers: &sphere_buffers,
                depth_write: true,
                cull_back: false,
                lines: false,
                depth_only: false,
            },
        );
        let depth_only = |label, shader, layout, buffers| {
            pipeline(
                device,
                format,
                samples,
                PipelineSpec {
                    label,
                    shader,
                    vertex: "vs_main",
                    layout,
                    buffers,
                    depth_write: true,
                    cull_back: false,
                    lines: false,
                    depth_only: true,
                },
            )
        };
        let terrain_depth = depth_only(
            "sward.draw.terrain_depth",
            "terrain.wgsl",
            terrain_layout,
            &[],
        );
        let spheres_depth = depth_only(
            "sward.draw.spheres_depth",
            "spheres.wgsl",
            spheres_layout,
            &sphere_buffers,
        );
        // Blades have no back: both sides are drawn and lit (two-sided lighting).
        let grass = pipeline(
            device,
            format,
            samples,
            PipelineSpec {
                label: "sward.draw.grass",
                shader: "grass.wgsl",
                vertex: "vs_lit",
                layout: grass_layout,
                buffers: &[],
                depth_write: true,
                cull_back: false,
                lines: false,
                depth_only: false,
            },
        );

        // Line rasterisation is an optional feature; without it the panel says so.
        let grass_lines = device
            .features()
            .contains(wgpu::Features::POLYGON_MODE_LINE)
            .then(|| {
                pipeline(
                    device,
                    format,
                    samples,
                    PipelineSpec {
                        label: "sward.draw.grass_lines",
                        shader: "grass.wgsl",
                        vertex: "vs_lit",
                        layout: grass_layout,
                        buffers: &[],
                        depth_write: true,
                        cull_back: false,
                        lines: true,
                        depth_only: false,
                    },
                )
            });

        let shadow_terrain = shadow_pipeline(
            device,
            "sward.light.shadow_terrain",
            ("terrain.wgsl", "vs_shadow"),
            terrain_layout,
            &[],
        );
        let shadow_spheres = shadow_pipeline(
            device,
            "sward.light.shadow_spheres",
            ("spheres.wgsl", "vs_main"),
            spheres_layout,
            &sphere_buffers,
        );
        let shadow_grass = shadow_pipeline(
            device,
            "sward.light.shadow_grass",
            ("grass.wgsl", "vs_main"),
            grass_layout,
            &[],
        );
        Self {
            samples,
            sky,
            terrain: terrain_pipeline,
            spheres,
            terrain_depth,
            spheres_depth,
            grass,
            shadow_terrain,
            shadow_spheres,
            shadow_grass,
            grass_lines,
        }
    }
}

impl DrawPass {
    /// `cull_params` is the cull pass's uniform buffer (the grass morph reads it);
    /// `multi_draw` draws all levels with one multi-draw-indirect (the device must have
    /// `INDIRECT_FIRST_INSTANCE`, and the cull pass must write first instances);
    /// `density` and `blend` shade the far ground ([`super::clipmap::grass_blend`]).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        gpu: &Gpu,
        buffers: &BladeBuffers,
        terrain: &HeightField,
        density: Option<&DensityMap>,
        blend: (f32, f32),
        lod: &LodMeshes,
        cull_params: &wgpu::Buffer,
        cull_output: &wgpu::Buffer,
        multi_draw: bool,
        format: wgpu::TextureFormat,
        samples: u32,
        model: ModelBuffers,
        traits: &crate::field::clumps::FieldTraits,
    ) -> Self {
        let device = &gpu.device;
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let frame = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.draw.frame"),
            size: std::mem::size_of::<FrameUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM
                | wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let frame_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.draw.frame_layout"),
            entries: &[uniform_entry(0, vf)],
        });
        let spheres_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.draw.spheres_layout"),
            entries: &[
                uniform_entry(0, vf),
                read_storage(1, wgpu::ShaderStages::VERTEX),
            ],
        });
        let frame_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sward.draw.frame_group"),
            layout: &frame_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: frame.as_entire_binding(),
            }],
        });
        // Without multi-draw each level binds its own region of the visible list (regions
        // are 256-byte aligned) and counts instances from 0.
        let region_bytes = buffers.region as u64 * 4;
        let levels: Vec<(u32, u64, Option<u64>)> = if multi_draw {
            vec![(LEVEL_FROM_INSTANCE, 0, None)]
        } else {
            (0..LOD_LEVELS as u32)
                .map(|k| (k, k as u64 * region_bytes, Some(region_bytes)))
                .collect()
        };
        let levels = levels
            .into_iter()
            .map(|(level, offset, size)| {
                let level_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("sward.draw.grass_level"),
                    contents: bytemuck::cast_slice(&[level, buffers.region, 0, 0]),
                    usage: wgpu::BufferUsages::UNIFORM,
                });
                (level_buffer, offset, size)
            })
            .collect();
        let grass = GrassBindings::new(
            device,
            &frame,
            buffers,
            cull_params,
            cull_output,
            levels,
            traits,
        );
        let grass_groups = grass.groups(device, model);
        let spheres_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sward.draw.spheres_group"),
            layout: &spheres_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: frame.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: buffers.spheres.as_entire_binding(),
                },
            ],
        });

        let terrain_pass = TerrainPass::new(gpu, terrain, density, blend, &frame);
        let pipelines = Pipelines::new(
            device,
            format,
            samples,
            [
                &frame_layout,
                &terrain_pass.layout,
                &spheres_layout,
                &grass.layout,
            ],
        );
        let sphere = |rings, sectors, label: &str| {
            let (sv, si) = sphere_mesh(rings, sectors);
            Mesh {
                vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(&format!("{label}.vertices")),
                    contents: bytemuck::cast_slice(&sv),
                    usage: wgpu::BufferUsages::VERTEX,
                }),
                indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(&format!("{label}.indices")),
                    contents: bytemuck::cast_slice(&si),
                    usage: wgpu::BufferUsages::INDEX,
                }),
                count: si.len() as u32,
            }
        };
        let sphere_mesh = sphere(16, 24, "sward.sphere");
        let occluder_sphere = sphere(6, 8, "sward.sphere_occluder");
        let blade_indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("sward.blade.indices"),
            contents: bytemuck::cast_slice(&lod.indices),
            usage: wgpu::BufferUsages::INDEX,
        });
        Self {
            frame,
            frame_group,
            grass_groups,
            spheres_group,
            frame_layout,
            grass,
            spheres_layout,
            format,
            pipelines,
            terrain_pass,
            sphere_mesh,
            occluder_sphere,
            blade_indices,
            objects: None,
        }
    }

    /// Bytes of the meshes and the frame uniforms.
    pub fn gpu_bytes(&self) -> u64 {
        [
            &self.frame,
            &self.sphere_mesh.vertices,
            &self.sphere_mesh.indices,
            &self.occluder_sphere.vertices,
            &self.occluder_sphere.indices,
            &self.blade_indices,
        ]
        .iter()
        .map(|b| b.size())
        .sum::<u64>()
            + self.terrain_pass.gpu_bytes()
    }

    /// The sample count the pipelines draw with.
    pub(super) fn grass_layout(&self) -> &wgpu::BindGroupLayout {
        &self.grass.layout
    }

    pub fn samples(&self) -> u32 {
        self.pipelines.samples
    }

    /// Rebuilds the pipelines for targets of `samples` samples (the panel's MSAA setting);
    /// buffers and bind groups stay.
    pub fn set_samples(&mut self, device: &wgpu::Device, samples: u32) {
        if let Some(o) = &mut self.objects {
            o.set_samples(device, samples);
        }
        if samples == self.pipelines.samples {
            return;
        }
        self.pipelines = Pipelines::new(
            device,
            self.format,
            samples,
            [
                &self.frame_layout,
                &self.terrain_pass.layout,
                &self.spheres_layout,
                &self.grass.layout,
            ],
        );
    }

    /// Binds the blade models' buffers anew (a new wind grid, the Verlet states allocated).
    pub fn bind_model(&mut self, device: &wgpu::Device, model: ModelBuffers) {
        self.grass_groups = self.grass.groups(device, model);
    }

    /// Whether the grass can be drawn as lines (the adapter supports line rasterisation).
    pub fn has_wireframe(&self) -> bool {
        self.pipelines.grass_lines.is_some()
    }

    /// The frame-uniform buffer (the overlay reads it too).
    pub fn frame_buffer(&self) -> &wgpu::Buffer {
        &self.frame
    }

    /// Writes this frame's uniforms (made for `camera`) and places the terrain's levels
    /// around the camera (the viewport and fog distance are in `frame.viewport_time`).
    /// The terrain's height uniforms and grid (for the billboards).
    pub fn terrain_buffers(&self) -> (&wgpu::Buffer, &wgpu::Buffer) {
        self.terrain_pass.height_buffers()
    }

    /// The far ground's grass colour (`clipmap::far_albedo` of the field).
    pub fn set_far_albedo(&mut self, albedo: glam::Vec3) {
        self.terrain_pass.grass_albedo = albedo;
    }

    /// Says whether blades grow past the terrain square (see `TerrainPass::grass_everywhere`).
    pub fn set_grass_everywhere(&mut self, everywhere: bool) {
        self.terrain_pass.grass_everywhere = everywhere;
    }

    pub fn prepare(&self, queue: &wgpu::Queue, frame: &FrameUniforms, camera: &CameraView) {
        queue.write_buffer(&self.frame, 0, bytemuck::bytes_of(frame));
        let [w, h, _, fog] = frame.viewport_time;
        self.terrain_pass
            .prepare(queue, camera, w / h.max(1.0), fog);
    }

    fn draw_terrain(&self, pass: &mut wgpu::RenderPass<'_>) {
        self.terrain_pass.draw(pass);
    }

    fn draw_spheres(&self, pass: &mut wgpu::RenderPass<'_>, mesh: &Mesh, spheres: &SphereDraw) {
        pass.set_bind_group(0, &self.spheres_group, &[]);
        pass.set_vertex_buffer(0, mesh.vertices.slice(..));
        pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
        for range in spheres.drawn() {
            if !range.is_empty() {
                pass.draw_indexed(0..mesh.count, 0, range);
            }
        }
    }

    /// Records the occluder pass: the opaque objects' depth only, into `depth` (cleared),
    /// which the depth pyramid is then built from.
    pub fn encode_occluders(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        depth: &wgpu::TextureView,
        spheres: &SphereDraw,
        q: PassQueries,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("sward.draw.occluders"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: q.render_writes(),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        q.begin(&mut pass);
        if spheres.any_drawn() {
            pass.set_pipeline(&self.pipelines.spheres_depth);
            self.draw_spheres(&mut pass, &self.occluder_sphere, spheres);
        }
        if let Some(o) = &self.objects {
            o.draw(&mut pass, true);
        }
        pass.set_pipeline(&self.pipelines.terrain_depth);
        self.draw_terrain(&mut pass);
        q.end(&mut pass);
    }

    /// Records the render pass into `color` with `depth`; `depth_loaded` keeps the depth
    /// of the occluder pass instead of clearing it.
    #[allow(clippy::too_many_arguments)]
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
        depth_loaded: bool,
        indirect: &wgpu::Buffer,
        spheres: &SphereDraw,
        wireframe: bool,
        billboards: Option<&super::billboard::BillboardPass>,
        light: &wgpu::BindGroup,
        q: PassQueries,
    ) {
        let depth_load = if depth_loaded {
            wgpu::LoadOp::Load
        } else {
            wgpu::LoadOp::Clear(1.0)
        };
        let mut pass = colour_pass(
            encoder,
            "sward.draw",
            (color, wgpu::LoadOp::Clear(wgpu::Color::BLACK)),
            (depth, depth_load),
            q.render_writes(),
        );
        pass.set_bind_group(1, light, &[]);
        q.begin(&mut pass);
        if spheres.any_drawn() {
            pass.set_pipeline(&self.pipelines.spheres);
            self.draw_spheres(&mut pass, &self.sphere_mesh, spheres);
        }
        if let Some(o) = &self.objects {
            o.draw(&mut pass, false);
        }
        q.end(&mut pass);

        // The lit grass is counted apart: its fragments per covered pixel are the figure
        // the frame's shading cost is held to.
        let grass = q.row(super::work::LIT_GRASS);
        grass.begin(&mut pass);
        self.draw_grass(&mut pass, self.grass_pipeline(wireframe), indirect, 0);
        grass.end(&mut pass);
        q.begin(&mut pass);
        if let Some(b) = billboards {
            b.draw(&mut pass);
        }

        // Front to back: what the grass covers of the ground and what the ground covers of
        // the sky is rejected by the depth test before it is shaded.
        pass.set_pipeline(&self.pipelines.terrain);
        self.draw_terrain(&mut pass);

        pass.set_pipeline(&self.pipelines.sky);
        pass.set_bind_group(0, &self.frame_group, &[]);
        pass.draw(0..3, 0..1);
        q.end(&mut pass);
    }

    /// The grass's level-of-detail draws whose arguments start at byte `offset` of
    /// `indirect` (one multi-draw, or one draw per level with its region bound).
    pub(super) fn draw_grass(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        pipeline: &wgpu::RenderPipeline,
        indirect: &wgpu::Buffer,
        offset: u64,
    ) {
        pass.set_pipeline(pipeline);
        pass.set_index_buffer(self.blade_indices.slice(..), wgpu::IndexFormat::Uint32);
        let stride = std::mem::size_of::<crate::sim::layout::DrawIndexedIndirect>() as u64;
        if let [all] = self.grass_groups.as_slice() {
            pass.set_bind_group(0, all, &[]);
            pass.multi_draw_indexed_indirect(indirect, offset, LOD_LEVELS as u32);
        } else {
            for (k, group) in self.grass_groups.iter().enumerate() {
                pass.set_bind_group(0, group, &[]);
                pass.draw_indexed_indirect(indirect, offset + k as u64 * stride);
            }
        }
    }

    /// The grass's colour pipeline: filled, or as lines where asked and supported.
    fn grass_pipeline(&self, wireframe: bool) -> &wgpu::RenderPipeline {
        let p = &self.pipelines;
        match (&p.grass_lines, wireframe) {
            (Some(lines), true) => lines,
            _ => &p.grass,
        }
    }

    /// Records the sun's shadow casters into a cascade's pass (the frame buffer holds the
    /// cascade's view): the colliders, the objects, the terrain, and with `grass_args` the
    /// blades the cull kept, drawn with the coarsest level's mesh out to the frame's
    /// shadow radius (`grass.wgsl`).
    pub fn draw_casters(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        spheres: &SphereDraw,
        grass_args: Option<(&wgpu::Buffer, u64)>,
    ) {
        if spheres.any_drawn() {
            // The colour pass's sphere: the shadow's outline is the drawn ball's.
            pass.set_pipeline(&self.pipelines.shadow_spheres);
            self.draw_spheres(pass, &self.sphere_mesh, spheres);
        }
        if let Some(o) = &self.objects {
            o.draw_shadow(pass);
        }
        pass.set_pipeline(&self.pipelines.shadow_terrain);
        self.draw_terrain(pass);
        if let Some((args, offset)) = grass_args {
            self.draw_grass(pass, &self.pipelines.shadow_grass, args, offset);
        }
    }

    /// Records the late grass draw of two-phase occlusion culling: the blades the late cull
    /// kept, over the frame the main draw left (colour and depth loaded). Needs
    /// multi-draw: the late lists start mid-region, at their draws' first instance.
    #[allow(clippy::too_many_arguments)]
    pub fn encode_late(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
        indirect: &wgpu::Buffer,
        wireframe: bool,
        light: &wgpu::BindGroup,
        q: PassQueries,
    ) {
        let mut pass = colour_pass(
            encoder,
            "sward.draw.late",
            (color, wgpu::LoadOp::Load),
            (depth, wgpu::LoadOp::Load),
            q.render_writes(),
        );
        pass.set_bind_group(1, light, &[]);
        q.begin(&mut pass);
        let offset = std::mem::offset_of!(crate::sim::layout::CullCounters, late_draws) as u64;
        self.draw_grass(&mut pass, self.grass_pipeline(wireframe), indirect, offset);
        q.end(&mut pass);
    }
}

/// A render pass into `color` and `depth` with the given loads, both stored: the main draw
/// (colour cleared) and the late grass draw (both loaded) differ only in those.
fn colour_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    color: (&wgpu::TextureView, wgpu::LoadOp<wgpu::Color>),
    depth: (&wgpu::TextureView, wgpu::LoadOp<f32>),
    timestamps: Option<wgpu::RenderPassTimestampWrites>,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: color.0,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: color.1,
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: depth.0,
            depth_ops: Some(wgpu::Operations {
                load: depth.1,
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: timestamps,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}
