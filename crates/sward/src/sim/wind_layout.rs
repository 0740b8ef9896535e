//! `#[repr(C)]` Pod twins of the wind solver's WGSL structs (`shaders/fluid_common.wgsl`),
//! with size assertions, and the host-side description of one solver step.

use bytemuck::{Pod, Zeroable};

/// Most AGC arrows uploaded per frame.
pub const MAX_ARROWS: usize = 256;
/// Most obstacles (collider footprints) per frame.
pub const MAX_OBSTACLES: usize = 1024;
/// Workgroup size of the 2D fluid passes (8 × 8).
pub const FLUID_WORKGROUP: u32 = 8;

/// One AGC arrow as the splat pass reads it.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct ArrowGpu {
    /// Start (x, z) and end (x, z) in world metres.
    pub segment: [f32; 4],
    /// Acceleration along the arrow in m/s² (already scaled by the activation ramp).
    pub strength: f32,
    /// Half-width of the pushed band in metres.
    pub radius: f32,
    /// How far the AGC sequence has switched the arrow on (0–1). The splat pass ignores
    /// it (`strength` is already scaled); the overlay draws off arrows grey.
    pub activation: f32,
    /// Padding to 32 bytes (`pad` in the WGSL structs).
    pub _pad: f32,
}

/// A collider footprint: cells inside it are solid and move with the collider.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct ObstacleGpu {
    /// x, z centre, radius, the centre's height above the ground under it (read by a 3D
    /// grid only, whose cells are solid inside the sphere; a 2D grid takes the circle).
    pub circle: [f32; 4],
    /// x, z, y velocity in m/s, unused.
    pub velocity: [f32; 4],
}

/// Uniforms of one multigrid level (`MgParams` in `shaders/fluid_multigrid.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct MgParams {
    /// Cells per side of the level.
    pub size: u32,
    /// 0 closed, 1 open, 2 periodic.
    pub boundary: u32,
    /// H² of the level in m² (H = the finest cell size · 2^level).
    pub h2: f32,
    /// The colour a red-black sweep updates: cells with (i + j) % 2 == colour.
    pub colour: u32,
    /// Factor on the open-border face weights of the next coarser level
    /// (`reference::fluid::multigrid::border_scale`).
    pub border_scale: f32,
    /// What `prolong` multiplies the next coarser level's edge value by for a cell beyond
    /// an open border (`reference::fluid::multigrid::open_ghost`).
    pub open_ghost: f32,
    /// Layers of the grid (every level has them all).
    pub layers: u32,
    /// H² / dy²: the weight of a vertical face relative to a horizontal one.
    pub vertical: f32,
}

/// Uniforms of every fluid pass.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct FluidParams {
    /// x, z of the grid's corner (cell (0,0)'s outer corner), cell size, 1 / cell size.
    pub origin_cell: [f32; 4],
    /// Global force x, z (m/s²); downwash radius, downwash strength.
    pub global_downwash: [f32; 4],
    /// Downwash centre x, z; unused ×2.
    pub downwash_pos: [f32; 4],
    /// Cells per side of the grid.
    pub resolution: u32,
    /// Δt of this step in seconds.
    pub dt: f32,
    /// Vorticity confinement ε in 1/s (the shader multiplies by h).
    pub vorticity: f32,
    /// Velocity dissipation per second (v /= 1 + dissipation · Δt after advection).
    pub dissipation: f32,
    /// ν Δt / h² of the diffusion Jacobi step.
    pub diffusion_alpha: f32,
    /// 0 closed, 1 open, 2 periodic.
    pub boundary: u32,
    /// AGC arrows in the arrow buffer this step (at most [`MAX_ARROWS`]).
    pub arrow_count: u32,
    /// Obstacles in the obstacle buffer this step (at most [`MAX_OBSTACLES`]).
    pub obstacle_count: u32,
    /// dy (layer thickness, m), 1/dy, νΔt/dy² (0 on a 2D grid), ground drag (1/s, 0 on
    /// a 2D grid).
    pub layer: [f32; 4],
    /// Layers of air (1 = a 2D grid).
    pub layers: u32,
    /// Padding to a 16-byte multiple (`pad_a` .. `pad_c` in WGSL).
    pub _pad: [u32; 3],
}

const _: () = assert!(std::mem::size_of::<ArrowGpu>() == 32);
const _: () = assert!(std::mem::size_of::<ObstacleGpu>() == 32);
const _: () = assert!(std::mem::size_of::<FluidParams>() == 112);
const _: () = assert!(std::mem::size_of::<MgParams>() == 32);

/// Everything that pushes the air during one step, in world units.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FluidForces {
    /// The AGC arrows, strengths already scaled by their activation (the first
    /// [`MAX_ARROWS`] are uploaded).
    pub arrows: Vec<ArrowGpu>,
    /// The colliders' footprints (the first [`MAX_OBSTACLES`] are uploaded).
    pub obstacles: Vec<ObstacleGpu>,
    /// Constant acceleration (x, z) in m/s².
    pub global: [f32; 2],
    /// Downwash centre (x, z), radius, strength; radius 0 = none.
    pub downwash: [f32; 4],
}
