// Wind step, pass 3 (vorticity): `compute_curl` writes ω = ∂v/∂x − ∂u/∂z at every cell
// centre (CWD-Sim Eq. 4; central differences of the cell-centred velocity, which on the
// staggered grid is exactly the mean of the curl at the cell's four corners), then
// `confine` adds Δt · ε h (N × ω) to every face, N the normalised gradient of |ω|, the force
// averaged from the two cells the face separates (Fedkiw, Stam & Jensen 2001, Eq. 11; the h
// makes the same ε give the same swirl on any grid; CWD-Sim Eq. 5). It feeds back the
// small swirls that the grid and semi-Lagrangian advection smear out. ε = 0 copies the
// velocity. Solid faces keep the obstacle's velocity, walls 0. On a 3D grid each layer is
// confined on its own with the vertical component of ω (the swirls in the plane of the
// grass, the ones that show in it); w faces are copied. CPU twin: `FluidCpu::vorticity`.
//!include fluid_common.wgsl

@group(0) @binding(0) var<uniform> params: FluidParams;
@group(0) @binding(1) var<storage, read> faces_in: array<f32>;
@group(0) @binding(2) var<storage, read_write> curl_field: array<f32>;
@group(0) @binding(3) var<storage, read_write> faces_out: array<f32>;
@group(0) @binding(4) var<storage, read> solid: array<u32>;

fn dims() -> vec2<i32> {
    return vec2<i32>(i32(params.resolution), i32(params.layers));
}

// Cell-centred (u, v) of cell (i, j) of layer k under the border rules of
// `fluid_velocity_ref`.
fn centre(i: i32, j: i32, k: i32) -> vec2<f32> {
    let d = dims();
    let n = d.x;
    let r = fluid_velocity_ref(i, j, n, params.boundary);
    let u = (faces_in[fluid_face_index(0u, r.i, r.j, k, n, d.y)]
        + faces_in[fluid_face_index(0u, r.i + 1, r.j, k, n, d.y)]) * 0.5;
    let v = (faces_in[fluid_face_index(1u, r.i, r.j, k, n, d.y)]
        + faces_in[fluid_face_index(1u, r.i, r.j + 1, k, n, d.y)]) * 0.5;
    return vec2<f32>(u, v) * r.sign;
}

@compute @workgroup_size(8, 8)
fn compute_curl(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = params.resolution;
    if gid.x >= n || gid.y >= n || gid.z >= params.layers {
        return;
    }
    let i = i32(gid.x);
    let j = i32(gid.y);
    let k = i32(gid.z);
    let dv_dx = centre(i + 1, j, k).y - centre(i - 1, j, k).y;
    let du_dz = centre(i, j + 1, k).x - centre(i, j - 1, k).x;
    curl_field[(gid.z * n + gid.y) * n + gid.x] = (dv_dx - du_dz) * (0.5 * params.origin_cell.w);
}

fn abs_curl(i: i32, j: i32, k: i32) -> f32 {
    return abs(curl_field[fluid_scalar_index(i, j, k, i32(params.resolution), params.boundary)]);
}

// ε h (N × ω) at the centre of in-grid cell (i, j, k); 0 in a solid cell.
fn cell_force(c: vec3<i32>) -> vec2<f32> {
    let n = i32(params.resolution);
    let i = c.x;
    let j = c.y;
    let k = c.z;
    let idx = fluid_scalar_index(i, j, k, n, params.boundary);
    if solid[idx] != 0u {
        return vec2<f32>(0.0, 0.0);
    }
    let g = vec2<f32>(
        abs_curl(i + 1, j, k) - abs_curl(i - 1, j, k),
        abs_curl(i, j + 1, k) - abs_curl(i, j - 1, k),
    ) * (0.5 * params.origin_cell.w);
    // The epsilon only keeps N finite where |ω| is flat; it is far below any real gradient
    // (1/(m·s)).
    let nrm = g / (sqrt(dot(g, g)) + 1e-5);
    return vec2<f32>(nrm.y, -nrm.x) * (params.vorticity * params.origin_cell.z * curl_field[idx]);
}

@compute @workgroup_size(8, 8)
fn confine(@builtin(global_invocation_id) gid: vec3<u32>) {
    let d = dims();
    let n = d.x;
    let face = fluid_face(gid, params.resolution, params.layers);
    if !face.valid {
        return;
    }
    let out = fluid_face_index(face.axis, face.i, face.j, face.k, n, d.y);
    if fluid_is_wall(face.axis, face.i, face.j, face.k, n, d.y, params.boundary) {
        faces_out[out] = 0.0;
        return;
    }
    let f = fluid_canonical(face, n, params.boundary);
    let at = fluid_face_index(f.axis, f.i, f.j, f.k, n, d.y);
    let v = faces_in[at];
    let cells = fluid_face_cells(f.axis, f.i, f.j, f.k);
    let lo = fluid_cell_ref(cells.lo, n, d.y, params.boundary);
    let hi = fluid_cell_ref(cells.hi, n, d.y, params.boundary);
    let solid_lo = lo >= 0 && solid[lo] != 0u;
    let solid_hi = hi >= 0 && solid[hi] != 0u;
    if params.vorticity == 0.0 || f.axis == 2u || solid_lo || solid_hi {
        faces_out[out] = v;
        return;
    }
    // A border face of an open grid has one cell: its force is the face's.
    var force = 0.0;
    if lo < 0 {
        force = cell_force(cells.hi)[f.axis];
    } else if hi < 0 {
        force = cell_force(cells.lo)[f.axis];
    } else {
        force = (cell_force(cells.lo)[f.axis] + cell_force(cells.hi)[f.axis]) * 0.5;
    }
    faces_out[out] = v + force * params.dt;
}
