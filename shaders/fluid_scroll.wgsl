// Scroll of a wind grid that follows the camera (`wind.fluid.extent > 0`): the grid moves
// by whole cells, so every face and cell that stays in it keeps its value exactly (a copy,
// no resampling, so nothing smears and nothing seams), and the faces and cells that enter
// take the old grid's nearest edge value: the air that blew at the edge goes on blowing
// there. One invocation per face (u then v, the layout of fluid_common.wgsl) also moves the
// cell at the same index (pressure, the warm start of the next solve). The twin is
// `FluidCpu::scroll`.

struct Scroll {
    // The grid corner's move in cells (new corner = old corner + shift).
    shift: vec2<i32>,
    resolution: u32,
    pad: u32,
}

@group(0) @binding(0) var<uniform> scroll: Scroll;
@group(0) @binding(1) var<storage, read> faces_in: array<f32>;
@group(0) @binding(2) var<storage, read_write> faces_out: array<f32>;
@group(0) @binding(3) var<storage, read> pressure_in: array<f32>;
@group(0) @binding(4) var<storage, read_write> pressure_out: array<f32>;

@compute @workgroup_size(64)
fn scroll_grid(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    let idx = id.x + id.y * groups.x * 64u;
    let n = i32(scroll.resolution);
    let d = scroll.shift;
    let u_faces = u32((n + 1) * n);
    if idx < u_faces {
        // u face (i, j), i in 0..=n, j in 0..n.
        let i = i32(idx % u32(n + 1));
        let j = i32(idx / u32(n + 1));
        let si = clamp(i + d.x, 0, n);
        let sj = clamp(j + d.y, 0, n - 1);
        faces_out[idx] = faces_in[sj * (n + 1) + si];
    } else if idx < 2u * u_faces {
        // v face (i, j), i in 0..n, j in 0..=n.
        let k = idx - u_faces;
        let i = i32(k % u32(n));
        let j = i32(k / u32(n));
        let si = clamp(i + d.x, 0, n - 1);
        let sj = clamp(j + d.y, 0, n);
        faces_out[idx] = faces_in[u_faces + u32(sj * n + si)];
    }
    if idx < u32(n * n) {
        let i = i32(idx % u32(n));
        let j = i32(idx / u32(n));
        let si = clamp(i + d.x, 0, n - 1);
        let sj = clamp(j + d.y, 0, n - 1);
        pressure_out[idx] = pressure_in[sj * n + si];
    }
}
