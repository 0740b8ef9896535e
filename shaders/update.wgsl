// Blade update, one invocation per blade of each patch on the update list the patch pass
// wrote (Jahrmann & Wimmer Eq. 1-16 and the state validation Eq. 9-13), dispatched
// indirectly. Throttled patches step with the longer Δt. The twin of
// `reference::update_blade`.
//!include common.wgsl
//!include wind.wgsl
//!include blade_pose.wgsl
//!include wind_sample.wgsl
//!include bvh_node.wgsl

// Most collide + validate rounds per step.
const COLLISION_ROUNDS: u32 = 4u;

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
// node, ...].
@group(0) @binding(6) var<storage, read> patch_spheres: array<u32>;
// Blades reset to their rest pose because their new state was non-finite or absurd,
// counted since the start (never cleared).
@group(0) @binding(7) var<storage, read_write> resets: atomic<u32>;

const THROTTLED: u32 = 0x80000000u;

// Whether x is a finite number. A bit test, because a compiler may assume that NaN never
// occurs and fold `x == x` away. The twin of `f32::is_finite`.
fn finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

fn finite3(v: vec3<f32>) -> bool {
    return finite(v.x) && finite(v.y) && finite(v.z);
}

// Whether a blade's new state is sound: every value finite and the curve's length (Eq. 12)
// within half a height of the height (the validation makes it equal; only overflow, e.g.
// from an absurd force, breaks that). The twin of `reference::state_sound`.
fn state_sound(v0: vec3<f32>, v1: vec3<f32>, v2: vec3<f32>, height: f32, eta: f32) -> bool {
    if !(finite3(v1) && finite3(v2) && finite(eta)) {
        return false;
    }
    let len = (2.0 * length(v2 - v0) + length(v1 - v0) + length(v2 - v1)) / 3.0;
    return abs(len - height) <= 0.5 * height;
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

// Eq. 14-16 for one sphere (c, r): against v2 and against the curve midpoint m (the push
// on m moves v2 four times as far); adds to v2 and to the collision strength.
fn push_out(c: vec3<f32>, r: f32, v0: vec3<f32>, v1: vec3<f32>, v2: ptr<function, vec3<f32>>, added: ptr<function, f32>) {
    let to_c = c - *v2;
    let dist = length(to_c);
    if dist < r && dist > 1e-6 {
        let d = (dist - r) * to_c / dist;
        *v2 += d;
        *added += params.collision_gain * dot(d, d);
    }
    let m = 0.25 * v0 + 0.5 * v1 + 0.25 * *v2;
    let to_cm = c - m;
    let distm = length(to_cm);
    if distm < r && distm > 1e-6 {
        let d = (distm - r) * to_cm / distm;
        *v2 += 4.0 * d;
        *added += params.collision_gain * dot(d, d);
    }
}

// The level at which a blade's walk of the hierarchy stops (`sim::bvh::depth_limit`).
fn bvh_depth_limit(v0: vec3<f32>, throttled: bool) -> u32 {
    return bvh_limit(distance(v0, params.bvh_camera.xyz), params.bvh_camera.w, params.bvh_info.z, throttled);
}

// The spheres the blade can reach under node `start`, walking the hierarchy depth first
// (left child first) down to `limit`, where a node's bounding sphere stands in for those
// under it (a loose node never does). `acc`: v2 and the strength added so far (a walk goes
// on from the last one's result); `stack`: the caller's, so that it is set up once per
// blade rather than once per listed node.
fn collide_bvh(start: u32, v0: vec3<f32>, v1: vec3<f32>, acc: vec4<f32>, height: f32, limit: u32, stack: ptr<function, array<u32, BVH_STACK>>) -> vec4<f32> {
    var v2 = acc.xyz;
    var added = acc.w;
    var top = 1u;
    (*stack)[0] = start;
    while top > 0u {
        top -= 1u;
        let node = bvh_node((*stack)[top]);
        let c = node.sphere.xyz;
        let r = node.sphere.w;
        // Out of the blade's reach: neither the tip nor the midpoint can be inside.
        if distance(c, v0) >= r + height {
            continue;
        }
        if node.link.z < BVH_LOOSE {
            let s = spheres[node.link.z];
            push_out(s.xyz, s.w, v0, v1, &v2, &added);
        } else if node.link.z == BVH_INTERNAL && node.link.w >= limit {
            push_out(c, r, v0, v1, &v2, &added);
        } else if top + 2u <= BVH_STACK {
            // Right below left, so that the left child is walked first.
            (*stack)[top] = node.link.y;
            (*stack)[top + 1u] = node.link.x;
            top += 2u;
        }
    }
    return vec4<f32>(v2, added);
}

// Eq. 14-16: the spheres on the patch's broad-phase list (in index order, like the CPU twin
// that tests all of them), or, when the hierarchy is on, the walk under each node on the
// patch's list (the broad phase's cut of the tree, in the order a walk from the root meets
// them, so that the pushes come as the twin's walk from the root makes them; from the root
// when the list overflowed). Returns the new v2 and the added collision strength.
fn collide(v0: vec3<f32>, v1: vec3<f32>, v2_in: vec3<f32>, patch_id: u32, height: f32, limit: u32) -> vec4<f32> {
    let base = patch_id * PATCH_SPHERE_STRIDE;
    let listed = patch_spheres[base];
    if params.bvh_info.x != 0u && params.bvh_info.y > 0u {
        var stack: array<u32, BVH_STACK>;
        if listed == SPHERES_ALL {
            return collide_bvh(0u, v0, v1, vec4<f32>(v2_in, 0.0), height, limit, &stack);
        }
        var v2 = v2_in;
        var added = 0.0;
        for (var k = 0u; k < listed; k++) {
            let node = bvh_node(patch_spheres[base + 1u + k]);
            if node.link.z < BVH_LOOSE {
                // A listed collider: pushed at once, as the walk would.
                let s = spheres[node.link.z];
                push_out(s.xyz, s.w, v0, v1, &v2, &added);
            } else {
                let c = collide_bvh(patch_spheres[base + 1u + k], v0, v1, vec4<f32>(v2, added), height, limit, &stack);
                v2 = c.xyz;
                added = c.w;
            }
        }
        return vec4<f32>(v2, added);
    }
    var v2 = v2_in;
    var added = 0.0;
    let all = listed == SPHERES_ALL;
    let n = select(listed, params.sphere_count, all);
    for (var k = 0u; k < n; k++) {
        let sphere = spheres[select(patch_spheres[base + 1u + k], k, all)];
        push_out(sphere.xyz, sphere.w, v0, v1, &v2, &added);
    }
    return vec4<f32>(v2, added);
}

@compute @workgroup_size(64)
fn main(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let per_patch = params.patch_size / 64u;
    let flat = wid.y * groups.x + wid.x;
    let slot = flat / per_patch;
    let list = params.patch_count + 1u;
    if slot >= patch_lists[list] {
        return;
    }
    let entry = patch_lists[list + 1u + slot];
    let patch_id = entry & ~THROTTLED;
    let i = patch_id * params.patch_size + (flat % per_patch) * 64u + lid;
    if i >= params.blade_count {
        return;
    }
    let blade = blades[i];
    let v0 = blade.v0_dir.xyz;
    let angle = blade.v0_dir.w;
    let height = blade.v1_height.w;
    // A blade the tile generation removed (density map, terrain edge): nothing to step.
    if height <= 0.0 {
        return;
    }
    var v2 = blade.v2_width.xyz;
    let up = blade.up_stiffness.xyz;
    let stiffness = blade.up_stiffness.w * params.stiffness_scale;
    let rest = states[i].rest_eta.xyz;
    var eta = states[i].rest_eta.w;
    let dt = select(params.dt, params.throttled_dt, (entry & THROTTLED) != 0u);
    let front = blade_frame(up, angle)[1];

    // Eq. 3: recovery, weakened while the blade is crippled by collisions.
    let recovery = (rest - v2) * stiffness * max(1.0 - eta, 0.1);
    // Eq. 4: environmental gravity, direction and centre blended by t.
    let gd = params.gravity_dir;
    let gc = params.gravity_center;
    let to_center = gc.xyz - v0;
    var center_dir = vec3<f32>(0.0);
    if length(to_center) > 1e-6 {
        center_dir = normalize(to_center);
    }
    let g_env = params.mass * (gd.xyz * gd.w * (1.0 - params.gravity_blend) + center_dir * gc.w * params.gravity_blend);
    // Eq. 5-6: front gravity.
    let gravity = g_env + 0.25 * length(g_env) * front;
    // Eq. 7-8: wind scaled by the alignment theta.
    // The fluid at the blade's own height: in a 3D grid tall grass reaches faster air.
    let wi = wind_at(v0, height);
    var wind = vec3<f32>(0.0);
    let wl = length(wi);
    let tip = v2 - v0;
    let tl = length(tip);
    if wl > 1e-6 && tl > 1e-6 {
        let fd = 1.0 - abs(dot(wi / wl, tip / tl));
        let fr = dot(tip, up) / height;
        wind = wi * (fd * fr);
    }
    // Eq. 1, the collision displacement follows below.
    v2 += (recovery + gravity + wind) * dt;
    // Eq. 2: the collision strength fades. The unclamped value joins the soundness test:
    // max() may swallow a NaN differently on every GPU.
    let decayed = eta - params.collision_decay * dt;
    eta = max(decayed, 0.0);

    // Validate first so that the midpoint m of the collision test is that of a valid curve
    // (v1 follows v2), then collide; the length correction after a push can pull a point
    // back into the sphere, so collide + validate repeats until nothing is pushed.
    var corrected = validate(v0, v2, up, height);
    if params.collisions != 0u {
        let limit = bvh_depth_limit(v0, (entry & THROTTLED) != 0u);
        for (var round = 0u; round < COLLISION_ROUNDS; round++) {
            let c = collide(v0, corrected[0], corrected[1], patch_id, height, limit);
            if c.w <= 0.0 {
                break;
            }
            eta += c.w;
            corrected = validate(v0, c.xyz, up, height);
        }
    }
    // A non-finite or absurd state is never kept: the blade starts over from its rest
    // pose, and the reset is counted. Tested before the ceiling, which is a comparison and
    // not min(): min() and max() may swallow a NaN differently on every GPU.
    let sound = finite(decayed) && state_sound(v0, corrected[0], corrected[1], height, eta);
    eta = select(eta, params.max_eta, eta > params.max_eta);
    if !sound {
        corrected = rest_curve(v0, rest, up, height);
        eta = 0.0;
        atomicAdd(&resets, 1u);
    }
    blades[i].v1_height = vec4<f32>(corrected[0], height);
    blades[i].v2_width = vec4<f32>(corrected[1], blade.v2_width.w);
    states[i].rest_eta.w = eta;
}
