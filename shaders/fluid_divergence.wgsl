// Wind step, pass 5 (divergence, CWD-Sim Eq. 6 on the staggered grid): the net outflow of
// each cell through its four faces, D = (u(i+1, j) − u(i, j) + v(i, j+1) − v(i, j)) / h.
// Faces of solid cells hold the obstacle's velocity and closed walls 0, so a moving obstacle
// pushes air. Solid cells get 0: they are not part of the pressure solve. CPU twin:
// `FluidCpu::divergence`.
//!include fluid_common.wgsl

@group(0) @binding(0) var<uniform> params: FluidParams;
@group(0) @binding(1) var<storage, read> faces: array<f32>;
@group(0) @binding(2) var<storage, read_write> divergence: array<f32>;
@group(0) @binding(3) var<storage, read> solid: array<u32>;

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
    let m = i32(n);
    let i = i32(gid.x);
    let j = i32(gid.y);
    let du = faces[fluid_face_index(0u, i + 1, j, m)] - faces[fluid_face_index(0u, i, j, m)];
    let dv = faces[fluid_face_index(1u, i, j + 1, m)] - faces[fluid_face_index(1u, i, j, m)];
    divergence[idx] = (du + dv) * params.origin_cell.w;
}
