// Shared structs and boundary helpers of the Stable-Fluids wind solver, included by every
// `fluid_*.wgsl` entry file with `//!include fluid_common.wgsl`. The structs have #[repr(C)]
// twins with size assertions in src/sim/wind_layout.rs; the helpers have CPU twins in
// src/sim/reference/fluid.rs (`velocity_ref`, `pressure_ref`, `scalar_index`).
//
// The grid is cell-centred (collocated): resolution² cells, row-major with x fastest, cell
// (i, j) centred at origin + (i + 0.5, j + 0.5) · h; velocity is (u along +x, v along +z).
// Names carry a `Fluid` / `fluid_` prefix so that a file including this one next to
// common.wgsl cannot collide with the blade structs.

struct FluidParams {
    // x, z of the grid corner, cell size h, 1 / h.
    origin_cell: vec4<f32>,
    // Global force x, z (m/s²), downwash radius, downwash strength.
    global_downwash: vec4<f32>,
    // Downwash centre x, z, unused ×2.
    downwash_pos: vec4<f32>,
    resolution: u32,
    dt: f32,
    vorticity: f32,
    dissipation: f32,
    // ν Δt / h² of the diffusion Jacobi step.
    diffusion_alpha: f32,
    boundary: u32,
    arrow_count: u32,
    obstacle_count: u32,
}

struct FluidArrow {
    // Start x, z and end x, z in metres.
    segment: vec4<f32>,
    strength: f32,
    radius: f32,
    pad: vec2<f32>,
}

struct FluidObstacle {
    // Centre x, z, radius, unused.
    circle: vec4<f32>,
    // Velocity x, z, unused ×2.
    velocity: vec4<f32>,
}

const FLUID_CLOSED: u32 = 0u;
const FLUID_OPEN: u32 = 1u;
const FLUID_PERIODIC: u32 = 2u;

// Index in [0, n) for any i (i32 `%` truncates, so add n once and take it again).
fn fluid_wrap(i: i32, n: i32) -> i32 {
    return ((i % n) + n) % n;
}

// Where to read the velocity of cell (i, j), which may lie outside the grid, and the sign
// to multiply it by. Closed: the mirror image across the wall (the edge cell with the normal
// component negated, so the wall-normal velocity interpolates to 0 on the wall). Open: the
// edge cell unchanged (zero gradient, air may cross). Periodic: the wrapped cell.
struct FluidVelocityRef {
    index: u32,
    sign: vec2<f32>,
}

fn fluid_velocity_ref(i: i32, j: i32, n: i32, boundary: u32) -> FluidVelocityRef {
    if boundary == FLUID_PERIODIC {
        return FluidVelocityRef(u32(fluid_wrap(j, n) * n + fluid_wrap(i, n)), vec2<f32>(1.0, 1.0));
    }
    var sign = vec2<f32>(1.0, 1.0);
    if boundary == FLUID_CLOSED {
        if i < 0 || i >= n {
            sign.x = -1.0;
        }
        if j < 0 || j >= n {
            sign.y = -1.0;
        }
    }
    let ci = clamp(i, 0, n - 1);
    let cj = clamp(j, 0, n - 1);
    return FluidVelocityRef(u32(cj * n + ci), sign);
}

// Where to read the pressure of cell (i, j). `inside` is false only for a cell outside an
// open border, whose pressure is 0 (Dirichlet: the air outside is at rest pressure, so flow
// can leave). Closed borders copy the edge cell (Neumann: no pressure push through walls).
struct FluidPressureRef {
    index: u32,
    inside: bool,
}

fn fluid_pressure_ref(i: i32, j: i32, n: i32, boundary: u32) -> FluidPressureRef {
    if boundary == FLUID_PERIODIC {
        return FluidPressureRef(u32(fluid_wrap(j, n) * n + fluid_wrap(i, n)), true);
    }
    let outside = i < 0 || i >= n || j < 0 || j >= n;
    let ci = clamp(i, 0, n - 1);
    let cj = clamp(j, 0, n - 1);
    return FluidPressureRef(u32(cj * n + ci), !(outside && boundary == FLUID_OPEN));
}

// Index of a scalar (the curl) at (i, j): wrapped when periodic, else the edge cell.
fn fluid_scalar_index(i: i32, j: i32, n: i32, boundary: u32) -> u32 {
    if boundary == FLUID_PERIODIC {
        return u32(fluid_wrap(j, n) * n + fluid_wrap(i, n));
    }
    return u32(clamp(j, 0, n - 1) * n + clamp(i, 0, n - 1));
}
