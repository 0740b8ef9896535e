// The cull's lists in an order that does not depend on how the adapter schedules its
// workgroups (included by cull.wgsl). Two blades can lie at exactly the same depth at a
// pixel (two crossing blades, within one step of a 32-bit depth near 1), and the depth test
// keeps whichever is drawn last: with lists appended by atomics in whatever order the
// workgroups run, the same frame drew either blade, one run or the next (a few pixels a
// frame on a multi-threaded software adapter). Here every list is in a fixed order:
//
// - the blade cull's chunk list in patch order, each patch's kept chunks in class order
//   (`finalize`: each patch writes its keep, one workgroup scans them); the patches from
//   the last to the first where the view looks from the last patch towards the first
//   (`list_from_last`). The field's patches follow a k-d split of the ground, low side
//   first, so the list then runs roughly near to far either way: the GPU skips shading a
//   blade hidden behind blades drawn before it, and drawn far to near, nature's view with
//   2,000,000 blades shaded 7.64 million fragments where the other way round took 2.45
//   (NVIDIA H200, 1920 × 1080; docs/performance.md);
// - each level's visible list in that chunk order, each chunk's blades in lane order: the
//   cull writes each lane's level (2 bits a lane, 4 words a chunk), `order_early` /
//   `order_late` scan the chunks' counts into offsets, and `order_scatter` (an invocation
//   per chunk) puts the chunk's drawn blades, in lane order, at its offsets.
//
// The twin is `reference::cull::list_order` (the key the lists are sorted by).
//!include workgroup_scan.wgsl

// Words per listed chunk in the order section: its lanes' codes (0: not drawn, else the
// level + 1; 2 bits a lane, 16 lanes a word), then where its blades of each level start.
const ORDER_STRIDE: u32 = 8u;
const ORDER_OFFSETS: u32 = 4u;
// A patch none of whose chunks is on the blade cull's list this frame.
const NOT_LISTED: u32 = 0xffffffffu;

// The patches' keep section of `patch_lists`, after the three lists: per patch, the classes
// its listed chunks hold (`patch_keep`), or NOT_LISTED.
fn keep_section() -> u32 {
    return 3u * (params.patch_count * (params.patch_size / CHUNK) + 1u);
}

// The order words of the `flat`-th chunk on the blade cull's list.
fn order_at(flat: u32) -> u32 {
    return keep_section() + params.patch_count + flat * ORDER_STRIDE;
}

// Bit 2j set where lane j's code in `w` is `code` (1, 2 or 3).
fn code_mask(w: u32, code: u32) -> u32 {
    let lo = w & 0x55555555u;
    let hi = (w >> 1u) & 0x55555555u;
    if code == 1u {
        return lo & ~hi;
    }
    if code == 2u {
        return hi & ~lo;
    }
    return lo & hi;
}

// Blades of each level in the `flat`-th listed chunk.
fn level_counts(flat: u32) -> vec3<u32> {
    let at = order_at(flat);
    var n = vec3<u32>(0u);
    for (var w = 0u; w < 4u; w++) {
        let word = patch_lists[at + w];
        n += vec3<u32>(
            countOneBits(code_mask(word, 1u)),
            countOneBits(code_mask(word, 2u)),
            countOneBits(code_mask(word, 3u)),
        );
    }
    return n;
}

// Chunks of patch `p` on the blade cull's list at `keep`.
fn listed_chunks(p: u32, keep: u32, per_patch: u32, n: u32) -> u32 {
    if keep == NOT_LISTED {
        return 0u;
    }
    if keep >= n {
        return per_patch;
    }
    var count = 0u;
    for (var c = 0u; c < per_patch; c++) {
        count += u32(chunk_kept(c, keep, p, params.patch_size, n));
    }
    return count;
}

// Whether the list runs from the last patch to the first (twin: `reference::cull::
// list_from_last`): where the view's direction on the ground points from the last patch's
// centre towards the first's.
fn list_from_last() -> bool {
    if params.patch_count < 2u {
        return false;
    }
    let first = patches[0];
    let last = patches[params.patch_count - 1u];
    let along = (last.min.xz + last.max.xz) - (first.min.xz + first.max.xz);
    // The clip w row of the view-projection: the view's direction.
    let m = params.view_proj;
    let view = vec2<f32>(m[0][3], m[2][3]);
    return dot(view, along) < 0.0;
}

// The patch at position `q` of the list's order.
fn listed_patch(q: u32, from_last: bool) -> u32 {
    return select(q, params.patch_count - 1u - q, from_last);
}

// The blade cull's chunk list in patch order, then the indirect dispatches (one workgroup).
@compute @workgroup_size(256)
fn finalize(@builtin(local_invocation_index) t: u32) {
    let per_patch = params.patch_size / CHUNK;
    let n = max(params.distance_levels, 1u);
    let slice = scan_slice(t, params.patch_count);
    let keeps = keep_section();
    let from_last = list_from_last();
    var count = 0u;
    for (var q = slice.x; q < slice.y; q++) {
        let p = listed_patch(q, from_last);
        count += listed_chunks(p, patch_lists[keeps + p], per_patch, n);
    }
    var k = 1u + exclusive_scan(t, vec3<u32>(count, 0u, 0u)).x;
    let vis = partial[SCAN_THREADS].x;
    for (var q = slice.x; q < slice.y; q++) {
        let p = listed_patch(q, from_last);
        let keep = patch_lists[keeps + p];
        if keep == NOT_LISTED {
            continue;
        }
        for (var c = 0u; c < per_patch; c++) {
            if keep >= n || chunk_kept(c, keep, p, params.patch_size, n) {
                patch_lists[k] = p * per_patch + c;
                k += 1u;
            }
        }
    }
    if t == 0u {
        write_dispatches(vis);
    }
}

// Turns the chunk counts into the indirect dispatches of the blade cull and the updates.
fn write_dispatches(vis: u32) {
    atomicStore(&out.visible_chunks, vis);
    let upd = atomicLoad(&out.collide_chunks);
    let free = atomicLoad(&out.free_chunks);
    patch_lists[0] = vis;
    patch_lists[update_list(false)] = upd;
    patch_lists[update_list(true)] = free;
    let c = split(vis);
    dispatch.cull_x = c.x;
    dispatch.cull_y = c.y;
    dispatch.cull_z = 1u;
    let u = split(upd);
    dispatch.update_x = u.x;
    dispatch.update_y = u.y;
    dispatch.update_z = 1u;
    let f = split(free);
    dispatch.free_x = f.x;
    dispatch.free_y = f.y;
    dispatch.free_z = 1u;
    let o = split((vis + 63u) / 64u);
    dispatch.order_x = o.x;
    dispatch.order_y = o.y;
    dispatch.order_z = 1u;
}

var<workgroup> lane_codes: array<atomic<u32>, 4>;

// Stores the workgroup's lanes' codes (`code`: 0, or the level + 1) in its chunk's order
// words. In uniform control flow only.
fn store_codes(wid: vec3<u32>, groups: vec3<u32>, lid: u32, code: u32) {
    if lid < 4u {
        atomicStore(&lane_codes[lid], 0u);
    }
    workgroupBarrier();
    if code != 0u {
        atomicOr(&lane_codes[lid / 16u], code << (2u * (lid % 16u)));
    }
    workgroupBarrier();
    let flat = wid.y * groups.x + wid.x;
    if lid < 4u && flat < patch_lists[0] {
        patch_lists[order_at(flat) + lid] = atomicLoad(&lane_codes[lid]);
    }
}

// Each listed chunk's first slot per level, after the chunks before it; `base` is where
// the lists start in each level's region. Returns the totals.
fn scan_offsets(t: u32, base: vec3<u32>) -> vec3<u32> {
    let slice = scan_slice(t, patch_lists[0]);
    var sum = vec3<u32>(0u);
    for (var f = slice.x; f < slice.y; f++) {
        sum += level_counts(f);
    }
    var run = base + exclusive_scan(t, sum);
    for (var f = slice.x; f < slice.y; f++) {
        let at = order_at(f) + ORDER_OFFSETS;
        patch_lists[at] = run.x;
        patch_lists[at + 1u] = run.y;
        patch_lists[at + 2u] = run.z;
        run += level_counts(f);
    }
    return partial[SCAN_THREADS];
}

// The early lists' offsets and counts, and their draws' instance counts (one workgroup).
@compute @workgroup_size(256)
fn order_early(@builtin(local_invocation_index) t: u32) {
    let total = scan_offsets(t, vec3<u32>(0u));
    if t == 0u {
        for (var k = 0u; k < 3u; k++) {
            atomicStore(&out.blades[k], total[k]);
            atomicStore(&out.draws[k].instance_count, (total[k] + DRAW_BATCH - 1u) / DRAW_BATCH);
        }
    }
}

// The late lists': each starts at the first whole draw batch after its level's early list.
@compute @workgroup_size(256)
fn order_late(@builtin(local_invocation_index) t: u32) {
    var base = vec3<u32>(0u);
    for (var k = 0u; k < 3u; k++) {
        base[k] = late_start(atomicLoad(&out.blades[k]));
    }
    let total = scan_offsets(t, base);
    if t == 0u {
        for (var k = 0u; k < 3u; k++) {
            atomicStore(&out.late_blades[k], total[k]);
            atomicStore(&out.late_draws[k].instance_count, (total[k] + DRAW_BATCH - 1u) / DRAW_BATCH);
            out.late_draws[k].first_instance = out.draws[k].first_instance
                + atomicLoad(&out.draws[k].instance_count);
        }
    }
}

// Puts each drawn blade of the listed chunks at its slot, one invocation per chunk walking
// its drawn lanes in order (after `order_early` or `order_late`; indirect, `dispatch.order`).
@compute @workgroup_size(64)
fn order_scatter(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    let flat = gid.y * groups.x * 64u + gid.x;
    if flat >= patch_lists[0] {
        return;
    }
    let size = params.patch_size;
    let n = max(params.distance_levels, 1u);
    let chunk = patch_lists[1u + flat];
    let per_patch = size / CHUNK;
    let p = chunk / per_patch;
    let first = (chunk % per_patch) * CHUNK;
    let at = order_at(flat);
    var slot = vec3<u32>(
        patch_lists[at + ORDER_OFFSETS],
        patch_lists[at + ORDER_OFFSETS + 1u],
        patch_lists[at + ORDER_OFFSETS + 2u],
    );
    let regions = region();
    for (var w = 0u; w < 4u; w++) {
        var word = patch_lists[at + w];
        while word != 0u {
            // The lowest drawn lane left in this word, its code, then off the word.
            let shift = countTrailingZeros(word) & ~1u;
            let level = ((word >> shift) & 3u) - 1u;
            word &= ~(3u << shift);
            let lane = w * 16u + shift / 2u;
            visible[level * regions + slot[level]] = p * size + order_blade(first + lane, size, n);
            slot[level] += 1u;
        }
    }
}
