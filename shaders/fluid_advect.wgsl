// Wind step, pass 7 (semi-Lagrangian self-advection, CWD-Sim Eq. 9–10, Stam's `advect`):
// trace each cell centre back by Δt · v / h cells, sample the velocity there bilinearly and
// divide by (1 + dissipation · Δt). Closed and open grids clamp the back-traced point to
// the grid's outer edge (half a cell beyond the outer centres), where the border rules of
// `fluid_velocity_ref` give the wall (closed: normal component 0) or the edge value (open);
// periodic grids wrap. Solid cells keep the obstacle velocity. CPU twin: `FluidCpu::advect`.
//!include fluid_common.wgsl

@group(0) @binding(0) var<uniform> params: FluidParams;
@group(0) @binding(1) var<storage, read> vel_in: array<vec2<f32>>;
@group(0) @binding(2) var<storage, read_write> vel_out: array<vec2<f32>>;
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
    let v = vel_in[idx];
    if solid[idx] != 0u {
        vel_out[idx] = v;
        return;
    }
    var pos = vec2<f32>(gid.xy) - v * (params.dt * params.origin_cell.w);
    if params.boundary != FLUID_PERIODIC {
        let edge = f32(n) - 0.5;
        pos = min(max(pos, vec2<f32>(-0.5, -0.5)), vec2<f32>(edge, edge));
    }
    let c = floor(pos);
    let f = pos - c;
    let i = i32(c.x);
    let j = i32(c.y);
    let a = vel(i, j);
    let b = vel(i + 1, j);
    let d = vel(i, j + 1);
    let e = vel(i + 1, j + 1);
    // Spelled out instead of mix(): mix's formula is up to the implementation and the CPU
    // twin must round the same way.
    let bottom = a + (b - a) * f.x;
    let top = d + (e - d) * f.x;
    let s = bottom + (top - bottom) * f.y;
    vel_out[idx] = s / (1.0 + params.dissipation * params.dt);
}
