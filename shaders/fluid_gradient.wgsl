// Wind step, pass 6 (subtract the pressure gradient, CWD-Sim Eq. 8):
// v −= (p_R − p_L, p_T − p_B) / 2h, with the same border and solid rules as the pressure
// pass. Solid cells keep the obstacle velocity. CPU twin: `FluidCpu::subtract_gradient`.
//!include fluid_common.wgsl

@group(0) @binding(0) var<uniform> params: FluidParams;
@group(0) @binding(1) var<storage, read> vel_in: array<vec2<f32>>;
@group(0) @binding(2) var<storage, read> pressure: array<f32>;
@group(0) @binding(3) var<storage, read_write> vel_out: array<vec2<f32>>;
@group(0) @binding(4) var<storage, read> solid: array<u32>;

fn p_at(i: i32, j: i32, centre: f32) -> f32 {
    let r = fluid_pressure_ref(i, j, i32(params.resolution), params.boundary);
    if !r.inside {
        return 0.0;
    }
    if solid[r.index] != 0u {
        return centre;
    }
    return pressure[r.index];
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = params.resolution;
    if gid.x >= n || gid.y >= n {
        return;
    }
    let idx = gid.y * n + gid.x;
    let v = vel_in[idx];
    if solid[idx] != 0u {
        vel_out[idx] = v;
        return;
    }
    let i = i32(gid.x);
    let j = i32(gid.y);
    let c = pressure[idx];
    let grad = vec2<f32>(
        p_at(i + 1, j, c) - p_at(i - 1, j, c),
        p_at(i, j + 1, c) - p_at(i, j - 1, c),
    );
    vel_out[idx] = v - grad * (0.5 * params.origin_cell.w);
}
