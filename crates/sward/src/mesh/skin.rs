//! Skinned glTF 2.0 meshes with skeletal animation (issue 29, point 1): the first skinned
//! mesh of a file with its skin (joints, inverse bind matrices), every node's rest
//! transform and parent, and the animations whose channels move nodes (translation,
//! rotation, scale; linear and step interpolation). [`SkinnedMesh::joint_matrices`] poses
//! the skeleton at a time and [`SkinnedMesh::skin`] skins the vertices on the CPU (the twin
//! of a GPU skinning pass). Everything a bad file could break is checked at load and named
//! with the file: a joint index past the skin's joints, an inverse bind matrix that cannot
//! be inverted, a channel aimed at a node that does not exist, a cyclic node graph, a
//! sampler whose keys and values disagree, weights that do not add up.

use std::path::Path;

use glam::{Mat4, Quat, Vec3, Vec4};

use super::{fail, gltf_roots, read_gltf_buffers, MAX_TRIANGLES};
use crate::error::Result;

/// The most joints a skin may have (the GPU pass keeps them in one uniform-sized array).
pub const MAX_JOINTS: usize = 256;

/// A node's local transform: translation, rotation, scale (applied scale first).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trs {
    /// Translation (the file's units).
    pub translation: Vec3,
    /// Rotation (unit quaternion).
    pub rotation: Quat,
    /// Scale per axis.
    pub scale: Vec3,
}

impl Trs {
    /// The matrix T · R · S.
    pub fn matrix(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }
}

/// What a channel animates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Property {
    /// The node's translation (values: x, y, z).
    Translation,
    /// The node's rotation (values: quaternion x, y, z, w).
    Rotation,
    /// The node's scale (values: x, y, z).
    Scale,
}

/// How a channel's value moves between its keys.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// Linear between keys (spherical for rotations).
    Linear,
    /// The value of the last key at or before the time.
    Step,
}

/// One animated property of one node.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    /// The node it moves (an index into [`SkinnedMesh::nodes`]).
    pub node: usize,
    /// Which of the node's properties.
    pub property: Property,
    /// Linear or step.
    pub interpolation: Interpolation,
    /// Key times in seconds, increasing.
    pub times: Vec<f32>,
    /// One value per key (xyz in the first three components for translation and scale).
    pub values: Vec<Vec4>,
}

impl Channel {
    /// The channel's value at time `t` (clamped to its first and last keys).
    pub fn sample(&self, t: f32) -> Vec4 {
        let n = self.times.len();
        if n == 1 || t <= self.times[0] {
            return self.values[0];
        }
        if t >= self.times[n - 1] {
            return self.values[n - 1];
        }
        // The key interval holding t: times[k] <= t < times[k + 1].
        let k = self.times.partition_point(|&x| x <= t).saturating_sub(1);
        let (a, b) = (self.values[k], self.values[k + 1]);
        if self.interpolation == Interpolation::Step {
            return a;
        }
        let span = self.times[k + 1] - self.times[k];
        let f = if span > 0.0 {
            (t - self.times[k]) / span
        } else {
            0.0
        };
        match self.property {
            Property::Rotation => {
                let qa = Quat::from_vec4(a).normalize();
                let qb = Quat::from_vec4(b).normalize();
                Vec4::from(qa.slerp(qb, f))
            }
            _ => a.lerp(b, f),
        }
    }
}

/// A named animation: its channels and its length.
#[derive(Clone, Debug, PartialEq)]
pub struct Animation {
    /// The file's name for it (or `animation N`).
    pub name: String,
    /// Seconds from the first key to the last of all its channels.
    pub duration: f32,
    /// The channels, each on one node property.
    pub channels: Vec<Channel>,
}

/// A node of the file's node graph.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkinNode {
    /// Its parent node, if any.
    pub parent: Option<usize>,
    /// Its transform at rest (where no channel moves it).
    pub rest: Trs,
}

/// A skinned mesh, its skeleton and its animations, as read from a glTF file.
#[derive(Clone, Debug, PartialEq)]
pub struct SkinnedMesh {
    /// Vertex positions in the mesh's bind space (the file's units).
    pub positions: Vec<[f32; 3]>,
    /// Unit vertex normals in bind space.
    pub normals: Vec<[f32; 3]>,
    /// Up to four joints per vertex (indices into [`SkinnedMesh::joints`]).
    pub joint_indices: Vec<[u16; 4]>,
    /// The four joints' weights per vertex, adding up to 1.
    pub weights: Vec<[f32; 4]>,
    /// Three per triangle.
    pub indices: Vec<u32>,
    /// Every node of the file, parents before or after children (see `parent`).
    pub nodes: Vec<SkinNode>,
    /// The skin's joints, as node indices.
    pub joints: Vec<usize>,
    /// Per joint, the inverse of its global transform at bind time.
    pub inverse_bind: Vec<Mat4>,
    /// The file's animations.
    pub animations: Vec<Animation>,
}

impl SkinnedMesh {
    /// Reads and checks the first skinned mesh of the glTF file at `path`.
    pub fn load(path: &Path) -> Result<Self> {
        let gltf::Gltf {
            document: doc,
            blob,
        } = gltf::Gltf::open(path).map_err(|e| fail(path, e.to_string()))?;
        let base = path.parent().unwrap_or_else(|| Path::new("."));
        let buffers = read_gltf_buffers(path, base, &doc, blob)?;
        // A cyclic or shared node graph is refused here, before any walk over it.
        gltf_roots(path, &doc)?;

        let mut nodes: Vec<SkinNode> = doc
            .nodes()
            .map(|n| {
                let (t, r, s) = n.transform().decomposed();
                SkinNode {
                    parent: None,
                    rest: Trs {
                        translation: t.into(),
                        rotation: Quat::from_array(r).normalize(),
                        scale: s.into(),
                    },
                }
            })
            .collect();
        for n in doc.nodes() {
            for c in n.children() {
                nodes[c.index()].parent = Some(n.index());
            }
        }
        let Some(node) = doc
            .nodes()
            .find(|n| n.mesh().is_some() && n.skin().is_some())
        else {
            return Err(fail(path, "no node has both a mesh and a skin"));
        };
        let (mesh, skin) = match (node.mesh(), node.skin()) {
            (Some(m), Some(s)) => (m, s),
            _ => return Err(fail(path, "no node has both a mesh and a skin")),
        };
        let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
        if joints.is_empty() || joints.len() > MAX_JOINTS {
            return Err(fail(
                path,
                format!(
                    "skin {} has {} joints: allowed 1..={MAX_JOINTS}",
                    skin.index(),
                    joints.len()
                ),
            ));
        }
        let inverse_bind = read_inverse_bind(path, &skin, joints.len(), &buffers)?;

        let mut out = SkinnedMesh {
            positions: Vec::new(),
            normals: Vec::new(),
            joint_indices: Vec::new(),
            weights: Vec::new(),
            indices: Vec::new(),
            nodes,
            joints,
            inverse_bind,
            animations: Vec::new(),
        };
        for prim in mesh.primitives() {
            out.read_primitive(path, &prim, &buffers)?;
        }
        if out.indices.is_empty() {
            return Err(fail(
                path,
                format!("mesh {} has no triangles", mesh.index()),
            ));
        }
        for anim in doc.animations() {
            let json = &doc.as_json().animations[anim.index()];
            let a = read_animation(path, &anim, json, out.nodes.len(), &buffers)?;
            out.animations.push(a);
        }
        Ok(out)
    }

    /// Appends one triangle primitive's vertices, checked.
    fn read_primitive(
        &mut self,
        path: &Path,
        prim: &gltf::Primitive,
        buffers: &[Vec<u8>],
    ) -> Result<()> {
        if prim.mode() != gltf::mesh::Mode::Triangles {
            return Ok(());
        }
        let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d[..]));
        let here = format!("primitive {}", prim.index());
        let positions: Vec<[f32; 3]> = reader
            .read_positions()
            .ok_or_else(|| fail(path, format!("{here} has no readable POSITION")))?
            .collect();
        let joints: Vec<[u16; 4]> = reader
            .read_joints(0)
            .ok_or_else(|| fail(path, format!("{here} has no readable JOINTS_0")))?
            .into_u16()
            .collect();
        let weights: Vec<[f32; 4]> = reader
            .read_weights(0)
            .ok_or_else(|| fail(path, format!("{here} has no readable WEIGHTS_0")))?
            .into_f32()
            .collect();
        if joints.len() != positions.len() || weights.len() != positions.len() {
            return Err(fail(
                path,
                format!(
                    "{here}: {} positions but {} joint and {} weight entries",
                    positions.len(),
                    joints.len(),
                    weights.len()
                ),
            ));
        }
        let base = self.positions.len() as u32;
        for (v, (p, (j, w))) in positions
            .iter()
            .zip(joints.iter().zip(&weights))
            .enumerate()
        {
            if !p.iter().all(|c| c.is_finite()) {
                return Err(fail(path, format!("{here}: vertex {v} is not finite")));
            }
            for (k, &joint) in j.iter().enumerate() {
                if w[k] != 0.0 && usize::from(joint) >= self.joints.len() {
                    return Err(fail(
                        path,
                        format!(
                            "{here}: vertex {v} names joint {joint}, but the skin has {} \
                             joints (0..={})",
                            self.joints.len(),
                            self.joints.len() - 1
                        ),
                    ));
                }
            }
            let sum: f32 = w.iter().sum();
            if !w.iter().all(|x| x.is_finite() && *x >= 0.0) || sum <= 1e-6 {
                return Err(fail(
                    path,
                    format!("{here}: vertex {v}'s weights {w:?} must be >= 0 and not all 0"),
                ));
            }
            self.weights.push(w.map(|x| x / sum));
            // A joint with weight 0 may name anything; it is pointed at joint 0.
            self.joint_indices
                .push(std::array::from_fn(|k| if w[k] == 0.0 { 0 } else { j[k] }));
        }
        self.positions.extend_from_slice(&positions);
        let count = positions.len() as u32;
        let indices: Vec<u32> = match reader.read_indices() {
            Some(ix) => ix.into_u32().collect(),
            None => (0..count - count % 3).collect(),
        };
        if let Some(bad) = indices.iter().find(|&&i| i >= count) {
            return Err(fail(
                path,
                format!("{here}: index {bad} is past its {count} vertices"),
            ));
        }
        if (self.indices.len() + indices.len()) / 3 > MAX_TRIANGLES {
            return Err(fail(path, format!("more than {MAX_TRIANGLES} triangles")));
        }
        self.indices.extend(indices.iter().map(|i| base + i));
        let normals: Option<Vec<[f32; 3]>> = reader.read_normals().map(|n| n.collect());
        match normals.filter(|n| n.len() == positions.len()) {
            Some(n) => self.normals.extend(
                n.iter()
                    .map(|v| Vec3::from(*v).normalize_or(Vec3::Y).to_array()),
            ),
            None => self.normals.extend(area_normals(&positions, &indices)),
        }
        Ok(())
    }

    /// Every node's local transform at time `t` of `animation` (rest where no channel
    /// moves it; `None`: the rest pose). The time wraps around the animation's duration,
    /// so a walk cycle loops.
    pub fn local_pose(&self, animation: Option<usize>, t: f32) -> Vec<Trs> {
        let mut pose: Vec<Trs> = self.nodes.iter().map(|n| n.rest).collect();
        let Some(a) = animation.and_then(|k| self.animations.get(k)) else {
            return pose;
        };
        let t = if a.duration > 0.0 {
            t.rem_euclid(a.duration)
        } else {
            0.0
        };
        for c in &a.channels {
            let v = c.sample(t);
            let p = &mut pose[c.node];
            match c.property {
                Property::Translation => p.translation = v.truncate(),
                Property::Rotation => p.rotation = Quat::from_vec4(v).normalize(),
                Property::Scale => p.scale = v.truncate(),
            }
        }
        pose
    }

    /// Every node's global transform for a local pose (parents applied; the graph is a
    /// forest, checked at load).
    pub fn global_pose(&self, local: &[Trs]) -> Vec<Mat4> {
        let mut global: Vec<Option<Mat4>> = vec![None; self.nodes.len()];
        for start in 0..self.nodes.len() {
            // The chain up to a node already placed (or a root), then back down.
            let mut chain = vec![start];
            while let Some(p) = self.nodes[*chain.last().unwrap_or(&start)].parent {
                if global[p].is_some() {
                    break;
                }
                chain.push(p);
            }
            for &n in chain.iter().rev() {
                if global[n].is_some() {
                    continue;
                }
                let parent = self.nodes[n]
                    .parent
                    .and_then(|p| global[p])
                    .unwrap_or(Mat4::IDENTITY);
                global[n] = Some(parent * local[n].matrix());
            }
        }
        global.into_iter().map(|m| m.unwrap_or_default()).collect()
    }

    /// The skinning matrix of each joint at time `t` of `animation`: its global transform
    /// times its inverse bind matrix (identity at the bind pose).
    pub fn joint_matrices(&self, animation: Option<usize>, t: f32) -> Vec<Mat4> {
        let global = self.global_pose(&self.local_pose(animation, t));
        self.joints
            .iter()
            .zip(&self.inverse_bind)
            .map(|(&node, inv)| global[node] * *inv)
            .collect()
    }

    /// The vertices skinned by `joints` (linear blend skinning: each position moved by its
    /// four joints' matrices, weighted).
    pub fn skin(&self, joints: &[Mat4]) -> Vec<[f32; 3]> {
        self.positions
            .iter()
            .zip(self.joint_indices.iter().zip(&self.weights))
            .map(|(p, (j, w))| {
                let p = Vec3::from(*p);
                let mut out = Vec3::ZERO;
                for k in 0..4 {
                    if w[k] > 0.0 {
                        let m = joints.get(usize::from(j[k])).copied().unwrap_or_default();
                        out += w[k] * m.transform_point3(p);
                    }
                }
                out.to_array()
            })
            .collect()
    }

    /// The normals skinned by `joints`: each turned by its vertex's weighted matrix's
    /// linear part, renormalised (kept where that sum vanishes) — `skin.wgsl`'s twin.
    pub fn skin_normals(&self, joints: &[Mat4]) -> Vec<[f32; 3]> {
        self.normals
            .iter()
            .zip(self.joint_indices.iter().zip(&self.weights))
            .map(|(n, (j, w))| {
                let n = Vec3::from(*n);
                let mut m = Mat4::ZERO;
                for k in 0..4 {
                    let joint = joints.get(usize::from(j[k])).copied().unwrap_or_default();
                    m += joint * w[k];
                }
                let turned = m.transform_vector3(n);
                let len = turned.length();
                if len > 1e-8 { turned / len } else { n }.to_array()
            })
            .collect()
    }
}

/// The skin's inverse bind matrices (identity when the file gives none), each invertible.
fn read_inverse_bind(
    path: &Path,
    skin: &gltf::Skin,
    joints: usize,
    buffers: &[Vec<u8>],
) -> Result<Vec<Mat4>> {
    let Some(accessor) = skin.inverse_bind_matrices() else {
        return Ok(vec![Mat4::IDENTITY; joints]);
    };
    let read: Vec<Mat4> = skin
        .reader(|b| buffers.get(b.index()).map(|d| &d[..]))
        .read_inverse_bind_matrices()
        .ok_or_else(|| {
            fail(
                path,
                format!(
                    "skin {}: accessor {} (inverse bind matrices) cannot be read",
                    skin.index(),
                    accessor.index()
                ),
            )
        })?
        .map(|m| Mat4::from_cols_array_2d(&m))
        .collect();
    if read.len() < joints {
        return Err(fail(
            path,
            format!(
                "skin {}: {} inverse bind matrices for {joints} joints",
                skin.index(),
                read.len()
            ),
        ));
    }
    for (j, m) in read.iter().enumerate().take(joints) {
        let det = m.determinant();
        if !m.is_finite() || !det.is_finite() || det.abs() < 1e-12 {
            return Err(fail(
                path,
                format!(
                    "skin {}: joint {j}'s inverse bind matrix cannot be inverted \
                     (determinant {det})",
                    skin.index()
                ),
            ));
        }
    }
    Ok(read.into_iter().take(joints).collect())
}

/// One animation's channels, checked: a node that exists, keys that increase and agree in
/// number with the values, and interpolation linear or step.
fn read_animation(
    path: &Path,
    anim: &gltf::Animation,
    json: &gltf::json::Animation,
    nodes: usize,
    buffers: &[Vec<u8>],
) -> Result<Animation> {
    use gltf::animation::util::ReadOutputs;
    let name = anim
        .name()
        .map_or_else(|| format!("animation {}", anim.index()), str::to_string);
    let mut channels = Vec::new();
    let mut duration: f32 = 0.0;
    for ch in anim.channels() {
        let here = format!("{name}, channel {}", ch.index());
        // Read from the JSON before `target().node()`: the gltf crate's validation leaves
        // a channel's target unchecked, and its `node()` panics on a missing node.
        let node = json.channels[ch.index()].target.node.value();
        if node >= nodes {
            return Err(fail(
                path,
                format!(
                    "{here} aims at node {node}, which does not exist (the file has {nodes} \
                     nodes)"
                ),
            ));
        }
        let interpolation = match ch.sampler().interpolation() {
            gltf::animation::Interpolation::Linear => Interpolation::Linear,
            gltf::animation::Interpolation::Step => Interpolation::Step,
            gltf::animation::Interpolation::CubicSpline => {
                return Err(fail(
                    path,
                    format!("{here}: CUBICSPLINE interpolation is not supported (LINEAR or STEP)"),
                ))
            }
        };
        let reader = ch.reader(|b| buffers.get(b.index()).map(|d| &d[..]));
        let times: Vec<f32> = reader
            .read_inputs()
            .ok_or_else(|| fail(path, format!("{here}: its key times cannot be read")))?
            .collect();
        let (property, values): (Property, Vec<Vec4>) = match reader.read_outputs() {
            Some(ReadOutputs::Translations(t)) => (
                Property::Translation,
                t.map(|v| Vec3::from(v).extend(0.0)).collect(),
            ),
            Some(ReadOutputs::Rotations(r)) => (
                Property::Rotation,
                r.into_f32().map(Vec4::from_array).collect(),
            ),
            Some(ReadOutputs::Scales(s)) => (
                Property::Scale,
                s.map(|v| Vec3::from(v).extend(0.0)).collect(),
            ),
            Some(ReadOutputs::MorphTargetWeights(_)) => continue,
            None => return Err(fail(path, format!("{here}: its values cannot be read"))),
        };
        if times.is_empty() || times.len() != values.len() {
            return Err(fail(
                path,
                format!(
                    "{here}: {} key times but {} values",
                    times.len(),
                    values.len()
                ),
            ));
        }
        let increasing = times.windows(2).all(|w| w[0] < w[1]);
        if !times.iter().all(|t| t.is_finite() && *t >= 0.0) || !increasing {
            return Err(fail(
                path,
                format!("{here}: key times must be finite, >= 0 and increasing"),
            ));
        }
        if !values.iter().all(|v| v.is_finite()) {
            return Err(fail(path, format!("{here}: a value is not finite")));
        }
        duration = duration.max(*times.last().unwrap_or(&0.0));
        channels.push(Channel {
            node,
            property,
            interpolation,
            times,
            values,
        });
    }
    Ok(Animation {
        name,
        duration,
        channels,
    })
}

/// Area-weighted vertex normals of a triangle list.
fn area_normals(positions: &[[f32; 3]], indices: &[u32]) -> Vec<[f32; 3]> {
    let mut n = vec![Vec3::ZERO; positions.len()];
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| Vec3::from(positions[i as usize]));
        let face = (b - a).cross(c - a);
        for &i in t {
            n[i as usize] += face;
        }
    }
    n.into_iter()
        .map(|v| v.normalize_or(Vec3::Y).to_array())
        .collect()
}

#[cfg(test)]
#[path = "skin_tests.rs"]
mod tests;
