//! The grass a moving object carries, as the field records it when it is generated: each
//! carried blade's rest values and each object's patches at rest (`sim::carry` moves them
//! every step and re-exports these types).

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};

use super::blade::{Blade, BladeState, PatchBox};

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
    /// Padding to 48 bytes, the size of the WGSL struct; always 0.
    pub _pad: u32,
}

const _: () = assert!(std::mem::size_of::<CarriedBlade>() == 48);

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
    /// The object's blades, in field order.
    pub blades: &'a [Blade],
    /// The blades' states, one per blade.
    pub states: &'a [BladeState],
    /// Its patches' boxes.
    pub boxes: &'a [PatchBox],
    /// Index of its first blade and first patch in the field (it fills whole patches).
    pub first_blade: usize,
    /// Index of its first patch in the field.
    pub first_patch: usize,
    /// Blades per patch.
    pub patch_size: usize,
}

/// Every carried blade and patch of a field (empty when nothing with grass moves).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Carried {
    /// Every carried blade's rest values, object by object.
    pub blades: Vec<CarriedBlade>,
    /// The patches of each moving object that carries grass.
    pub objects: Vec<CarriedPatches>,
}

impl Carried {
    /// Whether no blade is carried.
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
