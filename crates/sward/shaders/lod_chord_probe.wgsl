// Probe: the coarse levels' v (`chord_shape`, `chord_v`, `lod_v`, lod_chord.wgsl) at a
// list of (s, a, c, root), for the test against their CPU twins (`render::lod_chord`): the
// last two with one segment of shape a and with two of shapes a and c.
//!include lod_chord.wgsl

@group(0) @binding(0) var<storage, read> probe_in: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> probe_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn probe(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&probe_out) {
        return;
    }
    let p = probe_in[i];
    let one = lod_v(p.x, vec2<f32>(chord_code_one(p.y), p.w));
    let two = lod_v(p.x, vec2<f32>(chord_code_two(p.y, p.z), p.w));
    probe_out[i] = vec4<f32>(chord_v(p.x, p.y), chord_shape(p.z), one, two);
}
