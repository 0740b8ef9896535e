//! CPU twins of the GPU kernels: the blade update (`shaders/update.wgsl`) here, and the
//! cull predicate (`shaders/cull.wgsl`) in [`cull`], re-exported here. They follow the
//! shaders line by line, in f32, so that tests can compare GPU read-back with them;
//! `sward simulate --cpu` runs them too.
//! Equation numbers refer to Jahrmann & Wimmer 2017.

use glam::{Vec2, Vec3, Vec4, Vec4Swizzles};

use super::bvh::{self, BvhNode};

use super::layout::{Blade, BladeState, SimParams, WIND_ANALYTIC, WIND_FLUID};

pub use crate::field::blade::{blade_frame, curve_length, rest_pose, validate};

/// The analytic wind w_i(p) at time `time` (Section 5.1): travelling gust waves along a
/// direction plus a pulsing radial point source.
pub fn analytic_wind(p: Vec3, time: f32, params: &SimParams) -> Vec3 {
    let mut w = Vec3::ZERO;
    let dir = params.wind_dir;
    if dir[2] != 0.0 {
        let d = Vec2::new(dir[0], dir[1]);
        let k = std::f32::consts::TAU / params.wind_wave[0];
        let phase = (p.x * d.x + p.z * d.y - time * params.wind_wave[1]) * k;
        // Two incommensurate harmonics plus a slow cross-wind term keep the gusts from
        // looking like a single sine sweeping the field.
        let along = 1.0
            + dir[3] * (0.6 * phase.sin() + 0.4 * (2.7 * phase + 0.31 * p.x - 0.17 * p.z).sin());
        let across = 0.25 * dir[3] * (0.5 * phase + 0.23 * (p.x + p.z)).cos();
        let side = Vec2::new(-d.y, d.x);
        let f = (d * along + side * across) * dir[2];
        w += Vec3::new(f.x, 0.0, f.y);
    }
    let source = params.point_wind;
    if source[3] != 0.0 {
        let offset = Vec3::new(p.x - source[0], 0.0, p.z - source[2]);
        let dist = offset.length();
        let radius = params.point_wind_shape[0];
        if dist > 1e-4 && dist < radius {
            let falloff = (1.0 - dist / radius) * (1.0 - dist / radius);
            let pulse = 0.6
                + 0.4
                    * (std::f32::consts::TAU * params.point_wind_shape[1] * time - 1.5 * dist)
                        .sin();
            w += offset / dist * (source[3] * falloff * pulse);
        }
    }
    w
}

/// The fluid solver's velocity grid as the blade update reads it.
#[derive(Clone, Copy, Debug)]
pub struct WindGrid<'a> {
    /// resolution² cells per layer, layer 0 first, row-major, x fastest; (u, v) along
    /// (x, z) in m/s.
    pub velocity: &'a [[f32; 2]],
}

fn grid_at(grid: &WindGrid, i: i32, j: i32, k: i32, n: i32) -> Vec2 {
    let c = grid.velocity[((k * n + j.clamp(0, n - 1)) * n + i.clamp(0, n - 1)) as usize];
    Vec2::new(c[0], c[1])
}

/// `fluid_layer_velocity`: bilinear in layer k (or the cell's value, per cell).
fn layer_velocity(grid: &WindGrid, g: Vec2, k: i32, n: i32, per_cell: bool) -> Vec2 {
    if per_cell {
        let c = g.floor();
        return grid_at(grid, c.x as i32, c.y as i32, k, n);
    }
    let q = (g - 0.5).clamp(Vec2::ZERO, Vec2::splat((n - 1) as f32));
    let c = q.floor();
    let f = q - c;
    let (ci, cj) = (c.x as i32, c.y as i32);
    let a = grid_at(grid, ci, cj, k, n).lerp(grid_at(grid, ci + 1, cj, k, n), f.x);
    let b = grid_at(grid, ci, cj + 1, k, n).lerp(grid_at(grid, ci + 1, cj + 1, k, n), f.x);
    a.lerp(b, f.y)
}

/// Air velocity at a world position `height` metres above the ground (bilinear, or per
/// cell; in a 3D grid linear between the two layers around that height); the twin of
/// `fluid_velocity` in `wind_sample.wgsl`.
pub fn sample_grid(grid: &WindGrid, p: Vec3, height: f32, params: &SimParams) -> Vec2 {
    let n = params.fluid_info[0] as i32;
    let layers = params.fluid_info[3].max(1) as i32;
    let per_cell = params.fluid_info[2] != 0;
    let fg = params.fluid_grid;
    let g = (Vec2::new(p.x, p.z) - Vec2::new(fg[0], fg[1])) / fg[2];
    if layers == 1 {
        return layer_velocity(grid, g, 0, n, per_cell);
    }
    let y = height / params.fluid_layer_height;
    if per_cell {
        return layer_velocity(grid, g, (y.floor() as i32).clamp(0, layers - 1), n, true);
    }
    let q = (y - 0.5).clamp(0.0, (layers - 1) as f32);
    let k = (q.floor() as i32).min(layers - 2);
    let t = q - k as f32;
    layer_velocity(grid, g, k, n, false).lerp(layer_velocity(grid, g, k + 1, n, false), t)
}

/// w_i: the analytic functions at p and/or the fluid grid at p, `height` above the ground,
/// as the scene chooses.
pub fn wind_at(p: Vec3, height: f32, params: &SimParams, grid: &WindGrid) -> Vec3 {
    let mut w = Vec3::ZERO;
    if params.fluid_info[1] & WIND_ANALYTIC != 0 {
        w += analytic_wind(p, params.time, params);
    }
    if params.fluid_info[1] & WIND_FLUID != 0 {
        let v = sample_grid(grid, p, height, params) * params.fluid_grid[3];
        w += Vec3::new(v.x, 0.0, v.y);
    }
    w
}

/// Most collide + validate rounds per step; `COLLISION_ROUNDS` in WGSL.
pub const COLLISION_ROUNDS: u32 = 4;

pub(crate) fn v4(a: [f32; 4]) -> Vec4 {
    Vec4::from_array(a)
}

/// Eq. 14–16 for one sphere (c, r) against v2 and the curve midpoint m (the push on m
/// moves v2 four times as far); `push_out` in `update.wgsl`.
fn push_out(c: Vec3, r: f32, v0: Vec3, v1: Vec3, v2: &mut Vec3, added: &mut f32, gain: f32) {
    let to_c = c - *v2;
    let dist = to_c.length();
    if dist < r && dist > 1e-6 {
        let d = (dist - r) * to_c / dist;
        *v2 += d;
        *added += gain * d.dot(d);
    }
    let m = 0.25 * v0 + 0.5 * v1 + 0.25 * *v2;
    let to_c = c - m;
    let dist = to_c.length();
    if dist < r && dist > 1e-6 {
        let d = (dist - r) * to_c / dist;
        *v2 += 4.0 * d;
        *added += gain * d.dot(d);
    }
}

/// The collision hierarchy of one step and how deep each blade walks it (`collide_bvh` in
/// `update.wgsl`).
#[derive(Clone, Copy, Debug)]
pub struct Hierarchy<'a> {
    /// The hierarchy's nodes, node 0 the root (empty: test every sphere in index order).
    pub nodes: &'a [BvhNode],
    /// The level the walk stops at ([`bvh::depth_limit`]).
    pub limit: u32,
    /// The blade's height (the reach of its tip and midpoint from the root).
    pub height: f32,
}

/// Eq. 14–16: every sphere against v2 and the curve midpoint m, in index order, or the walk
/// of the hierarchy when one is given (depth first, left child first, a node's sphere
/// standing in for those under it at the blade's depth limit). Returns the new v2 and the
/// added collision strength.
pub fn collide(
    v0: Vec3,
    v1: Vec3,
    v2: Vec3,
    params: &SimParams,
    spheres: &[[f32; 4]],
    hierarchy: Option<Hierarchy>,
) -> (Vec3, f32) {
    let mut v2 = v2;
    let mut added = 0.0;
    let gain = params.collision_gain;
    visit_colliders(v0, params, spheres, hierarchy, |c, r| {
        push_out(c, r, v0, v1, &mut v2, &mut added, gain)
    });
    (v2, added)
}

/// Calls `push` with every collider (centre, radius) a blade rooted at `root` meets, in the
/// order the GPU pushes them (`collide_walk.wgsl`): every sphere in index order, or the
/// walk of the hierarchy when one is given (nothing beyond `hierarchy.height` of the root).
/// Shared by every blade model's twin.
pub fn visit_colliders(
    root: Vec3,
    params: &SimParams,
    spheres: &[[f32; 4]],
    hierarchy: Option<Hierarchy>,
    mut push: impl FnMut(Vec3, f32),
) {
    let Some(h) = hierarchy.filter(|h| !h.nodes.is_empty()) else {
        for s in spheres.iter().take(params.sphere_count as usize) {
            push(Vec3::new(s[0], s[1], s[2]), s[3]);
        }
        return;
    };
    let mut stack = vec![0u32];
    while let Some(k) = stack.pop() {
        let node = &h.nodes[k as usize];
        let c = Vec3::new(node.sphere[0], node.sphere[1], node.sphere[2]);
        let r = node.sphere[3];
        if c.distance(root) >= r + h.height {
            continue;
        }
        if bvh::is_leaf(node) {
            let s = spheres[node.link[2] as usize];
            push(Vec3::new(s[0], s[1], s[2]), s[3]);
        } else if node.link[2] == bvh::INTERNAL && node.link[3] >= h.limit {
            push(c, r);
        } else if stack.len() + 2 <= 32 {
            stack.push(node.link[1]);
            stack.push(node.link[0]);
        }
    }
}

/// The hierarchy a blade at `v0` walks this step (`None`: the flat list), as the update
/// shaders' `bvh_depth_limit` cuts it (every patch taken as stepped every frame).
pub fn blade_hierarchy<'a>(
    nodes: &'a [BvhNode],
    params: &SimParams,
    v0: Vec3,
    height: f32,
) -> Option<Hierarchy<'a>> {
    let camera = Vec3::new(
        params.bvh_camera[0],
        params.bvh_camera[1],
        params.bvh_camera[2],
    );
    (!nodes.is_empty()).then(|| Hierarchy {
        nodes,
        limit: bvh::depth_limit(
            params.bvh_info[2],
            v0.distance(camera),
            params.bvh_camera[3],
            false,
        ),
        height,
    })
}

/// Whether a blade's new state is sound: every value finite and the curve's length (Eq. 12)
/// within half a height of the height (the validation makes it equal; only overflow, e.g.
/// from an absurd force, breaks that). The twin of `state_sound` in `update.wgsl`.
pub fn state_sound(v0: Vec3, v1: Vec3, v2: Vec3, height: f32, eta: f32) -> bool {
    if !(v1.is_finite() && v2.is_finite() && eta.is_finite()) {
        return false;
    }
    (curve_length(v0, v1, v2) - height).abs() <= 0.5 * height
}

/// The rest pose (v1, v2) of a blade from its immutable data: the rest tip `rest` (the
/// state's `rest_eta.xyz`, straight up when that is not finite) through the validation.
/// The generator's pose is a fixed point of the validation, so this is that pose to
/// rounding. The twin of `rest_curve` in `update.wgsl`.
pub fn rest_curve(v0: Vec3, rest: Vec3, up: Vec3, height: f32) -> (Vec3, Vec3) {
    let tip = if rest.is_finite() {
        rest
    } else {
        v0 + up * height
    };
    validate(v0, tip, up, height)
}

/// The rest pose of `blade` as the update resets it: (v1, v2), η = 0.
pub fn blade_rest_pose(blade: &Blade, state: &BladeState) -> (Vec3, Vec3) {
    rest_curve(
        v4(blade.v0_dir).xyz(),
        v4(state.rest_eta).xyz(),
        v4(blade.up_stiffness).xyz(),
        blade.v1_height[3],
    )
}

/// Eq. 4: the environmental gravity on a blade rooted at `v0`, direction and centre blended
/// by t, times the mass (`environmental_gravity` in `update_common.wgsl`). Shared by every
/// blade model's twin.
pub fn environmental_gravity(params: &SimParams, v0: Vec3) -> Vec3 {
    let gd = v4(params.gravity_dir);
    let gc = v4(params.gravity_center);
    let to_center = gc.xyz() - v0;
    let center_dir = if to_center.length() > 1e-6 {
        to_center.normalize()
    } else {
        Vec3::ZERO
    };
    params.mass
        * (gd.xyz() * gd.w * (1.0 - params.gravity_blend)
            + center_dir * gc.w * params.gravity_blend)
}

/// One update step of one blade (Eq. 1–16 and the validation), the twin of `update.wgsl`.
/// Returns true when the new state was non-finite or absurd and the blade was reset to
/// its rest pose instead (see [`state_sound`]).
pub fn update_blade(
    blade: &mut Blade,
    state: &mut BladeState,
    params: &SimParams,
    spheres: &[[f32; 4]],
    grid: &WindGrid,
) -> bool {
    let nodes = hierarchy_of(params, spheres);
    step_blade(blade, state, params, spheres, grid, &nodes)
}

/// The collision hierarchy the GPU walks this step (empty when it is off).
pub fn hierarchy_of(params: &SimParams, spheres: &[[f32; 4]]) -> Vec<BvhNode> {
    if params.bvh_info[0] == 0 {
        return Vec::new();
    }
    bvh::build(&spheres[..(params.sphere_count as usize).min(spheres.len())])
}

/// [`update_blade`] with the step's hierarchy `nodes` (empty: the flat list). Every patch
/// is taken as stepped every frame (the twin has no throttle).
fn step_blade(
    blade: &mut Blade,
    state: &mut BladeState,
    params: &SimParams,
    spheres: &[[f32; 4]],
    grid: &WindGrid,
    nodes: &[BvhNode],
) -> bool {
    step_blade_push(blade, state, params, spheres, grid, nodes).0
}

/// [`step_blade`], also returning the collision push the tip received this step (zero
/// after a reset): what the grass-to-grass propagation splats (`sim::propagation`).
fn step_blade_push(
    blade: &mut Blade,
    state: &mut BladeState,
    params: &SimParams,
    spheres: &[[f32; 4]],
    grid: &WindGrid,
    nodes: &[BvhNode],
) -> (bool, Vec3) {
    let v0 = v4(blade.v0_dir).xyz();
    let angle = blade.v0_dir[3];
    let height = blade.v1_height[3];
    let mut v2 = v4(blade.v2_width).xyz();
    let up = v4(blade.up_stiffness).xyz();
    let stiffness = blade.up_stiffness[3] * params.stiffness_scale;
    let rest = v4(state.rest_eta).xyz();
    let mut eta = state.rest_eta[3];
    let dt = params.dt;
    // A blade the tile generation removed (height 0) is not stepped.
    if height <= 0.0 {
        return (false, Vec3::ZERO);
    }
    let (_, front) = blade_frame(up, angle);

    // Eq. 3: recovery, weakened by the collision strength.
    let recovery = (rest - v2) * stiffness * (1.0 - eta).max(0.1);
    // Eq. 4: environmental gravity, direction and centre blended by t.
    let g_env = environmental_gravity(params, v0);
    // Eq. 5–6: front gravity.
    let gravity = g_env + 0.25 * g_env.length() * front;
    // Eq. 7–8: wind with the alignment θ.
    let wi = wind_at(v0, height, params, grid);
    let mut wind = Vec3::ZERO;
    let wl = wi.length();
    let tip = v2 - v0;
    let tl = tip.length();
    if wl > 1e-6 && tl > 1e-6 {
        let fd = 1.0 - (wi / wl).dot(tip / tl).abs();
        let fr = tip.dot(up) / height;
        wind = wi * (fd * fr);
    }
    // Eq. 1 (the collision displacement d follows below).
    v2 += (recovery + gravity + wind) * dt;
    // Eq. 2: the collision strength fades (the unclamped value joins the soundness test).
    let decayed = eta - params.collision_decay * dt;
    eta = decayed.max(0.0);

    // Validate first so that the midpoint m of the collision test is that of a valid curve
    // (v1 follows v2), then collide; the length correction after a push can pull a point
    // back into the sphere, so collide + validate repeats until nothing is pushed.
    let (mut v1, mut v2) = validate(v0, v2, up, height);
    let mut pushed = Vec3::ZERO;
    if params.collisions != 0 {
        let hierarchy = blade_hierarchy(nodes, params, v0, height);
        for _ in 0..COLLISION_ROUNDS {
            let (cv2, added) = collide(v0, v1, v2, params, spheres, hierarchy);
            if added <= 0.0 {
                break;
            }
            eta += added;
            pushed += cv2 - v2;
            (v1, v2) = validate(v0, cv2, up, height);
        }
    }
    // A non-finite or absurd state is never kept: the blade starts over from its rest
    // pose. Tested before the ceiling, a comparison as in WGSL (where min() of a NaN is
    // undefined).
    let sound = decayed.is_finite() && state_sound(v0, v1, v2, height, eta);
    if eta > params.max_eta {
        eta = params.max_eta;
    }
    if !sound {
        (v1, v2) = rest_curve(v0, rest, up, height);
        eta = 0.0;
        pushed = Vec3::ZERO;
    }
    blade.v1_height = [v1.x, v1.y, v1.z, height];
    blade.v2_width = [v2.x, v2.y, v2.z, blade.v2_width[3]];
    state.rest_eta[3] = eta;
    (!sound, pushed)
}

/// Runs one update step over every blade; returns how many were reset to their rest pose
/// because their new state was non-finite or absurd.
pub fn update_all(
    blades: &mut [Blade],
    states: &mut [BladeState],
    params: &SimParams,
    spheres: &[[f32; 4]],
    grid: &WindGrid,
) -> u32 {
    update_all_splat(blades, states, params, spheres, grid, None)
}

/// [`update_all`], adding every blade's collision push to `splat` (the grass-to-grass
/// propagation's ancestors) when one is given.
pub fn update_all_splat(
    blades: &mut [Blade],
    states: &mut [BladeState],
    params: &SimParams,
    spheres: &[[f32; 4]],
    grid: &WindGrid,
    mut splat: Option<&mut super::propagation::Splat>,
) -> u32 {
    let nodes = hierarchy_of(params, spheres);
    let mut resets = 0;
    for (b, s) in blades.iter_mut().zip(states.iter_mut()) {
        let (reset, pushed) = step_blade_push(b, s, params, spheres, grid, &nodes);
        resets += reset as u32;
        if let Some(splat) = splat.as_deref_mut() {
            splat.add(v4(b.v0_dir).truncate(), pushed);
        }
    }
    resets
}

pub mod cull;
pub mod fluid;
pub mod hiz;
pub mod thin_order;

pub use cull::*;
