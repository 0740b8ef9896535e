// The colliders a blade can touch (Jahrmann & Wimmer Eq. 14-16 for each, Qiu et al.'s
// hierarchy to find them), for any blade model: the including shader defines
// `struct Contact` (the blade's points being pushed and the collision strength added) and
// `fn push_sphere(c, r, contact)`, which pushes them out of one sphere. The twin is
// `reference::collide` (and `sim::verlet`'s for the Verlet chain).

// The spheres the blade can reach under node `start`, walking the hierarchy depth first
// (left child first) down to `limit`, where a node's bounding sphere stands in for those
// under it (a loose node never does). `root`, `reach`: nothing beyond `reach` of the root
// can be touched. `stack`: the caller's, so that it is set up once per blade rather than
// once per listed node.
fn walk_bvh(start: u32, root: vec3<f32>, reach: f32, limit: u32, contact: ptr<function, Contact>, stack: ptr<function, array<u32, BVH_STACK>>) {
    var top = 1u;
    (*stack)[0] = start;
    while top > 0u {
        top -= 1u;
        let node = bvh_node((*stack)[top]);
        let c = node.sphere.xyz;
        let r = node.sphere.w;
        // Out of the blade's reach: none of its points can be inside.
        if distance(c, root) >= r + reach {
            continue;
        }
        if node.link.z < BVH_LOOSE {
            let s = spheres[node.link.z];
            push_sphere(s.xyz, s.w, contact);
        } else if node.link.z == BVH_INTERNAL && node.link.w >= limit {
            push_sphere(c, r, contact);
        } else if top + 2u <= BVH_STACK {
            // Right below left, so that the left child is walked first.
            (*stack)[top] = node.link.y;
            (*stack)[top + 1u] = node.link.x;
            top += 2u;
        }
    }
}

// The spheres on the patch's broad-phase list (in index order, like the CPU twin that tests
// all of them; in the pool when longer than the patch's slots), or, when the hierarchy is on, the walk under each node on the patch's list
// (the broad phase's cut of the tree, in the order a walk from the root meets them, so
// that the pushes come as the twin's walk from the root makes them; from the root when
// the list overflowed).
fn collide_listed(patch_id: u32, root: vec3<f32>, reach: f32, limit: u32, contact: ptr<function, Contact>) {
    let base = patch_id * PATCH_SPHERE_STRIDE;
    let listed = patch_spheres[base];
    if params.bvh_info.x != 0u && params.bvh_info.y > 0u {
        var stack: array<u32, BVH_STACK>;
        if listed == SPHERES_ALL {
            walk_bvh(0u, root, reach, limit, contact, &stack);
            return;
        }
        for (var k = 0u; k < listed; k++) {
            let node = bvh_node(patch_spheres[base + 1u + k]);
            if node.link.z < BVH_LOOSE {
                // A listed collider: pushed at once, as the walk would.
                let s = spheres[node.link.z];
                push_sphere(s.xyz, s.w, contact);
            } else {
                walk_bvh(patch_spheres[base + 1u + k], root, reach, limit, contact, &stack);
            }
        }
        return;
    }
    let all = listed == SPHERES_ALL;
    let n = select(listed, params.sphere_count, all);
    // A list longer than the patch's slots lies in the shared pool (`broad_phase`).
    let pooled = !all && listed > PATCH_SPHERE_STRIDE - 1u;
    let start = select(base + 1u, patch_spheres[base + 1u], pooled);
    for (var k = 0u; k < n; k++) {
        let sphere = spheres[select(patch_spheres[start + k], k, all)];
        push_sphere(sphere.xyz, sphere.w, contact);
    }
}
