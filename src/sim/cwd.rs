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
