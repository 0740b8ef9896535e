// Wind step, pass 4 (divergence, CWD-Sim Eq. 6): D = (u_R − u_L + v_T − v_B) / 2h, with the
// border rules of `fluid_velocity_ref`. Solid cells get 0: they are not part of the
// pressure solve. CPU twin: `FluidCpu::divergence`.
//!include fluid_common.wgsl

@group(0) @binding(0) var<uniform> params: FluidParams;
@group(0) @binding(1) var<storage, read> vel_in: array<vec2<f32>>;
@group(0) @binding(2) var<storage, read_write> divergence: array<f32>;
@group(0) @binding(3) var<storage, read> solid: array<u32>;

fn vel(i: i32, j: i32) -> vec2<f32> {
    let r = fluid_velocity_ref(i, j, i32(params.resolution), params.boundary);
    return vel_in[r.index] * r.sign;
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = params.resolution;
    if gid.x >= n || gid.y >= n {
        return;
    }
    let idx = gid.y * n + gid.x;
    if solid[idx] != 0u {
        divergence[idx] = 0.0;
        return;
    }
    let i = i32(gid.x);
    let j = i32(gid.y);
    let du = vel(i + 1, j).x - vel(i - 1, j).x;
    let dv = vel(i, j + 1).y - vel(i, j - 1).y;
    divergence[idx] = (du + dv) * (0.5 * params.origin_cell.w);
}
