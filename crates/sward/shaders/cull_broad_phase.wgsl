// The collision broad phase of the patch step (`cull.wgsl`, which binds `params`, `out`,
// `spheres` and `patch_spheres`): for each stepped patch, the colliders its blades are
// tested against, as a flat list of spheres or as the patch's cut of the colliders'
// hierarchy. The twins are `reference::patch_spheres` and `reference::patch_nodes`.

fn mark_used(s: u32) {
    atomicOr(&out.spheres_used[s / 32u], 1u << (s % 32u));
}

// The spheres a stepped patch's blades are tested against: those within one radius of the
// patch box (which holds every pose of its blades), in index order, like the CPU twin that
// tests them all (`reference::patch_spheres`). The extra radius keeps the list exact in
// practice: a push by an earlier sphere moves a tip by at most that sphere's radius (four
// times that through the midpoint, which is rarer), before validation pulls it back.
//
// Most patches touch no sphere: the colliders' tree (built whenever there are colliders)
// answers that in O(log n), and only a patch it cannot rule out scans the spheres. Up to
// PATCH_SPHERE_STRIDE - 1 fit the patch's own slots; a longer list goes to the shared pool
// after the slots (its start in slot 1), and only when the pool is full does the patch test
// every sphere (SPHERES_ALL), which is what every long list did before: a patch under a
// packed bunny then tested all 1,002 of its spheres per blade.
fn broad_phase(p: u32, pbox: PatchBox) {
    let base = p * PATCH_SPHERE_STRIDE;
    if params.collide.y == 0u || !tree_may_touch(pbox) {
        patch_spheres[base] = 0u;
        return;
    }
    var count = 0u;
    for (var s = 0u; s < params.collide.x; s++) {
        if sphere_near_box(s, pbox) {
            if count < PATCH_SPHERE_STRIDE - 1u {
                patch_spheres[base + 1u + count] = s;
            }
            count++;
        }
    }
    if count > PATCH_SPHERE_STRIDE - 1u {
        let at = atomicAdd(&out.pool_used, count);
        if at + count <= PATCH_SPHERE_POOL {
            // Listed again, now into the pool: the slots held only the first ones.
            let start = params.patch_count * PATCH_SPHERE_STRIDE + at;
            var k = 0u;
            for (var s = 0u; s < params.collide.x; s++) {
                if sphere_near_box(s, pbox) && k < count {
                    patch_spheres[start + k] = s;
                    mark_used(s);
                    k++;
                }
            }
            patch_spheres[base] = k;
            patch_spheres[base + 1u] = start;
            count = k;
        } else {
            patch_spheres[base] = SPHERES_ALL;
            for (var s = 0u; s < params.collide.x; s++) {
                mark_used(s);
            }
            count = params.collide.x;
        }
    } else {
        patch_spheres[base] = count;
        for (var k = 0u; k < count; k++) {
            mark_used(patch_spheres[base + 1u + k]);
        }
    }
    atomicAdd(&out.patch_sphere_pairs, count);
}

// The broad phase's test of one sphere against a patch box: its centre within two radii.
fn sphere_near_box(s: u32, pbox: PatchBox) -> bool {
    let sphere = spheres[s];
    let q = clamp(sphere.xyz, pbox.min.xyz, pbox.max.xyz);
    return distance(q, sphere.xyz) < 2.0 * sphere.w;
}

// Whether any sphere may pass `sphere_near_box` for the box: false only when the colliders'
// tree rules every one out. A node's sphere holds its children's whole, so a sphere within
// two of its radii of the box lies under a node within two of the node's radius (a hair
// more here, against rounding); true without a tree.
fn tree_may_touch(pbox: PatchBox) -> bool {
    if params.collide.z == 0u {
        return true;
    }
    var stack: array<u32, BVH_STACK>;
    var top = 1u;
    stack[0] = 0u;
    while top > 0u {
        top -= 1u;
        let node = bvh_node(stack[top]);
        let c = node.sphere.xyz;
        if distance(clamp(c, pbox.min.xyz, pbox.max.xyz), c) >= 2.0 * node.sphere.w * 1.0001 + 1e-6 {
            continue;
        }
        if node.link.z < BVH_LOOSE || top + 2u > BVH_STACK {
            return true;
        }
        stack[top] = node.link.y;
        stack[top + 1u] = node.link.x;
        top += 2u;
    }
    return false;
}

// The broad phase with the colliders' hierarchy (Qiu et al.; the twin is
// `reference::patch_nodes`): the patch's cut of the tree. A walk from the root skips the
// nodes that cannot touch the patch box (the same two radii as the flat list, which also
// covers every sphere under a node) and records, in the order it meets them, the leaves and
// the nodes at the level where the coarsest blade of the patch stops its own walk (the
// level of the box's farthest corner from the camera, a hair farther so that no blade
// rounds coarser). Each blade walks on from the recorded nodes down to its own level, and
// so meets exactly the spheres and bounding spheres, in the same order, that a walk from
// the root would push it with; the walk is O(log n) per listed node where the flat list
// tests every sphere per patch. A list that overflows makes the blades walk from the root.
fn broad_phase_bvh(p: u32, pbox: PatchBox, throttled: bool) {
    let base = p * PATCH_SPHERE_STRIDE;
    if params.collide.y == 0u {
        patch_spheres[base] = 0u;
        return;
    }
    let cam = params.bvh.xyz;
    let lo = pbox.min.xyz;
    let hi = pbox.max.xyz;
    let corner = select(lo, hi, abs(hi - cam) > abs(lo - cam));
    let cut = bvh_limit(distance(corner, cam) * 1.001, params.bvh.w, params.collide.w, throttled);
    var count = 0u;
    var stack: array<u32, BVH_STACK>;
    var top = 1u;
    stack[0] = 0u;
    while top > 0u {
        top -= 1u;
        let k = stack[top];
        let node = bvh_node(k);
        let c = node.sphere.xyz;
        if distance(clamp(c, lo, hi), c) >= 2.0 * node.sphere.w {
            continue;
        }
        if node.link.z < BVH_LOOSE || node.link.w >= cut {
            if count < PATCH_SPHERE_STRIDE - 1u {
                patch_spheres[base + 1u + count] = k;
                if node.link.z < BVH_LOOSE {
                    mark_used(node.link.z);
                }
            }
            count++;
        } else if top + 2u <= BVH_STACK {
            stack[top] = node.link.y;
            stack[top + 1u] = node.link.x;
            top += 2u;
        }
    }
    if count > PATCH_SPHERE_STRIDE - 1u {
        patch_spheres[base] = SPHERES_ALL;
        count = params.collide.z;
    } else {
        patch_spheres[base] = count;
    }
    atomicAdd(&out.patch_sphere_pairs, count);
}
