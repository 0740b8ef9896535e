// Blade update, one invocation per blade, every frame (Jahrmann & Wimmer Eq. 1-16 and the
// state validation Eq. 9-13). The twin of `reference::update_blade`.
//!include common.wgsl
//!include wind.wgsl

// Most collide + validate rounds per step.
const COLLISION_ROUNDS: u32 = 4u;

@group(0) @binding(0) var<uniform> params: SimParams;
@group(0) @binding(1) var<storage, read_write> blades: array<Blade>;
@group(0) @binding(2) var<storage, read_write> states: array<BladeState>;
@group(0) @binding(3) var<storage, read> spheres: array<vec4<f32>>;

// Eq. 9-13: v2 above the local ground plane, v1 from v2, curve length = height.
fn validate(v0: vec3<f32>, v2_in: vec3<f32>, up: vec3<f32>, height: f32) -> array<vec3<f32>, 2> {
    let v2 = v2_in - up * min(dot(up, v2_in - v0), 0.0);
    let rel = v2 - v0;
    let l_proj = length(rel - up * dot(rel, up));
    let v1 = v0 + up * height * max(1.0 - l_proj / height, 0.05 * max(l_proj / height, 1.0));
    let l0 = length(v2 - v0);
    let l1 = length(v1 - v0) + length(v2 - v1);
    let len = (2.0 * l0 + l1) / 3.0;
    let r = height / len;
    let v1c = v0 + r * (v1 - v0);
    let v2c = v1c + r * (v2 - v1);
    return array<vec3<f32>, 2>(v1c, v2c);
}

// Eq. 14-16: every sphere against v2 and against the curve midpoint m (the push on m moves
// v2 four times as far). Returns the new v2 and the added collision strength.
fn collide(v0: vec3<f32>, v1: vec3<f32>, v2_in: vec3<f32>) -> vec4<f32> {
    var v2 = v2_in;
    var added = 0.0;
    for (var s = 0u; s < params.sphere_count; s++) {
        let sphere = spheres[s];
        let c = sphere.xyz;
        let r = sphere.w;
        let to_c = c - v2;
        let dist = length(to_c);
        if dist < r && dist > 1e-6 {
            let d = (dist - r) * to_c / dist;
            v2 += d;
            added += params.collision_gain * dot(d, d);
        }
        let m = 0.25 * v0 + 0.5 * v1 + 0.25 * v2;
        let to_cm = c - m;
        let distm = length(to_cm);
        if distm < r && distm > 1e-6 {
            let d = (distm - r) * to_cm / distm;
            v2 += 4.0 * d;
            added += params.collision_gain * dot(d, d);
        }
    }
    return vec4<f32>(v2, added);
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.blade_count {
        return;
    }
    let blade = blades[i];
    let v0 = blade.v0_dir.xyz;
    let angle = blade.v0_dir.w;
    let height = blade.v1_height.w;
    var v2 = blade.v2_width.xyz;
    let up = blade.up_stiffness.xyz;
    let stiffness = blade.up_stiffness.w;
    let rest = states[i].rest_eta.xyz;
    var eta = states[i].rest_eta.w;
    let dt = params.dt;
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
    let wi = analytic_wind(v0, params.time, params);
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
    // Eq. 2: the collision strength fades.
    eta = max(eta - params.collision_decay * dt, 0.0);

    // Validate first so that the midpoint m of the collision test is that of a valid curve
    // (v1 follows v2), then collide; the length correction after a push can pull a point
    // back into the sphere, so collide + validate repeats until nothing is pushed.
    var corrected = validate(v0, v2, up, height);
    if params.collisions != 0u {
        for (var round = 0u; round < COLLISION_ROUNDS; round++) {
            let c = collide(v0, corrected[0], corrected[1]);
            if c.w <= 0.0 {
                break;
            }
            eta += c.w;
            corrected = validate(v0, c.xyz, up, height);
        }
    }
    eta = min(eta, params.max_eta);
    blades[i].v1_height = vec4<f32>(corrected[0], height);
    blades[i].v2_width = vec4<f32>(corrected[1], blade.v2_width.w);
    states[i].rest_eta.w = eta;
}
