//! Grass-to-grass propagation (Qiu et al., §5.2, Eq. 4; `physics.propagation`), the CPU
//! twin of `shaders/propagate.wgsl` and of the update's splat.
//!
//! The neighbour structure is a square grid of cells around the camera (Qiu's field is a
//! grid of blades; sward's blades are scattered, so a cell stands for the blades in it).
//! Each step:
//! 1. the update adds every collision push it gives a blade's tip (horizontal, metres) to
//!    the blade's cell, in fixed point (micrometres) so that the sums do not depend on the
//!    order of the atomics;
//! 2. `init`: a cell whose blades were pushed is an ancestor (generation 0) with the mean
//!    push as its force vector EF;
//! 3. `generation` g = 1..G: a cell not reached yet gathers from its four adjacent cells of
//!    generation g − 1 that are active (|EF| > L, Definition 2) the part of their force that
//!    points at it (the orthogonal decomposition of Step 2: the x part goes to the left or
//!    right neighbour, the z part up or down), times att (Eq. 4, EF_origin = 0 for an
//!    unreached cell); a cell reached is a child of generation g. Reached cells never take
//!    from later generations (the parallel relation of Definition 7);
//! 4. `apply`: the blades of every child cell are pushed by its force as by a collider (the
//!    tip moves, the validation follows, η grows by k·d·d), so the trail is wider and
//!    softer than the object. Ancestor cells' blades keep their own collisions.
//!
//! sward applies the propagation to Jahrmann's blades; Verlet blades feed it (their pushes
//! count as ancestors) but are not pushed by it, and Cwd blades have no collisions at all.

use glam::{Vec2, Vec3};

use super::layout::{Blade, BladeState, SimParams};
use super::reference::{v4, validate};
use crate::scene::Propagation;

/// Fixed point of the pushes: 1 = one micrometre.
pub const SCALE: f32 = 1.0e6;
/// A push is clamped to ±1 m before it is summed, so that 2,000 pushes fit an i32.
pub const MAX_PUSH: f32 = 1.0;
pub use crate::scene::limits::MAX_GENERATIONS;
/// The generation of a cell not reached.
pub const UNREACHED: f32 = -1.0;

/// The grid: corner, cell size and cells per side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridSpec {
    /// World x, z in metres of the grid's corner (cell (0, 0)'s corner).
    pub origin: Vec2,
    /// Side of a cell in metres.
    pub cell: f32,
    /// Cells per side (> 0; the grid has n² cells).
    pub n: u32,
}

impl GridSpec {
    /// The grid `params` describe (`None`: propagation off).
    pub fn from_params(params: &SimParams) -> Option<Self> {
        let n = params.propagation_info[0];
        (n > 0).then(|| Self {
            origin: Vec2::new(params.propagation[0], params.propagation[1]),
            cell: params.propagation[2],
            n,
        })
    }

    /// The cell a blade rooted at `v0` lies in.
    pub fn cell_of(&self, v0: Vec3) -> Option<usize> {
        let g = ((Vec2::new(v0.x, v0.z) - self.origin) / self.cell).floor();
        let n = self.n as f32;
        (g.x >= 0.0 && g.y >= 0.0 && g.x < n && g.y < n)
            .then(|| g.y as usize * self.n as usize + g.x as usize)
    }

    /// Number of cells in the grid, n².
    pub fn cells(&self) -> usize {
        self.n as usize * self.n as usize
    }
}

/// Cells per side of a propagation's grid.
pub fn cells_per_side(p: &Propagation) -> u32 {
    (p.extent / p.cell_size).ceil().max(1.0) as u32
}

/// Writes the propagation's uniforms: the grid centred on `eye`, snapped to whole cells.
pub fn fill_params(params: &mut SimParams, propagation: Option<&Propagation>, eye: Vec3) {
    let Some(p) = propagation else {
        params.propagation_info = [0; 4];
        return;
    };
    let n = cells_per_side(p);
    let half = n as f32 * 0.5 * p.cell_size;
    let snap = |x: f32| (x / p.cell_size).floor() * p.cell_size - half;
    params.propagation = [snap(eye.x), snap(eye.z), p.cell_size, p.att];
    params.propagation_info = [n, p.generations, p.threshold.to_bits(), 0];
}

/// The fixed-point value of one component of a push (`push_fixed` in WGSL).
pub fn fixed(x: f32) -> i32 {
    (x.clamp(-MAX_PUSH, MAX_PUSH) * SCALE + 0.5).floor() as i32
}

/// The pushes of one step per cell: x, z (fixed point) and how many pushes.
#[derive(Clone, Debug, PartialEq)]
pub struct Splat {
    /// The grid the pushes are summed on.
    pub spec: GridSpec,
    /// Per cell, row-major with x fastest: summed push x and z in micrometres ([`SCALE`]),
    /// and the number of pushes.
    pub sums: Vec<[i32; 3]>,
}

impl Splat {
    /// An empty splat on `spec`'s grid: every cell's sums 0.
    pub fn new(spec: GridSpec) -> Self {
        Self {
            spec,
            sums: vec![[0; 3]; spec.cells()],
        }
    }

    /// Adds the push `d` a blade rooted at `v0` received (`splat_push` in WGSL).
    pub fn add(&mut self, v0: Vec3, d: Vec3) {
        if d.x == 0.0 && d.z == 0.0 {
            return;
        }
        if let Some(c) = self.spec.cell_of(v0) {
            let s = &mut self.sums[c];
            s[0] = s[0].wrapping_add(fixed(d.x));
            s[1] = s[1].wrapping_add(fixed(d.z));
            s[2] = s[2].wrapping_add(1);
        }
    }
}

/// The force field: per cell EF.x, EF.z, the generation (`UNREACHED`: none), 0.
pub type Field = Vec<[f32; 4]>;

/// The ancestors: the mean push of each pushed cell (`init` in WGSL).
pub fn init(splat: &Splat) -> Field {
    splat
        .sums
        .iter()
        .map(|s| {
            if s[2] > 0 {
                let count = s[2] as f32;
                [
                    s[0] as f32 / count / SCALE,
                    s[1] as f32 / count / SCALE,
                    0.0,
                    0.0,
                ]
            } else {
                [0.0, 0.0, UNREACHED, 0.0]
            }
        })
        .collect()
}

/// Generation `g` of children (`generation` in WGSL).
pub fn generation(field: &mut Field, n: u32, g: u32, att: f32, threshold: f32) {
    let n = n as i64;
    let before = field.clone();
    let prev = (g - 1) as f32;
    let active = |c: &[f32; 4]| c[2] == prev && (c[0] * c[0] + c[1] * c[1]).sqrt() > threshold;
    for j in 0..n {
        for i in 0..n {
            let k = (j * n + i) as usize;
            if before[k][2] != UNREACHED {
                continue;
            }
            let at = |i: i64, j: i64| {
                (i >= 0 && j >= 0 && i < n && j < n).then(|| before[(j * n + i) as usize])
            };
            let (mut fx, mut fz, mut reached) = (0.0f32, 0.0f32, false);
            if let Some(c) = at(i - 1, j).filter(|c| active(c) && c[0] > 0.0) {
                fx += c[0] * att;
                reached = true;
            }
            if let Some(c) = at(i + 1, j).filter(|c| active(c) && c[0] < 0.0) {
                fx += c[0] * att;
                reached = true;
            }
            if let Some(c) = at(i, j - 1).filter(|c| active(c) && c[1] > 0.0) {
                fz += c[1] * att;
                reached = true;
            }
            if let Some(c) = at(i, j + 1).filter(|c| active(c) && c[1] < 0.0) {
                fz += c[1] * att;
                reached = true;
            }
            if reached {
                field[k] = [fx, fz, g as f32, 0.0];
            }
        }
    }
}

/// Every generation of one step from the splat.
pub fn propagate(splat: &Splat, params: &SimParams) -> Field {
    let mut field = init(splat);
    let threshold = f32::from_bits(params.propagation_info[2]);
    for g in 1..=params.propagation_info[1] {
        generation(
            &mut field,
            splat.spec.n,
            g,
            params.propagation[3],
            threshold,
        );
    }
    field
}

/// The push of a child cell on one Jahrmann blade (`apply` in WGSL).
pub fn apply(
    blade: &mut Blade,
    state: &mut BladeState,
    field: &Field,
    spec: &GridSpec,
    params: &SimParams,
) {
    let height = blade.v1_height[3];
    if height <= 0.0 {
        return;
    }
    let v0 = v4(blade.v0_dir).truncate();
    let Some(c) = spec.cell_of(v0) else {
        return;
    };
    let f = field[c];
    if f[2] < 1.0 || (f[0] == 0.0 && f[1] == 0.0) {
        return;
    }
    let up = v4(blade.up_stiffness).truncate();
    let d = Vec3::new(f[0], 0.0, f[1]);
    let d = d - up * d.dot(up);
    let v2 = v4(blade.v2_width).truncate() + d;
    let (v1, v2) = validate(v0, v2, up, height);
    let mut eta = state.rest_eta[3] + params.collision_gain * d.dot(d);
    if eta > params.max_eta {
        eta = params.max_eta;
    }
    blade.v1_height = [v1.x, v1.y, v1.z, height];
    blade.v2_width = [v2.x, v2.y, v2.z, blade.v2_width[3]];
    state.rest_eta[3] = eta;
}

/// `apply` over every blade.
pub fn apply_all(
    blades: &mut [Blade],
    states: &mut [BladeState],
    field: &Field,
    spec: &GridSpec,
    params: &SimParams,
) {
    for (b, s) in blades.iter_mut().zip(states.iter_mut()) {
        apply(b, s, field, spec, params);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(n: u32) -> GridSpec {
        GridSpec {
            origin: Vec2::ZERO,
            cell: 1.0,
            n,
        }
    }

    fn centre(i: u32, j: u32) -> Vec3 {
        Vec3::new(i as f32 + 0.5, 0.0, j as f32 + 0.5)
    }

    /// Eq. 4 generation by generation: an ancestor pushing +x passes att·F to the next
    /// cell in x, att²·F to the one after, and stops at the threshold; nothing goes back
    /// or sideways (the force has no z part).
    #[test]
    fn force_decays_by_att_along_its_direction_and_stops_at_the_threshold() {
        let s = spec(9);
        let mut splat = Splat::new(s);
        // Two blades of cell (2, 4) pushed 0.1 m and 0.3 m along +x: the mean is 0.2.
        splat.add(centre(2, 4), Vec3::new(0.1, 0.0, 0.0));
        splat.add(centre(2, 4), Vec3::new(0.3, 0.0, 0.0));
        let mut field = init(&splat);
        let att = 0.5;
        let threshold = 0.03;
        for g in 1..=8 {
            generation(&mut field, s.n, g, att, threshold);
        }
        let at = |i: usize, j: usize| field[j * 9 + i];
        assert!((at(2, 4)[0] - 0.2).abs() < 1e-6 && at(2, 4)[2] == 0.0);
        assert!((at(3, 4)[0] - 0.1).abs() < 1e-6 && at(3, 4)[2] == 1.0);
        assert!((at(4, 4)[0] - 0.05).abs() < 1e-6 && at(4, 4)[2] == 2.0);
        // 0.05 > L: one more child with 0.025, which is below L and passes nothing on.
        assert!((at(5, 4)[0] - 0.025).abs() < 1e-6 && at(5, 4)[2] == 3.0);
        assert_eq!(at(6, 4)[2], UNREACHED);
        assert_eq!(at(1, 4)[2], UNREACHED, "no propagation against the force");
        assert_eq!(at(2, 5)[2], UNREACHED, "no z part, no child in z");
    }

    /// A child is reached once: a later generation never adds to it (Definition 7), and
    /// two parents pointing at one cell both count (Eq. 4's sum).
    #[test]
    fn children_sum_their_parents_once() {
        let s = spec(5);
        let mut splat = Splat::new(s);
        splat.add(centre(1, 2), Vec3::new(0.2, 0.0, 0.0));
        splat.add(centre(2, 1), Vec3::new(0.0, 0.0, 0.4));
        let mut field = init(&splat);
        generation(&mut field, 5, 1, 0.5, 0.0);
        let c = field[2 * 5 + 2];
        assert_eq!(c[2], 1.0);
        assert!(
            (c[0] - 0.1).abs() < 1e-6 && (c[1] - 0.2).abs() < 1e-6,
            "{c:?}"
        );
        let before = field[2 * 5 + 2];
        generation(&mut field, 5, 2, 0.5, 0.0);
        assert_eq!(field[2 * 5 + 2], before);
    }

    #[test]
    fn cells_outside_the_grid_are_ignored() {
        let s = spec(4);
        assert_eq!(s.cell_of(Vec3::new(-0.1, 0.0, 1.0)), None);
        assert_eq!(s.cell_of(Vec3::new(4.0, 0.0, 1.0)), None);
        assert_eq!(s.cell_of(Vec3::new(3.9, 0.0, 0.0)), Some(3));
        let mut splat = Splat::new(s);
        splat.add(Vec3::new(10.0, 0.0, 10.0), Vec3::X);
        assert!(splat.sums.iter().all(|c| *c == [0; 3]));
    }

    #[test]
    fn fixed_point_rounds_and_clamps() {
        assert_eq!(fixed(1e-6), 1);
        assert_eq!(fixed(-2.5e-6), -2);
        assert_eq!(fixed(5.0), 1_000_000);
        assert_eq!(fixed(f32::NAN), 0);
    }
}
