// End of the wind step (timed with pass 7): the cell-centred velocity every consumer reads
// (blade update, billboards, overlay, AGC), the mean of each cell's two faces per horizontal
// axis, written to the solver's public `array<vec2<f32>>` (n² per layer, layer 0 first). CPU twin: `FluidCpu::centre`.
//!include fluid_common.wgsl

@group(0) @binding(0) var<uniform> params: FluidParams;
@group(0) @binding(1) var<storage, read> faces: array<f32>;
@group(0) @binding(2) var<storage, read_write> velocity: array<vec2<f32>>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = params.resolution;
    if gid.x >= n || gid.y >= n || gid.z >= params.layers {
        return;
    }
    let m = i32(n);
    let l = i32(params.layers);
    let i = i32(gid.x);
    let j = i32(gid.y);
    let k = i32(gid.z);
    let u = (faces[fluid_face_index(0u, i, j, k, m, l)] + faces[fluid_face_index(0u, i + 1, j, k, m, l)]) * 0.5;
    let v = (faces[fluid_face_index(1u, i, j, k, m, l)] + faces[fluid_face_index(1u, i, j + 1, k, m, l)]) * 0.5;
    velocity[(gid.z * n + gid.y) * n + gid.x] = vec2<f32>(u, v);
}
