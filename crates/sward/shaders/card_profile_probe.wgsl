// Probe: the cards' height profile (`card_profile.wgsl`) at a list of cases, for the test
// against its CPU twin (`render::billboard::atlas::profile_at`, `profile_luma`). Each case
// is 13 vec4s: the profile's upper and lower bands, (y, 0, 0, 0), a row band (colour and
// four facings), the sky's light and the four facings' sun (rgb).
//!include common.wgsl
//!include card_profile.wgsl

@group(0) @binding(0) var<storage, read> probe_in: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> probe_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn probe(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&probe_out) {
        return;
    }
    let b = i * 13u;
    let at = profile_at(probe_in[b], probe_in[b + 1u], probe_in[b + 2u].x);
    let row = ProfileRow(probe_in[b + 3u], array<vec4<f32>, 4>(probe_in[b + 4u], probe_in[b + 5u], probe_in[b + 6u], probe_in[b + 7u]));
    let sun = array<vec3<f32>, 4>(probe_in[b + 9u].rgb, probe_in[b + 10u].rgb, probe_in[b + 11u].rgb, probe_in[b + 12u].rgb);
    probe_out[i] = vec4<f32>(at, profile_luma(row, probe_in[b + 8u].rgb, sun), 0.0, 0.0);
}
