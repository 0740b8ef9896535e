// Wind step, pass 2 (splat), three entry points in order:
// `mark` – cells whose centre lies inside an obstacle become solid (o + 1 for obstacle o):
// inside its circle on a 2D grid, inside its sphere on a 3D one;
// `weights` – each fluid cell's six face weights of the pressure Laplacian (1 towards a
// fluid cell or an open border, 0 towards a solid cell, a closed wall, the ground or the
// top);
// `faces` – every face gets Δt · (global force + Σ arrows + downwash) at its own position,
// faces of a solid cell take the obstacle's velocity (a moving collider drags the air with
// it, a static one holds it still) and walls 0. On a 2D grid the downwash is a radial
// outflow on u, v; on a 3D grid it pushes w down in the column under the rotor and the
// ground turns it outwards (through the pressure solve). On a 3D grid the horizontal faces
// of layer k also feel the ground drag, v /= 1 + Δt c / (k + ½). CPU twin: `FluidCpu::splat`.
//!include fluid_common.wgsl

@group(0) @binding(0) var<uniform> params: FluidParams;
@group(0) @binding(1) var<storage, read> arrows: array<FluidArrow>;
@group(0) @binding(2) var<storage, read> obstacles: array<FluidObstacle>;
@group(0) @binding(3) var<storage, read> faces_in: array<f32>;
@group(0) @binding(4) var<storage, read_write> faces_out: array<f32>;
// 0 = fluid, k + 1 = inside obstacle k (read by the later passes).
@group(0) @binding(5) var<storage, read_write> solid: array<u32>;
// Two vec4 per cell: (−x, +x, −z, +z) and (below, above, 0, 0) face weights (the
// multigrid's finest level).
@group(0) @binding(6) var<storage, read_write> weights: array<vec4<f32>>;

fn dims() -> vec2<i32> {
    return vec2<i32>(i32(params.resolution), i32(params.layers));
}

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

// The 3D downwash: 1 inside half the radius, fading with a smoothstep to 0 at the radius.
fn downwash_column(p: vec2<f32>) -> f32 {
    let r = params.global_downwash.z;
    if r <= 0.0 {
        return 0.0;
    }
    let off = p - params.downwash_pos.xy;
    let dist = sqrt(dot(off, off));
    if dist >= r {
        return 0.0;
    }
    let half_r = 0.5 * r;
    if dist <= half_r {
        return 1.0;
    }
    let t = (dist - half_r) / half_r;
    return 1.0 - t * t * (3.0 - 2.0 * t);
}

// Dispatched over (n, n, L) cells.
@compute @workgroup_size(8, 8)
fn mark(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = params.resolution;
    if gid.x >= n || gid.y >= n || gid.z >= params.layers {
        return;
    }
    let h = params.origin_cell.z;
    let p = params.origin_cell.xy + (vec2<f32>(gid.xy) + 0.5) * h;
    let y = (f32(gid.z) + 0.5) * params.layer.x;
    let three_d = params.layers > 1u;
    var s = 0u;
    for (var o = 0u; o < params.obstacle_count; o++) {
        let ob = obstacles[o];
        let off = p - ob.circle.xy;
        var d2 = dot(off, off);
        if three_d {
            let dy = y - ob.circle.w;
            d2 = d2 + dy * dy;
        }
        if d2 < ob.circle.z * ob.circle.z {
            s = o + 1u;
            break;
        }
    }
    solid[(gid.z * n + gid.y) * n + gid.x] = s;
}

// Weight of the face towards neighbour cell c of a fluid cell: beyond the ground or the top
// it is 0, beyond an open border 1.
fn face_weight(c: vec3<i32>) -> f32 {
    let d = dims();
    let r = fluid_cell_ref(c, d.x, d.y, params.boundary);
    if r < 0 {
        let beside = c.z >= 0 && c.z < d.y;
        return select(0.0, 1.0, beside && params.boundary == FLUID_OPEN);
    }
    return select(0.0, 1.0, solid[r] == 0u);
}

@compute @workgroup_size(8, 8)
fn cell_weights(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = params.resolution;
    if gid.x >= n || gid.y >= n || gid.z >= params.layers {
        return;
    }
    let idx = (gid.z * n + gid.y) * n + gid.x;
    if solid[idx] != 0u {
        weights[2u * idx] = vec4<f32>(0.0);
        weights[2u * idx + 1u] = vec4<f32>(0.0);
        return;
    }
    let c = vec3<i32>(gid);
    weights[2u * idx] = vec4<f32>(
        face_weight(c - vec3<i32>(1, 0, 0)),
        face_weight(c + vec3<i32>(1, 0, 0)),
        face_weight(c - vec3<i32>(0, 1, 0)),
        face_weight(c + vec3<i32>(0, 1, 0)),
    );
    weights[2u * idx + 1u] = vec4<f32>(
        face_weight(c - vec3<i32>(0, 0, 1)),
        face_weight(c + vec3<i32>(0, 0, 1)),
        0.0,
        0.0,
    );
}

// The obstacle id (o + 1) of cell c, 0 for fluid or outside the grid.
fn solid_at(c: vec3<i32>) -> u32 {
    let d = dims();
    let r = fluid_cell_ref(c, d.x, d.y, params.boundary);
    if r < 0 {
        return 0u;
    }
    return solid[r];
}

@compute @workgroup_size(8, 8)
fn faces(@builtin(global_invocation_id) gid: vec3<u32>) {
    let d = dims();
    let m = d.x;
    let face = fluid_face(gid, params.resolution, params.layers);
    if !face.valid {
        return;
    }
    let out = fluid_face_index(face.axis, face.i, face.j, face.k, m, d.y);
    if fluid_is_wall(face.axis, face.i, face.j, face.k, m, d.y, params.boundary) {
        faces_out[out] = 0.0;
        return;
    }
    let f = fluid_canonical(face, m, params.boundary);
    let cells = fluid_face_cells(f.axis, f.i, f.j, f.k);
    var s = solid_at(cells.lo);
    if s == 0u {
        s = solid_at(cells.hi);
    }
    if s != 0u {
        faces_out[out] = obstacles[s - 1u].velocity[f.axis];
        return;
    }
    let h = params.origin_cell.z;
    let pos = fluid_face_pos(f.axis, f.i, f.j, f.k);
    let p = params.origin_cell.xy + pos.xy * h;
    let at = fluid_face_index(f.axis, f.i, f.j, f.k, m, d.y);
    if f.axis == 2u {
        faces_out[out] = faces_in[at] - params.global_downwash.w * downwash_column(p) * params.dt;
        return;
    }
    var force = params.global_downwash.xy;
    for (var a = 0u; a < params.arrow_count; a++) {
        force += arrow_force(arrows[a], p);
    }
    if d.y == 1 {
        force += downwash_force(p);
    }
    let pushed = faces_in[at] + force[f.axis] * params.dt;
    if d.y == 1 {
        faces_out[out] = pushed;
        return;
    }
    let drag = params.layer.w / (f32(f.k) + 0.5);
    faces_out[out] = pushed / (1.0 + drag * params.dt);
}
