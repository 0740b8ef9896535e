//! The Verlet blade of Zhang's prairie thesis (§3.2, `physics.model: Verlet`), the CPU
//! twin of `shaders/update_verlet.wgsl`: a cubic Bézier backbone P0..P3 whose free points
//! are integrated with Verlet (Eq. 7) from the wind at each point and gravity, kept above
//! the root's ground plane and pulled back to segments of a third of the height (§3.2.4),
//! then pushed out of the colliders with η trails as for Jahrmann's blade.
//!
//! Where the thesis is silent or would not settle, sward decides (and the shader's header
//! says the same): the forces are Jahrmann's at each point (recovery to the rest chain,
//! weakened by η; gravity Eq. 4; the wind at the point) times the stiffness s, so the blade
//! rests where Jahrmann's does and sways at ω = s, point k's recovery 3/k times as stiff
//! (the root segment stiffest, as along a cantilever); velocity damping (`physics.verlet.
//! damping`); Verlet with a varying Δt; sub-steps so that √3 s Δt <= 0.5.

use glam::Vec3;

use super::bvh::BvhNode;
use super::layout::{Blade, BladeState, SimParams, VerletState};
use super::reference::{
    blade_frame, blade_hierarchy, hierarchy_of, rest_curve, v4, visit_colliders, wind_at, WindGrid,
    COLLISION_ROUNDS,
};

/// Most sub-steps of one step (`MAX_SUBSTEPS` in WGSL).
pub const MAX_SUBSTEPS: u32 = 8;

/// P0 (the root) .. P3 (the tip).
pub type Chain = [Vec3; 4];

/// The shape constraint from the root up: each point pulled along its segment to `l` from
/// the one below; a segment that would end below the root's ground plane is laid flat at
/// the height of the point below instead.
pub fn constrain(p: &mut Chain, up: Vec3, front: Vec3, l: f32) {
    let v0 = p[0];
    for i in 1..4 {
        let below = p[i - 1];
        let d = p[i] - below;
        let len = d.length();
        let d = if len < 1e-6 { up } else { d / len };
        let mut q = below + d * l;
        if (q - v0).dot(up) < 0.0 {
            let mut flat = d - up * d.dot(up);
            if flat.length() < 1e-6 {
                flat = front;
            }
            q = below + flat.normalize() * l;
        }
        p[i] = q;
    }
}

/// The rest chain: the rest quadratic (v1, v2) raised to a cubic, then constrained.
pub fn rest_chain(v0: Vec3, up: Vec3, front: Vec3, rest: (Vec3, Vec3), height: f32) -> Chain {
    let (v1, v2) = rest;
    let mut c = [
        v0,
        v0 + (2.0 / 3.0) * (v1 - v0),
        v2 + (2.0 / 3.0) * (v1 - v2),
        v2,
    ];
    constrain(&mut c, up, front, height / 3.0);
    c
}

/// The four control points of a blade as the dump and the draw take them: the state's when
/// it belongs to the blade, else the blade's quadratic raised to a cubic.
pub fn control_points(blade: &Blade, state: &VerletState) -> [Vec3; 4] {
    let v0 = v4(blade.v0_dir).truncate();
    let v1 = v4(blade.v1_height).truncate();
    let v2 = v4(blade.v2_width).truncate();
    if owned(state, v0) {
        [v0, v1, v4(state.p2_dt).truncate(), v2]
    } else {
        [
            v0,
            v0 + (2.0 / 3.0) * (v1 - v0),
            v2 + (2.0 / 3.0) * (v1 - v2),
            v2,
        ]
    }
}

/// Whether `state` belongs to the blade rooted at `v0` and has been stepped
/// (`verlet_owned` in WGSL).
pub fn owned(state: &VerletState, v0: Vec3) -> bool {
    state.p2_dt[3] > 0.0 && Vec3::new(state.o1_x[3], state.o2_y[3], state.o3_z[3]) == v0
}

fn push_point(c: Vec3, r: f32, p: &mut Vec3, added: &mut f32, gain: f32) {
    let to_c = c - *p;
    let dist = to_c.length();
    if dist < r && dist > 1e-6 {
        let d = (dist - r) * to_c / dist;
        *p += d;
        *added += gain * d.dot(d);
    }
}

/// One step of one blade, the twin of `update_verlet.wgsl`. Returns true when the new
/// state was non-finite and the blade was reset to rest.
pub fn step(
    blade: &mut Blade,
    state: &mut BladeState,
    verlet: &mut VerletState,
    params: &SimParams,
    spheres: &[[f32; 4]],
    grid: &WindGrid,
    nodes: &[BvhNode],
) -> bool {
    step_push(blade, state, verlet, params, spheres, grid, nodes).0
}

/// [`step`], also returning the collision push the tip P3 received (zero after a reset).
pub fn step_push(
    blade: &mut Blade,
    state: &mut BladeState,
    verlet: &mut VerletState,
    params: &SimParams,
    spheres: &[[f32; 4]],
    grid: &WindGrid,
    nodes: &[BvhNode],
) -> (bool, Vec3) {
    let height = blade.v1_height[3];
    if height <= 0.0 {
        return (false, Vec3::ZERO);
    }
    let v0 = v4(blade.v0_dir).truncate();
    let up = v4(blade.up_stiffness).truncate();
    let (_, front) = blade_frame(up, blade.v0_dir[3]);
    let s = blade.up_stiffness[3] * params.stiffness_scale;
    let mut eta = state.rest_eta[3];
    let dt = params.dt;
    let l = height / 3.0;
    let rest = rest_chain(
        v0,
        up,
        front,
        rest_curve(v0, v4(state.rest_eta).truncate(), up, height),
        height,
    );
    let st = *verlet;
    let xyz = |a: [f32; 4]| Vec3::new(a[0], a[1], a[2]);
    let mut p: Chain = [v0, xyz(blade.v1_height), xyz(st.p2_dt), xyz(blade.v2_width)];
    let mut o: Chain = [v0, xyz(st.o1_x), xyz(st.o2_y), xyz(st.o3_z)];
    let mut dt_prev = st.p2_dt[3];
    let moved = v0 - Vec3::new(st.o1_x[3], st.o2_y[3], st.o3_z[3]);
    // NaN too, as `!(x > 0)` in WGSL.
    if dt_prev.is_nan() || dt_prev <= 0.0 || moved.length() > 0.5 * height {
        p = rest;
        o = rest;
        dt_prev = dt;
    } else if moved != Vec3::ZERO {
        p[2] += moved;
        o[1] += moved;
        o[2] += moved;
        o[3] += moved;
    }

    let g_env = super::reference::environmental_gravity(params, v0);
    let mut w = [Vec3::ZERO; 4];
    for k in 1..4 {
        w[k] = wind_at(p[k], (p[k] - v0).dot(up).max(0.0), params, grid) * params.model[3];
    }
    let weak = (1.0 - eta).max(0.1);
    let n = if dt > 0.0 {
        ((s * 3.0f32.sqrt() * dt / 0.5).ceil() as u32).clamp(1, MAX_SUBSTEPS)
    } else {
        0
    };
    let hs = dt / n.max(1) as f32;
    let damp = (-params.model[1] * hs).exp();
    for _ in 0..n {
        let ratio = hs / dt_prev;
        let reach = 0.5 * hs * (hs + dt_prev);
        for k in 1..4 {
            let a = s * (s * (3.0 / k as f32) * (rest[k] - p[k]) * weak + g_env + w[k]);
            let next = p[k] + (p[k] - o[k]) * (ratio * damp) + a * reach;
            o[k] = p[k];
            p[k] = next - up * (next - v0).dot(up).min(0.0);
        }
        dt_prev = hs;
        constrain(&mut p, up, front, l);
    }
    let decayed = eta - params.collision_decay * dt;
    eta = decayed.max(0.0);
    let mut pushed = Vec3::ZERO;
    if params.collisions != 0 {
        let hierarchy = blade_hierarchy(nodes, params, v0, height);
        let gain = params.collision_gain;
        for _ in 0..COLLISION_ROUNDS {
            let mut added = 0.0;
            let (mut p1, mut p2, mut p3) = (p[1], p[2], p[3]);
            visit_colliders(v0, params, spheres, hierarchy, |c, r| {
                push_point(c, r, &mut p1, &mut added, gain);
                push_point(c, r, &mut p2, &mut added, gain);
                push_point(c, r, &mut p3, &mut added, gain);
            });
            if added <= 0.0 {
                break;
            }
            eta += added;
            pushed += p3 - p[3];
            (p[1], p[2], p[3]) = (p1, p2, p3);
            constrain(&mut p, up, front, l);
        }
    }
    let sound = decayed.is_finite()
        && eta.is_finite()
        && p[1..].iter().all(|q| q.is_finite())
        && o[1..].iter().all(|q| q.is_finite());
    if eta > params.max_eta {
        eta = params.max_eta;
    }
    if !sound {
        p = rest;
        o = rest;
        eta = 0.0;
        pushed = Vec3::ZERO;
    }
    blade.v1_height = [p[1].x, p[1].y, p[1].z, height];
    blade.v2_width = [p[3].x, p[3].y, p[3].z, blade.v2_width[3]];
    state.rest_eta[3] = eta;
    *verlet = VerletState {
        p2_dt: [p[2].x, p[2].y, p[2].z, dt_prev],
        o1_x: [o[1].x, o[1].y, o[1].z, v0.x],
        o2_y: [o[2].x, o[2].y, o[2].z, v0.y],
        o3_z: [o[3].x, o[3].y, o[3].z, v0.z],
    };
    (!sound, pushed)
}

/// One step over every blade, the pushes added to `splat` when given; returns how many
/// were reset.
pub fn update_all(
    blades: &mut [Blade],
    states: &mut [BladeState],
    verlet: &mut [VerletState],
    params: &SimParams,
    spheres: &[[f32; 4]],
    grid: &WindGrid,
    mut splat: Option<&mut super::propagation::Splat>,
) -> u32 {
    let nodes = hierarchy_of(params, spheres);
    let mut resets = 0;
    for ((b, s), v) in blades
        .iter_mut()
        .zip(states.iter_mut())
        .zip(verlet.iter_mut())
    {
        let (reset, pushed) = step_push(b, s, v, params, spheres, grid, &nodes);
        resets += reset as u32;
        if let Some(splat) = splat.as_deref_mut() {
            splat.add(v4(b.v0_dir).truncate(), pushed);
        }
    }
    resets
}

/// The cubic Bézier point at t (thesis Eq. 5).
pub fn cubic(p: &[Vec3; 4], t: f32) -> Vec3 {
    let u = 1.0 - t;
    p[0] * (u * u * u) + p[1] * (3.0 * t * u * u) + p[2] * (3.0 * t * t * u) + p[3] * (t * t * t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Whatever the points, the constraint leaves segments of exactly `l` (to rounding)
        /// and nothing below the root's ground plane.
        #[test]
        fn constraint_keeps_length_and_ground(
            pts in proptest::collection::vec((-2.0f32..2.0, -2.0f32..2.0, -2.0f32..2.0), 3),
            l in 0.01f32..1.0,
        ) {
            let up = Vec3::Y;
            let mut c: Chain = [
                Vec3::ZERO,
                Vec3::from(pts[0]),
                Vec3::from(pts[1]),
                Vec3::from(pts[2]),
            ];
            constrain(&mut c, up, Vec3::Z, l);
            for k in 1..4 {
                prop_assert!((c[k].distance(c[k - 1]) - l).abs() <= 1e-5 * l.max(1.0));
                prop_assert!(c[k].y >= -1e-6);
            }
        }
    }

    /// Without forces a blade at rest stays at rest.
    #[test]
    fn rest_is_at_rest() {
        let v0 = Vec3::new(0.3, 0.0, -0.2);
        let (v1, v2) = super::super::reference::rest_pose(v0, Vec3::Y, Vec3::Z, 0.6, 0.3);
        let mut blade = Blade {
            v0_dir: [v0.x, v0.y, v0.z, 0.0],
            v1_height: [v1.x, v1.y, v1.z, 0.6],
            v2_width: [v2.x, v2.y, v2.z, 0.04],
            up_stiffness: [0.0, 1.0, 0.0, 9.0],
        };
        let mut state = BladeState {
            rest_eta: [v2.x, v2.y, v2.z, 0.0],
        };
        let mut verlet = VerletState::default();
        let params = SimParams {
            dt: 1.0 / 30.0,
            stiffness_scale: 1.0,
            model: [1.0, 3.0, 1.0, 1.0],
            ..Default::default()
        };
        let zero = [[0.0f32; 2]];
        let grid = WindGrid { velocity: &zero };
        step(
            &mut blade,
            &mut state,
            &mut verlet,
            &params,
            &[],
            &grid,
            &[],
        );
        let first = control_points(&blade, &verlet);
        for _ in 0..100 {
            step(
                &mut blade,
                &mut state,
                &mut verlet,
                &params,
                &[],
                &grid,
                &[],
            );
        }
        let last = control_points(&blade, &verlet);
        for k in 0..4 {
            assert!(first[k].distance(last[k]) < 1e-5, "point {k}");
        }
        assert!(owned(&verlet, v0));
    }
}
