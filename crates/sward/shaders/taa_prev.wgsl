// TAA's copy of the blades' control points before this frame's update moves them
// (`render/taa`): one invocation per blade slot, 48 of the blade's 64 bytes. Timed and
// counted with the TAA pass.
//!include common.wgsl

@group(0) @binding(0) var<storage, read> blades: array<Blade>;
@group(0) @binding(1) var<storage, read_write> prev: array<PrevBlade>;

// Invocations per workgroup (twin: `taa::COPY_GROUP`); the dispatch folds rows of at most
// 65,535 workgroups into y.
const COPY_GROUP: u32 = 256u;

@compute @workgroup_size(256)
fn copy_prev(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = id.x + id.y * groups.x * COPY_GROUP;
    if i >= arrayLength(&blades) {
        return;
    }
    let b = blades[i];
    prev[i] = PrevBlade(b.v0_dir, b.v1_height, b.v2_width);
}
