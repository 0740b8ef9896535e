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
    pub diffusion_iterations: u32,
    pub boundary: Boundary,
    pub advection: Advection,
    /// The grid follows the camera ([`super::FluidSolver::follow`]): `origin` is only
    /// where it starts.
    pub follow: bool,
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
        }
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

    /// Cells in the grid.
    pub fn cells(&self) -> usize {
        self.resolution as usize * self.resolution as usize
    }

    /// Faces in the grid: (n + 1) · n carrying u, then n · (n + 1) carrying v.
    pub fn faces(&self) -> usize {
        2 * self.resolution as usize * (self.resolution as usize + 1)
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
                "fluid.resolution = {} is out of range: allowed {MIN_RESOLUTION} <= resolution \
                 <= {MAX_RESOLUTION} cells per side",
                self.resolution
            )));
        }
        if self.pressure_solver == PressureSolver::Multigrid
            && self.boundary == Boundary::Periodic
            && self.resolution % 2 == 1
        {
            return Err(Error::Invalid(format!(
                "fluid.resolution = {} is odd: the Multigrid pressure solver with a Periodic \
                 boundary needs an even resolution (or use pressure_solver: Jacobi)",
                self.resolution
            )));
        }
        if !(1..=MAX_MULTIGRID_CYCLES).contains(&self.multigrid_cycles) {
            return Err(Error::Invalid(format!(
                "fluid.multigrid_cycles = {} is out of range: allowed 1 <= multigrid_cycles \
                 <= {MAX_MULTIGRID_CYCLES}",
                self.multigrid_cycles
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

/// A snapshot of the solver's grids on the host (read-back or the CPU twin), after a step.
#[derive(Clone, Debug, PartialEq)]
pub struct FluidState {
    pub resolution: u32,
    pub cell_size: f32,
    pub origin: [f32; 2],
    /// Cell-centred (u, v) in m/s, row-major, x fastest: what the blades read.
    pub velocity: Vec<[f32; 2]>,
    /// u (m/s) on the vertical faces, (n + 1) · n, face (i, j) at index j (n + 1) + i.
    pub u: Vec<f32>,
    /// v (m/s) on the horizontal faces, n · (n + 1), face (i, j) at index j n + i.
    pub v: Vec<f32>,
    /// 0 = fluid, k + 1 = inside obstacle k, per cell.
    pub solid: Vec<u32>,
    /// Pressure of the last solve (in m²/s: the Δt/ρ factor is folded in).
    pub pressure: Vec<f32>,
    /// Divergence (1/s) of the velocity that entered the last pressure solve.
    pub divergence: Vec<f32>,
}

impl FluidState {
    /// Cell-centred velocity of cell (i, j).
    pub fn at(&self, i: u32, j: u32) -> [f32; 2] {
        self.velocity[(j * self.resolution + i) as usize]
    }

    /// Largest cell-centred speed in the grid, in m/s.
    pub fn max_speed(&self) -> f32 {
        self.velocity
            .iter()
            .map(|v| (v[0] * v[0] + v[1] * v[1]).sqrt())
            .fold(0.0, f32::max)
    }

    /// The divergence (1/s) of the face velocities `u`, `v` per cell, on the solver's own
    /// stencil: (u(i+1, j) − u(i, j) + v(i, j+1) − v(i, j)) / h. Computed in f64 so that
    /// the measure adds no rounding of its own.
    pub fn face_divergence(&self) -> Vec<f64> {
        let n = self.resolution as usize;
        let h = f64::from(self.cell_size);
        let mut out = Vec::with_capacity(n * n);
        for j in 0..n {
            for i in 0..n {
                let du =
                    f64::from(self.u[j * (n + 1) + i + 1]) - f64::from(self.u[j * (n + 1) + i]);
                let dv = f64::from(self.v[(j + 1) * n + i]) - f64::from(self.v[j * n + i]);
                out.push((du + dv) / h);
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
