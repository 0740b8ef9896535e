//! The far levels calibrated on the blades, by measurement (issue 27, point 1): the
//! billboards and the far ground stand for the blades beyond their reach and are lit with
//! the blades' own light model (`far_grass_light`, far_grass.wgsl, which a blade's shading
//! averaged over what a distant eye sees of a canopy), but through an atlas, card coverage
//! and a ground texture of their own, which need not average to it. Every frame, after its
//! grass is lit, one workgroup (`shaders/far_gain_common.wgsl`) compares what the cards and
//! the ground between them show just beyond the blades' reach ([`RING`]) with what the
//! model says at the same points, before the fog, and keeps the ratio per colour channel
//! as the gain both are lit with in the next frame. Their radiance is proportional to the
//! gain they were lit with, so a measurement corrects it in one step; later ones move it
//! [`BLEND`] of the way, so a change of light settles in a few frames without flicker. The
//! gain lives in the far state beside the gusts' bend (`terrain::TerrainPass::waves`, from
//! word [`GAIN_WORD`]); until measured it is 1. A host's pass (`embed`, `prepare` /
//! `render`) is not measured: its cards keep the gain 1.
//!
//! The prairie (4x MSAA, lit deferred), before the gains: the cards at 28-50 m read 20-24
//! levels brighter than the blades there (`tests/far_field.rs`).

use glam::Vec3;

use crate::error::Result;
use crate::gpu::queries::PassQueries;
use crate::gpu::Gpu;

/// Columns and rows of the frame's pixels the measurement looks at (2,048 samples: 8 per
/// invocation of its one workgroup).
pub const GRID: (u32, u32) = (64, 32);

/// How far a frame's measurement moves a gain (after the first, taken as it is).
pub const BLEND: f32 = 0.25;

/// The ring measured, as multiples of the blades' reach: the far levels' first metres.
pub const RING: (f32, f32) = (1.0, 1.5);

/// The smallest and largest gain kept (twin of `GAIN_MIN`, `GAIN_MAX`).
pub const GAIN_RANGE: (f32, f32) = (0.25, 4.0);

/// The fewest pixels a measurement needs (twin of `GAIN_MIN_SAMPLES`).
pub const MIN_SAMPLES: f32 = 16.0;

/// Word of the far state where the gain starts (rgb, then 1 once measured).
pub const GAIN_WORD: usize = 4;

/// Bytes of the far state.
pub const STATE_BYTES: u64 = 32;

/// One pixel's terms: its radiance without the fog and the model's, both weighed by
/// (1 − f) (twin of `gain_terms`).
pub fn gain_terms(actual: Vec3, sky: Vec3, f: f32, model: Vec3) -> (Vec3, Vec3) {
    let clear = (1.0 - f).clamp(0.0, 1.0);
    ((actual - f * sky).max(Vec3::ZERO), model * clear)
}

/// The gain after a frame's sums over `count` pixels (twin of `next_gain`): `previous` is
/// (the gain the pixels were lit with, measured).
pub fn next_gain(
    shown: Vec3,
    model: Vec3,
    count: f32,
    previous: (Vec3, bool),
    blend: f32,
) -> (Vec3, bool) {
    if count < MIN_SAMPLES || shown.min_element() <= 1e-6 || model.min_element() <= 1e-6 {
        return previous;
    }
    let old = if previous.1 { previous.0 } else { Vec3::ONE };
    let aim = (old * model / shown).clamp(Vec3::splat(GAIN_RANGE.0), Vec3::splat(GAIN_RANGE.1));
    if !previous.1 {
        return (aim, true);
    }
    (old.lerp(aim, blend), true)
}

impl super::Renderer {
    /// The far levels' light gain the last frame measured (rgb), `None` before the first
    /// measurement (blocking read-back; for statistics and tests).
    pub fn far_gain(&self, gpu: &Gpu) -> Result<Option<Vec3>> {
        let bytes = crate::gpu::read_buffer(gpu, self.draw.waves_buffer(), STATE_BYTES)?;
        let words: &[f32] = bytemuck::cast_slice(&bytes);
        let g = &words[GAIN_WORD..GAIN_WORD + 4];
        Ok((g[3] > 0.5).then(|| Vec3::new(g[0], g[1], g[2])))
    }
}

/// The measuring pass: a pipeline per sample count (one sample, multisampled), its
/// parameters and the bind group of the frame's views (made again only when they change).
pub struct FarGainPass {
    device: wgpu::Device,
    queue: wgpu::Queue,
    params: wgpu::Buffer,
    pipelines: Vec<(u32, (wgpu::BindGroupLayout, wgpu::ComputePipeline))>,
    group: Option<(wgpu::TextureView, wgpu::TextureView, u32, wgpu::BindGroup)>,
}

/// The far gain's parameters (`GainParams`).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct GainParams {
    ring: [f32; 4],
    grid: [u32; 4],
}

/// What a frame's measurement reads.
pub struct GainInputs<'a> {
    /// The frame's uniforms (`Frame`).
    pub frame: &'a wgpu::Buffer,
    /// The terrain's height uniforms and grid.
    pub terrain: (&'a wgpu::Buffer, &'a wgpu::Buffer),
    /// The far state (gusts' bend and gain), written.
    pub state: &'a wgpu::Buffer,
    /// The lit radiance, resolved (one sample).
    pub color: &'a wgpu::TextureView,
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
            group: None,
        }
    }

    /// Writes the ring (metres, from the blades' reach `reach`) and the tallest blade.
    pub fn prepare(&self, reach: f32, tallest: f32) {
        let p = GainParams {
            ring: [RING.0 * reach, RING.1 * reach, tallest, BLEND],
            grid: [GRID.0, GRID.1, 0, 0],
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
        let fits = self.group.as_ref().is_some_and(|(c, d, s, _)| {
            c == inputs.color && d == inputs.depth && *s == inputs.samples
        });
        if !fits {
            // Dropped first: the old views are not held beside the new ones.
            self.group = None;
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
                ],
            });
            self.group = Some((
                inputs.color.clone(),
                inputs.depth.clone(),
                inputs.samples,
                group,
            ));
        }
        let pipeline = self.pipeline(inputs.samples).1.clone();
        let Some((_, _, _, group)) = &self.group else {
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

/// One pixel of the probe: its radiance, the fog's amount and colour, the model's.
#[derive(Clone, Copy, Debug)]
pub struct GainPixel {
    /// The frame's (fogged) radiance.
    pub actual: Vec3,
    /// The fog's colour.
    pub sky: Vec3,
    /// The fog's amount, 0 to 1.
    pub f: f32,
    /// The model's radiance (unfogged, without the gain).
    pub model: Vec3,
}

/// What the probe returns: the sums (shown, model), the next gain and whether it is
/// measured, and the gain the level would light with (`far_gain`).
pub type ProbeResult = (Vec3, Vec3, (Vec3, bool), Vec3);

/// Runs the WGSL arithmetic (`far_gain_math.wgsl`) over `pixels` from `previous`, on the
/// GPU, for the test against [`gain_terms`] and [`next_gain`].
pub fn probe(
    gpu: &Gpu,
    pixels: &[GainPixel],
    previous: (Vec3, bool),
    blend: f32,
) -> Result<ProbeResult> {
    let mut flat: Vec<[f32; 12]> = pixels
        .iter()
        .map(|s| {
            [
                s.actual.x, s.actual.y, s.actual.z, s.f, s.sky.x, s.sky.y, s.sky.z, 0.0, s.model.x,
                s.model.y, s.model.z, 0.0,
            ]
        })
        .collect();
    // A binding is never empty: an empty list is one pixel the probe does not read.
    if flat.is_empty() {
        flat.push([0.0; 12]);
    }
    let prev: [f32; 8] = [
        previous.0.x,
        previous.0.y,
        previous.0.z,
        if previous.1 { 1.0 } else { 0.0 },
        blend,
        pixels.len() as f32,
        0.0,
        0.0,
    ];
    let out = crate::gpu::run_vec4_probe(
        gpu,
        "sward.far_gain_probe",
        "far_gain_probe.wgsl",
        &[bytemuck::cast_slice(&flat), bytemuck::cast_slice(&prev)],
        4,
    )?;
    let v = |a: [f32; 4]| Vec3::new(a[0], a[1], a[2]);
    Ok((
        v(out[0]),
        v(out[1]),
        (v(out[2]), out[2][3] > 0.5),
        v(out[3]),
    ))
}
