// Wind step, pass 6 with `pressure_solver: Multigrid`: V-cycles on the pressure equation
// Σ w_k (p_k − p) / H² = f of every level (f = D on the finest, the restricted residual
// below), with the face weights w_k of `fluid_splat.wgsl` on the finest level and their
// averages below (`coarsen_weights`): a coarse face is as open as the two fine faces it
// covers (open-border faces rescaled, see `coarsen_weights`), so solids are carried down by
// their coefficients, and a coarse cell whose faces
// are all closed (all four children solid, or walled in) drops out of its level.
// Entry points, in the order of a cycle on each level:
// `smooth_colour` – red-black Gauss–Seidel over the cells of one colour (i + j parity);
// `restrict_residual` – the residual of the four children of each coarse cell, averaged,
//   is the coarse right-hand side; the coarse error starts at 0;
// `prolong` – the coarse error, bilinear (9/16, 3/16, 3/16, 1/16) from the four nearest
//   coarse cells, added to the fine pressure; beyond a border the coarse error is mirrored
//   (closed, Neumann) or extrapolated linearly to the open border's 0 (`open_ghost`), a
//   dropped-out coarse cell counts as the nearest one.
// CPU twin: src/sim/reference/fluid/multigrid.rs.
//!include fluid_common.wgsl

struct MgParams {
    // Cells per side of this level.
    size: u32,
    boundary: u32,
    // H² of this level (m²).
    h2: f32,
    // Which colour `smooth_colour` updates: cells with (i + j) % 2 == colour.
    colour: u32,
    // Factor on the open-border face weights of the next coarser level.
    border_scale: f32,
    // Factor on the coarse edge value for a coarse cell beyond an open border.
    open_ghost: f32,
    pad: vec2<u32>,
}

@group(0) @binding(0) var<uniform> level: MgParams;
@group(0) @binding(1) var<storage, read> f: array<f32>;
@group(0) @binding(2) var<storage, read> w: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read_write> p: array<f32>;
@group(0) @binding(4) var<storage, read_write> coarse_f: array<f32>;
@group(0) @binding(5) var<storage, read_write> coarse_p: array<f32>;
@group(0) @binding(6) var<storage, read_write> coarse_w: array<vec4<f32>>;

fn p_at(i: i32, j: i32) -> f32 {
    let c = fluid_cell_ref(i, j, i32(level.size), level.boundary);
    if c < 0 {
        return 0.0;
    }
    return p[c];
}

// Σ w_k p_k over the four neighbours of (i, j), whose weights are `wc`.
fn neighbour_sum(i: i32, j: i32, wc: vec4<f32>) -> f32 {
    return wc.x * p_at(i - 1, j) + wc.y * p_at(i + 1, j) + wc.z * p_at(i, j - 1)
        + wc.w * p_at(i, j + 1);
}

fn total(wc: vec4<f32>) -> f32 {
    return wc.x + wc.y + wc.z + wc.w;
}

// Dispatched over ⌈size / 2⌉ × size threads: thread x of row j is the x-th cell of that
// row with the wanted colour.
@compute @workgroup_size(8, 8)
fn smooth_colour(@builtin(global_invocation_id) gid: vec3<u32>) {
    let m = level.size;
    let j = gid.y;
    let i = 2u * gid.x + ((j + level.colour) & 1u);
    if i >= m || j >= m {
        return;
    }
    let idx = j * m + i;
    let wc = w[idx];
    let t = total(wc);
    if t == 0.0 {
        p[idx] = 0.0;
        return;
    }
    p[idx] = (neighbour_sum(i32(i), i32(j), wc) - level.h2 * f[idx]) / t;
}

// The residual f − A p of fine cell (i, j); 0 in a cell that dropped out.
fn residual(i: i32, j: i32) -> f32 {
    let idx = u32(j) * level.size + u32(i);
    let wc = w[idx];
    let t = total(wc);
    if t == 0.0 {
        return 0.0;
    }
    return f[idx] - (neighbour_sum(i, j, wc) - t * p[idx]) / level.h2;
}

// Dispatched over the coarse level's cells; `level` is the fine level.
@compute @workgroup_size(8, 8)
fn restrict_residual(@builtin(global_invocation_id) gid: vec3<u32>) {
    let mc = level.size / 2u;
    if gid.x >= mc || gid.y >= mc {
        return;
    }
    let i = 2 * i32(gid.x);
    let j = 2 * i32(gid.y);
    let sum = residual(i, j) + residual(i + 1, j) + residual(i, j + 1) + residual(i + 1, j + 1);
    let idx = gid.y * mc + gid.x;
    coarse_f[idx] = sum * 0.25;
    coarse_p[idx] = 0.0;
}

// Dispatched over the coarse level's cells; `level` is the fine level.
@compute @workgroup_size(8, 8)
fn coarsen_weights(@builtin(global_invocation_id) gid: vec3<u32>) {
    let mc = level.size / 2u;
    if gid.x >= mc || gid.y >= mc {
        return;
    }
    let m = level.size;
    let i = 2u * gid.x;
    let j = 2u * gid.y;
    let a = w[j * m + i];
    let b = w[j * m + i + 1u];
    let d = w[(j + 1u) * m + i];
    let e = w[(j + 1u) * m + i + 1u];
    var cw = vec4<f32>(
        (a.x + d.x) * 0.5,
        (b.y + e.y) * 0.5,
        (a.z + b.z) * 0.5,
        (d.w + e.w) * 0.5,
    );
    // The 0 pressure of an open border lies half a finest cell beyond it, which is farther
    // from a coarse cell's centre in its own units than from a fine one's: scale the
    // border faces so that every level puts it at the same place.
    if level.boundary != FLUID_PERIODIC {
        let last = mc - 1u;
        let s = level.border_scale;
        cw = cw * vec4<f32>(
            select(1.0, s, gid.x == 0u),
            select(1.0, s, gid.x == last),
            select(1.0, s, gid.y == 0u),
            select(1.0, s, gid.y == last),
        );
    }
    coarse_w[gid.y * mc + gid.x] = cw;
}

// The coarse error at (ci, cj), which may lie beyond the border; `centre` stands in for a
// dropped-out cell.
fn coarse_at(ci: i32, cj: i32, centre: f32) -> f32 {
    let mc = i32(level.size / 2u);
    var sign = 1.0;
    var i = ci;
    var j = cj;
    if level.boundary == FLUID_PERIODIC {
        i = fluid_wrap(ci, mc);
        j = fluid_wrap(cj, mc);
    } else {
        if level.boundary == FLUID_OPEN {
            if ci < 0 || ci >= mc {
                sign = sign * level.open_ghost;
            }
            if cj < 0 || cj >= mc {
                sign = sign * level.open_ghost;
            }
        }
        i = clamp(ci, 0, mc - 1);
        j = clamp(cj, 0, mc - 1);
    }
    let idx = j * mc + i;
    if total(coarse_w[idx]) == 0.0 {
        return sign * centre;
    }
    return sign * coarse_p[idx];
}

// Dispatched over the fine level's cells.
@compute @workgroup_size(8, 8)
fn prolong(@builtin(global_invocation_id) gid: vec3<u32>) {
    let m = level.size;
    if gid.x >= m || gid.y >= m {
        return;
    }
    let idx = gid.y * m + gid.x;
    if total(w[idx]) == 0.0 {
        return;
    }
    let mc = m / 2u;
    let ci = i32(gid.x / 2u);
    let cj = i32(gid.y / 2u);
    // The nearer coarse neighbour: left/below for an even child, right/above for an odd.
    let di = select(-1, 1, (gid.x & 1u) == 1u);
    let dj = select(-1, 1, (gid.y & 1u) == 1u);
    let centre = coarse_p[u32(cj) * mc + u32(ci)];
    let x = coarse_at(ci + di, cj, centre);
    let y = coarse_at(ci, cj + dj, centre);
    let d = coarse_at(ci + di, cj + dj, centre);
    p[idx] += ((0.5625 * centre + 0.1875 * x) + 0.1875 * y) + 0.0625 * d;
}
