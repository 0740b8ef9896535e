// Probe: the billboard placement of every cell and the top offset of each card, for the
// test that compares them with the CPU twin (`billboard::place_card`, `top_offset`).
//!include common.wgsl
//!include terrain_height.wgsl
//!include wind.wgsl
//!include billboard_place.wgsl

@group(0) @binding(3) var<uniform> bb: BillboardParams;
@group(0) @binding(6) var<storage, read> spheres: array<vec4<f32>>;
@group(0) @binding(7) var<uniform> params: SimParams;
@group(0) @binding(8) var<storage, read> wind_grid: array<vec2<f32>>;
// Per card: (x, y, z, fade), (variant, scale, mirror, accept), (top offset, level).
@group(0) @binding(10) var<storage, read_write> probe_out: array<vec4<f32>>;
// A trail map (`trails.wgsl`; a zeroed header: none).
@group(0) @binding(11) var<storage, read> trails: array<u32>;

fn trail_word(i: u32) -> u32 {
    return trails[i];
}

//!include wind_sample.wgsl
//!include trails.wgsl
//!include billboard_sway.wgsl

@compute @workgroup_size(64)
fn probe(@builtin(global_invocation_id) id: vec3<u32>) {
    let side = bb.levels.z;
    let i = id.x;
    if i >= bb.levels.x * side * side {
        return;
    }
    let c = card_at(i);
    let h = bb.eye_card.w * c.scale;
    probe_out[i * 3u] = vec4<f32>(c.pos, c.fade);
    probe_out[i * 3u + 1u] = vec4<f32>(f32(c.variant), c.scale, c.mirror, c.accept);
    probe_out[i * 3u + 2u] = vec4<f32>(top_offset(c.pos, h), f32(c.level));
}
