// Per-blade culling (Jahrmann & Wimmer Section 6.2): the patch box against the frustum,
// then orientation (Eq. 17), view frustum on v0 / m / v2 (Eq. 18) and distance levels
// (Eq. 19-20). Survivors append their index to `visible` and bump the indirect instance
// count; every culled blade bumps the counter of the test that culled it.
// The twin of `reference::cull_blade`.
//!include common.wgsl

// draw_indexed_indirect arguments followed by the cull counters (CullCounters in Rust).
struct DrawArgs {
    index_count: u32,
    instance_count: atomic<u32>,
    first_index: u32,
    base_vertex: i32,
    first_instance: u32,
    culled_patch: atomic<u32>,
    culled_orientation: atomic<u32>,
    culled_frustum: atomic<u32>,
    culled_distance: atomic<u32>,
    pad: array<u32, 7>,
}

const TEST_PATCH: u32 = 1u;
const TEST_ORIENTATION: u32 = 2u;
const TEST_FRUSTUM: u32 = 4u;
const TEST_DISTANCE: u32 = 8u;

@group(0) @binding(0) var<uniform> params: CullParams;
@group(0) @binding(1) var<storage, read> blades: array<Blade>;
@group(0) @binding(2) var<storage, read> patches: array<PatchBox>;
@group(0) @binding(3) var<storage, read_write> visible: array<u32>;
@group(0) @binding(4) var<storage, read_write> args: DrawArgs;

// Clears the counters and writes the constant draw arguments; one invocation per frame,
// dispatched before `main` in the same pass.
@compute @workgroup_size(1)
fn reset() {
    args.index_count = params.index_count;
    atomicStore(&args.instance_count, 0u);
    args.first_index = 0u;
    args.base_vertex = 0;
    args.first_instance = 0u;
    atomicStore(&args.culled_patch, 0u);
    atomicStore(&args.culled_orientation, 0u);
    atomicStore(&args.culled_frustum, 0u);
    atomicStore(&args.culled_distance, 0u);
}

fn in_frustum(p: vec3<f32>) -> bool {
    let c = params.view_proj * vec4<f32>(p, 1.0);
    let h = c.w + params.frustum_tolerance;
    return c.x >= -h && c.x <= h && c.y >= -h && c.y <= h && c.z >= -h && c.z <= h;
}

// The box against the six frustum planes of view_proj (Gribb-Hartmann): the corner furthest
// along each plane normal must be on the inner side.
fn box_in_frustum(bmin: vec3<f32>, bmax: vec3<f32>) -> bool {
    let m = transpose(params.view_proj);
    let planes = array<vec4<f32>, 6>(
        m[3] + m[0], m[3] - m[0], m[3] + m[1], m[3] - m[1], m[2], m[3] - m[2]
    );
    for (var k = 0u; k < 6u; k++) {
        let p = planes[k];
        let corner = select(bmin, bmax, p.xyz >= vec3<f32>(0.0));
        if dot(p.xyz, corner) + p.w < 0.0 {
            return false;
        }
    }
    return true;
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.blade_count {
        return;
    }
    // Patches are a multiple of the workgroup size, so the whole workgroup tests one box.
    if (params.tests & TEST_PATCH) != 0u {
        let pbox = patches[i / params.patch_size];
        if !box_in_frustum(pbox.min.xyz, pbox.max.xyz) {
            atomicAdd(&args.culled_patch, 1u);
            return;
        }
    }
    let blade = blades[i];
    let v0 = blade.v0_dir.xyz;
    let v1 = blade.v1_height.xyz;
    let v2 = blade.v2_width.xyz;
    let up = blade.up_stiffness.xyz;
    let camera = params.camera_pos.xyz;
    if (params.tests & TEST_ORIENTATION) != 0u {
        let width_dir = blade_frame(up, blade.v0_dir.w)[0];
        let to_blade = v0 - camera;
        var view_dir = vec3<f32>(0.0);
        if length(to_blade) > 0.0 {
            view_dir = normalize(to_blade);
        }
        if abs(dot(view_dir, width_dir)) > params.orientation_threshold {
            atomicAdd(&args.culled_orientation, 1u);
            return;
        }
    }
    if (params.tests & TEST_FRUSTUM) != 0u {
        let m = 0.25 * v0 + 0.5 * v1 + 0.25 * v2;
        if !in_frustum(v0) && !in_frustum(m) && !in_frustum(v2) {
            atomicAdd(&args.culled_frustum, 1u);
            return;
        }
    }
    // Eq. 20 as printed culls when `id mod n < floor(n (1 - d/d_max))`, which would cull
    // everything near the camera; the text says the nearest level culls nothing and each
    // further level one more blade in n, so a blade is kept when `id mod n` is below that.
    if (params.tests & TEST_DISTANCE) != 0u {
        let rel = v0 - camera;
        let d_proj = length(rel - up * dot(rel, up));
        let n = max(params.distance_levels, 1u);
        let keep = floor(f32(n) * (1.0 - d_proj / params.max_distance));
        if f32(i % n) >= keep {
            atomicAdd(&args.culled_distance, 1u);
            return;
        }
    }
    let slot = atomicAdd(&args.instance_count, 1u);
    visible[slot] = i;
}
