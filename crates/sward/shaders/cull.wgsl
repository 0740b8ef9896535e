// Culling on the GPU (Jahrmann & Wimmer Section 6.2), in two steps like the paper, and a
// third for grass hidden by grass:
//
// 1. `reset`, `patches`, `finalize` (one pass, before the update): every patch box is tested
//    against the frustum and the depth pyramid of the opaque objects; survivors go to the
//    visible-patch list. Patches in view or near the camera, and every `physics_throttle`-th
//    other patch in turn, go to the update list, in chunks of 64 blades in class order
//    (`thin_order.wgsl`): a patch in view steps the chunks of classes Eq. 20 may keep
//    every frame and the others (thinned everywhere in the patch) in turn, on one of two
//    lists by whether a collider is near it. `finalize` lists the visible patches' chunks
//    in patch order and turns the counts into the indirect dispatches of the two updates
//    and of step 2.
// 2. `main` (indirect, over visible patches only): every blade of a visible patch is tested
//    (but the classes Eq. 20 culls everywhere in the patch, culled by distance in step 1)
//    for orientation (Eq. 17), frustum on v0 / m / v2 (Eq. 18), distance levels (Eq. 19-20)
//    and occlusion (v0 / m / v2 against the depth pyramid with a bias). Survivors are sorted
//    by projected height into three level-of-detail lists, each drawn by its own indirect
//    draw, in a fixed order (`cull_order.wgsl`). Every culled blade bumps the counter of
//    the test that culled it.
// 3. `late` (with TEST_GRASS_OCCLUSION; after the early draw): two-phase occlusion
//    culling. Step 2 draws only the survivors that were seen last frame and marks the
//    others candidates; `late` tests the candidates on v0 / m / v2 against the depth, which
//    now holds the grass drawn early (level 0 of the pyramid, the only level a blade's test
//    reads: with one sample the depth buffer itself, multisampled its farthest samples,
//    rebuilt by `DepthPyramid::encode_base`), and draws those it does not hide. It also
//    re-tests the early blades, so that next frame's early set is what is visible now.
//    Nothing is culled on old information: a blade hidden now by grass drawn now. The twin is `reference::grass_hidden`.
// The twins are `reference::cull_patch` and `reference::cull_blade`.
//!include common.wgsl
//!include bvh_node.wgsl
//!include thin_order.wgsl
//!include cull_broad_phase.wgsl
//!include cull_order.wgsl

struct DrawArgs {
    index_count: u32,
    instance_count: atomic<u32>,
    first_index: u32,
    base_vertex: i32,
    first_instance: u32,
}

// CullCounters in Rust.
struct CullOutput {
    draws: array<DrawArgs, 3>,
    late_draws: array<DrawArgs, 3>,
    visible_patches: atomic<u32>,
    updated_patches: atomic<u32>,
    throttled_patches: atomic<u32>,
    culled_patch: atomic<u32>,
    culled_orientation: atomic<u32>,
    culled_frustum: atomic<u32>,
    culled_distance: atomic<u32>,
    culled_occlusion: atomic<u32>,
    culled_occlusion_patch: atomic<u32>,
    patch_sphere_pairs: atomic<u32>,
    culled_occlusion_grass: atomic<u32>,
    // Blades in each level's early and late lists; the draws' instance counts are these
    // in whole batches of DRAW_BATCH.
    blades: array<atomic<u32>, 3>,
    late_blades: array<atomic<u32>, 3>,
    // Entries of the broad phase's shared pool taken this frame.
    pool_used: atomic<u32>,
    spheres_used: array<atomic<u32>, SPHERE_WORDS>,
    // The gusts' bend at the edge of the blades' reach (`CullCounters::wave_sum`).
    wave_sum: atomic<u32>,
    wave_blades: atomic<u32>,
    // Update list entries (chunks of CHUNK blades) this frame, and of those the ones
    // stepped at the throttled rate (a throttled patch's, or thinned in a patch in view).
    updated_chunks: atomic<u32>,
    throttled_chunks: atomic<u32>,
    // Chunks on the blade cull's list (of visible patches, less the thinned classes).
    visible_chunks: atomic<u32>,
    // Of the update's chunks, those on the colliding list (their patch's broad phase
    // found something) and on the free list (it found nothing): the slots of each.
    collide_chunks: atomic<u32>,
    free_chunks: atomic<u32>,
}

// PatchDispatch in Rust: four dispatch_workgroups_indirect argument blocks (the blade
// cull, the update with collisions, the update without, the lists' order).
struct PatchDispatch {
    cull_x: u32,
    cull_y: u32,
    cull_z: u32,
    update_x: u32,
    update_y: u32,
    update_z: u32,
    free_x: u32,
    free_y: u32,
    free_z: u32,
    order_x: u32,
    order_y: u32,
    order_z: u32,
}

const TEST_PATCH: u32 = 1u;
const TEST_ORIENTATION: u32 = 2u;
// `field::clumps::STEM_WIDTH`: the width that marks a flower's stem.
const FLOWER_STEM_WIDTH: f32 = 0.006;
const TEST_FRUSTUM: u32 = 4u;
const TEST_DISTANCE: u32 = 8u;
const TEST_OCCLUSION: u32 = 16u;
const TEST_GRASS_OCCLUSION: u32 = 32u;
// No blade for this invocation.
const NO_BLADE: u32 = 0xffffffffu;
// An update list entry's rate bits: a throttled patch's chunk, and a thinned chunk of a
// patch stepped every frame (both step with the longer Δt; `update_slot.wgsl`).
const THROTTLED: u32 = 0x80000000u;
const THINNED: u32 = 0x40000000u;
// Largest workgroup count per dimension every adapter allows.
const MAX_GROUPS: u32 = 65535u;

// Read-only storage, not a uniform: lavapipe (Mesa 22.3) would recompile the cull with
// these parameters inlined at every dispatch and keep every copy (see grass.wgsl).
@group(0) @binding(0) var<storage, read> params: CullParams;
@group(0) @binding(1) var<storage, read> blades: array<Blade>;
@group(0) @binding(2) var<storage, read> patches: array<PatchBox>;
// Three regions of `region` slots, one per level of detail.
@group(0) @binding(3) var<storage, read_write> visible: array<u32>;
@group(0) @binding(4) var<storage, read_write> out: CullOutput;
// Three lists of patch_count * patch_size / CHUNK + 1 slots: [count, chunk, ...], the chunks
// of CHUNK blades (in class order) of the patches that passed the patch tests that the
// blade cull tests; then twice [count, chunk | rate bits, ...], the chunks the update
// steps, of patches with a collider near and without.
@group(0) @binding(5) var<storage, read_write> patch_lists: array<u32>;
// Max-depth pyramid of the opaque objects: levels 1 and up (mip k is level k + 1), and
// level 0, the depth buffer itself (with MSAA its farthest sample per pixel).
@group(0) @binding(7) var hiz: texture_2d<f32>;
@group(0) @binding(8) var hiz0: texture_2d<f32>;

// Texel `p` of pyramid level `level`.
fn hiz_texel(p: vec2<i32>, level: u32) -> f32 {
    if level == 0u {
        return textureLoad(hiz0, p, 0).r;
    }
    return textureLoad(hiz, p, i32(level) - 1).r;
}
// Written by the patch step only (the blade cull reads `dispatch` as its indirect
// argument, which may not be bound at the same time).
@group(1) @binding(0) var<storage, read_write> dispatch: PatchDispatch;
// The colliders, then their hierarchy's nodes from BVH_NODE_BASE (`bvh_node.wgsl`).
@group(1) @binding(1) var<storage, read> spheres: array<vec4<f32>>;
// Collision broad phase: per patch [count or SPHERES_ALL, sphere or (with the hierarchy)
// node, ...].
@group(1) @binding(2) var<storage, read_write> patch_spheres: array<u32>;
// The blade passes' second group: one SEEN_* word per blade.
@group(1) @binding(3) var<storage, read_write> seen: array<u32>;
// The blades' rest tips (the blade passes' group 1): how far the gusts bend them.
@group(1) @binding(4) var<storage, read> states: array<BladeState>;

// Where the update's lists start, each after the one before, of patch_count * patch_size /
// CHUNK + 1 slots (the blade cull's list first): `free` the list of chunks whose patch
// has no collider near (`update_slot.wgsl`).
fn update_list(free: bool) -> u32 {
    return (params.patch_count * (params.patch_size / CHUNK) + 1u) * (1u + u32(free));
}

// Slots per level-of-detail list.
fn region() -> u32 {
    return arrayLength(&visible) / 3u;
}

// Clears the counters and writes the constant draw arguments; one invocation per frame.
@compute @workgroup_size(1)
fn reset() {
    for (var k = 0u; k < 3u; k++) {
        out.draws[k].index_count = params.lod_index_count[k];
        atomicStore(&out.draws[k].instance_count, 0u);
        out.draws[k].first_index = params.lod_first_index[k];
        out.draws[k].base_vertex = 0;
        // With multi-draw, level k's instances (batches) start at its region; otherwise
        // each level binds its region at an offset and counts from 0.
        out.draws[k].first_instance = k * params.lod_index_count.w / DRAW_BATCH;
        // The late draws start after the early ones; `late` sets where.
        out.late_draws[k].index_count = params.lod_index_count[k];
        atomicStore(&out.late_draws[k].instance_count, 0u);
        out.late_draws[k].first_index = params.lod_first_index[k];
        out.late_draws[k].base_vertex = 0;
        out.late_draws[k].first_instance = k * params.lod_index_count.w / DRAW_BATCH;
        atomicStore(&out.blades[k], 0u);
        atomicStore(&out.late_blades[k], 0u);
    }
    atomicStore(&out.visible_patches, 0u);
    atomicStore(&out.updated_patches, 0u);
    atomicStore(&out.throttled_patches, 0u);
    atomicStore(&out.updated_chunks, 0u);
    atomicStore(&out.throttled_chunks, 0u);
    atomicStore(&out.visible_chunks, 0u);
    atomicStore(&out.collide_chunks, 0u);
    atomicStore(&out.free_chunks, 0u);
    atomicStore(&out.culled_patch, 0u);
    atomicStore(&out.culled_orientation, 0u);
    atomicStore(&out.culled_frustum, 0u);
    atomicStore(&out.culled_distance, 0u);
    atomicStore(&out.culled_occlusion, 0u);
    atomicStore(&out.culled_occlusion_patch, 0u);
    atomicStore(&out.patch_sphere_pairs, 0u);
    atomicStore(&out.culled_occlusion_grass, 0u);
    atomicStore(&out.pool_used, 0u);
    atomicStore(&out.wave_sum, 0u);
    atomicStore(&out.wave_blades, 0u);
    for (var w = 0u; w < SPHERE_WORDS; w++) {
        atomicStore(&out.spheres_used[w], 0u);
    }
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

// View distance of a depth-buffer value (perspective, depth 0 at near, 1 at far).
fn occluder_distance(d: f32) -> f32 {
    let n = params.clip.x;
    let f = params.clip.y;
    return n * f / max(f - d * (f - n), 1e-6);
}

// Whether something lies in front of a point at view distance `z` by more than `bias` (a
// fraction of z), given the farthest depth `d` over the pixels that cover it.
fn behind(z: f32, d: f32, bias: f32) -> bool {
    return z - occluder_distance(d) > bias * z;
}

fn to_pixel(ndc: vec2<f32>) -> vec2<i32> {
    let size = vec2<f32>(params.hiz.xy);
    let px = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * size;
    return clamp(vec2<i32>(floor(px)), vec2<i32>(0), vec2<i32>(params.hiz.xy) - 1);
}

// A point is occluded when it projects inside the screen, in front of the camera, and
// behind the depth at its pixel by more than `bias`.
fn point_occluded(p: vec3<f32>, bias: f32) -> bool {
    let c = params.view_proj * vec4<f32>(p, 1.0);
    if c.w <= params.clip.x {
        return false;
    }
    let ndc = c.xy / c.w;
    if any(abs(ndc) > vec2<f32>(1.0)) {
        return false;
    }
    let d = textureLoad(hiz0, to_pixel(ndc), 0).r;
    return behind(c.w, d, bias);
}

// The blade test of both occlusion passes (twin: `reference::blade_occluded`): v0, the
// curve's midpoint m and v2 all behind the depth by more than `bias`.
fn blade_occluded(v0: vec3<f32>, m: vec3<f32>, v2: vec3<f32>, bias: f32) -> bool {
    return point_occluded(v0, bias) && point_occluded(m, bias) && point_occluded(v2, bias);
}

// The box's screen rectangle against the pyramid level where it spans at most 2 x 2
// texels; occluded when its nearest corner is behind the farthest depth there.
fn box_occluded(bmin: vec3<f32>, bmax: vec3<f32>) -> bool {
    var lo = vec2<f32>(1e30);
    var hi = vec2<f32>(-1e30);
    var z_near = 1e30;
    for (var k = 0u; k < 8u; k++) {
        let corner = select(bmin, bmax, vec3<bool>((k & 1u) != 0u, (k & 2u) != 0u, (k & 4u) != 0u));
        let c = params.view_proj * vec4<f32>(corner, 1.0);
        if c.w <= params.clip.x {
            return false;
        }
        let ndc = c.xy / c.w;
        lo = min(lo, ndc);
        hi = max(hi, ndc);
        z_near = min(z_near, c.w);
    }
    if hi.x < -1.0 || lo.x > 1.0 || hi.y < -1.0 || lo.y > 1.0 {
        return false;
    }
    // Screen y runs down: the top-left pixel comes from (lo.x, hi.y).
    let p0 = to_pixel(vec2<f32>(lo.x, hi.y));
    let p1 = to_pixel(vec2<f32>(hi.x, lo.y));
    var level = 0u;
    let top = params.hiz.z - 1u;
    loop {
        let a = p0 >> vec2<u32>(level);
        let b = p1 >> vec2<u32>(level);
        if level >= top || (b.x - a.x <= 1 && b.y - a.y <= 1) {
            break;
        }
        level++;
    }
    let last = max(vec2<i32>(params.hiz.xy) >> vec2<u32>(level), vec2<i32>(1)) - 1;
    let a = min(p0 >> vec2<u32>(level), last);
    let b = min(p1 >> vec2<u32>(level), last);
    var d = 0.0;
    for (var y = a.y; y <= b.y; y++) {
        for (var x = a.x; x <= b.x; x++) {
            d = max(d, hiz_texel(vec2<i32>(x, y), level));
        }
    }
    return behind(z_near, d, params.occlusion_bias);
}

// Blades in patch `p` (the last patch may be short).
fn patch_blades(p: u32) -> u32 {
    return min(params.patch_size, params.blade_count - p * params.patch_size);
}

// A lower bound on the distance test's d_proj over every blade of the box (twin:
// `reference::patch_least_distance`). A blade's test measures d_proj, the camera's offset
// from its root across its up vector: |rel x up|. With up leaning at most to up.y = c (the
// box's max.w) and s = sqrt(1 - c^2), the horizontal part of rel x up alone gives
// d_proj >= c H - s |y|, H the horizontal and y the vertical offset. Over the box, H is at
// least the camera's distance to its (x, z) rectangle and |y| at most the camera's height
// span to it.
fn patch_least_distance(bmin: vec3<f32>, bmax: vec3<f32>, up_y: f32) -> f32 {
    let c = params.camera_pos.xyz;
    let dh = max(max(bmin.xz - c.xz, c.xz - bmax.xz), vec2<f32>(0.0));
    let h = length(dh);
    let y = max(abs(c.y - bmin.y), abs(c.y - bmax.y));
    let cos_up = clamp(up_y, 0.0, 1.0);
    let sin_up = sqrt(max(1.0 - cos_up * cos_up, 0.0));
    return cos_up * h - sin_up * y;
}

// Whether every blade of the box is beyond the distance test's reach, culled by Eq. 20
// (twin: `reference::patch_beyond_distance`).
fn patch_beyond_distance(bmin: vec3<f32>, bmax: vec3<f32>, up_y: f32) -> bool {
    return patch_least_distance(bmin, bmax, up_y) >= params.max_distance;
}

// Distance from the camera to the box (0 inside it).
fn box_distance(bmin: vec3<f32>, bmax: vec3<f32>) -> f32 {
    let c = params.camera_pos.xyz;
    return length(max(max(bmin - c, c - bmax), vec3<f32>(0.0)));
}

@compute @workgroup_size(64)
fn patches_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let p = gid.x;
    if p >= params.patch_count {
        return;
    }
    let pbox = patches[p];
    // An empty patch (a free tile slot, or a tile patch whose every blade was removed):
    // nothing to draw or step.
    if pbox.min.w != 0.0 {
        patch_lists[keep_section() + p] = NOT_LISTED;
        return;
    }
    let n = patch_blades(p);
    // The frustum test also drives the physics throttle, so it runs with patch culling off.
    let in_view = box_in_frustum(pbox.min.xyz, pbox.max.xyz);
    // Every blade of a patch beyond the blades' radius fails the distance test: the patch
    // is culled whole (counted as distance), and is not stepped every frame.
    let too_far = (params.tests & TEST_DISTANCE) != 0u
        && patch_beyond_distance(pbox.min.xyz, pbox.max.xyz, pbox.max.w);
    var visible_patch = true;
    if (params.tests & TEST_PATCH) != 0u {
        if !in_view {
            atomicAdd(&out.culled_patch, n);
            visible_patch = false;
        } else if too_far {
            atomicAdd(&out.culled_distance, n);
            visible_patch = false;
        } else if (params.tests & TEST_OCCLUSION) != 0u && box_occluded(pbox.min.xyz, pbox.max.xyz) {
            atomicAdd(&out.culled_occlusion, n);
            atomicAdd(&out.culled_occlusion_patch, n);
            visible_patch = false;
        }
    }
    if visible_patch {
        atomicAdd(&out.visible_patches, 1u);
        var keep = max(params.distance_levels, 1u);
        if (params.tests & TEST_DISTANCE) != 0u && n == params.patch_size {
            keep = patch_keep(pbox.min.xyz, pbox.max.xyz, pbox.max.w);
        }
        list_visible(p, keep);
    } else {
        patch_lists[keep_section() + p] = NOT_LISTED;
    }
    // Physics: patches in the frustum or near the camera every frame, the others in turn;
    // patches beyond the blades' radius not at all (no turn of the camera shows them as
    // blades; they go on from their last pose when the radius grows again), unless the
    // throttle is off.
    let throttle = max(params.physics_throttle, 1u);
    let near = box_distance(pbox.min.xyz, pbox.max.xyz) <= params.physics_radius;
    let every_frame = (in_view && !too_far) || near || throttle == 1u;
    let turn = !too_far && (params.frame + p) % throttle == 0u;
    if every_frame || turn {
        atomicAdd(&out.updated_patches, 1u);
        if !every_frame {
            atomicAdd(&out.throttled_patches, 1u);
        }
        // Thinning steps only the classes Eq. 20 may keep every frame where the patch would
        // step whole every frame for being in view; near the camera (the colliders' reach)
        // every blade steps every frame.
        var keep = max(params.distance_levels, 1u);
        if every_frame && !near && throttle > 1u && (params.tests & TEST_DISTANCE) != 0u {
            keep = patch_keep(pbox.min.xyz, pbox.max.xyz, pbox.max.w);
        }
        if (params.collide.y & COLLIDE_HIERARCHY) != 0u && params.collide.z > 0u {
            broad_phase_bvh(p, pbox, !every_frame);
        } else {
            broad_phase(p, pbox);
        }
        // A patch whose broad phase found no collider steps in the update's pipeline
        // without collisions: on a software adapter the collision rounds cost every blade
        // whether or not a sphere is near (half the update on the default meadow).
        list_chunks(p, every_frame, turn, keep, patch_spheres[p * PATCH_SPHERE_STRIDE] == 0u);
    }
}

// The most classes Eq. 20 keeps for any blade of a patch (`floor(n (1 - d / d_max))` at
// `patch_least_distance`, less a centimetre against rounding): a class at or above it is
// culled by distance in every blade of the patch. The twin is `reference::patch_keep`.
fn patch_keep(bmin: vec3<f32>, bmax: vec3<f32>, up_y: f32) -> u32 {
    let d = max(patch_least_distance(bmin, bmax, up_y) - 0.01, 0.0);
    let n = max(params.distance_levels, 1u);
    let keep = floor(f32(n) * (1.0 - d / params.max_distance));
    return u32(clamp(keep, 0.0, f32(n)));
}

// Marks visible patch `p`'s chunks for the blade cull's list (`finalize` lists them in
// patch order): those holding a class below `keep`. The others' blades are culled by
// distance here, whole (a partial patch, the field's last, lists every chunk). The twin is
// `reference::thin_order::cull_skips`.
fn list_visible(p: u32, keep: u32) {
    let per_patch = params.patch_size / CHUNK;
    let n = max(params.distance_levels, 1u);
    let skipped = (per_patch - listed_chunks(p, keep, per_patch, n)) * CHUNK;
    if skipped != 0u {
        atomicAdd(&out.culled_distance, skipped);
    }
    patch_lists[keep_section() + p] = keep;
}

// Puts stepped patch `p`'s chunks on an update list (the free one when it has no collider
// near): each chunk with a class below `keep` every frame (unmarked, or THROTTLED for a
// patch stepped only on its `turn`), the others marked THINNED on the patch's turn only.
fn list_chunks(p: u32, every_frame: bool, turn: bool, keep: u32, free: bool) {
    let size = params.patch_size;
    let per_patch = size / CHUNK;
    let n = max(params.distance_levels, 1u);
    var count = 0u;
    var thinned = 0u;
    for (var c = 0u; c < per_patch; c++) {
        let kept = chunk_kept(c, keep, p, size, n);
        count += u32(kept || turn);
        thinned += u32(!kept && turn);
    }
    atomicAdd(&out.updated_chunks, count);
    atomicAdd(&out.throttled_chunks, select(thinned, count, !every_frame));
    var at = 0u;
    if free {
        at = atomicAdd(&out.free_chunks, count);
    } else {
        at = atomicAdd(&out.collide_chunks, count);
    }
    var k = update_list(free) + 1u + at;
    for (var c = 0u; c < per_patch; c++) {
        let kept = chunk_kept(c, keep, p, size, n);
        var entry = p * per_patch + c;
        if !every_frame {
            entry |= THROTTLED;
        } else if !kept {
            entry |= THINNED;
        }
        if kept || turn {
            patch_lists[k] = entry;
            k += 1u;
        }
    }
}

// A 2D dispatch of `groups` workgroups that stays under the per-dimension limit.
fn split(groups: u32) -> vec3<u32> {
    if groups == 0u {
        return vec3<u32>(0u, 1u, 1u);
    }
    let x = min(groups, MAX_GROUPS);
    return vec3<u32>(x, (groups + x - 1u) / x, 1u);
}

// The blade of this invocation of an indirect blade pass over the visible patches' listed
// chunks (in class order, `thin_order.wgsl`), or NO_BLADE past the list or the field.
fn blade_of(wid: vec3<u32>, groups: vec3<u32>, lid: u32) -> u32 {
    let per_patch = params.patch_size / CHUNK;
    let flat = wid.y * groups.x + wid.x;
    if flat >= patch_lists[0] {
        return NO_BLADE;
    }
    let chunk = patch_lists[1u + flat];
    let p = chunk / per_patch;
    let pos = (chunk % per_patch) * CHUNK + lid;
    let i = p * params.patch_size + order_blade(pos, params.patch_size, max(params.distance_levels, 1u));
    if i >= params.blade_count {
        return NO_BLADE;
    }
    return i;
}

// Eq. 17-20 and the occlusion by opaque objects; false (and the culling test counted) when
// one of them culls blade `i`.
fn early_tests(i: u32, blade: Blade) -> bool {
    let v0 = blade.v0_dir.xyz;
    let v1 = blade.v1_height.xyz;
    let v2 = blade.v2_width.xyz;
    let up = blade.up_stiffness.xyz;
    let camera = params.camera_pos.xyz;
    // A flower's stem (STEM_WIDTH wide, `field::clumps`) carries a head that faces up: no
    // side of it is edge-on, so the orientation test spares it.
    if (params.tests & TEST_ORIENTATION) != 0u && blade.v2_width.w != FLOWER_STEM_WIDTH {
        let width_dir = blade_frame(up, blade.v0_dir.w)[0];
        let to_blade = v0 - camera;
        var view_dir = vec3<f32>(0.0);
        if length(to_blade) > 0.0 {
            view_dir = normalize(to_blade);
        }
        if abs(dot(view_dir, width_dir)) > params.orientation_threshold {
            atomicAdd(&out.culled_orientation, 1u);
            return false;
        }
    }
    let m = 0.25 * v0 + 0.5 * v1 + 0.25 * v2;
    if (params.tests & TEST_FRUSTUM) != 0u {
        if !in_frustum(v0) && !in_frustum(m) && !in_frustum(v2) {
            atomicAdd(&out.culled_frustum, 1u);
            return false;
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
            atomicAdd(&out.culled_distance, 1u);
            return false;
        }
    }
    if (params.tests & TEST_OCCLUSION) != 0u {
        if blade_occluded(v0, m, v2, params.occlusion_bias) {
            atomicAdd(&out.culled_occlusion, 1u);
            return false;
        }
    }
    return true;
}

@compute @workgroup_size(64)
fn main(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    store_codes(wid, groups, lid, early_code(blade_of(wid, groups, lid)));
}

// Blade `i`'s tests: 0 when culled (or marked a candidate for the late pass), else the
// level of detail it is drawn at early plus 1 (`order_scatter` lists it).
fn early_code(i: u32) -> u32 {
    if i == NO_BLADE {
        return 0u;
    }
    let blade = blades[i];
    // A blade the tile generation removed (density map, terrain edge) has height 0.
    if blade.v1_height.w <= 0.0 {
        return 0u;
    }
    let grass = (params.tests & TEST_GRASS_OCCLUSION) != 0u;
    if !early_tests(i, blade) {
        if grass {
            seen[i] = SEEN_NO;
        }
        return 0u;
    }
    if grass {
        if seen[i] != SEEN_YES {
            seen[i] = SEEN_CANDIDATE;
            return 0u;
        }
        seen[i] = SEEN_DRAWN_EARLY;
    }
    count_wave(i, blade);
    return lod_level(projected_height(blade.v0_dir.xyz, blade.v1_height.w, params), params) + 1u;
}

// The far levels' shading waves (far_grass.wgsl): the billboards and the far ground stand
// for blades the gusts bend as they bend the blades at the edge of the blades' reach, so
// the blades drawn there (from half the blade radius out; all of them without a distance
// test) count how far the gusts bend them from their rest, as the blades' shading waves
// read it (`blade_albedos`: clamp(1.5 |v2 − rest tip| / h, 0, 1)).
fn count_wave(i: u32, blade: Blade) {
    let v0 = blade.v0_dir.xyz;
    let up = blade.up_stiffness.xyz;
    let rel = v0 - params.camera_pos.xyz;
    let d_proj = length(rel - up * dot(rel, up));
    if (params.tests & TEST_DISTANCE) != 0u && d_proj < 0.5 * params.max_distance {
        return;
    }
    let gust = length(blade.v2_width.xyz - states[i].rest_eta.xyz) / max(blade.v1_height.w, 1e-4);
    atomicAdd(&out.wave_sum, u32(clamp(gust * 1.5, 0.0, 1.0) * 1024.0));
    atomicAdd(&out.wave_blades, 1u);
}

@compute @workgroup_size(64)
fn late(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    store_codes(wid, groups, lid, late_code(blade_of(wid, groups, lid)));
}

// Blade `i`'s late test: 0 when it is not drawn late, else its level of detail plus 1.
fn late_code(i: u32) -> u32 {
    if i == NO_BLADE {
        return 0u;
    }
    let state = seen[i];
    if state != SEEN_DRAWN_EARLY && state != SEEN_CANDIDATE {
        return 0u;
    }
    let blade = blades[i];
    let v0 = blade.v0_dir.xyz;
    let v2 = blade.v2_width.xyz;
    let m = 0.25 * v0 + 0.5 * blade.v1_height.xyz + 0.25 * v2;
    // A blade drawn early is in the depth itself and may hide itself at a small bias. That
    // costs nothing visible: it becomes a candidate next frame and is tested then against
    // a depth without itself. A larger bias here was measured to keep more hidden blades
    // in the early set (nature scene: 0.694 culled instead of 0.714).
    let hidden = blade_occluded(v0, m, v2, params.clip.z);
    if state == SEEN_DRAWN_EARLY {
        seen[i] = select(SEEN_YES, SEEN_NO, hidden);
        return 0u;
    }
    if hidden {
        seen[i] = SEEN_NO;
        atomicAdd(&out.culled_occlusion, 1u);
        atomicAdd(&out.culled_occlusion_grass, 1u);
        return 0u;
    }
    seen[i] = SEEN_YES;
    return lod_level(projected_height(v0, blade.v1_height.w, params), params) + 1u;
}
