// Probe: the far field's distance gain (`distance_gain`, `next_distance_gain`,
// far_gain_math.wgsl) at a list of points, for the test against their CPU twins
// (`render::far_gain::distance_gain`, `next_distance_gain`). Per point: (distance, reach,
// multiplier, unused); (shown, model, pixels, ring's need); (previous, measurements
// before, blend, unused).
//!include common.wgsl
//!include far_gain_math.wgsl

@group(0) @binding(0) var<storage, read> probe_at: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read> probe_sums: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> probe_prev: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read_write> probe_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn probe(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&probe_out) {
        return;
    }
    let a = probe_at[i];
    let s = probe_sums[i];
    let p = probe_prev[i];
    let g = distance_gain(a.x, a.y, bitcast<u32>(a.z));
    let next = next_distance_gain(s.xyz, s.w, p.x, p.y, p.z);
    probe_out[i] = vec4<f32>(g, next, 0.0, 0.0);
}
