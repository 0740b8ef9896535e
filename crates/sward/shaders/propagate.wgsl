// Grass-to-grass propagation (Qiu et al. §5.2, Eq. 4) over the grid of cells around the
// camera, after the update: `init` makes the pushed cells ancestors (generation 0, the
// mean push as the force vector), each `generation` dispatch adds the children of one more
// generation, and `apply` pushes the Jahrmann blades of every child cell by its force. The
// twin is `sim::propagation` (its module comment has the whole model).
//!include common.wgsl
//!include blade_pose.wgsl

@group(0) @binding(0) var<uniform> params: SimParams;
// The update's output: the reset counter, then per cell the pushes' x, z and count.
@group(0) @binding(1) var<storage, read_write> out: UpdateOut;
// Per cell: EF.x, EF.z, the generation (UNREACHED: none), unused.
@group(0) @binding(2) var<storage, read_write> field: array<vec4<f32>>;
// x: the generation this dispatch adds (`generation`).
@group(0) @binding(3) var<uniform> step: vec4<u32>;
@group(0) @binding(4) var<storage, read_write> blades: array<Blade>;
@group(0) @binding(5) var<storage, read_write> states: array<BladeState>;
@group(0) @binding(6) var<storage, read> patch_lists: array<u32>;

//!include update_slot.wgsl

const UNREACHED: f32 = -1.0;

fn cells() -> u32 {
    return params.propagation_info.x * params.propagation_info.x;
}

fn cell_index(gid: vec3<u32>, groups: vec3<u32>) -> u32 {
    return gid.y * groups.x * 64u + gid.x;
}

@compute @workgroup_size(64)
fn init(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let c = cell_index(gid, groups);
    if c >= cells() {
        return;
    }
    let count = atomicLoad(&out.splat[3u * c + 2u]);
    if count > 0 {
        let n = f32(count);
        let fx = f32(atomicLoad(&out.splat[3u * c])) / n / 1.0e6;
        let fz = f32(atomicLoad(&out.splat[3u * c + 1u])) / n / 1.0e6;
        field[c] = vec4<f32>(fx, fz, 0.0, 0.0);
    } else {
        field[c] = vec4<f32>(0.0, 0.0, UNREACHED, 0.0);
    }
}

// Whether cell (i, j) holds an active child of generation `prev` (|EF| > L); its force.
fn active_parent(i: i32, j: i32, prev: f32) -> vec4<f32> {
    let n = i32(params.propagation_info.x);
    if i < 0 || j < 0 || i >= n || j >= n {
        return vec4<f32>(0.0, 0.0, UNREACHED, 0.0);
    }
    let f = field[u32(j * n + i)];
    let threshold = bitcast<f32>(params.propagation_info.z);
    if f.z == prev && sqrt(f.x * f.x + f.y * f.y) > threshold {
        return f;
    }
    return vec4<f32>(0.0, 0.0, UNREACHED, 0.0);
}

// Generation g: an unreached cell gathers att times the part of each active adjacent
// parent's force that points at it (Eq. 4 with EF_origin = 0). Only cells of generation
// g - 1 are read and only unreached ones written, so one buffer serves.
@compute @workgroup_size(64)
fn generation(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let c = cell_index(gid, groups);
    if c >= cells() || field[c].z != UNREACHED {
        return;
    }
    let n = params.propagation_info.x;
    let i = i32(c % n);
    let j = i32(c / n);
    let prev = f32(step.x - 1u);
    let att = params.propagation.w;
    var fx = 0.0;
    var fz = 0.0;
    var reached = false;
    let left = active_parent(i - 1, j, prev);
    if left.z != UNREACHED && left.x > 0.0 {
        fx += left.x * att;
        reached = true;
    }
    let right = active_parent(i + 1, j, prev);
    if right.z != UNREACHED && right.x < 0.0 {
        fx += right.x * att;
        reached = true;
    }
    let down = active_parent(i, j - 1, prev);
    if down.z != UNREACHED && down.y > 0.0 {
        fz += down.y * att;
        reached = true;
    }
    let up = active_parent(i, j + 1, prev);
    if up.z != UNREACHED && up.y < 0.0 {
        fz += up.y * att;
        reached = true;
    }
    if reached {
        field[c] = vec4<f32>(fx, fz, f32(step.x), 0.0);
    }
}

// The blades of a child cell pushed by its force, as by a collider (Jahrmann's blades).
@compute @workgroup_size(64)
fn apply(
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
    let c = propagation_cell(v0);
    if c < 0 {
        return;
    }
    let f = field[u32(c)];
    if f.z < 1.0 || (f.x == 0.0 && f.y == 0.0) {
        return;
    }
    let up = blade.up_stiffness.xyz;
    var d = vec3<f32>(f.x, 0.0, f.y);
    d = d - up * dot(d, up);
    let v = validate(v0, blade.v2_width.xyz + d, up, height);
    var eta = states[i].rest_eta.w + params.collision_gain * dot(d, d);
    eta = select(eta, params.max_eta, eta > params.max_eta);
    blades[i].v1_height = vec4<f32>(v[0], height);
    blades[i].v2_width = vec4<f32>(v[1], blade.v2_width.w);
    states[i].rest_eta.w = eta;
}
