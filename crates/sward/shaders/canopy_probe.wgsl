// Probe: the canopy's handover and cells (canopy.wgsl) at a list of points, for the test
// that compares them with their CPU twins (`render::far_canopy`). In: per point a ground
// point (xyz) and an eye (xyz; w 1: the far ground's weight, else the cards'). Out: the
// weight, the cell's layer and turn, and the point's place in its cell (x, z over
// CANOPY_SIDE) turned as the cell turns it.
//!include common.wgsl
//!include canopy.wgsl

@group(0) @binding(0) var<storage, read> probe_points: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read> probe_eyes: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> probe_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn probe(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&probe_points) {
        return;
    }
    let p = probe_points[i].xyz;
    let cell = canopy_variant(p.xz);
    let uv = canopy_turn(fract(p.xz / CANOPY_SIDE), cell.y, 1.0);
    let eye = probe_eyes[i];
    let w = select(canopy_weight(p, eye.xyz), canopy_ground_weight(p, eye.xyz), eye.w > 0.5);
    probe_out[i] = vec4<f32>(w, f32(cell.x * 8u + cell.y), uv);
}
