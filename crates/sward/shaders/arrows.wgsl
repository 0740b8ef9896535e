// AGC guide arrows and points (src/render/arrows.rs): a CPU-built triangle mesh with face
// normals and colours, lit with Lambert + ambient so that shafts, heads and octahedra read
// as solids. No fog or tonemapping: the colour must stay the strength ramp's exact hue, so
// alpha 0 tells the tone-mapping pass (`tonemap.wgsl`) that it is a display colour.

struct ArrowUniforms {
    view_proj: mat4x4<f32>,
    // xyz: unit direction towards the sun; w: ambient light (fraction of full light).
    light: vec4<f32>,
}

@group(0) @binding(0) var<uniform> u: ArrowUniforms;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
}

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) color: vec4<f32>,
}

@vertex
fn vs_main(in: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = u.view_proj * vec4<f32>(in.position, 1.0);
    out.normal = in.normal;
    out.color = in.color;
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let ambient = u.light.w;
    let shade = ambient + (1.0 - ambient) * max(dot(n, u.light.xyz), 0.0);
    return vec4<f32>(in.color.rgb * shade, 0.0);
}
