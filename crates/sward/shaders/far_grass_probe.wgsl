// Probe: the far grass's light (`far_grass_facings`, far_grass.wgsl) at a list of points,
// under the frame's uniforms and the light's group, for the test that compares it with its
// CPU twin (`render::far_light`). In per point: position and mean wave, the ground's
// normal, the albedo. Out per point: the sky's part, then the sun's part of each facing.
//!include common.wgsl
//!include light.wgsl
//!include blade_shade.wgsl
//!include far_grass.wgsl

struct ProbePoint {
    p_wave: vec4<f32>,
    normal: vec4<f32>,
    albedo: vec4<f32>,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> probe_points: array<ProbePoint>;
@group(0) @binding(2) var<storage, read_write> probe_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn probe(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&probe_points) {
        return;
    }
    let q = probe_points[i];
    let f = far_grass_facings(q.p_wave.xyz, q.normal.xyz, q.albedo.rgb, q.p_wave.w);
    probe_out[5u * i] = vec4<f32>(f.ambient, 0.0);
    for (var j = 0u; j < 4u; j++) {
        probe_out[5u * i + 1u + j] = vec4<f32>(f.sun[j], 0.0);
    }
}
