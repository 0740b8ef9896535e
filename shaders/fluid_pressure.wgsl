// Wind step, pass 5 (pressure, CWD-Sim Eq. 7): one Jacobi iteration of ∇²p = D,
// p' = (p_L + p_R + p_B + p_T − h² D) / 4, reading p_in and writing p_out (the solver
// ping-pongs two buffers, one dispatch per iteration). Solid neighbours count as walls
// (Neumann: they take the centre cell's pressure) so no flow is driven through them; solid
// cells themselves hold 0. CPU twin: `FluidCpu::pressure`.
//!include fluid_common.wgsl

@group(0) @binding(0) var<uniform> params: FluidParams;
@group(0) @binding(1) var<storage, read> divergence: array<f32>;
@group(0) @binding(2) var<storage, read> p_in: array<f32>;
@group(0) @binding(3) var<storage, read_write> p_out: array<f32>;
@group(0) @binding(4) var<storage, read> solid: array<u32>;

fn p_at(i: i32, j: i32, centre: f32) -> f32 {
    let r = fluid_pressure_ref(i, j, i32(params.resolution), params.boundary);
    if !r.inside {
        return 0.0;
    }
    if solid[r.index] != 0u {
        return centre;
    }
    return p_in[r.index];
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = params.resolution;
    if gid.x >= n || gid.y >= n {
        return;
    }
    let idx = gid.y * n + gid.x;
    if solid[idx] != 0u {
        p_out[idx] = 0.0;
        return;
    }
    let i = i32(gid.x);
    let j = i32(gid.y);
    let c = p_in[idx];
    let h = params.origin_cell.z;
    let sum = p_at(i - 1, j, c) + p_at(i + 1, j, c) + p_at(i, j - 1, c) + p_at(i, j + 1, c);
    p_out[idx] = (sum - h * h * divergence[idx]) * 0.25;
}
