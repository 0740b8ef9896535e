// Probe: the thinning's widening and root (`thinning_widen_at`, `thinned_root_at`,
// thinning.wgsl) at a list of (distance, reach, distance levels, the cards' radius), for the test against
// their CPU twins (`render::thinning`).
//!include thinning.wgsl

@group(0) @binding(0) var<storage, read> probe_in: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> probe_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn probe(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&probe_out) {
        return;
    }
    let p = probe_in[i];
    probe_out[i] = vec4<f32>(thinning_widen_at(p.x, p.y, p.z), thinned_root_at(p.x, p.y, p.z, p.w), 0.0, 0.0);
}
