//! Species and clumps (issue 15, point 5): which species a blade is and which clump it
//! grows in, as pure functions of its root, so that the field generators (the CPU's
//! `placement::make_blades`, the tile kernel `shaders/tile_gen.wgsl` and its twin) and the
//! grass shader (colour and shape) agree without storing anything per blade. The WGSL twin
//! is `shaders/clumps.wgsl`.
//!
//! Clumps are the cells of a jittered grid (`clumps.size` apart); a blade belongs to the
//! nearest centre (a Voronoi cell, as Ghost of Tsushima's clumps). A clump has a direction
//! its blades turn towards (by `align`) and lean towards (`lean` degrees more bend), a
//! brightness, and one species, drawn by the species' shares. Without clumps each blade
//! draws its species from a hash of its root.
//!
//! Flowers (thesis §3.3–3.4) are blades too: a hash of the root makes `flowers.fraction`
//! of them thin stems of the flowers' height, and the grass draw puts a head of one of the
//! kinds at their tip.

use bytemuck::{Pod, Zeroable};

use super::noise::hash32;
use crate::scene::Field;

pub use crate::scene::limits::MAX_SPECIES;
const UNIT: f32 = 1.0 / 16_777_216.0;
const SALT_ANGLE: u32 = 0x68bc_21eb;
const SALT_TINT: u32 = 0x02e5_be93;
const SALT_SPECIES: u32 = 0x1b87_3593;

/// One species as the shaders read it (`Species` in `clumps.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct SpeciesGpu {
    /// Height min, span; width min, span (m).
    pub sizes: [f32; 4],
    /// Stiffness min, span; the cumulative share up to this species (the last is 1); the
    /// shape id.
    pub attrs: [f32; 4],
    /// Linear RGB; w: 1 = this colour, 0 = sward's own grass palette.
    pub color: [f32; 4],
}

/// The field's species and clumps (`FieldTraits` in `clumps.wgsl`), a uniform of the tile
/// kernel and of the grass draw.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct FieldTraits {
    /// Clump spacing (0: no clumps), align, lean (radians), colour variation.
    pub clumps: [f32; 4],
    /// Species count (at least 1), the seed, unused x2.
    pub info: [u32; 4],
    /// The species, the first `info[0]` of them in use (the rest zero).
    pub species: [SpeciesGpu; MAX_SPECIES],
    /// Flowers: the share of blades (0: none), stem height min and span, head radius.
    pub flowers: [f32; 4],
    /// Flowers: kind count, unused x3.
    pub flower_info: [u32; 4],
    /// Per kind: petal RGB and petal count, then centre RGB and 0.
    pub flower_kinds: [[f32; 4]; 2 * MAX_FLOWER_KINDS],
}

pub use crate::scene::limits::MAX_FLOWER_KINDS;
/// Width of a flower stem (m).
pub const STEM_WIDTH: f32 = 0.006;
const SALT_FLOWER: u32 = 0x7feb_352d;
const SALT_KIND: u32 = 0x846c_a68b;

const _: () = assert!(
    std::mem::size_of::<FieldTraits>() == 32 + 48 * MAX_SPECIES + 32 + 32 * MAX_FLOWER_KINDS
);

impl FieldTraits {
    /// The traits of `field`: its species (or one made of its own ranges, shape and the
    /// default palette) and its clumps.
    pub fn from_field(field: &Field) -> Self {
        let mut t = FieldTraits::default();
        let range = |r: crate::scene::Range| [r.min, r.max - r.min];
        if field.species.is_empty() {
            let [h0, h1] = range(field.height);
            let [w0, w1] = range(field.width);
            let [s0, s1] = range(field.stiffness);
            t.species[0] = SpeciesGpu {
                sizes: [h0, h1, w0, w1],
                attrs: [s0, s1, 1.0, field.shape.id() as f32],
                color: [0.0; 4],
            };
            t.info[0] = 1;
        } else {
            let n = field.species.len().min(MAX_SPECIES);
            let total: f32 = field.species[..n].iter().map(|s| s.share).sum();
            let mut acc = 0.0;
            for (k, s) in field.species[..n].iter().enumerate() {
                acc += s.share;
                let [h0, h1] = range(s.height);
                let [w0, w1] = range(s.width);
                let [s0, s1] = range(s.stiffness);
                let cum = if k + 1 == n { 1.0 } else { acc / total };
                t.species[k] = SpeciesGpu {
                    sizes: [h0, h1, w0, w1],
                    attrs: [s0, s1, cum, s.shape.id() as f32],
                    color: [s.color.0, s.color.1, s.color.2, 1.0],
                };
            }
            t.info[0] = n as u32;
        }
        t.info[1] = hash32(field.seed as u32 ^ hash32((field.seed >> 32) as u32 ^ 0x51ed_270b));
        if let Some(c) = &field.clumps {
            t.clumps = [c.size, c.align, c.lean.to_radians(), c.color_variation];
        }
        if let Some(f) = field.flowers.as_ref().filter(|f| !f.kinds.is_empty()) {
            t.flowers = [
                f.fraction,
                f.height.min,
                f.height.max - f.height.min,
                f.head_size,
            ];
            let n = f.kinds.len().min(MAX_FLOWER_KINDS);
            t.flower_info[0] = n as u32;
            for (k, kind) in f.kinds[..n].iter().enumerate() {
                let (p, c) = (kind.petals, kind.centre);
                t.flower_kinds[2 * k] = [p.0, p.1, p.2, kind.petal_count as f32];
                t.flower_kinds[2 * k + 1] = [c.0, c.1, c.2, 0.0];
            }
        }
        t
    }

    /// Whether the field grows in clumps (a clump spacing above 0).
    pub fn has_clumps(&self) -> bool {
        self.clumps[0] > 0.0
    }
}

/// The clump a root belongs to: its hash, direction (radians) and brightness draw in [0, 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clump {
    /// Hash of the clump's cell; the clump's species is drawn from it.
    pub hash: u32,
    /// Direction the clump's blades turn towards, in radians, in [0, 2π).
    pub angle: f32,
    /// The clump's brightness draw in [0, 1): its colour is scaled by
    /// 1 + `clumps.color_variation` · (tint − 0.5).
    pub tint: f32,
}

fn unit(h: u32) -> f32 {
    (h >> 8) as f32 * UNIT
}

fn cell_hash(seed: u32, cx: i32, cz: i32) -> u32 {
    hash32(seed ^ hash32((cx as u32) ^ hash32(cz as u32).rotate_left(17)))
}

/// The clump of the root (x, z) (`clump_of` in WGSL). Needs clumps on.
pub fn clump_of(t: &FieldTraits, x: f32, z: f32) -> Clump {
    let size = t.clumps[0];
    let gx = (x / size).floor() as i32;
    let gz = (z / size).floor() as i32;
    let mut best = f32::INFINITY;
    let mut best_hash = 0;
    for dz in -1..=1 {
        for dx in -1..=1 {
            let (cx, cz) = (gx.wrapping_add(dx), gz.wrapping_add(dz));
            let h = cell_hash(t.info[1], cx, cz);
            let px = (cx as f32 + unit(h)) * size;
            let pz = (cz as f32 + unit(hash32(h))) * size;
            let d = (px - x) * (px - x) + (pz - z) * (pz - z);
            if d < best {
                best = d;
                best_hash = h;
            }
        }
    }
    Clump {
        hash: best_hash,
        angle: unit(hash32(best_hash ^ SALT_ANGLE)) * std::f32::consts::TAU,
        tint: unit(hash32(best_hash ^ SALT_TINT)),
    }
}

/// The species of the root (x, z) (`species_of` in WGSL): the clump's, else the root's own.
pub fn species_of(t: &FieldTraits, x: f32, z: f32) -> usize {
    let n = t.info[0].clamp(1, MAX_SPECIES as u32) as usize;
    if n == 1 {
        return 0;
    }
    let h = if t.has_clumps() {
        hash32(clump_of(t, x, z).hash ^ SALT_SPECIES)
    } else {
        hash32(t.info[1] ^ hash32(x.to_bits() ^ hash32(z.to_bits()).rotate_left(17)))
    };
    let u = unit(h);
    (0..n).find(|&k| u < t.species[k].attrs[2]).unwrap_or(n - 1)
}

fn root_hash(t: &FieldTraits, x: f32, z: f32, salt: u32) -> u32 {
    hash32(t.info[1] ^ salt ^ hash32(x.to_bits() ^ hash32(z.to_bits()).rotate_left(17)))
}

/// Whether the blade rooted at (x, z) is a flower stem (`is_flower` in WGSL).
pub fn is_flower(t: &FieldTraits, x: f32, z: f32) -> bool {
    t.flowers[0] > 0.0 && unit(root_hash(t, x, z, SALT_FLOWER)) < t.flowers[0]
}

/// The kind of the flower rooted at (x, z) (`flower_kind` in WGSL).
pub fn flower_kind(t: &FieldTraits, x: f32, z: f32) -> usize {
    let n = t.flower_info[0].clamp(1, MAX_FLOWER_KINDS as u32);
    (root_hash(t, x, z, SALT_KIND) % n) as usize
}

/// A blade's attributes from its root and its uniform draws (`blade_traits` in WGSL):
/// the species' ranges, and with clumps the facing turned towards the clump's direction by
/// `align` and the bend grown by `lean`. Returns (angle, height, width, stiffness, bend).
pub fn blade_traits(
    t: &FieldTraits,
    x: f32,
    z: f32,
    angle: f32,
    bend: f32,
    draws: [f32; 3],
) -> (f32, f32, f32, f32, f32) {
    let s = &t.species[species_of(t, x, z)];
    let mut height = s.sizes[0] + s.sizes[1] * draws[0];
    let mut width = s.sizes[2] + s.sizes[3] * draws[1];
    let stiffness = s.attrs[0] + s.attrs[1] * draws[2];
    // A flower stem: the flowers' height, thin.
    if is_flower(t, x, z) {
        height = t.flowers[1] + t.flowers[2] * draws[0];
        width = STEM_WIDTH;
    }
    if !t.has_clumps() {
        return (angle, height, width, stiffness, bend);
    }
    let c = clump_of(t, x, z);
    let turned = c.angle + (angle - std::f32::consts::PI) * (1.0 - t.clumps[1]);
    (turned, height, width, stiffness, bend + t.clumps[2])
}
