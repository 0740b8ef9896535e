//! Which tiles are resident, and in which slot: the only per-frame decision the CPU makes
//! about the streamed field. Tiles within the blade radius are wanted; a resident tile is
//! released only when it is half a tile beyond the radius (so a camera hovering at a tile
//! edge does not regenerate it every frame), or when its slot is needed for a nearer tile.
//! New tiles are taken nearest first, at most `max_new` per update, so a jump of the camera
//! spreads the generation over a few frames and the blades at the camera come first.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use super::TileLayout;

/// Most slots freed by one update (with `max_new`, what bounds the jobs of one dispatch).
pub const MAX_RELEASES: usize = 2048;

/// One slot's change: generate `tile` into `slot`, or free the slot (`tile: None`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct TileJob {
    /// The pool slot that changes.
    pub slot: u32,
    /// The tile (x, z index) to generate into the slot; `None` frees it.
    pub tile: Option<(i32, i32)>,
}

/// The pool's slots and the tiles in them.
#[derive(Clone, Debug)]
pub struct TileResidency {
    layout: TileLayout,
    slots: Vec<Option<(i32, i32)>>,
    resident: HashMap<(i32, i32), u32>,
    /// Free slots, lowest first (so the assignment is deterministic).
    free: BTreeSet<u32>,
    /// Tiles generated since the start.
    generated: u64,
}

impl TileResidency {
    /// An empty pool of `layout.slots` slots.
    pub fn new(layout: TileLayout) -> Self {
        Self {
            layout,
            slots: vec![None; layout.slots as usize],
            resident: HashMap::new(),
            free: (0..layout.slots).collect(),
            generated: 0,
        }
    }

    /// How the field is cut into tiles and how many slots the pool has.
    pub fn layout(&self) -> &TileLayout {
        &self.layout
    }

    /// Tiles resident now.
    pub fn resident_count(&self) -> usize {
        self.resident.len()
    }

    /// Tiles generated since the start.
    pub fn generated(&self) -> u64 {
        self.generated
    }

    /// The tile in each slot.
    pub fn slots(&self) -> &[Option<(i32, i32)>] {
        &self.slots
    }

    /// The slot holding `tile`, if it is resident.
    pub fn slot_of(&self, tile: (i32, i32)) -> Option<u32> {
        self.resident.get(&tile).copied()
    }

    /// The tiles within the radius of (x, z) that have grass, nearest first (ties broken by
    /// the tile's coordinates, so the order is total).
    pub fn wanted(&self, x: f32, z: f32) -> Vec<(i32, i32)> {
        let l = &self.layout;
        let r = l.radius;
        let (x0, z0) = l.tile_of(x - r, z - r);
        let (x1, z1) = l.tile_of(x + r, z + r);
        let mut tiles = Vec::new();
        for tz in z0..=z1 {
            for tx in x0..=x1 {
                let d = l.distance_to((tx, tz), x, z);
                if d <= r && l.has_grass((tx, tz)) {
                    tiles.push((d, (tx, tz)));
                }
            }
        }
        tiles.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        tiles.into_iter().map(|(_, t)| t).collect()
    }

    /// Moves the pool towards the tiles wanted at camera position (x, z): frees the slots
    /// of tiles that left the radius (with half a tile of hysteresis) and assigns up to
    /// `max_new` entering tiles, nearest first. Returns one job per changed slot, ordered by
    /// slot: at most `MAX_RELEASES + max_new` jobs.
    pub fn update(&mut self, x: f32, z: f32, max_new: usize) -> Vec<TileJob> {
        let mut jobs: BTreeMap<u32, Option<(i32, i32)>> = BTreeMap::new();
        let keep = self.layout.radius + 0.5 * self.layout.tile_size();
        let mut leaving: Vec<(i32, i32)> = self
            .resident
            .keys()
            .copied()
            .filter(|&t| self.layout.distance_to(t, x, z) > keep)
            .collect();
        // The map's order is random: sort, so that which tiles go first is reproducible.
        leaving.sort_unstable();
        leaving.truncate(MAX_RELEASES);
        for tile in leaving {
            let slot = self.release(tile);
            jobs.insert(slot, None);
        }
        let mut added = 0;
        for tile in self.wanted(x, z) {
            if added == max_new {
                break;
            }
            if self.resident.contains_key(&tile) {
                continue;
            }
            let slot = match self.free.pop_first() {
                Some(slot) => slot,
                None => match self.farthest_unwanted(x, z) {
                    Some(old) => self.release_taken(old),
                    // Cannot happen: the pool holds every tile a disk of the radius touches.
                    None => break,
                },
            };
            self.slots[slot as usize] = Some(tile);
            self.resident.insert(tile, slot);
            self.generated += 1;
            jobs.insert(slot, Some(tile));
            added += 1;
        }
        jobs.into_iter()
            .map(|(slot, tile)| TileJob { slot, tile })
            .collect()
    }

    /// Frees `tile`'s slot and returns it.
    fn release(&mut self, tile: (i32, i32)) -> u32 {
        let slot = self.release_taken(tile);
        self.free.insert(slot);
        slot
    }

    /// Removes `tile` from its slot without putting the slot on the free list (the caller
    /// fills it at once).
    fn release_taken(&mut self, tile: (i32, i32)) -> u32 {
        let slot = self.resident.remove(&tile).expect("a resident tile");
        self.slots[slot as usize] = None;
        slot
    }

    /// The resident tile farthest from (x, z) outside the radius (the one to give up).
    fn farthest_unwanted(&self, x: f32, z: f32) -> Option<(i32, i32)> {
        let r = self.layout.radius;
        self.resident
            .keys()
            .copied()
            .map(|t| (self.layout.distance_to(t, x, z), t))
            .filter(|(d, _)| *d > r)
            .max_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
            .map(|(_, t)| t)
    }
}
