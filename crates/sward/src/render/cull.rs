//! The cull passes (`shaders/cull.wgsl`): patch boxes first (frustum and depth pyramid),
//! which also picks the patches the update steps and writes the indirect dispatches; then,
//! dispatched indirectly over the visible patches only, every blade, whose survivors go
//! into one visible list per level of detail with its own indirect draw; then, with grass
//! occlusion, the late pass over the same blades against a pyramid that holds the grass
//! drawn early (two-phase occlusion culling, see `cull.wgsl`). Every list comes out in the
//! same order whatever order the workgroups run in (`cull_order.wgsl`), so that a frame
//! draws the same pixels every time.

use crate::error::Result;
use crate::gpu::queries::PassQueries;
use crate::gpu::{read_buffer, Gpu};
use crate::shaders;
use crate::sim::layout::{
    CullCounters, CullParams, PatchDispatch, LOD_LEVELS, PATCH_SPHERE_STRIDE, SPHERES_ALL,
    WORKGROUP_SIZE,
};
use crate::sim::update::{compute_storage_entry, BladeBuffers};

/// Cull pipelines, their uniforms and the indirect-argument buffer the draw reads.
pub struct CullPass {
    reset: wgpu::ComputePipeline,
    patches: wgpu::ComputePipeline,
    finalize: wgpu::ComputePipeline,
    cull: wgpu::ComputePipeline,
    late: wgpu::ComputePipeline,
    /// The early and the late lists' offsets (`cull_order.wgsl`), and the pass that puts
    /// each drawn blade at its slot after either.
    order_early: wgpu::ComputePipeline,
    order_late: wgpu::ComputePipeline,
    order_scatter: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    bind_group: wgpu::BindGroup,
    dispatch_group: wgpu::BindGroup,
    /// The blade passes' second group: the seen flags.
    seen_group: wgpu::BindGroup,
    /// The uniforms (the grass vertex shader reads them too, for its morph).
    pub params: wgpu::Buffer,
    /// `CullCounters`: one draw_indexed_indirect block per level + counters.
    pub args: wgpu::Buffer,
    patch_count: u32,
}

fn bind_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    params: &wgpu::Buffer,
    args: &wgpu::Buffer,
    buffers: &BladeBuffers,
    (level0, pyramid): (&wgpu::TextureView, &wgpu::TextureView),
) -> wgpu::BindGroup {
    let buffer_entries = [
        &buffers.blades,
        &buffers.patches,
        &buffers.visible,
        args,
        &buffers.patch_lists,
    ];
    let mut entries = vec![wgpu::BindGroupEntry {
        binding: 0,
        resource: params.as_entire_binding(),
    }];
    entries.extend(
        buffer_entries
            .iter()
            .enumerate()
            .map(|(k, b)| wgpu::BindGroupEntry {
                binding: k as u32 + 1,
                resource: b.as_entire_binding(),
            }),
    );
    entries.push(wgpu::BindGroupEntry {
        binding: 7,
        resource: wgpu::BindingResource::TextureView(pyramid),
    });
    entries.push(wgpu::BindGroupEntry {
        binding: 8,
        resource: wgpu::BindingResource::TextureView(level0),
    });
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("sward.cull.bind_group"),
        layout,
        entries: &entries,
    })
}

impl CullPass {
    /// Builds the cull pipelines, their uniform and indirect-argument buffers and the bind
    /// groups over `buffers`; the occlusion test stays off until a depth pyramid is bound.
    pub fn new(gpu: &Gpu, buffers: &BladeBuffers) -> Self {
        let device = &gpu.device;
        let module = shaders::module(device, "cull.wgsl");
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.cull.layout"),
            entries: &[
                super::draw::read_storage(0, wgpu::ShaderStages::COMPUTE),
                compute_storage_entry(1, true),
                compute_storage_entry(2, true),
                compute_storage_entry(3, false),
                compute_storage_entry(4, false),
                compute_storage_entry(5, false),
                pyramid_entry(7),
                // Level 0: the depth buffer itself (a depth view binds as unfilterable
                // float) or, with MSAA, the pyramid's farthest-sample copy.
                pyramid_entry(8),
            ],
        });
        // The dispatch arguments are written by the patch pass only: the blade cull uses
        // the same buffer as its indirect argument, which may not be bound at the same time.
        // The broad phase's spheres ride along (8 storage buffers per stage in all, the
        // WebGPU default limit).
        let dispatch_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.cull.dispatch_layout"),
            entries: &[
                compute_storage_entry(0, false),
                compute_storage_entry(1, true),
                compute_storage_entry(2, false),
            ],
        });
        // The blade passes cannot bind `dispatch` (their indirect argument); their second
        // group holds the seen flags and the blades' rest tips (for the far levels' shading
        // waves), at bindings the patch step does not use.
        let seen_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.cull.seen_layout"),
            entries: &[
                compute_storage_entry(3, false),
                compute_storage_entry(4, true),
            ],
        });
        let seen_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sward.cull.seen_group"),
            layout: &seen_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: buffers.seen.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: buffers.states.as_entire_binding(),
                },
            ],
        });
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.cull.params"),
            size: std::mem::size_of::<CullParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM
                | wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let args = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.cull.indirect_args"),
            size: std::mem::size_of::<CullCounters>() as u64,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::INDIRECT
                | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        // Bound in place of the depth pyramid until `set_pyramid` (the test is off then).
        let no_pyramid = device
            .create_texture(&wgpu::TextureDescriptor {
                label: Some("sward.cull.no_pyramid"),
                size: wgpu::Extent3d {
                    width: 1,
                    height: 1,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::R32Float,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            })
            .create_view(&Default::default());
        let bind_group = bind_group(
            device,
            &layout,
            &params,
            &args,
            buffers,
            (&no_pyramid, &no_pyramid),
        );
        let dispatch_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sward.cull.dispatch_group"),
            layout: &dispatch_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: buffers.dispatch.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: buffers.spheres.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: buffers.patch_spheres.as_entire_binding(),
                },
            ],
        });
        let blade_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sward.cull.pipeline_layout"),
            bind_group_layouts: &[Some(&layout), Some(&seen_layout)],
            immediate_size: 0,
        });
        let patch_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sward.cull.patch_pipeline_layout"),
            bind_group_layouts: &[Some(&layout), Some(&dispatch_layout)],
            immediate_size: 0,
        });
        let make = |entry: &str, label: &str, layout: &wgpu::PipelineLayout| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(label),
                layout: Some(layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        Self {
            reset: make("reset", "sward.cull.reset", &patch_layout),
            patches: make("patches_main", "sward.cull.patches", &patch_layout),
            finalize: make("finalize", "sward.cull.finalize", &patch_layout),
            cull: make("main", "sward.cull.pipeline", &blade_layout),
            late: make("late", "sward.cull.late", &blade_layout),
            order_early: make("order_early", "sward.cull.order_early", &blade_layout),
            order_late: make("order_late", "sward.cull.order_late", &blade_layout),
            order_scatter: make("order_scatter", "sward.cull.order_scatter", &blade_layout),
            layout,
            bind_group,
            dispatch_group,
            seen_group,
            params,
            args,
            patch_count: buffers.patch_count,
        }
    }

    /// Binds a depth pyramid for the occlusion test: `level0` (the depth buffer, or with
    /// MSAA the pyramid's own level 0) and `pyramid`, levels 1 and up (`DepthPyramid::view`).
    /// Call when the pyramid or the depth buffer is created or resized.
    pub fn set_pyramid(
        &mut self,
        device: &wgpu::Device,
        buffers: &BladeBuffers,
        level0: &wgpu::TextureView,
        pyramid: &wgpu::TextureView,
    ) {
        self.bind_group = bind_group(
            device,
            &self.layout,
            &self.params,
            &self.args,
            buffers,
            (level0, pyramid),
        );
    }

    /// Writes this frame's camera and thresholds.
    pub fn prepare(&self, queue: &wgpu::Queue, params: &CullParams) {
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(params));
    }

    /// Records the patch step: reset, patch tests, then the indirect arguments. Must come
    /// before the update (which it picks the patches for) and the blade cull.
    pub fn encode_patches(&self, encoder: &mut wgpu::CommandEncoder, q: PassQueries) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("sward.cull.patches"),
            timestamp_writes: q.compute_writes(),
        });
        q.begin(&mut pass);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.set_bind_group(1, &self.dispatch_group, &[]);
        pass.set_pipeline(&self.reset);
        pass.dispatch_workgroups(1, 1, 1);
        if self.patch_count > 0 {
            pass.set_pipeline(&self.patches);
            pass.dispatch_workgroups(self.patch_count.div_ceil(WORKGROUP_SIZE), 1, 1);
        }
        pass.set_pipeline(&self.finalize);
        pass.dispatch_workgroups(1, 1, 1);
        q.end(&mut pass);
    }

    /// Records the blade cull, dispatched indirectly over the visible patches.
    pub fn encode_blades(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        dispatch: &wgpu::Buffer,
        q: PassQueries,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("sward.cull.blades"),
            timestamp_writes: q.compute_writes(),
        });
        q.begin(&mut pass);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.set_bind_group(1, &self.seen_group, &[]);
        pass.set_pipeline(&self.cull);
        let offset = std::mem::offset_of!(PatchDispatch, cull) as u64;
        pass.dispatch_workgroups_indirect(dispatch, offset);
        self.encode_order(&mut pass, &self.order_early, dispatch);
        q.end(&mut pass);
    }

    /// The lists in a fixed order (`cull_order.wgsl`): after the blade cull (or the late
    /// pass) has written each lane's level, `scan` (`order_early` or `order_late`) gives each
    /// chunk its offsets and the scatter puts each drawn blade at its slot.
    fn encode_order(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        scan: &wgpu::ComputePipeline,
        dispatch: &wgpu::Buffer,
    ) {
        pass.set_pipeline(scan);
        pass.dispatch_workgroups(1, 1, 1);
        pass.set_pipeline(&self.order_scatter);
        let offset = std::mem::offset_of!(PatchDispatch, order) as u64;
        pass.dispatch_workgroups_indirect(dispatch, offset);
    }

    /// Records the late pass (grass occlusion): the blades of the visible patches again,
    /// against the pyramid rebuilt after the early draw. Only with `TEST_GRASS_OCCLUSION`
    /// in this frame's uniforms.
    pub fn encode_late(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        dispatch: &wgpu::Buffer,
        q: PassQueries,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("sward.cull.late"),
            timestamp_writes: q.compute_writes(),
        });
        q.begin(&mut pass);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.set_bind_group(1, &self.seen_group, &[]);
        pass.set_pipeline(&self.late);
        let offset = std::mem::offset_of!(PatchDispatch, cull) as u64;
        pass.dispatch_workgroups_indirect(dispatch, offset);
        self.encode_order(&mut pass, &self.order_late, dispatch);
        q.end(&mut pass);
    }

    /// Reads the counters of the last frame back (blocking).
    pub fn read_counters(&self, gpu: &Gpu) -> Result<CullCounters> {
        let bytes = read_buffer(gpu, &self.args, std::mem::size_of::<CullCounters>() as u64)?;
        Ok(bytemuck::pod_read_unaligned(&bytes))
    }

    /// Reads the visible blade indices of the last frame back, per level, early blades
    /// first, then late ones (blocking).
    pub fn read_visible_levels(
        &self,
        gpu: &Gpu,
        buffers: &BladeBuffers,
    ) -> Result<[Vec<u32>; LOD_LEVELS]> {
        let counters = self.read_counters(gpu)?;
        let bytes = read_buffer(gpu, &buffers.visible, buffers.visible.size())?;
        let all: Vec<u32> = bytemuck::pod_collect_to_vec(&bytes);
        let region = buffers.region as usize;
        Ok(std::array::from_fn(|k| {
            // The late list starts at the first whole draw batch after the early one.
            let base = k * region;
            let early = counters.blades[k] as usize;
            let late = CullCounters::late_start(counters.blades[k]) as usize;
            let mut list = all[base..base + early].to_vec();
            list.extend_from_slice(
                &all[base + late..base + late + counters.late_blades[k] as usize],
            );
            list
        }))
    }

    /// Reads the broad phase's sphere list of every patch back (blocking), a long flat list
    /// from the shared pool: `None` where the patch tests every sphere (the pool was full;
    /// with the hierarchy, the list overflowed and the blades walk from the root). Lists of
    /// patches not stepped in the last frame are stale.
    pub fn read_patch_spheres(
        &self,
        gpu: &Gpu,
        buffers: &BladeBuffers,
    ) -> Result<Vec<Option<Vec<u32>>>> {
        let bytes = read_buffer(gpu, &buffers.patch_spheres, buffers.patch_spheres.size())?;
        let all: Vec<u32> = bytemuck::pod_collect_to_vec(&bytes);
        Ok(all
            .chunks(PATCH_SPHERE_STRIDE as usize)
            .take(buffers.patch_count as usize)
            .map(|c| match c[0] {
                SPHERES_ALL => None,
                n if n >= PATCH_SPHERE_STRIDE => {
                    let start = c[1] as usize;
                    all.get(start..start + n as usize).map(<[u32]>::to_vec)
                }
                n => Some(c[1..1 + n as usize].to_vec()),
            })
            .collect())
    }

    /// Reads the update lists of the last frame back (blocking): the chunks of patches with
    /// a collider near and of the others, each entry a chunk of
    /// [`crate::sim::layout::UPDATE_CHUNK`] blades with its rate bits, each list sorted
    /// (the patch step appends them in whatever order its invocations run).
    pub fn read_update_lists(&self, gpu: &Gpu, buffers: &BladeBuffers) -> Result<[Vec<u32>; 2]> {
        let bytes = read_buffer(gpu, &buffers.patch_lists, buffers.patch_lists.size())?;
        let all: Vec<u32> = bytemuck::pod_collect_to_vec(&bytes);
        let stride =
            crate::sim::update::list_chunks(buffers.patch_count, buffers.patch_size) as usize + 1;
        Ok([stride, 2 * stride].map(|start| {
            let count = all.get(start).copied().unwrap_or(0) as usize;
            let mut list = all
                .get(start + 1..start + 1 + count)
                .map(<[u32]>::to_vec)
                .unwrap_or_default();
            list.sort_unstable();
            list
        }))
    }

    /// Reads the visible blade indices of the last frame back, all levels (blocking).
    pub fn read_visible(&self, gpu: &Gpu, buffers: &BladeBuffers) -> Result<Vec<u32>> {
        Ok(self.read_visible_levels(gpu, buffers)?.concat())
    }
}

/// A texture the cull reads levels of the depth pyramid from (`textureLoad` only).
fn pyramid_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}
