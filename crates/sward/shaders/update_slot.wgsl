// Which blade an invocation of a per-blade pass over the update list steps, and the
// propagation grid's cells: shared by the update passes and the propagation's apply.
// Expects `params: SimParams` and `patch_lists` bound by the including shader.

//!include thin_order.wgsl

// An update list entry's rate bits (`cull.wgsl`): a throttled patch's chunk, and a
// thinned chunk of a patch stepped every frame (both step every `physics_throttle` frames).
const THROTTLED: u32 = 0x80000000u;
const THINNED: u32 = 0x40000000u;

// Which update list a pipeline steps (`cull.wgsl`): 0 the chunks of patches with a collider
// near, 1 those without (their pipeline leaves the collisions out).
override UPDATE_LIST: u32 = 0u;

// The update's output beside the reset counter: per propagation cell the pushes' x and z
// (fixed point, micrometres) and their count.
struct UpdateOut {
    resets: atomic<u32>,
    pad0: u32,
    pad1: u32,
    pad2: u32,
    splat: array<atomic<i32>>,
}

// The fixed-point value of one component of a push, clamped to +-1 m
// (`propagation::fixed`).
fn push_fixed(x: f32) -> i32 {
    return i32(floor(clamp(x, -1.0, 1.0) * 1.0e6 + 0.5));
}

// The propagation cell of a blade rooted at v0, or -1 outside the grid
// (`propagation::GridSpec::cell_of`).
fn propagation_cell(v0: vec3<f32>) -> i32 {
    let n = params.propagation_info.x;
    let g = floor((v0.xz - params.propagation.xy) / params.propagation.z);
    let nf = f32(n);
    if g.x < 0.0 || g.y < 0.0 || g.x >= nf || g.y >= nf {
        return -1;
    }
    return i32(u32(g.y) * n + u32(g.x));
}

// The blade an invocation steps: one per blade of each chunk on the update list the patch
// pass wrote (an entry is the chunk's number over the field, patch * (patch_size / CHUNK)
// + its chunk in the patch, and its rate bits), its blades in class order
// (`thin_order.wgsl`). `ok` is false past the list's end or the field's.
struct Slot {
    i: u32,
    patch_id: u32,
    // Stepped at the throttled rate, with the longer Δt.
    throttled: bool,
    // The whole patch is throttled: its broad phase and the blades' walks stop a level
    // sooner. A thinned chunk of a patch stepped every frame walks as its patch does.
    coarse: bool,
    ok: bool,
}

fn blade_slot(wid: vec3<u32>, groups: vec3<u32>, lid: u32) -> Slot {
    var s = Slot(0u, 0u, false, false, false);
    let per_patch = params.patch_size / CHUNK;
    let flat = wid.y * groups.x + wid.x;
    let list = (params.patch_count * per_patch + 1u) * (1u + UPDATE_LIST);
    if flat >= patch_lists[list] {
        return s;
    }
    let entry = patch_lists[list + 1u + flat];
    let chunk = entry & ~(THROTTLED | THINNED);
    s.patch_id = chunk / per_patch;
    s.throttled = (entry & (THROTTLED | THINNED)) != 0u;
    s.coarse = (entry & THROTTLED) != 0u;
    let pos = (chunk % per_patch) * CHUNK + lid;
    let n = max(params.distance_levels, 1u);
    s.i = s.patch_id * params.patch_size + order_blade(pos, params.patch_size, n);
    s.ok = s.i < params.blade_count;
    return s;
}
