// Wind step, pass 6 with `pressure_solver: Jacobi` (CWD-Sim Eq. 7 on the staggered grid):
// one Jacobi iteration of the pressure equation Σ w_k (p_k − p) = h² D, with w_k the face
// weights the splat pass wrote (0 towards solid cells and closed walls: Neumann; 1 towards
// fluid cells and the 0 pressure beyond an open border: Dirichlet),
// p' = (Σ w_k p_k − h² D) / Σ w_k, reading p_in and writing p_out (the solver ping-pongs two
// buffers, one dispatch per iteration). A cell with no open face (solid, or walled in)
// holds 0. CPU twin: `FluidCpu::pressure_jacobi`.
//!include fluid_common.wgsl

@group(0) @binding(0) var<uniform> params: FluidParams;
@group(0) @binding(1) var<storage, read> divergence: array<f32>;
@group(0) @binding(2) var<storage, read> p_in: array<f32>;
@group(0) @binding(3) var<storage, read_write> p_out: array<f32>;
@group(0) @binding(4) var<storage, read> weights: array<vec4<f32>>;

// Pressure of neighbour (i, j): 0 outside an open grid (a weight-0 face never reads it
// for closed grids).
fn p_at(i: i32, j: i32) -> f32 {
    let c = fluid_cell_ref(i, j, i32(params.resolution), params.boundary);
    if c < 0 {
        return 0.0;
    }
    return p_in[c];
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = params.resolution;
    if gid.x >= n || gid.y >= n {
        return;
    }
    let idx = gid.y * n + gid.x;
    let w = weights[idx];
    let total = w.x + w.y + w.z + w.w;
    if total == 0.0 {
        p_out[idx] = 0.0;
        return;
    }
    let i = i32(gid.x);
    let j = i32(gid.y);
    let h = params.origin_cell.z;
    let sum = w.x * p_at(i - 1, j) + w.y * p_at(i + 1, j) + w.z * p_at(i, j - 1)
        + w.w * p_at(i, j + 1);
    p_out[idx] = (sum - h * h * divergence[idx]) / total;
}
