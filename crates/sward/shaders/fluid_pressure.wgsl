// Wind step, pass 6 with `pressure_solver: Jacobi` (CWD-Sim Eq. 7 on the staggered grid):
// one Jacobi iteration of the pressure equation Σ w_k (p_k − p) / h² + Σ w_v (p_v − p) / dy²
// = D, with w_k the horizontal and w_v the vertical face weights the splat pass wrote (0
// towards solid cells, closed walls, the ground and the top: Neumann; 1 towards fluid
// cells and the 0 pressure beyond an open border: Dirichlet). Multiplied by h², with
// r = h²/dy²: p' = (Σ w_k p_k + r Σ w_v p_v − h² D) / (Σ w_k + r Σ w_v), reading p_in and
// writing p_out (the solver ping-pongs two buffers, one dispatch per iteration). A cell
// with no open face (solid, or walled in) holds 0. On a 2D grid the vertical weights are 0
// and this is the 5-point iteration exactly. CPU twin: `FluidCpu::pressure_jacobi`.
//!include fluid_common.wgsl

@group(0) @binding(0) var<uniform> params: FluidParams;
@group(0) @binding(1) var<storage, read> divergence: array<f32>;
@group(0) @binding(2) var<storage, read> p_in: array<f32>;
@group(0) @binding(3) var<storage, read_write> p_out: array<f32>;
@group(0) @binding(4) var<storage, read> weights: array<vec4<f32>>;

// Pressure of neighbour c: 0 outside an open grid (a weight-0 face never reads it for
// closed grids, the ground or the top).
fn p_at(c: vec3<i32>) -> f32 {
    let r = fluid_cell_ref(c, i32(params.resolution), i32(params.layers), params.boundary);
    if r < 0 {
        return 0.0;
    }
    return p_in[r];
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = params.resolution;
    if gid.x >= n || gid.y >= n || gid.z >= params.layers {
        return;
    }
    let idx = (gid.z * n + gid.y) * n + gid.x;
    let w = weights[2u * idx];
    let wv = weights[2u * idx + 1u];
    let h = params.origin_cell.z;
    let r = h * h * params.layer.y * params.layer.y;
    let total = (w.x + w.y + w.z + w.w) + r * (wv.x + wv.y);
    if total == 0.0 {
        p_out[idx] = 0.0;
        return;
    }
    let c = vec3<i32>(gid);
    let sum = w.x * p_at(c - vec3<i32>(1, 0, 0)) + w.y * p_at(c + vec3<i32>(1, 0, 0))
        + w.z * p_at(c - vec3<i32>(0, 1, 0)) + w.w * p_at(c + vec3<i32>(0, 1, 0));
    let vertical = wv.x * p_at(c - vec3<i32>(0, 0, 1)) + wv.y * p_at(c + vec3<i32>(0, 0, 1));
    p_out[idx] = (sum + r * vertical - h * h * divergence[idx]) / total;
}
