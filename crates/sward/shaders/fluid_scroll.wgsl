// Scroll of a wind grid that follows the camera (`wind.fluid.extent > 0`): the grid moves
// by whole cells, so every face and cell that stays in it keeps its value exactly (a copy,
// no resampling, so nothing smears and nothing seams), and the faces and cells that enter
// take the old grid's nearest edge value: the air that blew at the edge goes on blowing
// there. One invocation per face (u, v, then w, the layout of fluid_common.wgsl; every layer
// moves alike) also moves the cell at the same index (pressure, the warm start of the next solve). The twin is
// `FluidCpu::scroll`.

struct Scroll {
    // The grid corner's move in cells (new corner = old corner + shift).
    shift: vec2<i32>,
    resolution: u32,
    layers: u32,
}

@group(0) @binding(0) var<uniform> scroll: Scroll;
@group(0) @binding(1) var<storage, read> faces_in: array<f32>;
@group(0) @binding(2) var<storage, read_write> faces_out: array<f32>;
@group(0) @binding(3) var<storage, read> pressure_in: array<f32>;
@group(0) @binding(4) var<storage, read_write> pressure_out: array<f32>;

// Moves entry `k` of a w × h lattice (x fastest) by the shift, clamping to the lattice.
fn source(k: u32, w: i32, h: i32) -> u32 {
    let i = i32(k % u32(w));
    let j = i32(k / u32(w));
    let si = clamp(i + scroll.shift.x, 0, w - 1);
    let sj = clamp(j + scroll.shift.y, 0, h - 1);
    return u32(sj * w + si);
}

@compute @workgroup_size(64)
fn scroll_grid(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    let idx = id.x + id.y * groups.x * 64u;
    let n = i32(scroll.resolution);
    let layer_faces = u32((n + 1) * n);
    let plane = u32(n * n);
    let uv = scroll.layers * layer_faces;
    let w_faces = (scroll.layers + 1u) * plane;
    if idx < uv {
        // u faces of layer idx / layer_faces: (n + 1) × n.
        let base = idx - idx % layer_faces;
        faces_out[idx] = faces_in[base + source(idx % layer_faces, n + 1, n)];
    } else if idx < 2u * uv {
        // v faces: n × (n + 1).
        let base = idx - idx % layer_faces;
        faces_out[idx] = faces_in[base + source((idx - uv) % layer_faces, n, n + 1)];
    } else if idx < 2u * uv + w_faces {
        // w faces: n × n per plane.
        let base = idx - (idx - 2u * uv) % plane;
        faces_out[idx] = faces_in[base + source((idx - 2u * uv) % plane, n, n)];
    }
    if idx < scroll.layers * plane {
        let base = idx - idx % plane;
        pressure_out[idx] = pressure_in[base + source(idx % plane, n, n)];
    }
}
