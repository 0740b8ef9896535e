// Sphere colliders: a unit sphere mesh instanced once per collider, placed and scaled from
// the same sphere buffer the blade update reads.
//!include common.wgsl
//!include light.wgsl

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> spheres: array<vec4<f32>>;

struct VertexIn {
    @location(0) position: vec3<f32>,
}

struct VertexOut {
    // Invariant: the depth prepass and the colour pass must produce the same depth.
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) local: vec3<f32>,
}

@vertex
fn vs_main(in: VertexIn, @builtin(instance_index) inst: u32) -> VertexOut {
    let s = spheres[inst];
    let world = s.xyz + in.position * s.w;
    var out: VertexOut;
    out.clip = frame.view_proj * vec4<f32>(world, 1.0);
    out.world = world;
    out.normal = in.position;
    out.local = in.position;
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let sun = frame.sun_dir.xyz;
    let to_eye = normalize(frame.camera_pos.xyz - in.world);
    // A beach-ball band so that the sphere reads as a ball, not a blob.
    let band = step(0.5, fract(atan2(in.local.z, in.local.x) / TAU * 4.0));
    let albedo = mix(vec3<f32>(0.75, 0.12, 0.08), vec3<f32>(0.85, 0.8, 0.7), band);
    let lit = sun_visibility(in.world);
    let diffuse = max(dot(n, sun), 0.0) * lit;
    let h = normalize(sun + to_eye);
    let spec = pow(max(dot(n, h), 0.0), 60.0) * 0.5 * lit;
    var color = albedo * (light.ambient.rgb * (0.5 + 0.5 * n.y) + light.sun.rgb * diffuse * 1.4) + light.sun.rgb * spec;
    color = fog(color, in.world);
    return vec4<f32>(color, 1.0);
}
