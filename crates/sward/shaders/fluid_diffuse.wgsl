// Wind step, pass 4 (viscous diffusion, only when ν > 0): one Jacobi iteration of
// (I − νΔt∇²) u = u0 on every face, x' = (u0 + α Σ4 + α_v Σ2) / (1 + 4α + 2α_v) with
// α = νΔt/h² over the four faces of the same axis beside it and α_v = νΔt/dy² over the two
// above and below (0 on a 2D grid) (Stam's `diffuse`, with Jacobi instead of Gauss–Seidel
// so that every face updates in parallel). Faces of solid cells keep the obstacle
// velocity, walls 0. CPU twin: `FluidCpu::diffuse`.
//!include fluid_common.wgsl

@group(0) @binding(0) var<uniform> params: FluidParams;
@group(0) @binding(1) var<storage, read> vel_start: array<f32>;
@group(0) @binding(2) var<storage, read> x_in: array<f32>;
@group(0) @binding(3) var<storage, read_write> x_out: array<f32>;
@group(0) @binding(4) var<storage, read> solid: array<u32>;

fn x_at(axis: u32, i: i32, j: i32, k: i32) -> f32 {
    let n = i32(params.resolution);
    return x_in[fluid_face_ref(axis, i, j, k, n, i32(params.layers), params.boundary)];
}

fn is_solid(c: vec3<i32>) -> bool {
    let r = fluid_cell_ref(c, i32(params.resolution), i32(params.layers), params.boundary);
    return r >= 0 && solid[r] != 0u;
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = i32(params.resolution);
    let l = i32(params.layers);
    let face = fluid_face(gid, params.resolution, params.layers);
    if !face.valid {
        return;
    }
    let out = fluid_face_index(face.axis, face.i, face.j, face.k, n, l);
    if fluid_is_wall(face.axis, face.i, face.j, face.k, n, l, params.boundary) {
        x_out[out] = 0.0;
        return;
    }
    let f = fluid_canonical(face, n, params.boundary);
    let at = fluid_face_index(f.axis, f.i, f.j, f.k, n, l);
    let cells = fluid_face_cells(f.axis, f.i, f.j, f.k);
    if is_solid(cells.lo) || is_solid(cells.hi) {
        x_out[out] = vel_start[at];
        return;
    }
    let a = params.diffusion_alpha;
    let av = params.layer.z;
    let sum = x_at(f.axis, f.i - 1, f.j, f.k) + x_at(f.axis, f.i + 1, f.j, f.k)
        + x_at(f.axis, f.i, f.j - 1, f.k) + x_at(f.axis, f.i, f.j + 1, f.k);
    let vertical = x_at(f.axis, f.i, f.j, f.k - 1) + x_at(f.axis, f.i, f.j, f.k + 1);
    x_out[out] = (vel_start[at] + sum * a + vertical * av) / (1.0 + 4.0 * a + 2.0 * av);
}
