// Probe: the cards' contrast curve (`contrast_luma`, far_gain_math.wgsl) at a list of
// (luminance, card mean, contrast gain), for the test against its CPU twin
// (`render::far_gain::contrast_luma`).
//!include common.wgsl
//!include far_gain_math.wgsl

@group(0) @binding(0) var<storage, read> probe_in: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> probe_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn probe(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&probe_out) {
        return;
    }
    let p = probe_in[i];
    probe_out[i] = vec4<f32>(contrast_luma(p.x, p.y, p.z), 0.0, 0.0, 0.0);
}
