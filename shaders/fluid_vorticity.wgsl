// Wind step, pass 3 (vorticity): `compute_curl` writes ω = ∂v/∂x − ∂u/∂z at every cell
// centre (CWD-Sim Eq. 4; central differences of the cell-centred velocity, which on the
// staggered grid is exactly the mean of the curl at the cell's four corners), then
// `confine` adds Δt · ε h (N × ω) to every face, N the normalised gradient of |ω|, the force
// averaged from the two cells the face separates (Fedkiw, Stam & Jensen 2001, Eq. 11; the h
// makes the same ε give the same swirl on any grid; CWD-Sim Eq. 5). It feeds back the
// small swirls that the grid and semi-Lagrangian advection smear out. ε = 0 copies the
// velocity. Solid faces keep the obstacle's velocity, closed walls 0. CPU twin:
// `FluidCpu::vorticity`.
//!include fluid_common.wgsl

@group(0) @binding(0) var<uniform> params: FluidParams;
@group(0) @binding(1) var<storage, read> faces_in: array<f32>;
@group(0) @binding(2) var<storage, read_write> curl_field: array<f32>;
@group(0) @binding(3) var<storage, read_write> faces_out: array<f32>;
@group(0) @binding(4) var<storage, read> solid: array<u32>;

// Cell-centred velocity of cell (i, j) under the border rules of `fluid_velocity_ref`.
fn centre(i: i32, j: i32) -> vec2<f32> {
    let n = i32(params.resolution);
    let r = fluid_velocity_ref(i, j, n, params.boundary);
    let u = (faces_in[fluid_face_index(0u, r.i, r.j, n)]
        + faces_in[fluid_face_index(0u, r.i + 1, r.j, n)]) * 0.5;
    let v = (faces_in[fluid_face_index(1u, r.i, r.j, n)]
        + faces_in[fluid_face_index(1u, r.i, r.j + 1, n)]) * 0.5;
    return vec2<f32>(u, v) * r.sign;
}

@compute @workgroup_size(8, 8)
fn compute_curl(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = params.resolution;
    if gid.x >= n || gid.y >= n {
        return;
    }
    let i = i32(gid.x);
    let j = i32(gid.y);
    let dv_dx = centre(i + 1, j).y - centre(i - 1, j).y;
    let du_dz = centre(i, j + 1).x - centre(i, j - 1).x;
    curl_field[gid.y * n + gid.x] = (dv_dx - du_dz) * (0.5 * params.origin_cell.w);
}

fn abs_curl(i: i32, j: i32) -> f32 {
    return abs(curl_field[fluid_scalar_index(i, j, i32(params.resolution), params.boundary)]);
}

// ε h (N × ω) at the centre of in-grid cell (i, j); 0 in a solid cell.
fn cell_force(i: i32, j: i32) -> vec2<f32> {
    let n = i32(params.resolution);
    let idx = fluid_scalar_index(i, j, n, params.boundary);
    if solid[idx] != 0u {
        return vec2<f32>(0.0, 0.0);
    }
    let g = vec2<f32>(
        abs_curl(i + 1, j) - abs_curl(i - 1, j),
        abs_curl(i, j + 1) - abs_curl(i, j - 1),
    ) * (0.5 * params.origin_cell.w);
    // The epsilon only keeps N finite where |ω| is flat; it is far below any real gradient
    // (1/(m·s)).
    let nrm = g / (sqrt(dot(g, g)) + 1e-5);
    return vec2<f32>(nrm.y, -nrm.x) * (params.vorticity * params.origin_cell.z * curl_field[idx]);
}

@compute @workgroup_size(8, 8)
fn confine(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = i32(params.resolution);
    let face = fluid_face(gid, params.resolution);
    if !face.valid {
        return;
    }
    let out = fluid_face_index(face.axis, face.i, face.j, n);
    if fluid_is_wall(face.axis, face.i, face.j, n, params.boundary) {
        faces_out[out] = 0.0;
        return;
    }
    let f = fluid_canonical(face, n, params.boundary);
    let at = fluid_face_index(f.axis, f.i, f.j, n);
    let v = faces_in[at];
    let cells = fluid_face_cells(f.axis, f.i, f.j);
    let lo = fluid_cell_ref(cells.x, cells.y, n, params.boundary);
    let hi = fluid_cell_ref(cells.z, cells.w, n, params.boundary);
    let solid_lo = lo >= 0 && solid[lo] != 0u;
    let solid_hi = hi >= 0 && solid[hi] != 0u;
    if params.vorticity == 0.0 || solid_lo || solid_hi {
        faces_out[out] = v;
        return;
    }
    // A border face of an open grid has one cell: its force is the face's.
    var force = 0.0;
    if lo < 0 {
        force = cell_force(cells.z, cells.w)[f.axis];
    } else if hi < 0 {
        force = cell_force(cells.x, cells.y)[f.axis];
    } else {
        force = (cell_force(cells.x, cells.y)[f.axis] + cell_force(cells.z, cells.w)[f.axis]) * 0.5;
    }
    faces_out[out] = v + force * params.dt;
}
