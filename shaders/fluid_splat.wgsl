// Wind step, pass 2 (splat), three entry points in order:
// `mark` – cells whose centre lies inside an obstacle circle become solid (k + 1 for
// obstacle k); `weights` – each fluid cell's four face weights of the pressure Laplacian
// (1 towards a fluid cell or an open border, 0 towards a solid cell or a closed wall);
// `faces` – every face gets Δt · (global force + Σ arrows + downwash) at its own position,
// faces of a solid cell take the obstacle's velocity (a moving collider drags the air with
// it, a static one holds it still) and closed walls 0. CPU twin: `FluidCpu::splat`.
//!include fluid_common.wgsl

@group(0) @binding(0) var<uniform> params: FluidParams;
@group(0) @binding(1) var<storage, read> arrows: array<FluidArrow>;
@group(0) @binding(2) var<storage, read> obstacles: array<FluidObstacle>;
@group(0) @binding(3) var<storage, read> faces_in: array<f32>;
@group(0) @binding(4) var<storage, read_write> faces_out: array<f32>;
// 0 = fluid, k + 1 = inside obstacle k (read by the later passes).
@group(0) @binding(5) var<storage, read_write> solid: array<u32>;
// Left, right, bottom, top face weights of each cell (the multigrid's finest level).
@group(0) @binding(6) var<storage, read_write> weights: array<vec4<f32>>;

// AGC arrow (CWD-Sim Section 3.5): a band of half-width r around the segment pushed along
// it, with the smooth (1 − (d/r)²)² falloff so that the band has no visible edge.
fn arrow_force(a: FluidArrow, p: vec2<f32>) -> vec2<f32> {
    let s = a.segment.xy;
    let d = a.segment.zw - s;
    let len2 = dot(d, d);
    if len2 <= 0.0 || a.radius <= 0.0 {
        return vec2<f32>(0.0, 0.0);
    }
    let t = clamp(dot(p - s, d) / len2, 0.0, 1.0);
    let off = p - (s + d * t);
    let dist2 = dot(off, off);
    let r2 = a.radius * a.radius;
    if dist2 >= r2 {
        return vec2<f32>(0.0, 0.0);
    }
    let w = 1.0 - dist2 / r2;
    return d * (a.strength * w * w / sqrt(len2));
}

// Radial outflow: grows linearly from 0 at the centre (no direction there) to `strength`
// at r/2, then fades with a smoothstep to 0 at r.
fn downwash_force(p: vec2<f32>) -> vec2<f32> {
    let r = params.global_downwash.z;
    if r <= 0.0 {
        return vec2<f32>(0.0, 0.0);
    }
    let off = p - params.downwash_pos.xy;
    let dist = sqrt(dot(off, off));
    if dist <= 0.0 || dist >= r {
        return vec2<f32>(0.0, 0.0);
    }
    let half_r = 0.5 * r;
    var profile = dist / half_r;
    if dist > half_r {
        let t = (dist - half_r) / half_r;
        profile = 1.0 - t * t * (3.0 - 2.0 * t);
    }
    return off * (params.global_downwash.w * profile / dist);
}

@compute @workgroup_size(8, 8)
fn mark(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = params.resolution;
    if gid.x >= n || gid.y >= n {
        return;
    }
    let h = params.origin_cell.z;
    let p = params.origin_cell.xy + (vec2<f32>(gid.xy) + 0.5) * h;
    var s = 0u;
    for (var o = 0u; o < params.obstacle_count; o++) {
        let ob = obstacles[o];
        let off = p - ob.circle.xy;
        if dot(off, off) < ob.circle.z * ob.circle.z {
            s = o + 1u;
            break;
        }
    }
    solid[gid.y * n + gid.x] = s;
}

// Weight of the face towards neighbour cell (i, j) of a fluid cell.
fn face_weight(i: i32, j: i32, n: i32) -> f32 {
    let c = fluid_cell_ref(i, j, n, params.boundary);
    if c < 0 {
        return select(0.0, 1.0, params.boundary == FLUID_OPEN);
    }
    return select(0.0, 1.0, solid[c] == 0u);
}

@compute @workgroup_size(8, 8)
fn cell_weights(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = params.resolution;
    if gid.x >= n || gid.y >= n {
        return;
    }
    let idx = gid.y * n + gid.x;
    if solid[idx] != 0u {
        weights[idx] = vec4<f32>(0.0);
        return;
    }
    let i = i32(gid.x);
    let j = i32(gid.y);
    let m = i32(n);
    weights[idx] = vec4<f32>(
        face_weight(i - 1, j, m),
        face_weight(i + 1, j, m),
        face_weight(i, j - 1, m),
        face_weight(i, j + 1, m),
    );
}

// The obstacle id (k + 1) of cell (i, j), 0 for fluid or outside the grid.
fn solid_at(i: i32, j: i32, n: i32) -> u32 {
    let c = fluid_cell_ref(i, j, n, params.boundary);
    if c < 0 {
        return 0u;
    }
    return solid[c];
}

@compute @workgroup_size(8, 8)
fn faces(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = params.resolution;
    let m = i32(n);
    let face = fluid_face(gid, n);
    if !face.valid {
        return;
    }
    let out = fluid_face_index(face.axis, face.i, face.j, m);
    if fluid_is_wall(face.axis, face.i, face.j, m, params.boundary) {
        faces_out[out] = 0.0;
        return;
    }
    let f = fluid_canonical(face, m, params.boundary);
    let cells = fluid_face_cells(f.axis, f.i, f.j);
    var s = solid_at(cells.x, cells.y, m);
    if s == 0u {
        s = solid_at(cells.z, cells.w, m);
    }
    if s != 0u {
        faces_out[out] = obstacles[s - 1u].velocity[f.axis];
        return;
    }
    let h = params.origin_cell.z;
    let p = params.origin_cell.xy + fluid_face_pos(f.axis, f.i, f.j) * h;
    var force = params.global_downwash.xy;
    for (var a = 0u; a < params.arrow_count; a++) {
        force += arrow_force(arrows[a], p);
    }
    force += downwash_force(p);
    let at = fluid_face_index(f.axis, f.i, f.j, m);
    faces_out[out] = faces_in[at] + force[f.axis] * params.dt;
}
