// Grass carried by a moving object (`sim::carry`; the twin is `carry::carry_cpu`): one
// invocation per carried blade puts its root, up vector and rest tip where the object is
// now, from their rest values through M(t) = T(t) · T_rest⁻¹ (so they never drift), and
// moves its v1 and v2 with the step's motion M(t) · M(t − Δt)⁻¹ (so the blade keeps its bend
// and its trail). Runs before the patch pass and the update.
//!include common.wgsl

// `CarriedBlade` in Rust: the rest values of one carried blade.
struct CarriedBlade {
    v0: vec3<f32>,
    blade: u32,
    up: vec3<f32>,
    object: u32,
    tip: vec3<f32>,
    pad: u32,
}

// `CarryObject` in Rust: one moving object's motion this step.
struct CarryObject {
    model: mat4x4<f32>,
    step: mat4x4<f32>,
}

@group(0) @binding(0) var<storage, read_write> blades: array<Blade>;
@group(0) @binding(1) var<storage, read_write> states: array<BladeState>;
@group(0) @binding(2) var<storage, read> carried: array<CarriedBlade>;
@group(0) @binding(3) var<storage, read> objects: array<CarryObject>;

@compute @workgroup_size(64)
fn main(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let k = (wid.y * groups.x + wid.x) * 64u + lid;
    if k >= arrayLength(&carried) {
        return;
    }
    let c = carried[k];
    let o = objects[c.object];
    let i = c.blade;
    let b = blades[i];
    let v0 = (o.model * vec4<f32>(c.v0, 1.0)).xyz;
    var up = (o.model * vec4<f32>(c.up, 0.0)).xyz;
    let len = length(up);
    up = select(vec3<f32>(0.0), up / len, len > 0.0);
    let v1 = (o.step * vec4<f32>(b.v1_height.xyz, 1.0)).xyz;
    let v2 = (o.step * vec4<f32>(b.v2_width.xyz, 1.0)).xyz;
    let tip = (o.model * vec4<f32>(c.tip, 1.0)).xyz;
    blades[i].v0_dir = vec4<f32>(v0, b.v0_dir.w);
    blades[i].up_stiffness = vec4<f32>(up, b.up_stiffness.w);
    blades[i].v1_height = vec4<f32>(v1, b.v1_height.w);
    blades[i].v2_width = vec4<f32>(v2, b.v2_width.w);
    states[i].rest_eta = vec4<f32>(tip, states[i].rest_eta.w);
}
