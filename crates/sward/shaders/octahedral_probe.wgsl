// Probe: `octahedral_uv` (octahedral.wgsl), where the deferred light's fog reads the sky's
// table, at a list of directions, for the test against the table's own texel directions
// (tests/deferred.rs).
//!include octahedral.wgsl

@group(0) @binding(0) var<storage, read> probe_in: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> probe_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn probe(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&probe_out) {
        return;
    }
    probe_out[i] = vec4<f32>(octahedral_uv(probe_in[i].xyz), 0.0, 0.0);
}
