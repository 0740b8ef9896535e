//! The grass field, generated once before rendering (paper, Section 4): the terrain
//! height field, blade placement (tufts plus single blades), and the split into equally
//! sized, compact patches whose blades are sorted so that neighbours have close indices.
//! Everything is seeded: the same scene gives bit-identical buffers on every run.

pub mod blade;
pub mod carried;
pub mod clumps;
mod density;
pub(crate) mod grid;
mod noise;
mod patches;
mod placement;
mod poisson;
mod rng;
pub mod surface;
mod terrain;
#[cfg(test)]
pub(crate) mod tests;
pub mod tiles;
pub mod trails;

pub use density::DensityMap;
pub use noise::{
    fbm, fbm_grad, fbm_max_gradient, hash32, octave_offset, octave_seeds, value_noise,
};
pub use patches::morton;
pub use placement::rest_state;
pub use terrain::{slope_may_shadow, HeightField, NoiseSurface, Surface, MAX_RESOLUTION};

use crate::scene::types::Field;
use blade::{Blade, BladeState, PatchBox, WORKGROUP_SIZE};

/// The blades ready for upload: patch after patch, `patch_size` blades each.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GeneratedField {
    /// `patches.len() * patch_size` blades; patch `p` holds
    /// `blades[p * patch_size..(p + 1) * patch_size]`.
    pub blades: Vec<Blade>,
    /// One state per blade, same order: rest tip = the generated tip, η = 0.
    pub states: Vec<BladeState>,
    /// Bounds of each patch, grown by its tallest blade.
    pub patches: Vec<PatchBox>,
    /// Blades per patch, a multiple of `WORKGROUP_SIZE`.
    pub patch_size: u32,
    /// The blades and patches of moving objects' grass, which the renderer carries with
    /// their objects (`sim::carry`; empty when none moves).
    pub carried: carried::Carried,
}

impl GeneratedField {
    /// Number of blades in the field (`blades.len()`).
    pub fn blade_count(&self) -> usize {
        self.blades.len()
    }
}

/// `patch_size` rounded up to a multiple of the workgroup size (at least one workgroup),
/// so that a patch is always whole workgroups.
pub fn effective_patch_size(patch_size: u32) -> u32 {
    patch_size.max(1).div_ceil(WORKGROUP_SIZE) * WORKGROUP_SIZE
}

/// Generates the field over the whole terrain square: `density × size²` blades rounded up
/// to whole patches. A density map thins the placement by rejection and sampling goes on
/// until the count is reached; if the map rejects too much (a black map) the field comes
/// back short, cut to whole patches, possibly empty.
pub fn generate(
    field: &Field,
    terrain: &HeightField,
    density: Option<&DensityMap>,
) -> GeneratedField {
    let patch_size = effective_patch_size(field.patch_size);
    let wanted = f64::from(field.density) * f64::from(terrain.size).powi(2);
    // NaN, negative or infinite densities give no grass rather than a huge allocation.
    let wanted = if wanted.is_finite() && wanted > 0.0 {
        wanted.ceil() as usize
    } else {
        0
    };
    generate_count(field, terrain, density, wanted, patch_size)
}

/// The largest side of [`flat_field`]'s square: the largest `terrain.size`.
const MAX_FLAT_SIZE: f32 = 10000.0;

/// About `count` blades on a flat square sized so that the density is `field.density`
/// (for tests and `sward simulate --blades N`). The count is rounded up to a multiple of
/// 64, the patch size is `min(field.patch_size, that count)`, and the count is then
/// rounded up to whole patches. `count = 0` gives an empty field on a 1 m square. The
/// square is at most 10 km wide (denser than `field.density` if that is tiny).
pub fn flat_field(count: usize, field: &Field) -> (HeightField, GeneratedField) {
    let group = WORKGROUP_SIZE as usize;
    let rounded = count.div_ceil(group) * group;
    let patch_size = (effective_patch_size(field.patch_size) as usize).min(rounded.max(group));
    let total = rounded.div_ceil(patch_size) * patch_size;
    let density = if field.density.is_finite() && field.density > 0.0 {
        field.density
    } else {
        1.0
    };
    // A tiny density (1e-38 blades/m² is in range) would ask for a square of 1e20 m, where
    // f32 positions lose every centimetre and the blades turn to NaN: the square stays
    // within the largest terrain a scene may have, so the blades stand denser instead.
    let size = if total > 0 {
        (total as f32 / density).sqrt().min(MAX_FLAT_SIZE)
    } else {
        1.0
    };
    let terrain = HeightField::flat(size, 2);
    let generated = generate_count(field, &terrain, None, total, patch_size as u32);
    (terrain, generated)
}

/// Generates `wanted` blades (rounded up to whole patches of `patch_size`).
fn generate_count(
    field: &Field,
    terrain: &HeightField,
    density: Option<&DensityMap>,
    wanted: usize,
    patch_size: u32,
) -> GeneratedField {
    let per_patch = patch_size as usize;
    let target = wanted.div_ceil(per_patch) * per_patch;
    let mut roots = placement::place_roots(terrain.size, target, field, density).roots;
    placement::trim_to_multiple(&mut roots, per_patch, field.seed);
    let mut blades = placement::make_blades(&roots, terrain, field);
    let patches = patches::build_patches(&mut blades, per_patch);
    let states = blades.iter().map(placement::rest_state).collect();
    GeneratedField {
        blades,
        states,
        patches,
        patch_size,
        carried: Default::default(),
    }
}
