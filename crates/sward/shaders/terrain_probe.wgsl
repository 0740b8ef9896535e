// Probe: the terrain height function at a list of points, for the test that compares it
// with the CPU's HeightField (every GPU kernel has a CPU twin). Out: height, d/dx, d/dz.
//!include terrain_height.wgsl

@group(0) @binding(3) var<storage, read> probe_points: array<vec2<f32>>;
@group(0) @binding(4) var<storage, read_write> probe_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn probe(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&probe_points) {
        return;
    }
    probe_out[i] = vec4<f32>(terrain_height(probe_points[i]), 0.0);
}
