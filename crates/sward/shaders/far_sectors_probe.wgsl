// Probe: the sectors' arithmetic (far_sectors.wgsl), for the test against its CPU twin
// (`render::far_sectors`). In: per point a horizontal direction (xy) and the two state
// words its sectors would hold (zw, as floats); then the state: a frame's 32 sums, the 16
// previous multipliers (four vec4) and (measurements before, blend). Out: per point (a,
// b, t, the multiplier there), then the next multipliers (four vec4).
//!include common.wgsl
//!include far_gain_math.wgsl

@group(0) @binding(0) var<storage, read> probe_points: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read> probe_state: array<vec4<f32>, 37>;
@group(0) @binding(2) var<storage, read_write> probe_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn probe(@builtin(global_invocation_id) id: vec3<u32>) {
    let points = arrayLength(&probe_out) - 4u;
    let i = id.x;
    if i < points {
        let p = probe_points[i];
        let pair = sector_pair(p.xy);
        let g = sector_gain(pair, bitcast<u32>(p.z), bitcast<u32>(p.w));
        probe_out[i] = vec4<f32>(f32(pair.a), f32(pair.b), pair.t, g);
    }
    if i != 0u {
        return;
    }
    var sums: array<vec4<f32>, SECTOR_SUMS>;
    for (var k = 0u; k < SECTOR_SUMS; k++) {
        sums[k] = probe_state[k];
    }
    var previous: array<f32, SECTORS>;
    for (var k = 0u; k < SECTORS; k++) {
        previous[k] = probe_state[SECTOR_SUMS + k / 4u][k % 4u];
    }
    let last = probe_state[SECTOR_SUMS + 4u];
    let next = next_sectors(sums, previous, last.x, last.y);
    for (var k = 0u; k < 4u; k++) {
        probe_out[points + k] = vec4<f32>(next[4u * k], next[4u * k + 1u], next[4u * k + 2u], next[4u * k + 3u]);
    }
}
