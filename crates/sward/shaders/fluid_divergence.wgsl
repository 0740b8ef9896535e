// Wind step, pass 5 (divergence, CWD-Sim Eq. 6 on the staggered grid): the net outflow of
// each cell through its faces, D = (u(i+1) − u(i) + v(j+1) − v(j)) / h + (w(k+1) − w(k)) / dy.
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
    if gid.x >= n || gid.y >= n || gid.z >= params.layers {
        return;
    }
    let idx = (gid.z * n + gid.y) * n + gid.x;
    if solid[idx] != 0u {
        divergence[idx] = 0.0;
        return;
    }
    let m = i32(n);
    let l = i32(params.layers);
    let i = i32(gid.x);
    let j = i32(gid.y);
    let k = i32(gid.z);
    let du = faces[fluid_face_index(0u, i + 1, j, k, m, l)] - faces[fluid_face_index(0u, i, j, k, m, l)];
    let dv = faces[fluid_face_index(1u, i, j + 1, k, m, l)] - faces[fluid_face_index(1u, i, j, k, m, l)];
    let dw = faces[fluid_face_index(2u, i, j, k + 1, m, l)] - faces[fluid_face_index(2u, i, j, k, m, l)];
    divergence[idx] = (du + dv) * params.origin_cell.w + dw * params.layer.y;
}
