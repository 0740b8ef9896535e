// Tone mapping after the 3D passes (issue 16): the passes draw linear radiance into the
// half-float scene target (`render::post::HDR_FORMAT`), MSAA resolves it, and this one
// full-screen triangle applies the scene's exposure and filmic curve (`tonemap` in
// light.wgsl: ACES, AgX or a clamp) on the way to the 8-bit output.
//
// Alpha tells radiance from display colour: every lit pass leaves alpha 1 (the deferred
// grass more, `BLADE_ALPHA` in grass_vis.wgsl: the share of the pixel its blades cover),
// the window's arrows (whose colour must keep the strength ramp's exact hue) write alpha 0,
// and an anti-aliased edge between them mixes the two.

//!include common.wgsl
//!include light.wgsl

// Declared for light.wgsl's fog and shadow helpers; tone mapping reads neither.
@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var hdr: texture_2d<f32>;

@vertex
fn vs_tonemap(@builtin(vertex_index) vid: u32) -> @builtin(position) vec4<f32> {
    let xy = vec2<f32>(f32((vid << 1u) & 2u), f32(vid & 2u)) * 2.0 - 1.0;
    return vec4<f32>(xy, 0.0, 1.0);
}

@fragment
fn fs_tonemap(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let c = textureLoad(hdr, vec2<i32>(pixel.xy), 0);
    let radiance = clamp(c.a, 0.0, 1.0);
    return vec4<f32>(mix(c.rgb, tonemap(c.rgb), radiance), 1.0);
}
