// Wind step, pass 7 (subtract the pressure gradient, CWD-Sim Eq. 8 on the staggered grid):
// every face with weight 1 (between two fluid cells, or from a fluid cell to an open
// border) loses the pressure difference across it, u(i, j) −= (p(i, j) − p(i − 1, j)) / h
// (w: / dy), with p = 0 beyond an open border. That is the same stencil as the divergence and the
// pressure Laplacian, so after a converged solve the divergence is the solver's residual.
// Faces of solid cells keep the obstacle velocity, walls 0. CPU twin:
// `FluidCpu::subtract_gradient`.
//!include fluid_common.wgsl

@group(0) @binding(0) var<uniform> params: FluidParams;
@group(0) @binding(1) var<storage, read> faces_in: array<f32>;
@group(0) @binding(2) var<storage, read> pressure: array<f32>;
@group(0) @binding(3) var<storage, read_write> faces_out: array<f32>;
@group(0) @binding(4) var<storage, read> solid: array<u32>;

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
        faces_out[out] = 0.0;
        return;
    }
    let f = fluid_canonical(face, n, params.boundary);
    let v = faces_in[fluid_face_index(f.axis, f.i, f.j, f.k, n, l)];
    let cells = fluid_face_cells(f.axis, f.i, f.j, f.k);
    let lo = fluid_cell_ref(cells.lo, n, l, params.boundary);
    let hi = fluid_cell_ref(cells.hi, n, l, params.boundary);
    if (lo >= 0 && solid[lo] != 0u) || (hi >= 0 && solid[hi] != 0u) {
        faces_out[out] = v;
        return;
    }
    var p_lo = 0.0;
    if lo >= 0 {
        p_lo = pressure[lo];
    }
    var p_hi = 0.0;
    if hi >= 0 {
        p_hi = pressure[hi];
    }
    let inv = select(params.origin_cell.w, params.layer.y, f.axis == 2u);
    faces_out[out] = v - (p_hi - p_lo) * inv;
}
