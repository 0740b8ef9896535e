//! Qiu et al.'s bounding-volume hierarchy of the colliders (issue 14, point 3b): a binary
//! tree of bounding spheres over the frame's collision spheres, built on the CPU each frame
//! (at most `MAX_SPHERES` spheres, median splits along the longest axis; no per-blade data)
//! and walked on the GPU by every blade (`collide` in `update.wgsl`, twin
//! `reference::collide`).
//!
//! The spheres nest (a node's holds its children's whole), so a walk may start anywhere: the
//! patch pass's broad phase walks the tree once per stepped patch against its box and lists
//! the patch's cut of it (`broad_phase_bvh` in `cull_broad_phase.wgsl`, twin `reference::patch_nodes`),
//! and each blade walks on from the listed nodes, meeting what a walk from the root meets.
//!
//! The walk is depth first, left child first, and skips a node whose sphere the blade
//! cannot reach (farther from its root than the node's radius plus the blade's height:
//! exact, since the tip and the curve's midpoint stay within a height of the root). Its
//! precision is chosen per blade: a blade within `physics.hierarchy_precision_distance` of
//! the camera, in a patch stepped every frame, walks down to the leaves (the colliders
//! themselves); farther away each doubling of the distance, and a throttled patch, stops the
//! walk one level higher, where the node's bounding sphere stands in for the spheres under
//! it (coarser, and never smaller than what it stands for), unless the node is loose (its
//! spheres fill too little of it to stand in for them: [`MIN_FILL`]).

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

/// `BvhNode` in `update.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct BvhNode {
    /// Bounding sphere: centre, radius.
    pub sphere: [f32; 4],
    /// Left child, right child, the collider's index for a leaf ([`INTERNAL`] otherwise),
    /// the node's depth (the root is 0).
    pub link: [u32; 4],
}

const _: () = assert!(std::mem::size_of::<BvhNode>() == 32);

/// `link[2]` of an internal node.
pub const INTERNAL: u32 = u32::MAX;
/// `link[2]` of an internal node too loose to stand in for its spheres: they fill less than
/// [`MIN_FILL`] of its bounding sphere (spheres scattered over a field, unlike a packing),
/// so a walk always goes through it, whatever its precision.
pub const LOOSE: u32 = u32::MAX - 1;
/// The least share of the volume of the tightest sphere about their box's centre that a
/// node's spheres must fill (the sum of their volumes, overlaps counted again) for it to stand in for them at a coarse
/// precision. A packed object's nodes pass; a scattering of pebbles does not, whose bounding
/// spheres would crush metres of grass that nothing touches.
pub const MIN_FILL: f32 = 0.1;

/// Whether `node` is a leaf (one collider), not an inner or loose node.
pub fn is_leaf(node: &BvhNode) -> bool {
    node.link[2] < LOOSE
}

/// The hierarchy of `spheres` (`vec4(centre, radius)`), root first; empty without spheres.
/// Each node splits its spheres at the median of their centres along the longest axis of
/// the centres' box.
pub fn build(spheres: &[[f32; 4]]) -> Vec<BvhNode> {
    let mut nodes = Vec::with_capacity(spheres.len() * 2);
    if spheres.is_empty() {
        return nodes;
    }
    let mut order: Vec<u32> = (0..spheres.len() as u32).collect();
    node(spheres, &mut order, 0, &mut nodes);
    nodes
}

fn centre(s: &[f32; 4]) -> Vec3 {
    Vec3::new(s[0], s[1], s[2])
}

/// The smallest sphere holding spheres `a` and `b` whole (its radius a hair larger for the
/// rounding), so that a node's sphere nests its children's.
fn enclosing(a: [f32; 4], b: [f32; 4]) -> [f32; 4] {
    let (ca, cb) = (centre(&a), centre(&b));
    let d = ca.distance(cb);
    if d + b[3] <= a[3] {
        return a;
    }
    if d + a[3] <= b[3] {
        return b;
    }
    let radius = 0.5 * (d + a[3] + b[3]);
    let c = ca + (cb - ca) * ((radius - a[3]) / d);
    // The centre rounds by about an ulp of its coordinates.
    let hair = 1e-6 * (radius + c.abs().max_element());
    [c.x, c.y, c.z, radius + hair]
}

/// Builds the node of `members` at `depth`; returns its index. A leaf's sphere is its
/// collider; an inner node's is the smallest sphere that holds both children's spheres
/// whole, so the spheres nest: a node the blade cannot reach has no descendant it
/// can reach, and a walk that starts below the root (the broad phase's cut) meets exactly
/// what a walk from the root meets there.
fn node(spheres: &[[f32; 4]], members: &mut [u32], depth: u32, nodes: &mut Vec<BvhNode>) -> u32 {
    let index = nodes.len() as u32;
    let s = |i: u32| &spheres[i as usize];
    nodes.push(BvhNode {
        sphere: [0.0; 4],
        link: [0, 0, INTERNAL, depth],
    });
    if let [only] = members {
        nodes[index as usize].sphere = *s(*only);
        nodes[index as usize].link[2] = *only;
        return index;
    }
    let (clo, chi) = members.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), &i| (lo.min(centre(s(i))), hi.max(centre(s(i)))),
    );
    let extent = chi - clo;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    let half = members.len() / 2;
    // Ties by index, so that the tree is the same on every run.
    members.sort_by(|&a, &b| s(a)[axis].total_cmp(&s(b)[axis]).then(a.cmp(&b)));
    let (left, right) = members.split_at_mut(half);
    let l = node(spheres, left, depth + 1, nodes);
    let r = node(spheres, right, depth + 1, nodes);
    let sphere = enclosing(nodes[l as usize].sphere, nodes[r as usize].sphere);
    // How much of the space around its spheres they fill, measured on the tightest sphere
    // about their box's centre (the nested one can be much larger).
    let (lo, hi) = members.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), &i| {
            let r = Vec3::splat(s(i)[3]);
            (lo.min(centre(s(i)) - r), hi.max(centre(s(i)) + r))
        },
    );
    let mid = (lo + hi) * 0.5;
    let tight = members
        .iter()
        .map(|&i| mid.distance(centre(s(i))) + s(i)[3])
        .fold(0.0f32, f32::max);
    let filled: f32 = members.iter().map(|&i| s(i)[3].powi(3)).sum();
    let n = &mut nodes[index as usize];
    n.sphere = sphere;
    n.link[0] = l;
    n.link[1] = r;
    if filled < MIN_FILL * tight.powi(3) {
        n.link[2] = LOOSE;
    }
    index
}

/// Puts this step's tree (`nodes`, built from the uploaded spheres) and the camera into
/// `params`; the blades walk the tree with `hierarchy` (`Scene::collision_hierarchy`) and a
/// tree to walk.
pub fn fill_params(
    params: &mut crate::sim::layout::SimParams,
    nodes: &[BvhNode],
    hierarchy: bool,
    camera: Vec3,
) {
    params.bvh_camera[0] = camera.x;
    params.bvh_camera[1] = camera.y;
    params.bvh_camera[2] = camera.z;
    // The tree is built whenever there are colliders (the flat broad phase prunes with it
    // too); the blades walk it only when the scene says so.
    params.bvh_info[0] = u32::from(hierarchy && !nodes.is_empty());
    params.bvh_info[1] = nodes.len() as u32;
    params.bvh_info[2] = depth(nodes);
}

/// Puts the tree's size and depth and the precision camera into the cull pass's
/// parameters. With `hierarchy` the broad phase then lists each stepped patch's cut of the
/// tree (`broad_phase_bvh` in `cull_broad_phase.wgsl`, twin `reference::patch_nodes`); without, it
/// lists the spheres near each patch and uses the tree only to skip the patches near none.
/// `near` is `physics.hierarchy_precision_distance`.
pub fn fill_cull_params(
    params: &mut crate::sim::layout::CullParams,
    nodes: &[BvhNode],
    hierarchy: bool,
    camera: Vec3,
    near: f32,
) {
    if hierarchy {
        params.collide[1] |= crate::sim::layout::COLLIDE_HIERARCHY;
    }
    params.collide[2] = nodes.len() as u32;
    params.collide[3] = depth(nodes);
    params.bvh = [camera.x, camera.y, camera.z, near];
}

/// The nodes as the GPU reads them from the spheres buffer (`bvh_node.wgsl`): two `vec4`s
/// each, the bounding sphere, then left, right, the leaf's collider (-1 for an inner node,
/// -2 for a loose one)
/// and the depth as whole numbers in f32 (exact: fewer than 2^24 nodes). Whole numbers in
/// f32 rather than u32 bits, because small integers are denormal floats, which a GPU may
/// flush when it moves them as floats.
pub fn encode(nodes: &[BvhNode]) -> Vec<[f32; 4]> {
    nodes
        .iter()
        .flat_map(|n| {
            let leaf = match n.link[2] {
                INTERNAL => -1.0,
                LOOSE => -2.0,
                k => k as f32,
            };
            [
                n.sphere,
                [n.link[0] as f32, n.link[1] as f32, leaf, n.link[3] as f32],
            ]
        })
        .collect()
}

/// The level at which the broad phase cuts the tree for a patch box (`broad_phase_bvh`):
/// the level of the box corner farthest from the camera, taken 0.1 % farther so that no
/// blade in the box, whose own level comes from its root's distance in f32, rounds to a
/// coarser one.
pub fn cut_depth(
    tree_depth: u32,
    lo: Vec3,
    hi: Vec3,
    camera: Vec3,
    near: f32,
    throttled: bool,
) -> u32 {
    let pick = |l: f32, h: f32, c: f32| if (h - c).abs() > (l - c).abs() { h } else { l };
    let corner = Vec3::new(
        pick(lo.x, hi.x, camera.x),
        pick(lo.y, hi.y, camera.y),
        pick(lo.z, hi.z, camera.z),
    );
    depth_limit(tree_depth, corner.distance(camera) * 1.001, near, throttled)
}

/// The deepest level of `nodes`.
pub fn depth(nodes: &[BvhNode]) -> u32 {
    nodes.iter().map(|n| n.link[3]).max().unwrap_or(0)
}

/// The level a blade's walk stops at (`bvh_depth_limit` in `update.wgsl`): the tree's depth
/// within `near` metres of the camera in an every-frame patch, one level less per doubling
/// of the distance beyond, and one less again in a throttled patch.
pub fn depth_limit(tree_depth: u32, distance: f32, near: f32, throttled: bool) -> u32 {
    let ratio = distance / near.max(1e-3);
    let mut coarser = if ratio > 1.0 {
        ratio.log2().floor().min(31.0) as u32 + 1
    } else {
        0
    };
    if throttled {
        coarser += 1;
    }
    tree_depth.saturating_sub(coarser)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spheres(n: usize) -> Vec<[f32; 4]> {
        (0..n)
            .map(|i| {
                let t = i as f32 * 0.37;
                [
                    t.sin() * 3.0 + t * 0.1,
                    (t * 1.3).cos(),
                    t.cos() * 2.0,
                    0.1 + 0.05 * (i % 5) as f32,
                ]
            })
            .collect()
    }

    #[test]
    fn every_sphere_is_one_leaf_and_every_node_holds_its_children() {
        for n in [1usize, 2, 3, 17, 1000] {
            let s = spheres(n);
            let nodes = build(&s);
            assert_eq!(nodes.len(), 2 * n - 1);
            let mut leaves: Vec<u32> = nodes
                .iter()
                .filter(|n| is_leaf(n))
                .map(|n| n.link[2])
                .collect();
            leaves.sort_unstable();
            assert_eq!(leaves, (0..n as u32).collect::<Vec<_>>());
            // Every node's sphere holds the spheres of all the leaves under it.
            fn members(nodes: &[BvhNode], k: u32, out: &mut Vec<u32>) {
                let n = &nodes[k as usize];
                if is_leaf(n) {
                    out.push(n.link[2]);
                } else {
                    members(nodes, n.link[0], out);
                    members(nodes, n.link[1], out);
                }
            }
            for (k, node) in nodes.iter().enumerate() {
                let c = Vec3::new(node.sphere[0], node.sphere[1], node.sphere[2]);
                let mut under = Vec::new();
                members(&nodes, k as u32, &mut under);
                for i in under {
                    let sp = &s[i as usize];
                    assert!(c.distance(centre(sp)) + sp[3] <= node.sphere[3] + 1e-4);
                }
                if !is_leaf(node) {
                    for child in [node.link[0], node.link[1]] {
                        let ch = &nodes[child as usize];
                        assert_eq!(ch.link[3], node.link[3] + 1);
                        // The spheres nest: each child's lies inside its parent's.
                        let cc = Vec3::new(ch.sphere[0], ch.sphere[1], ch.sphere[2]);
                        assert!(c.distance(cc) + ch.sphere[3] <= node.sphere[3]);
                    }
                }
            }
            let expected = (n as f32).log2().ceil() as u32;
            assert!(depth(&nodes) <= expected, "depth {} for {n}", depth(&nodes));
        }
        assert!(build(&[]).is_empty());
    }

    #[test]
    fn scattered_spheres_make_loose_nodes_and_a_packing_tight_ones() {
        // Pebbles of 5 cm over 20 m: no inner node is filled.
        let pebbles: Vec<[f32; 4]> = (0..400)
            .map(|i| [(i % 20) as f32, 0.0, (i / 20) as f32, 0.05])
            .collect();
        let nodes = build(&pebbles);
        assert!(nodes
            .iter()
            .filter(|n| !is_leaf(n))
            .all(|n| n.link[2] == LOOSE));
        // A dense block of touching spheres: the root and most inner nodes may stand in
        // (a node of a few spheres in a row is too thin).
        let block: Vec<[f32; 4]> = (0..64)
            .map(|i| [(i % 4) as f32, ((i / 4) % 4) as f32, (i / 16) as f32, 0.5])
            .collect();
        let nodes = build(&block);
        let inner: Vec<&BvhNode> = nodes.iter().filter(|n| !is_leaf(n)).collect();
        let tight = inner.iter().filter(|n| n.link[2] == INTERNAL).count();
        assert_eq!(nodes[0].link[2], INTERNAL);
        assert!(
            4 * tight >= 3 * inner.len(),
            "{tight} of {} tight",
            inner.len()
        );
        let leaf = |k: u32| encode(&nodes)[2 * k as usize + 1][2];
        assert_eq!(leaf(0), -1.0);
        let loose = encode(&build(&pebbles));
        assert_eq!(loose[1][2], -2.0);
    }

    #[test]
    fn the_walk_is_exact_near_and_coarser_far_and_throttled() {
        assert_eq!(depth_limit(10, 3.0, 10.0, false), 10);
        assert_eq!(depth_limit(10, 10.0, 10.0, false), 10);
        assert_eq!(depth_limit(10, 15.0, 10.0, false), 9);
        assert_eq!(depth_limit(10, 25.0, 10.0, false), 8);
        assert_eq!(depth_limit(10, 3.0, 10.0, true), 9);
        assert_eq!(depth_limit(3, 1e9, 10.0, true), 0);
    }
}
