//! CPU twin of the Stable-Fluids wind solver (`shaders/fluid_*.wgsl`, driven by
//! [`crate::sim::fluid::FluidSolver`]). Every pass follows its shader line by line in f32,
//! with the same operand order, so that GPU read-back and this twin differ only by the
//! rounding freedom the GPU has (fused multiply-adds, division precision). The passes are
//! public one by one so that tests can stop between them (e.g. measure the divergence right
//! after the projection).

use glam::Vec2;

use crate::scene::Boundary;
use crate::sim::fluid::{FluidConfig, FluidState};
use crate::sim::wind_layout::{ArrowGpu, FluidForces, MAX_ARROWS, MAX_OBSTACLES};

/// `fluid_velocity_ref`: the cell to read for velocity at (i, j), which may be outside the
/// grid, and the sign to multiply it by. Closed: the edge cell mirrored across the wall (its
/// wall-normal component negated). Open: the edge cell (zero gradient). Periodic: wrapped.
pub fn velocity_ref(i: i32, j: i32, n: i32, boundary: Boundary) -> (usize, Vec2) {
    if boundary == Boundary::Periodic {
        return ((j.rem_euclid(n) * n + i.rem_euclid(n)) as usize, Vec2::ONE);
    }
    let mut sign = Vec2::ONE;
    if boundary == Boundary::Closed {
        if i < 0 || i >= n {
            sign.x = -1.0;
        }
        if j < 0 || j >= n {
            sign.y = -1.0;
        }
    }
    let (ci, cj) = (i.clamp(0, n - 1), j.clamp(0, n - 1));
    ((cj * n + ci) as usize, sign)
}

/// `fluid_pressure_ref`: the cell to read for pressure at (i, j), or `None` outside an open
/// border, where the pressure is 0 (Dirichlet). Closed borders copy the edge cell (Neumann).
pub fn pressure_ref(i: i32, j: i32, n: i32, boundary: Boundary) -> Option<usize> {
    if boundary == Boundary::Periodic {
        return Some((j.rem_euclid(n) * n + i.rem_euclid(n)) as usize);
    }
    let outside = i < 0 || i >= n || j < 0 || j >= n;
    if outside && boundary == Boundary::Open {
        return None;
    }
    Some((j.clamp(0, n - 1) * n + i.clamp(0, n - 1)) as usize)
}

/// `fluid_scalar_index`: wrapped when periodic, else the nearest edge cell.
pub fn scalar_index(i: i32, j: i32, n: i32, boundary: Boundary) -> usize {
    if boundary == Boundary::Periodic {
        return (j.rem_euclid(n) * n + i.rem_euclid(n)) as usize;
    }
    (j.clamp(0, n - 1) * n + i.clamp(0, n - 1)) as usize
}

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

/// The central-difference divergence (`fluid_divergence.wgsl`) of a velocity field with no
/// solid cells, in 1/s per cell.
pub fn divergence_field(
    velocity: &[[f32; 2]],
    resolution: u32,
    cell_size: f32,
    boundary: Boundary,
) -> Vec<f32> {
    let n = resolution as i32;
    let inv_h = 1.0 / cell_size;
    let vel = |i: i32, j: i32| {
        let (k, s) = velocity_ref(i, j, n, boundary);
        v2(velocity[k]) * s
    };
    let mut out = Vec::with_capacity(velocity.len());
    for j in 0..n {
        for i in 0..n {
            let du = vel(i + 1, j).x - vel(i - 1, j).x;
            let dv = vel(i, j + 1).y - vel(i, j - 1).y;
            out.push((du + dv) * (0.5 * inv_h));
        }
    }
    out
}

/// Root-mean-square divergence (1/s) of `state.velocity` under the solver's own discrete
/// operator: the L2 norm over the cells divided by √cells, so grids of different sizes
/// compare. Computed in f64 so that the measure adds no rounding of its own.
pub fn divergence_l2(state: &FluidState, boundary: Boundary) -> f32 {
    let d = divergence_field(&state.velocity, state.resolution, state.cell_size, boundary);
    let sum: f64 = d.iter().map(|&x| x as f64 * x as f64).sum();
    (sum / d.len().max(1) as f64).sqrt() as f32
}

/// Root-mean-square divergence (1/s) of the face velocities the compact pressure solve
/// projects, for a state read right after a step without obstacles: on the face between
/// cells a and b the velocity is (v_a + v_b) / 2 − (p_b − p_a) / h, whose divergence is
/// D − ∇²ₕp, the residual of the pressure equation. This is the divergence the Jacobi solve
/// drives to zero; the central divergence of the cell velocities ([`divergence_l2`]) only
/// drops as far as the collocated scheme allows (see `tests/fluid.rs`). `state.divergence`
/// must be the divergence that entered the solve and `state.pressure` its result.
pub fn face_divergence_l2(state: &FluidState, boundary: Boundary) -> f32 {
    let n = state.resolution as i32;
    let inv_h2 = 1.0 / (state.cell_size as f64 * state.cell_size as f64);
    let p =
        |i: i32, j: i32| pressure_ref(i, j, n, boundary).map_or(0.0, |k| state.pressure[k] as f64);
    let mut sum = 0.0f64;
    for j in 0..n {
        for i in 0..n {
            let c = p(i, j);
            let lap = (p(i - 1, j) + p(i + 1, j) + p(i, j - 1) + p(i, j + 1) - 4.0 * c) * inv_h2;
            let r = state.divergence[(j * n + i) as usize] as f64 - lap;
            sum += r * r;
        }
    }
    (sum / (n as f64 * n as f64)).sqrt() as f32
}

/// Air velocity at world (x, z): bilinear between cell centres, clamped to the outer cell
/// centres. The same formula as `fluid_velocity` in update.wgsl and `sample_velocity` in
/// overlay.wgsl.
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

/// The solver on the CPU: the same grids and passes as the GPU solver.
#[derive(Clone, Debug)]
pub struct FluidCpu {
    config: FluidConfig,
    velocity: Vec<Vec2>,
    pressure: Vec<f32>,
    divergence: Vec<f32>,
    curl: Vec<f32>,
    /// 0 = fluid, k + 1 = inside obstacle k (set by `splat`).
    solid: Vec<u32>,
}

impl FluidCpu {
    /// Still air, zero pressure, no solid cells. `config` should pass
    /// [`FluidConfig::validate`].
    pub fn new(config: &FluidConfig) -> Self {
        let cells = config.cells();
        Self {
            config: config.clone(),
            velocity: vec![Vec2::ZERO; cells],
            pressure: vec![0.0; cells],
            divergence: vec![0.0; cells],
            curl: vec![0.0; cells],
            solid: vec![0; cells],
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

    fn vel(&self, field: &[Vec2], i: i32, j: i32) -> Vec2 {
        let (k, s) = velocity_ref(i, j, self.n(), self.config.boundary);
        field[k] * s
    }

    /// Replaces the velocity grid.
    ///
    /// # Panics
    /// If `v` does not hold exactly resolution² cells.
    pub fn set_velocity(&mut self, v: Vec<[f32; 2]>) {
        assert_eq!(v.len(), self.config.cells(), "one velocity per cell");
        self.velocity = v.into_iter().map(v2).collect();
    }

    /// The grids as the GPU solver's `read_state` returns them.
    pub fn state(&self) -> FluidState {
        FluidState {
            resolution: self.config.resolution,
            cell_size: self.config.cell_size,
            origin: self.config.origin,
            velocity: self.velocity.iter().map(|v| v.to_array()).collect(),
            pressure: self.pressure.clone(),
            divergence: self.divergence.clone(),
        }
    }

    /// The obstacle mask of the last splat (0 = fluid, k + 1 = obstacle k).
    pub fn solid(&self) -> &[u32] {
        &self.solid
    }

    /// One full step: every pass in `FLUID_PASSES` order.
    pub fn step(&mut self, dt: f32, forces: &FluidForces) {
        self.splat(dt, forces);
        self.vorticity(dt);
        self.diffuse(dt);
        self.divergence();
        self.pressure();
        self.subtract_gradient();
        self.advect(dt);
    }

    /// Pass 1 (`fluid_splat.wgsl`).
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
        let n = self.config.resolution;
        for j in 0..n {
            for i in 0..n {
                let idx = (j * n + i) as usize;
                let p = origin + (Vec2::new(i as f32, j as f32) + 0.5) * h;
                let mut force = Vec2::new(params.global_downwash[0], params.global_downwash[1]);
                for a in arrows {
                    force += arrow_force(a, p);
                }
                force += downwash_force(downwash, p);
                let mut v = self.velocity[idx] + force * dt;
                let mut s = 0;
                for (o, ob) in obstacles.iter().enumerate() {
                    let off = p - Vec2::new(ob.circle[0], ob.circle[1]);
                    if off.dot(off) < ob.circle[2] * ob.circle[2] {
                        s = o as u32 + 1;
                        v = Vec2::new(ob.velocity[0], ob.velocity[1]);
                        break;
                    }
                }
                self.velocity[idx] = v;
                self.solid[idx] = s;
            }
        }
    }

    /// Pass 2 (`fluid_vorticity.wgsl`): curl, then confinement (a copy when λ = 0).
    pub fn vorticity(&mut self, dt: f32) {
        let n = self.n();
        let boundary = self.config.boundary;
        let half_inv_h = 0.5 * self.inv_h();
        let vin = &self.velocity;
        for j in 0..n {
            for i in 0..n {
                let dv_dx = self.vel(vin, i + 1, j).y - self.vel(vin, i - 1, j).y;
                let du_dz = self.vel(vin, i, j + 1).x - self.vel(vin, i, j - 1).x;
                self.curl[(j * n + i) as usize] = (dv_dx - du_dz) * half_inv_h;
            }
        }
        let lambda = self.config.vorticity;
        if lambda == 0.0 {
            return;
        }
        let curl = &self.curl;
        let abs_curl = |i: i32, j: i32| curl[scalar_index(i, j, n, boundary)].abs();
        let mut out = self.velocity.clone();
        for j in 0..n {
            for i in 0..n {
                let idx = (j * n + i) as usize;
                if self.solid[idx] != 0 {
                    continue;
                }
                let g = Vec2::new(
                    abs_curl(i + 1, j) - abs_curl(i - 1, j),
                    abs_curl(i, j + 1) - abs_curl(i, j - 1),
                ) * half_inv_h;
                let nrm = g / (g.dot(g).sqrt() + 1e-5);
                let f = Vec2::new(nrm.y, -nrm.x) * (lambda * curl[idx]);
                out[idx] = self.velocity[idx] + f * dt;
            }
        }
        self.velocity = out;
    }

    /// Pass 3 (`fluid_diffuse.wgsl`): `diffusion_iterations` Jacobi iterations, only when
    /// the viscosity is positive.
    pub fn diffuse(&mut self, dt: f32) {
        if !self.config.diffuses() {
            return;
        }
        let n = self.n();
        let a = self
            .config
            .params(dt, &FluidForces::default())
            .diffusion_alpha;
        let start = self.velocity.clone();
        let mut x = start.clone();
        for _ in 0..self.config.diffusion_iterations {
            let mut out = vec![Vec2::ZERO; x.len()];
            for j in 0..n {
                for i in 0..n {
                    let idx = (j * n + i) as usize;
                    if self.solid[idx] != 0 {
                        out[idx] = start[idx];
                        continue;
                    }
                    let sum = self.vel(&x, i - 1, j)
                        + self.vel(&x, i + 1, j)
                        + self.vel(&x, i, j - 1)
                        + self.vel(&x, i, j + 1);
                    out[idx] = (start[idx] + sum * a) / (1.0 + 4.0 * a);
                }
            }
            x = out;
        }
        self.velocity = x;
    }

    /// Pass 4 (`fluid_divergence.wgsl`); solid cells get 0.
    pub fn divergence(&mut self) {
        let n = self.n();
        let half_inv_h = 0.5 * self.inv_h();
        let vin = &self.velocity;
        for j in 0..n {
            for i in 0..n {
                let idx = (j * n + i) as usize;
                if self.solid[idx] != 0 {
                    self.divergence[idx] = 0.0;
                    continue;
                }
                let du = self.vel(vin, i + 1, j).x - self.vel(vin, i - 1, j).x;
                let dv = self.vel(vin, i, j + 1).y - self.vel(vin, i, j - 1).y;
                self.divergence[idx] = (du + dv) * half_inv_h;
            }
        }
    }

    /// Pressure of (i, j) as the pressure and gradient passes read it (`p_at`).
    fn p_at(&self, p: &[f32], i: i32, j: i32, centre: f32) -> f32 {
        match pressure_ref(i, j, self.n(), self.config.boundary) {
            None => 0.0,
            Some(k) if self.solid[k] != 0 => centre,
            Some(k) => p[k],
        }
    }

    /// Pass 5 (`fluid_pressure.wgsl`): `pressure_iterations` Jacobi iterations, from the
    /// last pressure when warm-starting, else from 0.
    pub fn pressure(&mut self) {
        let n = self.n();
        let h = self.config.cell_size;
        if !self.config.warm_start {
            self.pressure.iter_mut().for_each(|p| *p = 0.0);
        }
        for _ in 0..self.config.pressure_iterations {
            let pin = &self.pressure;
            let mut out = vec![0.0; pin.len()];
            for j in 0..n {
                for i in 0..n {
                    let idx = (j * n + i) as usize;
                    if self.solid[idx] != 0 {
                        continue;
                    }
                    let c = pin[idx];
                    let sum = self.p_at(pin, i - 1, j, c)
                        + self.p_at(pin, i + 1, j, c)
                        + self.p_at(pin, i, j - 1, c)
                        + self.p_at(pin, i, j + 1, c);
                    out[idx] = (sum - h * h * self.divergence[idx]) * 0.25;
                }
            }
            self.pressure = out;
        }
    }

    /// Pass 6 (`fluid_gradient.wgsl`).
    pub fn subtract_gradient(&mut self) {
        let n = self.n();
        let half_inv_h = 0.5 * self.inv_h();
        let p = &self.pressure;
        let mut out = self.velocity.clone();
        for j in 0..n {
            for i in 0..n {
                let idx = (j * n + i) as usize;
                if self.solid[idx] != 0 {
                    continue;
                }
                let c = p[idx];
                let grad = Vec2::new(
                    self.p_at(p, i + 1, j, c) - self.p_at(p, i - 1, j, c),
                    self.p_at(p, i, j + 1, c) - self.p_at(p, i, j - 1, c),
                );
                out[idx] = self.velocity[idx] - grad * half_inv_h;
            }
        }
        self.velocity = out;
    }

    /// Pass 7 (`fluid_advect.wgsl`).
    pub fn advect(&mut self, dt: f32) {
        let n = self.n();
        let scale = dt * self.inv_h();
        let damp = 1.0 + self.config.dissipation * dt;
        let edge = n as f32 - 0.5;
        let vin = &self.velocity;
        let mut out = vin.clone();
        for j in 0..n {
            for i in 0..n {
                let idx = (j * n + i) as usize;
                if self.solid[idx] != 0 {
                    continue;
                }
                let mut pos = Vec2::new(i as f32, j as f32) - vin[idx] * scale;
                if self.config.boundary != Boundary::Periodic {
                    pos = pos.max(Vec2::splat(-0.5)).min(Vec2::splat(edge));
                }
                let c = pos.floor();
                let f = pos - c;
                let (ci, cj) = (c.x as i32, c.y as i32);
                let a = self.vel(vin, ci, cj);
                let b = self.vel(vin, ci + 1, cj);
                let d = self.vel(vin, ci, cj + 1);
                let e = self.vel(vin, ci + 1, cj + 1);
                let bottom = a + (b - a) * f.x;
                let top = d + (e - d) * f.x;
                let s = bottom + (top - bottom) * f.y;
                out[idx] = s / damp;
            }
        }
        self.velocity = out;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_border_mirrors_the_normal_component() {
        let n = 8;
        // Inside: the cell itself, unchanged.
        assert_eq!(velocity_ref(3, 4, n, Boundary::Closed), (35, Vec2::ONE));
        // Left and right walls flip u only, bottom and top flip v only.
        assert_eq!(
            velocity_ref(-1, 2, n, Boundary::Closed),
            (16, Vec2::new(-1.0, 1.0))
        );
        assert_eq!(
            velocity_ref(8, 2, n, Boundary::Closed),
            (23, Vec2::new(-1.0, 1.0))
        );
        assert_eq!(
            velocity_ref(5, -1, n, Boundary::Closed),
            (5, Vec2::new(1.0, -1.0))
        );
        assert_eq!(
            velocity_ref(5, 8, n, Boundary::Closed),
            (61, Vec2::new(1.0, -1.0))
        );
        // A corner ghost flips both.
        assert_eq!(
            velocity_ref(-1, 8, n, Boundary::Closed),
            (56, Vec2::new(-1.0, -1.0))
        );
        // So the wall-normal velocity averages to 0 on the wall.
        let u = Vec2::new(2.0, 3.0);
        let (_, s) = velocity_ref(-1, 0, n, Boundary::Closed);
        assert_eq!(((u * s + u) * 0.5).x, 0.0);
    }

    #[test]
    fn open_border_copies_the_edge_cell() {
        let n = 8;
        assert_eq!(velocity_ref(-1, 2, n, Boundary::Open), (16, Vec2::ONE));
        assert_eq!(velocity_ref(9, 9, n, Boundary::Open), (63, Vec2::ONE));
        assert_eq!(velocity_ref(2, -3, n, Boundary::Open), (2, Vec2::ONE));
    }

    #[test]
    fn periodic_border_wraps() {
        let n = 8;
        assert_eq!(velocity_ref(-1, 0, n, Boundary::Periodic), (7, Vec2::ONE));
        assert_eq!(velocity_ref(8, 7, n, Boundary::Periodic), (56, Vec2::ONE));
        assert_eq!(velocity_ref(-9, -1, n, Boundary::Periodic), (63, Vec2::ONE));
        assert_eq!(pressure_ref(8, -1, n, Boundary::Periodic), Some(56));
        assert_eq!(scalar_index(-1, 8, n, Boundary::Periodic), 7);
    }

    #[test]
    fn pressure_is_neumann_when_closed_and_zero_outside_when_open() {
        let n = 8;
        // Closed: the outside neighbour of an edge cell is the edge cell itself.
        assert_eq!(pressure_ref(-1, 3, n, Boundary::Closed), Some(24));
        assert_eq!(pressure_ref(3, 8, n, Boundary::Closed), Some(59));
        // Open: outside is Dirichlet 0, inside is read normally.
        assert_eq!(pressure_ref(-1, 3, n, Boundary::Open), None);
        assert_eq!(pressure_ref(3, 8, n, Boundary::Open), None);
        assert_eq!(pressure_ref(3, 7, n, Boundary::Open), Some(59));
        // Scalars clamp for closed and open alike.
        assert_eq!(scalar_index(-1, 3, n, Boundary::Open), 24);
        assert_eq!(scalar_index(8, 3, n, Boundary::Closed), 31);
    }

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
            pressure: vec![0.0; 64],
            divergence: vec![0.0; 64],
        };
        // Cell (3, 2) is centred at (-2 + 3.5 · 0.5, -2 + 2.5 · 0.5).
        assert_eq!(sample_velocity(&state, -0.25, -0.75), [1.0, -2.0]);
        assert_eq!(sample_velocity(&state, 0.0, -0.75), [0.5, -1.0]);
        assert_eq!(sample_velocity(&state, -100.0, 100.0), [0.0, 0.0]);
    }
}
