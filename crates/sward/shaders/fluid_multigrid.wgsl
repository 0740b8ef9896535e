// Wind step, pass 6 with `pressure_solver: Multigrid`: V-cycles on the pressure equation
// Σ w_k (p_k − p) / H² + Σ w_v (p_v − p) / dy² = f of every level (f = D on the finest, the
// restricted residual below), with the face weights of `fluid_splat.wgsl` on the finest
// level and their averages below (`coarsen_weights`): a coarse face is as open as the fine
// faces it covers (open-border faces rescaled, see `coarsen_weights`), so solids are
// carried down by their coefficients, and a coarse cell whose faces are all closed drops out
// of its level. The levels halve the grid in x and z only; every level keeps all the layers
// (they are few, and the ground and the top bound them).
// Entry points, in the order of a cycle on each level:
// `smooth_colour` – red-black line Gauss–Seidel: each column of one colour (i + j parity)
//   is solved exactly along its layers (a tridiagonal system, Thomas' algorithm) with its
//   horizontal neighbours held. Coarse levels couple the layers ever more strongly than the
//   columns (H²/dy² grows 4× a level); relaxing whole columns is what keeps the smoother
//   good then. On a 2D grid a column is one cell and this is point Gauss–Seidel exactly;
// `restrict_residual` – the residual of the four children of each coarse cell (same
//   layer), averaged, is the coarse right-hand side; the coarse error starts at 0;
// `prolong` – the coarse error, bilinear (9/16, 3/16, 3/16, 1/16) from the four nearest
//   coarse cells of the layer, added to the fine pressure; beyond a border the coarse error
//   is mirrored (closed, Neumann) or extrapolated linearly to the open border's 0
//   (`open_ghost`), a dropped-out coarse cell counts as the nearest one.
// CPU twin: src/sim/reference/fluid/multigrid.rs.
//!include fluid_common.wgsl

// Most layers a column may have (`MAX_LAYERS` in src/sim/fluid/config.rs).
const MG_MAX_LAYERS: u32 = 16u;

// Whether the grid has more than one layer (set per pipeline, `fluid::multigrid`). On a 2D
// grid the column solve is one division, and `smooth_colour` is built without Thomas'
// algorithm, whose two private arrays llvmpipe keeps in memory for every lane.
override LAYERED: bool = true;

struct MgParams {
    // Cells per side of this level.
    size: u32,
    boundary: u32,
    // H² of this level (m²).
    h2: f32,
    // Which colour `smooth_colour` updates: columns with (i + j) % 2 == colour.
    colour: u32,
    // Factor on the open-border face weights of the next coarser level.
    border_scale: f32,
    // Factor on the coarse edge value for a coarse cell beyond an open border.
    open_ghost: f32,
    layers: u32,
    // H² / dy²: the weight of a vertical face relative to a horizontal one.
    vertical: f32,
}

@group(0) @binding(0) var<uniform> level: MgParams;
@group(0) @binding(1) var<storage, read> f: array<f32>;
// Two vec4 per cell: (−x, +x, −z, +z) and (below, above, 0, 0).
@group(0) @binding(2) var<storage, read> w: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read_write> p: array<f32>;
@group(0) @binding(4) var<storage, read_write> coarse_f: array<f32>;
@group(0) @binding(5) var<storage, read_write> coarse_p: array<f32>;
@group(0) @binding(6) var<storage, read_write> coarse_w: array<vec4<f32>>;

fn p_at(c: vec3<i32>) -> f32 {
    let r = fluid_cell_ref(c, i32(level.size), i32(level.layers), level.boundary);
    if r < 0 {
        return 0.0;
    }
    return p[r];
}

// Σ w_k p_k over the four horizontal neighbours of c, whose weights are `wc`.
fn neighbour_sum(c: vec3<i32>, wc: vec4<f32>) -> f32 {
    return wc.x * p_at(c - vec3<i32>(1, 0, 0)) + wc.y * p_at(c + vec3<i32>(1, 0, 0))
        + wc.z * p_at(c - vec3<i32>(0, 1, 0)) + wc.w * p_at(c + vec3<i32>(0, 1, 0));
}

// Σ w_v p_v over the cells below and above c.
fn vertical_sum(c: vec3<i32>, wv: vec4<f32>) -> f32 {
    return wv.x * p_at(c - vec3<i32>(0, 0, 1)) + wv.y * p_at(c + vec3<i32>(0, 0, 1));
}

// The diagonal: Σ w_k + (H²/dy²) Σ w_v.
fn total(wc: vec4<f32>, wv: vec4<f32>, vertical: f32) -> f32 {
    return (wc.x + wc.y + wc.z + wc.w) + vertical * (wv.x + wv.y);
}

fn cell_index(i: u32, j: u32, k: u32, m: u32) -> u32 {
    return (k * m + j) * m + i;
}

// Dispatched over ⌈size / 2⌉ × size threads: thread x of row j is the x-th column of that
// row with the wanted colour.
@compute @workgroup_size(8, 8)
fn smooth_colour(@builtin(global_invocation_id) gid: vec3<u32>) {
    let m = level.size;
    let j = gid.y;
    let i = 2u * gid.x + ((j + level.colour) & 1u);
    if i >= m || j >= m {
        return;
    }
    let layers = level.layers;
    let r = level.vertical;
    if !LAYERED {
        // Point Gauss–Seidel: Thomas' algorithm below with one layer, the same arithmetic
        // (p = d / b, 0 in a cell that dropped out).
        let idx = cell_index(i, j, 0u, m);
        let wc = w[2u * idx];
        let t = total(wc, w[2u * idx + 1u], r);
        var v = 0.0;
        if t != 0.0 {
            v = (neighbour_sum(vec3<i32>(i32(i), i32(j), 0), wc) - level.h2 * f[idx]) / t;
        }
        p[idx] = v;
        return;
    }
    // Thomas' algorithm on b_k p_k + a_k p_(k−1) + c_k p_(k+1) = d_k.
    var cp: array<f32, MG_MAX_LAYERS>;
    var dp: array<f32, MG_MAX_LAYERS>;
    for (var k = 0u; k < layers; k++) {
        let idx = cell_index(i, j, k, m);
        let wc = w[2u * idx];
        let wv = w[2u * idx + 1u];
        let t = total(wc, wv, r);
        var b = 1.0;
        var a = 0.0;
        var c = 0.0;
        var d = 0.0;
        if t != 0.0 {
            b = t;
            a = -(r * wv.x);
            c = -(r * wv.y);
            d = neighbour_sum(vec3<i32>(i32(i), i32(j), i32(k)), wc) - level.h2 * f[idx];
        }
        if k == 0u {
            cp[0] = c / b;
            dp[0] = d / b;
        } else {
            var den = b - a * cp[k - 1u];
            // A column walled in on every side but along itself is singular (Neumann all
            // round); keep its values finite.
            if den <= 1e-6 * b {
                den = b;
            }
            cp[k] = c / den;
            dp[k] = (d - a * dp[k - 1u]) / den;
        }
    }
    var above = 0.0;
    for (var kk = 0u; kk < layers; kk++) {
        let k = layers - 1u - kk;
        var v = dp[k];
        if kk > 0u {
            v = dp[k] - cp[k] * above;
        }
        p[cell_index(i, j, k, m)] = v;
        above = v;
    }
}

// The residual f − A p of fine cell c; 0 in a cell that dropped out.
fn residual(c: vec3<i32>) -> f32 {
    let idx = cell_index(u32(c.x), u32(c.y), u32(c.z), level.size);
    let wc = w[2u * idx];
    let wv = w[2u * idx + 1u];
    let t = total(wc, wv, level.vertical);
    if t == 0.0 {
        return 0.0;
    }
    let sum = neighbour_sum(c, wc) + level.vertical * vertical_sum(c, wv);
    return f[idx] - (sum - t * p[idx]) / level.h2;
}

// Dispatched over the coarse level's cells; `level` is the fine level.
@compute @workgroup_size(8, 8)
fn restrict_residual(@builtin(global_invocation_id) gid: vec3<u32>) {
    let mc = level.size / 2u;
    if gid.x >= mc || gid.y >= mc || gid.z >= level.layers {
        return;
    }
    let c = vec3<i32>(2 * i32(gid.x), 2 * i32(gid.y), i32(gid.z));
    let sum = residual(c) + residual(c + vec3<i32>(1, 0, 0)) + residual(c + vec3<i32>(0, 1, 0))
        + residual(c + vec3<i32>(1, 1, 0));
    let idx = cell_index(gid.x, gid.y, gid.z, mc);
    coarse_f[idx] = sum * 0.25;
    coarse_p[idx] = 0.0;
}

// Dispatched over the coarse level's cells; `level` is the fine level.
@compute @workgroup_size(8, 8)
fn coarsen_weights(@builtin(global_invocation_id) gid: vec3<u32>) {
    let mc = level.size / 2u;
    if gid.x >= mc || gid.y >= mc || gid.z >= level.layers {
        return;
    }
    let m = level.size;
    let i = 2u * gid.x;
    let j = 2u * gid.y;
    let k = gid.z;
    let ia = cell_index(i, j, k, m);
    let ib = cell_index(i + 1u, j, k, m);
    let id = cell_index(i, j + 1u, k, m);
    let ie = cell_index(i + 1u, j + 1u, k, m);
    let a = w[2u * ia];
    let b = w[2u * ib];
    let d = w[2u * id];
    let e = w[2u * ie];
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
    // A coarse cell's floor and ceiling are the four children's, as open as they are.
    let va = w[2u * ia + 1u];
    let vb = w[2u * ib + 1u];
    let vd = w[2u * id + 1u];
    let ve = w[2u * ie + 1u];
    let cv = ((va + vb) + (vd + ve)) * 0.25;
    let out = cell_index(gid.x, gid.y, gid.z, mc);
    coarse_w[2u * out] = cw;
    coarse_w[2u * out + 1u] = vec4<f32>(cv.xy, 0.0, 0.0);
}

// The coarse error at (ci, cj) of layer k, which may lie beyond the border; `centre` stands
// in for a dropped-out cell.
fn coarse_at(ci: i32, cj: i32, k: u32, centre: f32) -> f32 {
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
    let idx = cell_index(u32(i), u32(j), k, u32(mc));
    if total(coarse_w[2u * idx], coarse_w[2u * idx + 1u], 1.0) == 0.0 {
        return sign * centre;
    }
    return sign * coarse_p[idx];
}

// Dispatched over the fine level's cells.
@compute @workgroup_size(8, 8)
fn prolong(@builtin(global_invocation_id) gid: vec3<u32>) {
    let m = level.size;
    if gid.x >= m || gid.y >= m || gid.z >= level.layers {
        return;
    }
    let idx = cell_index(gid.x, gid.y, gid.z, m);
    if total(w[2u * idx], w[2u * idx + 1u], 1.0) == 0.0 {
        return;
    }
    let mc = m / 2u;
    let ci = i32(gid.x / 2u);
    let cj = i32(gid.y / 2u);
    // The nearer coarse neighbour: left/below for an even child, right/above for an odd.
    let di = select(-1, 1, (gid.x & 1u) == 1u);
    let dj = select(-1, 1, (gid.y & 1u) == 1u);
    let centre = coarse_p[cell_index(u32(ci), u32(cj), gid.z, mc)];
    let x = coarse_at(ci + di, cj, gid.z, centre);
    let y = coarse_at(ci, cj + dj, gid.z, centre);
    let d = coarse_at(ci + di, cj + dj, gid.z, centre);
    p[idx] += ((0.5625 * centre + 0.1875 * x) + 0.1875 * y) + 0.0625 * d;
}
