// The colliders' hierarchy (`sim::bvh`), read from the spheres buffer of the including pass
// (which names it `spheres`): node k is the two vec4s at BVH_NODE_BASE + 2k, its bounding
// sphere, then its left child, right child, the collider of a leaf (-1 for an inner node,
// -2 for a loose one, which never stands in for its spheres) and its depth as whole numbers in f32 (exact below 2^24; `bvh::encode`).

struct BvhNode {
    sphere: vec4<f32>,
    // Left, right, the collider of a leaf (BVH_INTERNAL or BVH_LOOSE otherwise), depth.
    link: vec4<u32>,
}

const BVH_INTERNAL: u32 = 0xffffffffu;
const BVH_LOOSE: u32 = 0xfffffffeu;
// Deep enough for any tree of MAX_SPHERES leaves (depth 14) with room to spare: a
// depth-first walk holds at most one sibling per level.
const BVH_STACK: u32 = 32u;

fn bvh_node(k: u32) -> BvhNode {
    let at = BVH_NODE_BASE + 2u * k;
    let l = spheres[at + 1u];
    let inner = select(BVH_INTERNAL, BVH_LOOSE, l.z < -1.5);
    let leaf = select(inner, u32(l.z), l.z >= 0.0);
    return BvhNode(spheres[at], vec4<u32>(u32(l.x), u32(l.y), leaf, u32(l.w)));
}

// The level a walk stops at for a point `dist` metres from the precision camera
// (`sim::bvh::depth_limit`): the tree's depth within `near` metres in an every-frame patch,
// one level less per doubling of the distance beyond, one less again when throttled.
fn bvh_limit(dist: f32, near: f32, tree_depth: u32, throttled: bool) -> u32 {
    let ratio = dist / max(near, 1e-3);
    var coarser = 0u;
    if ratio > 1.0 {
        coarser = u32(min(floor(log2(ratio)), 31.0)) + 1u;
    }
    if throttled {
        coarser += 1u;
    }
    return select(tree_depth - coarser, 0u, coarser > tree_depth);
}
