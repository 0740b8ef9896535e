//! Poisson-disk tuft centres for streamed tiles (issue 27, point 6). A whole field places
//! its tuft centres with Bridson's algorithm (`field::poisson`), which is sequential and
//! needs the whole square at once; a streamed tile must be generated on its own, on the
//! GPU, and meet its neighbours without a seam. So the centres of a *period* of
//! `period × period` tiles are laid out once, on the CPU, as a Poisson-disk set on a torus:
//! every pair of centres is at least [`TuftLayout::min_distance`] apart, measured with
//! wrap-around, so the layout tiles the plane with the same spacing across every tile and
//! period border. Each patch gets exactly `per_patch` centres (the kernel's blade `j` of a
//! patch belongs to tuft `j / 16`), placed by dart throwing in rounds of one centre per
//! patch, so that no patch fills before its neighbours.
//!
//! The centres are integer offsets in quanta from their patch's corner: the GPU kernel
//! (`tuft_centre` in `shaders/tile_gen.wgsl`) reads the same integers from a buffer, so the
//! twin and the kernel place every tuft identically. A tile's other draws (heights, angles,
//! colours, the blades inside a tuft) are still hashed per tile, so the period repeats only
//! the centres, every `period` tiles (about 29 m for the prairie).

use super::TileLayout;
use crate::field::rng::Rng;

/// Tiles along the period's side, at most.
pub const MAX_PERIOD: u32 = 4;
/// Centres in the period at most (8 bytes each on the GPU): the period shrinks to keep it.
pub const MAX_CENTRES: u64 = 65_536;
/// The first spacing tried, in units of the square root of the area per centre. Random
/// sequential dart throwing saturates at 0.83 (a packing fraction of 0.547), so 0.7 leaves
/// room for every patch to reach its quota.
const FIRST_SPACING: f64 = 0.7;
/// Each failed layout retries with the spacing times this.
const SHRINK: f64 = 0.9;
const MAX_LAYOUTS: u32 = 8;
/// Darts thrown into a patch for one centre before the layout is given up.
const DARTS: u32 = 200;
/// The RNG stream of the tuft layout.
const STREAM: u64 = 0x7475_6674;

/// Tiles along the period's side for tiles of `grid` patches with `per_patch` tufts each:
/// [`MAX_PERIOD`], or fewer where the period would hold more than [`MAX_CENTRES`].
pub fn period_for(grid: u32, per_patch: u32) -> u32 {
    let mut period = MAX_PERIOD;
    while period > 1
        && u64::from(period * grid.max(1)).pow(2) * u64::from(per_patch.max(1)) > MAX_CENTRES
    {
        period -= 1;
    }
    period
}

/// The tuft centres of one period of tiles.
#[derive(Clone, Debug, PartialEq)]
pub struct TuftLayout {
    /// Tiles along the period's side.
    pub period: u32,
    /// Tufts per patch.
    pub per_patch: u32,
    /// Patches along a tile's side.
    pub grid: u32,
    /// A patch's side in quanta.
    pub patch_q: i32,
    /// Offsets in quanta from the patch's corner, `per_patch` per patch, patches row-major
    /// over the period (`period · grid` per side).
    pub offsets: Vec<[u32; 2]>,
    /// The smallest distance between two centres anywhere in the plane (m); 0 when the
    /// dart throwing gave up and the centres are uniform.
    pub min_distance: f32,
}

impl TuftLayout {
    /// The layout for tiles of `layout`, `per_patch` tufts per patch, seeded by `key`.
    pub fn new(layout: &TileLayout, per_patch: u32, key: u32) -> Self {
        let grid = layout.grid.max(1);
        let patch_q = layout.patch_q.max(1);
        let per_patch = per_patch.max(1);
        let period = period_for(grid, per_patch);
        let mut out = Self {
            period,
            per_patch,
            grid,
            patch_q,
            offsets: Vec::new(),
            min_distance: 0.0,
        };
        let area = f64::from(patch_q) * f64::from(patch_q) / f64::from(per_patch);
        let mut r = FIRST_SPACING * area.sqrt();
        for _ in 0..MAX_LAYOUTS {
            if let Some(offsets) = out.throw(key, r) {
                out.offsets = offsets;
                out.min_distance = (r / f64::from(super::QUANTA_PER_METRE)) as f32;
                return out;
            }
            r *= SHRINK;
        }
        // Unreachable in practice (the last spacing fits six times the centres); uniform
        // centres keep the field whole if it ever happens.
        let mut rng = Rng::new(u64::from(key), STREAM);
        let q = patch_q as usize;
        out.offsets = (0..out.patches() * per_patch as usize)
            .map(|_| [rng.below(q) as u32, rng.below(q) as u32])
            .collect();
        out
    }

    /// Patches in the period.
    fn patches(&self) -> usize {
        (self.period * self.grid).pow(2) as usize
    }

    /// Dart throwing at spacing `r` (quanta) on the period's torus, one centre per patch
    /// per round; `None` when some patch finds no room.
    fn throw(&self, key: u32, r: f64) -> Option<Vec<[u32; 2]>> {
        let side = (self.period * self.grid) as usize;
        let patch_q = f64::from(self.patch_q);
        let length = side as f64 * patch_q;
        // Cells no wider than r/√2 hold at most one centre.
        let cells = ((length / (r / std::f64::consts::SQRT_2)).ceil() as usize).clamp(1, 4096);
        let cell = length / cells as f64;
        let reach = (r / cell).ceil() as i64;
        let mut grid = vec![u32::MAX; cells * cells];
        let mut points: Vec<(f64, f64)> = Vec::new();
        let mut offsets = vec![[0u32; 2]; side * side * self.per_patch as usize];
        let mut rng = Rng::new(u64::from(key), STREAM);
        let wrap = |d: f64| {
            let d = d.abs();
            d.min(length - d)
        };
        let q = self.patch_q as usize;
        for round in 0..self.per_patch as usize {
            for patch in 0..side * side {
                let (px, pz) = (patch % side, patch / side);
                let mut placed = false;
                for _ in 0..DARTS {
                    let o = [rng.below(q) as u32, rng.below(q) as u32];
                    let x = px as f64 * patch_q + f64::from(o[0]);
                    let z = pz as f64 * patch_q + f64::from(o[1]);
                    let (cx, cz) = (
                        ((x / cell) as usize).min(cells - 1),
                        ((z / cell) as usize).min(cells - 1),
                    );
                    let clear = (-reach..=reach).all(|dj| {
                        (-reach..=reach).all(|di| {
                            let i = (cx as i64 + di).rem_euclid(cells as i64) as usize;
                            let j = (cz as i64 + dj).rem_euclid(cells as i64) as usize;
                            let k = grid[j * cells + i];
                            k == u32::MAX || {
                                let (a, b) = points[k as usize];
                                let (dx, dz) = (wrap(a - x), wrap(b - z));
                                dx * dx + dz * dz >= r * r
                            }
                        })
                    });
                    if clear && grid[cz * cells + cx] == u32::MAX {
                        grid[cz * cells + cx] = points.len() as u32;
                        points.push((x, z));
                        offsets[patch * self.per_patch as usize + round] = o;
                        placed = true;
                        break;
                    }
                }
                if !placed {
                    return None;
                }
            }
        }
        Some(offsets)
    }

    /// The centre (quanta) of tuft `t` of patch `(px, pz)` of `tile`: the twin of
    /// `tuft_centre` in `shaders/tile_gen.wgsl`.
    pub fn centre(&self, tile: (i32, i32), patch: (u32, u32), t: u32) -> (i32, i32) {
        let p = self.period as i32;
        let (mx, mz) = (tile.0.rem_euclid(p) as u32, tile.1.rem_euclid(p) as u32);
        let side = self.period * self.grid;
        let index = (mz * self.grid + patch.1) * side + mx * self.grid + patch.0;
        let o = self.offsets[(index * self.per_patch + t) as usize];
        let tile_q = self.patch_q.wrapping_mul(self.grid as i32);
        let base_x = tile
            .0
            .wrapping_mul(tile_q)
            .wrapping_add((patch.0 * self.patch_q as u32) as i32);
        let base_z = tile
            .1
            .wrapping_mul(tile_q)
            .wrapping_add((patch.1 * self.patch_q as u32) as i32);
        (
            base_x.wrapping_add(o[0] as i32),
            base_z.wrapping_add(o[1] as i32),
        )
    }

    /// The offsets as the kernel's buffer holds them (never empty: a binding needs bytes).
    pub fn gpu_words(&self) -> Vec<[u32; 2]> {
        if self.offsets.is_empty() {
            vec![[0, 0]]
        } else {
            self.offsets.clone()
        }
    }
}
