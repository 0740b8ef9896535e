// What every blade-update pass shares (`update.wgsl` for Jahrmann's blade,
// `update_verlet.wgsl` for the thesis's, `update_cwd.wgsl` for CWD-Sim's pose): the
// bindings, the finite tests, and which blade an invocation steps.
//!include common.wgsl
//!include wind.wgsl
//!include blade_pose.wgsl
//!include wind_sample.wgsl
//!include bvh_node.wgsl
//!include update_slot.wgsl
//!include trails.wgsl

@group(0) @binding(0) var<uniform> params: SimParams;
@group(0) @binding(1) var<storage, read_write> blades: array<Blade>;
@group(0) @binding(2) var<storage, read_write> states: array<BladeState>;
// The colliders, then their hierarchy's nodes from BVH_NODE_BASE (`bvh_node.wgsl`).
@group(0) @binding(3) var<storage, read> spheres: array<vec4<f32>>;
// The fluid solver's velocity grid (one dummy cell when the fluid is off).
@group(0) @binding(4) var<storage, read> wind_grid: array<vec2<f32>>;
// The patch pass's lists (`cull.wgsl`): the update list [count, patch | THROTTLED?, ...]
// starts at patch_count + 1.
@group(0) @binding(5) var<storage, read> patch_lists: array<u32>;
// The broad phase's list per patch: [count or SPHERES_ALL, sphere or (with the hierarchy)
// node, ...], a longer flat list [count, start] with its spheres in the pool at `start`.
@group(0) @binding(6) var<storage, read> patch_spheres: array<u32>;
// Blades reset to their rest pose because their new state was non-finite or absurd,
// counted since the start (never cleared); then the collision pushes of this step per cell
// of the propagation grid (`propagate.wgsl`).
@group(0) @binding(7) var<storage, read_write> out: UpdateOut;
// The trail map (`trails.wgsl`): pressed blades of the tile pool write where they stand.
@group(0) @binding(9) var<storage, read_write> trails: array<atomic<u32>>;

fn trail_word(i: u32) -> u32 {
    return atomicLoad(&trails[i]);
}

// A pressed blade of the tile pool (index i, rooted at v0) leaves its trail: the largest
// stamp eta + a t of its texel, and the bend (tip off its rest tip, over the height, x and
// z) of the blade that wrote it. The twin of `trails::write`.
fn trail_write(i: u32, v0: vec3<f32>, eta: f32, bend: vec2<f32>) {
    if !(eta > TRAIL_MIN_ETA) || i >= trail_word(3u) {
        return;
    }
    let w = trail_texel_at(v0.x, v0.z);
    if w == TRAIL_NONE {
        return;
    }
    let s = eta + bitcast<f32>(trail_word(6u)) * bitcast<f32>(trail_word(5u));
    let old = atomicMax(&trails[w], bitcast<u32>(s));
    if bitcast<u32>(s) >= old {
        // The map's largest stamp, the readers' early out where no trail is left: only a
        // texel's new largest can be the map's.
        atomicMax(&trails[TRAIL_MAX_STAMP], bitcast<u32>(s));
        atomicStore(&trails[w + 1u], bitcast<u32>(bend.x));
        atomicStore(&trails[w + 2u], bitcast<u32>(bend.y));
    }
}

// Whether x is a finite number. A bit test, because a compiler may assume that NaN never
// occurs and fold `x == x` away. The twin of `f32::is_finite`.
fn finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

fn finite3(v: vec3<f32>) -> bool {
    return finite(v.x) && finite(v.y) && finite(v.z);
}

fn count_reset() {
    atomicAdd(&out.resets, 1u);
}

// Adds the collision push `d` a blade rooted at v0 received this step to its cell of the
// propagation grid (fixed point, so that the sums do not depend on the atomics' order).
// The twin of `propagation::Splat::add`.
fn splat_push(v0: vec3<f32>, d: vec3<f32>) {
    if params.propagation_info.x == 0u || (d.x == 0.0 && d.z == 0.0) {
        return;
    }
    let c = propagation_cell(v0);
    if c < 0 {
        return;
    }
    let k = 3u * u32(c);
    atomicAdd(&out.splat[k], push_fixed(d.x));
    atomicAdd(&out.splat[k + 1u], push_fixed(d.z));
    atomicAdd(&out.splat[k + 2u], 1);
}

// The level at which a blade's walk of the hierarchy stops (`sim::bvh::depth_limit`).
fn bvh_depth_limit(v0: vec3<f32>, throttled: bool) -> u32 {
    return bvh_limit(distance(v0, params.bvh_camera.xyz), params.bvh_camera.w, params.bvh_info.z, throttled);
}

// The rest pose from the blade's immutable data: the rest tip (straight up when that is not
// finite) through the validation. The twin of `reference::rest_curve`.
fn rest_curve(v0: vec3<f32>, rest: vec3<f32>, up: vec3<f32>, height: f32) -> array<vec3<f32>, 2> {
    var tip = rest;
    if !finite3(tip) {
        tip = v0 + up * height;
    }
    return validate(v0, tip, up, height);
}

// Eq. 4: the environmental gravity on a blade rooted at v0, direction and centre blended by
// t, times the mass. Shared by every blade model; the twin of
// `reference::environmental_gravity`.
fn environmental_gravity(v0: vec3<f32>) -> vec3<f32> {
    let gd = params.gravity_dir;
    let gc = params.gravity_center;
    let to_center = gc.xyz - v0;
    var center_dir = vec3<f32>(0.0);
    if length(to_center) > 1e-6 {
        center_dir = normalize(to_center);
    }
    return params.mass * (gd.xyz * gd.w * (1.0 - params.gravity_blend) + center_dir * gc.w * params.gravity_blend);
}
