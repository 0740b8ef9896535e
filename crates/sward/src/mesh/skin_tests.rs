//! The skin loader and pose evaluation against hand-computed values, and every bad skin
//! the loader must refuse with the file and what is wrong.

use super::*;
use glam::{Mat4, Quat, Vec3};
use std::path::PathBuf;

/// A two-joint arm: joint 0 (node 0) at the origin, joint 1 (node 1) one metre up as its
/// child, the mesh on node 2. Vertex 0 follows joint 0, vertex 1 (two metres up) joint 1,
/// vertex 2 both halves. Animation "bend": node 1 turns 90 degrees about z from t = 0 to
/// 1 s (linear); animation "hop": node 0 steps to x = 2 at t = 1 s (step).
struct Arm {
    joints: [[u16; 4]; 3],
    weights: [[f32; 4]; 3],
    inverse_bind: [Mat4; 2],
    /// The node the rotation channel aims at.
    target: u32,
    /// Node 1's children (a cycle when it names node 0).
    children_of_1: &'static str,
    interpolation: &'static str,
}

impl Default for Arm {
    fn default() -> Self {
        Arm {
            joints: [[0, 0, 0, 0], [1, 0, 0, 0], [0, 1, 0, 0]],
            weights: [
                [1.0, 0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0, 0.0],
                [0.5, 0.5, 0.0, 0.0],
            ],
            inverse_bind: [
                Mat4::IDENTITY,
                Mat4::from_translation(Vec3::new(0.0, -1.0, 0.0)),
            ],
            target: 1,
            children_of_1: "",
            interpolation: "LINEAR",
        }
    }
}

impl Arm {
    /// Writes the arm as `name.gltf` and `name.bin` in a fresh directory.
    fn write(&self, name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("sward-skin-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut bin: Vec<u8> = Vec::new();
        let f32s =
            |bin: &mut Vec<u8>, v: &[f32]| bin.extend(v.iter().flat_map(|f| f.to_le_bytes()));
        f32s(&mut bin, &[0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 1.0, 1.0, 0.0]); // 0: positions, 36 B
        for j in self.joints {
            bin.extend(j.iter().flat_map(|x| x.to_le_bytes())); // 36: joints, 24 B
        }
        for w in self.weights {
            f32s(&mut bin, &w); // 60: weights, 48 B
        }
        for m in self.inverse_bind {
            f32s(&mut bin, &m.to_cols_array()); // 108: inverse bind, 128 B
        }
        f32s(&mut bin, &[0.0, 1.0]); // 236: key times, 8 B
        let q = Quat::from_rotation_z(std::f32::consts::FRAC_PI_2);
        f32s(&mut bin, &[0.0, 0.0, 0.0, 1.0, q.x, q.y, q.z, q.w]); // 244: rotations, 32 B
        f32s(&mut bin, &[0.0, 0.0, 0.0, 2.0, 0.0, 0.0]); // 276: translations, 24 B
        assert_eq!(bin.len(), 300);
        std::fs::write(dir.join(format!("{name}.bin")), &bin).unwrap();
        let view = |offset: usize, len: usize| {
            format!(r#"{{"buffer":0,"byteOffset":{offset},"byteLength":{len}}}"#)
        };
        let text = format!(
            r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0,2]}}],
            "nodes":[{{"children":[1]}},{{"translation":[0,1,0]{children}}},{{"mesh":0,"skin":0}}],
            "skins":[{{"joints":[0,1],"inverseBindMatrices":3}}],
            "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"JOINTS_0":1,"WEIGHTS_0":2}}}}]}}],
            "animations":[
              {{"name":"bend","channels":[{{"sampler":0,"target":{{"node":{target},"path":"rotation"}}}}],
                "samplers":[{{"input":4,"output":5,"interpolation":"{interp}"}}]}},
              {{"name":"hop","channels":[{{"sampler":0,"target":{{"node":0,"path":"translation"}}}}],
                "samplers":[{{"input":4,"output":6,"interpolation":"STEP"}}]}}],
            "accessors":[
              {{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,2,0]}},
              {{"bufferView":1,"componentType":5123,"count":3,"type":"VEC4"}},
              {{"bufferView":2,"componentType":5126,"count":3,"type":"VEC4"}},
              {{"bufferView":3,"componentType":5126,"count":2,"type":"MAT4"}},
              {{"bufferView":4,"componentType":5126,"count":2,"type":"SCALAR","min":[0],"max":[1]}},
              {{"bufferView":5,"componentType":5126,"count":2,"type":"VEC4"}},
              {{"bufferView":6,"componentType":5126,"count":2,"type":"VEC3"}}],
            "bufferViews":[{},{},{},{},{},{},{}],
            "buffers":[{{"byteLength":300,"uri":"{name}.bin"}}]}}"#,
            view(0, 36),
            view(36, 24),
            view(60, 48),
            view(108, 128),
            view(236, 8),
            view(244, 32),
            view(276, 24),
            children = if self.children_of_1.is_empty() {
                String::new()
            } else {
                format!(r#","children":[{}]"#, self.children_of_1)
            },
            target = self.target,
            interp = self.interpolation,
        );
        let path = dir.join(format!("{name}.gltf"));
        std::fs::write(&path, text).unwrap();
        path
    }
}

fn close(a: [f32; 3], b: [f32; 3]) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-5)
}

#[test]
fn the_arm_loads_with_its_skin_and_animations() {
    let m = SkinnedMesh::load(&Arm::default().write("arm")).unwrap();
    assert_eq!(m.joints, vec![0, 1]);
    assert_eq!(m.nodes[1].parent, Some(0));
    assert_eq!(m.indices, vec![0, 1, 2]);
    assert_eq!(m.animations.len(), 2);
    assert_eq!(m.animations[0].name, "bend");
    assert_eq!(m.animations[0].duration, 1.0);
    // At the bind pose every skinning matrix is the identity: the mesh is where it was.
    for j in m.joint_matrices(None, 0.0) {
        assert!(j.abs_diff_eq(Mat4::IDENTITY, 1e-6), "{j}");
    }
    assert_eq!(m.skin(&m.joint_matrices(None, 0.0)), m.positions);
}

#[test]
fn joint_transforms_at_a_time_match_the_hand_computed_ones() {
    let m = SkinnedMesh::load(&Arm::default().write("pose")).unwrap();
    // t = 0.5 s of "bend": node 1 turned 45 degrees about z around its origin (0, 1, 0).
    let joints = m.joint_matrices(Some(0), 0.5);
    let expected = Mat4::from_translation(Vec3::Y)
        * Mat4::from_rotation_z(std::f32::consts::FRAC_PI_4)
        * Mat4::from_translation(-Vec3::Y);
    assert!(joints[0].abs_diff_eq(Mat4::IDENTITY, 1e-6));
    assert!(
        joints[1].abs_diff_eq(expected, 1e-5),
        "{}\n{expected}",
        joints[1]
    );
    let skinned = m.skin(&joints);
    let s = std::f32::consts::FRAC_1_SQRT_2;
    // Vertex 1, a metre above the elbow, swings 45 degrees to -x.
    assert!(close(skinned[1], [-s, 1.0 + s, 0.0]), "{:?}", skinned[1]);
    // Vertex 2 takes half of each joint's motion.
    let half =
        0.5 * Vec3::new(1.0, 1.0, 0.0) + 0.5 * expected.transform_point3(Vec3::new(1.0, 1.0, 0.0));
    assert!(close(skinned[2], half.to_array()), "{:?}", skinned[2]);
}

#[test]
fn step_channels_hold_their_key_and_time_wraps() {
    let m = SkinnedMesh::load(&Arm::default().write("hop")).unwrap();
    // "hop" is a STEP translation of node 0 to x = 2 at t = 1 s; the animation lasts 1 s.
    let at = |t: f32| m.local_pose(Some(1), t)[0].translation;
    assert_eq!(at(0.99), Vec3::ZERO, "a step holds the earlier key");
    assert_eq!(at(1.5), Vec3::ZERO, "time wraps around the duration");
    let c = &m.animations[1].channels[0];
    assert_eq!(c.interpolation, Interpolation::Step);
    assert_eq!(c.sample(1.0), Vec3::new(2.0, 0.0, 0.0).extend(0.0));
    // The same channel read linearly would be half-way at 0.5 s.
    let linear = Channel {
        interpolation: Interpolation::Linear,
        ..c.clone()
    };
    assert_eq!(linear.sample(0.5).x, 1.0);
}

fn load_error(arm: Arm, name: &str) -> String {
    match SkinnedMesh::load(&arm.write(name)) {
        Ok(_) => panic!("{name} loaded"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn bad_skins_are_refused_with_the_file_and_what_is_wrong() {
    let e = load_error(
        Arm {
            joints: [[0, 0, 0, 0], [5, 0, 0, 0], [0, 1, 0, 0]],
            ..Arm::default()
        },
        "joint_range",
    );
    assert!(
        e.contains("joint_range.gltf") && e.contains("vertex 1 names joint 5"),
        "{e}"
    );
    assert!(e.contains("the skin has 2 joints"), "{e}");

    let e = load_error(
        Arm {
            inverse_bind: [Mat4::IDENTITY, Mat4::ZERO],
            ..Arm::default()
        },
        "singular",
    );
    assert!(
        e.contains("joint 1's inverse bind matrix cannot be inverted"),
        "{e}"
    );

    let e = load_error(
        Arm {
            target: 9,
            ..Arm::default()
        },
        "missing_node",
    );
    assert!(e.contains("missing_node.gltf") && e.contains("node"), "{e}");

    let e = load_error(
        Arm {
            children_of_1: "0",
            ..Arm::default()
        },
        "cycle",
    );
    assert!(
        e.contains("cycle.gltf") && e.contains("ancestor") || e.contains("tree"),
        "{e}"
    );

    let e = load_error(
        Arm {
            weights: [[1.0, 0.0, 0.0, 0.0], [0.0; 4], [0.5, 0.5, 0.0, 0.0]],
            ..Arm::default()
        },
        "weights",
    );
    assert!(e.contains("vertex 1's weights"), "{e}");

    let e = load_error(
        Arm {
            interpolation: "CUBICSPLINE",
            ..Arm::default()
        },
        "cubic",
    );
    assert!(e.contains("CUBICSPLINE"), "{e}");
}
