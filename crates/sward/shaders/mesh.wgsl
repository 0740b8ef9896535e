// Mesh objects of the scene (`objects`, issue 14): a triangle mesh placed by its model
// matrix, lit like the colliders (ambient from the sky, the sun, a soft highlight), fogged
// and tone-mapped like everything else; also drawn depth-only into the occluder pass.
//!include common.wgsl
//!include light.wgsl

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> object: MeshObject;

struct MeshObject {
    model: mat4x4<f32>,
    // The inverse transpose of the model's upper 3×3 (normals), in the first three columns.
    normal: mat4x4<f32>,
    // Linear RGB albedo, unused.
    color: vec4<f32>,
}

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
    let world = (object.model * vec4<f32>(in.position, 1.0)).xyz;
    var out: VertexOut;
    out.clip = frame.view_proj * vec4<f32>(world, 1.0);
    out.world = world;
    out.normal = (object.normal * vec4<f32>(in.normal, 0.0)).xyz;
    return out;
}

@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var n = normalize(in.normal);
    // An open mesh shows its inside: light that side as seen.
    if !front {
        n = -n;
    }
    let sun = frame.sun_dir.xyz;
    let to_eye = normalize(frame.camera_pos.xyz - in.world);
    let albedo = object.color.rgb;
    let lit = sun_visibility(in.world);
    let diffuse = max(dot(n, sun), 0.0) * lit;
    let h = normalize(sun + to_eye);
    let spec = pow(max(dot(n, h), 0.0), 40.0) * 0.15 * lit;
    var color = albedo * (light.ambient.rgb * (0.5 + 0.5 * n.y) + light.sun.rgb * diffuse * 1.4)
        + light.sun.rgb * spec;
    color = fog(color, in.world);
    return vec4<f32>(color, 1.0);
}
