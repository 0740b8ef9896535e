//! The far gain's measuring pass (`shaders/far_gain.wgsl`, `far_gain_msaa.wgsl`): its
//! pipelines, its parameters and the bind groups of the frame's views. What it measures
//! and how the gains follow is in [`super::far_gain`].

use super::far_gain::{far_ring, near_ring, near_ring_marked, BLEND, GRID};
use crate::gpu::queries::PassQueries;
use crate::gpu::Gpu;

/// The measuring pass: a pipeline per sample count (one sample, multisampled), its
/// parameters and the bind groups of the frame's views (made again only when they change;
/// two kept, as the TAA's history alternates between two targets).
pub struct FarGainPass {
    device: wgpu::Device,
    queue: wgpu::Queue,
    params: wgpu::Buffer,
    pipelines: Vec<(u32, (wgpu::BindGroupLayout, wgpu::ComputePipeline))>,
    groups: Vec<ViewGroup>,
}

/// A bind group with the views it was made for: the radiance, what is shown, the depth and
/// its samples.
type ViewGroup = (
    (wgpu::TextureView, wgpu::TextureView),
    wgpu::TextureView,
    u32,
    wgpu::BindGroup,
);

/// Bind groups of views the pass keeps (the TAA's two history targets).
const KEPT_GROUPS: usize = 2;

/// The far gain's parameters (`GainParams`).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct GainParams {
    ring: [f32; 4],
    grid: [u32; 4],
    near: [f32; 4],
    contrast: [f32; 4],
}

/// What a frame's measurement reads.
pub struct GainInputs<'a> {
    /// The frame's uniforms (`Frame`).
    pub frame: &'a wgpu::Buffer,
    /// The terrain's height uniforms and grid.
    pub terrain: (&'a wgpu::Buffer, &'a wgpu::Buffer),
    /// The far state (gusts' bend and gain), written.
    pub state: &'a wgpu::Buffer,
    /// The lit radiance, resolved (one sample): the far ring is measured there.
    pub color: &'a wgpu::TextureView,
    /// What the frame shows (the TAA's history it was blended into, else `color`): the
    /// near ring's blades are measured there.
    pub shown: &'a wgpu::TextureView,
    /// The frame's depth (`samples` per pixel).
    pub depth: &'a wgpu::TextureView,
    /// Samples per pixel of `depth`.
    pub samples: u32,
    /// The light's group.
    pub light: &'a wgpu::BindGroup,
}

impl FarGainPass {
    /// The pass, with no pipeline built yet (one is built for the first frame of each
    /// sample count).
    pub fn new(gpu: &Gpu) -> Self {
        let device = &gpu.device;
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.far_gain.params"),
            size: std::mem::size_of::<GainParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self {
            device: device.clone(),
            queue: gpu.queue.clone(),
            params,
            pipelines: Vec::new(),
            groups: Vec::new(),
        }
    }

    /// Writes the rings (metres, from the blades' reach `reach` and the camera's `height`
    /// over the ground, [`far_ring`], [`near_ring`]; [`near_ring_marked`] for the blades
    /// when `marked`, the frame's grass lit deferred, which marks their share of each pixel),
    /// the tallest blade, the frame's number (which pixel of each grid cell is measured) and
    /// whether cards are drawn (the contrast gain is measured only then).
    pub fn prepare(
        &self,
        (reach, height): (f32, f32),
        tallest: f32,
        frame: u32,
        (cards, marked): (bool, bool),
    ) {
        let contrast = near_ring(reach, height);
        let near = if marked {
            near_ring_marked(reach, height)
        } else {
            contrast
        };
        let far = far_ring(reach, height);
        let flag = |on: bool| if on { 1.0 } else { 0.0 };
        let p = GainParams {
            ring: [far.0, far.1, tallest, BLEND],
            grid: [GRID.0, GRID.1, frame, 0],
            near: [near.0, near.1, flag(cards), flag(marked)],
            contrast: [contrast.0, contrast.1, 0.0, 0.0],
        };
        self.queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&p));
    }

    fn pipeline(&mut self, samples: u32) -> &(wgpu::BindGroupLayout, wgpu::ComputePipeline) {
        let at = match self.pipelines.iter().position(|(s, _)| *s == samples) {
            Some(i) => i,
            None => {
                let built = self.build(samples);
                self.pipelines.push((samples, built));
                self.pipelines.len() - 1
            }
        };
        &self.pipelines[at].1
    }

    /// The layout of the frame's group and the pipeline, for depth of `samples` samples
    /// (group 1 is the light's, whose layout is made by `light::layout`).
    fn build(&self, samples: u32) -> (wgpu::BindGroupLayout, wgpu::ComputePipeline) {
        let device = &self.device;
        let c = wgpu::ShaderStages::COMPUTE;
        let buffer = |binding, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: c,
            ty: wgpu::BindingType::Buffer {
                ty,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let storage = |read_only| wgpu::BufferBindingType::Storage { read_only };
        let texture = |binding, sample_type, multisampled| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: c,
            ty: wgpu::BindingType::Texture {
                sample_type,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled,
            },
            count: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.far_gain.layout"),
            entries: &[
                buffer(0, wgpu::BufferBindingType::Uniform),
                buffer(1, storage(true)),
                buffer(2, storage(true)),
                buffer(3, storage(false)),
                buffer(4, wgpu::BufferBindingType::Uniform),
                texture(
                    5,
                    wgpu::TextureSampleType::Float { filterable: false },
                    false,
                ),
                texture(6, wgpu::TextureSampleType::Depth, samples > 1),
                texture(
                    7,
                    wgpu::TextureSampleType::Float { filterable: false },
                    false,
                ),
            ],
        });
        let light = super::light::layout(device);
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sward.far_gain.pipeline_layout"),
            bind_group_layouts: &[Some(&layout), Some(&light)],
            immediate_size: 0,
        });
        let shader = if samples > 1 {
            "far_gain_msaa.wgsl"
        } else {
            "far_gain.wgsl"
        };
        let module = crate::shaders::module(device, shader);
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("sward.far_gain"),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some("measure"),
            compilation_options: Default::default(),
            cache: None,
        });
        (layout, pipeline)
    }

    /// Records the measurement of this frame into `encoder`.
    pub fn encode(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &GainInputs,
        q: PassQueries,
    ) {
        let fits = |((c, v), d, s, _): &ViewGroup| {
            c == inputs.color && v == inputs.shown && d == inputs.depth && *s == inputs.samples
        };
        if !self.groups.iter().any(fits) {
            // A frame of another size or sample count holds views no longer drawn: they
            // are dropped, not held beside the new ones.
            self.groups
                .retain(|((c, _), d, s, _)| *s == inputs.samples && d == inputs.depth && c == inputs.color);
            if self.groups.len() >= KEPT_GROUPS {
                self.groups.remove(0);
            }
            let layout = self.pipeline(inputs.samples).0.clone();
            let group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("sward.far_gain.group"),
                layout: &layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: inputs.frame.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: inputs.terrain.0.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: inputs.terrain.1.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: inputs.state.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 4,
                        resource: self.params.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 5,
                        resource: wgpu::BindingResource::TextureView(inputs.color),
                    },
                    wgpu::BindGroupEntry {
                        binding: 6,
                        resource: wgpu::BindingResource::TextureView(inputs.depth),
                    },
                    wgpu::BindGroupEntry {
                        binding: 7,
                        resource: wgpu::BindingResource::TextureView(inputs.shown),
                    },
                ],
            });
            self.groups.push((
                (inputs.color.clone(), inputs.shown.clone()),
                inputs.depth.clone(),
                inputs.samples,
                group,
            ));
        }
        let pipeline = self.pipeline(inputs.samples).1.clone();
        let Some((_, _, _, group)) = self.groups.iter().find(|g| fits(g)) else {
            return;
        };
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("sward.far_gain"),
            timestamp_writes: q.compute_writes(),
        });
        q.begin(&mut pass);
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.set_bind_group(1, inputs.light, &[]);
        pass.dispatch_workgroups(1, 1, 1);
        q.end(&mut pass);
    }
}
