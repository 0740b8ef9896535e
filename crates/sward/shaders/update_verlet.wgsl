// The Verlet blade of Zhang's prairie thesis (§3.2), one invocation per blade of each
// patch on the update list: a cubic Bézier whose control points P1..P3 are integrated
// with Verlet (Eq. 7) from the wind at each point and gravity, kept above the ground, and
// pulled back to segments of a third of the height from the root up (the shape
// constraint, §3.2.4); then pushed out of the colliders, with η trails as for Jahrmann's
// blade. The twin of `sim::verlet::step`.
//
// Forces: Jahrmann's at each point (recovery towards the rest chain, weakened by η;
// gravity Eq. 4; the wind at the point), times the stiffness s to make an acceleration, so
// that the blade rests where Jahrmann's rests and sways at ω = s. Point k's recovery is
// 3/k times as stiff (the root segment stiffest, as along a cantilever), so a steady push
// bends the blade into a curve rather than kinking it at the root. The thesis has no
// recovery (nothing brings its blades back) and no damping; sward adds both.
// Verlet with a varying Δt (frames and throttled patches differ) scales the last
// displacement by Δt / Δt_prev. Stiff blades take sub-steps so that √3 s Δt <= 0.5.
//!include update_common.wgsl
//!include collide_walk.wgsl

@group(0) @binding(8) var<storage, read_write> verlet: array<VerletState>;

const COLLISION_ROUNDS: u32 = 4u;

// Whether this pipeline collides: the update list of patches with no collider near is
// stepped by a pipeline without the collision rounds (a software adapter runs them for
// every blade, however few touch a sphere).
override COLLIDE: bool = true;
const MAX_SUBSTEPS: u32 = 8u;

// The backbone's control points P0 (the root) .. P3 (the tip).
alias Chain = array<vec3<f32>, 4>;

// The shape constraint (§3.2.4) from the root up: each point pulled along its segment to
// `l` from the one below; a segment that would end below the root's ground plane is laid
// flat at the height of the point below instead (the thesis mirrors y with abs()).
fn constrain(p: ptr<function, Chain>, up: vec3<f32>, front: vec3<f32>, l: f32) {
    let v0 = (*p)[0];
    for (var i = 1u; i < 4u; i++) {
        let below = (*p)[i - 1u];
        var d = (*p)[i] - below;
        let len = length(d);
        if len < 1e-6 {
            d = up;
        } else {
            d = d / len;
        }
        var q = below + d * l;
        if dot(q - v0, up) < 0.0 {
            var flat = d - up * dot(d, up);
            if length(flat) < 1e-6 {
                flat = front;
            }
            q = below + normalize(flat) * l;
        }
        (*p)[i] = q;
    }
}

// The rest chain: the rest quadratic raised to a cubic (P1 = v0 + 2/3 (v1 - v0),
// P2 = v2 + 2/3 (v1 - v2), P3 = v2), then constrained.
fn rest_chain(v0: vec3<f32>, up: vec3<f32>, front: vec3<f32>, rest: array<vec3<f32>, 2>, height: f32) -> Chain {
    let v1 = rest[0];
    let v2 = rest[1];
    var c = Chain(v0, v0 + (2.0 / 3.0) * (v1 - v0), v2 + (2.0 / 3.0) * (v1 - v2), v2);
    constrain(&c, up, front, height / 3.0);
    return c;
}

// What the collision walk pushes: the three free control points.
struct Contact {
    p1: vec3<f32>,
    p2: vec3<f32>,
    p3: vec3<f32>,
    added: f32,
}

fn push_point(c: vec3<f32>, r: f32, p: ptr<function, vec3<f32>>, added: ptr<function, f32>) {
    let to_c = c - *p;
    let dist = length(to_c);
    if dist < r && dist > 1e-6 {
        let d = (dist - r) * to_c / dist;
        *p += d;
        *added += params.collision_gain * dot(d, d);
    }
}

// Pointers are passed to whole variables only (WGSL without unrestricted pointer
// parameters): the fields go through locals.
fn push_sphere(c: vec3<f32>, r: f32, contact: ptr<function, Contact>) {
    var p1 = (*contact).p1;
    var p2 = (*contact).p2;
    var p3 = (*contact).p3;
    var added = (*contact).added;
    push_point(c, r, &p1, &added);
    push_point(c, r, &p2, &added);
    push_point(c, r, &p3, &added);
    *contact = Contact(p1, p2, p3, added);
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
    let blade = blades[i];
    let height = blade.v1_height.w;
    if height <= 0.0 {
        return;
    }
    let v0 = blade.v0_dir.xyz;
    let up = blade.up_stiffness.xyz;
    let front = blade_frame(up, blade.v0_dir.w)[1];
    let s = blade.up_stiffness.w * params.stiffness_scale;
    var eta = states[i].rest_eta.w;
    let dt = select(params.dt, params.throttled_dt, slot.throttled);
    let l = height / 3.0;
    let rest = rest_chain(v0, up, front, rest_curve(v0, states[i].rest_eta.xyz, up, height), height);

    let st = verlet[i];
    var p = Chain(v0, blade.v1_height.xyz, st.p2_dt.xyz, blade.v2_width.xyz);
    var o = Chain(v0, st.o1_x.xyz, st.o2_y.xyz, st.o3_z.xyz);
    var dt_prev = st.p2_dt.w;
    let moved = v0 - vec3<f32>(st.o1_x.w, st.o2_y.w, st.o3_z.w);
    if !(dt_prev > 0.0) || length(moved) > 0.5 * height {
        // A new blade (the first step, or a tile generated into this slot): at rest.
        p = rest;
        o = rest;
        dt_prev = dt;
    } else if any(moved != vec3<f32>(0.0)) {
        // Carried by a moving object: the carry pass moved P1 and P3; P2 and the previous
        // positions follow the root.
        p[2] += moved;
        o[1] += moved;
        o[2] += moved;
        o[3] += moved;
    }

    // Eq. 4: environmental gravity, as Jahrmann's.
    let g_env = environmental_gravity(v0);
    // The wind at each control point, at its own height (§3.2.2), read once per step.
    var w = Chain(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0));
    for (var k = 1u; k < 4u; k++) {
        w[k] = wind_at(p[k], max(dot(p[k] - v0, up), 0.0)) * params.model.w;
    }
    let weak = max(1.0 - eta, 0.1);
    // A paused step (Δt = 0) moves nothing and keeps the last Δt.
    let n = select(0u, clamp(u32(ceil(s * sqrt(3.0) * dt / 0.5)), 1u, MAX_SUBSTEPS), dt > 0.0);
    let hs = dt / f32(max(n, 1u));
    let damp = exp(-params.model.y * hs);
    for (var step = 0u; step < n; step++) {
        let ratio = hs / dt_prev;
        let reach = 0.5 * hs * (hs + dt_prev);
        for (var k = 1u; k < 4u; k++) {
            let a = s * (s * (3.0 / f32(k)) * (rest[k] - p[k]) * weak + g_env + w[k]);
            let next = p[k] + (p[k] - o[k]) * (ratio * damp) + a * reach;
            o[k] = p[k];
            p[k] = next - up * min(dot(next - v0, up), 0.0);
        }
        dt_prev = hs;
        constrain(&p, up, front, l);
    }
    let decayed = eta - params.collision_decay * dt;
    eta = max(decayed, 0.0);
    var pushed = vec3<f32>(0.0);
    if COLLIDE && params.collisions != 0u {
        let limit = bvh_depth_limit(v0, slot.coarse);
        for (var round = 0u; round < COLLISION_ROUNDS; round++) {
            var contact = Contact(p[1], p[2], p[3], 0.0);
            collide_listed(slot.patch_id, v0, height, limit, &contact);
            if contact.added <= 0.0 {
                break;
            }
            eta += contact.added;
            pushed += contact.p3 - p[3];
            p[1] = contact.p1;
            p[2] = contact.p2;
            p[3] = contact.p3;
            constrain(&p, up, front, l);
        }
    }
    // A non-finite state is never kept: the blade starts over at rest.
    let sound = finite(decayed) && finite(eta) && finite3(p[1]) && finite3(p[2]) && finite3(p[3])
        && finite3(o[1]) && finite3(o[2]) && finite3(o[3]);
    eta = select(eta, params.max_eta, eta > params.max_eta);
    if !sound {
        p = rest;
        o = rest;
        eta = 0.0;
        pushed = vec3<f32>(0.0);
        count_reset();
    }
    splat_push(v0, pushed);
    trail_write(i, v0, eta, (p[3].xz - rest[3].xz) / height);
    blades[i].v1_height = vec4<f32>(p[1], height);
    blades[i].v2_width = vec4<f32>(p[3], blade.v2_width.w);
    states[i].rest_eta.w = eta;
    verlet[i] = VerletState(vec4<f32>(p[2], dt_prev), vec4<f32>(o[1], v0.x), vec4<f32>(o[2], v0.y), vec4<f32>(o[3], v0.z));
}
