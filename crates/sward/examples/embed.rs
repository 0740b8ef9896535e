//! A wgpu program of its own that embeds sward's grass: its own device, camera, ground
//! and a coloured box in its own depth buffer, and sward's blades drawn into its render
//! pass, depth-tested against that world and culled by its depth.
//!
//! `cargo run --release -p sward --example embed -- --out grass.png [--size 640x360]
//! [--frames 24]` renders headless (any adapter, the software one included) and writes a
//! PNG; without `--out` it opens a window (Esc closes it, or `--frames N` after N frames).

use std::path::PathBuf;
use std::process::ExitCode;

use glam::Vec3;
use sward::embed::{required_limits, OPTIONAL_FEATURES, REQUIRED_FEATURES};
use sward::{CameraView, Collider, ColorOutput, FrameInputs, GrassRenderer, SceneSource};
use wgpu::util::DeviceExt;

const COLOR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The grass: a 24 m square of gentle hills, light wind. The host reads the hills back
/// (`GrassRenderer::ground_height`) to build its own ground under the blades.
pub const SCENE: &str = r#"(
    terrain: (size: 24.0, resolution: 65, height: Noise(seed: 3, amplitude: 0.8, wavelength: 14.0, octaves: 2)),
    field: (density: 90.0, height: (min: 0.3, max: 0.7), seed: 2),
    wind: (directional: Some((direction: (1.0, 0.3), strength: 2.0, gust: 0.8, wavelength: 8.0, speed: 3.0))),
    render: (billboard_distance: 0.0),
    light: (time_of_day: Some(16.5)),
)"#;

/// The host's own shader: coloured vertices, one sun, its own view-projection, and sward's
/// sun shadows received through `GrassRenderer::shadow_receiver_wgsl` (group 1).
const HOST_WGSL: &str = r#"
struct Frame { view_proj: mat4x4<f32>, sun: vec4<f32>, eye: vec4<f32> }
@group(0) @binding(0) var<uniform> frame: Frame;
struct Out {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) world: vec3<f32>,
}
@vertex
fn vs(@location(0) pos: vec3<f32>, @location(1) normal: vec3<f32>, @location(2) color: vec3<f32>) -> Out {
    return Out(frame.view_proj * vec4<f32>(pos, 1.0), color, normal, pos);
}
@fragment
fn fs(in: Out) -> @location(0) vec4<f32> {
    // frame.sun.w: 1 to receive sward's shadows.
    var shadow = 1.0;
    if frame.sun.w > 0.5 {
        shadow = sward_sun_visibility(in.world, frame.eye.xyz, frame.sun.xyz);
    }
    let lit = 0.35 + 0.65 * max(dot(normalize(in.normal), frame.sun.xyz), 0.0) * shadow;
    return vec4<f32>(in.color * lit, 1.0);
}
"#;

/// The host's shadow caster: its box, depth only, into one of sward's sun cascades.
const CASTER_WGSL: &str = r#"
@group(0) @binding(0) var<uniform> sun_view_proj: mat4x4<f32>;
@vertex
fn vs(@location(0) pos: vec3<f32>) -> @builtin(position) vec4<f32> {
    return sun_view_proj * vec4<f32>(pos, 1.0);
}
"#;

/// Indices of the box at the end of `world`'s mesh (six faces of two triangles).
const BOX_INDICES: u32 = 36;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Vertex {
    pos: [f32; 3],
    normal: [f32; 3],
    color: [f32; 3],
}

/// The host's world: its pipeline, the ground and the box, and the frame's targets.
pub struct Host {
    grass: GrassRenderer,
    pipeline: wgpu::RenderPipeline,
    uniforms: wgpu::Buffer,
    group: wgpu::BindGroup,
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    /// The host's ball, rewritten each frame where it rolls (sward's collider).
    ball_vertices: wgpu::Buffer,
    ball_indices: wgpu::Buffer,
    ball_index_count: u32,
    depth: wgpu::TextureView,
    size: (u32, u32),
    time: f32,
    /// Whether sward's cull sees the host's depth (occlusion by the host's world).
    pub occlusion: bool,
    /// Whether the grass is drawn at all (the host's world alone, for comparison).
    pub grass_on: bool,
    /// Whether the host's world receives sward's sun shadows.
    pub shadows: bool,
    /// Whether the host's box casts into sward's sun shadows (`shadow_casters`).
    pub casts: bool,
    /// The caster pipeline and, per cascade, its view-projection's buffer and group.
    caster: wgpu::RenderPipeline,
    caster_groups: Vec<(wgpu::Buffer, wgpu::BindGroup)>,
}

impl Host {
    fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        size: (u32, u32),
        color: wgpu::TextureFormat,
        scene: &str,
    ) -> sward::Result<Self> {
        // sward's part: a descriptor with the host's formats, and the scene.
        let grass = GrassRenderer::new(
            device,
            queue,
            sward::GrassRendererDescriptor {
                color_format: color,
                depth_format: DEPTH,
                sample_count: 1,
                output: ColorOutput::ToneMapped,
                scene: SceneSource::Ron(scene.into()),
            },
        )?;
        let (vertices, indices) = world(&grass);
        // The host's shader with sward's shadow lookup at its group 1.
        let source = format!("{HOST_WGSL}{}", GrassRenderer::shadow_receiver_wgsl(1));
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("host.shader"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let receiver = grass.shadow_receiver();
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("host.frame_layout"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("host.pipeline_layout"),
            bind_group_layouts: &[Some(&layout), Some(receiver.layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("host.pipeline"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<Vertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x3],
                })],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::LessEqual),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[Some(color.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("host.frame"),
            size: 96,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("host.frame_group"),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniforms.as_entire_binding(),
            }],
        });
        let index_count = indices.len() as u32;
        let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("host.vertices"),
            contents: bytemuck::cast_slice(&vertices),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("host.indices"),
            contents: bytemuck::cast_slice(&indices),
            usage: wgpu::BufferUsages::INDEX,
        });
        let (ball, ball_index) = sphere(Vec3::ZERO, BALL_RADIUS);
        let ball_vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("host.ball_vertices"),
            contents: bytemuck::cast_slice(&ball),
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
        });
        let ball_indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("host.ball_indices"),
            contents: bytemuck::cast_slice(&ball_index),
            usage: wgpu::BufferUsages::INDEX,
        });
        let (caster, caster_groups) = caster_pipeline(device);
        Ok(Self {
            caster,
            caster_groups,
            casts: true,
            ball_vertices,
            ball_indices,
            ball_index_count: ball_index.len() as u32,
            depth: depth_view(device, size),
            grass,
            pipeline,
            uniforms,
            group,
            vertices,
            indices,
            index_count,
            size,
            time: 0.0,
            occlusion: true,
            grass_on: true,
            shadows: true,
        })
    }

    /// One frame into `color`: the host's world, then sward's grass in the host's pass.
    fn frame(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        color: &wgpu::TextureView,
        dt: f32,
    ) -> sward::Result<()> {
        self.time += dt;
        let camera = CameraView {
            eye: Vec3::new(-7.5, 2.6, 6.5),
            target: Vec3::new(0.0, 0.6, 0.0),
            fov_y: 55.0,
            near: 0.05,
            far: 200.0,
        };
        let view_proj = camera.view_proj(self.size.0 as f32 / self.size.1 as f32);
        // The host lights its world with sward's sun, so the shadows fall where it shines.
        let sun = self.grass.shadow_receiver().sun_direction;
        let receive = if self.shadows { 1.0 } else { 0.0 };
        let mut frame = view_proj.to_cols_array().to_vec();
        frame.extend([sun.x, sun.y, sun.z, receive]);
        frame.extend([camera.eye.x, camera.eye.y, camera.eye.z, 1.0]);
        queue.write_buffer(&self.uniforms, 0, bytemuck::cast_slice(&frame));
        // A ball of the host's rolls through the grass and presses it.
        let x = -4.0 + 1.2 * self.time;
        let ball = Collider {
            center: Vec3::new(x, self.grass.ground_height(x, 1.5) + BALL_RADIUS, 1.5),
            radius: BALL_RADIUS,
            velocity: Vec3::new(1.2, 0.0, 0.0),
        };
        let (moved, _) = sphere(ball.center, BALL_RADIUS);
        queue.write_buffer(&self.ball_vertices, 0, bytemuck::cast_slice(&moved));
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("host.frame"),
        });
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("host.world"),
                color_attachments: &[Some(attachment(color, Some(SKY)))],
                depth_stencil_attachment: Some(depth_attachment(&self.depth, true)),
                ..Default::default()
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.group, &[]);
            // The shadow maps of the last `prepare`: the host's opaque pass comes before this
            // frame's (which reads its depth), so its shadows are one frame old.
            pass.set_bind_group(1, self.grass.shadow_receiver().group, &[]);
            pass.set_vertex_buffer(0, self.vertices.slice(..));
            pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..self.index_count, 0, 0..1);
            pass.set_vertex_buffer(0, self.ball_vertices.slice(..));
            pass.set_index_buffer(self.ball_indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..self.ball_index_count, 0, 0..1);
        }
        let inputs = FrameInputs {
            camera,
            size: self.size,
            dt,
            colliders: &[ball],
            depth: self.occlusion.then_some(&self.depth),
            wind: None,
        };
        self.grass.prepare(device, queue, &mut encoder, &inputs)?;
        if self.casts {
            // The host's box into each sun cascade sward drew this frame, over sward's own
            // casters: the grass and the host's ground then lie in its shadow.
            for (caster, (buffer, group)) in
                self.grass.shadow_casters().iter().zip(&self.caster_groups)
            {
                queue.write_buffer(buffer, 0, bytemuck::bytes_of(&caster.view_proj));
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("host.box_shadow"),
                    color_attachments: &[],
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: caster.depth,
                        depth_ops: Some(wgpu::Operations {
                            load: wgpu::LoadOp::Load,
                            store: wgpu::StoreOp::Store,
                        }),
                        stencil_ops: None,
                    }),
                    ..Default::default()
                });
                pass.set_pipeline(&self.caster);
                pass.set_bind_group(0, group, &[]);
                pass.set_vertex_buffer(0, self.vertices.slice(..));
                pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(self.index_count - BOX_INDICES..self.index_count, 0, 0..1);
            }
        }
        if self.grass_on {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("host.grass"),
                color_attachments: &[Some(attachment(color, None))],
                depth_stencil_attachment: Some(depth_attachment(&self.depth, false)),
                ..Default::default()
            });
            self.grass.render(&mut pass);
        }
        queue.submit([encoder.finish()]);
        Ok(())
    }
}

/// The host's depth-only pipeline for its shadow casters (sward's shadow format and bias),
/// and one view-projection buffer and group for each of the (at most four) cascades.
fn caster_pipeline(
    device: &wgpu::Device,
) -> (wgpu::RenderPipeline, Vec<(wgpu::Buffer, wgpu::BindGroup)>) {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("host.caster_shader"),
        source: wgpu::ShaderSource::Wgsl(CASTER_WGSL.into()),
    });
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("host.caster_layout"),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }],
    });
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("host.caster_pipeline_layout"),
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("host.caster"),
        layout: Some(&pipeline_layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs"),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<Vertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3],
            })],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: Some(wgpu::DepthStencilState {
            format: sward::embed::SHADOW_DEPTH_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::LessEqual),
            stencil: Default::default(),
            bias: sward::embed::SHADOW_DEPTH_BIAS,
        }),
        multisample: Default::default(),
        fragment: None,
        multiview_mask: None,
        cache: None,
    });
    let groups = (0..4)
        .map(|_| {
            let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("host.caster_view_proj"),
                size: 64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("host.caster_group"),
                layout: &layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: buffer.as_entire_binding(),
                }],
            });
            (buffer, group)
        })
        .collect();
    (pipeline, groups)
}

const SKY: wgpu::Color = wgpu::Color {
    r: 0.45,
    g: 0.62,
    b: 0.85,
    a: 1.0,
};

/// A colour attachment of `view`, cleared to `clear` or loaded, stored.
pub fn attachment(
    view: &wgpu::TextureView,
    clear: Option<wgpu::Color>,
) -> wgpu::RenderPassColorAttachment<'_> {
    wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load: clear.map_or(wgpu::LoadOp::Load, wgpu::LoadOp::Clear),
            store: wgpu::StoreOp::Store,
        },
    }
}

/// A depth attachment of `view`, cleared to 1 or loaded, stored.
pub fn depth_attachment(
    view: &wgpu::TextureView,
    clear: bool,
) -> wgpu::RenderPassDepthStencilAttachment<'_> {
    wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(wgpu::Operations {
            load: if clear {
                wgpu::LoadOp::Clear(1.0)
            } else {
                wgpu::LoadOp::Load
            },
            store: wgpu::StoreOp::Store,
        }),
        stencil_ops: None,
    }
}

/// The host's depth: sampled by sward's occlusion cull, so it has `TEXTURE_BINDING`.
fn depth_view(device: &wgpu::Device, (width, height): (u32, u32)) -> wgpu::TextureView {
    device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("host.depth"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        })
        .create_view(&Default::default())
}

/// The host's ground (a grid over sward's heights) and a red-green-blue box on it.
fn world(grass: &GrassRenderer) -> (Vec<Vertex>, Vec<u32>) {
    let mut v = Vec::new();
    let mut i = Vec::new();
    let half = grass.scene().terrain.size * 0.5 + 20.0;
    let n = 96;
    let h = |x: f32, z: f32| grass.ground_height(x, z);
    for row in 0..=n {
        for col in 0..=n {
            let x = -half + 2.0 * half * col as f32 / n as f32;
            let z = -half + 2.0 * half * row as f32 / n as f32;
            let e = 0.05;
            let normal = Vec3::new(
                h(x - e, z) - h(x + e, z),
                2.0 * e,
                h(x, z - e) - h(x, z + e),
            )
            .normalize();
            v.push(Vertex {
                pos: [x, h(x, z), z],
                normal: normal.into(),
                color: [0.22, 0.2, 0.1],
            });
        }
    }
    for row in 0..n {
        for col in 0..n {
            let a = row * (n + 1) + col;
            let b = a + n + 1;
            i.extend([a, b, a + 1, a + 1, b, b + 1]);
        }
    }
    // The box: 1.2 m on a side, standing on the ground at the origin.
    let base = h(0.0, 0.0) - 0.1;
    let faces: [(Vec3, [f32; 3]); 6] = [
        (Vec3::X, [0.85, 0.15, 0.1]),
        (Vec3::NEG_X, [0.85, 0.15, 0.1]),
        (Vec3::Y, [0.9, 0.9, 0.85]),
        (Vec3::NEG_Y, [0.9, 0.9, 0.85]),
        (Vec3::Z, [0.15, 0.3, 0.85]),
        (Vec3::NEG_Z, [0.15, 0.3, 0.85]),
    ];
    let centre = Vec3::new(0.0, base + 0.6, 0.0);
    for (normal, color) in faces {
        let (u, w) = normal.any_orthonormal_pair();
        let first = v.len() as u32;
        for (su, sw) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            let p = centre + 0.6 * (normal + su * u + sw * w);
            v.push(Vertex {
                pos: p.into(),
                normal: normal.into(),
                color,
            });
        }
        i.extend([first, first + 1, first + 2, first, first + 2, first + 3]);
    }
    (v, i)
}

const BALL_RADIUS: f32 = 0.45;

/// A yellow sphere of `radius` at `centre` (latitude-longitude).
fn sphere(centre: Vec3, radius: f32) -> (Vec<Vertex>, Vec<u32>) {
    let (rings, segments) = (12u32, 24u32);
    let mut v = Vec::new();
    for r in 0..=rings {
        let theta = std::f32::consts::PI * r as f32 / rings as f32;
        for k in 0..=segments {
            let phi = std::f32::consts::TAU * k as f32 / segments as f32;
            let n = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            v.push(Vertex {
                pos: (centre + radius * n).into(),
                normal: n.into(),
                color: [0.95, 0.75, 0.1],
            });
        }
    }
    let mut i = Vec::new();
    for r in 0..rings {
        for k in 0..segments {
            let a = r * (segments + 1) + k;
            let b = a + segments + 1;
            i.extend([a, a + 1, b, a + 1, b + 1, b]);
        }
    }
    (v, i)
}

/// A device for the host: sward's required features and limits, and its optional features
/// where the adapter has them.
pub fn open() -> Result<(wgpu::Device, wgpu::Queue), String> {
    let instance =
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter = pollster::block_on(instance.request_adapter(&Default::default()))
        .map_err(|e| format!("no adapter: {e}"))?;
    pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("host.device"),
        required_features: REQUIRED_FEATURES | (adapter.features() & OPTIONAL_FEATURES),
        required_limits: required_limits(&adapter.limits()),
        ..Default::default()
    }))
    .map_err(|e| format!("no device: {e}"))
}

/// Renders `frames` frames headless with the host set up by `setup`; returns the last
/// frame and the blades sward drew in it.
pub fn render_image(
    size: (u32, u32),
    frames: u32,
    setup: impl FnOnce(&mut Host),
) -> Result<(image::RgbaImage, u64), String> {
    render_scene(SCENE, size, frames, setup).map(|(image, blades, _)| (image, blades))
}

/// [`render_image`] of another scene: the picture, the blades and the billboards drawn.
pub fn render_scene(
    scene: &str,
    size: (u32, u32),
    frames: u32,
    setup: impl FnOnce(&mut Host),
) -> Result<(image::RgbaImage, u64, u32), String> {
    let (device, queue) = open()?;
    let mut host = Host::new(&device, &queue, size, COLOR, scene).map_err(|e| e.to_string())?;
    setup(&mut host);
    let target = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("host.color"),
        size: wgpu::Extent3d {
            width: size.0,
            height: size.1,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: COLOR,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = target.create_view(&Default::default());
    for _ in 0..frames {
        host.frame(&device, &queue, &view, 1.0 / 30.0)
            .map_err(|e| e.to_string())?;
        device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| e.to_string())?;
    }
    let drawn = host.grass.drawn_blades().map_err(|e| e.to_string())?;
    let cards = host.grass.drawn_billboards().map_err(|e| e.to_string())?;
    let image = read_back(&device, &queue, &target, size)?;
    Ok((image, drawn, cards))
}

/// Renders `frames` frames headless and writes the last as a PNG at `out` (through a
/// temporary file renamed into place).
fn headless(out: &PathBuf, size: (u32, u32), frames: u32) -> Result<(), String> {
    if out.exists() && !out.is_file() {
        return Err(format!(
            "--out {}: exists and is not a regular file",
            out.display()
        ));
    }
    let (image, drawn) = render_image(size, frames, |_| {})?;
    let tmp = out.with_extension("png.tmp");
    image
        .save_with_format(&tmp, image::ImageFormat::Png)
        .map_err(|e| format!("{}: {e}", tmp.display()))?;
    std::fs::rename(&tmp, out).map_err(|e| format!("{}: {e}", out.display()))?;
    println!(
        "wrote {} ({}x{}, {frames} frames, {drawn} blades drawn)",
        out.display(),
        size.0,
        size.1
    );
    Ok(())
}

/// Copies `texture` (8-bit RGBA, `COPY_SRC` usage) of `size` back into an image (blocks).
pub fn read_back(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    (width, height): (u32, u32),
) -> Result<image::RgbaImage, String> {
    let row = (width * 4).div_ceil(256) * 256;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("host.read_back"),
        size: u64::from(row * height),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: None,
            },
        },
        texture.size(),
    );
    queue.submit([encoder.finish()]);
    buffer.slice(..).map_async(wgpu::MapMode::Read, |_| {});
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| e.to_string())?;
    let data = buffer
        .slice(..)
        .get_mapped_range()
        .map_err(|e| format!("read-back: {e}"))?;
    let mut pixels = Vec::with_capacity((width * height * 4) as usize);
    for y in 0..height {
        let start = (y * row) as usize;
        pixels.extend_from_slice(&data[start..start + (width * 4) as usize]);
    }
    image::RgbaImage::from_raw(width, height, pixels).ok_or_else(|| "image size".to_string())
}

fn main() -> ExitCode {
    let mut out = None;
    let mut size = (640, 360);
    let mut frames = None;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let value = args.next();
        let parsed = match (a.as_str(), value) {
            ("--out", Some(v)) => {
                out = Some(PathBuf::from(v));
                Ok(())
            }
            ("--size", Some(v)) => v
                .split_once('x')
                .and_then(|(w, h)| Some((w.parse().ok()?, h.parse().ok()?)))
                .filter(|&(w, h): &(u32, u32)| (1..=8192).contains(&w) && (1..=8192).contains(&h))
                .map(|s| size = s)
                .ok_or(format!("--size {v}: expected WxH, each 1..=8192")),
            ("--frames", Some(v)) => v
                .parse()
                .ok()
                .filter(|n| (1..=10_000).contains(n))
                .map(|n| frames = Some(n))
                .ok_or(format!("--frames {v}: expected 1..=10000")),
            (flag, _) => Err(format!(
                "unknown or incomplete argument {flag}: use --out FILE, --size WxH, --frames N"
            )),
        };
        if let Err(e) = parsed {
            eprintln!("embed: {e}");
            return ExitCode::from(2);
        }
    }
    let run = match out {
        Some(out) => headless(&out, size, frames.unwrap_or(24)),
        None => window::run(size, frames),
    };
    match run {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("embed: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The same host in a window (winit): the grass drawn into the surface's frame.
mod window {
    use super::*;
    use std::sync::Arc;
    use winit::application::ApplicationHandler;
    use winit::event::{ElementState, KeyEvent, WindowEvent};
    use winit::event_loop::{ActiveEventLoop, EventLoop};
    use winit::keyboard::{Key, NamedKey};
    use winit::window::{Window, WindowId};

    struct App {
        size: (u32, u32),
        /// Close after this many frames (`--frames`); `None`: when asked.
        frames: Option<u32>,
        drawn: u32,
        state: Option<State>,
        error: Option<String>,
    }

    struct State {
        window: Arc<Window>,
        surface: wgpu::Surface<'static>,
        device: wgpu::Device,
        queue: wgpu::Queue,
        host: Host,
        last: std::time::Instant,
    }

    impl State {
        fn new(window: Arc<Window>, size: (u32, u32)) -> Result<Self, String> {
            let instance = wgpu::Instance::new(
                wgpu::InstanceDescriptor::new_without_display_handle_from_env(),
            );
            let surface = instance
                .create_surface(window.clone())
                .map_err(|e| e.to_string())?;
            let adapter =
                pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
                    compatible_surface: Some(&surface),
                    ..Default::default()
                }))
                .map_err(|e| format!("no adapter: {e}"))?;
            let (device, queue) =
                pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
                    label: Some("host.device"),
                    required_features: REQUIRED_FEATURES | (adapter.features() & OPTIONAL_FEATURES),
                    required_limits: required_limits(&adapter.limits()),
                    ..Default::default()
                }))
                .map_err(|e| format!("no device: {e}"))?;
            let mut config = surface
                .get_default_config(&adapter, size.0, size.1)
                .ok_or("the surface does not fit this adapter")?;
            // An sRGB format of the surface's: the grass writes display colour.
            let caps = surface.get_capabilities(&adapter);
            config.format = caps
                .formats
                .iter()
                .copied()
                .find(|f| f.is_srgb())
                .ok_or("the surface has no sRGB format")?;
            surface.configure(&device, &config);
            let host = Host::new(&device, &queue, size, config.format, SCENE)
                .map_err(|e| e.to_string())?;
            Ok(Self {
                window,
                surface,
                device,
                queue,
                host,
                last: std::time::Instant::now(),
            })
        }

        fn redraw(&mut self) -> Result<(), String> {
            let frame = match self.surface.get_current_texture() {
                wgpu::CurrentSurfaceTexture::Success(f)
                | wgpu::CurrentSurfaceTexture::Suboptimal(f) => f,
                _ => return Ok(()),
            };
            let view = frame.texture.create_view(&Default::default());
            let dt = self.last.elapsed().as_secs_f32().min(0.1);
            self.last = std::time::Instant::now();
            self.host
                .frame(&self.device, &self.queue, &view, dt)
                .map_err(|e| e.to_string())?;
            self.window.pre_present_notify();
            self.queue.present(frame);
            self.window.request_redraw();
            Ok(())
        }
    }

    impl ApplicationHandler for App {
        fn resumed(&mut self, event_loop: &ActiveEventLoop) {
            if self.state.is_some() {
                return;
            }
            let attributes = Window::default_attributes()
                .with_title("sward embedded in a host")
                .with_resizable(false)
                .with_inner_size(winit::dpi::PhysicalSize::new(self.size.0, self.size.1));
            let made = event_loop
                .create_window(attributes)
                .map_err(|e| e.to_string())
                .and_then(|w| State::new(Arc::new(w), self.size));
            match made {
                Ok(s) => {
                    s.window.request_redraw();
                    self.state = Some(s);
                }
                Err(e) => {
                    self.error = Some(e);
                    event_loop.exit();
                }
            }
        }

        fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
            match event {
                WindowEvent::CloseRequested
                | WindowEvent::KeyboardInput {
                    event:
                        KeyEvent {
                            logical_key: Key::Named(NamedKey::Escape),
                            state: ElementState::Pressed,
                            ..
                        },
                    ..
                } => event_loop.exit(),
                WindowEvent::RedrawRequested => {
                    if let Some(s) = &mut self.state {
                        if let Err(e) = s.redraw() {
                            self.error = Some(e);
                            event_loop.exit();
                        }
                        self.drawn += 1;
                        if self.frames.is_some_and(|n| self.drawn >= n) {
                            println!("closed after {} frames", self.drawn);
                            event_loop.exit();
                        }
                    }
                }
                _ => {}
            }
        }
    }

    pub fn run(size: (u32, u32), frames: Option<u32>) -> Result<(), String> {
        let event_loop = EventLoop::new().map_err(|e| format!("no display: {e}"))?;
        let mut app = App {
            size,
            frames,
            drawn: 0,
            state: None,
            error: None,
        };
        event_loop.run_app(&mut app).map_err(|e| e.to_string())?;
        app.error.map_or(Ok(()), Err)
    }
}
