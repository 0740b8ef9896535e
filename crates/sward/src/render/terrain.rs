//! The terrain's GPU resources: the clipmap's index buffer ([`super::clipmap`]), the
//! height-function uniforms, the height grid of a `Png` terrain, the density map as a
//! texture for the far ground colour, the canopy seen from above
//! ([`super::far_canopy`]), and their bind group; plus [`probe_heights`], the
//! compute kernel that evaluates the WGSL height function at given points so that tests
//! can hold it against the CPU's [`HeightField`].

use std::cell::Cell;

use glam::{Vec2, Vec3};
use wgpu::util::DeviceExt;

use super::camera::CameraView;
use super::clipmap::{self, TerrainUniforms, MAX_LEVELS, VARIANTS};
use super::draw::read_storage;
use crate::error::Result;
use crate::field::{DensityMap, HeightField, Surface};
use crate::gpu::Gpu;
use crate::shaders;
use crate::sim::update::uniform_entry;

/// Buffers, texture and bind group of the terrain draw.
pub struct TerrainPass {
    /// The terrain's bind group layout: frame uniforms (0), terrain parameters (1), height
    /// grid (2), density texture (3) and its sampler (4), the far state (5), the trail map
    /// (6), the canopy seen from above (7) and its sampler (8).
    pub layout: wgpu::BindGroupLayout,
    params: wgpu::Buffer,
    grid: wgpu::Buffer,
    density: wgpu::Texture,
    canopy: wgpu::Texture,
    group: wgpu::BindGroup,
    /// The far state: the gusts' bend at the edge of the blades' reach (two words: the sum
    /// in 1/1024ths and the blades counted), for the far grass's shading waves, and the far
    /// levels' measured light gain (from word `far_gain::GAIN_WORD`).
    pub waves: wgpu::Buffer,
    indices: wgpu::Buffer,
    ranges: [(u32, u32); VARIANTS],
    /// The terrain without its grid heights: what the uniforms are computed from.
    shape: HeightField,
    has_density: bool,
    /// Blades grow past the terrain square too (a streamed field on an unbounded terrain):
    /// the ground there is shaded like the ground under the near blades.
    pub grass_everywhere: bool,
    /// The far ground's grass colour (`clipmap::far_albedo` of the field).
    pub grass_albedo: glam::Vec3,
    /// What `prepare` placed: the variant each level draws, and the level count.
    drawn: Cell<([u8; MAX_LEVELS], u32)>,
    /// [`TerrainPass::shadow_key`] of the last `prepare`.
    shadow_key: Cell<u64>,
    /// The ground's steepest slope, bounded (`HeightField::max_slope`).
    max_slope: f32,
    /// The field's tallest blade (m): how sharp the canopy's texels are shown.
    tallest: f32,
}

/// The height grid a `Png` terrain binds (a single 0 for analytic terrains).
fn grid_values(terrain: &HeightField) -> &[f32] {
    match terrain.surface {
        Surface::Grid if !terrain.heights.is_empty() => &terrain.heights,
        _ => &[0.0],
    }
}

pub(crate) fn grid_buffer(device: &wgpu::Device, terrain: &HeightField) -> wgpu::Buffer {
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("sward.terrain.grid"),
        contents: bytemuck::cast_slice(grid_values(terrain)),
        usage: wgpu::BufferUsages::STORAGE,
    })
}

pub(crate) fn params_buffer(device: &wgpu::Device, label: &str) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: std::mem::size_of::<TerrainUniforms>() as u64,
        usage: wgpu::BufferUsages::UNIFORM
            | wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// The density map as an R8 texture (every `step`-th texel where the map is larger than
/// the device allows), or one white texel.
pub(crate) fn density_texture(gpu: &Gpu, density: Option<&DensityMap>) -> wgpu::Texture {
    let max = gpu.device.limits().max_texture_dimension_2d.max(1);
    let (w, h, texels) = match density {
        Some(map) => {
            let (w, h, values) = map.texels();
            let step = w.max(h).div_ceil(max).max(1);
            let (tw, th) = (w.div_ceil(step), h.div_ceil(step));
            let mut texels = Vec::with_capacity((tw * th) as usize);
            for j in 0..th {
                for i in 0..tw {
                    let v = values[((j * step).min(h - 1) * w + (i * step).min(w - 1)) as usize];
                    texels.push((v.clamp(0.0, 1.0) * 255.0).round() as u8);
                }
            }
            (tw, th, texels)
        }
        None => (1, 1, vec![255]),
    };
    gpu.device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: Some("sward.terrain.density"),
            size: wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R8Unorm,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        &texels,
    )
}

impl TerrainPass {
    /// Uploads the terrain and renders the canopy of `field` seen from above; `frame` is the
    /// draw pass's frame-uniform buffer and `trails` the trail map (the far ground shows the
    /// trails pressed into it).
    pub fn new(
        gpu: &Gpu,
        (terrain, field): (&HeightField, &crate::scene::Field),
        density: Option<&DensityMap>,
        frame: &wgpu::Buffer,
        trails: &wgpu::Buffer,
    ) -> Self {
        let device = &gpu.device;
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.terrain.layout"),
            entries: &[
                uniform_entry(0, vf),
                read_storage(1, vf),
                read_storage(2, wgpu::ShaderStages::VERTEX),
                wgpu::BindGroupLayoutEntry {
                    binding: 3,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 4,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
                read_storage(5, vf),
                read_storage(6, wgpu::ShaderStages::FRAGMENT),
                wgpu::BindGroupLayoutEntry {
                    binding: 7,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 8,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        // The far state: the gusts' bend at the edge of the blades' reach, copied from the
        // cull's counters each frame (`CullCounters::wave_sum`, `wave_blades`: the far
        // grass's shading waves), in word 2 the far field's distance gain, from word 4
        // their light gains and from word 12 the sectors' multipliers the frame's
        // measurement writes (`far_gain`, `far_sectors`; zero: not measured yet).
        let waves = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.terrain.waves"),
            size: super::far_gain::STATE_BYTES,
            // Read back for the far gain's figure (`Renderer::far_gain`).
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let params = params_buffer(device, "sward.terrain.params");
        let grid = grid_buffer(device, terrain);
        let density_tex = density_texture(gpu, density);
        let view = density_tex.create_view(&wgpu::TextureViewDescriptor {
            label: Some("sward.terrain.density_view"),
            ..Default::default()
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("sward.terrain.density_sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let canopy = super::far_canopy::texture(gpu, field);
        let canopy_view = canopy.create_view(&wgpu::TextureViewDescriptor {
            label: Some("sward.terrain.canopy_view"),
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        // Each cell shows a whole layer, which wraps: repeat, so the filter wraps too.
        let canopy_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("sward.terrain.canopy_sampler"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sward.terrain.group"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: frame.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: params.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: grid.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(&view),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::Sampler(&sampler),
                },
                wgpu::BindGroupEntry {
                    binding: 5,
                    resource: waves.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 6,
                    resource: trails.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 7,
                    resource: wgpu::BindingResource::TextureView(&canopy_view),
                },
                wgpu::BindGroupEntry {
                    binding: 8,
                    resource: wgpu::BindingResource::Sampler(&canopy_sampler),
                },
            ],
        });
        let (indices, ranges) = clipmap::ring_indices();
        let indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("sward.terrain.indices"),
            contents: bytemuck::cast_slice(&indices),
            usage: wgpu::BufferUsages::INDEX,
        });
        let shape = HeightField {
            size: terrain.size,
            resolution: terrain.resolution,
            heights: Vec::new(),
            surface: terrain.surface.clone(),
            unbounded: terrain.unbounded,
        };
        Self {
            layout,
            params,
            grid,
            density: density_tex,
            canopy,
            group,
            waves,
            indices,
            ranges,
            shape,
            has_density: density.is_some(),
            grass_everywhere: false,
            grass_albedo: super::clipmap::far_grass_albedo(),
            drawn: Cell::new(([0; MAX_LEVELS], 0)),
            shadow_key: Cell::new(0),
            max_slope: terrain.max_slope(),
            tallest: super::light::blade_heights(field).1,
        }
    }

    /// What the ground's shadow depth depends on this frame: its clipmap (the uniforms
    /// but the camera's projection and the colours) and the eye, which the clipmap's
    /// vertices slide with (`light::ground_cache`).
    pub fn shadow_key(&self) -> u64 {
        self.shadow_key.get()
    }

    /// Whether the scene gave a density map (the lit terrain reads it only then).
    pub fn has_density_map(&self) -> bool {
        self.has_density
    }

    /// Whether the ground goes into the shadow maps under a sun whose direction has height
    /// `sun_y` (`HeightField::may_shadow`): flat ground and gentle hills under a high sun
    /// are left out, which filled the maps with depth for nothing (on llvmpipe the ground
    /// was half the shadow pass's fragments: a whole map per cascade).
    pub fn casts_shadow(&self, sun_y: f32) -> bool {
        crate::field::slope_may_shadow(self.max_slope, sun_y)
    }

    /// Bytes of the terrain's buffers and texture.
    pub fn gpu_bytes(&self) -> u64 {
        let s = self.density.size();
        self.params.size()
            + self.grid.size()
            + self.indices.size()
            + u64::from(s.width) * u64::from(s.height)
            + super::far_canopy::texture_bytes(self.canopy.size())
    }

    /// Places the levels around the camera projected with `aspect` and cropped by `crop`
    /// (`Renderer::view_proj`), with fog distance `fog`; the ground turns to grass over the
    /// blades' reach `reach` (`clipmap::grass_blend`), this frame's: the window's frame
    /// budget and its panel change it while the renderer lives (a blend kept from the
    /// start left the ground past a shortened reach half soil, and the near ring the far
    /// gain measures bare).
    pub fn prepare(
        &self,
        queue: &wgpu::Queue,
        camera: &CameraView,
        (aspect, crop): (f32, glam::Mat4),
        fog: f32,
        reach: f32,
    ) {
        let mut u = clipmap::terrain_uniforms(
            &self.shape,
            self.has_density,
            clipmap::grass_blend(reach),
            camera.eye,
            camera.far,
            fog,
        );
        u.view_proj_relative = (crop * camera.view_proj_relative(aspect)).to_cols_array_2d();
        u.grid[3] = u32::from(self.grass_everywhere);
        u.grass_albedo = self.grass_albedo.extend(self.tallest).into();
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&u));
        self.shadow_key.set(shadow_key(&u, camera.eye));
        let levels = u.info[3].min(MAX_LEVELS as u32);
        let mut variants = [0u8; MAX_LEVELS];
        for (k, v) in variants.iter_mut().enumerate().take(levels as usize) {
            *v = clipmap::variant(&u, k) as u8;
        }
        self.drawn.set((variants, levels));
    }

    /// The height-function uniforms and the height grid (the billboards place their cards
    /// on the same ground).
    pub fn height_buffers(&self) -> (&wgpu::Buffer, &wgpu::Buffer) {
        (&self.params, &self.grid)
    }

    /// Draws every level (the pipeline is set by the caller).
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_bind_group(0, &self.group, &[]);
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        let (variants, levels) = self.drawn.get();
        for k in 0..levels {
            let (first, count) = self.ranges[variants[k as usize] as usize];
            pass.draw_indexed(first..first + count, 0, k..k + 1);
        }
    }
}

/// The WGSL height function (`terrain_height`) at `points`: height, ∂h/∂x, ∂h/∂z each,
/// read back from the GPU. The twin of [`HeightField::height`] and [`HeightField::normal`].
pub fn probe_heights(gpu: &Gpu, terrain: &HeightField, points: &[Vec2]) -> Result<Vec<Vec3>> {
    let device = &gpu.device;
    let count = points.len().max(1);
    let c = wgpu::ShaderStages::COMPUTE;
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("sward.terrain_probe.layout"),
        entries: &[
            read_storage(1, c),
            read_storage(2, c),
            read_storage(3, c),
            crate::sim::update::compute_storage_entry(4, false),
        ],
    });
    let params = params_buffer(device, "sward.terrain_probe.params");
    let u = clipmap::terrain_uniforms(terrain, false, (0.0, 1.0), Vec3::ZERO, 1.0, 0.0);
    gpu.queue.write_buffer(&params, 0, bytemuck::bytes_of(&u));
    let grid = grid_buffer(device, terrain);
    let mut flat: Vec<[f32; 2]> = points.iter().map(|p| [p.x, p.y]).collect();
    flat.resize(count, [0.0; 2]);
    let input = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("sward.terrain_probe.points"),
        contents: bytemuck::cast_slice(&flat),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let out_size = (count * 16) as u64;
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("sward.terrain_probe.out"),
        size: out_size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("sward.terrain_probe.group"),
        layout: &layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 1,
                resource: params.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: grid.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: input.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 4,
                resource: output.as_entire_binding(),
            },
        ],
    });
    let module = shaders::module(device, "terrain_probe.wgsl");
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("sward.terrain_probe.pipeline_layout"),
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("sward.terrain_probe"),
        layout: Some(&pipeline_layout),
        module: &module,
        entry_point: Some("probe"),
        compilation_options: Default::default(),
        cache: None,
    });
    let bytes = crate::gpu::run_probe(
        gpu,
        "sward.terrain_probe",
        &pipeline,
        &[&group],
        count,
        (&output, out_size),
    )?;
    let values: &[[f32; 4]] = bytemuck::cast_slice(&bytes);
    Ok(values
        .iter()
        .take(points.len())
        .map(|v| Vec3::new(v[0], v[1], v[2]))
        .collect())
}

/// FNV-1a over the bytes the ground's shadow depth depends on: `u` without the camera's
/// projection, the soil-to-grass blend and the far albedo (the colour pass's alone), and
/// the eye's bits.
fn shadow_key(u: &clipmap::TerrainUniforms, eye: glam::Vec3) -> u64 {
    let mut shape = *u;
    shape.view_proj_relative = [[0.0; 4]; 4];
    shape.blend = [0.0; 4];
    shape.grass_albedo = [0.0; 4];
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    let eye = eye.to_array().map(f32::to_bits);
    for b in bytemuck::bytes_of(&shape)
        .iter()
        .chain(bytemuck::bytes_of(&eye))
    {
        h = (h ^ u64::from(*b)).wrapping_mul(0x0100_0000_01b3);
    }
    h
}
