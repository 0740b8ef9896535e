//! A blade as the field holds it, and its geometry: the paper's four 4D vectors (Jahrmann &
//! Wimmer 2017, Section 4), the state beside it, the patch boxes, and the rest pose the
//! field is generated in (the blade's frame, its curve length and the state validation of
//! Eq. 9–13 that makes the rest pose a fixed point). They sit with the field, below the
//! simulation, because generating a field needs them and the simulation steps what the
//! field generated; `sim::layout` and `sim::reference` re-export them.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

/// Workgroup size of every per-blade compute pass; patches are a multiple of it.
pub const WORKGROUP_SIZE: u32 = 64;

/// One blade of grass: the paper's four 4D vectors (Section 4).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct Blade {
    /// v0 (root, fixed) and the direction angle in radians.
    pub v0_dir: [f32; 4],
    /// v1 (middle control point) and the height h.
    pub v1_height: [f32; 4],
    /// v2 (tip, moved by the forces) and the width w.
    pub v2_width: [f32; 4],
    /// Local up vector and the stiffness s.
    pub up_stiffness: [f32; 4],
}

/// Per-blade simulation state beside the blade: the rest tip I_v2 and the collision
/// strength η (the paper keeps η in the fourth channel of its force map).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct BladeState {
    /// xyz: the rest position of the tip I_v2 (where recovery pulls it); w: the collision
    /// strength η (Eq. 2).
    pub rest_eta: [f32; 4],
}

/// A patch's bounding box, already grown by the tallest blade so that it holds every pose.
/// `min[3]`: 1 for an empty patch; `max[3]`: the smallest up.y of its blades.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct PatchBox {
    /// The box's lowest corner (xyz); w: 1 for an empty patch, else 0.
    pub min: [f32; 4],
    /// The box's highest corner (xyz); w: the smallest up.y of the patch's blades.
    pub max: [f32; 4],
}

/// The blade's width direction and front direction (perpendicular to width and up), from
/// its up vector and direction angle. Same construction as `blade_frame` in WGSL.
pub fn blade_frame(up: Vec3, angle: f32) -> (Vec3, Vec3) {
    let reference = if up.z.abs() > 0.99 { Vec3::X } else { Vec3::Z };
    let tx = up.cross(reference).normalize();
    let tz = tx.cross(up);
    let width_dir = tx * angle.cos() + tz * angle.sin();
    let front = width_dir.cross(up);
    (width_dir, front)
}

/// The three validation steps (Eq. 9–13): v2 above the local ground plane, v1 placed from
/// v2, curve length corrected to the height. Returns the corrected (v1, v2).
pub fn validate(v0: Vec3, v2: Vec3, up: Vec3, height: f32) -> (Vec3, Vec3) {
    // Eq. 9
    let v2 = v2 - up * (up.dot(v2 - v0)).min(0.0);
    // Eq. 10
    let rel = v2 - v0;
    let l_proj = (rel - up * rel.dot(up)).length();
    // Eq. 11
    let v1 = v0 + up * height * (1.0 - l_proj / height).max(0.05 * (l_proj / height).max(1.0));
    // Eq. 12 with n = 2
    let l0 = (v2 - v0).length();
    let l1 = (v1 - v0).length() + (v2 - v1).length();
    let length = (2.0 * l0 + l1) / 3.0;
    // Eq. 13
    let r = height / length;
    let v1c = v0 + r * (v1 - v0);
    let v2c = v1c + r * (v2 - v1);
    (v1c, v2c)
}

/// Approximate curve length of a quadratic Bézier (Eq. 12, n = 2).
pub fn curve_length(v0: Vec3, v1: Vec3, v2: Vec3) -> f32 {
    let l0 = (v2 - v0).length();
    let l1 = (v1 - v0).length() + (v2 - v1).length();
    (2.0 * l0 + l1) / 3.0
}

/// The rest pose of a blade leaning `bend` radians towards its front: the tip on that
/// direction at the distance where the validated curve length equals the height, so that
/// the rest pose is a fixed point of the validation (and of the update without forces).
pub fn rest_pose(v0: Vec3, up: Vec3, front: Vec3, height: f32, bend: f32) -> (Vec3, Vec3) {
    let dir = up * bend.cos() + front * bend.sin();
    let length_at = |lambda: f32| {
        let v2 = v0 + dir * lambda;
        let rel = v2 - v0;
        let l_proj = (rel - up * rel.dot(up)).length();
        let v1 = v0 + up * height * (1.0 - l_proj / height).max(0.05 * (l_proj / height).max(1.0));
        curve_length(v0, v1, v2)
    };
    // The curve length grows monotonically with the tip distance: bisect on [0, h].
    let (mut lo, mut hi) = (0.0f32, height);
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if length_at(mid) < height {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let v2 = v0 + dir * (0.5 * (lo + hi));
    validate(v0, v2, up, height)
}
