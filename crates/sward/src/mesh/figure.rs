//! A walking figure sward builds itself (issue 29, point 1): a 1.8 m figure of boxes — pelvis,
//! torso, head, thighs, shins with feet, arms — each bound to one joint of a nine-joint
//! skeleton (the corners at a joint's pivot 60/40 with its parent, so it bends there), and a looped one-second walk cycle ("walk": thighs and arms swinging in
//! opposition, knees bending in the swing, the hips bobbing twice a cycle), written as one
//! glTF 2.0 file with its buffer embedded. `sward figure --out FILE` writes it;
//! `assets/models/walker.gltf` is its output. It is read back like any other file by
//! [`super::skin::SkinnedMesh::load`].

use glam::{Mat4, Quat, Vec3};
use serde_json::json;

/// The skeleton: name, parent, global position at rest (m). Joint k is node k.
const JOINTS: [(&str, Option<usize>, [f32; 3]); 9] = [
    ("hips", None, [0.0, 0.95, 0.0]),
    ("spine", Some(0), [0.0, 1.1, 0.0]),
    ("head", Some(1), [0.0, 1.6, 0.0]),
    ("thigh.L", Some(0), [0.1, 0.92, 0.0]),
    ("shin.L", Some(3), [0.1, 0.5, 0.0]),
    ("thigh.R", Some(0), [-0.1, 0.92, 0.0]),
    ("shin.R", Some(5), [-0.1, 0.5, 0.0]),
    ("arm.L", Some(1), [0.24, 1.52, 0.0]),
    ("arm.R", Some(1), [-0.24, 1.52, 0.0]),
];

/// The boxes: joint, centre at rest (m), size (m).
const BOXES: [(usize, [f32; 3], [f32; 3]); 11] = [
    (0, [0.0, 0.98, 0.0], [0.3, 0.16, 0.18]),
    (1, [0.0, 1.32, 0.0], [0.36, 0.48, 0.2]),
    (2, [0.0, 1.7, 0.0], [0.2, 0.24, 0.22]),
    (3, [0.1, 0.71, 0.0], [0.13, 0.42, 0.13]),
    (4, [0.1, 0.28, 0.0], [0.11, 0.42, 0.11]),
    (4, [0.1, 0.04, 0.05], [0.11, 0.08, 0.24]),
    (5, [-0.1, 0.71, 0.0], [0.13, 0.42, 0.13]),
    (6, [-0.1, 0.28, 0.0], [0.11, 0.42, 0.11]),
    (6, [-0.1, 0.04, 0.05], [0.11, 0.08, 0.24]),
    (7, [0.27, 1.24, 0.0], [0.09, 0.56, 0.09]),
    (8, [-0.27, 1.24, 0.0], [0.09, 0.56, 0.09]),
];

/// Keys per walk cycle (plus the closing one at 1 s, equal to the first).
const KEYS: usize = 16;

/// The walk's local rotation of joint `j` at phase `phi` (radians, one cycle = 2 pi):
/// about x, positive swinging the limb's lower end backwards (-z).
fn walk_angle(j: usize, phi: f32) -> f32 {
    let s = phi.sin();
    match j {
        3 => -0.5 * s,                         // left thigh forward while sin > 0
        5 => 0.5 * s,                          // right thigh in opposition
        4 => 0.7 * (phi + 0.6).cos().max(0.0), // knees bend in the swing
        6 => 0.7 * (phi + 0.6 + std::f32::consts::PI).cos().max(0.0),
        7 => 0.4 * s, // arms opposite to the legs
        8 => -0.4 * s,
        _ => 0.0,
    }
}

/// The figure as glTF JSON text with its buffer embedded (base64).
pub fn walker_gltf() -> String {
    let mut positions: Vec<[f32; 3]> = Vec::new();
    let mut normals: Vec<[f32; 3]> = Vec::new();
    let mut joints: Vec<[u16; 4]> = Vec::new();
    let mut weights: Vec<[f32; 4]> = Vec::new();
    let mut indices: Vec<u32> = Vec::new();
    for (joint, centre, size) in BOXES {
        let c = Vec3::from(centre);
        let h = Vec3::from(size) * 0.5;
        for axis in [
            Vec3::X,
            Vec3::NEG_X,
            Vec3::Y,
            Vec3::NEG_Y,
            Vec3::Z,
            Vec3::NEG_Z,
        ] {
            // u x w = axis: the quad below runs counter-clockwise seen from outside.
            let u = Vec3::new(axis.z, axis.x, axis.y);
            let w = axis.cross(u);
            let first = positions.len() as u32;
            for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let p = c + h * (axis + a * u + b * w);
                positions.push(p.to_array());
                normals.push(axis.to_array());
                // A corner at the joint's own pivot follows its parent partly, so the
                // figure bends there instead of breaking apart.
                let at_pivot = (p.y - JOINTS[joint].2[1]).abs() < 0.03;
                match JOINTS[joint].1.filter(|_| at_pivot) {
                    Some(parent) => {
                        joints.push([joint as u16, parent as u16, 0, 0]);
                        weights.push([0.6, 0.4, 0.0, 0.0]);
                    }
                    None => {
                        joints.push([joint as u16, 0, 0, 0]);
                        weights.push([1.0, 0.0, 0.0, 0.0]);
                    }
                }
            }
            indices.extend([first, first + 1, first + 2, first, first + 2, first + 3]);
        }
    }
    let n = positions.len();
    let mut bin: Vec<u8> = Vec::new();
    let push_f32 = |bin: &mut Vec<u8>, v: &[f32]| {
        bin.extend(v.iter().flat_map(|x| x.to_le_bytes()));
    };
    let mut views = Vec::new();
    let mut view = |bin: &Vec<u8>, start: usize| {
        views.push(json!({"buffer": 0, "byteOffset": start, "byteLength": bin.len() - start}));
        views.len() - 1
    };
    let start = bin.len();
    positions.iter().for_each(|p| push_f32(&mut bin, p));
    let v_pos = view(&bin, start);
    let start = bin.len();
    normals.iter().for_each(|p| push_f32(&mut bin, p));
    let v_nrm = view(&bin, start);
    let start = bin.len();
    joints
        .iter()
        .for_each(|j| bin.extend(j.iter().flat_map(|x| x.to_le_bytes())));
    let v_jnt = view(&bin, start);
    let start = bin.len();
    weights.iter().for_each(|w| push_f32(&mut bin, w));
    let v_wgt = view(&bin, start);
    let start = bin.len();
    indices.iter().for_each(|i| bin.extend(i.to_le_bytes()));
    let v_idx = view(&bin, start);
    let start = bin.len();
    for (_, _, at) in JOINTS {
        push_f32(
            &mut bin,
            &Mat4::from_translation(-Vec3::from(at)).to_cols_array(),
        );
    }
    let v_ibm = view(&bin, start);
    // The walk: one input of key times, one output per animated joint.
    let times: Vec<f32> = (0..=KEYS).map(|k| k as f32 / KEYS as f32).collect();
    let start = bin.len();
    push_f32(&mut bin, &times);
    let v_time = view(&bin, start);
    let mut outputs = Vec::new();
    for j in 3..9 {
        let start = bin.len();
        for t in &times {
            let q = Quat::from_rotation_x(walk_angle(j, std::f32::consts::TAU * t));
            push_f32(&mut bin, &q.to_array());
        }
        outputs.push((j, "rotation", view(&bin, start)));
    }
    let start = bin.len();
    for t in &times {
        let bob = 0.025 * (2.0 * std::f32::consts::TAU * t).cos();
        push_f32(&mut bin, &[0.0, JOINTS[0].2[1] + bob, 0.0]);
    }
    outputs.push((0, "translation", view(&bin, start)));

    let (lo, hi) = positions.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(Vec3::from(*p)), hi.max(Vec3::from(*p))),
    );
    let mut accessors = vec![
        json!({"bufferView": v_pos, "componentType": 5126, "count": n, "type": "VEC3",
               "min": lo.to_array(), "max": hi.to_array()}),
        json!({"bufferView": v_nrm, "componentType": 5126, "count": n, "type": "VEC3"}),
        json!({"bufferView": v_jnt, "componentType": 5123, "count": n, "type": "VEC4"}),
        json!({"bufferView": v_wgt, "componentType": 5126, "count": n, "type": "VEC4"}),
        json!({"bufferView": v_idx, "componentType": 5125, "count": indices.len(), "type": "SCALAR"}),
        json!({"bufferView": v_ibm, "componentType": 5126, "count": JOINTS.len(), "type": "MAT4"}),
        json!({"bufferView": v_time, "componentType": 5126, "count": times.len(), "type": "SCALAR",
               "min": [0.0], "max": [1.0]}),
    ];
    let mut channels = Vec::new();
    let mut samplers = Vec::new();
    for (j, property, v) in outputs {
        let kind = if property == "rotation" {
            "VEC4"
        } else {
            "VEC3"
        };
        accessors.push(
            json!({"bufferView": v, "componentType": 5126, "count": times.len(), "type": kind}),
        );
        samplers
            .push(json!({"input": 6, "output": accessors.len() - 1, "interpolation": "LINEAR"}));
        channels
            .push(json!({"sampler": samplers.len() - 1, "target": {"node": j, "path": property}}));
    }
    let mut nodes: Vec<serde_json::Value> = JOINTS
        .iter()
        .enumerate()
        .map(|(k, (name, parent, at))| {
            let local = match parent {
                Some(p) => Vec3::from(*at) - Vec3::from(JOINTS[*p].2),
                None => Vec3::from(*at),
            };
            let children: Vec<usize> = (0..JOINTS.len())
                .filter(|&c| JOINTS[c].1 == Some(k))
                .collect();
            let mut node = json!({"name": name, "translation": local.to_array()});
            if !children.is_empty() {
                node["children"] = json!(children);
            }
            node
        })
        .collect();
    nodes.push(json!({"name": "walker", "mesh": 0, "skin": 0}));
    let doc = json!({
        "asset": {"version": "2.0", "generator": "sward figure (mesh::figure)"},
        "scene": 0,
        "scenes": [{"nodes": [0, JOINTS.len()]}],
        "nodes": nodes,
        "skins": [{"joints": (0..JOINTS.len()).collect::<Vec<_>>(), "inverseBindMatrices": 5, "skeleton": 0}],
        "meshes": [{"name": "walker", "primitives": [{
            "attributes": {"POSITION": 0, "NORMAL": 1, "JOINTS_0": 2, "WEIGHTS_0": 3},
            "indices": 4}]}],
        "animations": [{"name": "walk", "channels": channels, "samplers": samplers}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": bin.len(),
                     "uri": format!("data:application/octet-stream;base64,{}", base64(&bin))}],
    });
    serde_json::to_string_pretty(&doc).unwrap_or_default()
}

/// Standard base64 with padding (RFC 4648), for the embedded buffer.
pub fn base64(bytes: &[u8]) -> String {
    const T: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for c in bytes.chunks(3) {
        let n = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for k in 0..4 {
            if k <= c.len() {
                out.push(T[((n >> (18 - 6 * k)) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::skin::SkinnedMesh;

    #[test]
    fn base64_matches_the_rfc_examples() {
        assert_eq!(base64(b"f"), "Zg==");
        assert_eq!(base64(b"fo"), "Zm8=");
        assert_eq!(base64(b"foobar"), "Zm9vYmFy");
    }

    #[test]
    fn the_walker_reads_back_and_walks() {
        let dir = std::env::temp_dir().join(format!("sward-walker-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("walker.gltf");
        std::fs::write(&path, walker_gltf()).unwrap();
        let m = SkinnedMesh::load(&path).unwrap();
        assert_eq!(m.joints.len(), 9);
        assert_eq!(m.indices.len(), BOXES.len() * 36);
        let walk = m.animations.iter().position(|a| a.name == "walk").unwrap();
        assert_eq!(m.animations[walk].duration, 1.0);
        // At rest the feet touch the ground (y = 0) and the head tops out near 1.82 m.
        let (lo, hi) = m
            .positions
            .iter()
            .fold((f32::MAX, f32::MIN), |(lo, hi), p| {
                (lo.min(p[1]), hi.max(p[1]))
            });
        assert!(lo.abs() < 1e-6 && (hi - 1.82).abs() < 1e-5, "{lo} {hi}");
        // A quarter into the cycle the left foot is ahead (+z) and the right one behind.
        let skinned = m.skin(&m.joint_matrices(Some(walk), 0.25));
        let foot_z = |x_sign: f32| {
            let feet: Vec<f32> = skinned
                .iter()
                .zip(&m.positions)
                .filter(|(_, rest)| rest[1] < 0.09 && rest[0] * x_sign > 0.0)
                .map(|(p, _)| p[2])
                .collect();
            feet.iter().sum::<f32>() / feet.len() as f32
        };
        assert!(
            foot_z(1.0) > 0.2 && foot_z(-1.0) < -0.2,
            "{} {}",
            foot_z(1.0),
            foot_z(-1.0)
        );
    }
}
