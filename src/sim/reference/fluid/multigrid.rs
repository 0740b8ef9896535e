//! CPU twin of the pressure solvers (`shaders/fluid_pressure.wgsl` for Jacobi,
//! `shaders/fluid_multigrid.wgsl` for the V-cycles) on the equation every level shares,
//! Σ w_k (p_k − p) / H² = f, with w_k the weight of the face towards neighbour k.
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
//! - Red-black Gauss–Seidel smoothing, [`PRE_SWEEPS`] before and [`POST_SWEEPS`] after the
//!   coarse correction; [`coarsest_sweeps`] on the coarsest level.
//! - Restriction averages the residuals of the four children; prolongation is bilinear
//!   (9/16, 3/16, 3/16, 1/16), beyond a closed border mirrored, beyond an open one
//!   extrapolated to the border's 0 ([`open_ghost`]).

use crate::scene::Boundary;

use super::grid::cell_ref;

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

/// Red-black sweeps on the coarsest level of side `m`: enough to carry a correction across
/// it (the 4² level of a power-of-two grid gets 8).
pub fn coarsest_sweeps(m: u32) -> u32 {
    (2 * m).clamp(8, 128)
}

/// One level of the hierarchy.
#[derive(Clone, Debug)]
pub struct Level {
    pub size: u32,
    /// H² in m².
    pub h2: f32,
    /// Pressure (finest) or error (below).
    pub p: Vec<f32>,
    /// Right-hand side: the divergence (finest) or the restricted residual.
    pub f: Vec<f32>,
    /// Left, right, bottom, top face weights per cell.
    pub w: Vec<[f32; 4]>,
}

impl Level {
    /// A zeroed level of side `size` and cell side `h`.
    pub fn new(size: u32, h: f32) -> Self {
        let cells = size as usize * size as usize;
        Self {
            size,
            h2: h * h,
            p: vec![0.0; cells],
            f: vec![0.0; cells],
            w: vec![[0.0; 4]; cells],
        }
    }
}

fn total(w: [f32; 4]) -> f32 {
    w[0] + w[1] + w[2] + w[3]
}

/// `neighbour_sum`: Σ w_k p_k, with p = 0 beyond an open border.
fn neighbour_sum(p: &[f32], n: i32, boundary: Boundary, i: i32, j: i32, w: [f32; 4]) -> f32 {
    let at = |i: i32, j: i32| cell_ref(i, j, n, boundary).map_or(0.0, |c| p[c]);
    w[0] * at(i - 1, j) + w[1] * at(i + 1, j) + w[2] * at(i, j - 1) + w[3] * at(i, j + 1)
}

/// One Jacobi iteration (`fluid_pressure.wgsl`): a new pressure from `p`.
pub fn jacobi(
    p: &[f32],
    f: &[f32],
    w: &[[f32; 4]],
    n: u32,
    h: f32,
    boundary: Boundary,
) -> Vec<f32> {
    let m = n as i32;
    let mut out = vec![0.0; p.len()];
    for j in 0..m {
        for i in 0..m {
            let idx = (j * m + i) as usize;
            let t = total(w[idx]);
            if t == 0.0 {
                continue;
            }
            out[idx] = (neighbour_sum(p, m, boundary, i, j, w[idx]) - h * h * f[idx]) / t;
        }
    }
    out
}

/// `smooth`: one half-sweep of red-black Gauss–Seidel over the cells of `colour`.
pub fn smooth(level: &mut Level, boundary: Boundary, colour: u32) {
    let m = level.size as i32;
    for j in 0..m {
        for i in 0..m {
            if (i + j) as u32 % 2 != colour {
                continue;
            }
            let idx = (j * m + i) as usize;
            let w = level.w[idx];
            let t = total(w);
            level.p[idx] = if t == 0.0 {
                0.0
            } else {
                (neighbour_sum(&level.p, m, boundary, i, j, w) - level.h2 * level.f[idx]) / t
            };
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

/// The residual f − A p of cell (i, j) of `level`; 0 in a dropped-out cell.
pub fn residual(level: &Level, boundary: Boundary, i: i32, j: i32) -> f32 {
    let m = level.size as i32;
    let idx = (j * m + i) as usize;
    let w = level.w[idx];
    let t = total(w);
    if t == 0.0 {
        return 0.0;
    }
    level.f[idx] - (neighbour_sum(&level.p, m, boundary, i, j, w) - t * level.p[idx]) / level.h2
}

/// `restrict_residual`: the coarse right-hand side, and a zero coarse error.
pub fn restrict_residual(fine: &Level, coarse: &mut Level, boundary: Boundary) {
    let mc = coarse.size as i32;
    for cj in 0..mc {
        for ci in 0..mc {
            let (i, j) = (2 * ci, 2 * cj);
            let sum = residual(fine, boundary, i, j)
                + residual(fine, boundary, i + 1, j)
                + residual(fine, boundary, i, j + 1)
                + residual(fine, boundary, i + 1, j + 1);
            let idx = (cj * mc + ci) as usize;
            coarse.f[idx] = sum * 0.25;
            coarse.p[idx] = 0.0;
        }
    }
}

/// `coarsen_weights`: each coarse face weighs the mean of the two fine faces it covers,
/// open-border faces times `scale` ([`border_scale`] of the fine level).
pub fn coarsen_weights(fine: &Level, coarse: &mut Level, boundary: Boundary, scale: f32) {
    let (m, mc) = (fine.size as usize, coarse.size as usize);
    for cj in 0..mc {
        for ci in 0..mc {
            let (i, j) = (2 * ci, 2 * cj);
            let a = fine.w[j * m + i];
            let b = fine.w[j * m + i + 1];
            let d = fine.w[(j + 1) * m + i];
            let e = fine.w[(j + 1) * m + i + 1];
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
            coarse.w[cj * mc + ci] = w;
        }
    }
}

/// `coarse_at`: the coarse error at (ci, cj), mirrored beyond a closed border, times
/// `ghost` ([`open_ghost`]) per axis beyond an open one, `centre` for a dropped-out cell.
fn coarse_at(coarse: &Level, boundary: Boundary, ghost: f32, ci: i32, cj: i32, centre: f32) -> f32 {
    let mc = coarse.size as i32;
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
    let idx = (j * mc + i) as usize;
    if total(coarse.w[idx]) == 0.0 {
        sign * centre
    } else {
        sign * coarse.p[idx]
    }
}

/// `prolong`: adds the bilinear coarse error to every fine cell that takes part; `ghost` is
/// [`open_ghost`] of the coarse level.
pub fn prolong(coarse: &Level, fine: &mut Level, boundary: Boundary, ghost: f32) {
    let (m, mc) = (fine.size as usize, coarse.size as usize);
    for j in 0..m {
        for i in 0..m {
            let idx = j * m + i;
            if total(fine.w[idx]) == 0.0 {
                continue;
            }
            let (ci, cj) = ((i / 2) as i32, (j / 2) as i32);
            let di = if i % 2 == 1 { 1 } else { -1 };
            let dj = if j % 2 == 1 { 1 } else { -1 };
            let centre = coarse.p[cj as usize * mc + ci as usize];
            let x = coarse_at(coarse, boundary, ghost, ci + di, cj, centre);
            let y = coarse_at(coarse, boundary, ghost, ci, cj + dj, centre);
            let d = coarse_at(coarse, boundary, ghost, ci + di, cj + dj, centre);
            fine.p[idx] += ((0.5625 * centre + 0.1875 * x) + 0.1875 * y) + 0.0625 * d;
        }
    }
}

/// `cycles` V-cycles on `levels` (finest first, its `p`, `f` and `w` set), after coarsening
/// the weights: `Multigrid::encode` on the GPU.
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
