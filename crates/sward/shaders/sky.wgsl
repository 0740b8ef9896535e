// Sky: one full-screen triangle drawn last, behind everything; the view ray of each pixel comes from the
// inverse view-projection, the colour from `sky_with_sun` (light.wgsl: Preetham's sky, whose
// `sky_radiance` the fog shares).
//!include common.wgsl
//!include light.wgsl

@group(0) @binding(0) var<uniform> frame: Frame;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) ndc: vec2<f32>,
}

@vertex
fn vs_main(@builtin(vertex_index) vid: u32) -> VertexOut {
    let xy = vec2<f32>(f32((vid << 1u) & 2u), f32(vid & 2u)) * 2.0 - 1.0;
    var out: VertexOut;
    // At the far plane, drawn last: only pixels nothing else covered pass the depth test.
    out.clip = vec4<f32>(xy, 1.0, 1.0);
    out.ndc = xy;
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let far = frame.inv_view_proj * vec4<f32>(in.ndc, 1.0, 1.0);
    let dir = normalize(far.xyz / far.w - frame.camera_pos.xyz);
    return vec4<f32>(sky_with_sun(dir), 1.0);
}
