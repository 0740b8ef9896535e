// Probe: `div_small` (common.wgsl) at a list of (a, b), for the test against integer
// division (tests/div_small.rs).
//!include common.wgsl

@group(0) @binding(0) var<storage, read> probe_in: array<vec4<u32>>;
@group(0) @binding(1) var<storage, read_write> probe_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn probe(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&probe_out) {
        return;
    }
    let p = probe_in[i];
    // Quotients below 2^23 are exact in f32.
    probe_out[i] = vec4<f32>(f32(div_small(p.x, p.y)), 0.0, 0.0, 0.0);
}
