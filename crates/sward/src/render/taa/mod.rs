//! Temporal anti-aliasing (issue 27, point 5; `shaders/taa.wgsl`), `render.taa`.
//!
//! Every frame the 3D passes draw one sample per pixel through a projection moved by a
//! sub-pixel offset from the Halton (2, 3) sequence ([`jitter`], [`jitter_matrix`]), and one
//! full-screen pass after them blends the frame into a history target: each pixel finds
//! where its surface was one frame ago (the depth, and for grass the blade's own motion
//! from the change of its control points, read from a copy of the blade buffer taken
//! before the update), reads the history there, clamps it to its 3 × 3 neighbourhood and
//! keeps [`BLEND`] of the new sample. Tone mapping then reads the history.
//!
//! Why it replaces MSAA rather than adding to it: on the software adapter 4× MSAA costs
//! more than the rest of the frame, while the history costs one full-screen pass and a
//! copy of the blades; both anti-alias edges, but only the history also averages a thin
//! blade's coverage over frames, which is what stops it flickering as the wind moves it.
//!
//! Headless renders of N frames use the history exactly as the window does, and the jitter
//! sequence starts over with each renderer, so `sward render` stays deterministic.

pub mod reference;

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec2, Vec3};

use crate::error::Result;
use crate::gpu::queries::PassQueries;
use crate::gpu::Gpu;
use crate::sim::layout::Blade;

/// The weight of the new frame in the blend (`params.x`): the history keeps the rest, so
/// about `1 / BLEND` frames contribute.
pub const BLEND: f32 = 0.1;

/// Moving colliders (balls) whose surface pixels move with them, at most; the others move
/// by the depth alone.
pub const MAX_MOVING: usize = 8;

/// Jitter offsets before the sequence repeats.
pub const JITTER_PHASES: u32 = 8;

/// The radical inverse of `index` in `base` (the Halton sequence), in [0, 1).
pub fn halton(mut index: u32, base: u32) -> f32 {
    let mut f = 1.0;
    let mut r = 0.0;
    while index > 0 {
        f /= base as f32;
        r += f * (index % base) as f32;
        index /= base;
    }
    r
}

/// The sub-pixel offset of frame `frame` in pixels, each axis in (-0.5, 0.5): Halton (2, 3)
/// from index 1, repeating every [`JITTER_PHASES`] frames.
pub fn jitter(frame: u32) -> Vec2 {
    let i = frame % JITTER_PHASES + 1;
    Vec2::new(halton(i, 2), halton(i, 3)) - 0.5
}

/// The clip-space translation that moves the picture by `offset` pixels (x right, y down)
/// in a target of `size`: applied after the projection, it shifts x by `2 dx / w` and y by
/// `-2 dy / h` times w, so depth and the pixel's world point are otherwise unchanged.
pub fn jitter_matrix(offset: Vec2, size: (u32, u32)) -> Mat4 {
    let (w, h) = (size.0.max(1) as f32, size.1.max(1) as f32);
    Mat4::from_translation(Vec3::new(2.0 * offset.x / w, -2.0 * offset.y / h, 0.0))
}

/// What the pass does, for measurements and tests: the defaults are the pass as shipped;
/// switching a part off shows what it contributes (e.g. `blend` 1 makes the history the
/// last frame exactly, and `blend` 0 without the clamp shows the last frame moved to this
/// one by the motion alone).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TaaSettings {
    /// The new frame's weight where the history is found and still.
    pub blend: f32,
    /// Clamp the history to the neighbourhood's box.
    pub clamp: bool,
    /// Jitter the projection.
    pub jitter: bool,
    /// Move grass pixels with their blades (else with the depth alone).
    pub blade_motion: bool,
}

impl Default for TaaSettings {
    fn default() -> Self {
        Self {
            blend: BLEND,
            clamp: true,
            jitter: true,
            blade_motion: true,
        }
    }
}

/// The pass's uniforms (`TaaUniforms` in the shader).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct TaaUniforms {
    /// This frame's jittered view-projection relative to its eye, inverted.
    pub inv_view_proj: [[f32; 4]; 4],
    /// The last frame's unjittered view-projection relative to its eye.
    pub prev_view_proj: [[f32; 4]; 4],
    /// This eye minus the last one; w: 1 where a history exists.
    pub eye_shift: [f32; 4],
    /// [`BLEND`], 1 with a visibility buffer, the target's width and height.
    pub params: [f32; 4],
    /// xy: this frame's jitter in normalised device coordinates; z: 1 to clamp the
    /// history; w: how many spheres of `moving` are used.
    pub jitter: [f32; 4],
    /// The colliders that moved since the last frame, in pairs: the centre now relative
    /// to this eye and the radius, then the centre then relative to this eye.
    pub moving: [[f32; 4]; 2 * MAX_MOVING],
}

/// One frame's views, as the pass reads them.
pub struct FrameViews {
    /// This frame's view-projection relative to the eye, without the jitter.
    pub view_proj: Mat4,
    /// The jitter applied after it.
    pub jitter: Mat4,
    /// The camera's world position this frame (m), the origin of `view_proj`.
    pub eye: Vec3,
    /// The colliders this frame (centre and radius, world), in the renderer's order.
    pub spheres: Vec<[f32; 4]>,
}

/// The uniforms of a frame of `size` drawn with `now`, after a frame drawn with `last`
/// (`None`: no history yet).
pub fn uniforms(
    now: &FrameViews,
    last: Option<&FrameViews>,
    has_vis: bool,
    size: (u32, u32),
    settings: &TaaSettings,
) -> TaaUniforms {
    let inv = (now.jitter * now.view_proj).as_dmat4().inverse().as_mat4();
    let (prev, shift, valid) = match last {
        Some(l) => (l.view_proj, now.eye - l.eye, 1.0),
        None => (Mat4::IDENTITY, Vec3::ZERO, 0.0),
    };
    let moving = last.map_or((0, [[0.0; 4]; 2 * MAX_MOVING]), |l| moving_spheres(now, l));
    TaaUniforms {
        inv_view_proj: inv.to_cols_array_2d(),
        prev_view_proj: prev.to_cols_array_2d(),
        eye_shift: shift.extend(valid).into(),
        params: [
            settings.blend,
            if has_vis && settings.blade_motion {
                1.0
            } else {
                0.0
            },
            size.0 as f32,
            size.1 as f32,
        ],
        jitter: [
            now.jitter.w_axis.x,
            now.jitter.w_axis.y,
            if settings.clamp { 1.0 } else { 0.0 },
            moving.0 as f32,
        ],
        moving: moving.1,
    }
}

/// The first [`MAX_MOVING`] colliders of `now` whose centre differs from the same
/// collider's in `last`, as the shader reads them, and how many.
fn moving_spheres(now: &FrameViews, last: &FrameViews) -> (usize, [[f32; 4]; 2 * MAX_MOVING]) {
    let mut out = [[0.0; 4]; 2 * MAX_MOVING];
    let mut n = 0;
    for (a, b) in now.spheres.iter().zip(&last.spheres) {
        if n == MAX_MOVING {
            break;
        }
        if a[..3] != b[..3] {
            let rel = |c: &[f32; 4]| (Vec3::new(c[0], c[1], c[2]) - now.eye).extend(c[3]);
            out[2 * n] = rel(a).into();
            out[2 * n + 1] = rel(b).into();
            n += 1;
        }
    }
    (n, out)
}

/// The two history targets of one size (written in turn) and the bind groups that read
/// them: the pass's (one per target read) and the tone mapping's (one per target written).
struct History {
    size: (u32, u32),
    /// Kept: the bind groups reference their views.
    _textures: [wgpu::Texture; 2],
    views: [wgpu::TextureView; 2],
    tonemap_groups: [wgpu::BindGroup; 2],
    /// The pass's groups, with the views and buffer they were made for.
    groups: Option<(GroupKey, [wgpu::BindGroup; 2])>,
    /// The target the next frame writes.
    write: usize,
}

/// What the pass's bind groups were made from: rebuilt when one of them changes.
#[derive(PartialEq)]
struct GroupKey {
    scene: wgpu::TextureView,
    depth: wgpu::TextureView,
    vis: Option<wgpu::TextureView>,
}

/// The pass, its history and the copy of the blades from before the update.
pub struct TaaPass {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    uniforms: wgpu::Buffer,
    sampler: wgpu::Sampler,
    /// Bound where the grass is drawn forward (no visibility buffer).
    no_vis: wgpu::TextureView,
    /// The blades' control points as the last frame drew them, and the copy pass's group
    /// that writes them.
    prev_blades: Option<(wgpu::Buffer, wgpu::BindGroup)>,
    /// The copy pass (`shaders/taa_prev.wgsl`).
    copy: wgpu::ComputePipeline,
    history: Option<History>,
    /// Frames drawn with this pass (the jitter's phase).
    frame: u32,
    /// The last frame's views (`None`: no history yet).
    last: Option<FrameViews>,
    /// This frame's, until [`TaaPass::encode`] makes them the last.
    now: Option<FrameViews>,
    /// What the pass does (the shipped pass by default).
    pub settings: TaaSettings,
    /// The uniforms of the last [`TaaPass::prepare`] (the twin's test reads them).
    written: TaaUniforms,
}

impl TaaPass {
    /// The pass for blades held in `blades`.
    pub fn new(gpu: &Gpu, blades: &wgpu::Buffer) -> Self {
        let device = &gpu.device;
        let fragment = wgpu::ShaderStages::FRAGMENT;
        let texture = |binding, sample_type| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: fragment,
            ty: wgpu::BindingType::Texture {
                sample_type,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        let storage = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: fragment,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only: true },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let float = |filterable| wgpu::TextureSampleType::Float { filterable };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.taa.layout"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: fragment,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                texture(1, float(false)),
                texture(2, float(true)),
                wgpu::BindGroupLayoutEntry {
                    binding: 3,
                    visibility: fragment,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
                texture(4, wgpu::TextureSampleType::Depth),
                texture(5, wgpu::TextureSampleType::Uint),
                storage(6),
                storage(7),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sward.taa.pipeline_layout"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let module = crate::shaders::module(device, "taa.wgsl");
        let pipeline = super::pipelines::fullscreen_pipeline(
            device,
            "sward.taa.pipeline",
            &pipeline_layout,
            &module,
            ("vs_taa", "fs_taa"),
            super::post::HDR_FORMAT,
            None,
            &[],
        );
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.taa.uniforms"),
            size: std::mem::size_of::<TaaUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("sward.taa.sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let no_vis = device
            .create_texture(&wgpu::TextureDescriptor {
                label: Some("sward.taa.no_vis"),
                size: wgpu::Extent3d {
                    width: 1,
                    height: 1,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: super::deferred::VIS_FORMAT,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            })
            .create_view(&Default::default());
        let copy = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("sward.taa.copy_prev"),
            // The layout is the shader's: the blades, read, and their copy, written.
            layout: None,
            module: &crate::shaders::module(device, "taa_prev.wgsl"),
            entry_point: Some("copy_prev"),
            compilation_options: Default::default(),
            cache: None,
        });
        let prev_blades = Some(prev_blades_buffer(device, &copy, blades));
        Self {
            copy,
            pipeline,
            layout,
            uniforms,
            sampler,
            no_vis,
            prev_blades,
            history: None,
            frame: 0,
            last: None,
            now: None,
            settings: TaaSettings::default(),
            written: TaaUniforms::zeroed(),
        }
    }

    /// Bytes of GPU memory the pass holds: the blades' copy and the two history targets.
    pub fn gpu_bytes(&self) -> u64 {
        let history = self
            .history
            .as_ref()
            .map_or(0, |h| 2 * h.size.0 as u64 * h.size.1 as u64 * 8);
        self.prev_blades.as_ref().map_or(0, |b| b.0.size()) + history
    }

    /// Lets go of the history and the blades' copy while the pass is switched off (the
    /// pipeline stays: building it again each time costs the software adapter memory).
    pub fn release(&mut self) {
        self.history = None;
        self.prev_blades = None;
        self.last = None;
        self.now = None;
    }

    /// Takes the blades' copy back after [`TaaPass::release`]; the history starts over.
    pub fn resume(&mut self, device: &wgpu::Device, blades: &wgpu::Buffer) {
        if self.prev_blades.is_none() {
            self.prev_blades = Some(prev_blades_buffer(device, &self.copy, blades));
        }
    }

    /// Whether this frame was prepared and its pass can be recorded.
    pub fn ready(&self) -> bool {
        self.now.is_some() && self.history.as_ref().is_some_and(|h| h.groups.is_some())
    }

    /// Whether the pass holds its buffers (not released).
    pub fn active(&self) -> bool {
        self.prev_blades.is_some()
    }

    /// This frame's jitter as a clip-space matrix for a target of `size` (advances the
    /// sequence: call once per frame).
    pub fn next_jitter(&mut self, size: (u32, u32)) -> Mat4 {
        let offset = if self.settings.jitter {
            jitter(self.frame)
        } else {
            Vec2::ZERO
        };
        self.frame = self.frame.wrapping_add(1);
        jitter_matrix(offset, size)
    }

    /// Records the copy of the blades' control points as the last frame left them, before
    /// this frame's update moves them (the grass's motion is the difference): a compute
    /// pass over `blade_count` slots, timed and counted as part of the TAA.
    pub fn copy_blades(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        blade_count: u64,
        q: PassQueries,
    ) {
        let Some((_, group)) = &self.prev_blades else {
            return;
        };
        let groups = blade_count.div_ceil(u64::from(COPY_GROUP)).max(1);
        let x = groups.min(u64::from(MAX_GROUPS_X));
        let y = groups.div_ceil(x);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("sward.taa.copy_prev"),
            timestamp_writes: q.compute_writes(),
        });
        q.begin(&mut pass);
        pass.set_pipeline(&self.copy);
        pass.set_bind_group(0, group, &[]);
        pass.dispatch_workgroups(x as u32, y as u32, 1);
        q.end(&mut pass);
    }

    /// Sets this frame's views and inputs (`scene`, this frame's radiance; `depth`; `vis`,
    /// the visibility buffer where the grass was deferred; `blades`, as the update left
    /// them) and writes the uniforms of a target of `size`. The history is (re)allocated
    /// at a new size and starts empty.
    #[allow(clippy::too_many_arguments)]
    pub fn prepare(
        &mut self,
        gpu: &Gpu,
        tonemap: &super::post::ToneMap,
        now: FrameViews,
        (scene, depth, vis): (
            &wgpu::TextureView,
            &wgpu::TextureView,
            Option<&wgpu::TextureView>,
        ),
        blades: &wgpu::Buffer,
        size: (u32, u32),
    ) {
        if self.history.as_ref().map(|h| h.size) != Some(size) {
            // Dropped first: the old targets are not held beside the new ones.
            self.history = None;
            self.history = Some(self.allocate(gpu, tonemap, size));
            self.last = None;
        }
        let u = uniforms(
            &now,
            self.last.as_ref(),
            vis.is_some(),
            size,
            &self.settings,
        );
        gpu.queue
            .write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&u));
        self.written = u;
        self.now = Some(now);
        let key = GroupKey {
            scene: scene.clone(),
            depth: depth.clone(),
            vis: vis.cloned(),
        };
        let (Some(h), Some((prev, _))) = (&self.history, &self.prev_blades) else {
            return;
        };
        if h.groups.as_ref().map(|g| &g.0) == Some(&key) {
            return;
        }
        let group = |read: usize| {
            gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("sward.taa.bind_group"),
                layout: &self.layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: self.uniforms.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(scene),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::TextureView(&h.views[read]),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: wgpu::BindingResource::Sampler(&self.sampler),
                    },
                    wgpu::BindGroupEntry {
                        binding: 4,
                        resource: wgpu::BindingResource::TextureView(depth),
                    },
                    wgpu::BindGroupEntry {
                        binding: 5,
                        resource: wgpu::BindingResource::TextureView(vis.unwrap_or(&self.no_vis)),
                    },
                    wgpu::BindGroupEntry {
                        binding: 6,
                        resource: blades.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 7,
                        resource: prev.as_entire_binding(),
                    },
                ],
            })
        };
        let groups = [group(0), group(1)];
        if let Some(h) = &mut self.history {
            h.groups = Some((key, groups));
        }
    }

    fn allocate(&self, gpu: &Gpu, tonemap: &super::post::ToneMap, size: (u32, u32)) -> History {
        let make = |i: usize| {
            gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some(["sward.taa.history0", "sward.taa.history1"][i]),
                size: wgpu::Extent3d {
                    width: size.0.max(1),
                    height: size.1.max(1),
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: super::post::HDR_FORMAT,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            })
        };
        let textures = [make(0), make(1)];
        let views = [0, 1].map(|i| textures[i].create_view(&Default::default()));
        let tonemap_groups = [0, 1].map(|i| tonemap.bind_view(&gpu.device, &views[i]));
        History {
            size,
            _textures: textures,
            views,
            tonemap_groups,
            groups: None,
            write: 0,
        }
    }

    /// Records the pass: this frame (drawn with the jitter of [`TaaPass::next_jitter`])
    /// blended with the history into the other history target, and returns the tone
    /// mapping's bind group that reads the result. `None` without a
    /// [`TaaPass::prepare`] this frame; [`TaaPass::finish`] after the tone mapping.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        q: PassQueries,
    ) -> Option<&wgpu::BindGroup> {
        self.now.as_ref()?;
        let h = self.history.as_ref()?;
        let (_, groups) = h.groups.as_ref()?;
        let write = h.write;
        let mut pass = super::pipelines::fullscreen_pass(encoder, "sward.taa", &h.views[write], &q);
        q.begin(&mut pass);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &groups[1 - write], &[]);
        pass.draw(0..3, 0..1);
        q.end(&mut pass);
        Some(&h.tonemap_groups[write])
    }

    /// The history target this frame's [`TaaPass::encode`] wrote (what the tone mapping
    /// shows), until [`TaaPass::finish`]; `None` without a frame encoded.
    pub fn written(&self) -> Option<&wgpu::TextureView> {
        self.now.as_ref()?;
        let h = self.history.as_ref()?;
        h.groups.as_ref()?;
        Some(&h.views[h.write])
    }

    /// Ends a frame that [`TaaPass::encode`] recorded: what it wrote becomes the history.
    pub fn finish(&mut self) {
        if let (Some(now), Some(h)) = (self.now.take(), &mut self.history) {
            h.write = 1 - h.write;
            self.last = Some(now);
        }
    }

    /// Reads the last finished frame's inputs and outputs back (blocking; for the twin's
    /// test): `blades` is the blade buffer the pass read. `None` before a finished frame.
    pub fn read_frame(
        &self,
        gpu: &Gpu,
        blades: &wgpu::Buffer,
    ) -> Result<Option<reference::TaaFrame>> {
        let Some(h) = &self.history else {
            return Ok(None);
        };
        let Some((key, _)) = &h.groups else {
            return Ok(None);
        };
        if self.last.is_none() {
            return Ok(None);
        }
        let size = h.size;
        let read = |view: &wgpu::TextureView, texel: u32, aspect| {
            super::target::read_texels_sized(
                gpu,
                wgpu::TexelCopyTextureInfo {
                    texture: view.texture(),
                    mip_level: 0,
                    origin: wgpu::Origin3d::ZERO,
                    aspect,
                },
                size,
                texel,
                "sward.taa.read_frame",
            )
        };
        let all = wgpu::TextureAspect::All;
        let halves = |view: &wgpu::TextureView| {
            super::target::read_rgba16f(gpu, view.texture(), size, "sward.taa.read_frame")
        };
        let floats = |view, aspect| -> Result<Vec<f32>> {
            Ok(bytemuck::pod_collect_to_vec(&read(view, 4, aspect)?))
        };
        let blade_list = |buffer: &wgpu::Buffer| -> Result<Vec<Blade>> {
            let bytes = crate::gpu::read_buffer(gpu, buffer, buffer.size())?;
            Ok(bytemuck::pod_collect_to_vec(&bytes))
        };
        // `finish` has turned the targets: the next frame writes the one this one read.
        let (input, output) = (h.write, 1 - h.write);
        let vis = match &key.vis {
            Some(v) => Some(bytemuck::pod_collect_to_vec(&read(v, 16, all)?)),
            None => None,
        };
        Ok(Some(reference::TaaFrame {
            size,
            uniforms: self.written,
            scene: halves(&key.scene)?,
            depth: floats(&key.depth, wgpu::TextureAspect::DepthOnly)?,
            vis,
            blades: blade_list(blades)?,
            prev_blades: match &self.prev_blades {
                Some((b, _)) => {
                    // 48 bytes a slot: v0 and direction, v1 and height, v2 and width.
                    let words: Vec<[f32; 12]> =
                        bytemuck::pod_collect_to_vec(&crate::gpu::read_buffer(gpu, b, b.size())?);
                    words
                        .iter()
                        .map(|w| Blade {
                            v0_dir: [w[0], w[1], w[2], w[3]],
                            v1_height: [w[4], w[5], w[6], w[7]],
                            v2_width: [w[8], w[9], w[10], w[11]],
                            up_stiffness: [0.0; 4],
                        })
                        .collect()
                }
                None => return Ok(None),
            },
            history: halves(&h.views[input])?,
            output: halves(&h.views[output])?,
        }))
    }
}

/// Invocations per workgroup of the copy pass (`COPY_GROUP` in `taa_prev.wgsl`).
pub const COPY_GROUP: u32 = 256;
/// Workgroups along x a dispatch may have (WebGPU's limit); the copy folds the rest into y.
const MAX_GROUPS_X: u32 = 65_535;
/// Bytes of one blade's copy: v0, v1 and v2 with their fourth components.
pub const PREV_BLADE_BYTES: u64 = 48;

/// The copy of the blades' control points from before the update (48 of each blade's 64
/// bytes), and the copy pass's group that writes it from `blades`.
fn prev_blades_buffer(
    device: &wgpu::Device,
    copy: &wgpu::ComputePipeline,
    blades: &wgpu::Buffer,
) -> (wgpu::Buffer, wgpu::BindGroup) {
    let slots = blades.size() / std::mem::size_of::<Blade>() as u64;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("sward.taa.prev_blades"),
        size: slots.max(1) * PREV_BLADE_BYTES,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("sward.taa.copy_prev.group"),
        layout: &copy.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: blades.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: buffer.as_entire_binding(),
            },
        ],
    });
    (buffer, group)
}
