// Blade update, one invocation per blade of each patch on the update list the patch pass
// wrote (Jahrmann & Wimmer Eq. 1-16 and the state validation Eq. 9-13), dispatched
// indirectly. Throttled patches step with the longer Δt. The twin of
// `reference::update_blade`.
//!include update_common.wgsl
//!include collide_walk.wgsl

// Most collide + validate rounds per step.
const COLLISION_ROUNDS: u32 = 4u;

// Whether this pipeline collides: the update list of patches with no collider near is
// stepped by a pipeline without the collision rounds (a software adapter runs them for
// every blade, however few touch a sphere).
override COLLIDE: bool = true;

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

// What the collision walk pushes: v2 (through itself and the curve midpoint) of the blade
// (v0, v1, v2), and the collision strength added.
struct Contact {
    v0: vec3<f32>,
    v1: vec3<f32>,
    v2: vec3<f32>,
    added: f32,
}

// Pointers are passed to whole variables only (WGSL without unrestricted pointer
// parameters): the fields go through locals.
fn push_sphere(c: vec3<f32>, r: f32, contact: ptr<function, Contact>) {
    var v2 = (*contact).v2;
    var added = (*contact).added;
    push_out(c, r, (*contact).v0, (*contact).v1, &v2, &added);
    (*contact).v2 = v2;
    (*contact).added = added;
}

// Eq. 14-16 against the colliders the patch can touch (`collide_walk.wgsl`). Returns the
// new v2 and the added collision strength.
fn collide(v0: vec3<f32>, v1: vec3<f32>, v2: vec3<f32>, patch_id: u32, height: f32, limit: u32) -> vec4<f32> {
    var contact = Contact(v0, v1, v2, 0.0);
    collide_listed(patch_id, v0, height, limit, &contact);
    return vec4<f32>(contact.v2, contact.added);
}

@compute @workgroup_size(64)
fn main(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let slot = blade_slot(wid, groups, lid);
    if !slot.ok {
        return;
    }
    let i = slot.i;
    let patch_id = slot.patch_id;
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
    let dt = select(params.dt, params.throttled_dt, slot.throttled);
    let front = blade_frame(up, angle)[1];

    // Eq. 3: recovery, weakened while the blade is crippled by collisions.
    let recovery = (rest - v2) * stiffness * max(1.0 - eta, 0.1);
    // Eq. 4: environmental gravity, direction and centre blended by t.
    let g_env = environmental_gravity(v0);
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
    // The push the colliders gave the tip: the propagation's ancestors.
    var pushed = vec3<f32>(0.0);
    if COLLIDE && params.collisions != 0u {
        let limit = bvh_depth_limit(v0, slot.coarse);
        for (var round = 0u; round < COLLISION_ROUNDS; round++) {
            let c = collide(v0, corrected[0], corrected[1], patch_id, height, limit);
            if c.w <= 0.0 {
                break;
            }
            eta += c.w;
            pushed += c.xyz - corrected[1];
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
        pushed = vec3<f32>(0.0);
        count_reset();
    }
    splat_push(v0, pushed);
    trail_write(i, v0, eta, (corrected[1].xz - rest.xz) / height);
    blades[i].v1_height = vec4<f32>(corrected[0], height);
    blades[i].v2_width = vec4<f32>(corrected[1], blade.v2_width.w);
    states[i].rest_eta.w = eta;
}
