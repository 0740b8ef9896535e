//! CPU twin of the staggered-grid Stable-Fluids wind solver (`shaders/fluid_*.wgsl`, driven
//! by [`crate::sim::fluid::FluidSolver`]). Every pass follows its shader line by line in
//! f32, with the same operand order, so that GPU read-back and this twin differ only by the
//! rounding freedom the GPU has (fused multiply-adds, division precision). The passes are
//! public one by one so that tests can stop between them (e.g. measure the divergence right
//! after the projection). The grid helpers are in [`grid`], the pressure solvers in
//! [`multigrid`].

pub mod grid;
pub mod multigrid;

use glam::Vec2;

use crate::scene::{Advection, Boundary, PressureSolver};
use crate::sim::fluid::{FluidConfig, FluidState};
use crate::sim::wind_layout::{ArrowGpu, FluidForces, MAX_ARROWS, MAX_OBSTACLES};
use grid::{
    blend, canonical, cell_ref, clamp_pos, face_cells, face_index, face_pos, face_ref, is_wall,
    scalar_index, stencil, velocity_ref,
};
use multigrid::Level;

fn v2(a: [f32; 2]) -> Vec2 {
    Vec2::new(a[0], a[1])
}

/// `arrow_force` in fluid_splat.wgsl.
pub fn arrow_force(a: &ArrowGpu, p: Vec2) -> Vec2 {
    let s = Vec2::new(a.segment[0], a.segment[1]);
    let d = Vec2::new(a.segment[2], a.segment[3]) - s;
    let len2 = d.dot(d);
    if len2 <= 0.0 || a.radius <= 0.0 {
        return Vec2::ZERO;
    }
    let t = ((p - s).dot(d) / len2).clamp(0.0, 1.0);
    let off = p - (s + d * t);
    let dist2 = off.dot(off);
    let r2 = a.radius * a.radius;
    if dist2 >= r2 {
        return Vec2::ZERO;
    }
    let w = 1.0 - dist2 / r2;
    d * (a.strength * w * w / len2.sqrt())
}

/// `downwash_force` in fluid_splat.wgsl: `downwash` = centre x, z, radius, strength.
pub fn downwash_force(downwash: [f32; 4], p: Vec2) -> Vec2 {
    let r = downwash[2];
    if r <= 0.0 {
        return Vec2::ZERO;
    }
    let off = p - Vec2::new(downwash[0], downwash[1]);
    let dist = off.dot(off).sqrt();
    if dist <= 0.0 || dist >= r {
        return Vec2::ZERO;
    }
    let half_r = 0.5 * r;
    let mut profile = dist / half_r;
    if dist > half_r {
        let t = (dist - half_r) / half_r;
        profile = 1.0 - t * t * (3.0 - 2.0 * t);
    }
    off * (downwash[3] * profile / dist)
}

/// Air velocity at world (x, z): bilinear between cell centres of the cell-centred
/// velocity, clamped to the outer cell centres. The same formula as `fluid_velocity` in
/// wind_sample.wgsl and `sample_velocity` in overlay.wgsl.
pub fn sample_velocity(state: &FluidState, x: f32, z: f32) -> [f32; 2] {
    let n = state.resolution as i32;
    let g = (Vec2::new(x, z) - v2(state.origin)) / state.cell_size;
    let q = (g - 0.5).clamp(Vec2::ZERO, Vec2::splat((n - 1) as f32));
    let c = q.floor();
    let f = q - c;
    let (ci, cj) = (c.x as i32, c.y as i32);
    let at =
        |i: i32, j: i32| v2(state.velocity[(j.clamp(0, n - 1) * n + i.clamp(0, n - 1)) as usize]);
    let a = at(ci, cj) + (at(ci + 1, cj) - at(ci, cj)) * f.x;
    let b = at(ci, cj + 1) + (at(ci + 1, cj + 1) - at(ci, cj + 1)) * f.x;
    (a + (b - a) * f.y).to_array()
}

/// An n² staggered grid's u faces, v faces and pressure moved by `shift` whole cells (the
/// new cell (i, j) is the old cell (i + shift.x, j + shift.y)); what falls outside the old
/// grid takes its nearest edge value. The twin of `scroll_grid` in `fluid_scroll.wgsl`.
pub fn scroll_grids(
    n: usize,
    u: &[f32],
    v: &[f32],
    pressure: &[f32],
    shift: [i32; 2],
) -> (Vec<f32>, Vec<f32>, Vec<f32>) {
    let n = n as i64;
    let (dx, dy) = (i64::from(shift[0]), i64::from(shift[1]));
    let at = |i: i64, j: i64, w: i64, h: i64| {
        ((j + dy).clamp(0, h - 1) * w + (i + dx).clamp(0, w - 1)) as usize
    };
    let mut su = vec![0.0; u.len()];
    for j in 0..n {
        for i in 0..=n {
            su[(j * (n + 1) + i) as usize] = u[at(i, j, n + 1, n)];
        }
    }
    let mut sv = vec![0.0; v.len()];
    for j in 0..=n {
        for i in 0..n {
            sv[(j * n + i) as usize] = v[at(i, j, n, n + 1)];
        }
    }
    let mut sp = vec![0.0; pressure.len()];
    for j in 0..n {
        for i in 0..n {
            sp[(j * n + i) as usize] = pressure[at(i, j, n, n)];
        }
    }
    (su, sv, sp)
}

/// Makes the last face of each axis equal to the first, as a periodic grid keeps them.
pub fn periodic_faces(u: &mut [f32], v: &mut [f32], n: usize) {
    for j in 0..n {
        u[j * (n + 1) + n] = u[j * (n + 1)];
    }
    for i in 0..n {
        v[n * n + i] = v[i];
    }
}

/// Every face (axis, i, j) of an n² grid, u faces first, x fastest.
fn faces_of(n: i32) -> impl Iterator<Item = (u32, i32, i32)> {
    (0..2u32).flat_map(move |axis| {
        let (ni, nj) = if axis == 0 { (n + 1, n) } else { (n, n + 1) };
        (0..nj).flat_map(move |j| (0..ni).map(move |i| (axis, i, j)))
    })
}

/// The solver on the CPU: the same grids and passes as the GPU solver.
#[derive(Clone, Debug)]
pub struct FluidCpu {
    config: FluidConfig,
    /// u then v, as `FluidSolver`'s face buffers.
    faces: Vec<f32>,
    velocity: Vec<Vec2>,
    divergence: Vec<f32>,
    curl: Vec<f32>,
    /// 0 = fluid, k + 1 = inside obstacle k (set by `splat`).
    solid: Vec<u32>,
    /// The multigrid hierarchy; level 0 holds the pressure and the cell weights.
    levels: Vec<Level>,
}

impl FluidCpu {
    /// Still air, zero pressure, no solid cells. `config` should pass
    /// [`FluidConfig::validate`].
    pub fn new(config: &FluidConfig) -> Self {
        let cells = config.cells();
        let levels = config
            .multigrid_levels()
            .iter()
            .enumerate()
            .map(|(l, &size)| Level::new(size, config.cell_size * (1u32 << l) as f32))
            .collect();
        Self {
            config: config.clone(),
            faces: vec![0.0; config.faces()],
            velocity: vec![Vec2::ZERO; cells],
            divergence: vec![0.0; cells],
            curl: vec![0.0; cells],
            solid: vec![0; cells],
            levels,
        }
    }

    pub fn config(&self) -> &FluidConfig {
        &self.config
    }

    fn n(&self) -> i32 {
        self.config.resolution as i32
    }

    /// 1 / h exactly as the GPU gets it (`FluidParams::origin_cell.w`).
    fn inv_h(&self) -> f32 {
        self.config.params(0.0, &FluidForces::default()).origin_cell[3]
    }

    /// Replaces the face velocities (u then v, as [`FluidState`] holds them).
    ///
    /// # Panics
    /// If `u` or `v` does not hold (n + 1) · n faces.
    pub fn set_faces(&mut self, u: &[f32], v: &[f32]) {
        let half = self.config.faces() / 2;
        assert!(
            u.len() == half && v.len() == half,
            "(n + 1) · n faces per axis"
        );
        self.faces = u.iter().chain(v).copied().collect();
    }

    /// Moves a following grid by `shift` whole cells (the twin of `fluid_scroll.wgsl`, as
    /// `FluidSolver::follow` records it): faces and
    /// pressure that stay keep their values, entering ones take the old grid's edge values;
    /// the corner moves by `shift` cells.
    pub fn scroll(&mut self, shift: [i32; 2]) {
        let n = self.config.resolution as usize;
        let (u, v) = self.faces.split_at(n * (n + 1));
        let (u, v, p) = scroll_grids(n, u, v, &self.levels[0].p, shift);
        self.faces = u.into_iter().chain(v).collect();
        self.levels[0].p = p;
        let h = self.config.cell_size;
        self.config.origin[0] += shift[0] as f32 * h;
        self.config.origin[1] += shift[1] as f32 * h;
    }

    /// The grids as the GPU solver's `read_state` returns them.
    pub fn state(&self) -> FluidState {
        let n = self.config.resolution as usize;
        let (u, v) = self.faces.split_at(n * (n + 1));
        FluidState {
            resolution: self.config.resolution,
            cell_size: self.config.cell_size,
            origin: self.config.origin,
            velocity: self.velocity.iter().map(|v| v.to_array()).collect(),
            u: u.to_vec(),
            v: v.to_vec(),
            solid: self.solid.clone(),
            pressure: self.levels[0].p.clone(),
            divergence: self.divergence.clone(),
        }
    }

    /// The obstacle mask of the last splat (0 = fluid, k + 1 = obstacle k).
    pub fn solid(&self) -> &[u32] {
        &self.solid
    }

    /// One full step: every pass in `FLUID_PASSES` order.
    pub fn step(&mut self, dt: f32, forces: &FluidForces) {
        self.advect(dt);
        self.splat(dt, forces);
        self.vorticity(dt);
        self.diffuse(dt);
        self.divergence();
        self.pressure();
        self.subtract_gradient();
        self.centre();
    }

    /// Pass 1 (`fluid_advect.wgsl`): semi-Lagrangian or MacCormack, as configured.
    pub fn advect(&mut self, dt: f32) {
        let cells = -dt * self.inv_h();
        let damping = 1.0 + self.config.dissipation * dt;
        let q = &self.faces;
        let out = match self.config.advection {
            Advection::SemiLagrangian => self.carry(q, q, cells, |s, _| s / damping),
            Advection::MacCormack => {
                let hat = self.carry(q, q, cells, |s, _| s);
                let tilde = self.carry(q, &hat, -cells, |s, _| s);
                self.carry(q, q, cells, |_, (idx, st)| {
                    let [a, b, d, e] = st.map(|k| q[k]);
                    let lo = a.min(b).min(d.min(e));
                    let hi = a.max(b).max(d.max(e));
                    let v = hat[idx] + 0.5 * (q[idx] - tilde[idx]);
                    v.max(lo).min(hi) / damping
                })
            }
        };
        self.faces = out;
    }

    /// The trace of every face through `vel` over `cells` (= ±Δt / h), then `finish` of the
    /// value of `q` sampled there and of (the face's index, the stencil's indices); closed
    /// walls get 0. `advect`, `forward`, `backward` and `correct` in the shader.
    fn carry(
        &self,
        vel: &[f32],
        q: &[f32],
        cells: f32,
        finish: impl Fn(f32, (usize, [usize; 4])) -> f32,
    ) -> Vec<f32> {
        let (n, boundary) = (self.n(), self.config.boundary);
        let sample = |field: &[f32], axis: u32, pos: Vec2| {
            let (s, f) = stencil(axis, pos, n, boundary);
            blend(field[s[0]], field[s[1]], field[s[2]], field[s[3]], f)
        };
        let velocity_at = |pos: Vec2| Vec2::new(sample(vel, 0, pos), sample(vel, 1, pos));
        let mut out = vec![0.0; q.len()];
        for (axis, i, j) in faces_of(n) {
            let idx = face_index(axis, i, j, n);
            if is_wall(axis, i, j, n, boundary) {
                continue;
            }
            let (ci, cj) = canonical(axis, i, j, n, boundary);
            let start = face_pos(axis, ci, cj);
            let mid = clamp_pos(start + velocity_at(start) * (0.5 * cells), n, boundary);
            let pos = clamp_pos(start + velocity_at(mid) * cells, n, boundary);
            let (s, f) = stencil(axis, pos, n, boundary);
            let value = blend(q[s[0]], q[s[1]], q[s[2]], q[s[3]], f);
            out[idx] = finish(value, (idx, s));
        }
        out
    }

    /// Pass 2 (`fluid_splat.wgsl`): solid cells, cell weights, forces on the faces.
    pub fn splat(&mut self, dt: f32, forces: &FluidForces) {
        let params = self.config.params(dt, forces);
        let arrows = &forces.arrows[..forces.arrows.len().min(MAX_ARROWS)];
        let obstacles = &forces.obstacles[..forces.obstacles.len().min(MAX_OBSTACLES)];
        let origin = Vec2::new(params.origin_cell[0], params.origin_cell[1]);
        let h = params.origin_cell[2];
        let downwash = [
            params.downwash_pos[0],
            params.downwash_pos[1],
            params.global_downwash[2],
            params.global_downwash[3],
        ];
        let (n, boundary) = (self.n(), self.config.boundary);
        for j in 0..n {
            for i in 0..n {
                let p = origin + (Vec2::new(i as f32, j as f32) + 0.5) * h;
                let inside = obstacles.iter().position(|ob| {
                    let off = p - Vec2::new(ob.circle[0], ob.circle[1]);
                    off.dot(off) < ob.circle[2] * ob.circle[2]
                });
                self.solid[(j * n + i) as usize] = inside.map_or(0, |o| o as u32 + 1);
            }
        }
        let solid = &self.solid;
        let solid_at = |i: i32, j: i32| cell_ref(i, j, n, boundary).map_or(0, |c| solid[c]);
        let weight = |i: i32, j: i32| match cell_ref(i, j, n, boundary) {
            None if boundary == Boundary::Open => 1.0,
            None => 0.0,
            Some(c) if solid[c] == 0 => 1.0,
            Some(_) => 0.0,
        };
        for j in 0..n {
            for i in 0..n {
                let idx = (j * n + i) as usize;
                self.levels[0].w[idx] = if solid[idx] != 0 {
                    [0.0; 4]
                } else {
                    [
                        weight(i - 1, j),
                        weight(i + 1, j),
                        weight(i, j - 1),
                        weight(i, j + 1),
                    ]
                };
            }
        }
        let mut out = vec![0.0; self.faces.len()];
        for (axis, i, j) in faces_of(n) {
            let idx = face_index(axis, i, j, n);
            if is_wall(axis, i, j, n, boundary) {
                continue;
            }
            let (ci, cj) = canonical(axis, i, j, n, boundary);
            let [lo, hi] = face_cells(axis, ci, cj);
            let mut s = solid_at(lo.0, lo.1);
            if s == 0 {
                s = solid_at(hi.0, hi.1);
            }
            if s != 0 {
                out[idx] = obstacles[s as usize - 1].velocity[axis as usize];
                continue;
            }
            let p = origin + face_pos(axis, ci, cj) * h;
            let mut force = Vec2::new(params.global_downwash[0], params.global_downwash[1]);
            for a in arrows {
                force += arrow_force(a, p);
            }
            force += downwash_force(downwash, p);
            let at = face_index(axis, ci, cj, n);
            out[idx] = self.faces[at] + force[axis as usize] * dt;
        }
        self.faces = out;
    }

    /// Pass 3 (`fluid_vorticity.wgsl`): curl, then confinement (a copy when ε = 0).
    pub fn vorticity(&mut self, dt: f32) {
        let (n, boundary) = (self.n(), self.config.boundary);
        let inv_h = self.inv_h();
        let h = self.config.params(dt, &FluidForces::default()).origin_cell[2];
        let fin = &self.faces;
        let centre = |i: i32, j: i32| {
            let (ri, rj, sign) = velocity_ref(i, j, n, boundary);
            let u = (fin[face_index(0, ri, rj, n)] + fin[face_index(0, ri + 1, rj, n)]) * 0.5;
            let v = (fin[face_index(1, ri, rj, n)] + fin[face_index(1, ri, rj + 1, n)]) * 0.5;
            Vec2::new(u, v) * sign
        };
        for j in 0..n {
            for i in 0..n {
                let dv_dx = centre(i + 1, j).y - centre(i - 1, j).y;
                let du_dz = centre(i, j + 1).x - centre(i, j - 1).x;
                self.curl[(j * n + i) as usize] = (dv_dx - du_dz) * (0.5 * inv_h);
            }
        }
        let epsilon = self.config.vorticity;
        let (curl, solid) = (&self.curl, &self.solid);
        let abs_curl = |i: i32, j: i32| curl[scalar_index(i, j, n, boundary)].abs();
        let cell_force = |i: i32, j: i32| {
            let idx = scalar_index(i, j, n, boundary);
            if solid[idx] != 0 {
                return Vec2::ZERO;
            }
            let g = Vec2::new(
                abs_curl(i + 1, j) - abs_curl(i - 1, j),
                abs_curl(i, j + 1) - abs_curl(i, j - 1),
            ) * (0.5 * inv_h);
            let nrm = g / (g.dot(g).sqrt() + 1e-5);
            Vec2::new(nrm.y, -nrm.x) * (epsilon * h * curl[idx])
        };
        let mut out = vec![0.0; fin.len()];
        for (axis, i, j) in faces_of(n) {
            let idx = face_index(axis, i, j, n);
            if is_wall(axis, i, j, n, boundary) {
                continue;
            }
            let (ci, cj) = canonical(axis, i, j, n, boundary);
            let v = fin[face_index(axis, ci, cj, n)];
            let [a, b] = face_cells(axis, ci, cj);
            let (lo, hi) = (
                cell_ref(a.0, a.1, n, boundary),
                cell_ref(b.0, b.1, n, boundary),
            );
            let is_solid = |c: Option<usize>| c.is_some_and(|c| solid[c] != 0);
            if epsilon == 0.0 || is_solid(lo) || is_solid(hi) {
                out[idx] = v;
                continue;
            }
            let k = axis as usize;
            let force = match (lo, hi) {
                (None, _) => cell_force(b.0, b.1)[k],
                (_, None) => cell_force(a.0, a.1)[k],
                _ => (cell_force(a.0, a.1)[k] + cell_force(b.0, b.1)[k]) * 0.5,
            };
            out[idx] = v + force * dt;
        }
        self.faces = out;
    }

    /// Pass 4 (`fluid_diffuse.wgsl`): `diffusion_iterations` Jacobi iterations on the
    /// faces, only when the viscosity is positive.
    pub fn diffuse(&mut self, dt: f32) {
        if !self.config.diffuses() {
            return;
        }
        let (n, boundary) = (self.n(), self.config.boundary);
        let a = self
            .config
            .params(dt, &FluidForces::default())
            .diffusion_alpha;
        let start = self.faces.clone();
        let solid = &self.solid;
        let is_solid = |i: i32, j: i32| cell_ref(i, j, n, boundary).is_some_and(|c| solid[c] != 0);
        let mut x = start.clone();
        for _ in 0..self.config.diffusion_iterations {
            let mut out = vec![0.0; x.len()];
            for (axis, i, j) in faces_of(n) {
                let idx = face_index(axis, i, j, n);
                if is_wall(axis, i, j, n, boundary) {
                    continue;
                }
                let (ci, cj) = canonical(axis, i, j, n, boundary);
                let at = face_index(axis, ci, cj, n);
                let [lo, hi] = face_cells(axis, ci, cj);
                if is_solid(lo.0, lo.1) || is_solid(hi.0, hi.1) {
                    out[idx] = start[at];
                    continue;
                }
                let xr = |i: i32, j: i32| x[face_ref(axis, i, j, n, boundary)];
                let sum = xr(ci - 1, cj) + xr(ci + 1, cj) + xr(ci, cj - 1) + xr(ci, cj + 1);
                out[idx] = (start[at] + sum * a) / (1.0 + 4.0 * a);
            }
            x = out;
        }
        self.faces = x;
    }

    /// Pass 5 (`fluid_divergence.wgsl`); solid cells get 0.
    pub fn divergence(&mut self) {
        let n = self.n();
        let inv_h = self.inv_h();
        let f = &self.faces;
        for j in 0..n {
            for i in 0..n {
                let idx = (j * n + i) as usize;
                if self.solid[idx] != 0 {
                    self.divergence[idx] = 0.0;
                    continue;
                }
                let du = f[face_index(0, i + 1, j, n)] - f[face_index(0, i, j, n)];
                let dv = f[face_index(1, i, j + 1, n)] - f[face_index(1, i, j, n)];
                self.divergence[idx] = (du + dv) * inv_h;
            }
        }
    }

    /// Pass 6 with the configured solver, from the last pressure when warm-starting, else
    /// from 0.
    pub fn pressure(&mut self) {
        if !self.config.warm_start {
            self.levels[0].p.iter_mut().for_each(|p| *p = 0.0);
        }
        match self.config.pressure_solver {
            PressureSolver::Jacobi => self.pressure_jacobi(self.config.jacobi_iterations()),
            PressureSolver::Multigrid => self.pressure_multigrid(self.config.v_cycles()),
        }
    }

    /// `iterations` Jacobi iterations (`fluid_pressure.wgsl`) from the current pressure.
    pub fn pressure_jacobi(&mut self, iterations: u32) {
        let h = self.config.params(0.0, &FluidForces::default()).origin_cell[2];
        let level = &mut self.levels[0];
        for _ in 0..iterations {
            level.p = multigrid::jacobi(
                &level.p,
                &self.divergence,
                &level.w,
                self.config.resolution,
                h,
                self.config.boundary,
            );
        }
    }

    /// `cycles` V-cycles (`fluid_multigrid.wgsl`) from the current pressure.
    pub fn pressure_multigrid(&mut self, cycles: u32) {
        self.levels[0].f.clone_from(&self.divergence);
        multigrid::v_cycles(&mut self.levels, self.config.boundary, cycles);
    }

    /// Pass 7 (`fluid_gradient.wgsl`).
    pub fn subtract_gradient(&mut self) {
        let (n, boundary) = (self.n(), self.config.boundary);
        let inv_h = self.inv_h();
        let (fin, p, solid) = (&self.faces, &self.levels[0].p, &self.solid);
        let mut out = vec![0.0; fin.len()];
        for (axis, i, j) in faces_of(n) {
            let idx = face_index(axis, i, j, n);
            if is_wall(axis, i, j, n, boundary) {
                continue;
            }
            let (ci, cj) = canonical(axis, i, j, n, boundary);
            let v = fin[face_index(axis, ci, cj, n)];
            let [a, b] = face_cells(axis, ci, cj);
            let (lo, hi) = (
                cell_ref(a.0, a.1, n, boundary),
                cell_ref(b.0, b.1, n, boundary),
            );
            if lo.is_some_and(|c| solid[c] != 0) || hi.is_some_and(|c| solid[c] != 0) {
                out[idx] = v;
                continue;
            }
            let p_lo = lo.map_or(0.0, |c| p[c]);
            let p_hi = hi.map_or(0.0, |c| p[c]);
            out[idx] = v - (p_hi - p_lo) * inv_h;
        }
        self.faces = out;
    }

    /// End of pass 7 (`fluid_centre.wgsl`): the cell-centred velocity.
    pub fn centre(&mut self) {
        let n = self.n();
        let f = &self.faces;
        for j in 0..n {
            for i in 0..n {
                let u = (f[face_index(0, i, j, n)] + f[face_index(0, i + 1, j, n)]) * 0.5;
                let v = (f[face_index(1, i, j, n)] + f[face_index(1, i, j + 1, n)]) * 0.5;
                self.velocity[(j * n + i) as usize] = Vec2::new(u, v);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arrow_force_peaks_on_the_segment_and_vanishes_at_the_radius() {
        let a = ArrowGpu {
            segment: [0.0, 0.0, 4.0, 0.0],
            strength: 3.0,
            radius: 1.0,
            activation: 1.0,
            _pad: 0.0,
        };
        assert_eq!(arrow_force(&a, Vec2::new(2.0, 0.0)), Vec2::new(3.0, 0.0));
        let half = arrow_force(&a, Vec2::new(2.0, 0.5));
        assert!((half.x - 3.0 * 0.75 * 0.75).abs() < 1e-6);
        assert_eq!(arrow_force(&a, Vec2::new(2.0, 1.0)), Vec2::ZERO);
        // Beyond the end the distance is to the end point.
        assert_eq!(arrow_force(&a, Vec2::new(5.5, 0.0)), Vec2::ZERO);
    }

    #[test]
    fn downwash_is_radial_and_peaks_at_half_the_radius() {
        let dw = [1.0, 1.0, 4.0, 5.0];
        assert_eq!(downwash_force(dw, Vec2::new(1.0, 1.0)), Vec2::ZERO);
        let peak = downwash_force(dw, Vec2::new(3.0, 1.0));
        assert!((peak - Vec2::new(5.0, 0.0)).length() < 1e-6);
        let inner = downwash_force(dw, Vec2::new(1.0, 2.0));
        assert!((inner - Vec2::new(0.0, 2.5)).length() < 1e-6);
        assert_eq!(downwash_force(dw, Vec2::new(5.0, 1.0)), Vec2::ZERO);
    }

    #[test]
    fn sample_velocity_interpolates_between_cell_centres_and_clamps() {
        let mut velocity = vec![[0.0, 0.0]; 64];
        velocity[8 * 2 + 3] = [1.0, -2.0];
        let state = FluidState {
            resolution: 8,
            cell_size: 0.5,
            origin: [-2.0, -2.0],
            velocity,
            u: vec![0.0; 72],
            v: vec![0.0; 72],
            solid: vec![0; 64],
            pressure: vec![0.0; 64],
            divergence: vec![0.0; 64],
        };
        // Cell (3, 2) is centred at (-2 + 3.5 · 0.5, -2 + 2.5 · 0.5).
        assert_eq!(sample_velocity(&state, -0.25, -0.75), [1.0, -2.0]);
        assert_eq!(sample_velocity(&state, 0.0, -0.75), [0.5, -1.0]);
        assert_eq!(sample_velocity(&state, -100.0, 100.0), [0.0, 0.0]);
    }

    #[test]
    fn centre_is_the_mean_of_the_faces() {
        let cfg = FluidConfig {
            resolution: 8,
            cell_size: 1.0,
            origin: [0.0, 0.0],
            pressure_solver: PressureSolver::Jacobi,
            pressure_iterations: 0,
            multigrid_cycles: 1,
            warm_start: false,
            vorticity: 0.0,
            dissipation: 0.0,
            viscosity: 0.0,
            diffusion_iterations: 0,
            boundary: Boundary::Open,
            advection: Advection::SemiLagrangian,
            follow: false,
        };
        let mut cpu = FluidCpu::new(&cfg);
        let u: Vec<f32> = (0..72).map(|k| k as f32).collect();
        let v: Vec<f32> = (0..72).map(|k| -(k as f32)).collect();
        cpu.set_faces(&u, &v);
        cpu.centre();
        let s = cpu.state();
        // Cell (2, 3): u faces 3·9+2, 3·9+3; v faces 3·8+2, 4·8+2.
        assert_eq!(s.at(2, 3), [29.5, -30.0]);
    }
}
