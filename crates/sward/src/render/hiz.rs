//! The hierarchical depth pyramid ("Hi-Z", `shaders/hiz.wgsl`) for occlusion culling: an
//! R32Float mip chain above the depth buffer, each texel the farthest depth of the texels
//! below it. Level 0 is the depth buffer itself (not copied: the cull binds it beside the
//! pyramid, [`DepthPyramid::level0_view`]); the pyramid texture holds levels 1 and up, which
//! the cull reads with `textureLoad(hiz, coord, level - 1)` through [`DepthPyramid::view`].
//! With MSAA the depth is multisampled and the pyramid keeps a level 0 of its own, the
//! farthest sample of each pixel. CPU twin: [`crate::sim::reference::hiz`].

use crate::error::{Error, Result};
use crate::gpu::queries::PassQueries;
use crate::gpu::Gpu;
use crate::shaders;

/// Threads per workgroup along x and y (`@workgroup_size(8, 8)` in WGSL).
const TILE: u32 = 8;

/// Format of the pyramid: single-channel float, writable as a storage texture in core
/// WebGPU (depth formats are not).
pub const HIZ_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// The pyramid texture, its views, and the two pipelines that build it.
pub struct DepthPyramid {
    /// Size of level 0 (the depth buffer's).
    size: (u32, u32),
    /// Levels in all, level 0 included: a full chain down to 1 x 1.
    levels: u32,
    /// Levels 1 and up as mips 0 and up (a 1 x 1 stand-in when level 0 is all there is).
    texture: wgpu::Texture,
    /// Levels 1 and up, for the culling shader.
    view: wgpu::TextureView,
    /// One view per level from 1: `mip_views[k - 1]` is level k, the storage target of its
    /// own level and the sampled source of the next (a storage binding needs one mip).
    mip_views: Vec<wgpu::TextureView>,
    /// With MSAA, level 0: the farthest sample of each pixel.
    level0: Option<(wgpu::Texture, wgpu::TextureView)>,
    /// Samples per pixel of the depth buffers it is built from.
    samples: u32,
    copy_layout: wgpu::BindGroupLayout,
    copy: wgpu::ComputePipeline,
    downsample: wgpu::ComputePipeline,
    /// `level_groups[k - 2]` reads level k - 1 and writes level k. They never change, so
    /// they are built once; only the first pass's depends on the caller's depth view.
    level_groups: Vec<wgpu::BindGroup>,
}

impl DepthPyramid {
    /// A pyramid for a single-sample depth buffer of `width` x `height` (both at least 1).
    pub fn new(gpu: &Gpu, width: u32, height: u32) -> Self {
        Self::with_samples(gpu, width, height, 1)
    }

    /// A pyramid for a depth buffer of `width` x `height` with `samples` samples per pixel.
    pub fn with_samples(gpu: &Gpu, width: u32, height: u32, samples: u32) -> Self {
        let device = &gpu.device;
        let size = wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        };
        // A full chain down to 1x1; wgpu's own mip rules (halve, round down, at least 1)
        // so that the sizes here are the texture's.
        let levels = size.max_mips(wgpu::TextureDimension::D2);
        let r32 = |label: &str, size: wgpu::Extent3d, mips: u32| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size,
                mip_level_count: mips,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: HIZ_FORMAT,
                usage: wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::STORAGE_BINDING
                    | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            })
        };
        let upper = levels.saturating_sub(1);
        let texture = r32(
            "sward.hiz.pyramid",
            size.mip_level_size(upper.min(1), wgpu::TextureDimension::D2),
            upper.max(1),
        );
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some("sward.hiz.view"),
            usage: Some(wgpu::TextureUsages::TEXTURE_BINDING),
            ..Default::default()
        });
        let mip_views: Vec<_> = (0..upper)
            .map(|mip| {
                texture.create_view(&wgpu::TextureViewDescriptor {
                    label: Some(&format!("sward.hiz.level{}", mip + 1)),
                    base_mip_level: mip,
                    mip_level_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        let level0 = (samples > 1).then(|| {
            let t = r32("sward.hiz.level0", size, 1);
            let v = t.create_view(&wgpu::TextureViewDescriptor {
                label: Some("sward.hiz.level0_view"),
                ..Default::default()
            });
            (t, v)
        });

        let module = shaders::module(device, "hiz.wgsl");
        let dst_entry = wgpu::BindGroupLayoutEntry {
            binding: 2,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::StorageTexture {
                access: wgpu::StorageTextureAccess::WriteOnly,
                format: HIZ_FORMAT,
                view_dimension: wgpu::TextureViewDimension::D2,
            },
            count: None,
        };
        let texture_entry = |binding, sample_type| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Texture {
                sample_type,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        // Single-sample: the depth into level 1 (`dst`). MSAA: the samples into level 0
        // (`dst`) and, with two levels or more, level 1 (`dst1`) too.
        let mut copy_entries = vec![depth_entry(samples), dst_entry];
        if samples > 1 && levels >= 2 {
            copy_entries.push(wgpu::BindGroupLayoutEntry {
                binding: 5,
                ..dst_entry
            });
        }
        let copy_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.hiz.copy_layout"),
            entries: &copy_entries,
        });
        // R32Float is not filterable without a feature; textureLoad needs no filtering.
        let downsample_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.hiz.downsample_layout"),
            entries: &[
                texture_entry(1, wgpu::TextureSampleType::Float { filterable: false }),
                dst_entry,
            ],
        });
        let make = |layout: &wgpu::BindGroupLayout, entry: &str, label: &str| {
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(&format!("{label}_layout")),
                bind_group_layouts: &[Some(layout)],
                immediate_size: 0,
            });
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(label),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let copy_entry = match (samples > 1, levels >= 2) {
            (true, true) => "copy_depth2_ms",
            (true, false) => "copy_depth_ms",
            (false, _) => "reduce_depth",
        };
        let copy = make(&copy_layout, copy_entry, "sward.hiz.copy");
        let downsample = make(&downsample_layout, "downsample", "sward.hiz.downsample");
        let level_groups = (2..levels as usize)
            .map(|level| {
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some(&format!("sward.hiz.downsample{level}")),
                    layout: &downsample_layout,
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: wgpu::BindingResource::TextureView(&mip_views[level - 2]),
                        },
                        wgpu::BindGroupEntry {
                            binding: 2,
                            resource: wgpu::BindingResource::TextureView(&mip_views[level - 1]),
                        },
                    ],
                })
            })
            .collect();
        Self {
            size: (width, height),
            levels,
            texture,
            view,
            mip_views,
            level0,
            samples,
            copy_layout,
            copy,
            downsample,
            level_groups,
        }
    }

    /// Size of level 0 (the depth buffer's size).
    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    fn level_size(&self, level: u32) -> (u32, u32) {
        let e = wgpu::Extent3d {
            width: self.size.0,
            height: self.size.1,
            depth_or_array_layers: 1,
        }
        .mip_level_size(level, wgpu::TextureDimension::D2);
        (e.width, e.height)
    }

    /// Samples per pixel of the depth it reads.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// Number of levels, level 0 included, the last one 1x1.
    pub fn levels(&self) -> u32 {
        self.levels
    }

    /// Levels 1 and up as an unfilterable-float 2D texture, for
    /// `textureLoad(hiz, coord, level - 1)`.
    pub fn view(&self) -> &wgpu::TextureView {
        &self.view
    }

    /// Level 0 for a pyramid built from `depth`: `depth` itself (bound as an
    /// unfilterable-float texture), or with MSAA the pyramid's own farthest-sample level.
    pub fn level0_view<'a>(&'a self, depth: &'a wgpu::TextureView) -> &'a wgpu::TextureView {
        self.level0.as_ref().map_or(depth, |(_, v)| v)
    }

    /// Records the build of every level above the depth buffer from `depth`, a
    /// Depth32Float view of this pyramid's size and sample count with TEXTURE_BINDING usage.
    ///
    /// One compute pass per level (with MSAA, levels 0 and 1 share the first): each pass
    /// reads the level the previous one wrote, and a pass boundary is where that
    /// read-after-write is synchronised for certain. With `q`'s timestamps, the first pass
    /// writes the start and the last one the end; every level's pass is counted. A 1 x 1
    /// single-sample target has nothing to build: one empty pass keeps the timestamps.
    pub fn encode(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        depth: &wgpu::TextureView,
        q: PassQueries,
    ) {
        self.encode_levels(device, encoder, depth, q, self.levels);
    }

    /// Records only what the per-blade occlusion test reads, level 0 (the late pass after
    /// the early grass draw: `point_occluded` reads level 0 alone; the coarser levels serve
    /// the patch boxes, tested before the draw). With one sample level 0 is the depth
    /// buffer itself and nothing is built (one empty pass keeps the timestamps);
    /// multisampled, the first pass writes it (and level 1 with it).
    pub fn encode_base(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        depth: &wgpu::TextureView,
        q: PassQueries,
    ) {
        if self.level0.is_some() {
            self.encode_levels(device, encoder, depth, q, self.levels.min(2));
        } else {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("sward.hiz.level0"),
                timestamp_writes: q.compute_writes_part(true, true),
            });
            q.begin(&mut pass);
            q.end(&mut pass);
        }
    }

    /// `encode` of the levels below `upto`.
    fn encode_levels(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        depth: &wgpu::TextureView,
        q: PassQueries,
        upto: u32,
    ) {
        // The first pass's group is made per call: the depth view is the caller's and is
        // replaced on resize.
        let mut entries = vec![wgpu::BindGroupEntry {
            binding: if self.samples > 1 { 3 } else { 0 },
            resource: wgpu::BindingResource::TextureView(depth),
        }];
        let first_target = match &self.level0 {
            Some((_, level0)) => Some(level0),
            None => self.mip_views.first(),
        };
        if let Some(target) = first_target {
            entries.push(wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::TextureView(target),
            });
        }
        if self.level0.is_some() && self.levels >= 2 {
            entries.push(wgpu::BindGroupEntry {
                binding: 5,
                resource: wgpu::BindingResource::TextureView(&self.mip_views[0]),
            });
        }
        let copy_group = first_target.map(|_| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("sward.hiz.copy"),
                layout: &self.copy_layout,
                entries: &entries,
            })
        });
        // The first pass writes level 1 (and with MSAA level 0): its dispatch covers the
        // texels of the level it reduces to, level 1, or level 0 when that is all there is.
        let passes = std::iter::once(1).chain(2..upto);
        let last = upto.max(2) - 1;
        for level in passes {
            let (w, h) = self.level_size(level.min(self.levels - 1));
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(&format!("sward.hiz.level{level}")),
                timestamp_writes: q.compute_writes_part(level == 1, level == last),
            });
            q.begin(&mut pass);
            if level == 1 {
                if let Some(group) = &copy_group {
                    pass.set_pipeline(&self.copy);
                    pass.set_bind_group(0, group, &[]);
                    pass.dispatch_workgroups(w.div_ceil(TILE), h.div_ceil(TILE), 1);
                }
            } else {
                pass.set_pipeline(&self.downsample);
                pass.set_bind_group(0, &self.level_groups[level as usize - 2], &[]);
                pass.dispatch_workgroups(w.div_ceil(TILE), h.div_ceil(TILE), 1);
            }
            q.end(&mut pass);
        }
    }

    /// Reads one level back, row-major (blocking; for tests). Level 0 of a single-sample
    /// pyramid is the depth buffer: [`DepthPyramid::read_levels`] reads it from there.
    pub fn read_level(&self, gpu: &Gpu, level: u32) -> Result<Vec<f32>> {
        if level >= self.levels() {
            return Err(Error::Invalid(format!(
                "depth pyramid level {level} does not exist: it has {} levels",
                self.levels()
            )));
        }
        let (texture, mip_level) = match (level, &self.level0) {
            (0, Some((t, _))) => (t, 0),
            (0, None) => {
                return Err(Error::Invalid(
                    "level 0 of a single-sample pyramid is the depth buffer itself".into(),
                ))
            }
            (k, _) => (&self.texture, k - 1),
        };
        let bytes = super::target::read_texels(
            gpu,
            wgpu::TexelCopyTextureInfo {
                texture,
                mip_level,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            self.level_size(level),
            "sward.hiz.readback",
        )?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }

    /// Every level of the pyramid built from `depth` (its level 0 read from `depth` itself
    /// when single-sample), row-major (blocking; for tests).
    pub fn read_levels(&self, gpu: &Gpu, depth: &wgpu::TextureView) -> Result<Vec<Vec<f32>>> {
        let level0 = if self.samples > 1 {
            self.read_level(gpu, 0)?
        } else {
            self.dump_depth(gpu, depth, 1)?
        };
        std::iter::once(Ok(level0))
            .chain((1..self.levels).map(|k| self.read_level(gpu, k)))
            .collect()
    }

    /// Every sample of a multisampled Depth32Float `depth` of this pyramid's size, at
    /// `[(y * width + x) * samples + s]` (blocking; for the test of the farthest-sample
    /// reduction: multisampled textures cannot be copied to a buffer).
    pub fn read_depth_samples(&self, gpu: &Gpu, depth: &wgpu::TextureView) -> Result<Vec<f32>> {
        if self.samples < 2 {
            return Err(Error::Invalid(
                "read_depth_samples needs a multisampled pyramid".into(),
            ));
        }
        self.dump_depth(gpu, depth, self.samples)
    }

    /// Every sample of `depth` (this pyramid's size, `samples` per pixel) through a compute
    /// copy into a buffer: a depth texture of either kind read as the cull reads it.
    fn dump_depth(&self, gpu: &Gpu, depth: &wgpu::TextureView, samples: u32) -> Result<Vec<f32>> {
        let device = &gpu.device;
        let (w, h) = self.size();
        let size = w as u64 * h as u64 * samples as u64 * 4;
        let buffer = |label, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        let out = buffer(
            "sward.hiz.samples",
            wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        );
        let staging = buffer(
            "sward.hiz.samples_staging",
            wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        );
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.hiz.dump_layout"),
            entries: &[
                depth_entry(samples),
                wgpu::BindGroupLayoutEntry {
                    binding: 4,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only: false },
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sward.hiz.dump_pipeline_layout"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("sward.hiz.dump"),
            layout: Some(&pipeline_layout),
            module: &shaders::module(device, "hiz.wgsl"),
            entry_point: Some(if samples > 1 {
                "dump_samples"
            } else {
                "dump_depth"
            }),
            compilation_options: Default::default(),
            cache: None,
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sward.hiz.dump_group"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: depth_entry(samples).binding,
                    resource: wgpu::BindingResource::TextureView(depth),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: out.as_entire_binding(),
                },
            ],
        });
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("sward.hiz.dump"),
        });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("sward.hiz.dump"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(w.div_ceil(TILE), h.div_ceil(TILE), 1);
        }
        encoder.copy_buffer_to_buffer(&out, 0, &staging, 0, size);
        gpu.queue.submit([encoder.finish()]);
        let bytes = crate::gpu::map_and_read(gpu, &staging)?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }

    /// GPU memory of the pyramid (its levels, level 0 only with MSAA; 4 bytes a texel).
    pub fn gpu_bytes(&self) -> u64 {
        let first = if self.level0.is_some() { 0 } else { 1 };
        (first..self.levels)
            .map(|level| {
                let (w, h) = self.level_size(level);
                w as u64 * h as u64 * 4
            })
            .sum()
    }
}

/// The depth binding of a pass reading a depth of `samples` per pixel: `texture_depth_2d`
/// at 0 (`reduce_depth`, `dump_depth`) or `texture_depth_multisampled_2d` at 3 (the
/// multisampled copies, `dump_samples`).
fn depth_entry(samples: u32) -> wgpu::BindGroupLayoutEntry {
    if samples > 1 {
        return multisampled_depth_entry(3);
    }
    wgpu::BindGroupLayoutEntry {
        binding: 0,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Depth,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

/// A `texture_depth_multisampled_2d` binding for compute.
fn multisampled_depth_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Depth,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: true,
        },
        count: None,
    }
}
