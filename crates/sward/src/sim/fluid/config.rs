//! What the wind solver is set up with ([`FluidConfig`], from the scene's `wind.fluid`) and
//! what it hands back ([`FluidState`], the grids on the host, from the GPU or the CPU twin).

use crate::error::{Error, Result};
use crate::scene::{Advection, Boundary, Fluid, PressureSolver};
use crate::sim::wind_layout::{FluidForces, FluidParams, MAX_ARROWS, MAX_OBSTACLES};

/// Smallest grid side the solver accepts (one workgroup; the stencils need a few cells).
pub const MIN_RESOLUTION: u32 = 8;
/// Largest grid side the solver accepts (4 Mi cells, 32 MiB per face buffer).
pub const MAX_RESOLUTION: u32 = 2048;
/// Most V-cycles per step.
pub const MAX_MULTIGRID_CYCLES: u32 = 20;
/// The coarsest multigrid level is at least this many cells per side.
pub const MIN_LEVEL_SIZE: u32 = 4;
/// Most layers of a 3D grid (each column is solved as one line by the multigrid smoother,
/// in a private array of this size).
pub const MAX_LAYERS: u32 = 16;

/// How the solver is set up; fixed for the life of a [`super::FluidSolver`] except where
/// [`super::FluidSolver::apply_settings`] says.
#[derive(Clone, Debug, PartialEq)]
pub struct FluidConfig {
    /// Cells per side.
    pub resolution: u32,
    /// Cell side h in metres.
    pub cell_size: f32,
    /// World x, z of the grid's outer corner (cell (0, 0)'s corner).
    pub origin: [f32; 2],
    /// How the pressure Poisson equation is solved: Jacobi iterations or multigrid V-cycles.
    pub pressure_solver: PressureSolver,
    /// Jacobi iterations (`PressureSolver::Jacobi`).
    pub pressure_iterations: u32,
    /// V-cycles (`PressureSolver::Multigrid`).
    pub multigrid_cycles: u32,
    /// Start the pressure solve from the last step's pressure instead of 0.
    pub warm_start: bool,
    /// Vorticity confinement ε in 1/s (0 = off); the force is ε h (N × ω).
    pub vorticity: f32,
    /// Velocity dissipation per second (v /= 1 + dissipation · Δt after advection).
    pub dissipation: f32,
    /// Kinematic viscosity ν in m²/s (0 = no diffusion pass work).
    pub viscosity: f32,
    /// Jacobi iterations of the viscous diffusion (none run while `viscosity` is 0).
    pub diffusion_iterations: u32,
    /// What happens at the grid's border: closed walls, open, or periodic.
    pub boundary: Boundary,
    /// How the velocity is carried along itself: semi-Lagrangian or MacCormack.
    pub advection: Advection,
    /// The grid follows the camera ([`super::FluidSolver::follow`]): `origin` is only
    /// where it starts.
    pub follow: bool,
    /// Layers of air (1 = 2D); see `scene::Fluid::layers`.
    pub layers: u32,
    /// Thickness dy of a layer in metres.
    pub layer_height: f32,
    /// Ground drag c in 1/s (layer k's horizontal wind feels c / (k + ½)); 3D only.
    pub ground_drag: f32,
}

impl FluidConfig {
    /// The grid of a scene: the square terrain centred on 0, or with `fluid.extent > 0` a
    /// square of that side that follows the camera (centred on 0 until it first moves).
    pub fn from_scene(fluid: &Fluid, terrain_size: f32) -> Self {
        let resolution = fluid.resolution;
        let follow = fluid.extent > 0.0;
        let side = if follow { fluid.extent } else { terrain_size };
        Self {
            resolution,
            cell_size: side / resolution.max(1) as f32,
            origin: [-0.5 * side, -0.5 * side],
            follow,
            pressure_solver: fluid.pressure_solver,
            pressure_iterations: fluid.pressure_iterations,
            multigrid_cycles: fluid.multigrid_cycles,
            warm_start: fluid.warm_start,
            vorticity: fluid.vorticity,
            dissipation: fluid.dissipation,
            viscosity: fluid.viscosity,
            diffusion_iterations: fluid.diffusion_iterations,
            boundary: fluid.boundary,
            advection: fluid.advection,
            layers: fluid.layers,
            layer_height: fluid.layer_height,
            ground_drag: fluid.ground_drag,
        }
    }

    /// A 2D grid (one layer) with the given settings; tests and benches build configs
    /// field by field and take the 2D defaults from here.
    pub fn flat(self) -> Self {
        Self { layers: 1, ..self }
    }

    /// Cells of one layer (n²).
    pub fn layer_cells(&self) -> usize {
        self.resolution as usize * self.resolution as usize
    }

    /// u faces of one layer ((n + 1) · n; as many v faces).
    pub fn layer_faces(&self) -> usize {
        self.resolution as usize * (self.resolution as usize + 1)
    }

    /// Whether the grid has more than one layer.
    pub fn is_3d(&self) -> bool {
        self.layers > 1
    }

    /// The corner (in whole cells from the world origin) of a following grid centred on the
    /// cell under `eye` (x, z).
    pub fn corner_for(&self, eye: [f32; 2]) -> [i64; 2] {
        let h = f64::from(self.cell_size);
        let half = i64::from(self.resolution / 2);
        eye.map(|e| {
            let c = (f64::from(e) / h).floor();
            // A camera beyond any sane range (validated elsewhere) cannot overflow.
            c.clamp(-1e15, 1e15) as i64 - half
        })
    }

    /// Cells in the grid (n² per layer).
    pub fn cells(&self) -> usize {
        self.layer_cells() * self.layers as usize
    }

    /// Faces in the grid: per layer (n + 1) · n carrying u, then per layer n · (n + 1)
    /// carrying v, then n² carrying w on each of the layers + 1 horizontal planes (the
    /// ground, between layers, the top).
    pub fn faces(&self) -> usize {
        let l = self.layers as usize;
        2 * l * self.layer_faces() + (l + 1) * self.layer_cells()
    }

    /// Jacobi iterations a step runs: `pressure_iterations`, rounded up to even when
    /// warm-starting. On the staggered grid the residual a solve leaves is the next step's
    /// divergence, so a warm-started solve starts from an error twice its last one minus
    /// the one before (e' = m (2e − e₋₁) per mode, m the solve's error factor), which grows
    /// when m < −1/3. Jacobi's factor for checkerboard-like modes is μ^K with μ near −1: an
    /// odd K makes it negative and those modes blow up within a second; an even K keeps
    /// every factor ≥ 0 and the recursion decays (|e| shrinks like √m).
    pub fn jacobi_iterations(&self) -> u32 {
        let k = self.pressure_iterations;
        if self.warm_start {
            k + k % 2
        } else {
            k
        }
    }

    /// V-cycles a step runs: `multigrid_cycles`, rounded up to even when warm-starting, for
    /// the reason of [`Self::jacobi_iterations`]: one V-cycle can overshoot near a moving
    /// obstacle (a negative error factor), two cannot.
    pub fn v_cycles(&self) -> u32 {
        let k = self.multigrid_cycles;
        if self.warm_start {
            k + k % 2
        } else {
            k
        }
    }

    /// Whether the diffusion pass does any work.
    pub fn diffuses(&self) -> bool {
        self.viscosity > 0.0 && self.diffusion_iterations > 0
    }

    /// The id the shaders switch on (`FLUID_CLOSED` / `FLUID_OPEN` / `FLUID_PERIODIC`).
    pub fn boundary_id(&self) -> u32 {
        boundary_id(self.boundary)
    }

    /// The side of every multigrid level, finest first. A level is halved while its side
    /// is even and the half is at least [`MIN_LEVEL_SIZE`]; on a periodic grid the half
    /// must be even too, so that red-black colouring holds across the seam on every level.
    pub fn multigrid_levels(&self) -> Vec<u32> {
        let mut sizes = vec![self.resolution];
        loop {
            let m = *sizes.last().expect("one level at least");
            let half = m / 2;
            let periodic_ok = self.boundary != Boundary::Periodic || half % 2 == 0;
            if m % 2 != 0 || half < MIN_LEVEL_SIZE || !periodic_ok {
                return sizes;
            }
            sizes.push(half);
        }
    }

    /// Checks the values a scene or a caller can get wrong, before anything is allocated.
    pub fn validate(&self) -> Result<()> {
        if !(MIN_RESOLUTION..=MAX_RESOLUTION).contains(&self.resolution) {
            return Err(Error::Invalid(format!(
                "wind.fluid.resolution = {} is out of range: allowed {MIN_RESOLUTION} <= resolution \
                 <= {MAX_RESOLUTION} cells per side",
                self.resolution
            )));
        }
        if self.pressure_solver == PressureSolver::Multigrid
            && self.boundary == Boundary::Periodic
            && self.resolution % 2 == 1
        {
            return Err(Error::Invalid(format!(
                "wind.fluid.resolution = {} is odd: the Multigrid pressure solver with a Periodic \
                 boundary needs an even resolution (or use pressure_solver: Jacobi)",
                self.resolution
            )));
        }
        if !(1..=MAX_MULTIGRID_CYCLES).contains(&self.multigrid_cycles) {
            return Err(Error::Invalid(format!(
                "wind.fluid.multigrid_cycles = {} is out of range: allowed 1 <= multigrid_cycles \
                 <= {MAX_MULTIGRID_CYCLES}",
                self.multigrid_cycles
            )));
        }
        if !(1..=MAX_LAYERS).contains(&self.layers) {
            return Err(Error::Invalid(format!(
                "wind.fluid.layers = {} is out of range: allowed 1 <= layers <= {MAX_LAYERS}",
                self.layers
            )));
        }
        if !(self.layer_height.is_finite() && self.layer_height > 0.0) {
            return Err(Error::Invalid(format!(
                "wind.fluid.layer_height = {} m is out of range: allowed a positive number",
                self.layer_height
            )));
        }
        if !(self.cell_size.is_finite() && self.cell_size > 0.0) {
            return Err(Error::Invalid(format!(
                "fluid cell size {} m is not a positive number (terrain size / resolution)",
                self.cell_size
            )));
        }
        let nonneg = [
            ("wind.fluid.vorticity", self.vorticity),
            ("wind.fluid.dissipation", self.dissipation),
            ("wind.fluid.viscosity", self.viscosity),
            ("wind.fluid.ground_drag", self.ground_drag),
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
            layer: self.layer_uniforms(dt),
            layers: self.layers,
            _pad: [0; 3],
        }
    }

    /// `FluidParams::layer`: dy, 1/dy, the vertical diffusion factor νΔt/dy² and the ground
    /// drag, the last two 0 on a 2D grid so that its arithmetic is the 2D solver's exactly.
    fn layer_uniforms(&self, dt: f32) -> [f32; 4] {
        let dy = self.layer_height;
        if !self.is_3d() {
            return [dy, 1.0 / dy, 0.0, 0.0];
        }
        [
            dy,
            1.0 / dy,
            self.viscosity * dt / (dy * dy),
            self.ground_drag,
        ]
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

/// A snapshot of the solver's grids on the host (read-back or the CPU twin), after a step.
/// Every per-cell array holds n² cells per layer, layer 0 (at the ground) first, row-major,
/// x fastest.
#[derive(Clone, Debug, PartialEq)]
pub struct FluidState {
    /// Cells per side n.
    pub resolution: u32,
    /// Layers of air (1 = a 2D grid).
    pub layers: u32,
    /// Cell side h in metres.
    pub cell_size: f32,
    /// Thickness of a layer in metres.
    pub layer_height: f32,
    /// World x, z in metres of the grid's outer corner (cell (0, 0)'s corner) at this step.
    pub origin: [f32; 2],
    /// Cell-centred (u, v) in m/s: what the blades read.
    pub velocity: Vec<[f32; 2]>,
    /// u (m/s) on the faces normal to x, (n + 1) · n per layer, face (i, j, k) at index
    /// k (n + 1) n + j (n + 1) + i.
    pub u: Vec<f32>,
    /// v (m/s) on the faces normal to z, n · (n + 1) per layer, face (i, j, k) at index
    /// k n (n + 1) + j n + i.
    pub v: Vec<f32>,
    /// w (m/s, up) on the n² faces of each of the layers + 1 planes (the ground, between
    /// layers, the top), face (i, j, k) at index k n² + j n + i; the ground and the top
    /// hold 0.
    pub w: Vec<f32>,
    /// 0 = fluid, k + 1 = inside obstacle k, per cell.
    pub solid: Vec<u32>,
    /// Pressure of the last solve (in m²/s: the Δt/ρ factor is folded in).
    pub pressure: Vec<f32>,
    /// Divergence (1/s) of the velocity that entered the last pressure solve.
    pub divergence: Vec<f32>,
}

impl FluidState {
    /// Cell-centred velocity of cell (i, j) of the lowest layer.
    pub fn at(&self, i: u32, j: u32) -> [f32; 2] {
        self.at_layer(i, j, 0)
    }

    /// Cell-centred velocity of cell (i, j) of layer `k`.
    pub fn at_layer(&self, i: u32, j: u32, k: u32) -> [f32; 2] {
        let n = self.resolution;
        self.velocity[((k * n + j) * n + i) as usize]
    }

    /// w at the centre of cell (i, j, k): the mean of its floor and ceiling.
    pub fn w_at(&self, i: u32, j: u32, k: u32) -> f32 {
        let n = self.resolution as usize;
        let plane = n * n;
        let c = j as usize * n + i as usize;
        0.5 * (self.w[k as usize * plane + c] + self.w[(k as usize + 1) * plane + c])
    }

    /// Largest cell-centred horizontal speed in the grid, in m/s.
    pub fn max_speed(&self) -> f32 {
        self.velocity
            .iter()
            .map(|v| (v[0] * v[0] + v[1] * v[1]).sqrt())
            .fold(0.0, f32::max)
    }

    /// The divergence (1/s) of the face velocities per cell, on the solver's own stencil:
    /// (u(i+1) − u(i) + v(j+1) − v(j)) / h + (w(k+1) − w(k)) / dy. Computed in f64 so that
    /// the measure adds no rounding of its own.
    pub fn face_divergence(&self) -> Vec<f64> {
        let n = self.resolution as usize;
        let layers = self.layers.max(1) as usize;
        let h = f64::from(self.cell_size);
        let dy = f64::from(self.layer_height);
        let (lu, plane) = (n * (n + 1), n * n);
        let mut out = Vec::with_capacity(plane * layers);
        for k in 0..layers {
            for j in 0..n {
                for i in 0..n {
                    let u = |i: usize| f64::from(self.u[k * lu + j * (n + 1) + i]);
                    let v = |j: usize| f64::from(self.v[k * lu + j * n + i]);
                    let w = |k: usize| {
                        self.w
                            .get(k * plane + j * n + i)
                            .map_or(0.0, |w| f64::from(*w))
                    };
                    let dw = if layers > 1 {
                        (w(k + 1) - w(k)) / dy
                    } else {
                        0.0
                    };
                    out.push((u(i + 1) - u(i) + v(j + 1) - v(j)) / h + dw);
                }
            }
        }
        out
    }

    /// Root-mean-square divergence (1/s) of the faces after the step, over the fluid
    /// cells: what the projection left. 0 without fluid cells.
    pub fn rms_divergence(&self) -> f64 {
        let d = self.face_divergence();
        rms(d
            .iter()
            .zip(&self.solid)
            .filter(|(_, &s)| s == 0)
            .map(|(d, _)| *d))
    }

    /// Root-mean-square of the divergence that entered the last pressure solve, over the
    /// fluid cells: what the projection started from.
    pub fn rms_divergence_before(&self) -> f64 {
        rms(self
            .divergence
            .iter()
            .zip(&self.solid)
            .filter(|(_, &s)| s == 0)
            .map(|(d, _)| f64::from(*d)))
    }
}

fn rms(values: impl Iterator<Item = f64>) -> f64 {
    let (sum, count) = values.fold((0.0, 0usize), |(s, c), x| (s + x * x, c + 1));
    if count == 0 {
        0.0
    } else {
        (sum / count as f64).sqrt()
    }
}
