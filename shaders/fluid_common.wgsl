// Shared structs, grid indexing and boundary helpers of the Stable-Fluids wind solver,
// included by every `fluid_*.wgsl` entry file with `//!include fluid_common.wgsl`. The
// structs have #[repr(C)] twins with size assertions in src/sim/wind_layout.rs; the helpers
// have CPU twins of the same names in src/sim/reference/fluid/grid.rs.
//
// The grid is staggered (MAC, Harlow & Welch 1965): n × n cells, cell (i, j) spans
// origin + [i, i + 1] × [j, j + 1] · h. Pressure, divergence, curl and the solid mask live
// at cell centres (row-major, x fastest). The velocity lives on the faces, in one
// `array<f32>`: first u (along +x) on the vertical faces, (n + 1) · n of them, face (i, j)
// at x = i h, z = (j + ½) h, index j (n + 1) + i; then v (along +z) on the horizontal faces,
// n · (n + 1), face (i, j) at x = (i + ½) h, z = j h, index n (n + 1) + j n + i. "Axis" 0 is
// u, 1 is v. Positions inside kernels are in cell units from the grid corner.
//
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
    // Vorticity confinement ε (1/s); the force is ε h (N × ω).
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

// A face-kernel thread: gid.z is the axis, gid.xy the face (i, j). `valid` is false for the
// threads of the padded dispatch beyond the faces of their axis.
struct FluidFace {
    axis: u32,
    i: i32,
    j: i32,
    valid: bool,
}

fn fluid_face(gid: vec3<u32>, n: u32) -> FluidFace {
    let ni = select(n + 1u, n, gid.z == 1u);
    let nj = select(n, n + 1u, gid.z == 1u);
    return FluidFace(gid.z, i32(gid.x), i32(gid.y), gid.x < ni && gid.y < nj);
}

// The face whose value a thread computes: on a periodic grid the last face of an axis
// (i = n for u, j = n for v) is the first one again, so it computes face 0's value and the
// two copies stay bit-identical.
fn fluid_canonical(f: FluidFace, n: i32, boundary: u32) -> FluidFace {
    var c = f;
    if boundary == FLUID_PERIODIC {
        if f.axis == 0u && f.i == n {
            c.i = 0;
        }
        if f.axis == 1u && f.j == n {
            c.j = 0;
        }
    }
    return c;
}

fn fluid_face_index(axis: u32, i: i32, j: i32, n: i32) -> u32 {
    if axis == 0u {
        return u32(j * (n + 1) + i);
    }
    return u32(n * (n + 1) + j * n + i);
}

// Whether face (axis, i, j) lies on the border of a closed grid (its velocity is the wall's,
// 0, whatever the passes compute).
fn fluid_is_wall(axis: u32, i: i32, j: i32, n: i32, boundary: u32) -> bool {
    if boundary != FLUID_CLOSED {
        return false;
    }
    if axis == 0u {
        return i == 0 || i == n;
    }
    return j == 0 || j == n;
}

// Where to read face (axis, i, j), which may be outside the stored range: wrapped when
// periodic, else the nearest stored face of the axis (zero gradient: the tangential
// velocity slips along a closed wall and continues past an open border).
fn fluid_face_ref(axis: u32, i: i32, j: i32, n: i32, boundary: u32) -> u32 {
    if boundary == FLUID_PERIODIC {
        return fluid_face_index(axis, fluid_wrap(i, n), fluid_wrap(j, n), n);
    }
    let ni = select(n, n - 1, axis == 1u);
    let nj = select(n - 1, n, axis == 1u);
    return fluid_face_index(axis, clamp(i, 0, ni), clamp(j, 0, nj), n);
}

// The two cells a face separates: (i − 1, j) and (i, j) for u, (i, j − 1) and (i, j) for v.
fn fluid_face_cells(axis: u32, i: i32, j: i32) -> vec4<i32> {
    if axis == 0u {
        return vec4<i32>(i - 1, j, i, j);
    }
    return vec4<i32>(i, j - 1, i, j);
}

// The cell index of (i, j), wrapped when periodic; -1 outside a closed or open grid.
fn fluid_cell_ref(i: i32, j: i32, n: i32, boundary: u32) -> i32 {
    if boundary == FLUID_PERIODIC {
        return fluid_wrap(j, n) * n + fluid_wrap(i, n);
    }
    if i < 0 || i >= n || j < 0 || j >= n {
        return -1;
    }
    return j * n + i;
}

// Position of face (axis, i, j) in cell units.
fn fluid_face_pos(axis: u32, i: i32, j: i32) -> vec2<f32> {
    if axis == 0u {
        return vec2<f32>(f32(i), f32(j) + 0.5);
    }
    return vec2<f32>(f32(i) + 0.5, f32(j));
}

// The four faces of one axis around a position (cell units) and the bilinear weights:
// faces a (i, j), b (i + 1, j), d (i, j + 1), e (i + 1, j + 1) of the axis' own lattice.
struct FluidStencil {
    index: vec4<u32>,
    f: vec2<f32>,
}

fn fluid_stencil(axis: u32, pos: vec2<f32>, n: i32, boundary: u32) -> FluidStencil {
    var g = pos - vec2<f32>(0.0, 0.5);
    if axis == 1u {
        g = pos - vec2<f32>(0.5, 0.0);
    }
    let c = floor(g);
    let i = i32(c.x);
    let j = i32(c.y);
    let index = vec4<u32>(
        fluid_face_ref(axis, i, j, n, boundary),
        fluid_face_ref(axis, i + 1, j, n, boundary),
        fluid_face_ref(axis, i, j + 1, n, boundary),
        fluid_face_ref(axis, i + 1, j + 1, n, boundary),
    );
    return FluidStencil(index, g - c);
}

// Bilinear blend of the stencil's four values, spelled out instead of mix(): mix's formula
// is up to the implementation and the CPU twin must round the same way.
fn fluid_blend(a: f32, b: f32, d: f32, e: f32, f: vec2<f32>) -> f32 {
    let bottom = a + (b - a) * f.x;
    let top = d + (e - d) * f.x;
    return bottom + (top - bottom) * f.y;
}

// A back-traced point stays on the grid unless it wraps: closed and open grids clamp it to
// the outer edge, where the face lookups give the wall (closed: the normal component is 0)
// or the edge value (open).
fn fluid_clamp_pos(pos: vec2<f32>, n: i32, boundary: u32) -> vec2<f32> {
    if boundary == FLUID_PERIODIC {
        return pos;
    }
    return min(max(pos, vec2<f32>(0.0, 0.0)), vec2<f32>(f32(n), f32(n)));
}

// Where to read the cell-centred velocity of cell (i, j), which may lie outside the grid,
// and the sign to multiply it by. Closed: the mirror image across the wall (the edge cell
// with the normal component negated). Open: the edge cell unchanged. Periodic: wrapped.
struct FluidVelocityRef {
    i: i32,
    j: i32,
    sign: vec2<f32>,
}

fn fluid_velocity_ref(i: i32, j: i32, n: i32, boundary: u32) -> FluidVelocityRef {
    if boundary == FLUID_PERIODIC {
        return FluidVelocityRef(fluid_wrap(i, n), fluid_wrap(j, n), vec2<f32>(1.0, 1.0));
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
    return FluidVelocityRef(clamp(i, 0, n - 1), clamp(j, 0, n - 1), sign);
}

// Index of a cell scalar (the curl) at (i, j): wrapped when periodic, else the edge cell.
fn fluid_scalar_index(i: i32, j: i32, n: i32, boundary: u32) -> u32 {
    if boundary == FLUID_PERIODIC {
        return u32(fluid_wrap(j, n) * n + fluid_wrap(i, n));
    }
    return u32(clamp(j, 0, n - 1) * n + clamp(i, 0, n - 1));
}

// Pressure outside an open border is 0 (Dirichlet: the air outside is at rest pressure, so
// flow can leave); closed borders and solid cells are Neumann walls (their faces have
// weight 0 in the Laplacian and are not pushed by the gradient).
