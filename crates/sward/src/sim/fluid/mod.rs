//! The Stable-Fluids wind solver on the GPU (CWD-Sim Eq. 4–10 after Dobryakov's WebGL fluid,
//! Stam's solver as the prairie thesis lays it out) on a staggered (MAC) grid over the
//! terrain: u and v on the faces normal to x and z, pressure at the cell centres, so that
//! divergence, pressure Laplacian and gradient share one compact stencil and a converged
//! solve leaves no divergence but the solver's residual. With `wind.fluid.layers` > 1 the
//! grid is 3D: layers of air that follow the terrain, w on the faces between them, the
//! ground and the top closed (the layout is in `shaders/fluid_common.wgsl`). One step per frame, each
//! stage its own timed compute pass:
//!
//! 1. `advect` – self-advection of every face from its own position, semi-Lagrangian or
//!    MacCormack (`wind.fluid.advection`), with dissipation
//! 2. `splat` – obstacle cells become solid, the pressure weights of every cell, forces
//!    (global, AGC arrows, downwash) at the face positions; solid faces take the obstacle's
//!    velocity
//! 3. `vorticity` – curl, then vorticity confinement ε h (N × ω)
//! 4. `diffuse` – Jacobi viscous diffusion on the faces (empty pass when ν = 0)
//! 5. `divergence`
//! 6. `pressure` – Jacobi iterations or multigrid V-cycles, warm-started from the last frame
//!    when configured
//! 7. `gradient` – subtract the pressure gradient, then write the cell-centred velocity
//!
//! Advection comes first (Stam's order: advect, add forces, project) so that what the step
//! leaves, and what `--dump-wind` writes, is the projected field. The grids live in storage
//! buffers rather than textures so that the blade update can read them with plain indexing
//! and so that the solver works on adapters without filterable float textures. Every step
//! ends with the cell-centred velocity (the mean of each cell's two faces per axis) in the
//! same buffer ([`FluidSolver::velocity`], `array<vec2<f32>>`, n² per layer), so every
//! consumer binds it once and needs to know nothing of the staggered grid. The CPU twin of every pass is
//! [`crate::sim::reference::fluid::FluidCpu`].

mod config;
mod kernels;
mod multigrid;
mod scroll;

use kernels::{module, FluidTimer, Kernel, Slot};
use multigrid::{Finest, Multigrid};
use scroll::Scroller;

use super::wind_layout::{
    ArrowGpu, FluidForces, FluidParams, ObstacleGpu, FLUID_WORKGROUP, MAX_ARROWS, MAX_OBSTACLES,
};
use crate::error::Result;
use crate::gpu::queries::PassQueries;
use crate::gpu::{map_and_read, read_buffer, Gpu};
use crate::scene::{Advection, Fluid, PressureSolver};

pub use super::reference::fluid::sample_velocity;
pub use config::{
    boundary_id, FluidConfig, FluidState, MAX_LAYERS, MAX_MULTIGRID_CYCLES, MAX_RESOLUTION,
    MIN_LEVEL_SIZE, MIN_RESOLUTION,
};

/// The passes of one step, in the order of their timestamp pairs.
pub const FLUID_PASSES: [&str; 7] = [
    "advect",
    "splat",
    "vorticity",
    "diffuse",
    "divergence",
    "pressure",
    "gradient",
];

/// Index of the pressure pass in [`FLUID_PASSES`].
pub const PRESSURE_PASS: usize = 5;

/// Labels of the compute passes, in `FLUID_PASSES` order.
const PASS_LABELS: [&str; FLUID_PASSES.len()] = [
    "sward.fluid.advect",
    "sward.fluid.splat",
    "sward.fluid.vorticity",
    "sward.fluid.diffuse",
    "sward.fluid.divergence",
    "sward.fluid.pressure",
    "sward.fluid.gradient",
];

/// The kernels of one step.
struct Kernels {
    advect: Kernel,
    forward: Kernel,
    backward: Kernel,
    correct: Kernel,
    mark: Kernel,
    cell_weights: Kernel,
    splat: Kernel,
    curl: Kernel,
    confine: Kernel,
    diffuse: Kernel,
    divergence: Kernel,
    jacobi: Kernel,
    gradient: Kernel,
    centre: Kernel,
}

impl Kernels {
    fn new(device: &wgpu::Device) -> Self {
        use Slot::{Read, Uniform, Write};
        let advect = module(device, "advect");
        let sl = [Uniform, Read, Read, Write];
        let splat = module(device, "splat");
        // One layout for the three splat entry points; each uses a subset of it.
        let splat_slots = [Uniform, Read, Read, Read, Write, Write, Write];
        let vorticity = module(device, "vorticity");
        let vorticity_slots = [Uniform, Read, Write, Write, Read];
        Self {
            advect: Kernel::new(device, &advect, "advect", "advect", &sl),
            forward: Kernel::new(device, &advect, "advect_forward", "forward", &sl),
            backward: Kernel::new(device, &advect, "advect_backward", "backward", &sl),
            correct: Kernel::new(
                device,
                &advect,
                "advect_correct",
                "correct",
                &[Uniform, Read, Read, Write, Read, Read],
            ),
            mark: Kernel::new(device, &splat, "mark", "mark", &splat_slots),
            cell_weights: Kernel::new(device, &splat, "weights", "cell_weights", &splat_slots),
            splat: Kernel::new(device, &splat, "splat", "faces", &splat_slots),
            curl: Kernel::new(device, &vorticity, "curl", "compute_curl", &vorticity_slots),
            confine: Kernel::new(device, &vorticity, "confine", "confine", &vorticity_slots),
            diffuse: Kernel::new(
                device,
                &module(device, "diffuse"),
                "diffuse",
                "main",
                &[Uniform, Read, Read, Write, Read],
            ),
            divergence: Kernel::new(
                device,
                &module(device, "divergence"),
                "divergence",
                "main",
                &[Uniform, Read, Write, Read],
            ),
            jacobi: Kernel::new(
                device,
                &module(device, "pressure"),
                "jacobi",
                "main",
                &[Uniform, Read, Read, Write, Read],
            ),
            gradient: Kernel::new(
                device,
                &module(device, "gradient"),
                "gradient",
                "main",
                &[Uniform, Read, Read, Write, Read],
            ),
            centre: Kernel::new(
                device,
                &module(device, "centre"),
                "centre",
                "main",
                &[Uniform, Read, Write],
            ),
        }
    }
}

/// The bind groups of one step. Face buffers are `faces[0]` (the state between steps) and
/// three scratch buffers; which one holds what depends only on the configuration
/// (diffusion on/off and the parity of its iterations), so all groups are made once.
struct Groups {
    /// Semi-Lagrangian faces[0] → faces[1].
    advect: wgpu::BindGroup,
    /// MacCormack: faces[0] → faces[2] (q̂), faces[2] → faces[3] (q̃), correction → faces[1].
    forward: wgpu::BindGroup,
    backward: wgpu::BindGroup,
    correct: wgpu::BindGroup,
    /// faces[1] → faces[2], solid, weights.
    splat: wgpu::BindGroup,
    /// Curl of faces[2], confinement faces[2] → faces[1].
    vorticity: wgpu::BindGroup,
    /// Iteration 0 (faces[1] → faces[2]), then odd (faces[2] → faces[3]) and even
    /// (faces[3] → faces[2]).
    diffuse: Option<[wgpu::BindGroup; 3]>,
    divergence: wgpu::BindGroup,
    /// Jacobi pressure[0] → pressure[1] and pressure[1] → pressure[0].
    jacobi: [wgpu::BindGroup; 2],
    /// Gradient into faces[0] with the final pressure in pressure[0] or pressure[1].
    gradient: [wgpu::BindGroup; 2],
    /// faces[0] → the public cell-centred velocity.
    centre: wgpu::BindGroup,
}

/// The GPU wind solver: owns its pipelines, grids, uniforms and timestamp queries.
pub struct FluidSolver {
    config: FluidConfig,
    params: wgpu::Buffer,
    arrows: wgpu::Buffer,
    obstacles: wgpu::Buffer,
    /// The cell-centred velocity every consumer reads.
    velocity: wgpu::Buffer,
    faces: [wgpu::Buffer; 4],
    pressure: [wgpu::Buffer; 2],
    divergence: wgpu::Buffer,
    solid: wgpu::Buffer,
    weights: wgpu::Buffer,
    // Only bound, never read back; held so the struct visibly owns every grid it uses.
    _curl: wgpu::Buffer,
    kernels: Kernels,
    multigrid: Multigrid,
    groups: Groups,
    /// Which pressure buffer holds the latest solve (the warm start of the next one).
    pressure_current: usize,
    timer: Option<FluidTimer>,
    scroller: Scroller,
    /// The grid's corner now: `config.origin`, or where [`Self::follow`] moved it.
    origin: [f32; 2],
    /// A following grid's corner in whole cells, once it has followed a camera.
    corner: Option<[i64; 2]>,
}

/// Workgroups covering `cells` along one axis.
fn groups_of(cells: u32) -> u32 {
    cells.div_ceil(FLUID_WORKGROUP)
}

impl FluidSolver {
    /// Builds the solver after checking the grid against the range and the device limits;
    /// nothing is allocated when a check fails.
    pub fn new(gpu: &Gpu, config: &FluidConfig) -> Result<Self> {
        config.validate()?;
        let n = config.resolution;
        let what = format!("a fluid grid of {n}x{n}x{} cells", config.layers);
        let remedy = "lower wind.fluid.resolution or wind.fluid.layers";
        gpu.check_storage_or(&what, config.faces() as u64 * 4, remedy)?;
        gpu.check_storage_or(&what, config.cells() as u64 * 32, remedy)?;
        gpu.check_dispatch(&what, groups_of(n + 1))?;
        gpu.check_dispatch(&what, 3 * (config.layers + 1))?;

        let device = &gpu.device;
        let buffer = |label: &str, size: u64| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(&format!("sward.fluid.{label}")),
                size,
                // COPY_SRC for read-back, COPY_DST for `write_faces` and the pressure clear
                // of a cold start. New buffers are zeroed by wgpu: the air starts still.
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_SRC
                    | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let cells = config.cells() as u64;
        let face_bytes = config.faces() as u64 * 4;
        let faces = [
            buffer("faces", face_bytes),
            buffer("faces_scratch_a", face_bytes),
            buffer("faces_scratch_b", face_bytes),
            buffer("faces_scratch_c", face_bytes),
        ];
        let velocity = buffer("velocity", cells * 8);
        let pressure = [
            buffer("pressure_a", cells * 4),
            buffer("pressure_b", cells * 4),
        ];
        let divergence = buffer("divergence", cells * 4);
        let curl = buffer("curl", cells * 4);
        let solid = buffer("solid", cells * 4);
        let weights = buffer("weights", cells * 32);
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

        let k = Kernels::new(device);
        let f = &faces;
        let projected_in = result_of_diffusion(config);
        let diffuse = config.diffuses().then(|| {
            [
                k.diffuse.bind(
                    device,
                    "diffuse.first",
                    &[&params, &f[1], &f[1], &f[2], &solid],
                ),
                k.diffuse.bind(
                    device,
                    "diffuse.odd",
                    &[&params, &f[1], &f[2], &f[3], &solid],
                ),
                k.diffuse.bind(
                    device,
                    "diffuse.even",
                    &[&params, &f[1], &f[3], &f[2], &solid],
                ),
            ]
        });
        let p = &pressure;
        let groups = Groups {
            advect: k
                .advect
                .bind(device, "advect", &[&params, &f[0], &f[0], &f[1]]),
            forward: k
                .forward
                .bind(device, "advect.forward", &[&params, &f[0], &f[0], &f[2]]),
            backward: k
                .backward
                .bind(device, "advect.backward", &[&params, &f[0], &f[2], &f[3]]),
            correct: k.correct.bind(
                device,
                "advect.correct",
                &[&params, &f[0], &f[0], &f[1], &f[2], &f[3]],
            ),
            splat: k.splat.bind(
                device,
                "splat",
                &[&params, &arrows, &obstacles, &f[1], &f[2], &solid, &weights],
            ),
            vorticity: k
                .curl
                .bind(device, "vorticity", &[&params, &f[2], &curl, &f[1], &solid]),
            diffuse,
            divergence: k.divergence.bind(
                device,
                "divergence",
                &[&params, &f[projected_in], &divergence, &solid],
            ),
            jacobi: [
                k.jacobi.bind(
                    device,
                    "jacobi.a_to_b",
                    &[&params, &divergence, &p[0], &p[1], &weights],
                ),
                k.jacobi.bind(
                    device,
                    "jacobi.b_to_a",
                    &[&params, &divergence, &p[1], &p[0], &weights],
                ),
            ],
            gradient: [0, 1].map(|v| {
                k.gradient.bind(
                    device,
                    &format!("gradient.p{v}"),
                    &[&params, &f[projected_in], &p[v], &f[0], &solid],
                )
            }),
            centre: k
                .centre
                .bind(device, "centre", &[&params, &f[0], &velocity]),
        };
        let multigrid = Multigrid::new(
            device,
            config,
            Finest {
                pressure: [&pressure[0], &pressure[1]],
                divergence: &divergence,
                weights: &weights,
            },
        );
        let scroller = Scroller::new(device, [&faces[0], &faces[1]], [&pressure[0], &pressure[1]]);
        Ok(Self {
            config: config.clone(),
            origin: config.origin,
            corner: None,
            scroller,
            params,
            arrows,
            obstacles,
            velocity,
            faces,
            pressure,
            divergence,
            solid,
            weights,
            _curl: curl,
            kernels: k,
            multigrid,
            groups,
            pressure_current: 0,
            timer: FluidTimer::new(gpu, FLUID_PASSES.len()),
        })
    }

    /// The cell-centred velocity after the last step: `array<vec2<f32>>`, resolution²
    /// cells per layer, layer 0 (at the ground) first, STORAGE | COPY_SRC | COPY_DST. Always
    /// the same buffer object.
    pub fn velocity(&self) -> &wgpu::Buffer {
        &self.velocity
    }

    /// The settings the solver runs with: those it was created with, as last changed by
    /// [`Self::apply_settings`].
    pub fn config(&self) -> &FluidConfig {
        &self.config
    }

    /// The world x, z of the grid's corner now (it moves when the grid follows the camera).
    pub fn origin(&self) -> [f32; 2] {
        self.origin
    }

    /// For a grid that follows the camera (`config.follow`): centres it on the cell under
    /// `eye` (x, z), recording a scroll by whole cells when that cell changed; returns the
    /// shift in cells. The first call only places the grid (the air is still then). A jump
    /// farther than the grid (a teleport) fills it from the old grid's edge, which is as
    /// close as anything to the air that blows there. Call before [`Self::prepare`].
    /// `work`: the counter row the scroll's pass is counted into, as [`Self::encode`]'s.
    pub fn follow(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        eye: [f32; 2],
        work: PassQueries<'_>,
    ) -> [i64; 2] {
        if !(self.config.follow && eye[0].is_finite() && eye[1].is_finite()) {
            return [0, 0];
        }
        let target = self.config.corner_for(eye);
        let h = f64::from(self.config.cell_size);
        self.origin = target.map(|c| (c as f64 * h) as f32);
        let Some(corner) = self.corner.replace(target) else {
            return [0, 0];
        };
        let shift = [target[0] - corner[0], target[1] - corner[1]];
        if shift != [0, 0] {
            let n = self.config.resolution;
            let limit = i64::from(n) + 1;
            let clamped = shift.map(|s| s.clamp(-limit, limit) as i32);
            self.scroller.encode(
                queue,
                encoder,
                clamped,
                n,
                self.config.layers,
                [&self.faces[0], &self.faces[1]],
                [&self.pressure[0], &self.pressure[1]],
                self.pressure_current,
                work,
            );
        }
        shift
    }

    /// The side of every multigrid level, finest first.
    pub fn multigrid_levels(&self) -> &[u32] {
        self.multigrid.sizes()
    }

    /// Bytes of GPU memory the solver's buffers hold.
    pub fn gpu_bytes(&self) -> u64 {
        let grids: u64 = self
            .faces
            .iter()
            .chain(self.pressure.iter())
            .chain([
                &self.velocity,
                &self.divergence,
                &self._curl,
                &self.solid,
                &self.weights,
            ])
            .map(|b| b.size())
            .sum();
        grids
            + self.multigrid.gpu_bytes()
            + self.params.size()
            + self.arrows.size()
            + self.obstacles.size()
    }

    /// Takes the scene's solver settings for the next steps (the panel edits them live).
    /// Returns false, changing nothing, when the change needs a new solver: another grid
    /// resolution or terrain size, diffusion switched on or off (its bind groups exist
    /// only when it runs), or a boundary that changes the multigrid hierarchy.
    pub fn apply_settings(&mut self, fluid: &Fluid, terrain_size: f32) -> bool {
        let next = FluidConfig::from_scene(fluid, terrain_size);
        if next.resolution != self.config.resolution
            || next.layers != self.config.layers
            || next.cell_size != self.config.cell_size
            || next.diffuses() != self.config.diffuses()
            || next.multigrid_levels() != self.multigrid.sizes()
            || next.validate().is_err()
        {
            return false;
        }
        self.config = next;
        true
    }

    /// The pressure of the last solve (`array<f32>`, STORAGE | COPY_SRC). With an odd
    /// Jacobi iteration count (cold start) the solve alternates between two buffers, so
    /// fetch this after each `encode` instead of binding it once.
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
        let mut params = self.config.params(dt, forces);
        params.origin_cell[0] = self.origin[0];
        params.origin_cell[1] = self.origin[1];
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        self.multigrid.prepare(queue, &self.config);
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

    /// Records pass `index` of `FLUID_PASSES`: timed when there is a timer, counted into
    /// `work`'s row, its dispatches recorded by `record`.
    fn pass(
        timer: &Option<FluidTimer>,
        encoder: &mut wgpu::CommandEncoder,
        index: usize,
        work: PassQueries<'_>,
        record: impl FnOnce(&mut wgpu::ComputePass<'_>),
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(PASS_LABELS[index]),
            timestamp_writes: timer.as_ref().map(|t| wgpu::ComputePassTimestampWrites {
                query_set: &t.queries,
                beginning_of_pass_write_index: Some(index as u32 * 2),
                end_of_pass_write_index: Some(index as u32 * 2 + 1),
            }),
        });
        work.begin(&mut pass);
        record(&mut pass);
        work.end(&mut pass);
    }

    /// Records one full step (every pass of `FLUID_PASSES`, in order) and, with timestamp
    /// queries, their resolve. Call `prepare` first. `work`: the work counter's row the
    /// passes are counted into (the frame's "wind"), or `PassQueries::NONE`.
    pub fn encode(&mut self, encoder: &mut wgpu::CommandEncoder, work: PassQueries<'_>) {
        let n = self.config.resolution;
        let layers = self.config.layers;
        let (cells, faces) = (groups_of(n), groups_of(n + 1));
        let g = &self.groups;
        let k = &self.kernels;
        let timer = &self.timer;
        let dispatch = |pass: &mut wgpu::ComputePass, kernel: &Kernel, group, face: bool| {
            pass.set_pipeline(&kernel.pipeline);
            pass.set_bind_group(0, group, &[]);
            if face {
                pass.dispatch_workgroups(faces, faces, face_slices(layers));
            } else {
                pass.dispatch_workgroups(cells, cells, layers);
            }
        };
        // Dispatches in one pass: wgpu orders storage writes between dispatches.
        Self::pass(timer, encoder, 0, work, |pass| match self.config.advection {
            Advection::SemiLagrangian => dispatch(pass, &k.advect, &g.advect, true),
            Advection::MacCormack => {
                dispatch(pass, &k.forward, &g.forward, true);
                dispatch(pass, &k.backward, &g.backward, true);
                dispatch(pass, &k.correct, &g.correct, true);
            }
        });
        Self::pass(timer, encoder, 1, work, |pass| {
            dispatch(pass, &k.mark, &g.splat, false);
            dispatch(pass, &k.cell_weights, &g.splat, false);
            dispatch(pass, &k.splat, &g.splat, true);
        });
        Self::pass(timer, encoder, 2, work, |pass| {
            dispatch(pass, &k.curl, &g.vorticity, false);
            dispatch(pass, &k.confine, &g.vorticity, true);
        });
        // Always begun, even when empty, so that the timestamp pairs line up with
        // FLUID_PASSES.
        Self::pass(timer, encoder, 3, work, |pass| {
            if let Some(groups) = &g.diffuse {
                for it in 0..self.config.diffusion_iterations {
                    let group = match it {
                        0 => &groups[0],
                        it if it % 2 == 1 => &groups[1],
                        _ => &groups[2],
                    };
                    dispatch(pass, &k.diffuse, group, true);
                }
            }
        });
        Self::pass(timer, encoder, 4, work, |pass| {
            dispatch(pass, &k.divergence, &g.divergence, false);
        });
        let mut current = self.pressure_current;
        if !self.config.warm_start {
            encoder.clear_buffer(&self.pressure[current], 0, None);
        }
        Self::pass(timer, encoder, PRESSURE_PASS, work, |pass| {
            match self.config.pressure_solver {
                PressureSolver::Jacobi => {
                    for _ in 0..self.config.jacobi_iterations() {
                        dispatch(pass, &k.jacobi, &g.jacobi[current], false);
                        current = 1 - current;
                    }
                }
                PressureSolver::Multigrid => {
                    self.multigrid.encode(pass, current, self.config.v_cycles());
                }
            }
        });
        Self::pass(timer, encoder, 6, work, |pass| {
            dispatch(pass, &k.gradient, &g.gradient[current], true);
            dispatch(pass, &k.centre, &g.centre, false);
        });
        self.pressure_current = current;
        if let Some(t) = &self.timer {
            encoder.resolve_query_set(&t.queries, 0..t.count, &t.resolve, 0);
            encoder.copy_buffer_to_buffer(&t.resolve, 0, &t.staging, 0, t.count as u64 * 8);
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

    /// Reads the grids back (blocking): faces, cell-centred velocity, solid mask, the latest
    /// pressure and the divergence that entered its solve.
    pub fn read_state(&self, gpu: &Gpu) -> Result<FluidState> {
        let n = self.config.resolution as usize;
        let cells = self.config.cells() as u64;
        let faces: Vec<f32> = bytemuck::pod_collect_to_vec(&read_buffer(
            gpu,
            &self.faces[0],
            self.config.faces() as u64 * 4,
        )?);
        let read = |b: &wgpu::Buffer, bytes: u64| read_buffer(gpu, b, cells * bytes);
        let uv = n * (n + 1) * self.config.layers as usize;
        let (u, rest) = faces.split_at(uv);
        let (v, w) = rest.split_at(uv);
        Ok(FluidState {
            resolution: self.config.resolution,
            layers: self.config.layers,
            cell_size: self.config.cell_size,
            layer_height: self.config.layer_height,
            origin: self.origin,
            velocity: bytemuck::pod_collect_to_vec(&read(&self.velocity, 8)?),
            u: u.to_vec(),
            v: v.to_vec(),
            w: w.to_vec(),
            solid: bytemuck::pod_collect_to_vec(&read(&self.solid, 4)?),
            pressure: bytemuck::pod_collect_to_vec(&read(self.pressure(), 4)?),
            divergence: bytemuck::pod_collect_to_vec(&read(&self.divergence, 4)?),
        })
    }

    /// Replaces the face velocities, u, v and w as in [`FluidState`] (tests, resets); an
    /// empty `w` means still vertical air. On a periodic grid the last face of each axis
    /// must equal the first (the kernels keep them equal;
    /// [`crate::sim::reference::fluid::periodic_faces`] makes them so).
    ///
    /// # Panics
    /// If `u` or `v` does not hold (n + 1) · n faces per layer, or `w` is neither empty nor
    /// n² per plane.
    pub fn write_faces(&self, queue: &wgpu::Queue, u: &[f32], v: &[f32], w: &[f32]) {
        let faces = face_vector(&self.config, u, v, w);
        queue.write_buffer(&self.faces[0], 0, bytemuck::cast_slice(&faces));
    }
}

/// u, v and w (still when empty) as one face array, checked against the grid.
///
/// # Panics
/// If a component has the wrong length.
pub fn face_vector(config: &FluidConfig, u: &[f32], v: &[f32], w: &[f32]) -> Vec<f32> {
    let uv = config.layer_faces() * config.layers as usize;
    let planes = config.layer_cells() * (config.layers as usize + 1);
    assert!(
        u.len() == uv && v.len() == uv,
        "the faces need (n + 1) · n values per axis and layer"
    );
    assert!(
        w.is_empty() || w.len() == planes,
        "w needs n² values per plane (layers + 1 planes)"
    );
    let mut faces = Vec::with_capacity(config.faces());
    faces.extend_from_slice(u);
    faces.extend_from_slice(v);
    if w.is_empty() {
        faces.resize(config.faces(), 0.0);
    } else {
        faces.extend_from_slice(w);
        // The ground's and the ceiling's w are walls, 0 whatever was given: no pass writes
        // the ceiling (`face_slices`), and the ground is 0 after the first step anyway.
        let plane = config.layer_cells();
        let start = 2 * uv;
        faces[start..start + plane].fill(0.0);
        let top = faces.len() - plane;
        faces[top..].fill(0.0);
    }
    faces
}

/// Workgroups along z of a face dispatch (`fluid_face` in fluid_common.wgsl: z = axis + 3 k,
/// the u, v and w faces of layer k): the layers below the top plane, whose u and v do not
/// exist and whose w is the ceiling; a 2D grid's one layer only its u and v, since both its
/// w planes are the ground and the ceiling. What is left out are walls (`fluid_is_wall`),
/// 0 in buffers made zeroed and in what `write_faces` writes, and written by no pass.
/// llvmpipe runs a kernel's whole body for the invocations that return at once: a 2D
/// grid's six slices cost three times the two it needs (the helicopter's 256² grid at
/// 160 × 90: the vorticity pass 23.3 / 18.7 → 10.9 / 10.3 ms, the splat 16.4 / 13.8 → 9.7 /
/// 9.0 ms, alternating; the frame the same to the byte).
pub fn face_slices(layers: u32) -> u32 {
    if layers <= 1 {
        2
    } else {
        3 * layers
    }
}

/// Which face buffer holds the field after the diffusion pass: faces[1] when it does no
/// work, else the last Jacobi output (iteration 0 writes faces[2], odd iterations faces[3],
/// even ones faces[2]).
fn result_of_diffusion(config: &FluidConfig) -> usize {
    if !config.diffuses() {
        1
    } else if config.diffusion_iterations % 2 == 1 {
        2
    } else {
        3
    }
}
