//! Billboards in the middle distance (issue 12): past the blades, out to
//! `render.billboard_distance`, the grass is drawn as camera-facing cards showing tufts of
//! sward's own blades ([`atlas`]). Cards have no state: one per cell of a square grid of
//! cells centred on the camera's cell, placed by a hash of the cell (positions in integer
//! quanta of 1/1024 m, so the CPU twin [`place_card`] matches the GPU exactly), drawn in one
//! non-instanced draw (six vertices per cell; cells outside the ring or thinned by the
//! density map become degenerate triangles). The cost is the grid's vertices, bounded by
//! the billboard radius whatever the terrain's size.
//!
//! Cards fade in over the band where the blades thin out (from 0.6 of `culling.max_distance`
//! to it: Eq. 20's half of the cross-fade) and out over the last 15 % of the billboard
//! radius, where the ground's grass colour takes over; sway with the wind the blades read
//! and bend away from colliders and balls ([`top_offset`]).

pub mod atlas;
pub mod probe;

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec2, Vec3};

use super::draw::DEPTH_FORMAT;
use crate::field::tiles::QUANTA_PER_METRE;
use crate::field::{hash32, DensityMap, HeightField};
use crate::gpu::Gpu;
use crate::scene::types::{Culling, Field, Render};
use crate::shaders;
use crate::sim::layout::SimParams;
use crate::sim::reference::{wind_at, WindGrid};
use crate::sim::update::{compute_storage_entry, uniform_entry};

/// Cells across the billboard radius: the grid is about `2 · CELLS_PER_RADIUS + 1` cells
/// wide, so the vertex count is fixed whatever the radius.
pub const CELLS_PER_RADIUS: f32 = 100.0;
/// The smallest cell (m).
const MIN_CELL: f32 = 0.5;
/// Card width per cell side, and card height per tallest blade.
const CARD_WIDTH: f32 = 2.0;
const CARD_HEIGHT: f32 = 0.9;
/// Top offset per m/s² of wind, per metre of card height.
pub const SWAY_GAIN: f32 = 0.08;
/// How far past a sphere's radius a card's top is pushed away, in card heights.
pub const BEND_REACH: f32 = 0.5;

/// Uniforms of the billboard shaders; mirrors `BillboardParams` in
/// `shaders/billboard_place.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct BillboardParams {
    /// Camera cell x, z; cells per side; cell side in quanta.
    pub cells: [i32; 4],
    /// Fade-in start, end; fade-out start, end (m).
    pub fade: [f32; 4],
    /// Camera x, z; card width and height (m).
    pub eye_card: [f32; 4],
    /// Seed key, atlas variants, 1 = density map, sphere count.
    pub info: [u32; 4],
    /// Sway gain, bend reach, terrain size, unused.
    pub shape: [f32; 4],
}

const _: () = assert!(std::mem::size_of::<BillboardParams>() == 80);

/// The layout of the billboard grid for a scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BillboardLayout {
    pub radius: f32,
    pub cell_q: i32,
    pub cells: i32,
    pub card: (f32, f32),
    pub key: u32,
}

impl BillboardLayout {
    /// `None` when `render.billboard_distance` is 0 (no billboards).
    pub fn from_scene(render: &Render, field: &Field) -> Option<Self> {
        let radius = render.billboard_distance;
        if radius.is_nan() || radius <= 0.0 {
            return None;
        }
        let cell = (radius / CELLS_PER_RADIUS).max(MIN_CELL);
        let cell_q = (cell * QUANTA_PER_METRE as f32).round().max(1.0) as i32;
        let cell = cell_q as f32 / QUANTA_PER_METRE as f32;
        let half = (radius / cell).ceil() as i32;
        Some(Self {
            radius,
            cell_q,
            cells: 2 * half + 1,
            card: (cell * CARD_WIDTH, field.height.max * CARD_HEIGHT),
            key: hash32(field.seed as u32 ^ 0xB111_B0A2 ^ hash32((field.seed >> 32) as u32)),
        })
    }

    pub fn cell_size(&self) -> f32 {
        self.cell_q as f32 / QUANTA_PER_METRE as f32
    }

    /// Cards in the grid (drawn or not).
    pub fn card_count(&self) -> u32 {
        (self.cells * self.cells) as u32
    }

    /// The uniforms for a camera at `eye` with the blades' radius `max_distance`.
    pub fn params(
        &self,
        eye: Vec3,
        max_distance: f32,
        density: bool,
        spheres: u32,
        terrain_size: f32,
    ) -> BillboardParams {
        let cell = self.cell_size();
        let cx = (eye.x / cell).floor().clamp(-1e9, 1e9) as i32;
        let cz = (eye.z / cell).floor().clamp(-1e9, 1e9) as i32;
        let blades = if max_distance.is_finite() {
            max_distance.max(0.0)
        } else {
            0.0
        };
        let fade_in = (0.6 * blades, blades.max(1e-3));
        BillboardParams {
            cells: [cx, cz, self.cells, self.cell_q],
            fade: [fade_in.0, fade_in.1, 0.85 * self.radius, self.radius],
            eye_card: [eye.x, eye.z, self.card.0, self.card.1],
            info: [self.key, atlas::VARIANTS, u32::from(density), spheres],
            shape: [SWAY_GAIN, BEND_REACH, terrain_size, 0.0],
        }
    }
}

/// One card as the placement gives it (the twin of `card_at` in `billboard_place.wgsl`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Card {
    pub pos: Vec3,
    /// 0: outside the ring (not drawn); else the fade factor in (0, 1].
    pub fade: f32,
    pub variant: u32,
    pub scale: f32,
    pub mirror: f32,
    pub accept: f32,
}

fn rotl17(x: u32) -> u32 {
    x.rotate_left(17)
}

fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Card `i` of the grid.
pub fn place_card(p: &BillboardParams, terrain: &HeightField, i: u32) -> Card {
    let g = p.cells[2] as u32;
    let cx = p.cells[0]
        .wrapping_sub((g / 2) as i32)
        .wrapping_add((i % g) as i32);
    let cz = p.cells[1]
        .wrapping_sub((g / 2) as i32)
        .wrapping_add((i / g) as i32);
    let cell_q = p.cells[3];
    let h = hash32(p.info[0] ^ hash32((cx as u32) ^ rotl17(hash32((cz as u32) ^ 0x68e3_1da4))));
    let h1 = hash32(h.wrapping_add(0x9E37_79B9));
    let h2 = hash32(h.wrapping_add(0x3C6E_F372));
    let h3 = hash32(h.wrapping_add(0xDAA6_6D2B));
    let xq = cx
        .wrapping_mul(cell_q)
        .wrapping_add((h % cell_q as u32) as i32);
    let zq = cz
        .wrapping_mul(cell_q)
        .wrapping_add((h1 % cell_q as u32) as i32);
    let quantum = 1.0 / QUANTA_PER_METRE as f32;
    let (x, z) = (xq as f32 * quantum, zq as f32 * quantum);
    let unit = 1.0 / 16_777_216.0;
    let d = (Vec2::new(x, z) - Vec2::new(p.eye_card[0], p.eye_card[1])).length();
    let fade = if d >= p.fade[0] && d <= p.fade[3] {
        smoothstep(p.fade[0], p.fade[1], d) * (1.0 - smoothstep(p.fade[2], p.fade[3], d))
    } else {
        0.0
    };
    Card {
        pos: Vec3::new(x, terrain.height(x, z), z),
        fade,
        variant: h2 % p.info[1].max(1),
        scale: 0.8 + 0.4 * (h3 >> 8) as f32 * unit,
        mirror: if h2 & 0x100 != 0 { 1.0 } else { -1.0 },
        accept: (hash32(h3) >> 8) as f32 * unit,
    }
}

/// How far the top of a card of height `h` rooted at `root` moves (the twin of
/// `top_offset` in `billboard_sway.wgsl`): the wind the blades feel times the sway gain,
/// then away from and down under each sphere near it; at most 0.9 h.
pub fn top_offset(
    p: &BillboardParams,
    sim: &SimParams,
    grid: &WindGrid,
    spheres: &[[f32; 4]],
    root: Vec3,
    h: f32,
) -> Vec3 {
    let top = root + Vec3::Y * h;
    let w = wind_at(top, sim, grid);
    let mut off = Vec3::new(w.x, 0.0, w.z) * p.shape[0] * h;
    for s in spheres.iter().take(p.info[3] as usize) {
        let reach = s[3] + h * p.shape[1];
        let d = Vec2::new(top.x - s[0], top.z - s[2]);
        let dist = d.length();
        if dist < reach && (top.y - s[1]).abs() < s[3] + h {
            let away = if dist > 1e-4 {
                d / dist.max(1e-4)
            } else {
                Vec2::X
            };
            let push = reach - dist;
            off += Vec3::new(away.x * push, -0.5 * push, away.y * push);
        }
    }
    let len = off.length();
    if len > 0.9 * h {
        off *= 0.9 * h / len;
    }
    off
}

/// Cards the draw shows for `view_proj`: in the ring, kept by the density map, their
/// centre in the view (with a card's margin).
pub fn count_drawn(
    p: &BillboardParams,
    terrain: &HeightField,
    density: Option<&DensityMap>,
    view_proj: Mat4,
) -> u32 {
    let g = p.cells[2] as u32;
    let mut n = 0;
    for i in 0..g * g {
        let c = place_card(p, terrain, i);
        if c.fade <= 0.0 || density.is_some_and(|m| c.accept >= m.sample(c.pos.x, c.pos.z)) {
            continue;
        }
        let centre = c.pos + Vec3::Y * (0.5 * p.eye_card[3] * c.scale);
        let clip = view_proj * centre.extend(1.0);
        let margin = 1.0 + p.eye_card[2] / clip.w.max(1e-3);
        if clip.w > 0.0
            && clip.x.abs() <= clip.w * margin
            && clip.y.abs() <= clip.w * margin
            && clip.z <= clip.w
        {
            n += 1;
        }
    }
    n
}

fn buf(binding: u32, b: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: b.as_entire_binding(),
    }
}

/// The billboard draw: the atlas, the uniforms and the pipeline for one sample count.
pub struct BillboardPass {
    pub layout: BillboardLayout,
    params: wgpu::Buffer,
    bind_layout: wgpu::BindGroupLayout,
    group: wgpu::BindGroup,
    pipeline: wgpu::RenderPipeline,
    format: wgpu::TextureFormat,
    samples: u32,
    atlas: wgpu::Texture,
    sampler: wgpu::Sampler,
    density: wgpu::Texture,
    has_density: bool,
    /// The coverage-weighted mean albedo of the atlas.
    pub mean_albedo: [f32; 3],
}

/// The buffers the billboards read from the rest of the frame.
pub struct Inputs<'a> {
    pub frame: &'a wgpu::Buffer,
    pub terrain_params: &'a wgpu::Buffer,
    pub terrain_grid: &'a wgpu::Buffer,
    pub spheres: &'a wgpu::Buffer,
    pub sim_params: &'a wgpu::Buffer,
    pub wind_grid: &'a wgpu::Buffer,
}

impl BillboardPass {
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
            .map(|v| atlas::render_layer(field, v))
            .collect();
        // The cards average to the far ground's grass colour, so that the middle and the
        // far level read as one field (the tufts keep their variation around it).
        atlas::match_mean(&mut layers, super::clipmap::far_grass_albedo().into());
        let mean_albedo = atlas::mean_color(&layers);
        let chains: Vec<Vec<Vec<[f32; 4]>>> = layers.iter().map(atlas::mip_chain).collect();
        let mips = chains[0].len() as u32;
        let atlas_tex = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("sward.billboard.atlas"),
            size: wgpu::Extent3d {
                width: atlas::WIDTH,
                height: atlas::HEIGHT,
                depth_or_array_layers: atlas::VARIANTS,
            },
            mip_level_count: mips,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8UnormSrgb,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        for (layer, chain) in chains.iter().enumerate() {
            for (level, texels) in chain.iter().enumerate() {
                let w = (atlas::WIDTH >> level).max(1);
                let h = (atlas::HEIGHT >> level).max(1);
                gpu.queue.write_texture(
                    wgpu::TexelCopyTextureInfo {
                        texture: &atlas_tex,
                        mip_level: level as u32,
                        origin: wgpu::Origin3d {
                            x: 0,
                            y: 0,
                            z: layer as u32,
                        },
                        aspect: wgpu::TextureAspect::All,
                    },
                    &atlas::encode(texels),
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
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("sward.billboard.sampler"),
            address_mode_u: wgpu::AddressMode::ClampToEdge,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        let density_tex = super::terrain::density_texture(gpu, density);
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.billboard.params"),
            size: std::mem::size_of::<BillboardParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let v = wgpu::ShaderStages::VERTEX;
        let read = |binding| {
            let mut e = compute_storage_entry(binding, true);
            e.visibility = v;
            e
        };
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
        let bind_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.billboard.layout"),
            entries: &[
                uniform_entry(0, vf),
                uniform_entry(1, v),
                read(2),
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
                read(6),
                uniform_entry(7, v),
                read(8),
                texture(9, wgpu::TextureViewDimension::D2, v),
            ],
        });
        let group = Self::bind(
            device,
            &bind_layout,
            &params,
            &atlas_tex,
            &sampler,
            &density_tex,
            inputs,
        );
        let pipeline = Self::pipeline(device, &bind_layout, format, samples);
        Self {
            layout,
            params,
            bind_layout,
            group,
            pipeline,
            format,
            samples,
            atlas: atlas_tex,
            sampler,
            density: density_tex,
            has_density: density.is_some(),
            mean_albedo,
        }
    }

    fn bind(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        params: &wgpu::Buffer,
        atlas_tex: &wgpu::Texture,
        sampler: &wgpu::Sampler,
        density: &wgpu::Texture,
        inputs: &Inputs,
    ) -> wgpu::BindGroup {
        let atlas_view = atlas_tex.create_view(&wgpu::TextureViewDescriptor {
            label: Some("sward.billboard.atlas_view"),
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let density_view = density.create_view(&Default::default());
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sward.billboard.group"),
            layout,
            entries: &[
                buf(0, inputs.frame),
                buf(1, inputs.terrain_params),
                buf(2, inputs.terrain_grid),
                buf(3, params),
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::TextureView(&atlas_view),
                },
                wgpu::BindGroupEntry {
                    binding: 5,
                    resource: wgpu::BindingResource::Sampler(sampler),
                },
                buf(6, inputs.spheres),
                buf(7, inputs.sim_params),
                buf(8, inputs.wind_grid),
                wgpu::BindGroupEntry {
                    binding: 9,
                    resource: wgpu::BindingResource::TextureView(&density_view),
                },
            ],
        })
    }

    /// Rebinds the frame's buffers (after the wind solver or the update was rebuilt).
    pub fn rebind(&mut self, device: &wgpu::Device, inputs: &Inputs) {
        self.group = Self::bind(
            device,
            &self.bind_layout,
            &self.params,
            &self.atlas,
            &self.sampler,
            &self.density,
            inputs,
        );
    }

    fn pipeline(
        device: &wgpu::Device,
        bind_layout: &wgpu::BindGroupLayout,
        format: wgpu::TextureFormat,
        samples: u32,
    ) -> wgpu::RenderPipeline {
        let module = shaders::module(device, "billboard.wgsl");
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sward.billboard.pipeline_layout"),
            bind_group_layouts: &[Some(bind_layout)],
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
                format: DEPTH_FORMAT,
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

    /// Rebuilds the pipeline for another sample count.
    pub fn set_samples(&mut self, device: &wgpu::Device, samples: u32) {
        if samples != self.samples {
            self.samples = samples;
            self.pipeline = Self::pipeline(device, &self.bind_layout, self.format, samples);
        }
    }

    /// Writes this frame's uniforms for the share `share` of the billboard radius; returns
    /// them (the stats count the cards with them).
    pub fn prepare(
        &self,
        queue: &wgpu::Queue,
        eye: Vec3,
        culling: &Culling,
        spheres: u32,
        terrain_size: f32,
        share: f32,
    ) -> BillboardParams {
        let mut p = self.layout.params(
            eye,
            culling.max_distance,
            self.has_density,
            spheres,
            terrain_size,
        );
        // The frame budget may draw only the nearer part of the ring (the grid stays).
        let radius = self.layout.radius * share.clamp(0.0, 1.0);
        let radius = radius.max(p.fade[1]);
        p.fade[2] = 0.85 * radius;
        p.fade[3] = radius;
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&p));
        p
    }

    /// Draws every cell's card (in the caller's colour pass).
    pub fn draw<'a>(&'a self, pass: &mut wgpu::RenderPass<'a>) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.group, &[]);
        pass.draw(0..self.layout.card_count() * 6, 0..1);
    }

    /// GPU bytes held: the atlas with its mips and the uniforms.
    pub fn gpu_bytes(&self) -> u64 {
        (atlas::WIDTH * atlas::HEIGHT * 4 * atlas::VARIANTS) as u64 * 4 / 3
            + std::mem::size_of::<BillboardParams>() as u64
    }
}
