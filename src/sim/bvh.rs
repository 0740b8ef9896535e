//! Qiu et al.'s bounding-volume hierarchy of the colliders (issue 14, point 3b): a binary
//! tree of bounding spheres over the frame's collision spheres, built on the CPU each frame
//! (at most `MAX_SPHERES` spheres: microseconds, and no per-blade data) and walked on the
//! GPU by every blade (`collide` in `update.wgsl`, twin `reference::collide`).
//!
//! The walk is depth first, left child first, and skips a node whose sphere the blade
//! cannot reach (farther from its root than the node's radius plus the blade's height:
//! exact, since the tip and the curve's midpoint stay within a height of the root). Its
//! precision is chosen per blade: a blade within `physics.bvh_precision_distance` of the
//! camera, in a patch stepped every frame, walks down to the leaves (the colliders
//! themselves); farther away each doubling of the distance, and a throttled patch, stops the
//! walk one level higher, where the node's bounding sphere stands in for the spheres under
//! it (coarser, and never smaller than what it stands for).

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

/// Builds the node of `members` at `depth`; returns its index.
fn node(spheres: &[[f32; 4]], members: &mut [u32], depth: u32, nodes: &mut Vec<BvhNode>) -> u32 {
    let index = nodes.len() as u32;
    let s = |i: u32| &spheres[i as usize];
    // The bounding sphere: the centre of the members' box, the farthest member surface.
    let (lo, hi) = members.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), &i| {
            let c = centre(s(i));
            let r = Vec3::splat(s(i)[3]);
            (lo.min(c - r), hi.max(c + r))
        },
    );
    let c = (lo + hi) * 0.5;
    let radius = members
        .iter()
        .map(|&i| c.distance(centre(s(i))) + s(i)[3])
        .fold(0.0f32, f32::max);
    nodes.push(BvhNode {
        sphere: [c.x, c.y, c.z, radius],
        link: [0, 0, INTERNAL, depth],
    });
    if let [only] = members {
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
    nodes[index as usize].link[0] = l;
    nodes[index as usize].link[1] = r;
    index
}

/// Puts this step's tree (`nodes`, built from the uploaded spheres) and the camera into
/// `params` (whose `bvh_info.x` and `bvh_camera.w` come from the scene).
pub fn fill_params(params: &mut crate::sim::layout::SimParams, nodes: &[BvhNode], camera: Vec3) {
    params.bvh_camera[0] = camera.x;
    params.bvh_camera[1] = camera.y;
    params.bvh_camera[2] = camera.z;
    // A tree is built only when the scene walks it (`Scene::collision_hierarchy`).
    params.bvh_info[0] = u32::from(!nodes.is_empty());
    params.bvh_info[1] = nodes.len() as u32;
    params.bvh_info[2] = depth(nodes);
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
                .filter(|n| n.link[2] != INTERNAL)
                .map(|n| n.link[2])
                .collect();
            leaves.sort_unstable();
            assert_eq!(leaves, (0..n as u32).collect::<Vec<_>>());
            // Every node's sphere holds the spheres of all the leaves under it.
            fn members(nodes: &[BvhNode], k: u32, out: &mut Vec<u32>) {
                let n = &nodes[k as usize];
                if n.link[2] != INTERNAL {
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
                if node.link[2] == INTERNAL {
                    for child in [node.link[0], node.link[1]] {
                        assert_eq!(nodes[child as usize].link[3], node.link[3] + 1);
                    }
                }
            }
            let expected = (n as f32).log2().ceil() as u32;
            assert!(depth(&nodes) <= expected, "depth {} for {n}", depth(&nodes));
        }
        assert!(build(&[]).is_empty());
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
