// Wind step, pass 4 (viscous diffusion, only when ν > 0): one Jacobi iteration of
// (I − νΔt∇²) u = u0 on every face, x' = (u0 + α Σ neighbours of x) / (1 + 4α) with
// α = νΔt/h² and the four neighbours the faces of the same axis around it (Stam's
// `diffuse`, with Jacobi instead of Gauss–Seidel so that every face updates in parallel).
// Faces of solid cells keep the obstacle velocity, closed walls 0. CPU twin:
// `FluidCpu::diffuse`.
//!include fluid_common.wgsl

@group(0) @binding(0) var<uniform> params: FluidParams;
@group(0) @binding(1) var<storage, read> vel_start: array<f32>;
@group(0) @binding(2) var<storage, read> x_in: array<f32>;
@group(0) @binding(3) var<storage, read_write> x_out: array<f32>;
@group(0) @binding(4) var<storage, read> solid: array<u32>;

fn x_at(axis: u32, i: i32, j: i32) -> f32 {
    return x_in[fluid_face_ref(axis, i, j, i32(params.resolution), params.boundary)];
}

fn is_solid(i: i32, j: i32) -> bool {
    let c = fluid_cell_ref(i, j, i32(params.resolution), params.boundary);
    return c >= 0 && solid[c] != 0u;
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = i32(params.resolution);
    let face = fluid_face(gid, params.resolution);
    if !face.valid {
        return;
    }
    let out = fluid_face_index(face.axis, face.i, face.j, n);
    if fluid_is_wall(face.axis, face.i, face.j, n, params.boundary) {
        x_out[out] = 0.0;
        return;
    }
    let f = fluid_canonical(face, n, params.boundary);
    let at = fluid_face_index(f.axis, f.i, f.j, n);
    let cells = fluid_face_cells(f.axis, f.i, f.j);
    if is_solid(cells.x, cells.y) || is_solid(cells.z, cells.w) {
        x_out[out] = vel_start[at];
        return;
    }
    let a = params.diffusion_alpha;
    let sum = x_at(f.axis, f.i - 1, f.j) + x_at(f.axis, f.i + 1, f.j) + x_at(f.axis, f.i, f.j - 1)
        + x_at(f.axis, f.i, f.j + 1);
    x_out[out] = (vel_start[at] + sum * a) / (1.0 + 4.0 * a);
}
