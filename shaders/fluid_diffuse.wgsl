// Wind step, pass 3 (viscous diffusion, only when ν > 0): one Jacobi iteration of
// (I − νΔt∇²) v = v0, x' = (v0 + α Σ neighbours of x) / (1 + 4α) with α = νΔt/h²
// (Stam's `diffuse`, with Jacobi instead of Gauss–Seidel so that every cell updates in
// parallel).
// Solid cells keep their obstacle velocity. CPU twin: `FluidCpu::diffuse`.
//!include fluid_common.wgsl

@group(0) @binding(0) var<uniform> params: FluidParams;
@group(0) @binding(1) var<storage, read> vel_start: array<vec2<f32>>;
@group(0) @binding(2) var<storage, read> x_in: array<vec2<f32>>;
@group(0) @binding(3) var<storage, read_write> x_out: array<vec2<f32>>;
@group(0) @binding(4) var<storage, read> solid: array<u32>;

fn x_at(i: i32, j: i32) -> vec2<f32> {
    let r = fluid_velocity_ref(i, j, i32(params.resolution), params.boundary);
    return x_in[r.index] * r.sign;
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = params.resolution;
    if gid.x >= n || gid.y >= n {
        return;
    }
    let idx = gid.y * n + gid.x;
    if solid[idx] != 0u {
        x_out[idx] = vel_start[idx];
        return;
    }
    let i = i32(gid.x);
    let j = i32(gid.y);
    let a = params.diffusion_alpha;
    let sum = x_at(i - 1, j) + x_at(i + 1, j) + x_at(i, j - 1) + x_at(i, j + 1);
    x_out[idx] = (vel_start[idx] + sum * a) / (1.0 + 4.0 * a);
}
