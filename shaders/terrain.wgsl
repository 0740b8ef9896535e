// Terrain: the height-field mesh, lit by the sun and the sky, with a soil/grass colour that
// varies over the ground so that thin grass does not sit on a flat colour.
//!include common.wgsl

@group(0) @binding(0) var<uniform> frame: Frame;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
}

struct VertexOut {
    // Invariant: the depth prepass and the colour pass must produce the same depth.
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
}

@vertex
fn vs_main(in: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = frame.view_proj * vec4<f32>(in.position, 1.0);
    out.world = in.position;
    out.normal = in.normal;
    return out;
}

fn value_noise(p: vec2<f32>) -> f32 {
    let i = floor(p);
    let f = fract(p);
    let s = f * f * (3.0 - 2.0 * f);
    let h = vec4<f32>(
        hash01(u32(i32(i.x) * 73856093 ^ i32(i.y) * 19349663)),
        hash01(u32(i32(i.x + 1.0) * 73856093 ^ i32(i.y) * 19349663)),
        hash01(u32(i32(i.x) * 73856093 ^ i32(i.y + 1.0) * 19349663)),
        hash01(u32(i32(i.x + 1.0) * 73856093 ^ i32(i.y + 1.0) * 19349663)),
    );
    return mix(mix(h.x, h.y, s.x), mix(h.z, h.w, s.x), s.y);
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let sun = frame.sun_dir.xyz;
    let q = in.world.xz;
    let patchy = value_noise(q * 0.35) * 0.6 + value_noise(q * 1.7) * 0.3 + value_noise(q * 7.0) * 0.1;
    let soil = vec3<f32>(0.13, 0.11, 0.06);
    let turf = vec3<f32>(0.06, 0.15, 0.03);
    let albedo = mix(soil, turf, smoothstep(0.15, 0.55, patchy));
    let diffuse = max(dot(n, sun), 0.0);
    var color = albedo * (AMBIENT_COLOR * (0.5 + 0.5 * n.y) + SUN_COLOR * diffuse * 1.5);
    color = apply_fog(color, in.world, frame);
    return vec4<f32>(tonemap(color), 1.0);
}
