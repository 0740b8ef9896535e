//! The scene file's wind: the analytic winds of Jahrmann & Wimmer, the Stable-Fluids grid
//! (`Fluid`, 2D or layered 3D), the AGC guides, the global wind and the downwash.

use serde::{Deserialize, Serialize};

use super::{default_motion, Motion};

/// Directional wind waves (Section 5.1): a sum of travelling sine waves along `direction`.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct DirectionalWind {
    /// Direction in the x/z plane (normalised on load).
    pub direction: (f32, f32),
    /// Mean force in m/s².
    pub strength: f32,
    /// Gust amplitude relative to `strength`.
    pub gust: f32,
    /// Wave length of the gusts in metres.
    pub wavelength: f32,
    /// Speed of the wave fronts in m/s.
    pub speed: f32,
}

impl Default for DirectionalWind {
    fn default() -> Self {
        Self {
            direction: (1.0, 0.3),
            strength: 2.0,
            gust: 0.8,
            wavelength: 9.0,
            speed: 4.0,
        }
    }
}

/// A point wind source (a fan, a helicopter's downwash): radial outflow with pulsing rings.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct PointWind {
    /// Where the source is, in metres (each component within ±100000 m).
    pub position: (f32, f32, f32),
    /// Force at the source in m/s².
    pub strength: f32,
    /// Distance in metres beyond which the source has no effect.
    pub radius: f32,
    /// Pulses per second of the rings moving outwards.
    pub frequency: f32,
}

impl Default for PointWind {
    fn default() -> Self {
        Self {
            position: (0.0, 3.0, 0.0),
            strength: 6.0,
            radius: 8.0,
            frequency: 1.5,
        }
    }
}

/// Which wind the blades feel.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
pub enum WindSource {
    /// The paper's analytic functions (`directional`, `point`).
    #[default]
    Analytic,
    /// The Stable-Fluids grid driven by `guides`, `global`, `downwash` and the colliders.
    Fluid,
    /// Both added.
    Both,
}

/// How the fluid grid treats its border.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
pub enum Boundary {
    /// Walls: no flow through the border.
    Closed,
    /// Air leaves and enters freely (zero pressure outside).
    #[default]
    Open,
    /// What leaves one side enters the opposite one.
    Periodic,
}

/// How the pressure Poisson equation of the projection is solved.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
pub enum PressureSolver {
    /// `pressure_iterations` Jacobi iterations (slow to remove smooth divergence).
    Jacobi,
    /// `multigrid_cycles` V-cycles (red-black Gauss–Seidel smoothing on a grid hierarchy).
    #[default]
    Multigrid,
}

/// How the velocity is carried along itself.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
pub enum Advection {
    /// One semi-Lagrangian back-trace (Stam): stable, smears small swirls.
    #[default]
    SemiLagrangian,
    /// MacCormack (Selle et al. 2008): a forward and a backward trace cancel most of the
    /// smearing; clamped to the values it interpolated from, so it cannot overshoot.
    MacCormack,
}

/// The Stable-Fluids wind solver (CWD-Sim Eq. 4–10, Stam's solver) on a square staggered
/// (MAC) grid laid over the terrain; the cell size is the terrain size / resolution.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct Fluid {
    /// Cells per side (the grid is resolution²).
    pub resolution: u32,
    /// How the pressure is solved.
    pub pressure_solver: PressureSolver,
    /// Jacobi iterations of the pressure solve (`pressure_solver: Jacobi`); with
    /// `warm_start` an odd count runs one more (see `FluidConfig::jacobi_iterations`).
    pub pressure_iterations: u32,
    /// V-cycles of the pressure solve (`pressure_solver: Multigrid`); with `warm_start` an
    /// odd count runs one more.
    pub multigrid_cycles: u32,
    /// Start the pressure solve from the last frame's pressure.
    pub warm_start: bool,
    /// Vorticity confinement ε in 1/s: the force is ε h (N × ω) (Fedkiw et al. 2001), with
    /// h the cell size, so that a scene swirls alike at any grid resolution.
    pub vorticity: f32,
    /// Velocity dissipation per second (v /= 1 + dissipation · Δt after advection).
    pub dissipation: f32,
    /// Kinematic viscosity ν in m²/s; 0 skips the diffusion pass.
    pub viscosity: f32,
    /// Jacobi iterations of the viscous diffusion.
    pub diffusion_iterations: u32,
    /// How the grid's border treats the air: `Closed`, `Open` (the default) or `Periodic`.
    pub boundary: Boundary,
    /// How the velocity is carried along itself: `SemiLagrangian` (the default) or
    /// `MacCormack`.
    pub advection: Advection,
    /// Wind force on a blade per m/s of air speed (1/s): w_i = response · velocity.
    pub response: f32,
    /// CWD-Sim's grouping: every blade of a cell takes the cell's value (no interpolation).
    pub per_cell: bool,
    /// Colliders block the air (their footprint cells take the collider's velocity).
    pub obstacles: bool,
    /// Side in metres of a grid that follows the camera (scrolling by whole cells; the
    /// cells that enter take the old grid's edge values), or 0: the grid covers the terrain
    /// square. For unbounded terrains, where a terrain-sized grid would have huge cells.
    pub extent: f32,
    /// Layers of air over the terrain (1 = the 2D solver). With more, the grid is 3D:
    /// layers of `layer_height` that follow the terrain (layer k spans k·dy to (k+1)·dy above
    /// the ground under it), the ground and the top of the last layer closed, a vertical
    /// velocity w on the faces between layers; blades read the layer at their own height.
    pub layers: u32,
    /// Thickness dy of one layer in metres (3D grid only).
    pub layer_height: f32,
    /// Drag of the ground and the grass on the air in 1/s, felt by the horizontal wind of
    /// layer k as c / (k + ½) (strongest at the ground, fading upwards like the log profile
    /// of a boundary layer), so that the wind grows with the height and tall grass bends
    /// more. 3D grid only (one layer has no height to grow over).
    pub ground_drag: f32,
}

impl Default for Fluid {
    fn default() -> Self {
        Self {
            resolution: 256,
            pressure_solver: PressureSolver::Multigrid,
            pressure_iterations: 30,
            multigrid_cycles: 2,
            warm_start: true,
            // 1.5 / h of the default grid (40 m / 256): the confinement the collocated
            // solver's λ = 1.5 gave there, before the h factor.
            vorticity: 9.6,
            dissipation: 0.15,
            viscosity: 0.0,
            diffusion_iterations: 20,
            boundary: Boundary::Open,
            advection: Advection::SemiLagrangian,
            response: 1.2,
            per_cell: false,
            obstacles: true,
            extent: 0.0,
            layers: 1,
            layer_height: 0.5,
            ground_drag: 2.0,
        }
    }
}

/// One point of an AGC guide. Point 0 is the root; every other point names its parent, and
/// the edge parent → point is an arrow that pushes the air along it.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct GuidePoint {
    /// (x, z) on the terrain.
    pub position: (f32, f32),
    /// Index of the parent point in the guide's list (None only for the root, point 0).
    #[serde(default)]
    pub parent: Option<usize>,
    /// Overrides the guide's strength for the arrow that ends at this point.
    #[serde(default)]
    pub strength: Option<f32>,
    /// Overrides the guide's radius for the arrow that ends at this point.
    #[serde(default)]
    pub radius: Option<f32>,
}

/// An Arrow-Guided wind Control guide (CWD-Sim Section 3.5): a tree of points.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Guide {
    /// Acceleration the arrows give the air, in m/s².
    pub strength: f32,
    /// Half-width of the band each arrow pushes, in metres.
    pub radius: f32,
    /// The tree's points, root first: at least one, and every parent before its children.
    pub points: Vec<GuidePoint>,
    /// Scene time in seconds at which this guide's sequence starts (see `sim::agc`): 0 for
    /// a guide loaded with the scene, the time of creation for one added in the editor, the
    /// time of the click for "replay the sequence". Not saved: a loaded guide starts when
    /// its scene does.
    #[serde(skip)]
    pub started: f32,
}

/// A constant push on the whole fluid grid.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct GlobalWind {
    /// Direction in the x/z plane (normalised on load).
    pub direction: (f32, f32),
    /// Acceleration in m/s².
    pub strength: f32,
}

/// What `--set wind.global.strength=..` fills in when the scene has no global wind.
impl Default for GlobalWind {
    fn default() -> Self {
        Self {
            direction: (1.0, 0.0),
            strength: 2.0,
        }
    }
}

/// Radial outflow under a (moving) point: a helicopter's downwash or a fan pointing down.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Downwash {
    /// Where the source is at t = 0 (for `Path`, y is the height above the ground).
    pub position: (f32, f32, f32),
    /// Radius of the outflow in metres.
    pub radius: f32,
    /// Outward acceleration in m/s² at half the radius.
    pub strength: f32,
    /// How the source moves; `Static` when left out.
    #[serde(default = "default_motion")]
    pub motion: Motion,
}

/// What `--set wind.downwash.strength=..` fills in when the scene has no downwash: a
/// source 4 m above the centre of the field.
impl Default for Downwash {
    fn default() -> Self {
        Self {
            position: (0.0, 4.0, 0.0),
            radius: 4.0,
            strength: 20.0,
            motion: Motion::Static,
        }
    }
}

/// The wind: the paper's analytic functions and/or the fluid grid with its forces.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct Wind {
    /// Which wind the blades feel: `Analytic` (the default), `Fluid` or `Both`.
    pub source: WindSource,
    /// The analytic directional wind waves, felt with `source: Analytic` or `Both`; on by
    /// default, `None` turns them off.
    pub directional: Option<DirectionalWind>,
    /// An analytic point source, felt with `source: Analytic` or `Both`; `None` (the
    /// default): none.
    pub point: Option<PointWind>,
    /// The fluid grid's settings, used with `source: Fluid` or `Both`.
    pub fluid: Fluid,
    /// AGC guides whose arrows push the fluid's air along them; empty by default.
    pub guides: Vec<Guide>,
    /// A constant push on the whole fluid grid; `None` (the default): none.
    pub global: Option<GlobalWind>,
    /// Radial outflow of the fluid's air under a (moving) point; `None` (the default):
    /// none.
    pub downwash: Option<Downwash>,
}

impl Default for Wind {
    fn default() -> Self {
        Self {
            source: WindSource::Analytic,
            directional: Some(DirectionalWind::default()),
            point: None,
            fluid: Fluid::default(),
            guides: Vec::new(),
            global: None,
            downwash: None,
        }
    }
}
