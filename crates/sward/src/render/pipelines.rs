//! The draw pass's render pipelines: the builders every lit and depth-only pass shares
//! (`pipeline`, `shadow_pipeline`, and `fullscreen_pipeline` for the passes that draw one
//! full-screen triangle), the fixed pipelines of one colour format and sample
//! count (`Pipelines`), and the grass's, which are also built for the scene's
//! specialisation (`GrassPipelines`, see `grass_spec`).

use super::draw::DEPTH_FORMAT;
use super::grass_spec::GrassSpec;
use crate::shaders;

/// A pass that draws one full-screen triangle (no vertex buffers, no depth) into one colour
/// target of `format` with `blend`: the tone mapping, the upscale, the window's panel
/// composite. `entries`: the vertex and fragment entry points of `module`; `constants`: the
/// fragment stage's overridable constants.
#[allow(clippy::too_many_arguments)]
pub fn fullscreen_pipeline(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    entries: (&str, &str),
    format: wgpu::TextureFormat,
    blend: Option<wgpu::BlendState>,
    constants: &[(&str, f64)],
) -> wgpu::RenderPipeline {
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(entries.0),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(entries.1),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants,
                ..Default::default()
            },
            targets: &[Some(wgpu::ColorTargetState {
                format,
                blend,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// A render pass that clears `view` and draws into it alone, with `q`'s timestamps: the
/// full-screen passes (TAA, tone mapping, upscale) begin with it.
pub fn fullscreen_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    view: &wgpu::TextureView,
    q: &crate::gpu::queries::PassQueries<'_>,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: None,
        timestamp_writes: q.render_writes(),
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

pub(crate) struct PipelineSpec<'a> {
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
    /// The shader's pipeline-overridable constants (the grass's `GrassSpec`).
    pub constants: &'a [(&'a str, f64)],
}

pub(crate) fn pipeline(
    device: &wgpu::Device,
    format: wgpu::TextureFormat,
    samples: u32,
    spec: PipelineSpec,
) -> wgpu::RenderPipeline {
    pipeline_for(device, (format, DEPTH_FORMAT), samples, spec)
}

/// [`pipeline`] for a colour target and a depth buffer of the given formats (a host's
/// pass, `render::host`).
pub(crate) fn pipeline_for(
    device: &wgpu::Device,
    (format, depth_format): (wgpu::TextureFormat, wgpu::TextureFormat),
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
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: spec.constants,
                ..Default::default()
            },
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
            format: depth_format,
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
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: spec.constants,
                ..Default::default()
            },
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

/// How a depth-only pipeline tests and writes depth (`depth_only_pipeline`).
pub(crate) struct DepthOnly {
    pub compare: wgpu::CompareFunction,
    pub write: bool,
    pub bias: wgpu::DepthBiasState,
    pub samples: u32,
}

/// A vertex stage without a fragment stage, both sides drawn, into a depth target: the
/// shadow casters and the grass's coverage measurement.
pub(crate) fn depth_only_pipeline(
    device: &wgpu::Device,
    label: &str,
    (shader, entry): (&str, &str),
    layout: &wgpu::BindGroupLayout,
    buffers: &[Option<wgpu::VertexBufferLayout>],
    constants: &[(&str, f64)],
    depth: DepthOnly,
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
            compilation_options: wgpu::PipelineCompilationOptions {
                constants,
                ..Default::default()
            },
            buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::TriangleList,
            cull_mode: None,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(depth.write),
            depth_compare: Some(depth.compare),
            stencil: Default::default(),
            bias: depth.bias,
        }),
        multisample: wgpu::MultisampleState {
            count: depth.samples,
            ..Default::default()
        },
        fragment: None,
        multiview_mask: None,
        cache: None,
    })
}

/// A shadow caster's pipeline: `entry` of `shader` into a single-sample depth map, both
/// sides drawn, with a slope-scaled depth bias against acne on surfaces at grazing sun.
/// The depth bias of every shadow caster (sward's own and a host's, `embed`): enough to
/// keep a lit surface from shadowing itself at the maps' resolution.
pub const SHADOW_BIAS: wgpu::DepthBiasState = wgpu::DepthBiasState {
    constant: 2,
    slope_scale: 1.5,
    clamp: 0.0,
};

pub(crate) fn shadow_pipeline(
    device: &wgpu::Device,
    label: &str,
    stage: (&str, &str),
    layout: &wgpu::BindGroupLayout,
    buffers: &[Option<wgpu::VertexBufferLayout>],
    constants: &[(&str, f64)],
) -> wgpu::RenderPipeline {
    let depth = DepthOnly {
        compare: wgpu::CompareFunction::LessEqual,
        write: true,
        bias: SHADOW_BIAS,
        samples: 1,
    };
    depth_only_pipeline(device, label, stage, layout, buffers, constants, depth)
}

/// The render pipelines of the draw pass, for one colour format and sample count.
pub(super) struct Pipelines {
    pub samples: u32,
    pub sky: wgpu::RenderPipeline,
    pub terrain: wgpu::RenderPipeline,
    /// What `terrain` was specialised for.
    pub terrain_spec: TerrainSpec,
    pub spheres: wgpu::RenderPipeline,
    /// Depth-only terrain and colliders (the occluder pass).
    pub terrain_depth: wgpu::RenderPipeline,
    pub spheres_depth: wgpu::RenderPipeline,
    /// The sun's shadow casters: terrain and colliders (the grass's are in `grass`).
    pub shadow_terrain: wgpu::RenderPipeline,
    pub shadow_spheres: wgpu::RenderPipeline,
    pub grass: GrassPipelines,
}

/// The lit terrain's specialisation: the lookups its field has no data for are compiled
/// out. A software rasteriser runs both sides of an `if` for its whole SIMD batch, so a
/// lookup behind a uniform test still costs every ground pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TerrainSpec {
    /// The field has a trail map (`TRAILS`).
    pub trails: bool,
    /// The scene has a density map (`DENSITY_MAP`).
    pub density_map: bool,
}

impl TerrainSpec {
    /// The terrain shader's pipeline-overridable constants.
    fn constants(self) -> [(&'static str, f64); 2] {
        [
            ("TRAILS", f64::from(u8::from(self.trails))),
            ("DENSITY_MAP", f64::from(u8::from(self.density_map))),
        ]
    }
}

impl Pipelines {
    /// `layouts`: frame, terrain, spheres and grass bind group layouts; `spec`: the
    /// grass pipelines' specialisation; `terrain`: the terrain's.
    pub fn new(
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        samples: u32,
        layouts: [&wgpu::BindGroupLayout; 4],
        spec: GrassSpec,
        terrain: TerrainSpec,
    ) -> Self {
        let [frame_layout, terrain_layout, spheres_layout, grass_layout] = layouts;
        let sphere_attrs = wgpu::vertex_attr_array![0 => Float32x3];
        let sphere_buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: 12,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &sphere_attrs,
        })];
        let sky = sky_pipeline(device, (format, samples), frame_layout, spec);
        let terrain_pipeline = pipeline(
            device,
            format,
            samples,
            PipelineSpec {
                label: "sward.draw.terrain",
                shader: "terrain.wgsl",
                vertex: "vs_lit",
                layout: terrain_layout,
                buffers: &[],
                depth_write: true,
                cull_back: true,
                lines: false,
                depth_only: false,
                constants: &terrain.constants(),
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
                constants: &[],
            },
        );
        let depth_only = |label, shader, layout, buffers, cull_back| {
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
                    cull_back,
                    lines: false,
                    depth_only: true,
                    constants: &[],
                },
            )
        };
        let terrain_depth = depth_only(
            "sward.draw.terrain_depth",
            "terrain.wgsl",
            terrain_layout,
            &[],
            true,
        );
        let spheres_depth = depth_only(
            "sward.draw.spheres_depth",
            "spheres.wgsl",
            spheres_layout,
            &sphere_buffers,
            false,
        );
        let shadow_terrain = shadow_pipeline(
            device,
            "sward.light.shadow_terrain",
            ("terrain.wgsl", "vs_shadow"),
            terrain_layout,
            &[],
            &[],
        );
        let shadow_spheres = shadow_pipeline(
            device,
            "sward.light.shadow_spheres",
            ("spheres.wgsl", "vs_main"),
            spheres_layout,
            &sphere_buffers,
            &[],
        );
        let grass = GrassPipelines::new(device, format, samples, grass_layout, spec);
        Self {
            samples,
            sky,
            terrain: terrain_pipeline,
            terrain_spec: terrain,
            spheres,
            terrain_depth,
            spheres_depth,
            shadow_terrain,
            shadow_spheres,
            grass,
        }
    }
}

/// The sky pass's pipeline, built for `spec`'s sky model (`GrassSpec::sky_constant`;
/// `None`: the uniform's): the pass shades every pixel the sky shows, and llvmpipe would
/// run both models for each.
pub(super) fn sky_pipeline(
    device: &wgpu::Device,
    (format, samples): (wgpu::TextureFormat, u32),
    frame_layout: &wgpu::BindGroupLayout,
    spec: GrassSpec,
) -> wgpu::RenderPipeline {
    let constants = [spec.sky_constant()];
    pipeline(
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
            constants: &constants,
        },
    )
}

/// The grass's pipelines for one colour format, sample count and specialisation: lit,
/// as lines, and the shadow casters'.
pub(super) struct GrassPipelines {
    pub spec: GrassSpec,
    pub grass: wgpu::RenderPipeline,
    /// The grass as lines, when the device has `POLYGON_MODE_LINE`.
    pub grass_lines: Option<wgpu::RenderPipeline>,
    /// The blades into a sun's shadow cascade (the coarsest level's mesh).
    pub shadow_grass: wgpu::RenderPipeline,
    /// The deferred shading's (`render::deferred`): with a specialisation without flower
    /// heads or debug views, at this sample count.
    pub deferred: Option<super::deferred::DeferredPipelines>,
}

impl GrassPipelines {
    pub fn new(
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        samples: u32,
        layout: &wgpu::BindGroupLayout,
        spec: GrassSpec,
    ) -> Self {
        let constants = spec.constants();
        // Blades have no back: both sides are drawn and lit (two-sided lighting).
        let grass = pipeline(
            device,
            format,
            samples,
            PipelineSpec {
                label: "sward.draw.grass",
                shader: "grass.wgsl",
                vertex: "vs_lit",
                layout,
                buffers: &[],
                depth_write: true,
                cull_back: false,
                lines: false,
                depth_only: false,
                constants: &constants,
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
                        layout,
                        buffers: &[],
                        depth_write: true,
                        cull_back: false,
                        lines: true,
                        depth_only: false,
                        constants: &constants,
                    },
                )
            });

        // The casters' vertex stage is built for the cascades' draw (`CASTER`).
        let mut caster_constants = constants.to_vec();
        caster_constants.push(("CASTER", 1.0));
        let shadow_grass = shadow_pipeline(
            device,
            "sward.light.shadow_grass",
            ("grass.wgsl", "vs_main"),
            layout,
            &[],
            &caster_constants,
        );
        // Multisampled, where every adapter multisamples the visibility buffer's format
        // with this count (WebGPU guarantees 4x); otherwise the grass is drawn forward.
        let vis_samples = samples == 1
            || super::deferred::VIS_MS_FORMAT
                .guaranteed_format_features(device.features())
                .flags
                .sample_count_supported(samples);
        let deferred = (vis_samples && !spec.flowers && !spec.debug_views)
            .then(|| {
                super::deferred::DeferredPipelines::new(
                    device,
                    layout,
                    &constants,
                    samples,
                    spec.sun_per_row,
                )
            });
        Self {
            spec,
            grass,
            grass_lines,
            shadow_grass,
            deferred,
        }
    }
}
