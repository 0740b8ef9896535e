// Wind step, pass 2 (vorticity): `compute_curl` writes ω = ∂v/∂x − ∂u/∂z (central
// differences, CWD-Sim Eq. 4), then `confine` adds Δt · λ (N × ω) with N the normalised
// gradient of |ω| (Fedkiw et al. 2001, Dobryakov's WebGL fluid; CWD-Sim Eq. 5), which
// feeds back the small swirls that the coarse grid and semi-Lagrangian advection smear
// out. λ = 0 copies the velocity. CPU twin: `FluidCpu::vorticity`.
//!include fluid_common.wgsl

@group(0) @binding(0) var<uniform> params: FluidParams;
@group(0) @binding(1) var<storage, read> vel_in: array<vec2<f32>>;
@group(0) @binding(2) var<storage, read_write> curl_field: array<f32>;
@group(0) @binding(3) var<storage, read_write> vel_out: array<vec2<f32>>;
@group(0) @binding(4) var<storage, read> solid: array<u32>;

fn vel(i: i32, j: i32) -> vec2<f32> {
    let r = fluid_velocity_ref(i, j, i32(params.resolution), params.boundary);
    return vel_in[r.index] * r.sign;
}

fn abs_curl(i: i32, j: i32) -> f32 {
    return abs(curl_field[fluid_scalar_index(i, j, i32(params.resolution), params.boundary)]);
}

@compute @workgroup_size(8, 8)
fn compute_curl(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = params.resolution;
    if gid.x >= n || gid.y >= n {
        return;
    }
    let i = i32(gid.x);
    let j = i32(gid.y);
    let dv_dx = vel(i + 1, j).y - vel(i - 1, j).y;
    let du_dz = vel(i, j + 1).x - vel(i, j - 1).x;
    curl_field[gid.y * n + gid.x] = (dv_dx - du_dz) * (0.5 * params.origin_cell.w);
}

@compute @workgroup_size(8, 8)
fn confine(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = params.resolution;
    if gid.x >= n || gid.y >= n {
        return;
    }
    let idx = gid.y * n + gid.x;
    let v = vel_in[idx];
    if params.vorticity == 0.0 || solid[idx] != 0u {
        vel_out[idx] = v;
        return;
    }
    let i = i32(gid.x);
    let j = i32(gid.y);
    let g = vec2<f32>(
        abs_curl(i + 1, j) - abs_curl(i - 1, j),
        abs_curl(i, j + 1) - abs_curl(i, j - 1),
    ) * (0.5 * params.origin_cell.w);
    // The epsilon only keeps N finite where |ω| is flat; it is far below any real gradient
    // (1/(m·s)).
    let nrm = g / (sqrt(dot(g, g)) + 1e-5);
    let f = vec2<f32>(nrm.y, -nrm.x) * (params.vorticity * curl_field[idx]);
    vel_out[idx] = v + f * params.dt;
}
