//! The billboards' GPU side: the atlas, the uniforms, the cull that keeps the cards in the
//! ring and in view (`billboard_cull.wgsl`, one invocation per cell) and the indirect draw
//! of the cards it kept (`billboard.wgsl`).

use crate::gpu::queries::PassQueries;
use bytemuck::{Pod, Zeroable};

use super::{atlas, BillboardLayout, BillboardParams};
use crate::error::Result;
use crate::field::DensityMap;
use crate::gpu::{read_buffer, Gpu};
use crate::render::draw::DEPTH_FORMAT;
use crate::scene::types::{Culling, Field};
use crate::shaders;
use crate::sim::update::{compute_storage_entry, uniform_entry};

/// A card the cull kept (`DrawnCard` in `billboard_place.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct DrawnCard {
    /// Root on the terrain; fade in (0, 1].
    pub pos_fade: [f32; 4],
    /// Offset of the card's top (sway and bending); size factor.
    pub top_scale: [f32; 4],
    /// Cell index, atlas variant, 1 = mirrored, level.
    pub info: [u32; 4],
    /// The blades' light on the card per unit of the atlas's mean albedo: the sky's part
    /// (rgb), and in w the contrast gain its texels are shown with (`far_gain`, handed over
    /// to 1 far out).
    pub light_ambient: [f32; 4],
    /// The sun's part of the blades' light on the card, one rgb per atlas facing
    /// ([`atlas::FACINGS`]), per unit of the atlas's mean albedo; the first facing's w is
    /// the mip bias of the card's texels (0 far out), the others' unused.
    pub light_sun: [[f32; 4]; atlas::FACINGS],
}

const _: () = assert!(std::mem::size_of::<DrawnCard>() == 128);

/// Cells per workgroup of the cull.
const CULL_WORKGROUP: u32 = 64;

/// Bytes of the cards' draw arguments: the indirect draw (16), then per workgroup of the
/// cull its lanes' kept bits and its first slot (three words, `ORDER_WORDS`).
fn args_bytes(cards: u32) -> u64 {
    16 + u64::from(cards.div_ceil(CULL_WORKGROUP)) * 12
}

fn buf(binding: u32, b: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: b.as_entire_binding(),
    }
}

/// The billboard pass: the atlas, the uniforms, the cull and the draw for one sample count.
pub struct BillboardPass {
    /// The grids the cards are placed on (radius, base cell, levels, card size).
    pub layout: BillboardLayout,
    params: wgpu::Buffer,
    /// Each atlas layer's height profile (`atlas::profile`, binding 7 of the draw).
    profile: wgpu::Buffer,
    /// The kept cards, and the draw's indirect arguments (six vertices per card).
    cards: wgpu::Buffer,
    args: wgpu::Buffer,
    cull_layout: wgpu::BindGroupLayout,
    cull_group: wgpu::BindGroup,
    /// The cull's three passes (`billboard_cull.wgsl`): mark each workgroup's kept cards,
    /// give each workgroup its first slot, write the cards: the list is in the order the
    /// cells are visited, whatever order the workgroups run in.
    cull_pipeline: [wgpu::ComputePipeline; 3],
    draw_layout: wgpu::BindGroupLayout,
    draw_group: wgpu::BindGroup,
    pipeline: wgpu::RenderPipeline,
    format: wgpu::TextureFormat,
    samples: u32,
    density: wgpu::Texture,
    has_density: bool,
    /// The coverage-weighted mean albedo of the atlas.
    pub mean_albedo: [f32; 3],
}

/// The buffers the billboards read from the rest of the frame.
pub struct Inputs<'a> {
    /// The draw pass's frame uniforms (`Frame`, binding 0).
    pub frame: &'a wgpu::Buffer,
    /// The terrain's parameters (`TerrainParams` in `terrain_height.wgsl`, binding 1).
    pub terrain_params: &'a wgpu::Buffer,
    /// The terrain's height grid (a dummy for analytic terrains; binding 2).
    pub terrain_grid: &'a wgpu::Buffer,
    /// The collider spheres (`vec4`: centre xyz and radius, m) that bend the cards (binding 6).
    pub spheres: &'a wgpu::Buffer,
    /// The simulation's uniforms (`SimParams`, binding 7).
    pub sim_params: &'a wgpu::Buffer,
    /// The wind solver's velocity grid (`vec2` per cell, m/s along x, z; binding 8).
    pub wind_grid: &'a wgpu::Buffer,
    /// The gusts' bend at the edge of the blades' reach (the far levels' shading waves).
    pub waves: &'a wgpu::Buffer,
    /// The trail map (`field::trails`; a zeroed header when the field keeps none).
    pub trails: &'a wgpu::Buffer,
}

impl BillboardPass {
    /// Renders the atlas for `field` on the CPU and uploads it, then builds the cull and the
    /// draw for colour `format` and `samples` MSAA samples, bound to `inputs` and to the
    /// density map when there is one.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        gpu: &Gpu,
        layout: BillboardLayout,
        field: &Field,
        density: Option<&DensityMap>,
        inputs: &Inputs,
        format: wgpu::TextureFormat,
        samples: u32,
    ) -> Self {
        let device = &gpu.device;
        let mut layers: Vec<atlas::Layer> = (0..atlas::VARIANTS)
            .map(|v| atlas::render_layer(field, layout.card, v))
            .collect();
        // The cards average to the far ground's grass colour, so that the middle and the
        // far level read as one field (the tufts keep their variation around it).
        atlas::match_mean(
            &mut layers,
            crate::render::clipmap::far_albedo(field).into(),
        );
        let mean_albedo = atlas::mean_color(&layers);
        // Each layer's height profile, the mean its texels are moved from by the contrast
        // gain (`card_profile.wgsl`).
        let profile_rows: Vec<atlas::ProfileRow> = layers.iter().flat_map(atlas::profile).collect();
        let profile = wgpu::util::DeviceExt::create_buffer_init(
            device,
            &wgpu::util::BufferInitDescriptor {
                label: Some("sward.billboard.profile"),
                contents: bytemuck::cast_slice(&profile_rows),
                usage: wgpu::BufferUsages::STORAGE,
            },
        );
        let atlas_tex = upload_atlas(
            gpu,
            "sward.billboard.atlas",
            wgpu::TextureFormat::Rgba8UnormSrgb,
            &layers,
            &layers.iter().map(atlas::mip_chain).collect::<Vec<_>>(),
            atlas::encode,
        );
        let facing_tex = upload_atlas(
            gpu,
            "sward.billboard.facing",
            wgpu::TextureFormat::Rgba8Unorm,
            &layers,
            &layers.iter().map(atlas::facing_chain).collect::<Vec<_>>(),
            atlas::encode_facing,
        );
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("sward.billboard.sampler"),
            // A level-k card repeats the strip 2^k times across.
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Nearest,
            ..Default::default()
        });
        let density_tex = crate::render::terrain::density_texture(gpu, density);
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.billboard.params"),
            size: std::mem::size_of::<BillboardParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let cards = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.billboard.cards"),
            size: layout.card_count() as u64 * std::mem::size_of::<DrawnCard>() as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let args = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.billboard.args"),
            size: args_bytes(layout.card_count()),
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::INDIRECT
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let c = wgpu::ShaderStages::COMPUTE;
        let texture = |binding, dim, visibility| wgpu::BindGroupLayoutEntry {
            binding,
            visibility,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: true },
                view_dimension: dim,
                multisampled: false,
            },
            count: None,
        };
        let cull_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.billboard.cull_layout"),
            entries: &[
                uniform_entry(0, c),
                crate::render::draw::read_storage(1, c),
                compute_storage_entry(2, true),
                uniform_entry(3, c),
                compute_storage_entry(6, true),
                uniform_entry(7, c),
                compute_storage_entry(8, true),
                texture(9, wgpu::TextureViewDimension::D2, c),
                compute_storage_entry(10, false),
                compute_storage_entry(11, false),
                compute_storage_entry(12, true),
                compute_storage_entry(13, true),
            ],
        });
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let v = wgpu::ShaderStages::VERTEX;
        let mut cards_entry = compute_storage_entry(10, true);
        cards_entry.visibility = v;
        let mut profile_entry = compute_storage_entry(7, true);
        profile_entry.visibility = v;
        // The terrain's height function (bindings 1, 2): the ground's normal under a card.
        let mut grid_entry = compute_storage_entry(2, true);
        grid_entry.visibility = v;
        let draw_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.billboard.draw_layout"),
            entries: &[
                uniform_entry(0, vf),
                crate::render::draw::read_storage(1, v),
                grid_entry,
                uniform_entry(3, vf),
                texture(
                    4,
                    wgpu::TextureViewDimension::D2Array,
                    wgpu::ShaderStages::FRAGMENT,
                ),
                wgpu::BindGroupLayoutEntry {
                    binding: 5,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
                texture(
                    6,
                    wgpu::TextureViewDimension::D2Array,
                    wgpu::ShaderStages::FRAGMENT,
                ),
                profile_entry,
                cards_entry,
            ],
        });
        let cull_module = shaders::module(device, "billboard_cull.wgsl");
        // Group 1: the frame's light (the cull lights each card with the blades' terms).
        let light_layout = crate::render::light::layout(device);
        let cull_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sward.billboard.cull_pipeline_layout"),
            bind_group_layouts: &[Some(&cull_layout), Some(&light_layout)],
            immediate_size: 0,
        });
        let cull_stage = |entry: &str, label: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(label),
                layout: Some(&cull_pipeline_layout),
                module: &cull_module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let cull_pipeline = [
            cull_stage("mark_cards", "sward.billboard.cull.mark"),
            cull_stage("order_cards", "sward.billboard.cull.order"),
            cull_stage("cull_cards", "sward.billboard.cull"),
        ];
        let atlas_view = atlas_tex.create_view(&wgpu::TextureViewDescriptor {
            label: Some("sward.billboard.atlas_view"),
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let facing_view = facing_tex.create_view(&wgpu::TextureViewDescriptor {
            label: Some("sward.billboard.facing_view"),
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let draw_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sward.billboard.draw_group"),
            layout: &draw_layout,
            entries: &[
                buf(0, inputs.frame),
                buf(1, inputs.terrain_params),
                buf(2, inputs.terrain_grid),
                buf(3, &params),
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::TextureView(&atlas_view),
                },
                wgpu::BindGroupEntry {
                    binding: 5,
                    resource: wgpu::BindingResource::Sampler(&sampler),
                },
                wgpu::BindGroupEntry {
                    binding: 6,
                    resource: wgpu::BindingResource::TextureView(&facing_view),
                },
                buf(7, &profile),
                buf(10, &cards),
            ],
        });
        let cull_group = Self::bind_cull(
            device,
            &cull_layout,
            &params,
            &cards,
            &args,
            &density_tex,
            inputs,
        );
        let pipeline = Self::pipeline(device, &draw_layout, (format, DEPTH_FORMAT), samples, false);
        Self {
            layout,
            params,
            profile,
            cards,
            args,
            cull_layout,
            cull_group,
            cull_pipeline,
            draw_layout,
            draw_group,
            pipeline,
            format,
            samples,
            density: density_tex,
            has_density: density.is_some(),
            mean_albedo,
        }
    }

    fn bind_cull(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        params: &wgpu::Buffer,
        cards: &wgpu::Buffer,
        args: &wgpu::Buffer,
        density: &wgpu::Texture,
        inputs: &Inputs,
    ) -> wgpu::BindGroup {
        let density_view = density.create_view(&Default::default());
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sward.billboard.cull_group"),
            layout,
            entries: &[
                buf(0, inputs.frame),
                buf(1, inputs.terrain_params),
                buf(2, inputs.terrain_grid),
                buf(3, params),
                buf(6, inputs.spheres),
                buf(7, inputs.sim_params),
                buf(8, inputs.wind_grid),
                wgpu::BindGroupEntry {
                    binding: 9,
                    resource: wgpu::BindingResource::TextureView(&density_view),
                },
                buf(10, cards),
                buf(11, args),
                buf(12, inputs.waves),
                buf(13, inputs.trails),
            ],
        })
    }

    /// Rebinds the frame's buffers (after the wind solver or the update was rebuilt). The
    /// draw reads only the frame uniforms, which the draw pass keeps for its life.
    pub fn rebind(&mut self, device: &wgpu::Device, inputs: &Inputs) {
        self.cull_group = Self::bind_cull(
            device,
            &self.cull_layout,
            &self.params,
            &self.cards,
            &self.args,
            &self.density,
            inputs,
        );
    }

    /// The cards' pipeline for colour and depth `formats` and `samples`; `display`: the
    /// scene's tone curve applied (a host's 8-bit target).
    fn pipeline(
        device: &wgpu::Device,
        bind_layout: &wgpu::BindGroupLayout,
        formats: (wgpu::TextureFormat, wgpu::TextureFormat),
        samples: u32,
        display: bool,
    ) -> wgpu::RenderPipeline {
        let (format, depth_format) = formats;
        let constants = [("DISPLAY_OUTPUT", f64::from(u8::from(display)))];
        let module = shaders::module(device, "billboard.wgsl");
        // Group 1: the sun, the sky and the shadow map (bound by the colour pass).
        let light = crate::render::light::layout(device);
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sward.billboard.pipeline_layout"),
            bind_group_layouts: &[Some(bind_layout), Some(&light)],
            immediate_size: 0,
        });
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("sward.billboard"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: depth_format,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::LessEqual),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            // With MSAA the card's alpha also covers samples (alpha-to-coverage): smooth
            // cut-outs without sorting.
            multisample: wgpu::MultisampleState {
                count: samples,
                alpha_to_coverage_enabled: samples > 1,
                ..Default::default()
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_main"),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: &constants,
                    ..Default::default()
                },
                // Alpha drives the coverage; the scene target's alpha (1: radiance, for
                // the tone mapper) stays as the sky or the ground left it.
                targets: &[Some(wgpu::ColorTargetState {
                    format,
                    blend: None,
                    write_mask: wgpu::ColorWrites::COLOR,
                })],
            }),
            multiview_mask: None,
            cache: None,
        })
    }

    /// Rebuilds the pipeline for another sample count.
    pub fn set_samples(&mut self, device: &wgpu::Device, samples: u32) {
        if samples != self.samples {
            self.samples = samples;
            self.pipeline =
                Self::pipeline(device, &self.draw_layout, (self.format, DEPTH_FORMAT), samples, false);
        }
    }

    /// The radius the cards are drawn to (m) for the share `share` of the billboard radius
    /// (the frame budget may draw only the nearer part of the ring; the grid stays), never
    /// short of where they have faded in for the blades' reach `max_distance`.
    pub fn drawn_radius(&self, share: f32, max_distance: f32) -> f32 {
        (self.layout.radius * share.clamp(0.0, 1.0)).max(super::fade_in(max_distance).1)
    }

    /// Writes this frame's uniforms for the share `share` of the billboard radius; returns
    /// them (the stats count the cards with them).
    pub fn prepare(
        &self,
        queue: &wgpu::Queue,
        camera: &crate::render::camera::CameraView,
        culling: &Culling,
        spheres: u32,
        terrain_size: f32,
        share: f32,
    ) -> BillboardParams {
        let eye = camera.eye;
        let mut p = self.layout.params(
            eye,
            culling.max_distance,
            self.has_density,
            spheres,
            terrain_size,
        );
        let radius = self.drawn_radius(share, culling.max_distance);
        p.fade[2] = super::FADE_OUT * radius;
        p.fade[3] = radius;
        p.levels[3] = super::visit_flags(camera.target - camera.eye);
        p.albedo = [
            self.mean_albedo[0],
            self.mean_albedo[1],
            self.mean_albedo[2],
            0.0,
        ];
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&p));
        p
    }

    /// Records the cull over every cell of the grid (after [`Self::prepare`], the frame
    /// uniforms and the light's, before the draw pass), with the frame's `light` group.
    pub fn encode_cull(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        light: &wgpu::BindGroup,
        q: PassQueries,
    ) {
        encoder.clear_buffer(&self.args, 0, None);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("sward.billboard.cull"),
            timestamp_writes: q.compute_writes(),
        });
        q.begin(&mut pass);
        pass.set_bind_group(0, &self.cull_group, &[]);
        pass.set_bind_group(1, light, &[]);
        let groups = self.layout.card_count().div_ceil(CULL_WORKGROUP);
        let [mark, order, cull] = &self.cull_pipeline;
        pass.set_pipeline(mark);
        pass.dispatch_workgroups(groups, 1, 1);
        pass.set_pipeline(order);
        pass.dispatch_workgroups(1, 1, 1);
        pass.set_pipeline(cull);
        pass.dispatch_workgroups(groups, 1, 1);
        q.end(&mut pass);
    }

    /// Draws the cards the cull kept (in the caller's colour pass).
    pub fn draw<'a>(&'a self, pass: &mut wgpu::RenderPass<'a>) {
        self.draw_with(pass, &self.pipeline);
    }

    /// The cards' pipeline for a host's pass (`render::host`): its colour and depth formats
    /// and samples, display colour where the host's target is 8-bit.
    pub fn host_pipeline(
        &self,
        device: &wgpu::Device,
        target: crate::render::host::HostTarget,
    ) -> wgpu::RenderPipeline {
        Self::pipeline(
            device,
            &self.draw_layout,
            (target.color_format, target.depth_format),
            target.samples,
            target.display,
        )
    }

    /// Draws the cards the cull kept with `pipeline` (this pass's own or a host's).
    pub fn draw_with(&self, pass: &mut wgpu::RenderPass<'_>, pipeline: &wgpu::RenderPipeline) {
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &self.draw_group, &[]);
        pass.draw_indirect(&self.args, 0);
    }

    /// How many cards the last cull kept (blocking).
    pub fn read_drawn(&self, gpu: &Gpu) -> Result<u32> {
        let args: Vec<u32> = bytemuck::pod_collect_to_vec(&read_buffer(gpu, &self.args, 16)?);
        Ok(args[0] / 6)
    }

    /// Reads the cards the last cull kept back (blocking), in the order it wrote them.
    pub fn read_cards(&self, gpu: &Gpu) -> Result<Vec<DrawnCard>> {
        let n = self.read_drawn(gpu)? as usize;
        if n == 0 {
            return Ok(Vec::new());
        }
        let bytes = read_buffer(
            gpu,
            &self.cards,
            (n * std::mem::size_of::<DrawnCard>()) as u64,
        )?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }

    /// GPU bytes held: the atlas and its facings with their mips, the uniforms, the card
    /// list and its draw.
    pub fn gpu_bytes(&self) -> u64 {
        let (w, h) = atlas::layer_size(self.layout.card);
        2 * (w * h * 4 * atlas::VARIANTS) as u64 * 4 / 3
            + std::mem::size_of::<BillboardParams>() as u64
            + self.profile.size()
            + self.cards.size()
            + self.args.size()
    }
}

/// One texture array of the atlas (one layer per variant) from its mip chains, each
/// level encoded to RGBA8 by `encode`.
fn upload_atlas<T>(
    gpu: &Gpu,
    label: &str,
    format: wgpu::TextureFormat,
    layers: &[atlas::Layer],
    chains: &[Vec<Vec<T>>],
    encode: impl Fn(&[T]) -> Vec<u8>,
) -> wgpu::Texture {
    let mips = chains[0].len() as u32;
    let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: layers[0].width,
            height: layers[0].height,
            depth_or_array_layers: atlas::VARIANTS,
        },
        mip_level_count: mips,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for (layer, chain) in chains.iter().enumerate() {
        for (level, texels) in chain.iter().enumerate() {
            let w = (layers[0].width >> level).max(1);
            let h = (layers[0].height >> level).max(1);
            gpu.queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &texture,
                    mip_level: level as u32,
                    origin: wgpu::Origin3d {
                        x: 0,
                        y: 0,
                        z: layer as u32,
                    },
                    aspect: wgpu::TextureAspect::All,
                },
                &encode(texels),
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(4 * w),
                    rows_per_image: Some(h),
                },
                wgpu::Extent3d {
                    width: w,
                    height: h,
                    depth_or_array_layers: 1,
                },
            );
        }
    }
    texture
}
