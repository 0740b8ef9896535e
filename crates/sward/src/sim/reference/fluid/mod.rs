//! CPU twin of the staggered-grid Stable-Fluids wind solver (`shaders/fluid_*.wgsl`, driven
//! by [`crate::sim::fluid::FluidSolver`]). Every pass follows its shader line by line in
//! f32, with the same operand order, so that GPU read-back and this twin differ only by the
//! rounding freedom the GPU has (fused multiply-adds, division precision). The passes are
//! public one by one so that tests can stop between them (e.g. measure the divergence right
//! after the projection). The grid helpers are in [`grid`], the pressure solvers in
//! [`multigrid`].

pub mod grid;
pub mod multigrid;

use glam::{IVec3, Vec2, Vec3};

use crate::scene::{Advection, Boundary, PressureSolver};
use crate::sim::fluid::{FluidConfig, FluidState};
use crate::sim::wind_layout::{ArrowGpu, FluidForces, MAX_ARROWS, MAX_OBSTACLES};
use grid::{
    blend3, canonical, cell_ref, clamp_pos, face_cells, face_index, face_pos, face_ref, is_wall,
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

/// `downwash_column` in fluid_splat.wgsl: the 3D downwash's weight at p (1 inside half the
/// radius, a smoothstep to 0 at the radius).
pub fn downwash_column(downwash: [f32; 4], p: Vec2) -> f32 {
    let r = downwash[2];
    if r <= 0.0 {
        return 0.0;
    }
    let off = p - Vec2::new(downwash[0], downwash[1]);
    let dist = off.dot(off).sqrt();
    if dist >= r {
        return 0.0;
    }
    let half_r = 0.5 * r;
    if dist <= half_r {
        return 1.0;
    }
    let t = (dist - half_r) / half_r;
    1.0 - t * t * (3.0 - 2.0 * t)
}

/// Air velocity at world (x, z) in the lowest layer: bilinear between cell centres of the
/// cell-centred velocity, clamped to the outer cell centres. The same formula as
/// `fluid_velocity` in wind_sample.wgsl and `sample_velocity` in overlay.wgsl.
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

/// The grids of an n² staggered grid of `layers` layers (u, v, w faces and pressure) moved
/// by `shift` whole cells (the new cell (i, j) is the old cell (i + shift.x, j + shift.y),
/// in every layer); what falls outside the old grid takes its nearest edge value. The twin
/// of `scroll_grid` in `fluid_scroll.wgsl`.
pub struct Scrolled {
    /// u (m/s) on the faces normal to x, (n + 1) · n per layer, x fastest.
    pub u: Vec<f32>,
    /// v (m/s) on the faces normal to z, n · (n + 1) per layer, x fastest.
    pub v: Vec<f32>,
    /// w (m/s, up) on the n² faces of each horizontal plane (layers + 1 of them).
    pub w: Vec<f32>,
    /// Pressure per cell, n² per layer.
    pub pressure: Vec<f32>,
}

/// See [`Scrolled`].
pub fn scroll_grids(
    n: usize,
    layers: usize,
    faces: (&[f32], &[f32], &[f32]),
    pressure: &[f32],
    shift: [i32; 2],
) -> Scrolled {
    let n = n as i64;
    let (dx, dy) = (i64::from(shift[0]), i64::from(shift[1]));
    // Moves every w × h slab of `field` (x fastest).
    let moved = |field: &[f32], w: i64, h: i64| -> Vec<f32> {
        let slab = (w * h) as usize;
        let mut out = vec![0.0; field.len()];
        for (k, chunk) in out.chunks_mut(slab).enumerate() {
            for j in 0..h {
                for i in 0..w {
                    let src = (j + dy).clamp(0, h - 1) * w + (i + dx).clamp(0, w - 1);
                    chunk[(j * w + i) as usize] = field[k * slab + src as usize];
                }
            }
        }
        out
    };
    let _ = layers;
    Scrolled {
        u: moved(faces.0, n + 1, n),
        v: moved(faces.1, n, n + 1),
        w: moved(faces.2, n, n),
        pressure: moved(pressure, n, n),
    }
}

/// Makes the last face of each horizontal axis equal to the first in every layer, as a
/// periodic grid keeps them (`u`, `v` of n (n + 1) faces per layer).
pub fn periodic_faces(u: &mut [f32], v: &mut [f32], n: usize) {
    let per_layer = n * (n + 1);
    for (u, v) in u.chunks_mut(per_layer).zip(v.chunks_mut(per_layer)) {
        for j in 0..n {
            u[j * (n + 1) + n] = u[j * (n + 1)];
        }
        for i in 0..n {
            v[n * n + i] = v[i];
        }
    }
}

/// Every face (axis, i, j, k) of an n² grid of `layers` layers, in buffer order.
fn faces_of(n: i32, layers: i32) -> impl Iterator<Item = (u32, i32, i32, i32)> {
    (0..3u32).flat_map(move |axis| {
        let (ni, nj, nk) = match axis {
            0 => (n + 1, n, layers),
            1 => (n, n + 1, layers),
            _ => (n, n, layers + 1),
        };
        (0..nk).flat_map(move |k| (0..nj).flat_map(move |j| (0..ni).map(move |i| (axis, i, j, k))))
    })
}

/// Every cell (i, j, k), in buffer order.
fn cells_of(n: i32, layers: i32) -> impl Iterator<Item = IVec3> {
    (0..layers)
        .flat_map(move |k| (0..n).flat_map(move |j| (0..n).map(move |i| IVec3::new(i, j, k))))
}

/// The solver on the CPU: the same grids and passes as the GPU solver.
#[derive(Clone, Debug)]
pub struct FluidCpu {
    config: FluidConfig,
    /// u, v then w, as `FluidSolver`'s face buffers.
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
            .map(|(l, &size)| Level::new(config, l, size))
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

    /// The settings the solver was created with.
    pub fn config(&self) -> &FluidConfig {
        &self.config
    }

    fn n(&self) -> i32 {
        self.config.resolution as i32
    }

    fn layers(&self) -> i32 {
        self.config.layers as i32
    }

    /// The uniforms exactly as the GPU gets them.
    fn uniforms(&self, dt: f32) -> crate::sim::wind_layout::FluidParams {
        self.config.params(dt, &FluidForces::default())
    }

    /// 1 / h exactly as the GPU gets it (`FluidParams::origin_cell.w`).
    fn inv_h(&self) -> f32 {
        self.uniforms(0.0).origin_cell[3]
    }

    /// 1 / dy exactly as the GPU gets it (`FluidParams::layer.y`).
    fn inv_dy(&self) -> f32 {
        self.uniforms(0.0).layer[1]
    }

    /// Replaces the face velocities (u, v and w as [`FluidState`] holds them; an empty `w`
    /// is still vertical air).
    ///
    /// # Panics
    /// If a component has the wrong length.
    pub fn set_faces(&mut self, u: &[f32], v: &[f32], w: &[f32]) {
        self.faces = crate::sim::fluid::face_vector(&self.config, u, v, w);
    }

    fn split_faces(&self) -> (&[f32], &[f32], &[f32]) {
        let uv = self.config.layer_faces() * self.config.layers as usize;
        let (u, rest) = self.faces.split_at(uv);
        let (v, w) = rest.split_at(uv);
        (u, v, w)
    }

    /// Moves a following grid by `shift` whole cells (the twin of `fluid_scroll.wgsl`, as
    /// `FluidSolver::follow` records it): faces and pressure that stay keep their values,
    /// entering ones take the old grid's edge values; the corner moves by `shift` cells.
    pub fn scroll(&mut self, shift: [i32; 2]) {
        let n = self.config.resolution as usize;
        let layers = self.config.layers as usize;
        let s = scroll_grids(n, layers, self.split_faces(), &self.levels[0].p, shift);
        self.faces = s.u.into_iter().chain(s.v).chain(s.w).collect();
        self.levels[0].p = s.pressure;
        let h = self.config.cell_size;
        self.config.origin[0] += shift[0] as f32 * h;
        self.config.origin[1] += shift[1] as f32 * h;
    }

    /// The grids as the GPU solver's `read_state` returns them.
    pub fn state(&self) -> FluidState {
        let (u, v, w) = self.split_faces();
        FluidState {
            resolution: self.config.resolution,
            layers: self.config.layers,
            cell_size: self.config.cell_size,
            layer_height: self.config.layer_height,
            origin: self.config.origin,
            velocity: self.velocity.iter().map(|v| v.to_array()).collect(),
            u: u.to_vec(),
            v: v.to_vec(),
            w: w.to_vec(),
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
        let damping = 1.0 + self.config.dissipation * dt;
        let q = &self.faces;
        let out = match self.config.advection {
            Advection::SemiLagrangian => self.carry(q, q, -1.0, dt, |s, _| s / damping),
            Advection::MacCormack => {
                let hat = self.carry(q, q, -1.0, dt, |s, _| s);
                let tilde = self.carry(q, &hat, 1.0, dt, |s, _| s);
                self.carry(q, q, -1.0, dt, |_, (idx, st)| {
                    let v = st.map(|k| q[k]);
                    let lo = v[0]
                        .min(v[1])
                        .min(v[2].min(v[3]))
                        .min(v[4].min(v[5]).min(v[6].min(v[7])));
                    let hi = v[0]
                        .max(v[1])
                        .max(v[2].max(v[3]))
                        .max(v[4].max(v[5]).max(v[6].max(v[7])));
                    let x = hat[idx] + 0.5 * (q[idx] - tilde[idx]);
                    x.max(lo).min(hi) / damping
                })
            }
        };
        self.faces = out;
    }

    /// The trace of every face through `vel` over `sign` · Δt, then `finish` of the value
    /// of `q` sampled there and of (the face's index, the stencil's indices); walls get 0.
    /// `advect`, `forward`, `backward` and `correct` in the shader.
    fn carry(
        &self,
        vel: &[f32],
        q: &[f32],
        sign: f32,
        dt: f32,
        finish: impl Fn(f32, (usize, [usize; 8])) -> f32,
    ) -> Vec<f32> {
        let (n, layers, boundary) = (self.n(), self.layers(), self.config.boundary);
        let (inv_h, inv_dy) = (self.inv_h(), self.inv_dy());
        let cells = Vec3::new(inv_h, inv_h, inv_dy) * (sign * dt);
        let sample = |field: &[f32], axis: u32, pos: Vec3| {
            let (s, f) = stencil(axis, pos, n, layers, boundary);
            blend3(s.map(|k| field[k]), f)
        };
        let velocity_at = |pos: Vec3| {
            Vec3::new(
                sample(vel, 0, pos),
                sample(vel, 1, pos),
                sample(vel, 2, pos),
            )
        };
        let mut out = vec![0.0; q.len()];
        for (axis, i, j, k) in faces_of(n, layers) {
            let idx = face_index(axis, i, j, k, n, layers);
            if is_wall(axis, i, j, k, n, layers, boundary) {
                continue;
            }
            let (ci, cj) = canonical(axis, i, j, n, boundary);
            let start = face_pos(axis, ci, cj, k);
            let mid = clamp_pos(
                start + velocity_at(start) * (0.5 * cells),
                n,
                layers,
                boundary,
            );
            let pos = clamp_pos(start + velocity_at(mid) * cells, n, layers, boundary);
            let (s, f) = stencil(axis, pos, n, layers, boundary);
            let value = blend3(s.map(|k| q[k]), f);
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
        let (n, layers, boundary) = (self.n(), self.layers(), self.config.boundary);
        let three_d = layers > 1;
        for c in cells_of(n, layers) {
            let p = origin + (Vec2::new(c.x as f32, c.y as f32) + 0.5) * h;
            let y = (c.z as f32 + 0.5) * params.layer[0];
            let inside = obstacles.iter().position(|ob| {
                let off = p - Vec2::new(ob.circle[0], ob.circle[1]);
                let mut d2 = off.dot(off);
                if three_d {
                    let dy = y - ob.circle[3];
                    d2 += dy * dy;
                }
                d2 < ob.circle[2] * ob.circle[2]
            });
            self.solid[((c.z * n + c.y) * n + c.x) as usize] = inside.map_or(0, |o| o as u32 + 1);
        }
        let solid = &self.solid;
        let solid_at = |c: IVec3| cell_ref(c, n, layers, boundary).map_or(0, |r| solid[r]);
        let weight = |c: IVec3| match cell_ref(c, n, layers, boundary) {
            None if boundary == Boundary::Open && c.z >= 0 && c.z < layers => 1.0,
            None => 0.0,
            Some(r) if solid[r] == 0 => 1.0,
            Some(_) => 0.0,
        };
        let level = &mut self.levels[0];
        for c in cells_of(n, layers) {
            let idx = ((c.z * n + c.y) * n + c.x) as usize;
            if solid[idx] != 0 {
                level.w[idx] = [0.0; 4];
                level.wv[idx] = [0.0; 2];
                continue;
            }
            level.w[idx] = [
                weight(c - IVec3::X),
                weight(c + IVec3::X),
                weight(c - IVec3::Y),
                weight(c + IVec3::Y),
            ];
            level.wv[idx] = [weight(c - IVec3::Z), weight(c + IVec3::Z)];
        }
        let mut out = vec![0.0; self.faces.len()];
        for (axis, i, j, k) in faces_of(n, layers) {
            let idx = face_index(axis, i, j, k, n, layers);
            if is_wall(axis, i, j, k, n, layers, boundary) {
                continue;
            }
            let (ci, cj) = canonical(axis, i, j, n, boundary);
            let [lo, hi] = face_cells(axis, ci, cj, k);
            let mut s = solid_at(lo);
            if s == 0 {
                s = solid_at(hi);
            }
            if s != 0 {
                out[idx] = obstacles[s as usize - 1].velocity[axis as usize];
                continue;
            }
            let pos = face_pos(axis, ci, cj, k);
            let p = origin + Vec2::new(pos.x, pos.y) * h;
            let at = face_index(axis, ci, cj, k, n, layers);
            if axis == 2 {
                out[idx] = self.faces[at] - downwash[3] * downwash_column(downwash, p) * dt;
                continue;
            }
            let mut force = Vec2::new(params.global_downwash[0], params.global_downwash[1]);
            for a in arrows {
                force += arrow_force(a, p);
            }
            if !three_d {
                force += downwash_force(downwash, p);
            }
            let pushed = self.faces[at] + force[axis as usize] * dt;
            if !three_d {
                out[idx] = pushed;
                continue;
            }
            let drag = params.layer[3] / (k as f32 + 0.5);
            out[idx] = pushed / (1.0 + drag * dt);
        }
        self.faces = out;
    }

    /// Pass 3 (`fluid_vorticity.wgsl`): curl, then confinement (a copy when ε = 0), each
    /// layer on its own.
    pub fn vorticity(&mut self, dt: f32) {
        let (n, layers, boundary) = (self.n(), self.layers(), self.config.boundary);
        let inv_h = self.inv_h();
        let h = self.uniforms(dt).origin_cell[2];
        let fin = &self.faces;
        let centre = |i: i32, j: i32, k: i32| {
            let (ri, rj, sign) = velocity_ref(i, j, n, boundary);
            let f = |axis, i, j| fin[face_index(axis, i, j, k, n, layers)];
            let u = (f(0, ri, rj) + f(0, ri + 1, rj)) * 0.5;
            let v = (f(1, ri, rj) + f(1, ri, rj + 1)) * 0.5;
            Vec2::new(u, v) * sign
        };
        for c in cells_of(n, layers) {
            let (i, j, k) = (c.x, c.y, c.z);
            let dv_dx = centre(i + 1, j, k).y - centre(i - 1, j, k).y;
            let du_dz = centre(i, j + 1, k).x - centre(i, j - 1, k).x;
            self.curl[((k * n + j) * n + i) as usize] = (dv_dx - du_dz) * (0.5 * inv_h);
        }
        let epsilon = self.config.vorticity;
        let (curl, solid) = (&self.curl, &self.solid);
        let abs_curl = |i: i32, j: i32, k: i32| curl[scalar_index(i, j, k, n, boundary)].abs();
        let cell_force = |c: IVec3| {
            let (i, j, k) = (c.x, c.y, c.z);
            let idx = scalar_index(i, j, k, n, boundary);
            if solid[idx] != 0 {
                return Vec2::ZERO;
            }
            let g = Vec2::new(
                abs_curl(i + 1, j, k) - abs_curl(i - 1, j, k),
                abs_curl(i, j + 1, k) - abs_curl(i, j - 1, k),
            ) * (0.5 * inv_h);
            let nrm = g / (g.dot(g).sqrt() + 1e-5);
            Vec2::new(nrm.y, -nrm.x) * (epsilon * h * curl[idx])
        };
        let mut out = vec![0.0; fin.len()];
        for (axis, i, j, k) in faces_of(n, layers) {
            let idx = face_index(axis, i, j, k, n, layers);
            if is_wall(axis, i, j, k, n, layers, boundary) {
                continue;
            }
            let (ci, cj) = canonical(axis, i, j, n, boundary);
            let v = fin[face_index(axis, ci, cj, k, n, layers)];
            let [a, b] = face_cells(axis, ci, cj, k);
            let (lo, hi) = (
                cell_ref(a, n, layers, boundary),
                cell_ref(b, n, layers, boundary),
            );
            let is_solid = |c: Option<usize>| c.is_some_and(|c| solid[c] != 0);
            if epsilon == 0.0 || axis == 2 || is_solid(lo) || is_solid(hi) {
                out[idx] = v;
                continue;
            }
            let ax = axis as usize;
            let force = match (lo, hi) {
                (None, _) => cell_force(b)[ax],
                (_, None) => cell_force(a)[ax],
                _ => (cell_force(a)[ax] + cell_force(b)[ax]) * 0.5,
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
        let (n, layers, boundary) = (self.n(), self.layers(), self.config.boundary);
        let params = self.uniforms(dt);
        let (a, av) = (params.diffusion_alpha, params.layer[2]);
        let start = self.faces.clone();
        let solid = &self.solid;
        let is_solid = |c: IVec3| cell_ref(c, n, layers, boundary).is_some_and(|r| solid[r] != 0);
        let mut x = start.clone();
        for _ in 0..self.config.diffusion_iterations {
            let mut out = vec![0.0; x.len()];
            for (axis, i, j, k) in faces_of(n, layers) {
                let idx = face_index(axis, i, j, k, n, layers);
                if is_wall(axis, i, j, k, n, layers, boundary) {
                    continue;
                }
                let (ci, cj) = canonical(axis, i, j, n, boundary);
                let at = face_index(axis, ci, cj, k, n, layers);
                let [lo, hi] = face_cells(axis, ci, cj, k);
                if is_solid(lo) || is_solid(hi) {
                    out[idx] = start[at];
                    continue;
                }
                let xr = |i: i32, j: i32, k: i32| x[face_ref(axis, i, j, k, n, layers, boundary)];
                let sum =
                    xr(ci - 1, cj, k) + xr(ci + 1, cj, k) + xr(ci, cj - 1, k) + xr(ci, cj + 1, k);
                let vertical = xr(ci, cj, k - 1) + xr(ci, cj, k + 1);
                out[idx] = (start[at] + sum * a + vertical * av) / (1.0 + 4.0 * a + 2.0 * av);
            }
            x = out;
        }
        self.faces = x;
    }

    /// Pass 5 (`fluid_divergence.wgsl`); solid cells get 0.
    pub fn divergence(&mut self) {
        let (n, layers) = (self.n(), self.layers());
        let (inv_h, inv_dy) = (self.inv_h(), self.inv_dy());
        let f = &self.faces;
        for c in cells_of(n, layers) {
            let (i, j, k) = (c.x, c.y, c.z);
            let idx = ((k * n + j) * n + i) as usize;
            if self.solid[idx] != 0 {
                self.divergence[idx] = 0.0;
                continue;
            }
            let fi = |axis, i, j, k| f[face_index(axis, i, j, k, n, layers)];
            let du = fi(0, i + 1, j, k) - fi(0, i, j, k);
            let dv = fi(1, i, j + 1, k) - fi(1, i, j, k);
            let dw = fi(2, i, j, k + 1) - fi(2, i, j, k);
            self.divergence[idx] = (du + dv) * inv_h + dw * inv_dy;
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
        let h = self.uniforms(0.0).origin_cell[2];
        let inv_dy = self.inv_dy();
        let level = &mut self.levels[0];
        level.f.clone_from(&self.divergence);
        for _ in 0..iterations {
            level.p = multigrid::jacobi(level, h, inv_dy, self.config.boundary);
        }
    }

    /// `cycles` V-cycles (`fluid_multigrid.wgsl`) from the current pressure.
    pub fn pressure_multigrid(&mut self, cycles: u32) {
        self.levels[0].f.clone_from(&self.divergence);
        multigrid::v_cycles(&mut self.levels, self.config.boundary, cycles);
    }

    /// Pass 7 (`fluid_gradient.wgsl`).
    pub fn subtract_gradient(&mut self) {
        let (n, layers, boundary) = (self.n(), self.layers(), self.config.boundary);
        let (inv_h, inv_dy) = (self.inv_h(), self.inv_dy());
        let (fin, p, solid) = (&self.faces, &self.levels[0].p, &self.solid);
        let mut out = vec![0.0; fin.len()];
        for (axis, i, j, k) in faces_of(n, layers) {
            let idx = face_index(axis, i, j, k, n, layers);
            if is_wall(axis, i, j, k, n, layers, boundary) {
                continue;
            }
            let (ci, cj) = canonical(axis, i, j, n, boundary);
            let v = fin[face_index(axis, ci, cj, k, n, layers)];
            let [a, b] = face_cells(axis, ci, cj, k);
            let (lo, hi) = (
                cell_ref(a, n, layers, boundary),
                cell_ref(b, n, layers, boundary),
            );
            if lo.is_some_and(|c| solid[c] != 0) || hi.is_some_and(|c| solid[c] != 0) {
                out[idx] = v;
                continue;
            }
            let p_lo = lo.map_or(0.0, |c| p[c]);
            let p_hi = hi.map_or(0.0, |c| p[c]);
            let inv = if axis == 2 { inv_dy } else { inv_h };
            out[idx] = v - (p_hi - p_lo) * inv;
        }
        self.faces = out;
    }

    /// End of pass 7 (`fluid_centre.wgsl`): the cell-centred velocity of every layer.
    pub fn centre(&mut self) {
        let (n, layers) = (self.n(), self.layers());
        let f = &self.faces;
        for c in cells_of(n, layers) {
            let (i, j, k) = (c.x, c.y, c.z);
            let fi = |axis, i, j| f[face_index(axis, i, j, k, n, layers)];
            let u = (fi(0, i, j) + fi(0, i + 1, j)) * 0.5;
            let v = (fi(1, i, j) + fi(1, i, j + 1)) * 0.5;
            self.velocity[((k * n + j) * n + i) as usize] = Vec2::new(u, v);
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
            layers: 1,
            cell_size: 0.5,
            layer_height: 1.0,
            origin: [-2.0, -2.0],
            velocity,
            u: vec![0.0; 72],
            v: vec![0.0; 72],
            w: vec![0.0; 128],
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
            layers: 1,
            layer_height: 1.0,
            ground_drag: 0.0,
        };
        let mut cpu = FluidCpu::new(&cfg);
        let u: Vec<f32> = (0..72).map(|k| k as f32).collect();
        let v: Vec<f32> = (0..72).map(|k| -(k as f32)).collect();
        cpu.set_faces(&u, &v, &[]);
        cpu.centre();
        let s = cpu.state();
        // Cell (2, 3): u faces 3·9+2, 3·9+3; v faces 3·8+2, 4·8+2.
        assert_eq!(s.at(2, 3), [29.5, -30.0]);
    }
}
