// Upscale: the 3D passes' image, drawn at a lower resolution when the frame budget asks for
// it, stretched over the window with bilinear filtering (one full-screen triangle). The
// CPU twin is `render::upscale::upscale_cpu`.

@group(0) @binding(0) var image: texture_2d<f32>;
@group(0) @binding(1) var linear: sampler;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
}

@vertex
fn vs_upscale(@builtin(vertex_index) vid: u32) -> VertexOut {
    let xy = vec2<f32>(f32((vid << 1u) & 2u), f32(vid & 2u)) * 2.0 - 1.0;
    var out: VertexOut;
    out.clip = vec4<f32>(xy, 0.0, 1.0);
    // Texture space has y down.
    out.uv = vec2<f32>(xy.x * 0.5 + 0.5, 0.5 - xy.y * 0.5);
    return out;
}

@fragment
fn fs_upscale(in: VertexOut) -> @location(0) vec4<f32> {
    return vec4<f32>(textureSampleLevel(image, linear, in.uv, 0.0).rgb, 1.0);
}
