//! Blades streamed in square tiles around the camera (issue 12): the field is cut into
//! tiles of whole patches, a fixed pool of tile slots on the GPU holds the tiles within the
//! blade radius, and a tile entering the radius is generated on the GPU
//! (`shaders/tile_gen.wgsl`). The CPU only decides which tiles are resident
//! ([`TileResidency`]); [`generate_tile`] is the generation kernel's CPU twin.
//!
//! Positions are integers in quanta of 1/1024 m before they become f32: a tile's blades
//! are then the same on the CPU and the GPU whatever the tile's distance from the origin
//! (a product of an integer and a power of two is exact), and the same tile always gets
//! the same blades. A tile is a square of `grid × grid` patches of `patch_size` blades, so
//! patch culling, the update, the blade cull and both occlusion passes run on it as on a
//! generated field.

mod generate;
mod residency;
pub mod tufts;

pub use generate::{
    empty_patch, generate_pool, generate_tile, patch_box, tile_key, GenParams, TileBlades,
    TRAITS_OFFSET,
};
pub use residency::{TileJob, TileResidency, MAX_RELEASES};
pub use tufts::TuftLayout;

use crate::scene::types::{Culling, Field, Terrain};

/// Position quanta per metre (positions are integers of 1/1024 m before they become f32).
pub const QUANTA_PER_METRE: i32 = 1024;
/// Most patches along a tile's side.
pub const MAX_GRID: u32 = 16;
/// Most blades in a tile: 65535 workgroups of 64 (one dispatch dimension).
pub const MAX_TILE_BLADES: u32 = 65535 * 64;
/// The largest pool of blades a streamed field may ask for: 20 million blades is 1.9 GB of
/// blade buffers, past what any adapter binds at once and minutes of CPU-twin generation.
pub const MAX_POOL_BLADES: u64 = 20_000_000;
/// `PatchBox::min[3]` of a patch that holds no blade (a free slot, or a tile whose every
/// blade the density map or the terrain's edge removed): the patch pass skips it.
pub const EMPTY_PATCH: f32 = 1.0;

/// How a tiled field is cut and how many tiles the pool holds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TileLayout {
    /// Side of a patch in quanta (1/1024 m).
    pub patch_q: i32,
    /// Patches along a tile's side.
    pub grid: u32,
    /// Blades per patch.
    pub patch_size: u32,
    /// Tiles whose square comes within this many metres of the camera (x/z) are resident.
    pub radius: f32,
    /// Tile slots in the pool: the most tiles a disk of `radius` can touch.
    pub slots: u32,
    /// Half the side of the terrain square when the grass stops at its edge (a bounded
    /// terrain); `None`: grass everywhere.
    pub bounds: Option<f32>,
}

impl TileLayout {
    /// The layout of a scene's tiled field, or `None` when `field.tile_size` is 0 (the whole
    /// field generated at once, as the papers' scenes are). The patch side makes a patch
    /// hold `patch_size` blades at `field.density`; a tile is the whole number of patches
    /// nearest `tile_size`.
    pub fn from_scene(field: &Field, terrain: &Terrain, culling: &Culling) -> Option<Self> {
        if field.tile_size.is_nan() || field.tile_size <= 0.0 {
            return None;
        }
        let patch_size = crate::field::effective_patch_size(field.patch_size);
        let side = (patch_size as f32 / field.density.max(1e-6)).sqrt();
        let patch_q = (side * QUANTA_PER_METRE as f32)
            .round()
            .clamp(1.0, (1 << 24) as f32) as i32;
        let mut grid = ((field.tile_size / side).round() as u32).clamp(1, MAX_GRID);
        // A tile's blades are the x dimension of the generation dispatch (64 per group).
        while grid > 1 && grid * grid * patch_size > MAX_TILE_BLADES {
            grid -= 1;
        }
        let radius = if culling.max_distance.is_finite() {
            culling.max_distance.max(0.0)
        } else {
            0.0
        };
        let mut layout = Self {
            patch_q,
            grid,
            patch_size,
            radius,
            slots: 0,
            bounds: (!terrain.unbounded).then_some(0.5 * terrain.size),
        };
        layout.slots = layout.max_resident();
        Some(layout)
    }

    /// Side of a tile in quanta.
    pub fn tile_q(&self) -> i64 {
        i64::from(self.patch_q) * i64::from(self.grid)
    }

    /// Side of a tile in metres.
    pub fn tile_size(&self) -> f32 {
        self.tile_q() as f32 / QUANTA_PER_METRE as f32
    }

    /// Patches in one tile (`grid²`).
    pub fn patches_per_tile(&self) -> u32 {
        self.grid * self.grid
    }

    /// Blades in one tile: its patches times `patch_size`.
    pub fn blades_per_tile(&self) -> u32 {
        self.patches_per_tile() * self.patch_size
    }

    /// Blades in the whole pool.
    pub fn pool_blades(&self) -> u64 {
        u64::from(self.slots) * u64::from(self.blades_per_tile())
    }

    /// The blade density the layout gives (patch_size blades per patch square).
    pub fn density(&self) -> f32 {
        let side = self.patch_q as f32 / QUANTA_PER_METRE as f32;
        self.patch_size as f32 / (side * side)
    }

    /// The most tiles a disk of `radius` touches: the tiles across its bounding square,
    /// whatever the camera's position inside a tile.
    fn max_resident(&self) -> u32 {
        let across = (2.0 * self.radius / self.tile_size()).ceil() as u64 + 1;
        (across * across).min(u64::from(u32::MAX)) as u32
    }

    /// The tile holding the point (x, z) in metres.
    pub fn tile_of(&self, x: f32, z: f32) -> (i32, i32) {
        let t = self.tile_size();
        let clamp = |v: f32| (v / t).floor().clamp(i32::MIN as f32, i32::MAX as f32) as i32;
        (clamp(x), clamp(z))
    }

    /// Distance in metres from (x, z) to the square of tile `(tx, tz)`.
    pub fn distance_to(&self, tile: (i32, i32), x: f32, z: f32) -> f32 {
        let t = f64::from(self.tile_size());
        let gap = |p: f32, i: i32| {
            let lo = f64::from(i) * t;
            let p = f64::from(p);
            (lo - p).max(p - (lo + t)).max(0.0)
        };
        let (dx, dz) = (gap(x, tile.0), gap(z, tile.1));
        (dx * dx + dz * dz).sqrt() as f32
    }

    /// Whether any of the tile lies on the grass (a bounded terrain has none past its edge).
    pub fn has_grass(&self, tile: (i32, i32)) -> bool {
        match self.bounds {
            None => true,
            Some(half) => {
                let t = f64::from(self.tile_size());
                let half = f64::from(half);
                let overlaps = |i: i32| {
                    let lo = f64::from(i) * t;
                    lo < half && lo + t > -half
                };
                overlaps(tile.0) && overlaps(tile.1)
            }
        }
    }
}

#[cfg(test)]
mod tests;
