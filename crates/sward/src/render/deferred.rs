//! Deferred grass shading (`shaders/grass_deferred.wgsl`; issue 26, point 5): the grass
//! draw writes a visibility buffer (which blade, where on it, its depth) instead of lit
//! colours, and the light runs once per grass pixel in two compute passes: one lists the
//! pixels where the grass is still the nearest surface, one lights them into the scene
//! target.
//!
//! Why: a software rasteriser shades a fragment for every pixel of each 4 x 4 block a
//! triangle touches, so blades a pixel or two wide ran the lit shading about 25 times per
//! pixel they cover (nature at 1280x720: 24.5 lit fragments per covered pixel), and the
//! rasteriser's threads spent a third of the draw on it. The compute passes run on every
//! core and shade each grass pixel once.
//!
//! With multisampling (`shaders/grass_deferred_msaa.wgsl`) the visibility buffer is
//! multisampled too and the light still runs in one invocation per grass pixel: after the
//! hardware resolve, each of the pixel's first two blades is lit once, at the first sample
//! it covers, and the pixel is resolved again from its samples (each grass sample under its
//! own blade's light, the multisampled colour in the others). The visibility draws write
//! alpha [`GRASS_ALPHA`] into the colour's samples they cover, so the samples nothing
//! covered after the grass are known. Forward MSAA shaded about 42 lit fragments per covered pixel on nature at
//! 1280x720.
//!
//! The path is taken with filled triangles and grass pipelines specialised without flower
//! heads or debug views (`DrawPass::deferred`); everything else is drawn forward, as
//! before.

use crate::error::{Error, Result};
use crate::gpu::queries::PassQueries;
use crate::gpu::Gpu;

/// The visibility buffer: blade index, `pack2x16unorm(u, v)`, the depth's bits, and 1
/// where grass was drawn (0 cleared).
pub const VIS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;

/// The multisampled visibility buffer: blade index in two 16-bit halves, u and v in 16
/// bits each (a format every adapter can multisample).
pub const VIS_MS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Uint;

/// The alpha the multisampled visibility draws leave in the colour's grass samples: a
/// sample still at it after every draw is grass that nothing covered later. Negative, so
/// no pass writes it (lit passes write 1, the arrows 0, the cards' coverage 0 to 1); exact
/// in half floats.
pub const GRASS_ALPHA: f64 = -1.0;

/// The alpha the deferred shading leaves in the scene target for each grass sample it
/// lights (`BLADE_ALPHA` in `grass_vis.wgsl`): above the 1 of every other lit pass, so a
/// pixel's alpha `1 + (BLADE_ALPHA − 1) s` tells the share `s` of it the blades cover. The
/// far gain's measurement tells the near blades from the cards by it (`far_gain`); the
/// tone mapping reads any alpha of 1 or more as radiance.
pub const BLADE_ALPHA: f32 = 3.0;

/// Widest multisampled target the path takes: the pixel list packs x and y in 14 bits.
const MS_MAX_SIDE: u32 = 1 << 14;

/// Pixels along a row that one invocation of the one-sample pixel pass lists (`LIST_RUN`
/// in `grass_deferred.wgsl`).
pub const LIST_RUN: u32 = 4;

/// Invocations per workgroup of the shading pass (`SHADE_GROUP` in the shader).
pub const SHADE_GROUP: u32 = 256;

/// Values of the sun's visibility kept along each drawn blade for the deferred shading
/// (`SUN_POINTS` in `grass_vis.wgsl`), at v = k / (points − 1), 8 bits each.
pub const SUN_POINTS: u32 = 8;
/// Invocations of the sun's pass (`SUN_INVOCATIONS`), in workgroups of [`SUN_GROUP`]: each
/// takes every 1,024th drawn blade.
pub const SUN_INVOCATIONS: u32 = 1024;
/// Workgroup size of the sun's pass.
const SUN_GROUP: u32 = 64;

/// Blade `index`'s sun at height `v` from its [`SUN_POINTS`] values (`words`, as the sun's
/// pass packs them: 8 bits each, four to a word, root first), linearly between them: the
/// CPU twin of `sun_at` in `grass_vis.wgsl`.
pub fn sun_at(words: [u32; 2], v: f32) -> f32 {
    let byte = |k: u32| ((words[(k / 4) as usize] >> (8 * (k % 4))) & 0xff) as f32;
    let x = v.clamp(0.0, 1.0) * (SUN_POINTS - 1) as f32;
    let k = (x as u32).min(SUN_POINTS - 2);
    let (a, b) = (byte(k), byte(k + 1));
    (a + (b - a) * (x - k as f32)) / 255.0
}

/// Bytes of the indirect dispatch arguments and the list length (`ShadeArgs`).
const ARGS_BYTES: u64 = 16;

/// Texels per side of the sky's table for the fog (`SKY_LUT_SIDE` in
/// `grass_deferred.wgsl`): an octahedral map of every direction, about 2.8° a texel.
pub const SKY_LUT_SIDE: u32 = 64;
/// The sky table's format: filterable, and writable as a storage texture everywhere.
const SKY_LUT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The unit direction at `uv` of the sky table's octahedral map (the CPU twin of
/// `octahedral_direction` in `grass_deferred.wgsl`): the upper hemisphere in the diamond
/// around the centre, the lower folded into the corners.
pub fn octahedral_direction(uv: glam::Vec2) -> glam::Vec3 {
    let f = uv * 2.0 - glam::Vec2::ONE;
    let mut d = glam::Vec3::new(f.x, 1.0 - f.x.abs() - f.y.abs(), f.y);
    let t = (-d.y).max(0.0);
    d.x += if d.x >= 0.0 { -t } else { t };
    d.z += if d.z >= 0.0 { -t } else { t };
    d.normalize()
}

/// The direction of texel (`x`, `y`)'s centre in the sky table.
pub fn sky_lut_direction(x: u32, y: u32) -> glam::Vec3 {
    let side = SKY_LUT_SIDE as f32;
    octahedral_direction(glam::Vec2::new(
        (x as f32 + 0.5) / side,
        (y as f32 + 0.5) / side,
    ))
}

/// The deferred path's bind group layout (group 2 of its compute passes): the visibility
/// buffer, the depth (multisampled: the multisampled colour instead), the scene target,
/// the pixel list, the shading's arguments, and the sky's table for the fog (written by
/// the one-sample pixel pass, sampled by its shading, with its sampler).
pub fn layout(device: &wgpu::Device, samples: u32) -> wgpu::BindGroupLayout {
    let multisampled = samples > 1;
    let compute = wgpu::ShaderStages::COMPUTE;
    let storage = |binding| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: compute,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: false },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(if multisampled {
            "sward.deferred.layout_ms"
        } else {
            "sward.deferred.layout"
        }),
        entries: &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: compute,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Uint,
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: compute,
                ty: wgpu::BindingType::Texture {
                    sample_type: if multisampled {
                        wgpu::TextureSampleType::Float { filterable: false }
                    } else {
                        wgpu::TextureSampleType::Depth
                    },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 2,
                visibility: compute,
                ty: wgpu::BindingType::StorageTexture {
                    access: wgpu::StorageTextureAccess::WriteOnly,
                    format: super::post::HDR_FORMAT,
                    view_dimension: wgpu::TextureViewDimension::D2,
                },
                count: None,
            },
            storage(3),
            storage(4),
            wgpu::BindGroupLayoutEntry {
                binding: 5,
                visibility: compute,
                ty: wgpu::BindingType::StorageTexture {
                    access: wgpu::StorageTextureAccess::WriteOnly,
                    format: SKY_LUT_FORMAT,
                    view_dimension: wgpu::TextureViewDimension::D2,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 6,
                visibility: compute,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: true },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 7,
                visibility: compute,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                count: None,
            },
        ],
    })
}

/// The deferred path's pipelines for one grass specialisation.
pub(super) struct DeferredPipelines {
    /// The blades into the visibility buffer.
    pub vis: wgpu::RenderPipeline,
    /// Lists the pixels the grass is nearest in.
    pub pixels: wgpu::ComputePipeline,
    /// Lights the listed pixels.
    pub shade: wgpu::ComputePipeline,
    /// Fills the sky's table for the fog (one sample per pixel; the multisampled shading
    /// looks the sky up per pixel).
    pub sky: Option<wgpu::ComputePipeline>,
    /// Looks the sun up along the drawn blades at their rows, for either shading, with
    /// `BladeShadowLookup::PerRow`.
    pub sun: Option<wgpu::ComputePipeline>,
}

impl DeferredPipelines {
    /// `grass_layout`: the grass draw's group 0; `constants`: the specialisation's;
    /// `samples`: the colour pass's samples per pixel (the multisampled path above 1);
    /// `sun_per_row`: the sun looked up along the drawn blades at their rows
    /// (`BladeShadowLookup::PerRow`) instead of per pixel.
    pub fn new(
        device: &wgpu::Device,
        grass_layout: &wgpu::BindGroupLayout,
        constants: &[(&str, f64)],
        samples: u32,
        sun_per_row: bool,
    ) -> Self {
        let ms = samples > 1;
        let (file, fs, pixels, shade, format) = if ms {
            (
                "grass_deferred_msaa.wgsl",
                "fs_vis_ms",
                "grass_pixels_ms",
                "shade_pixels_ms",
                VIS_MS_FORMAT,
            )
        } else {
            (
                "grass_deferred.wgsl",
                "fs_vis",
                "grass_pixels",
                "shade_pixels",
                VIS_FORMAT,
            )
        };
        let module = crate::shaders::module(device, file);
        // The deferred modules' own constant: where the shading takes the sun from.
        let mut own_constants = constants.to_vec();
        own_constants.push(("SUN_PER_PIXEL", if sun_per_row { 0.0 } else { 1.0 }));
        let options = || wgpu::PipelineCompilationOptions {
            constants: &own_constants,
            ..Default::default()
        };
        // The multisampled module's own constant: where its samples lie.
        let mut vis_constants = own_constants.clone();
        if ms {
            vis_constants.push(("MSAA_SAMPLES", f64::from(samples)));
        }
        let vis_options = || wgpu::PipelineCompilationOptions {
            constants: &vis_constants,
            ..Default::default()
        };
        let vis_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sward.deferred.vis.layout"),
            bind_group_layouts: &[Some(grass_layout)],
            immediate_size: 0,
        });
        let vis = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("sward.deferred.vis"),
            layout: Some(&vis_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_vis"),
                compilation_options: vis_options(),
                buffers: &[],
            },
            // Blades have no back: both sides are drawn.
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: super::draw::DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::LessEqual),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState {
                count: samples,
                ..Default::default()
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some(fs),
                compilation_options: vis_options(),
                // Multisampled, the colour too: its grass samples marked.
                targets: &[
                    Some(wgpu::ColorTargetState {
                        format,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    }),
                    ms.then_some(wgpu::ColorTargetState {
                        format: super::post::HDR_FORMAT,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    }),
                ][..1 + usize::from(ms)],
            }),
            multiview_mask: None,
            cache: None,
        });
        let light = super::light::layout(device);
        let own = layout(device, samples);
        let compute_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sward.deferred.compute.layout"),
            bind_group_layouts: &[Some(grass_layout), Some(&light), Some(&own)],
            immediate_size: 0,
        });
        let compute = |label: &str, entry: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(label),
                layout: Some(&compute_layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: options(),
                cache: None,
            })
        };
        Self {
            vis,
            pixels: compute("sward.deferred.pixels", pixels),
            shade: compute("sward.deferred.shade", shade),
            sky: (!ms).then(|| compute("sward.deferred.sky_lut", "sky_directions")),
            sun: sun_per_row.then(|| compute("sward.deferred.blade_sun", "blade_sun_points")),
        }
    }
}

/// The visibility buffer and the pixel list, sized to the 3D passes' target.
pub struct DeferredTargets {
    size: (u32, u32),
    samples: u32,
    vis_view: wgpu::TextureView,
    /// `PixelList`: the length, then one packed pixel per grass pixel at most (width x
    /// height entries).
    list: wgpu::Buffer,
    /// `ShadeArgs`: x (workgroups), y = z = 1.
    args: wgpu::Buffer,
    /// Bound in `args`'s place to the shading pass, which reads `args` as its indirect
    /// arguments.
    stand_in: wgpu::Buffer,
    /// The sky's table for the fog ([`SKY_LUT_SIDE`]²), and a 1 × 1 texture bound in its
    /// place where a pass must not see it (written and sampled by different passes).
    sky_lut: wgpu::TextureView,
    sky_stand_in: wgpu::TextureView,
    sky_sampler: wgpu::Sampler,
    layout: wgpu::BindGroupLayout,
}

impl DeferredTargets {
    /// Workgroups (8 x 8 invocations) of the pixel pass: one-sample, each invocation lists
    /// a run of [`LIST_RUN`] pixels along a row; multisampled, one pixel.
    fn list_groups(&self) -> (u32, u32) {
        let run = if self.samples > 1 { 1 } else { LIST_RUN };
        (self.size.0.div_ceil(8 * run), self.size.1.div_ceil(8))
    }

    /// Whether the adapter can hold the path's buffers for a target of `size` (the list
    /// is one storage binding of width x height words) and dispatch its shading (a
    /// workgroup per [`SHADE_GROUP`] pixels along x, when every pixel is grass).
    /// Multisampled (`samples` > 1), the sides are at most [`MS_MAX_SIDE`] and the device
    /// must multisample [`VIS_MS_FORMAT`] with that count.
    pub fn fits(gpu: &Gpu, size: (u32, u32), samples: u32) -> bool {
        if samples > 1
            && (size.0 > MS_MAX_SIDE
                || size.1 > MS_MAX_SIDE
                || !super::msaa::format_supports(gpu, VIS_MS_FORMAT, samples))
        {
            return false;
        }
        let limits = gpu.device.limits();
        let bytes = list_bytes(size);
        let pixels = u64::from(size.0) * u64::from(size.1);
        bytes <= limits.max_storage_buffer_binding_size
            && bytes <= limits.max_buffer_size
            && size.0 <= 1 << 16
            && size.1 <= 1 << 16
            && limits.max_compute_invocations_per_workgroup >= SHADE_GROUP
            && limits.max_compute_workgroup_size_x >= SHADE_GROUP
            && pixels.div_ceil(u64::from(SHADE_GROUP))
                <= u64::from(limits.max_compute_workgroups_per_dimension)
    }

    /// Buffers for a target of `size` drawn with `samples` samples per pixel; an error
    /// when the adapter cannot hold them.
    pub fn new(gpu: &Gpu, size: (u32, u32), samples: u32) -> Result<Self> {
        if samples > 1 && !Self::fits(gpu, size, samples) && Self::fits(gpu, size, 1) {
            return Err(Error::Limits(format!(
                "the multisampled deferred grass shading for {}x{} with {samples} samples: \
                 sides up to {MS_MAX_SIDE} and a {VIS_MS_FORMAT:?} visibility buffer the \
                 device multisamples {samples}x",
                size.0, size.1
            )));
        }
        if !Self::fits(gpu, size, samples) {
            return Err(Error::Limits(format!(
                "the deferred grass shading's pixel list for {}x{} ({} bytes) exceeds the \
                 adapter's storage binding limit",
                size.0,
                size.1,
                list_bytes(size)
            )));
        }
        let device = &gpu.device;
        let vis = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("sward.deferred.vis_buffer"),
            size: wgpu::Extent3d {
                width: size.0.max(1),
                height: size.1.max(1),
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: samples,
            dimension: wgpu::TextureDimension::D2,
            format: if samples > 1 {
                VIS_MS_FORMAT
            } else {
                VIS_FORMAT
            },
            // Copied out: the TAA twin's test reads it back (a multisampled texture cannot
            // be copied).
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | if samples > 1 {
                    wgpu::TextureUsages::empty()
                } else {
                    wgpu::TextureUsages::COPY_SRC
                },
            view_formats: &[],
        });
        let list = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.deferred.pixel_list"),
            size: list_bytes(size),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let args = wgpu::util::DeviceExt::create_buffer_init(
            device,
            &wgpu::util::BufferInitDescriptor {
                label: Some("sward.deferred.shade_args"),
                contents: bytemuck::cast_slice(&[0u32, 1, 1, 0]),
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::INDIRECT
                    | wgpu::BufferUsages::COPY_DST,
            },
        );
        let stand_in = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.deferred.args_stand_in"),
            size: ARGS_BYTES,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let sky_texture = |label, side: u32| {
            device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: wgpu::Extent3d {
                        width: side,
                        height: side,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format: SKY_LUT_FORMAT,
                    usage: wgpu::TextureUsages::STORAGE_BINDING
                        | wgpu::TextureUsages::TEXTURE_BINDING
                        | wgpu::TextureUsages::COPY_SRC,
                    view_formats: &[],
                })
                .create_view(&Default::default())
        };
        let sky_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("sward.deferred.sky_sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        Ok(Self {
            size,
            samples,
            vis_view: vis.create_view(&Default::default()),
            list,
            args,
            stand_in,
            sky_lut: sky_texture("sward.deferred.sky_lut", SKY_LUT_SIDE),
            sky_stand_in: sky_texture("sward.deferred.sky_stand_in", 1),
            sky_sampler,
            layout: layout(device, samples),
        })
    }

    /// The size the buffers were made for.
    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    /// The samples per pixel they were made for.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// The visibility buffer, the grass draws' colour attachment.
    pub fn vis_view(&self) -> &wgpu::TextureView {
        &self.vis_view
    }

    /// Bytes of GPU memory held: the visibility buffer, the list and the sky's table.
    pub fn gpu_bytes(&self) -> u64 {
        let pixels = u64::from(self.size.0) * u64::from(self.size.1);
        let texel = if self.samples > 1 { 8 } else { 16 };
        let sky = (u64::from(SKY_LUT_SIDE).pow(2) + 1) * 8;
        pixels * texel * u64::from(self.samples) + list_bytes(self.size) + 2 * ARGS_BYTES + sky
    }

    /// The sky's table of the last frame, row-major, read back (blocking; the twin's
    /// test): the radiance along [`sky_lut_direction`] of each texel.
    pub fn read_sky_lut(&self, gpu: &Gpu) -> Result<Vec<[f32; 3]>> {
        let texels = super::target::read_rgba16f(
            gpu,
            self.sky_lut.texture(),
            (SKY_LUT_SIDE, SKY_LUT_SIDE),
            "sward.deferred.read_sky_lut",
        )?;
        Ok(texels.iter().map(|t| [t[0], t[1], t[2]]).collect())
    }

    /// The bind groups of a frame's light passes (the pixel pass's, then the shading's):
    /// `depth` is, with one sample, the finished depth; multisampled, the multisampled
    /// colour. `scene`: the single-sample scene target the light writes (the size of these
    /// buffers). Made per frame, like the pyramid's: they bind the caller's views.
    pub(super) fn light_groups(
        &self,
        device: &wgpu::Device,
        depth: &wgpu::TextureView,
        scene: &wgpu::TextureView,
    ) -> [wgpu::BindGroup; 2] {
        let group = |args: &wgpu::Buffer, (written, sampled): (&wgpu::TextureView, &wgpu::TextureView)| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("sward.deferred.group"),
                layout: &self.layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::TextureView(&self.vis_view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(depth),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::TextureView(scene),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: self.list.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 4,
                        resource: args.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 5,
                        resource: wgpu::BindingResource::TextureView(written),
                    },
                    wgpu::BindGroupEntry {
                        binding: 6,
                        resource: wgpu::BindingResource::TextureView(sampled),
                    },
                    wgpu::BindGroupEntry {
                        binding: 7,
                        resource: wgpu::BindingResource::Sampler(&self.sky_sampler),
                    },
                ],
            })
        };
        // The pixel pass writes the sky's table, the shading samples it.
        [
            group(&self.args, (&self.sky_lut, &self.sky_stand_in)),
            group(&self.stand_in, (&self.sky_stand_in, &self.sky_lut)),
        ]
    }

    /// Records the two compute passes with `light` ([`DeferredTargets::light_groups`]):
    /// the grass pixels listed, then lit. `groups`: the grass draw's group 0 and the
    /// light's group 1.
    pub(super) fn encode_light(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipelines: &DeferredPipelines,
        groups: (&[wgpu::BindGroup], &wgpu::BindGroup),
        light: &[wgpu::BindGroup; 2],
        queries: (PassQueries, PassQueries),
    ) {
        // The workgroup count and the list's length start at 0; y and z stay 1.
        encoder.clear_buffer(&self.args, 0, Some(4));
        encoder.clear_buffer(&self.list, 0, Some(4));
        let (q_pixels, q_shade) = queries;
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("sward.deferred.pixels"),
                timestamp_writes: q_pixels.compute_writes_part(true, false),
            });
            q_pixels.begin(&mut pass);
            pass.set_bind_group(1, groups.1, &[]);
            pass.set_bind_group(2, &light[0], &[]);
            // The sun along the drawn blades: with one draw per level, each level's group
            // binds its own list.
            if let Some(sun) = &pipelines.sun {
                pass.set_pipeline(sun);
                for group in groups.0 {
                    pass.set_bind_group(0, group, &[]);
                    pass.dispatch_workgroups(SUN_INVOCATIONS / SUN_GROUP, 1, 1);
                }
            }
            pass.set_pipeline(&pipelines.pixels);
            pass.set_bind_group(0, &groups.0[0], &[]);
            if let Some(sky) = &pipelines.sky {
                pass.set_pipeline(sky);
                let groups = SKY_LUT_SIDE.div_ceil(8);
                pass.dispatch_workgroups(groups, groups, 1);
                pass.set_pipeline(&pipelines.pixels);
            }
            let (run_x, run_y) = self.list_groups();
            pass.dispatch_workgroups(run_x, run_y, 1);
            q_pixels.end(&mut pass);
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("sward.deferred.shade"),
            timestamp_writes: q_shade.compute_writes_part(false, true),
        });
        q_shade.begin(&mut pass);
        pass.set_pipeline(&pipelines.shade);
        pass.set_bind_group(0, &groups.0[0], &[]);
        pass.set_bind_group(1, groups.1, &[]);
        pass.set_bind_group(2, &light[1], &[]);
        pass.dispatch_workgroups_indirect(&self.args, 0);
        q_shade.end(&mut pass);
    }
}

/// Bytes of the pixel list for a target of `size`: its length, then a word per pixel.
fn list_bytes(size: (u32, u32)) -> u64 {
    4 + u64::from(size.0.max(1)) * u64::from(size.1.max(1)) * 4
}
