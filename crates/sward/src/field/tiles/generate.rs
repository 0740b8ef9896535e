//! The CPU twin of the tile generation kernel (`shaders/tile_gen.wgsl`, `gen_blades` and
//! `gen_boxes`). Every blade is a pure function of the field's seed, its tile and its index,
//! so tiles generate in parallel and the same tile always gets the same blades.
//!
//! Placement per patch (a square of the tile): the first `tuft_blades` blades grow in
//! tufts around Poisson-disk centres ([`TuftLayout`]: a layout of a period of tiles with
//! the same minimum spacing across every border), denser towards the centre; the rest are
//! single blades uniform over the patch (the paper keeps singles unstructured).
//! A density map or a bounded terrain's edge removes blades: a removed blade has height 0,
//! which the update and the cull skip.
//!
//! Roots and the seeded attributes (height, width, stiffness, bend, angle, removal) are
//! bit-identical on both sides; the root's height and normal come from the terrain function,
//! which the CPU evaluates in f64 and the GPU in f32, and the rest pose from trigonometry,
//! so the derived points agree within the terrain twin's tolerance.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use super::tufts::{period_for, TuftLayout};
use super::{TileLayout, EMPTY_PATCH, QUANTA_PER_METRE};
use crate::field::blade::{blade_frame, rest_pose};
use crate::field::blade::{Blade, BladeState, PatchBox};
use crate::field::{hash32, DensityMap, HeightField};
use crate::scene::types::Field;

/// Candidate blades per tuft.
const TUFT_BLADES: u32 = 16;
/// Shortest blade generated (the validation divides by the height).
const MIN_HEIGHT: f32 = 1e-3;
/// Spreads a blade's draws over the 32-bit hash (the golden ratio in 32 bits).
const GOLDEN: u32 = 0x9E37_79B9;
/// 2^-24: a 24-bit integer times this is exact in f32 and below 1.
const UNIT: f32 = 1.0 / 16_777_216.0;
/// The bit of `GenParams::map[2]`: a density map is bound.
pub const FLAG_DENSITY: u32 = 1;
/// The bit of `GenParams::map[2]`: grass stops at the terrain square's edge.
pub const FLAG_BOUNDED: u32 = 2;

/// Uniforms of the generation kernel; mirrors `GenParams` in `shaders/tile_gen.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct GenParams {
    /// Patch side in quanta, patches per tile side, blades per patch, blades per tile.
    pub layout: [u32; 4],
    /// The field's 32-bit seed key, tuft blades per patch, tuft radius in quanta, tufts per
    /// patch.
    pub key: [u32; 4],
    /// Height min and span, width min and span (m).
    pub sizes: [f32; 4],
    /// Stiffness min and span, bend min and span (radians).
    pub attrs: [f32; 4],
    /// Density map width and height in texels, `FLAG_*` bits, jobs this dispatch.
    pub map: [u32; 4],
    /// Half the terrain side (bounded grass), the density map's square side, unused ×2.
    pub extent: [f32; 4],
    /// Tiles along the side of the tuft layout's period ([`TuftLayout::period`]), unused ×3.
    pub tufts: [u32; 4],
    /// Up to the 256-byte uniform offset alignment: the traits are bound on their own.
    pub _pad: [[u32; 4]; 9],
    /// The field's species and clumps (`traits` in `tile_gen.wgsl`, bound at
    /// [`TRAITS_OFFSET`] of the same buffer).
    pub traits: crate::field::clumps::FieldTraits,
}

/// Byte offset of [`GenParams::traits`]: a multiple of the uniform offset alignment.
pub const TRAITS_OFFSET: u64 = 256;

const _: () = assert!(std::mem::offset_of!(GenParams, traits) == TRAITS_OFFSET as usize);

impl GenParams {
    /// The uniforms for `field` cut by `layout`, with a density map of `map` texels.
    pub fn new(layout: &TileLayout, field: &Field, density: Option<&DensityMap>) -> Self {
        let ps = layout.patch_size;
        let fraction = if field.tuft_fraction.is_finite() {
            field.tuft_fraction.clamp(0.0, 1.0)
        } else {
            0.0
        };
        let tuft_blades = ((fraction * ps as f32).round() as u32).min(ps);
        let tufts = tuft_blades.div_ceil(TUFT_BLADES).max(1);
        let radius_q = (field.tuft_radius.max(0.0) * QUANTA_PER_METRE as f32)
            .round()
            .clamp(1.0, 1e7) as u32;
        let (mw, mh, msize) = match density {
            Some(m) => {
                let (w, h, _) = m.texels();
                (w, h, m.size())
            }
            None => (1, 1, 1.0),
        };
        let mut flags = 0;
        if density.is_some() {
            flags |= FLAG_DENSITY;
        }
        if layout.bounds.is_some() {
            flags |= FLAG_BOUNDED;
        }
        let to_rad = std::f32::consts::PI / 180.0;
        Self {
            layout: [
                layout.patch_q as u32,
                layout.grid,
                ps,
                layout.blades_per_tile(),
            ],
            key: [seed_key(field.seed), tuft_blades, radius_q, tufts],
            sizes: [
                field.height.min,
                field.height.max - field.height.min,
                field.width.min,
                field.width.max - field.width.min,
            ],
            attrs: [
                field.stiffness.min,
                field.stiffness.max - field.stiffness.min,
                field.bend.min * to_rad,
                (field.bend.max - field.bend.min) * to_rad,
            ],
            map: [mw, mh, flags, 0],
            extent: [layout.bounds.unwrap_or(0.0), msize, 0.0, 0.0],
            tufts: [period_for(layout.grid, tufts), 0, 0, 0],
            _pad: [[0; 4]; 9],
            traits: crate::field::clumps::FieldTraits::from_field(field),
        }
    }

    /// The tuft centres these uniforms index (built once per field; `layout` is the one
    /// the uniforms were made for).
    pub fn tuft_layout(&self, layout: &TileLayout) -> TuftLayout {
        TuftLayout::new(layout, self.key[3], self.key[0])
    }
}

/// The 32 bits of the field's 64-bit seed the kernel hashes with.
pub fn seed_key(seed: u64) -> u32 {
    hash32(seed as u32 ^ hash32((seed >> 32) as u32))
}

/// The hash that seeds every blade of tile `(tx, tz)`.
pub fn tile_key(key: u32, tile: (i32, i32)) -> u32 {
    hash32(key ^ hash32((tile.0 as u32) ^ hash32(tile.1 as u32).rotate_left(17)))
}

/// One tile's blades, their states and the boxes of its patches, in slot order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TileBlades {
    /// The tile's blades in slot order; a removed blade has height 0.
    pub blades: Vec<Blade>,
    /// Each blade's rest state (its rest tip, η = 0).
    pub states: Vec<BladeState>,
    /// The bounding box of each of the tile's patches.
    pub patches: Vec<PatchBox>,
}

/// A blade's root (quanta) and seeded attributes, or `None` when it is removed.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Draw {
    x: f32,
    z: f32,
    angle: f32,
    height: f32,
    width: f32,
    stiffness: f32,
    bend: f32,
}

/// Blade `i` of `tile`: the twin of `draw_blade` in `shaders/tile_gen.wgsl`.
fn draw_blade(
    p: &GenParams,
    tufts: &TuftLayout,
    density: Option<&DensityMap>,
    tile: (i32, i32),
    i: u32,
) -> Option<Draw> {
    let [patch_q, grid, ps, _] = p.layout;
    let [key, tuft_blades, radius_q, _] = p.key;
    let tkey = tile_key(key, tile);
    let patch = i / ps;
    let j = i % ps;
    let (px, pz) = (patch % grid, patch / grid);
    let tile_q = (patch_q * grid) as i32;
    let base_x = tile
        .0
        .wrapping_mul(tile_q)
        .wrapping_add((px * patch_q) as i32);
    let base_z = tile
        .1
        .wrapping_mul(tile_q)
        .wrapping_add((pz * patch_q) as i32);
    let h0 = hash32(tkey ^ hash32(i));
    let r = |k: u32| hash32(h0.wrapping_add(k.wrapping_mul(GOLDEN)));
    let u = |k: u32| (r(k) >> 8) as f32 * UNIT;
    let (xq, zq) = if j < tuft_blades {
        // Around its tuft's centre, closer to it more often (the offset's scale is a draw),
        // across the patch's edge where the tuft stands near it: the boxes follow the blades.
        let (centre_x, centre_z) = tufts.centre(tile, (px, pz), j / TUFT_BLADES);
        let span = 2 * radius_q + 1;
        let s = (r(2) >> 24) as i32;
        let ox = ((r(0) % span) as i32 - radius_q as i32) * s / 256;
        let oz = ((r(1) % span) as i32 - radius_q as i32) * s / 256;
        (centre_x.wrapping_add(ox), centre_z.wrapping_add(oz))
    } else {
        (
            base_x.wrapping_add((r(0) % patch_q) as i32),
            base_z.wrapping_add((r(1) % patch_q) as i32),
        )
    };
    let quantum = 1.0 / QUANTA_PER_METRE as f32;
    let (x, z) = (xq as f32 * quantum, zq as f32 * quantum);
    let flags = p.map[2];
    if flags & FLAG_BOUNDED != 0 {
        let half = p.extent[0];
        if x.abs() > half || z.abs() > half {
            return None;
        }
    }
    if flags & FLAG_DENSITY != 0 {
        if let Some(map) = density {
            if u(8) >= map.sample(x, z) {
                return None;
            }
        }
    }
    // The species' ranges and the clump's facing and lean (`blade_traits`).
    let (angle, height, width, stiffness, bend) = crate::field::clumps::blade_traits(
        &p.traits,
        x,
        z,
        (r(3) >> 8) as f32 * (std::f32::consts::TAU * UNIT),
        p.attrs[2] + p.attrs[3] * u(7),
        [u(4), u(5), u(6)],
    );
    Some(Draw {
        x,
        z,
        angle,
        height: height.max(MIN_HEIGHT),
        width,
        stiffness,
        bend,
    })
}

/// A removed blade: height 0 (skipped by the update and the cull), everything else 0.
fn removed() -> Blade {
    Blade::default()
}

/// The blades of `tile` as the kernel writes them into a slot, with their patch boxes.
pub fn generate_tile(
    params: &GenParams,
    tufts: &TuftLayout,
    terrain: &HeightField,
    density: Option<&DensityMap>,
    tile: (i32, i32),
) -> TileBlades {
    let per_tile = params.layout[3];
    let ps = params.layout[2] as usize;
    let mut blades = Vec::with_capacity(per_tile as usize);
    let mut states = Vec::with_capacity(per_tile as usize);
    for i in 0..per_tile {
        let blade = match draw_blade(params, tufts, density, tile, i) {
            Some(d) => pose(&d, terrain),
            None => removed(),
        };
        let v2 = blade.v2_width;
        states.push(BladeState {
            rest_eta: [v2[0], v2[1], v2[2], 0.0],
        });
        blades.push(blade);
    }
    let patches = blades.chunks(ps).map(patch_box).collect();
    TileBlades {
        blades,
        states,
        patches,
    }
}

/// The blade in its rest pose on the terrain (the twin of the kernel's `pose`).
fn pose(d: &Draw, terrain: &HeightField) -> Blade {
    let v0 = Vec3::new(d.x, terrain.height(d.x, d.z), d.z);
    let up = terrain.normal(d.x, d.z);
    let (_, front) = blade_frame(up, d.angle);
    let (v1, v2) = rest_pose(v0, up, front, d.height, d.bend);
    Blade {
        v0_dir: [v0.x, v0.y, v0.z, d.angle],
        v1_height: [v1.x, v1.y, v1.z, d.height],
        v2_width: [v2.x, v2.y, v2.z, d.width],
        up_stiffness: [up.x, up.y, up.z, d.stiffness],
    }
}

/// The box of a patch's live blades grown by the tallest, with their smallest up.y in
/// `max[3]` (like a generated field's), or an
/// empty patch (`min[3] = EMPTY_PATCH`) when every blade was removed.
pub fn patch_box(patch: &[Blade]) -> PatchBox {
    let mut min = [f32::INFINITY; 3];
    let mut max = [f32::NEG_INFINITY; 3];
    let mut tallest = 0.0f32;
    let mut up_y = 1.0f32;
    for b in patch.iter().filter(|b| b.v1_height[3] > 0.0) {
        for k in 0..3 {
            min[k] = min[k].min(b.v0_dir[k]);
            max[k] = max[k].max(b.v0_dir[k]);
        }
        tallest = tallest.max(b.v1_height[3]);
        up_y = up_y.min(b.up_stiffness[1]);
    }
    if tallest <= 0.0 {
        return empty_patch();
    }
    PatchBox {
        min: [min[0] - tallest, min[1] - tallest, min[2] - tallest, 0.0],
        max: [max[0] + tallest, max[1] + tallest, max[2] + tallest, up_y],
    }
}

/// The box of a patch with no blade (a free slot's patches too).
pub fn empty_patch() -> PatchBox {
    PatchBox {
        min: [0.0, 0.0, 0.0, EMPTY_PATCH],
        max: [0.0; 4],
    }
}

/// The whole pool as the GPU holds it after filling the tiles within the radius of (x, z)
/// (the CPU twin of `TileStreamer::fill`): resident slots with their tiles, free slots
/// with removed blades and empty patches.
pub fn generate_pool(
    layout: &super::TileLayout,
    field: &Field,
    terrain: &HeightField,
    density: Option<&DensityMap>,
    x: f32,
    z: f32,
) -> crate::field::GeneratedField {
    let params = GenParams::new(layout, field, density);
    let tufts = params.tuft_layout(layout);
    let mut residency = super::TileResidency::new(*layout);
    while !residency.update(x, z, usize::MAX).is_empty() {}
    let per_tile = layout.blades_per_tile() as usize;
    let per_slot_patches = layout.patches_per_tile() as usize;
    let slots = layout.slots as usize;
    let mut out = crate::field::GeneratedField {
        blades: vec![Blade::default(); slots * per_tile],
        states: vec![BladeState::default(); slots * per_tile],
        patches: vec![empty_patch(); slots * per_slot_patches],
        patch_size: layout.patch_size,
        carried: Default::default(),
    };
    for (slot, tile) in residency.slots().iter().enumerate() {
        if let Some(tile) = tile {
            let t = generate_tile(&params, &tufts, terrain, density, *tile);
            out.blades[slot * per_tile..(slot + 1) * per_tile].copy_from_slice(&t.blades);
            out.states[slot * per_tile..(slot + 1) * per_tile].copy_from_slice(&t.states);
            out.patches[slot * per_slot_patches..(slot + 1) * per_slot_patches]
                .copy_from_slice(&t.patches);
        }
    }
    out
}
