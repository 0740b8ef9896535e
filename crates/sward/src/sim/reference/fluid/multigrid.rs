//! CPU twin of the pressure solvers (`shaders/fluid_pressure.wgsl` for Jacobi,
//! `shaders/fluid_multigrid.wgsl` for the V-cycles) on the equation every level shares,
//! Σ w_k (p_k − p) / H² + Σ w_v (p_v − p) / dy² = f, with w_k the weight of the face towards
//! horizontal neighbour k and w_v those of the faces below and above (0 on a 2D grid).
//!
//! Choices, which the GPU solver follows:
//! - Cell-centred geometric multigrid: each level halves the side while it is even and the
//!   half is at least 4 cells (and, on a periodic grid, even); see
//!   [`crate::sim::fluid::FluidConfig::multigrid_levels`].
//! - Solids by their coefficients: a coarse face weighs the mean of the two fine faces it
//!   covers, so a half-blocked coarse face passes half the flow. A coarse cell all of whose
//!   faces weigh 0 (all four children solid, or walled in) drops out: pressure 0, never
//!   read. Open-border faces are rescaled level by level ([`border_weight`]) so that every
//!   level puts the border's 0 pressure at the same place. The coarse operator is
//!   rediscretised (w / H²), not Galerkin: with bilinear
//!   prolongation that is the pairing that converges at the textbook rate.
//! - Semi-coarsening: the levels halve x and z and keep every layer (a 3D grid has at most
//!   16, bounded by the ground and the top).
//! - Red-black line Gauss–Seidel smoothing: each column of one colour is solved exactly
//!   along its layers (Thomas' algorithm) with its horizontal neighbours held, which stays a
//!   good smoother when the coarse levels couple the layers far more strongly than the
//!   columns (H²/dy² grows 4× per level); on a 2D grid it is point red-black Gauss–Seidel.
//!   [`PRE_SWEEPS`] before and [`POST_SWEEPS`] after the coarse correction;
//!   [`coarsest_sweeps`] on the coarsest level.
//! - Restriction averages the residuals of the four children; prolongation is bilinear
//!   (9/16, 3/16, 3/16, 1/16), beyond a closed border mirrored, beyond an open one
//!   extrapolated to the border's 0 ([`open_ghost`]).

use crate::scene::Boundary;

use glam::IVec3;

use super::grid::cell_ref;
use crate::sim::fluid::FluidConfig;

/// Red-black sweeps before the restriction on every level.
pub const PRE_SWEEPS: u32 = 2;
/// Red-black sweeps after the prolongation on every level.
pub const POST_SWEEPS: u32 = 2;

/// The weight of an open-border face at level `l` relative to an interior one:
/// 2^(l+1) / (2^l + 1). The finest level reads the 0 pressure of an open border at the ghost
/// cell's centre, h beyond its last centre (h/2 beyond the face). A coarse cell's centre is
/// H/2 inside the face, so that place is H/2 + h/2 away, and the flux through the face is
/// p / (H/2 + h/2) = (2H / (H + h)) · p / H: weight 1 on the finest level, 4/3 on the next,
/// towards 2 below. With weight 1 on every level the coarse grids put the border too far
/// out, and smooth divergence near an open border converged the slower the more levels
/// there were (5.6× per two V-cycles at 256², 1.2× at 1024², instead of ~170×).
pub fn border_weight(l: usize) -> f32 {
    let h_ratio = (1u32 << l) as f32;
    2.0 * h_ratio / (h_ratio + 1.0)
}

/// The factor `coarsen_weights` puts on the open-border faces of level `l + 1` (their fine
/// faces already carry [`border_weight`]`(l)`).
pub fn border_scale(l: usize) -> f32 {
    border_weight(l + 1) / border_weight(l)
}

/// What `prolong` takes for a coarse cell of level `l` beyond an open border, as a factor on
/// the edge cell's value: the line through the edge centre and the border's 0, which lies
/// H/2 + h/2 beyond it ([`border_weight`]), read one coarse cell H out: 1 − 2H / (H + h)
/// (−1/3 on level 1, towards −1 below).
pub fn open_ghost(l: usize) -> f32 {
    1.0 - border_weight(l)
}

/// H² of level `l` and H²/dy², the weight of a vertical face relative to a horizontal one
/// (what `MgParams` carries).
pub fn level_scales(config: &FluidConfig, l: usize) -> (f32, f32) {
    let cell = config.cell_size * (1u32 << l) as f32;
    let h2 = cell * cell;
    let inv_dy = 1.0 / config.layer_height;
    (h2, h2 * inv_dy * inv_dy)
}

/// Red-black sweeps on the coarsest level of side `m`: enough to carry a correction across
/// it (the 4² level of a power-of-two grid gets 8).
pub fn coarsest_sweeps(m: u32) -> u32 {
    (2 * m).clamp(8, 128)
}

/// One level of the hierarchy.
#[derive(Clone, Debug)]
pub struct Level {
    /// Cells per side of this level (the finest grid's side halved once per level).
    pub size: u32,
    /// Layers of air, the same on every level (the hierarchy coarsens only horizontally).
    pub layers: u32,
    /// H² in m².
    pub h2: f32,
    /// H² / dy².
    pub vertical: f32,
    /// Pressure (finest) or error (below).
    pub p: Vec<f32>,
    /// Right-hand side: the divergence (finest) or the restricted residual.
    pub f: Vec<f32>,
    /// −x, +x, −z, +z face weights per cell.
    pub w: Vec<[f32; 4]>,
    /// Below, above face weights per cell.
    pub wv: Vec<[f32; 2]>,
}

impl Level {
    /// A zeroed level `l` of side `size` of the grid `config`.
    pub fn new(config: &FluidConfig, l: usize, size: u32) -> Self {
        let cells = size as usize * size as usize * config.layers as usize;
        let (h2, vertical) = level_scales(config, l);
        Self {
            size,
            layers: config.layers,
            h2,
            vertical,
            p: vec![0.0; cells],
            f: vec![0.0; cells],
            w: vec![[0.0; 4]; cells],
            wv: vec![[0.0; 2]; cells],
        }
    }

    fn index(&self, i: i32, j: i32, k: i32) -> usize {
        let m = self.size as i32;
        ((k * m + j) * m + i) as usize
    }

    /// `total`: Σ w_k + (H²/dy²) Σ w_v of cell `idx`, with `vertical` the factor.
    fn total(&self, idx: usize, vertical: f32) -> f32 {
        let w = self.w[idx];
        let v = self.wv[idx];
        (w[0] + w[1] + w[2] + w[3]) + vertical * (v[0] + v[1])
    }
}

/// `neighbour_sum`: Σ w_k p_k over the horizontal neighbours, with p = 0 beyond an open
/// border.
fn neighbour_sum(p: &[f32], n: i32, layers: i32, boundary: Boundary, c: IVec3, w: [f32; 4]) -> f32 {
    let at = |d: IVec3| cell_ref(c + d, n, layers, boundary).map_or(0.0, |r| p[r]);
    w[0] * at(IVec3::new(-1, 0, 0))
        + w[1] * at(IVec3::new(1, 0, 0))
        + w[2] * at(IVec3::new(0, -1, 0))
        + w[3] * at(IVec3::new(0, 1, 0))
}

/// `vertical_sum`: Σ w_v p_v over the cells below and above.
fn vertical_sum(p: &[f32], n: i32, layers: i32, boundary: Boundary, c: IVec3, w: [f32; 2]) -> f32 {
    let at = |d: IVec3| cell_ref(c + d, n, layers, boundary).map_or(0.0, |r| p[r]);
    w[0] * at(IVec3::new(0, 0, -1)) + w[1] * at(IVec3::new(0, 0, 1))
}

/// One Jacobi iteration (`fluid_pressure.wgsl`) on the finest level: a new pressure from
/// its `p`; `h` the cell size, `inv_dy` 1 / the layer height.
pub fn jacobi(level: &Level, h: f32, inv_dy: f32, boundary: Boundary) -> Vec<f32> {
    let (m, layers) = (level.size as i32, level.layers as i32);
    let r = h * h * inv_dy * inv_dy;
    let mut out = vec![0.0; level.p.len()];
    for k in 0..layers {
        for j in 0..m {
            for i in 0..m {
                let idx = level.index(i, j, k);
                let t = level.total(idx, r);
                if t == 0.0 {
                    continue;
                }
                let c = IVec3::new(i, j, k);
                let sum = neighbour_sum(&level.p, m, layers, boundary, c, level.w[idx]);
                let vertical = vertical_sum(&level.p, m, layers, boundary, c, level.wv[idx]);
                out[idx] = (sum + r * vertical - h * h * level.f[idx]) / t;
            }
        }
    }
    out
}

/// `smooth_colour`: one half-sweep of red-black line Gauss–Seidel over the columns of
/// `colour`, each solved along its layers with Thomas' algorithm.
pub fn smooth(level: &mut Level, boundary: Boundary, colour: u32) {
    let (m, layers) = (level.size as i32, level.layers as i32);
    let r = level.vertical;
    let (mut cp, mut dp) = (vec![0.0f32; layers as usize], vec![0.0f32; layers as usize]);
    for j in 0..m {
        for i in 0..m {
            if (i + j) as u32 % 2 != colour {
                continue;
            }
            for k in 0..layers {
                let idx = level.index(i, j, k);
                let t = level.total(idx, r);
                let (mut b, mut a, mut c, mut d) = (1.0f32, 0.0f32, 0.0f32, 0.0f32);
                if t != 0.0 {
                    let wv = level.wv[idx];
                    b = t;
                    a = -(r * wv[0]);
                    c = -(r * wv[1]);
                    let at = IVec3::new(i, j, k);
                    d = neighbour_sum(&level.p, m, layers, boundary, at, level.w[idx])
                        - level.h2 * level.f[idx];
                }
                let k = k as usize;
                if k == 0 {
                    cp[0] = c / b;
                    dp[0] = d / b;
                } else {
                    let mut den = b - a * cp[k - 1];
                    if den <= 1e-6 * b {
                        den = b;
                    }
                    cp[k] = c / den;
                    dp[k] = (d - a * dp[k - 1]) / den;
                }
            }
            let mut above = 0.0;
            for kk in 0..layers as usize {
                let k = layers as usize - 1 - kk;
                let v = if kk > 0 { dp[k] - cp[k] * above } else { dp[k] };
                let idx = level.index(i, j, k as i32);
                level.p[idx] = v;
                above = v;
            }
        }
    }
}

/// `sweeps` red-black sweeps (red then black).
pub fn sweep(level: &mut Level, boundary: Boundary, sweeps: u32) {
    for _ in 0..sweeps {
        smooth(level, boundary, 0);
        smooth(level, boundary, 1);
    }
}

/// The residual f − A p of cell c of `level`; 0 in a dropped-out cell.
pub fn residual(level: &Level, boundary: Boundary, c: IVec3) -> f32 {
    let (m, layers) = (level.size as i32, level.layers as i32);
    let idx = level.index(c.x, c.y, c.z);
    let t = level.total(idx, level.vertical);
    if t == 0.0 {
        return 0.0;
    }
    let sum = neighbour_sum(&level.p, m, layers, boundary, c, level.w[idx])
        + level.vertical * vertical_sum(&level.p, m, layers, boundary, c, level.wv[idx]);
    level.f[idx] - (sum - t * level.p[idx]) / level.h2
}

/// `restrict_residual`: the coarse right-hand side, and a zero coarse error.
pub fn restrict_residual(fine: &Level, coarse: &mut Level, boundary: Boundary) {
    let mc = coarse.size as i32;
    for k in 0..coarse.layers as i32 {
        for cj in 0..mc {
            for ci in 0..mc {
                let c = IVec3::new(2 * ci, 2 * cj, k);
                let sum = residual(fine, boundary, c)
                    + residual(fine, boundary, c + IVec3::new(1, 0, 0))
                    + residual(fine, boundary, c + IVec3::new(0, 1, 0))
                    + residual(fine, boundary, c + IVec3::new(1, 1, 0));
                let idx = coarse.index(ci, cj, k);
                coarse.f[idx] = sum * 0.25;
                coarse.p[idx] = 0.0;
            }
        }
    }
}

/// `coarsen_weights`: each coarse face weighs the mean of the fine faces it covers,
/// open-border faces times `scale` ([`border_scale`] of the fine level).
pub fn coarsen_weights(fine: &Level, coarse: &mut Level, boundary: Boundary, scale: f32) {
    let mc = coarse.size as i32;
    for k in 0..coarse.layers as i32 {
        for cj in 0..mc {
            for ci in 0..mc {
                let (i, j) = (2 * ci, 2 * cj);
                let ia = fine.index(i, j, k);
                let ib = fine.index(i + 1, j, k);
                let id = fine.index(i, j + 1, k);
                let ie = fine.index(i + 1, j + 1, k);
                let (a, b, d, e) = (fine.w[ia], fine.w[ib], fine.w[id], fine.w[ie]);
                let mut w = [
                    (a[0] + d[0]) * 0.5,
                    (b[1] + e[1]) * 0.5,
                    (a[2] + b[2]) * 0.5,
                    (d[3] + e[3]) * 0.5,
                ];
                if boundary != Boundary::Periodic {
                    let border = [ci == 0, ci == mc - 1, cj == 0, cj == mc - 1];
                    for (w, on) in w.iter_mut().zip(border) {
                        *w *= if on { scale } else { 1.0 };
                    }
                }
                let v = |s: usize| {
                    ((fine.wv[ia][s] + fine.wv[ib][s]) + (fine.wv[id][s] + fine.wv[ie][s])) * 0.25
                };
                let out = coarse.index(ci, cj, k);
                coarse.w[out] = w;
                coarse.wv[out] = [v(0), v(1)];
            }
        }
    }
}

/// `coarse_at`: the coarse error at (ci, cj) of layer k, mirrored beyond a closed border,
/// times `ghost` ([`open_ghost`]) per axis beyond an open one, `centre` for a dropped-out
/// cell.
fn coarse_at(coarse: &Level, boundary: Boundary, ghost: f32, c: IVec3, centre: f32) -> f32 {
    let mc = coarse.size as i32;
    let (ci, cj) = (c.x, c.y);
    let mut sign = 1.0f32;
    let (i, j) = if boundary == Boundary::Periodic {
        (ci.rem_euclid(mc), cj.rem_euclid(mc))
    } else {
        if boundary == Boundary::Open {
            if ci < 0 || ci >= mc {
                sign *= ghost;
            }
            if cj < 0 || cj >= mc {
                sign *= ghost;
            }
        }
        (ci.clamp(0, mc - 1), cj.clamp(0, mc - 1))
    };
    let idx = coarse.index(i, j, c.z);
    if coarse.total(idx, 1.0) == 0.0 {
        sign * centre
    } else {
        sign * coarse.p[idx]
    }
}

/// `prolong`: adds the bilinear coarse error to every fine cell that takes part; `ghost` is
/// [`open_ghost`] of the coarse level.
pub fn prolong(coarse: &Level, fine: &mut Level, boundary: Boundary, ghost: f32) {
    let m = fine.size as i32;
    for k in 0..fine.layers as i32 {
        for j in 0..m {
            for i in 0..m {
                let idx = fine.index(i, j, k);
                if fine.total(idx, 1.0) == 0.0 {
                    continue;
                }
                let (ci, cj) = (i / 2, j / 2);
                let di = if i % 2 == 1 { 1 } else { -1 };
                let dj = if j % 2 == 1 { 1 } else { -1 };
                let centre = coarse.p[coarse.index(ci, cj, k)];
                let at = |x: i32, y: i32| {
                    coarse_at(coarse, boundary, ghost, IVec3::new(x, y, k), centre)
                };
                let x = at(ci + di, cj);
                let y = at(ci, cj + dj);
                let d = at(ci + di, cj + dj);
                fine.p[idx] += ((0.5625 * centre + 0.1875 * x) + 0.1875 * y) + 0.0625 * d;
            }
        }
    }
}

/// `cycles` V-cycles on `levels` (finest first, its `p`, `f` and weights set), after
/// coarsening the weights: `Multigrid::encode` on the GPU.
pub fn v_cycles(levels: &mut [Level], boundary: Boundary, cycles: u32) {
    let last = levels.len() - 1;
    for l in 0..last {
        let (fine, coarse) = levels.split_at_mut(l + 1);
        coarsen_weights(&fine[l], &mut coarse[0], boundary, border_scale(l));
    }
    for _ in 0..cycles {
        for l in 0..last {
            sweep(&mut levels[l], boundary, PRE_SWEEPS);
            let (fine, coarse) = levels.split_at_mut(l + 1);
            restrict_residual(&fine[l], &mut coarse[0], boundary);
        }
        let coarsest = levels[last].size;
        sweep(&mut levels[last], boundary, coarsest_sweeps(coarsest));
        for l in (0..last).rev() {
            let (fine, coarse) = levels.split_at_mut(l + 1);
            prolong(&coarse[0], &mut fine[l], boundary, open_ghost(l + 1));
            sweep(&mut levels[l], boundary, POST_SWEEPS);
        }
    }
}
