//! Light (issue 16): the sun placed by the time of day ([`sun`]), Preetham's sky
//! ([`sky`]), exposure and tone mapping ([`tone`]), and the sun's cascaded shadow maps
//! ([`cascades`]): their uniforms, the depth map array, and the passes that draw the
//! casters (terrain, objects, balls and colliders, and the grass at its coarsest level
//! within a radius) into it before the colour passes read it.
//!
//! The casters are drawn by the colour passes' own vertex shaders: for each cascade the
//! frame uniform buffer is overwritten (a buffer copy in the command stream) with a frame
//! whose view-projection is the cascade's, and restored to the camera's before the colour
//! passes. So no caster needs a second set of bind groups.

pub mod canopy;
pub mod cascades;
mod caster_levels;
pub mod ground_cache;
pub mod receiver;
pub mod schedule;
pub mod sky;
pub mod sun;
pub mod tone;

use crate::gpu::queries::PassQueries;
use glam::Vec3;

use crate::error::Result;
use crate::gpu::Gpu;
use crate::render::camera::CameraView;
use crate::scene::{Scene, SkyModel};
use crate::sim::layout::{DrawIndexedIndirect, FrameUniforms, LightUniforms, LOD_LEVELS};

use super::draw::DEPTH_FORMAT;
use ground_cache::GroundStep;

/// The sun and sky of the `Gradient` sky (sward's look before issue 16).
const GRADIENT_SUN: Vec3 = Vec3::new(1.0, 0.93, 0.80);
const GRADIENT_AMBIENT: Vec3 = Vec3::new(0.36, 0.44, 0.55);
/// Where the shadows start to fade out, as a share of their distance.
const FADE_START: f32 = 0.85;

/// The light's bind group layout (group 1 of every lit pass and of the deferred grass
/// shading's compute passes): the uniforms, the shadow map array and its comparison
/// sampler. wgpu deduplicates equal layouts, so each pipeline may build its own.
pub fn layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let stages = wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE;
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("sward.light.layout"),
        entries: &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: stages,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: stages,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Depth,
                    view_dimension: wgpu::TextureViewDimension::D2Array,
                    multisampled: false,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 2,
                visibility: stages,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
                count: None,
            },
        ],
    })
}

/// The shadow map: one depth layer per cascade.
struct ShadowMap {
    texture: wgpu::Texture,
    resolution: u32,
    layers: u32,
    array: wgpu::TextureView,
    layer_views: Vec<wgpu::TextureView>,
}

/// A depth texture of `layers` square layers of `resolution` texels: the shadow map's
/// shape, which the ground's cache shares.
fn depth_layers(
    device: &wgpu::Device,
    label: &str,
    (resolution, layers): (u32, u32),
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: resolution,
            height: resolution,
            depth_or_array_layers: layers,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: DEPTH_FORMAT,
        usage,
        view_formats: &[],
    })
}

impl ShadowMap {
    fn new(device: &wgpu::Device, resolution: u32, layers: u32) -> Self {
        let texture = depth_layers(
            device,
            "sward.light.shadow_map",
            (resolution, layers),
            wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC
                // The ground's cached depth is copied back in (`ground_cache`).
                | wgpu::TextureUsages::COPY_DST,
        );
        let array = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some("sward.light.shadow_map.array"),
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let layer_views = (0..layers)
            .map(|k| {
                texture.create_view(&wgpu::TextureViewDescriptor {
                    label: Some("sward.light.shadow_map.layer"),
                    dimension: Some(wgpu::TextureViewDimension::D2),
                    base_array_layer: k,
                    array_layer_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        Self {
            texture,
            resolution,
            layers,
            array,
            layer_views,
        }
    }
}

/// The light's uniforms, shadow map and cascade frames.
pub struct LightPass {
    layout: wgpu::BindGroupLayout,
    uniform: wgpu::Buffer,
    sampler: wgpu::Sampler,
    map: ShadowMap,
    group: wgpu::BindGroup,
    /// The camera's frame, then one frame per cascade: copied over the frame uniform
    /// buffer around the shadow passes.
    frames: wgpu::Buffer,
    /// The grass's shadow draws: the cull's instance counts with the coarsest level's mesh.
    grass_args: wgpu::Buffer,
    /// What the last `prepare` computed.
    last: LightUniforms,
    cascades: u32,
    grass_radius: f32,
    /// When each cascade is drawn again, and which are drawn this frame and take the
    /// grass's shadows (those that begin within `grass_radius`).
    schedule: schedule::Schedule,
    drawn: [bool; 4],
    grass_in: [bool; 4],
    grass_levels: [[bool; LOD_LEVELS]; 4],
    /// The ground's depth in each cascade, kept while it would be drawn the same, and how
    /// each cascade drawn this frame gets it ([`LightPass::plan_ground`]).
    ground: ground_cache::GroundCache,
    ground_steps: [GroundStep; 4],
    /// The far light's canopy table, summed when the field's outlines change.
    canopy: canopy::CanopyCache,
}

/// Which of the casters a shadow pass draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Casters {
    /// Every caster.
    All,
    /// The ground alone (to be kept in [`ground_cache`]).
    Ground,
    /// Everything but the ground (over a ground copied in or drawn before).
    Moving,
}

const FRAME_BYTES: u64 = std::mem::size_of::<FrameUniforms>() as u64;
/// How the blades cast shadows this frame.
#[derive(Clone, Copy, Debug)]
pub struct GrassCasters {
    /// The coarsest level's mesh they cast with: its index count and first index.
    pub mesh: (u32, u32),
    /// The cull's level-of-detail parameters (`CullParams::lod`), for the levels each
    /// cascade draws (`caster_levels`).
    pub lod: [f32; 4],
}

/// Cascades a scene may ask for (`light.shadows.cascades`).
const MAX_CASCADES: usize = 4;
const ARGS_BYTES: u64 = std::mem::size_of::<DrawIndexedIndirect>() as u64;

/// Checks that the adapter holds the scene's shadow map before it is allocated.
pub fn check_shadow_map(gpu: &Gpu, scene: &Scene) -> Result<()> {
    let s = &scene.light.shadows;
    if s.enabled {
        gpu.check_texture(
            "a shadow map (light.shadows.resolution)",
            s.resolution,
            s.resolution,
        )?;
    }
    Ok(())
}

impl LightPass {
    /// Allocates the light uniform, the shadow map and the cascades' frames for `scene`'s
    /// light; fails when the adapter cannot hold the shadow map it asks for.
    pub fn new(gpu: &Gpu, scene: &Scene) -> Result<Self> {
        check_shadow_map(gpu, scene)?;
        let device = &gpu.device;
        let layout = layout(device);
        let uniform = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.light.uniforms"),
            size: std::mem::size_of::<LightUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("sward.light.shadow_sampler"),
            address_mode_u: wgpu::AddressMode::ClampToEdge,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        });
        let frames = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.light.cascade_frames"),
            size: FRAME_BYTES * 5,
            usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let grass_args = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.light.grass_args"),
            size: ARGS_BYTES * (LOD_LEVELS * MAX_CASCADES) as u64,
            usage: wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let map = ShadowMap::new(device, 1, 1);
        let group = Self::make_group(device, &layout, &uniform, &map, &sampler);
        let mut pass = Self {
            layout,
            uniform,
            sampler,
            map,
            group,
            frames,
            grass_args,
            last: LightUniforms::default(),
            cascades: 0,
            grass_radius: 0.0,
            schedule: schedule::Schedule::default(),
            drawn: [false; 4],
            grass_in: [false; 4],
            grass_levels: [[true; LOD_LEVELS]; 4],
            ground: ground_cache::GroundCache::new(),
            ground_steps: [GroundStep::None; 4],
            canopy: canopy::CanopyCache::default(),
        };
        pass.sync_map(device, scene);
        Ok(pass)
    }

    fn make_group(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        uniform: &wgpu::Buffer,
        map: &ShadowMap,
        sampler: &wgpu::Sampler,
    ) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sward.light.group"),
            layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: uniform.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&map.array),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::Sampler(sampler),
                },
            ],
        })
    }

    /// Reallocates the map when the scene's shadows changed size or cascade count (the
    /// panel); off, a 1-texel map keeps the group valid.
    fn sync_map(&mut self, device: &wgpu::Device, scene: &Scene) {
        let s = &scene.light.shadows;
        let (res, layers) = if s.enabled {
            let max = device.limits().max_texture_dimension_2d;
            (s.resolution.min(max), s.cascades.clamp(1, 4))
        } else {
            (1, 1)
        };
        if (self.map.resolution, self.map.layers) != (res, layers) {
            self.schedule.reset();
            self.ground.clear();
            self.map = ShadowMap::new(device, res, layers);
            self.group = Self::make_group(
                device,
                &self.layout,
                &self.uniform,
                &self.map,
                &self.sampler,
            );
        }
    }

    /// The group every lit pass binds at 1.
    pub fn group(&self) -> &wgpu::BindGroup {
        &self.group
    }

    /// The uniforms of the last frame.
    pub fn uniforms(&self) -> &LightUniforms {
        &self.last
    }

    /// Cascade `k`'s depth map (row-major, `resolution`² values), read back (blocking).
    pub fn read_cascade(&self, gpu: &Gpu, k: u32) -> Result<(u32, Vec<f32>)> {
        let r = self.map.resolution;
        let k = k.min(self.map.layers - 1);
        let bytes = super::target::read_texels(
            gpu,
            wgpu::TexelCopyTextureInfo {
                texture: &self.map.texture,
                mip_level: 0,
                origin: wgpu::Origin3d { x: 0, y: 0, z: k },
                aspect: wgpu::TextureAspect::DepthOnly,
            },
            (r, r),
            "sward.light.shadow_readback",
        )?;
        let depths = bytes
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        Ok((r, depths))
    }

    /// Bytes of the shadow map and of the ground's cached depth.
    pub fn gpu_bytes(&self) -> u64 {
        let r = self.map.resolution as u64;
        r * r * 4 * self.map.layers as u64 + self.ground.gpu_bytes()
    }

    /// Computes the frame's light and writes its uniforms, the cascades' frames (from the
    /// camera's `frame`) and the grass's shadow draw arguments. `grass`: how the blades
    /// cast, or `None` to keep them out of the maps whatever the scene's radius (the
    /// window's frame budget). Returns the number of cascades to draw.
    pub fn prepare(
        &mut self,
        gpu: &Gpu,
        scene: &Scene,
        camera: &CameraView,
        aspect: f32,
        frame: &FrameUniforms,
        grass: Option<GrassCasters>,
    ) -> u32 {
        let grass_lod = grass.map(|g| g.mesh);
        let cull_lod = grass.map_or([0.0; 4], |g| g.lod);
        self.sync_map(&gpu.device, scene);
        let grass_radius = grass_lod.map_or(0.0, |_| scene.light.shadows.grass_radius);
        let lod = grass_lod.unwrap_or((0, 0));
        let sun = Vec3::from_slice(&frame.sun_dir[..3]);
        let l = &scene.light;
        let mut u = uniforms_with(scene, sun, &mut self.canopy);
        let s = &l.shadows;
        self.cascades = 0;
        // No shadows with the sun below the horizon: nothing is lit to be shadowed.
        if s.enabled && sun.y > 0.0 {
            let cs = cascades::cascades(
                camera,
                aspect,
                sun,
                self.map.resolution,
                s.distance,
                self.map.layers,
            );
            let mut frames = vec![*frame];
            let plan = self.schedule.plan(&cs, sun);
            for (k, (c, (drawn, view))) in cs.iter().zip(&plan).enumerate() {
                // A cascade kept from an earlier frame is looked up with its own view.
                u.cascades[k] = view.view_proj.to_cols_array_2d();
                u.splits[k] = c.far;
                u.texel_world[k] = view.texel;
                self.drawn[k] = *drawn;
                // The blades cast into the cascades whose slice begins within their radius,
                // each with the levels of detail its blades can have.
                let begins = if k == 0 { 0.0 } else { cs[k - 1].far };
                self.grass_in[k] = begins < grass_radius;
                self.grass_levels[k] = caster_levels::levels(
                    (begins, c.far.min(grass_radius)),
                    blade_heights(&scene.field),
                    sun,
                    cull_lod,
                );
                let mut f = *frame;
                f.view_proj = view.view_proj.to_cols_array_2d();
                f.inv_view_proj = view.view_proj.inverse().to_cols_array_2d();
                // No width correction in the sun's view, and the grass's shadow radius.
                f.width_correction[1] = 0.0;
                // Nor the 3D displacement (Eq. 23): a caster's "v" cross-section changes
                // its shadow by a fraction of a blade's width, below a shadow texel, but its
                // folded triangles cost a third more shadow-pass time on llvmpipe.
                f.shape[3] = 0.0;
                f.debug[2] = grass_radius.max(1e-3);
                frames.push(f);
            }
            let last = cs.last().map_or(s.distance, |c| c.far);
            u.shadow = [1.0, cs.len() as f32, s.softness, s.bias];
            u.shadow_map = [
                1.0 / self.map.resolution as f32,
                self.map.resolution as f32,
                last * FADE_START,
                0.0,
            ];
            gpu.queue
                .write_buffer(&self.frames, 0, bytemuck::cast_slice(&frames));
            self.cascades = cs.len() as u32;
            self.grass_radius = grass_radius;
            let args: Vec<DrawIndexedIndirect> = (0..LOD_LEVELS * MAX_CASCADES)
                .map(|_| DrawIndexedIndirect {
                    index_count: lod.0,
                    instance_count: 0,
                    first_index: lod.1,
                    base_vertex: 0,
                    first_instance: 0,
                })
                .collect();
            gpu.queue
                .write_buffer(&self.grass_args, 0, bytemuck::cast_slice(&args));
        }
        if self.cascades == 0 {
            self.schedule.reset();
            self.ground.clear();
        }
        gpu.queue
            .write_buffer(&self.uniform, 0, bytemuck::bytes_of(&u));
        self.last = u;
        self.cascades
    }

    /// Whether cascade `k` is drawn this frame (else its map is kept from an earlier one).
    pub fn cascade_drawn(&self, k: usize) -> bool {
        k < self.cascades as usize && self.drawn[k]
    }

    /// The cascades drawn this frame (0: no shadows).
    pub fn cascades(&self) -> u32 {
        self.cascades
    }

    /// Whether the grass casts shadows this frame.
    pub fn grass_casts(&self) -> bool {
        self.cascades > 0 && self.grass_radius > 0.0
    }

    /// The grass's shadow draw arguments (cascade by cascade: see
    /// [`LightPass::grass_args_offset`]).
    pub fn grass_args(&self) -> &wgpu::Buffer {
        &self.grass_args
    }

    /// Where cascade `k`'s grass draw arguments start in [`LightPass::grass_args`].
    pub fn grass_args_offset(&self, k: usize) -> u64 {
        (k * LOD_LEVELS) as u64 * ARGS_BYTES
    }

    /// Decides, after [`LightPass::prepare`], how the ground gets into each cascade drawn
    /// this frame: `ground` is the clipmap's key (`TerrainPass::shadow_key`) when the
    /// ground casts, `None` when it does not (or is not to be kept). A cascade whose view
    /// and clipmap are those its ground was last drawn with has it copied back from
    /// [`ground_cache`]; any other draws it and keeps it.
    pub fn plan_ground(&mut self, device: &wgpu::Device, ground: Option<u64>) {
        let shape = (self.map.resolution, self.map.layers);
        for k in 0..self.cascades as usize {
            self.ground_steps[k] = if self.drawn[k] {
                let key = ground.map(|g| {
                    let view = glam::Mat4::from_cols_array_2d(&self.last.cascades[k]);
                    ground_cache::GroundKey::new(view, g)
                });
                self.ground.plan(device, shape, k, key)
            } else {
                GroundStep::None
            };
        }
    }

    /// Records the shadow passes: for each cascade drawn this frame, its frame over
    /// `frame_buffer`, then `draw` records the casters into the cascade's layer (with the
    /// grass or not: the second argument; which casters: the third); at the end the
    /// camera's frame is put back. `cull_args` are the cull's draw arguments, whose
    /// instance counts the grass's shadow draws take. The ground is drawn, or copied back
    /// from [`ground_cache`], as [`LightPass::plan_ground`] decided (the copy lies between
    /// the timed passes: the wall clock sees it, the pass timestamps do not).
    pub fn encode<F>(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame_buffer: &wgpu::Buffer,
        cull_args: &wgpu::Buffer,
        q: PassQueries,
        mut draw: F,
    ) where
        F: FnMut(&mut wgpu::RenderPass<'_>, Option<u64>, Casters),
    {
        if self.cascades == 0 {
            return;
        }
        if self.grass_casts() {
            // Each cascade's draws take the cull's instances of the levels its blades can
            // have; the others stay at 0 instances.
            for c in 0..self.cascades as usize {
                if !(self.drawn[c] && self.grass_in[c]) {
                    continue;
                }
                for level in 0..LOD_LEVELS {
                    if !self.grass_levels[c][level] {
                        continue;
                    }
                    for field in [4u64, 16] {
                        let from = level as u64 * ARGS_BYTES + field;
                        let to = self.grass_args_offset(c) + from;
                        encoder.copy_buffer_to_buffer(cull_args, from, &self.grass_args, to, 4);
                    }
                }
            }
        }
        let drawn: Vec<usize> = (0..self.cascades as usize)
            .filter(|&k| self.drawn[k])
            .collect();
        let (Some(&first), Some(&last)) = (drawn.first(), drawn.last()) else {
            return;
        };
        for k in drawn {
            let step = self.ground_steps[k];
            let from = FRAME_BYTES * (k as u64 + 1);
            encoder.copy_buffer_to_buffer(&self.frames, from, frame_buffer, 0, FRAME_BYTES);
            let grass = (self.grass_in[k] && self.grass_casts()).then(|| self.grass_args_offset(k));
            // The passes of this cascade: (which casters, whether the layer is cleared).
            let passes: &[(Casters, bool)] = match step {
                GroundStep::None => &[(Casters::All, true)],
                GroundStep::Draw => &[(Casters::Ground, true), (Casters::Moving, false)],
                GroundStep::Copy => &[(Casters::Moving, false)],
            };
            if step == GroundStep::Copy {
                self.ground
                    .encode_copy(encoder, &self.map.texture, k as u32, step);
            }
            for (i, &(casters, clear)) in passes.iter().enumerate() {
                // One timer scope over the cascades drawn: it starts with the first pass
                // and ends with the last.
                let writes = q.render_writes_part(
                    k == first && i == 0,
                    k == last && i + 1 == passes.len(),
                );
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("sward.light.shadow_pass"),
                    color_attachments: &[],
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: &self.map.layer_views[k],
                        depth_ops: Some(wgpu::Operations {
                            load: if clear {
                                wgpu::LoadOp::Clear(1.0)
                            } else {
                                wgpu::LoadOp::Load
                            },
                            store: wgpu::StoreOp::Store,
                        }),
                        stencil_ops: None,
                    }),
                    timestamp_writes: writes,
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                q.begin(&mut pass);
                draw(&mut pass, grass, casters);
                q.end(&mut pass);
                drop(pass);
                if casters == Casters::Ground {
                    self.ground
                        .encode_copy(encoder, &self.map.texture, k as u32, step);
                }
            }
        }
        encoder.copy_buffer_to_buffer(&self.frames, 0, frame_buffer, 0, FRAME_BYTES);
    }
}

impl LightPass {
    /// How many times the far light's canopy table was summed since the pass was made:
    /// once per change of the field's outlines, not once per frame.
    pub fn canopy_sums(&self) -> u64 {
        self.canopy.sums()
    }

    /// The cascades the last `prepare` drew this frame, each with the sun's view-projection
    /// it was drawn with and its layer of the shadow map: where a program embedding sward
    /// draws its own shadow casters (after the frame's shadow passes, loading the depth).
    /// The cascades not listed keep what was drawn into them before.
    pub fn caster_targets(&self) -> Vec<(glam::Mat4, &wgpu::TextureView)> {
        (0..self.cascades as usize)
            .filter(|&k| self.drawn[k])
            .map(|k| {
                (
                    glam::Mat4::from_cols_array_2d(&self.last.cascades[k]),
                    &self.map.layer_views[k],
                )
            })
            .collect()
    }
}

/// The shortest and tallest blade the field can grow (its own heights, its species' and its
/// flowers' stems), for which levels of detail a cascade's casters can have.
pub(crate) fn blade_heights(field: &crate::scene::Field) -> (f32, f32) {
    let ranges = std::iter::once(field.height)
        .chain(field.species.iter().map(|s| s.height))
        .chain(field.flowers.iter().map(|f| f.height));
    ranges.fold((f32::INFINITY, 0.0f32), |(lo, hi), r| {
        (lo.min(r.min.min(r.max)), hi.max(r.max.max(r.min)))
    })
}

/// The sky's colour along `dir` (without the sun's disk) as the sRGB output stores it: the
/// CPU twin of the sky pass's `sky_radiance(dir)` through the tone-mapping pass
/// (`tonemap` in `shaders/light.wgsl`, run by `render::post`).
pub fn sky_srgb(scene: &Scene, sun: Vec3, dir: Vec3) -> [u8; 3] {
    let l = &scene.light;
    let u = uniforms(scene, sun);
    let c = tone::tonemap(sky_radiance(scene, sun, dir), l.tone_mapping, u.sun[3]);
    [tone::srgb8(c.x), tone::srgb8(c.y), tone::srgb8(c.z)]
}

/// The sky's radiance along `dir` (normalised, without the sun's disk) under the scene's
/// sky model: the CPU twin of `sky_radiance` in `shaders/light.wgsl`.
pub fn sky_radiance(scene: &Scene, sun: Vec3, dir: Vec3) -> Vec3 {
    let l = &scene.light;
    match l.sky {
        SkyModel::Preetham => {
            let u = uniforms(scene, sun);
            let ground = Vec3::from_slice(&u.ambient[..3]) * 0.35;
            sky::PreethamSky::new(sun, l.turbidity).radiance(dir, ground)
        }
        SkyModel::Gradient => sky::gradient_radiance(dir, sun),
    }
}

/// The light uniforms of `scene` for a sun in direction `sun`, without the cascades.
pub fn uniforms(scene: &Scene, sun: Vec3) -> LightUniforms {
    uniforms_with(scene, sun, &mut canopy::CanopyCache::default())
}

/// [`uniforms`] with the canopy's table taken from `canopy`, summed again only when the
/// field's outlines change (the light pass keeps one across frames).
pub fn uniforms_with(scene: &Scene, sun: Vec3, canopy: &mut canopy::CanopyCache) -> LightUniforms {
    let l = &scene.light;
    let sky = sky::PreethamSky::new(sun, l.turbidity);
    let (sun_rgb, ambient) = match l.sky {
        SkyModel::Preetham => (
            sky::sun_radiance(sun, l.turbidity),
            sky.ambient() * sky::SKY_LIGHT,
        ),
        SkyModel::Gradient => (GRADIENT_SUN, GRADIENT_AMBIENT),
    };
    let c = sky.coefficients;
    let sh = &l.shading;
    let field = &scene.field;
    // The canopy's leaf area per ground area: blades per m² times a blade's mean area.
    let leaf_area = field.density * field.height.lerp(0.5) * field.width.lerp(0.5);
    // The shortest blade over the tallest: how the canopy's leaf area thins towards its top
    // (`canopy::canopy_table`).
    let (shortest, tallest) = blade_heights(field);
    let height_spread = if tallest > 0.0 {
        (shortest / tallest).clamp(0.0, 1.0)
    } else {
        1.0
    };
    LightUniforms {
        sun: sun_rgb
            .extend(tone::exposure_multiplier(l.tone_mapping, l.exposure))
            .into(),
        ambient: ambient.extend(l.tone_mapping.id() as f32).into(),
        sky: [
            l.sky.id() as f32,
            l.turbidity,
            sky::SUN_DISK_RADIUS.cos(),
            sky::SUN_DISK_GAIN,
        ],
        perez: [0, 1, 2, 3, 4].map(|i| c[i].extend(0.0).into()),
        zenith: sky.zenith.extend(sun.y.clamp(-1.0, 1.0).acos()).into(),
        shading: [
            [
                sh.rounded_normal,
                sh.translucency,
                sh.specular,
                sh.ambient_occlusion,
            ],
            [sh.color_variation, sh.wind_waves, leaf_area, height_spread],
        ],
        canopy_widths: {
            let [lo, hi] = canopy::width_quartiles(field);
            [lo, hi, 0.0, 0.0]
        },
        canopy: canopy.table(field, height_spread),
        ..Default::default()
    }
}
