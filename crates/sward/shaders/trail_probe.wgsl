// Probe: the far ground's trail (`trail_wave_smooth`) at a list of points, for the test that
// compares it with its CPU twin (`field::trails::wave_smooth`). In: world x, z. Out: the
// wave there, and the trail at the point itself (`trail_at`: eta, bend x, bend z).
//!include common.wgsl

@group(0) @binding(0) var<storage, read> trails: array<u32>;
@group(0) @binding(1) var<storage, read> probe_points: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> probe_out: array<vec4<f32>>;

fn trail_word(i: u32) -> u32 {
    return trails[i];
}
//!include trails.wgsl

@compute @workgroup_size(64)
fn probe(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&probe_points) {
        return;
    }
    let p = probe_points[i].xy;
    let t = trail_at(p.x, p.y);
    probe_out[i] = vec4<f32>(trail_wave_smooth(p.x, p.y), t);
}
