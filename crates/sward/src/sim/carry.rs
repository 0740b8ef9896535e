//! Grass carried by a moving object (issue 14, point 2: "on a moving object the grass moves
//! with it"). The blades of an object with `grass` and a `motion` are grown at the object's
//! rest transform; each step a compute pass (`shaders/carry.wgsl`, twin [`carry_cpu`])
//! puts them where the object is now:
//! - the root, the up vector and the rest tip (the recovery force's target) from immutable
//!   copies of their rest values through M(t) = T(t) · T_rest⁻¹, so they never drift;
//! - the moving points v1 and v2 through the step's motion M(t) · M(t − Δt)⁻¹, so a blade
//!   keeps its bend and its trail as the object carries it, and the update that follows
//!   bends it further.
//!
//! The CPU moves the objects' patch boxes (per patch, not per blade): the rest box's corners
//! through M(t), and the smallest up.y of the patch (the distance test's lean bound) from a
//! cone around the patch's rest ups, turned by M(t). The carried blades' rest copies are
//! 48 bytes each, kept only for objects that move.

use bytemuck::{Pod, Zeroable};
use glam::{DMat4, Mat4, Vec3};

use crate::field::HeightField;
use crate::scene::MeshObject;
use crate::sim::colliders::object_transform;
use crate::sim::layout::{Blade, BladeState, PatchBox};

pub use crate::field::carried::{Carried, CarriedBlade, CarriedPatches, Grown};

/// One moving object's motion this step (`CarryObject` in `carry.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct CarryObject {
    /// M(t) = T(t) · T_rest⁻¹, column-major: rest world space to where the object is now.
    pub model: [[f32; 4]; 4],
    /// M(t) · M(t − Δt)⁻¹: last step's pose to this one's.
    pub step: [[f32; 4]; 4],
}

const _: () = assert!(std::mem::size_of::<CarryObject>() == 128);

/// One step of the carried objects at `time`: each one's M(t) (its transform now times the
/// inverse of its rest transform, composed in f64) and its motion from `previous` (last
/// step's M, identity at the start), which becomes this step's. The renderer and the CPU
/// twin both step through here.
pub fn step(
    carried: &Carried,
    objects: &[MeshObject],
    terrain: &HeightField,
    time: f32,
    previous: &mut [Mat4],
) -> (Vec<Mat4>, Vec<CarryObject>) {
    let models: Vec<Mat4> = carried
        .objects
        .iter()
        .map(|c| {
            let now = object_transform(&objects[c.object], terrain, time);
            (now.as_dmat4() * c.rest.as_dmat4().inverse()).as_mat4()
        })
        .collect();
    let motions = models
        .iter()
        .zip(previous.iter())
        .map(|(m, p)| {
            let step: DMat4 = m.as_dmat4() * p.as_dmat4().inverse();
            CarryObject {
                model: m.to_cols_array_2d(),
                step: step.as_mat4().to_cols_array_2d(),
            }
        })
        .collect();
    previous.copy_from_slice(&models);
    (models, motions)
}

/// The carried objects' patch boxes under `models`: each rest box's eight corners through
/// M(t) (a box of roots grown by the tallest blade stays one, turned), and max.w the
/// smallest up.y the turned cone of the patch's ups allows. `(first patch, boxes)` per
/// object.
pub fn moved_boxes(carried: &Carried, models: &[Mat4]) -> Vec<(usize, Vec<PatchBox>)> {
    carried
        .objects
        .iter()
        .zip(models)
        .map(|(c, m)| {
            // A motion without a turn leaves every up vector as it was, and the rest bound.
            let turns = m.transform_vector3(Vec3::X).distance(Vec3::X) > 1e-6
                || m.transform_vector3(Vec3::Y).distance(Vec3::Y) > 1e-6;
            let boxes = c
                .boxes
                .iter()
                .zip(&c.cones)
                .map(|(b, &(axis, angle))| {
                    let mut lo = Vec3::splat(f32::INFINITY);
                    let mut hi = Vec3::splat(f32::NEG_INFINITY);
                    for k in 0..8 {
                        let corner = Vec3::new(
                            if k & 1 == 0 { b.min[0] } else { b.max[0] },
                            if k & 2 == 0 { b.min[1] } else { b.max[1] },
                            if k & 4 == 0 { b.min[2] } else { b.max[2] },
                        );
                        let p = m.transform_point3(corner);
                        lo = lo.min(p);
                        hi = hi.max(p);
                    }
                    let turned = m.transform_vector3(axis).normalize_or_zero();
                    let tilt = turned.y.clamp(-1.0, 1.0).acos() + angle;
                    let up_y = if !turns {
                        b.max[3]
                    } else if tilt >= std::f32::consts::PI {
                        -1.0
                    } else {
                        tilt.cos()
                    };
                    PatchBox {
                        min: [lo.x, lo.y, lo.z, b.min[3]],
                        max: [hi.x, hi.y, hi.z, up_y],
                    }
                })
                .collect();
            (c.first_patch, boxes)
        })
        .collect()
}

/// The twin of `carry.wgsl`: every carried blade put where its object is now.
pub fn carry_cpu(
    blades: &mut [Blade],
    states: &mut [BladeState],
    carried: &[CarriedBlade],
    objects: &[CarryObject],
) {
    for c in carried {
        let o = &objects[c.object as usize];
        let model = Mat4::from_cols_array_2d(&o.model);
        let step = Mat4::from_cols_array_2d(&o.step);
        let i = c.blade as usize;
        let b = &mut blades[i];
        let v0 = model * Vec3::from(c.v0).extend(1.0);
        // Divided by its length as the kernel does (not glam's reciprocal multiply).
        let turned = (model * Vec3::from(c.up).extend(0.0)).truncate();
        let len = turned.length();
        let up = if len > 0.0 { turned / len } else { Vec3::ZERO };
        let v1 = step * Vec3::new(b.v1_height[0], b.v1_height[1], b.v1_height[2]).extend(1.0);
        let v2 = step * Vec3::new(b.v2_width[0], b.v2_width[1], b.v2_width[2]).extend(1.0);
        let tip = model * Vec3::from(c.tip).extend(1.0);
        b.v0_dir = [v0.x, v0.y, v0.z, b.v0_dir[3]];
        b.up_stiffness = [up.x, up.y, up.z, b.up_stiffness[3]];
        b.v1_height = [v1.x, v1.y, v1.z, b.v1_height[3]];
        b.v2_width = [v2.x, v2.y, v2.z, b.v2_width[3]];
        let s = &mut states[i];
        s.rest_eta = [tip.x, tip.y, tip.z, s.rest_eta[3]];
    }
}
