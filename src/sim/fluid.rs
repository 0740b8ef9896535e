//! The Stable-Fluids wind solver on the GPU (CWD-Sim Eq. 4–10 after Dobryakov's WebGL fluid,
//! Stam's solver as the prairie thesis lays it out): a 2D cell-centred velocity grid over the
//! terrain, one step per frame, each stage its own timed compute pass:
//!
//! 1. `splat` – global force, AGC arrows, downwash; obstacle cells take the collider velocity
//! 2. `vorticity` – curl, then vorticity confinement
//! 3. `diffuse` – Jacobi viscous diffusion (empty pass when ν = 0)
//! 4. `divergence`
//! 5. `pressure` – Jacobi iterations, warm-started from the last frame when configured
//! 6. `gradient` – subtract the pressure gradient
//! 7. `advect` – semi-Lagrangian self-advection with dissipation
//!
//! The grid lives in storage buffers (`array<vec2<f32>>`, row-major, x fastest) rather than
//! textures so that the blade update can read it with plain indexing and so that it works on
//! adapters without filterable float textures. Every step ends in the same buffer
//! ([`FluidSolver::velocity`]), so other passes bind it once. The CPU twin of every pass is
//! [`crate::sim::reference::fluid::FluidCpu`].

use super::update::{compute_storage_entry, uniform_entry};
use super::wind_layout::{
    ArrowGpu, FluidForces, FluidParams, ObstacleGpu, FLUID_WORKGROUP, MAX_ARROWS, MAX_OBSTACLES,
};
use crate::error::{Error, Result};
use crate::gpu::{map_and_read, read_buffer, Gpu};
use crate::scene::{Boundary, Fluid};
use crate::shaders;

pub use super::reference::fluid::{divergence_l2, face_divergence_l2, sample_velocity};

/// Smallest grid side the solver accepts (one workgroup; the stencils need a few cells).
pub const MIN_RESOLUTION: u32 = 8;
/// Largest grid side the solver accepts (4 Mi cells, 32 MiB per velocity buffer).
pub const MAX_RESOLUTION: u32 = 2048;

/// The passes of one step, in the order of their timestamp pairs.
pub const FLUID_PASSES: [&str; 7] = [
    "splat",
    "vorticity",
    "diffuse",
    "divergence",
    "pressure",
    "gradient",
    "advect",
];

/// Labels of the compute passes, in `FLUID_PASSES` order.
const PASS_LABELS: [&str; FLUID_PASSES.len()] = [
    "sward.fluid.splat",
    "sward.fluid.vorticity",
    "sward.fluid.diffuse",
    "sward.fluid.divergence",
    "sward.fluid.pressure",
    "sward.fluid.gradient",
    "sward.fluid.advect",
];

/// How the solver is set up; fixed for the life of a [`FluidSolver`].
#[derive(Clone, Debug, PartialEq)]
pub struct FluidConfig {
    /// Cells per side.
    pub resolution: u32,
    /// Cell side h in metres.
    pub cell_size: f32,
    /// World x, z of the grid's outer corner (cell (0, 0)'s corner).
    pub origin: [f32; 2],
    pub pressure_iterations: u32,
    /// Start the pressure solve from the last step's pressure instead of 0.
    pub warm_start: bool,
    /// Vorticity confinement λ (0 = off).
    pub vorticity: f32,
    /// Velocity dissipation per second (v /= 1 + dissipation · Δt after advection).
    pub dissipation: f32,
    /// Kinematic viscosity ν in m²/s (0 = no diffusion pass work).
    pub viscosity: f32,
    pub diffusion_iterations: u32,
    pub boundary: Boundary,
}

impl FluidConfig {
    /// The grid of a scene: it covers the square terrain centred on 0.
    pub fn from_scene(fluid: &Fluid, terrain_size: f32) -> Self {
        let resolution = fluid.resolution;
        Self {
            resolution,
            cell_size: terrain_size / resolution.max(1) as f32,
            origin: [-0.5 * terrain_size, -0.5 * terrain_size],
            pressure_iterations: fluid.pressure_iterations,
            warm_start: fluid.warm_start,
            vorticity: fluid.vorticity,
            dissipation: fluid.dissipation,
            viscosity: fluid.viscosity,
            diffusion_iterations: fluid.diffusion_iterations,
            boundary: fluid.boundary,
        }
    }

    /// Cells in the grid.
    pub fn cells(&self) -> usize {
        self.resolution as usize * self.resolution as usize
    }

    /// Whether the diffusion pass does any work.
    pub fn diffuses(&self) -> bool {
        self.viscosity > 0.0 && self.diffusion_iterations > 0
    }

    /// The id the shaders switch on (`FLUID_CLOSED` / `FLUID_OPEN` / `FLUID_PERIODIC`).
    pub fn boundary_id(&self) -> u32 {
        boundary_id(self.boundary)
    }

    /// Checks the values a scene or a caller can get wrong, before anything is allocated.
    pub fn validate(&self) -> Result<()> {
        if !(MIN_RESOLUTION..=MAX_RESOLUTION).contains(&self.resolution) {
            return Err(Error::Invalid(format!(
                "fluid.resolution = {} is out of range: allowed {MIN_RESOLUTION} <= resolution \
                 <= {MAX_RESOLUTION} cells per side",
                self.resolution
            )));
        }
        if !(self.cell_size.is_finite() && self.cell_size > 0.0) {
            return Err(Error::Invalid(format!(
                "fluid cell size {} m is not a positive number (terrain size / resolution)",
                self.cell_size
            )));
        }
        let nonneg = [
            ("fluid.vorticity", self.vorticity),
            ("fluid.dissipation", self.dissipation),
            ("fluid.viscosity", self.viscosity),
        ];
        for (name, value) in nonneg {
            if !(value.is_finite() && value >= 0.0) {
                return Err(Error::Invalid(format!(
                    "{name} = {value} is out of range: allowed a finite value >= 0"
                )));
            }
        }
        Ok(())
    }

    /// The uniforms of one step. The GPU passes and the CPU twin both take their constants
    /// from here, so they start from bit-identical values (1/h and νΔt/h² included).
    pub fn params(&self, dt: f32, forces: &FluidForces) -> FluidParams {
        let h = self.cell_size;
        FluidParams {
            origin_cell: [self.origin[0], self.origin[1], h, 1.0 / h],
            global_downwash: [
                forces.global[0],
                forces.global[1],
                forces.downwash[2],
                forces.downwash[3],
            ],
            downwash_pos: [forces.downwash[0], forces.downwash[1], 0.0, 0.0],
            resolution: self.resolution,
            dt,
            vorticity: self.vorticity,
            dissipation: self.dissipation,
            diffusion_alpha: self.viscosity * dt / (h * h),
            boundary: self.boundary_id(),
            arrow_count: forces.arrows.len().min(MAX_ARROWS) as u32,
            obstacle_count: forces.obstacles.len().min(MAX_OBSTACLES) as u32,
        }
    }
}

/// The shader id of a boundary mode.
pub fn boundary_id(boundary: Boundary) -> u32 {
    match boundary {
        Boundary::Closed => 0,
        Boundary::Open => 1,
        Boundary::Periodic => 2,
    }
}

/// A snapshot of the solver's grids on the host (read-back or the CPU twin).
#[derive(Clone, Debug, PartialEq)]
pub struct FluidState {
    pub resolution: u32,
    pub cell_size: f32,
    pub origin: [f32; 2],
    /// (u, v) in m/s per cell, row-major, x fastest: the velocity after the last step.
    pub velocity: Vec<[f32; 2]>,
    /// Pressure of the last solve (in m²/s: the Δt/ρ factor is folded in).
    pub pressure: Vec<f32>,
    /// Divergence (1/s) of the velocity that entered the last pressure solve.
    pub divergence: Vec<f32>,
}

impl FluidState {
    /// Velocity of cell (i, j).
    pub fn at(&self, i: u32, j: u32) -> [f32; 2] {
        self.velocity[(j * self.resolution + i) as usize]
    }

    /// Largest speed in the grid, in m/s.
    pub fn max_speed(&self) -> f32 {
        self.velocity
            .iter()
            .map(|v| (v[0] * v[0] + v[1] * v[1]).sqrt())
            .fold(0.0, f32::max)
    }
}

/// How a binding of a fluid kernel is used.
#[derive(Clone, Copy)]
enum Slot {
    Uniform,
    Read,
    Write,
}

/// One compute kernel: its layout and pipeline.
struct Kernel {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

fn bind_group_layout(device: &wgpu::Device, name: &str, slots: &[Slot]) -> wgpu::BindGroupLayout {
    let entries: Vec<_> = slots
        .iter()
        .enumerate()
        .map(|(i, slot)| match slot {
            Slot::Uniform => uniform_entry(i as u32, wgpu::ShaderStages::COMPUTE),
            Slot::Read => compute_storage_entry(i as u32, true),
            Slot::Write => compute_storage_entry(i as u32, false),
        })
        .collect();
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(&format!("sward.fluid.{name}.layout")),
        entries: &entries,
    })
}

fn pipeline(
    device: &wgpu::Device,
    name: &str,
    module: &wgpu::ShaderModule,
    entry: &str,
    layout: &wgpu::BindGroupLayout,
) -> wgpu::ComputePipeline {
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(&format!("sward.fluid.{name}.pipeline_layout")),
        bind_group_layouts: &[Some(layout)],
        immediate_size: 0,
    });
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(&format!("sward.fluid.{name}.pipeline")),
        layout: Some(&pipeline_layout),
        module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    })
}

impl Kernel {
    fn new(device: &wgpu::Device, name: &str, slots: &[Slot]) -> Self {
        let module = shaders::module(device, &format!("fluid_{name}.wgsl"));
        let layout = bind_group_layout(device, name, slots);
        let pipeline = pipeline(device, name, &module, "main", &layout);
        Self { layout, pipeline }
    }

    fn bind(
        &self,
        device: &wgpu::Device,
        label: &str,
        buffers: &[&wgpu::Buffer],
    ) -> wgpu::BindGroup {
        let entries: Vec<_> = buffers
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: b.as_entire_binding(),
            })
            .collect();
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(&format!("sward.fluid.{label}.bind_group")),
            layout: &self.layout,
            entries: &entries,
        })
    }
}

/// Timestamp queries of the fluid passes and their read-back buffers.
struct FluidTimer {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    staging: wgpu::Buffer,
    period_ns: f32,
}

const QUERY_COUNT: u32 = FLUID_PASSES.len() as u32 * 2;

impl FluidTimer {
    fn new(gpu: &Gpu) -> Option<Self> {
        if !gpu.timestamps {
            return None;
        }
        let size = QUERY_COUNT as u64 * 8;
        Some(Self {
            queries: gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("sward.fluid.timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: QUERY_COUNT,
            }),
            resolve: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("sward.fluid.timestamps.resolve"),
                size,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            staging: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("sward.fluid.timestamps.staging"),
                size,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            }),
            period_ns: gpu.queue.get_timestamp_period(),
        })
    }
}

/// The bind groups of one step. Velocity buffers are `vel[0]` (the public, final one) and
/// two scratch buffers; which scratch buffer holds what depends only on the configuration
/// (diffusion on/off and the parity of its iterations), so all groups are made once.
struct Groups {
    splat: wgpu::BindGroup,
    vorticity: wgpu::BindGroup,
    /// Iteration 0 (start → vel[1]), then odd (vel[1] → vel[0]) and even (vel[0] → vel[1]).
    diffuse: Option<[wgpu::BindGroup; 3]>,
    divergence: wgpu::BindGroup,
    /// Jacobi pressure[0] → pressure[1] and pressure[1] → pressure[0].
    pressure: [wgpu::BindGroup; 2],
    /// Gradient with the final pressure in pressure[0] or pressure[1].
    gradient: [wgpu::BindGroup; 2],
    advect: wgpu::BindGroup,
}

/// The GPU wind solver: owns its pipelines, grids, uniforms and timestamp queries.
pub struct FluidSolver {
    config: FluidConfig,
    params: wgpu::Buffer,
    arrows: wgpu::Buffer,
    obstacles: wgpu::Buffer,
    velocity: [wgpu::Buffer; 3],
    pressure: [wgpu::Buffer; 2],
    divergence: wgpu::Buffer,
    // Only bound, never read back; held so the struct visibly owns every grid it uses.
    _curl: wgpu::Buffer,
    _solid: wgpu::Buffer,
    splat: Kernel,
    vorticity: Kernel,
    confine: wgpu::ComputePipeline,
    diffuse: Kernel,
    divergence_kernel: Kernel,
    pressure_kernel: Kernel,
    gradient: Kernel,
    advect: Kernel,
    groups: Groups,
    /// Which pressure buffer holds the latest solve (the warm start of the next one).
    pressure_current: usize,
    workgroups: u32,
    timer: Option<FluidTimer>,
}

impl FluidSolver {
    /// Builds the solver after checking the grid against the range and the device limits;
    /// nothing is allocated when a check fails.
    pub fn new(gpu: &Gpu, config: &FluidConfig) -> Result<Self> {
        config.validate()?;
        let n = config.resolution;
        let what = format!("a fluid grid of {n}x{n} cells");
        // check_storage's own hint is about blades; say what to change for the grid.
        gpu.check_storage(&what, config.cells() as u64 * 8)
            .map_err(|e| {
                Error::Limits(format!("{e}; for the wind grid, lower fluid.resolution"))
            })?;
        let workgroups = n.div_ceil(FLUID_WORKGROUP);
        gpu.check_dispatch(&what, workgroups)?;

        let device = &gpu.device;
        let cells = config.cells() as u64;
        let grid = |label: &str, bytes_per_cell: u64| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(&format!("sward.fluid.{label}")),
                size: cells * bytes_per_cell,
                // COPY_SRC for read-back, COPY_DST for `write_velocity` and the pressure
                // clear of a cold start. New buffers are zeroed by wgpu: the air starts still.
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_SRC
                    | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let velocity = [
            grid("velocity", 8),
            grid("velocity_scratch_a", 8),
            grid("velocity_scratch_b", 8),
        ];
        let pressure = [grid("pressure_a", 4), grid("pressure_b", 4)];
        let divergence = grid("divergence", 4);
        let curl = grid("curl", 4);
        let solid = grid("solid", 4);
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.fluid.params"),
            size: std::mem::size_of::<FluidParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        // Full-size lists: storage bindings may not be empty, and the counts in the
        // uniforms say how many entries are live.
        let arrows = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.fluid.arrows"),
            size: (MAX_ARROWS * std::mem::size_of::<ArrowGpu>()) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let obstacles = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.fluid.obstacles"),
            size: (MAX_OBSTACLES * std::mem::size_of::<ObstacleGpu>()) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });

        use Slot::{Read, Uniform, Write};
        let splat = Kernel::new(device, "splat", &[Uniform, Read, Read, Read, Write, Write]);
        // Curl and confinement share one module and one layout (the curl is written by the
        // first entry point and read by the second, so it is bound read-write to both).
        let vorticity_module = shaders::module(device, "fluid_vorticity.wgsl");
        let vorticity_layout =
            bind_group_layout(device, "vorticity", &[Uniform, Read, Write, Write, Read]);
        let vorticity = Kernel {
            pipeline: pipeline(
                device,
                "curl",
                &vorticity_module,
                "compute_curl",
                &vorticity_layout,
            ),
            layout: vorticity_layout,
        };
        let confine = pipeline(
            device,
            "confine",
            &vorticity_module,
            "confine",
            &vorticity.layout,
        );
        let diffuse = Kernel::new(device, "diffuse", &[Uniform, Read, Read, Write, Read]);
        let divergence_kernel = Kernel::new(device, "divergence", &[Uniform, Read, Write, Read]);
        let pressure_kernel = Kernel::new(device, "pressure", &[Uniform, Read, Read, Write, Read]);
        let gradient = Kernel::new(device, "gradient", &[Uniform, Read, Read, Write, Read]);
        let advect = Kernel::new(device, "advect", &[Uniform, Read, Write, Read]);

        // Where the velocity is after each stage: splat vel[0] → vel[1], vorticity
        // vel[1] → vel[2], diffusion ping-pongs vel[1] / vel[0] from vel[2], the gradient
        // writes the scratch buffer the projected input is not in, advection ends in vel[0].
        let projected_in = result_of_diffusion(config);
        let projected_out = if projected_in == 1 { 2 } else { 1 };
        let v = &velocity;
        let diffuse_groups = config.diffuses().then(|| {
            [
                diffuse.bind(
                    device,
                    "diffuse.first",
                    &[&params, &v[2], &v[2], &v[1], &solid],
                ),
                diffuse.bind(
                    device,
                    "diffuse.odd",
                    &[&params, &v[2], &v[1], &v[0], &solid],
                ),
                diffuse.bind(
                    device,
                    "diffuse.even",
                    &[&params, &v[2], &v[0], &v[1], &solid],
                ),
            ]
        });
        let groups = Groups {
            splat: splat.bind(
                device,
                "splat",
                &[&params, &arrows, &obstacles, &v[0], &v[1], &solid],
            ),
            vorticity: vorticity.bind(device, "vorticity", &[&params, &v[1], &curl, &v[2], &solid]),
            diffuse: diffuse_groups,
            divergence: divergence_kernel.bind(
                device,
                "divergence",
                &[&params, &v[projected_in], &divergence, &solid],
            ),
            pressure: [
                pressure_kernel.bind(
                    device,
                    "pressure.a_to_b",
                    &[&params, &divergence, &pressure[0], &pressure[1], &solid],
                ),
                pressure_kernel.bind(
                    device,
                    "pressure.b_to_a",
                    &[&params, &divergence, &pressure[1], &pressure[0], &solid],
                ),
            ],
            gradient: [
                gradient.bind(
                    device,
                    "gradient.a",
                    &[
                        &params,
                        &v[projected_in],
                        &pressure[0],
                        &v[projected_out],
                        &solid,
                    ],
                ),
                gradient.bind(
                    device,
                    "gradient.b",
                    &[
                        &params,
                        &v[projected_in],
                        &pressure[1],
                        &v[projected_out],
                        &solid,
                    ],
                ),
            ],
            advect: advect.bind(
                device,
                "advect",
                &[&params, &v[projected_out], &v[0], &solid],
            ),
        };

        Ok(Self {
            config: config.clone(),
            params,
            arrows,
            obstacles,
            velocity,
            pressure,
            divergence,
            _curl: curl,
            _solid: solid,
            splat,
            vorticity,
            confine,
            diffuse,
            divergence_kernel,
            pressure_kernel,
            gradient,
            advect,
            groups,
            pressure_current: 0,
            workgroups,
            timer: FluidTimer::new(gpu),
        })
    }

    /// The velocity grid after the last step: `array<vec2<f32>>`, resolution² cells,
    /// STORAGE | COPY_SRC | COPY_DST. Always the same buffer object.
    pub fn velocity(&self) -> &wgpu::Buffer {
        &self.velocity[0]
    }

    pub fn config(&self) -> &FluidConfig {
        &self.config
    }

    /// Bytes of GPU memory the solver's buffers hold.
    pub fn gpu_bytes(&self) -> u64 {
        let grids: u64 = self
            .velocity
            .iter()
            .chain(self.pressure.iter())
            .chain([&self.divergence, &self._curl, &self._solid])
            .map(|b| b.size())
            .sum();
        grids + self.params.size() + self.arrows.size() + self.obstacles.size()
    }

    /// Takes the scene's solver settings for the next steps (the panel edits them live).
    /// Returns false, changing nothing, when the change needs a new solver: another grid
    /// resolution or terrain size, or diffusion switched on or off (its bind groups exist
    /// only when it runs).
    pub fn apply_settings(&mut self, fluid: &Fluid, terrain_size: f32) -> bool {
        let next = FluidConfig::from_scene(fluid, terrain_size);
        if next.resolution != self.config.resolution
            || next.cell_size != self.config.cell_size
            || next.diffuses() != self.config.diffuses()
            || next.validate().is_err()
        {
            return false;
        }
        self.config = next;
        true
    }

    /// The pressure of the last solve (`array<f32>`, STORAGE | COPY_SRC). With warm start
    /// and an odd iteration count the solve alternates between two buffers, so fetch this
    /// after each `encode` instead of binding it once.
    pub fn pressure(&self) -> &wgpu::Buffer {
        &self.pressure[self.pressure_current]
    }

    /// The divergence that entered the last pressure solve (`array<f32>`, STORAGE |
    /// COPY_SRC); always the same buffer.
    pub fn divergence(&self) -> &wgpu::Buffer {
        &self.divergence
    }

    /// Writes this step's uniforms and force lists. At most `MAX_ARROWS` arrows and
    /// `MAX_OBSTACLES` obstacles are used; the rest are dropped with a warning.
    ///
    /// The writes go through `Queue::write_buffer`, which lands before the next submit: one
    /// `prepare` + `encode` per submitted command buffer. Two steps recorded into one
    /// command buffer would both run with the second step's uniforms.
    pub fn prepare(&mut self, queue: &wgpu::Queue, dt: f32, forces: &FluidForces) {
        let params = self.config.params(dt, forces);
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        let arrows = params.arrow_count as usize;
        if arrows < forces.arrows.len() {
            log::warn!("only the first {MAX_ARROWS} wind arrows are simulated");
        }
        if arrows > 0 {
            queue.write_buffer(
                &self.arrows,
                0,
                bytemuck::cast_slice(&forces.arrows[..arrows]),
            );
        }
        let obstacles = params.obstacle_count as usize;
        if obstacles < forces.obstacles.len() {
            log::warn!("only the first {MAX_OBSTACLES} obstacles block the wind");
        }
        if obstacles > 0 {
            queue.write_buffer(
                &self.obstacles,
                0,
                bytemuck::cast_slice(&forces.obstacles[..obstacles]),
            );
        }
    }

    fn begin<'e>(
        timer: &'e Option<FluidTimer>,
        encoder: &'e mut wgpu::CommandEncoder,
        index: usize,
    ) -> wgpu::ComputePass<'e> {
        encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(PASS_LABELS[index]),
            timestamp_writes: timer.as_ref().map(|t| wgpu::ComputePassTimestampWrites {
                query_set: &t.queries,
                beginning_of_pass_write_index: Some(index as u32 * 2),
                end_of_pass_write_index: Some(index as u32 * 2 + 1),
            }),
        })
    }

    /// Records one full step (every pass of `FLUID_PASSES`, in order) and, with timestamp
    /// queries, their resolve. Call `prepare` first.
    pub fn encode(&mut self, encoder: &mut wgpu::CommandEncoder) {
        let wg = self.workgroups;
        let g = &self.groups;
        let timer = &self.timer;
        {
            let mut pass = Self::begin(timer, encoder, 0);
            pass.set_pipeline(&self.splat.pipeline);
            pass.set_bind_group(0, &g.splat, &[]);
            pass.dispatch_workgroups(wg, wg, 1);
        }
        {
            // Two dispatches in one pass: wgpu orders storage writes between dispatches.
            let mut pass = Self::begin(timer, encoder, 1);
            pass.set_bind_group(0, &g.vorticity, &[]);
            pass.set_pipeline(&self.vorticity.pipeline);
            pass.dispatch_workgroups(wg, wg, 1);
            pass.set_pipeline(&self.confine);
            pass.dispatch_workgroups(wg, wg, 1);
        }
        {
            // Always begun, even when empty, so that the timestamp pairs line up with
            // FLUID_PASSES.
            let mut pass = Self::begin(timer, encoder, 2);
            if let Some(groups) = &g.diffuse {
                pass.set_pipeline(&self.diffuse.pipeline);
                for k in 0..self.config.diffusion_iterations {
                    let group = match k {
                        0 => &groups[0],
                        k if k % 2 == 1 => &groups[1],
                        _ => &groups[2],
                    };
                    pass.set_bind_group(0, group, &[]);
                    pass.dispatch_workgroups(wg, wg, 1);
                }
            }
        }
        {
            let mut pass = Self::begin(timer, encoder, 3);
            pass.set_pipeline(&self.divergence_kernel.pipeline);
            pass.set_bind_group(0, &g.divergence, &[]);
            pass.dispatch_workgroups(wg, wg, 1);
        }
        let mut current = self.pressure_current;
        if !self.config.warm_start {
            encoder.clear_buffer(&self.pressure[current], 0, None);
        }
        {
            let mut pass = Self::begin(timer, encoder, 4);
            pass.set_pipeline(&self.pressure_kernel.pipeline);
            for _ in 0..self.config.pressure_iterations {
                pass.set_bind_group(0, &g.pressure[current], &[]);
                pass.dispatch_workgroups(wg, wg, 1);
                current = 1 - current;
            }
        }
        {
            let mut pass = Self::begin(timer, encoder, 5);
            pass.set_pipeline(&self.gradient.pipeline);
            pass.set_bind_group(0, &g.gradient[current], &[]);
            pass.dispatch_workgroups(wg, wg, 1);
        }
        {
            let mut pass = Self::begin(timer, encoder, 6);
            pass.set_pipeline(&self.advect.pipeline);
            pass.set_bind_group(0, &g.advect, &[]);
            pass.dispatch_workgroups(wg, wg, 1);
        }
        self.pressure_current = current;
        if let Some(t) = &self.timer {
            encoder.resolve_query_set(&t.queries, 0..QUERY_COUNT, &t.resolve, 0);
            encoder.copy_buffer_to_buffer(&t.resolve, 0, &t.staging, 0, QUERY_COUNT as u64 * 8);
        }
    }

    /// GPU milliseconds per pass of the last submitted step, in `FLUID_PASSES` order
    /// (blocks until the GPU is idle); `None` without timestamp queries.
    pub fn read_pass_ms(&self, gpu: &Gpu) -> Result<Option<Vec<(&'static str, f64)>>> {
        let Some(t) = &self.timer else {
            return Ok(None);
        };
        let bytes = map_and_read(gpu, &t.staging)?;
        let stamps: Vec<u64> = bytemuck::pod_collect_to_vec(&bytes);
        Ok(Some(
            FLUID_PASSES
                .iter()
                .enumerate()
                .map(|(i, name)| {
                    let ticks = stamps[2 * i + 1].saturating_sub(stamps[2 * i]);
                    (*name, ticks as f64 * t.period_ns as f64 / 1e6)
                })
                .collect(),
        ))
    }

    /// Reads the velocity, the latest pressure and the divergence back (blocking).
    pub fn read_state(&self, gpu: &Gpu) -> Result<FluidState> {
        let cells = self.config.cells() as u64;
        let velocity = read_buffer(gpu, &self.velocity[0], cells * 8)?;
        let pressure = read_buffer(gpu, self.pressure(), cells * 4)?;
        let divergence = read_buffer(gpu, &self.divergence, cells * 4)?;
        Ok(FluidState {
            resolution: self.config.resolution,
            cell_size: self.config.cell_size,
            origin: self.config.origin,
            velocity: bytemuck::pod_collect_to_vec(&velocity),
            pressure: bytemuck::pod_collect_to_vec(&pressure),
            divergence: bytemuck::pod_collect_to_vec(&divergence),
        })
    }

    /// Replaces the velocity grid (tests, resets).
    ///
    /// # Panics
    /// If `velocity` does not hold exactly resolution² cells.
    pub fn write_velocity(&self, queue: &wgpu::Queue, velocity: &[[f32; 2]]) {
        assert_eq!(
            velocity.len(),
            self.config.cells(),
            "write_velocity needs one value per cell"
        );
        queue.write_buffer(&self.velocity[0], 0, bytemuck::cast_slice(velocity));
    }
}

/// Which velocity buffer holds the field after the diffusion pass: vel[2] when it does no
/// work, else the last Jacobi output (iteration k writes vel[1] when k is even, vel[0] when
/// odd).
fn result_of_diffusion(config: &FluidConfig) -> usize {
    if !config.diffuses() {
        2
    } else if config.diffusion_iterations % 2 == 1 {
        1
    } else {
        0
    }
}
