//! The hierarchical depth pyramid ("Hi-Z", `shaders/hiz.wgsl`) for occlusion culling: an
//! R32Float mip chain whose level 0 is a copy of the depth buffer and whose every texel
//! above holds the farthest depth of the texels below it. A cull shader reads it with
//! `textureLoad(hiz, coord, level)` through [`DepthPyramid::view`]. With MSAA the depth is
//! multisampled and level 0 keeps the farthest sample of each pixel. CPU twin:
//! [`crate::sim::reference::hiz`].

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
    texture: wgpu::Texture,
    /// All levels, for the culling shader.
    view: wgpu::TextureView,
    /// One view per level: each is the storage target of its own level and the sampled
    /// source of the next (a storage binding needs a single-mip view).
    mip_views: Vec<wgpu::TextureView>,
    /// Samples per pixel of the depth buffers it is built from.
    samples: u32,
    copy_layout: wgpu::BindGroupLayout,
    copy: wgpu::ComputePipeline,
    downsample: wgpu::ComputePipeline,
    /// `level_groups[k - 1]` reads level k - 1 and writes level k. They never change, so
    /// they are built once; only level 0's depends on the caller's depth view.
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
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("sward.hiz.pyramid"),
            size,
            mip_level_count: levels,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: HIZ_FORMAT,
            usage: wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some("sward.hiz.view"),
            usage: Some(wgpu::TextureUsages::TEXTURE_BINDING),
            ..Default::default()
        });
        let mip_views: Vec<_> = (0..levels)
            .map(|level| {
                texture.create_view(&wgpu::TextureViewDescriptor {
                    label: Some(&format!("sward.hiz.level{level}")),
                    base_mip_level: level,
                    mip_level_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();

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
        // With two levels or more the copy writes level 1 as well (`copy_depth2`).
        let fused = levels >= 2;
        let depth_entry = if samples > 1 {
            multisampled_depth_entry(3)
        } else {
            texture_entry(0, wgpu::TextureSampleType::Depth)
        };
        let level1_entry = wgpu::BindGroupLayoutEntry {
            binding: 5,
            ..dst_entry
        };
        let copy_entries = [depth_entry, dst_entry, level1_entry];
        let copy_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.hiz.copy_layout"),
            entries: &copy_entries[..if fused { 3 } else { 2 }],
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
        let copy_entry = match (fused, samples > 1) {
            (true, true) => "copy_depth2_ms",
            (true, false) => "copy_depth2",
            (false, true) => "copy_depth_ms",
            (false, false) => "copy_depth",
        };
        let copy = make(&copy_layout, copy_entry, "sward.hiz.copy");
        let downsample = make(&downsample_layout, "downsample", "sward.hiz.downsample");
        let level_groups = (1..levels as usize)
            .map(|level| {
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some(&format!("sward.hiz.downsample{level}")),
                    layout: &downsample_layout,
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: wgpu::BindingResource::TextureView(&mip_views[level - 1]),
                        },
                        wgpu::BindGroupEntry {
                            binding: 2,
                            resource: wgpu::BindingResource::TextureView(&mip_views[level]),
                        },
                    ],
                })
            })
            .collect();
        Self {
            texture,
            view,
            mip_views,
            samples,
            copy_layout,
            copy,
            downsample,
            level_groups,
        }
    }

    /// Size of level 0 (the depth buffer's size).
    pub fn size(&self) -> (u32, u32) {
        (self.texture.width(), self.texture.height())
    }

    fn level_size(&self, level: u32) -> (u32, u32) {
        let e = self
            .texture
            .size()
            .mip_level_size(level, wgpu::TextureDimension::D2);
        (e.width, e.height)
    }

    /// Samples per pixel of the depth it reads.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// Number of levels, the last one 1x1.
    pub fn levels(&self) -> u32 {
        self.mip_views.len() as u32
    }

    /// The whole mip chain as an unfilterable-float 2D texture, for
    /// `textureLoad(hiz, coord, level)`.
    pub fn view(&self) -> &wgpu::TextureView {
        &self.view
    }

    /// Records the build of every level from `depth`, a Depth32Float view of this
    /// pyramid's size and sample count with TEXTURE_BINDING usage.
    ///
    /// One compute pass per level (levels 0 and 1 share the first): each pass reads the
    /// level the previous one wrote, and a pass boundary is where that read-after-write is
    /// synchronised for certain. With
    /// `q`'s timestamps, the first pass writes the start and the last one the end; every
    /// level's pass is counted.
    pub fn encode(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        depth: &wgpu::TextureView,
        q: PassQueries,
    ) {
        // Made per call: the depth view is the caller's and is replaced on resize.
        let fused = self.levels() >= 2;
        let mut entries = vec![
            wgpu::BindGroupEntry {
                binding: if self.samples > 1 { 3 } else { 0 },
                resource: wgpu::BindingResource::TextureView(depth),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::TextureView(&self.mip_views[0]),
            },
        ];
        if fused {
            entries.push(wgpu::BindGroupEntry {
                binding: 5,
                resource: wgpu::BindingResource::TextureView(&self.mip_views[1]),
            });
        }
        let copy_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sward.hiz.copy"),
            layout: &self.copy_layout,
            entries: &entries,
        });
        // The last pass: the fused copy itself when there are only levels 0 and 1.
        let last = if fused && self.levels() == 2 {
            0
        } else {
            self.levels() - 1
        };
        // The fused copy writes level 1 too: its dispatch covers level 1's texels.
        let passes = std::iter::once(0).chain(if fused { 2 } else { 1 }..self.levels());
        for level in passes {
            let (w, h) = self.level_size(if level == 0 && fused { 1 } else { level });
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(&format!("sward.hiz.level{level}")),
                timestamp_writes: q.compute_writes_part(level == 0, level == last),
            });
            q.begin(&mut pass);
            if level == 0 {
                pass.set_pipeline(&self.copy);
                pass.set_bind_group(0, &copy_group, &[]);
            } else {
                pass.set_pipeline(&self.downsample);
                pass.set_bind_group(0, &self.level_groups[level as usize - 1], &[]);
            }
            pass.dispatch_workgroups(w.div_ceil(TILE), h.div_ceil(TILE), 1);
            q.end(&mut pass);
        }
    }

    /// Reads one level back, row-major (blocking; for tests).
    pub fn read_level(&self, gpu: &Gpu, level: u32) -> Result<Vec<f32>> {
        if level >= self.levels() {
            return Err(Error::Invalid(format!(
                "depth pyramid level {level} does not exist: it has {} levels",
                self.levels()
            )));
        }
        let bytes = super::target::read_texels(
            gpu,
            wgpu::TexelCopyTextureInfo {
                texture: &self.texture,
                mip_level: level,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            self.level_size(level),
            "sward.hiz.readback",
        )?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
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
        let device = &gpu.device;
        let (w, h) = self.size();
        let size = w as u64 * h as u64 * self.samples as u64 * 4;
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
                multisampled_depth_entry(3),
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
            entry_point: Some("dump_samples"),
            compilation_options: Default::default(),
            cache: None,
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sward.hiz.dump_group"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 3,
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

    /// GPU memory of the pyramid (all levels, 4 bytes a texel).
    pub fn gpu_bytes(&self) -> u64 {
        (0..self.levels())
            .map(|level| {
                let (w, h) = self.level_size(level);
                w as u64 * h as u64 * 4
            })
            .sum()
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
