// CWD-Sim's blades (`physics.model: Cwd`) keep no state between frames: the grass vertex
// shader bends every vertex from the wind of the blade's cell (`cwd.wgsl`). This pass only
// tells the culling where the bent blade is: it writes the quadratic through the root,
// the bent blade's middle and its tip into v1 and v2, from this frame's wind alone (no
// collisions, no trails: η stays 0). The twin is `sim::cwd::pose_all`.
//!include update_common.wgsl
//!include cwd.wgsl

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
    let wind = cwd_wind(v0, height);
    let mid = cwd_point(v0, up, front, height, wind, 0.5).p;
    let tip = cwd_point(v0, up, front, height, wind, 1.0).p;
    var v1 = 2.0 * mid - 0.5 * (v0 + tip);
    var v2 = tip;
    // A wind beyond any range (the scene bounds it) falls back to the upright blade.
    if !(finite3(v1) && finite3(v2)) {
        v1 = v0 + up * (0.5 * height);
        v2 = v0 + up * height;
        count_reset();
    }
    blades[i].v1_height = vec4<f32>(v1, height);
    blades[i].v2_width = vec4<f32>(v2, blade.v2_width.w);
    states[i].rest_eta.w = 0.0;
}
