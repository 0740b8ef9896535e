// Shared structs, grid indexing and boundary helpers of the Stable-Fluids wind solver,
// included by every `fluid_*.wgsl` entry file with `//!include fluid_common.wgsl`. The
// structs have #[repr(C)] twins with size assertions in src/sim/wind_layout.rs; the helpers
// have CPU twins of the same names in src/sim/reference/fluid/grid.rs.
//
// The grid is staggered (MAC, Harlow & Welch 1965): n × n cells per layer and L layers
// (L = 1: the 2D solver). Cell (i, j, k) spans origin + [i, i + 1] × [j, j + 1] · h in x, z
// and [k, k + 1] · dy above the ground under it (the layers follow the terrain). Pressure,
// divergence, curl and the solid mask live at cell centres, index k n² + j n + i. The
// velocity lives on the faces, in one `array<f32>`: first u (along +x) on the vertical
// faces normal to x, (n + 1) · n per layer, face (i, j, k) at x = i h, z = (j + ½) h, index
// k U + j (n + 1) + i with U = n (n + 1); then v (along +z), n · (n + 1) per layer, face
// (i, j, k) at x = (i + ½) h, z = j h, index L U + k U + j n + i; then w (up), n² on each of
// the L + 1 horizontal planes, face (i, j, k) at height k dy, index 2 L U + k n² + j n + i.
// The planes k = 0 (the ground) and k = L (the top) are closed. "Axis" 0 is u, 1 is v, 2 is
// w. Positions inside kernels are in cell units from the grid corner: (x / h, z / h,
// height / dy).
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
    // dy, 1 / dy, ν Δt / dy² of the vertical diffusion (0 in 2D), ground drag (1/s, 0 in 2D).
    layer: vec4<f32>,
    layers: u32,
    pad_a: u32,
    pad_b: u32,
    pad_c: u32,
}

struct FluidArrow {
    // Start x, z and end x, z in metres.
    segment: vec4<f32>,
    strength: f32,
    radius: f32,
    pad: vec2<f32>,
}

struct FluidObstacle {
    // Centre x, z, radius, centre height above the ground (3D grids).
    circle: vec4<f32>,
    // Velocity x, z, y, unused.
    velocity: vec4<f32>,
}

const FLUID_CLOSED: u32 = 0u;
const FLUID_OPEN: u32 = 1u;
const FLUID_PERIODIC: u32 = 2u;

// Index in [0, n) for any i (i32 `%` truncates, so add n once and take it again).
fn fluid_wrap(i: i32, n: i32) -> i32 {
    return ((i % n) + n) % n;
}

// A face-kernel thread: gid.xy is the face (i, j), gid.z = axis + 3 k. `valid` is false for
// the threads of the padded dispatch beyond the faces of their axis.
struct FluidFace {
    axis: u32,
    i: i32,
    j: i32,
    k: i32,
    valid: bool,
}

fn fluid_face(gid: vec3<u32>, n: u32, layers: u32) -> FluidFace {
    let axis = gid.z % 3u;
    let k = gid.z / 3u;
    let ni = select(n + 1u, n, axis != 0u);
    let nj = select(n, n + 1u, axis == 1u);
    let nk = select(layers, layers + 1u, axis == 2u);
    return FluidFace(axis, i32(gid.x), i32(gid.y), i32(k), gid.x < ni && gid.y < nj && k < nk);
}

// Workgroups along z of a face dispatch: 3 L, or 2 on a 2D grid (`fluid::face_slices`:
// the ceiling's w, and a 2D grid's ground, are walls no pass writes).

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

fn fluid_face_index(axis: u32, i: i32, j: i32, k: i32, n: i32, layers: i32) -> u32 {
    let per_layer = n * (n + 1);
    if axis == 0u {
        return u32(k * per_layer + j * (n + 1) + i);
    }
    if axis == 1u {
        return u32(layers * per_layer + k * per_layer + j * n + i);
    }
    return u32(2 * layers * per_layer + k * n * n + j * n + i);
}

// Whether face (axis, i, j, k) lies on the border of a closed grid, or on the ground or the
// top (its velocity is the wall's, 0, whatever the passes compute).
fn fluid_is_wall(axis: u32, i: i32, j: i32, k: i32, n: i32, layers: i32, boundary: u32) -> bool {
    if axis == 2u {
        return k == 0 || k == layers;
    }
    if boundary != FLUID_CLOSED {
        return false;
    }
    if axis == 0u {
        return i == 0 || i == n;
    }
    return j == 0 || j == n;
}

// Where to read face (axis, i, j, k), which may be outside the stored range: wrapped in x, z
// when periodic, else the nearest stored face of the axis (zero gradient: the tangential
// velocity slips along a closed wall, the ground and the top, and continues past an open
// border).
fn fluid_face_ref(axis: u32, i: i32, j: i32, k: i32, n: i32, layers: i32, boundary: u32) -> u32 {
    let nk = select(layers - 1, layers, axis == 2u);
    let kk = clamp(k, 0, nk);
    if boundary == FLUID_PERIODIC {
        return fluid_face_index(axis, fluid_wrap(i, n), fluid_wrap(j, n), kk, n, layers);
    }
    let ni = select(n - 1, n, axis == 0u);
    let nj = select(n - 1, n, axis == 1u);
    return fluid_face_index(axis, clamp(i, 0, ni), clamp(j, 0, nj), kk, n, layers);
}

// The two cells a face separates: (i − 1, j, k) and (i, j, k) for u, (i, j − 1, k) and
// (i, j, k) for v, (i, j, k − 1) and (i, j, k) for w; as two vec3 (lo, hi).
struct FluidPair {
    lo: vec3<i32>,
    hi: vec3<i32>,
}

fn fluid_face_cells(axis: u32, i: i32, j: i32, k: i32) -> FluidPair {
    if axis == 0u {
        return FluidPair(vec3<i32>(i - 1, j, k), vec3<i32>(i, j, k));
    }
    if axis == 1u {
        return FluidPair(vec3<i32>(i, j - 1, k), vec3<i32>(i, j, k));
    }
    return FluidPair(vec3<i32>(i, j, k - 1), vec3<i32>(i, j, k));
}

// The cell index of (i, j, k), wrapped in x, z when periodic; -1 below the ground, above
// the top, and outside a closed or open grid.
fn fluid_cell_ref(c: vec3<i32>, n: i32, layers: i32, boundary: u32) -> i32 {
    if c.z < 0 || c.z >= layers {
        return -1;
    }
    if boundary == FLUID_PERIODIC {
        return c.z * n * n + fluid_wrap(c.y, n) * n + fluid_wrap(c.x, n);
    }
    if c.x < 0 || c.x >= n || c.y < 0 || c.y >= n {
        return -1;
    }
    return c.z * n * n + c.y * n + c.x;
}

// Position of face (axis, i, j, k) in cell units (x, z, height).
fn fluid_face_pos(axis: u32, i: i32, j: i32, k: i32) -> vec3<f32> {
    if axis == 0u {
        return vec3<f32>(f32(i), f32(j) + 0.5, f32(k) + 0.5);
    }
    if axis == 1u {
        return vec3<f32>(f32(i) + 0.5, f32(j), f32(k) + 0.5);
    }
    return vec3<f32>(f32(i) + 0.5, f32(j) + 0.5, f32(k));
}

// The eight faces of one axis around a position (cell units) and the trilinear weights:
// faces a (i, j), b (i + 1, j), d (i, j + 1), e (i + 1, j + 1) of the axis' own lattice in
// layer (or plane) k, then the same four in k + 1. On a 2D grid the two layers are the same
// and f.z is 0, so the blend is the bilinear one exactly.
struct FluidStencil {
    lower: vec4<u32>,
    upper: vec4<u32>,
    f: vec3<f32>,
}

fn fluid_stencil(axis: u32, pos: vec3<f32>, n: i32, layers: i32, boundary: u32) -> FluidStencil {
    var g = pos - vec3<f32>(0.0, 0.5, 0.5);
    if axis == 1u {
        g = pos - vec3<f32>(0.5, 0.0, 0.5);
    }
    if axis == 2u {
        g = pos - vec3<f32>(0.5, 0.5, 0.0);
    }
    let c = floor(g);
    let i = i32(c.x);
    let j = i32(c.y);
    let k = i32(c.z);
    let lower = vec4<u32>(
        fluid_face_ref(axis, i, j, k, n, layers, boundary),
        fluid_face_ref(axis, i + 1, j, k, n, layers, boundary),
        fluid_face_ref(axis, i, j + 1, k, n, layers, boundary),
        fluid_face_ref(axis, i + 1, j + 1, k, n, layers, boundary),
    );
    let upper = vec4<u32>(
        fluid_face_ref(axis, i, j, k + 1, n, layers, boundary),
        fluid_face_ref(axis, i + 1, j, k + 1, n, layers, boundary),
        fluid_face_ref(axis, i, j + 1, k + 1, n, layers, boundary),
        fluid_face_ref(axis, i + 1, j + 1, k + 1, n, layers, boundary),
    );
    // Below the first stored layer of an axis the lookups clamp to it: the vertical
    // fraction is then 0 (a 2D grid's u and v sit at height ½ with c.z = 0, f.z = 0).
    return FluidStencil(lower, upper, g - c);
}

// Bilinear blend of four values, spelled out instead of mix(): mix's formula is up to the
// implementation and the CPU twin must round the same way.
fn fluid_blend(a: f32, b: f32, d: f32, e: f32, f: vec2<f32>) -> f32 {
    let bottom = a + (b - a) * f.x;
    let top = d + (e - d) * f.x;
    return bottom + (top - bottom) * f.y;
}

// Trilinear blend of the stencil's values in `q`: bilinear in each layer, then linear
// between the layers.
fn fluid_blend3(lower: vec4<f32>, upper: vec4<f32>, f: vec3<f32>) -> f32 {
    let lo = fluid_blend(lower.x, lower.y, lower.z, lower.w, f.xy);
    let hi = fluid_blend(upper.x, upper.y, upper.z, upper.w, f.xy);
    return lo + (hi - lo) * f.z;
}

// A back-traced point stays on the grid unless it wraps (in x, z): closed and open grids
// clamp it to the outer edge, where the face lookups give the wall (closed: the normal
// component is 0) or the edge value (open); the height is always clamped between the
// ground and the top.
fn fluid_clamp_pos(pos: vec3<f32>, n: i32, layers: i32, boundary: u32) -> vec3<f32> {
    let y = clamp(pos.z, 0.0, f32(layers));
    if boundary == FLUID_PERIODIC {
        return vec3<f32>(pos.xy, y);
    }
    return vec3<f32>(min(max(pos.xy, vec2<f32>(0.0, 0.0)), vec2<f32>(f32(n), f32(n))), y);
}

// Where to read the cell-centred velocity of cell (i, j) of a layer, which may lie outside
// the grid, and the sign to multiply it by. Closed: the mirror image across the wall (the
// edge cell with the normal component negated). Open: the edge cell unchanged. Periodic:
// wrapped.
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

// Index of a cell scalar (the curl) at (i, j) of layer k: wrapped when periodic, else the
// edge cell.
fn fluid_scalar_index(i: i32, j: i32, k: i32, n: i32, boundary: u32) -> u32 {
    if boundary == FLUID_PERIODIC {
        return u32(k * n * n + fluid_wrap(j, n) * n + fluid_wrap(i, n));
    }
    return u32(k * n * n + clamp(j, 0, n - 1) * n + clamp(i, 0, n - 1));
}

// Pressure outside an open border is 0 (Dirichlet: the air outside is at rest pressure, so
// flow can leave); closed borders, the ground, the top and solid cells are Neumann walls
// (their faces have weight 0 in the Laplacian and are not pushed by the gradient). Each
// cell has two vec4 of face weights, index 2 c: (−x, +x, −z, +z), index 2 c + 1: (below,
// above, 0, 0).
