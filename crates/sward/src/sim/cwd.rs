//! CWD-Sim's grass deformation (Choi & Sung 2024, §3.3, Eq. 11–13; `physics.model: Cwd`),
//! the CPU twin of `shaders/cwd.wgsl` and of the pose pass `shaders/update_cwd.wgsl`.
//!
//! A Cwd blade has no state between frames: every vertex of the straight rest blade (Py = v
//! in blade heights, v = 0 at the root, 1 at the tip) is bent by gravity (Eq. 11) and
//! translated by the wind V of the blade's cell (Eq. 12):
//! P' = (Px, Py − k1·Py², Pz + k2·Py²), T = F·(Vx·P'y², −|V|·P'y², Vz·P'y²). Eq. 13 as
//! printed, P'' = M((1 − λ)T + λP'), would shrink a windless blade to λ of its height;
//! sward reads it as P'' = M(P' + (1 − λ)T). No vertex goes below the root's ground plane.
//! Without state there are no collisions and no trails.

use glam::Vec3;

use super::layout::{Blade, BladeState, SimParams, WIND_FLUID};
use super::reference::{blade_frame, v4, wind_at, WindGrid};

/// Where a Cwd blade rooted at `v0` reads the wind: the centre of its cell.
pub fn sample_point(v0: Vec3, params: &SimParams) -> Vec3 {
    let (origin, size) = if params.fluid_info[1] & WIND_FLUID != 0 {
        (
            glam::Vec2::new(params.fluid_grid[0], params.fluid_grid[1]),
            params.fluid_grid[2],
        )
    } else {
        (glam::Vec2::ZERO, params.model[2])
    };
    let cell = ((glam::Vec2::new(v0.x, v0.z) - origin) / size).floor();
    let c = origin + (cell + 0.5) * size;
    Vec3::new(c.x, v0.y, c.y)
}

/// The wind a Cwd blade feels (Eq. 12's V).
pub fn blade_wind(v0: Vec3, height: f32, params: &SimParams, grid: &WindGrid) -> Vec3 {
    wind_at(sample_point(v0, params), height, params, grid)
}

/// The point at v along a Cwd blade and its tangent d/dv (`cwd_point` in WGSL).
pub fn point(
    v0: Vec3,
    up: Vec3,
    front: Vec3,
    height: f32,
    wind: Vec3,
    v: f32,
    cwd: [f32; 4],
) -> (Vec3, Vec3) {
    let [k1, k2, lambda, force] = cwd;
    let s = (1.0 - lambda) * force;
    let w = wind - up * wind.dot(up);
    let speed = w.length();
    let q = v - k1 * v * v;
    let dq = 1.0 - 2.0 * k1 * v;
    let z = k2 * v * v;
    let dz = 2.0 * k2 * v;
    let mut y = q - s * speed * q * q;
    let mut dy = dq - 2.0 * s * speed * q * dq;
    if y < 0.0 {
        y = 0.0;
        dy = 0.0;
    }
    let p = v0 + height * (up * y + front * z + w * (s * q * q));
    let t = height * (up * dy + front * dz + w * (2.0 * s * q * dq));
    (p, t)
}

/// The pose the culling sees (v1, v2): the quadratic through the root, the bent blade's
/// middle and its tip.
pub fn pose(blade: &Blade, params: &SimParams, grid: &WindGrid) -> (Vec3, Vec3) {
    let v0 = v4(blade.v0_dir).truncate();
    let up = v4(blade.up_stiffness).truncate();
    let height = blade.v1_height[3];
    let (_, front) = blade_frame(up, blade.v0_dir[3]);
    let wind = blade_wind(v0, height, params, grid);
    let (mid, _) = point(v0, up, front, height, wind, 0.5, params.cwd);
    let (tip, _) = point(v0, up, front, height, wind, 1.0, params.cwd);
    (2.0 * mid - 0.5 * (v0 + tip), tip)
}

/// The pose pass over every blade; returns how many fell back to upright (non-finite).
pub fn pose_all(
    blades: &mut [Blade],
    states: &mut [BladeState],
    params: &SimParams,
    grid: &WindGrid,
) -> u32 {
    let mut resets = 0;
    for (b, s) in blades.iter_mut().zip(states.iter_mut()) {
        let height = b.v1_height[3];
        if height <= 0.0 {
            continue;
        }
        let (mut v1, mut v2) = pose(b, params, grid);
        if !(v1.is_finite() && v2.is_finite()) {
            let v0 = v4(b.v0_dir).truncate();
            let up = v4(b.up_stiffness).truncate();
            v1 = v0 + up * (0.5 * height);
            v2 = v0 + up * height;
            resets += 1;
        }
        b.v1_height = [v1.x, v1.y, v1.z, height];
        b.v2_width = [v2.x, v2.y, v2.z, b.v2_width[3]];
        s.rest_eta[3] = 0.0;
    }
    resets
}

/// The length of the bent centreline, by `n` straight pieces.
pub fn centreline_length(
    v0: Vec3,
    up: Vec3,
    front: Vec3,
    height: f32,
    wind: Vec3,
    cwd: [f32; 4],
    n: u32,
) -> f32 {
    let mut len = 0.0;
    let mut last = v0;
    for k in 1..=n {
        let (p, _) = point(v0, up, front, height, wind, k as f32 / n as f32, cwd);
        len += p.distance(last);
        last = p;
    }
    len
}

#[cfg(test)]
mod tests {
    use super::*;

    const PAPER: [f32; 4] = [0.05, 0.1, 0.2, 0.1];
    const UP: Vec3 = Vec3::Y;
    const FRONT: Vec3 = Vec3::Z;

    #[test]
    fn windless_blade_is_eq_11() {
        let h = 0.8;
        for k in 0..=10 {
            let v = k as f32 / 10.0;
            let (p, _) = point(Vec3::ZERO, UP, FRONT, h, Vec3::ZERO, v, PAPER);
            let expected = Vec3::new(0.0, h * (v - 0.05 * v * v), h * 0.1 * v * v);
            assert!(p.distance(expected) < 1e-6, "v = {v}: {p} vs {expected}");
        }
    }

    /// The tangent is the derivative of the point (the vertex shader's normal uses it).
    #[test]
    fn tangent_is_the_derivative() {
        let wind = Vec3::new(3.0, 0.0, -1.0);
        for k in 1..20 {
            let v = k as f32 / 20.0;
            let e = 1e-3;
            let (a, _) = point(Vec3::ZERO, UP, FRONT, 1.0, wind, v - e, PAPER);
            let (b, _) = point(Vec3::ZERO, UP, FRONT, 1.0, wind, v + e, PAPER);
            let (_, t) = point(Vec3::ZERO, UP, FRONT, 1.0, wind, v, PAPER);
            let numeric = (b - a) / (2.0 * e);
            assert!(numeric.distance(t) < 1e-2, "v = {v}: {t} vs {numeric}");
        }
    }

    /// Continuous in the force: a change ΔV of the wind moves no vertex further than
    /// 2 (1 − λ) F h |ΔV| (the translation is (1 − λ) F h P'y² (V_t, −|V_t|) with P'y <= 1).
    #[test]
    fn deformation_is_continuous_in_the_force() {
        let h = 0.9;
        let lipschitz = 2.0 * (1.0 - PAPER[2]) * PAPER[3] * h;
        let mut seed = 7u32;
        let mut rnd = || {
            seed = seed.wrapping_mul(1664525).wrapping_add(1013904223);
            (seed >> 8) as f32 / (1 << 24) as f32 * 2.0 - 1.0
        };
        for _ in 0..500 {
            let w = Vec3::new(rnd() * 6.0, 0.0, rnd() * 6.0);
            let dw = Vec3::new(rnd(), 0.0, rnd()) * 0.01;
            for k in 0..=8 {
                let v = k as f32 / 8.0;
                let (a, _) = point(Vec3::ZERO, UP, FRONT, h, w, v, PAPER);
                let (b, _) = point(Vec3::ZERO, UP, FRONT, h, w + dw, v, PAPER);
                assert!(
                    a.distance(b) <= lipschitz * dw.length() * 1.0001 + 1e-6,
                    "wind {w} + {dw}, v = {v}: moved {}",
                    a.distance(b)
                );
            }
        }
    }

    /// The length change is bounded by the translation's own length: the centre line of the
    /// wind term is (1 − λ) F h P'y² (V_t, −|V_t|), at most √2 s h P'y(1)² long with
    /// s = (1 − λ) F |V|, so |L(V) − L(0)| <= √2 s h q(1)² while no vertex touches the
    /// ground. Measured over winds from calm to the edge of the ground.
    #[test]
    fn length_change_is_bounded() {
        let h = 1.0;
        let q1 = 1.0 - PAPER[0];
        let rest = centreline_length(Vec3::ZERO, UP, FRONT, h, Vec3::ZERO, PAPER, 400);
        let mut worst = 0.0f32;
        for k in 0..=40 {
            let speed = k as f32 * 0.25;
            let s = (1.0 - PAPER[2]) * PAPER[3] * speed;
            // Beyond s q(1) >= 1 the tip reaches the ground plane.
            if s * q1 >= 1.0 {
                break;
            }
            let wind = Vec3::new(0.6, 0.0, 0.8) * speed;
            let len = centreline_length(Vec3::ZERO, UP, FRONT, h, wind, PAPER, 400);
            let bound = 2f32.sqrt() * s * h * q1 * q1;
            worst = worst.max((len - rest).abs() / bound.max(1e-9));
            assert!(
                (len - rest).abs() <= bound + 1e-4,
                "|V| = {speed}: length {len} vs {rest}, bound {bound}"
            );
        }
        assert!(
            worst > 0.1,
            "the test must reach the bound's order ({worst})"
        );
    }

    #[test]
    fn no_vertex_goes_below_the_ground() {
        let wind = Vec3::new(40.0, 0.0, 0.0);
        for k in 0..=20 {
            let (p, _) = point(Vec3::ZERO, UP, FRONT, 1.0, wind, k as f32 / 20.0, PAPER);
            assert!(p.y >= 0.0, "{p}");
        }
    }
}
