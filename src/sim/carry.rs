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

/// The rest values of one carried blade (`CarriedBlade` in `carry.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct CarriedBlade {
    /// Root at rest, world space.
    pub v0: [f32; 3],
    /// Index of the blade in the field.
    pub blade: u32,
    /// Up vector at rest.
    pub up: [f32; 3],
    /// Index into the step's object motions.
    pub object: u32,
    /// Rest tip at rest (`BladeState::rest_eta.xyz`).
    pub tip: [f32; 3],
    pub _pad: u32,
}

const _: () = assert!(std::mem::size_of::<CarriedBlade>() == 48);

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

/// The patches of one carried object, at rest.
#[derive(Clone, Debug, PartialEq)]
pub struct CarriedPatches {
    /// Index of the object in `scene.objects`.
    pub object: usize,
    /// Its rest transform T_rest (what the grass was grown at).
    pub rest: Mat4,
    /// Index of its first patch in the field.
    pub first_patch: usize,
    /// Its patches' boxes at rest.
    pub boxes: Vec<PatchBox>,
    /// Per patch: the mean of its blades' rest ups and the largest angle (radians) between
    /// it and any of them.
    pub cones: Vec<(Vec3, f32)>,
}

/// An object's grass as grown at rest, and where it sits in the field.
pub struct Grown<'a> {
    pub blades: &'a [Blade],
    pub states: &'a [BladeState],
    /// Its patches' boxes.
    pub boxes: &'a [PatchBox],
    /// Index of its first blade and first patch in the field (it fills whole patches).
    pub first_blade: usize,
    pub first_patch: usize,
    pub patch_size: usize,
}

/// Every carried blade and patch of a field (empty when nothing with grass moves).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Carried {
    pub blades: Vec<CarriedBlade>,
    pub objects: Vec<CarriedPatches>,
}

impl Carried {
    pub fn is_empty(&self) -> bool {
        self.blades.is_empty()
    }

    /// The same records for blades and patches that sit `blades` and `patches` further on
    /// (a streamed field's object grass follows the tile pool in the GPU buffers).
    pub fn shifted(&self, blades: usize, patches: usize) -> Carried {
        let mut out = self.clone();
        for c in &mut out.blades {
            c.blade += blades as u32;
        }
        for o in &mut out.objects {
            o.first_patch += patches;
        }
        out
    }

    /// Records the grass of object `object` (rest transform `rest`).
    pub fn add(&mut self, object: usize, rest: Mat4, grass: Grown<'_>) {
        let Grown {
            blades,
            states,
            boxes,
            first_blade,
            first_patch,
            patch_size,
        } = grass;
        let slot = self.objects.len() as u32;
        for (k, (b, s)) in blades.iter().zip(states).enumerate() {
            self.blades.push(CarriedBlade {
                v0: [b.v0_dir[0], b.v0_dir[1], b.v0_dir[2]],
                blade: (first_blade + k) as u32,
                up: [b.up_stiffness[0], b.up_stiffness[1], b.up_stiffness[2]],
                object: slot,
                tip: [s.rest_eta[0], s.rest_eta[1], s.rest_eta[2]],
                _pad: 0,
            });
        }
        let cones = blades
            .chunks(patch_size)
            .map(|patch| {
                let ups: Vec<Vec3> = patch
                    .iter()
                    .filter(|b| b.v1_height[3] > 0.0)
                    .map(|b| Vec3::new(b.up_stiffness[0], b.up_stiffness[1], b.up_stiffness[2]))
                    .collect();
                let axis = ups.iter().copied().sum::<Vec3>().normalize_or_zero();
                if axis == Vec3::ZERO {
                    // Ups that cancel: any direction.
                    return (Vec3::Y, std::f32::consts::PI);
                }
                let angle = ups
                    .iter()
                    .map(|u| axis.dot(*u).clamp(-1.0, 1.0).acos())
                    .fold(0.0f32, f32::max);
                (axis, angle)
            })
            .collect();
        self.objects.push(CarriedPatches {
            object,
            rest,
            first_patch,
            boxes: boxes.to_vec(),
            cones,
        });
    }
}

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
