// Which blade an invocation of a per-blade pass over the update list steps, and the
// propagation grid's cells: shared by the update passes and the propagation's apply.
// Expects `params: SimParams` and `patch_lists` bound by the including shader.

const THROTTLED: u32 = 0x80000000u;

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

// The blade an invocation steps: one per blade of each patch on the update list the patch
// pass wrote. `ok` is false past the list's end or the field's.
struct Slot {
    i: u32,
    patch_id: u32,
    throttled: bool,
    ok: bool,
}

fn blade_slot(wid: vec3<u32>, groups: vec3<u32>, lid: u32) -> Slot {
    var s = Slot(0u, 0u, false, false);
    let per_patch = params.patch_size / 64u;
    let flat = wid.y * groups.x + wid.x;
    let slot = flat / per_patch;
    let list = params.patch_count + 1u;
    if slot >= patch_lists[list] {
        return s;
    }
    let entry = patch_lists[list + 1u + slot];
    s.patch_id = entry & ~THROTTLED;
    s.throttled = (entry & THROTTLED) != 0u;
    s.i = s.patch_id * params.patch_size + (flat % per_patch) * 64u + lid;
    s.ok = s.i < params.blade_count;
    return s;
}

