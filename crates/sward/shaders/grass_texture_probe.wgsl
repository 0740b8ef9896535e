// Probe: the far grass's texture at a list of points, for the test that compares it with
// its CPU twin (`render::far_texture`). In: world x, z and the footprint (m per pixel).
// Out: the three octaves and the texture.
//!include common.wgsl
//!include grass_texture.wgsl

@group(0) @binding(0) var<storage, read> probe_points: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> probe_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn probe(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&probe_points) {
        return;
    }
    let p = probe_points[i];
    let octaves = grass_octaves(p.xy);
    probe_out[i] = vec4<f32>(octaves, grass_texture(octaves, p.z));
}
