//! Billboards in the middle distance (issue 12): past the blades, out to
//! `render.billboard_distance`, the grass is drawn as cards facing the camera showing tufts
//! of sward's own blades ([`atlas`]). Cards have no state: one per cell of nested grids
//! around the camera, placed by a hash of the cell (positions in integer quanta of 1/1024
//! m, so the CPU twin [`place_card`] matches the GPU exactly). A compute pass keeps the
//! cards in the ring, kept by the density map and in view ([`count_drawn`] is its CPU twin)
//! and one indirect, non-instanced draw shows them, six vertices per card
//! ([`BillboardPass`]). The cost is bounded by the grids, whatever the terrain's size.
//!
//! The grids are the prairie thesis's levels of detail by grid distance (its Eq. 8-9,
//! issue 27 point 2): level k's cells are 2^k times the base cell, and it covers the cells
//! whose Chebyshev distance from the camera's cell (in its own cells) is from [`LEVEL_HALF`]
//! to twice that (level 0 from the camera's cell), so the cards get larger and sparser
//! with distance and keep about the same size on the screen. A level-k card is 2^k base
//! cards wide and repeats the atlas's strip 2^k times, so its blades keep their width; it
//! is as tall as the blades. One card per 3 m cell out to 300 m stood in visible rows at
//! grazing angles; the nested cells are 1.5 m near the blades and each card is turned a
//! little off the camera (±20°), so no regular structure is left.
//!
//! Cards fade in over the band where the blades thin out (from 0.5 to 0.75 of
//! `culling.max_distance`: Eq. 20's last levels keep fewer than half the blades, which
//! widen at most twice, `grass.wgsl`, so the cards fill what the thinning leaves) and out
//! over the last 15 % of the billboard radius, where the ground's grass colour takes over;
//! sway with the wind the blades read and bend away from colliders and balls
//! ([`top_offset`]). A card's texels are sampled three mip levels sharper than its
//! footprint (`billboard.wgsl`): a pixel shows a few of the strip's blades, as a pixel of
//! the blades shows one, not their average, and the measured contrast gain (`far_gain`)
//! brings their spread to the blades'.
//!
//! Seen from above, upright cards read as rows of strokes: they fade out by the view's
//! elevation over each card (from 5.7° to 23.6°, [`crate::render::far_canopy::weight`]),
//! where the far ground's canopy seen from above takes over.

pub mod atlas;
mod pass;
pub mod probe;

pub use pass::{BillboardPass, DrawnCard, Inputs};

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec2, Vec3};

use crate::field::tiles::QUANTA_PER_METRE;
use crate::field::{hash32, DensityMap, HeightField};
use crate::scene::types::{Field, Render};
use crate::sim::layout::SimParams;
use crate::sim::reference::{wind_at, WindGrid};
use crate::render::light::sky::smoothstep;

/// Base cells across the billboard radius: the base cell is the radius over this (at least
/// `MIN_CELL`, at most [`CELL_RADIUS_CAP`] over this); the levels double the cells out
/// to any radius, so the number of cards grows with its logarithm only.
pub const CELLS_PER_RADIUS: f32 = 200.0;
/// The smallest base cell (m).
const MIN_CELL: f32 = 0.5;
/// The radius past which the base cell stops growing (m): 1.5 m cells.
pub const CELL_RADIUS_CAP: f32 = 300.0;
/// A level's inner half-size in its own cells: level k covers Chebyshev distances from
/// this to twice this (its cells), so each level is a square ring of `(4 · LEVEL_HALF −
/// 2)²` cells less the hole the level inside it fills.
pub const LEVEL_HALF: i32 = 19;
/// Most levels: 2^11 base cells of 0.5 m reach past 40 km.
const MAX_LEVELS: u32 = 12;
/// How far a card is turned off facing the camera, at most (radians).
pub const CARD_TURN: f32 = 0.35;
/// Where the cards fade in, as multiples of the blades' reach (`culling.max_distance`):
/// Eq. 20's levels from half the reach keep fewer than half the blades, which widen at
/// most twice (`grass.wgsl`), and the cards fill what they leave.
pub const FADE_IN: (f32, f32) = (0.5, 0.75);
/// Where the cards fade out, as a share of the radius they are drawn to (to all of it):
/// the thinned blades' root cut goes over to the whole blade there too
/// (`render::thinning::root`).
pub const FADE_OUT: f32 = 0.85;

/// Where the cards fade in (m, [`FADE_IN`]) for the blades' reach `max_distance` (from the
/// camera on without a finite reach).
pub fn fade_in(max_distance: f32) -> (f32, f32) {
    let blades = if max_distance.is_finite() {
        max_distance.max(0.0)
    } else {
        0.0
    };
    (FADE_IN.0 * blades, FADE_IN.1 * blades)
}
/// Card width per cell side, and card height per tallest blade.
const CARD_WIDTH: f32 = 2.0;
const CARD_HEIGHT: f32 = 0.9;
/// Top offset per m/s² of wind, per metre of card height.
pub const SWAY_GAIN: f32 = 0.08;
/// How far past a sphere's radius a card's top is pushed away, in card heights.
pub const BEND_REACH: f32 = 0.5;

/// Uniforms of the billboard shaders; mirrors `BillboardParams` in
/// `shaders/billboard_place.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct BillboardParams {
    /// Camera cell x, z; cells per side; cell side in quanta.
    pub cells: [i32; 4],
    /// Fade-in start, end; fade-out start, end (m).
    pub fade: [f32; 4],
    /// Camera x, z; card width and height (m).
    pub eye_card: [f32; 4],
    /// Seed key, atlas variants, 1 = density map, sphere count.
    pub info: [u32; 4],
    /// Sway gain, bend reach, terrain size, the camera's height (world y, m).
    pub shape: [f32; 4],
    /// The atlas's mean albedo (rgb), unused: the cull lights the cards per unit of it.
    pub albedo: [f32; 4],
    /// Levels, a level's inner half-size in its cells ([`LEVEL_HALF`]), cells per level
    /// side of the index space (`4 · LEVEL_HALF − 2`), the order the cull visits a level's
    /// cells in ([`visit_flags`], set per frame).
    pub levels: [u32; 4],
}

const _: () = assert!(std::mem::size_of::<BillboardParams>() == 112);

/// The layout of the billboard grids for a scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BillboardLayout {
    /// How far from the camera billboards are drawn (`render.billboard_distance`, m).
    pub radius: f32,
    /// The base cell (level 0's) in quanta.
    pub cell_q: i32,
    /// Levels of doubling cells that reach the radius.
    pub levels: u32,
    /// A level-0 card's width and height (m).
    pub card: (f32, f32),
    /// Hash of the field's seed that keys the card placement (`BillboardParams::info[0]`).
    pub key: u32,
}

/// Cells per side of one level's index space.
pub const fn level_side() -> i32 {
    4 * LEVEL_HALF - 2
}

impl BillboardLayout {
    /// `None` when `render.billboard_distance` is 0 (no billboards).
    pub fn from_scene(render: &Render, field: &Field) -> Option<Self> {
        let radius = render.billboard_distance;
        if radius.is_nan() || radius <= 0.0 {
            return None;
        }
        // The base cell follows the radius up to CELL_RADIUS_CAP and stays there: a larger
        // radius adds levels of larger cells far away instead of coarsening the cards
        // near the blades.
        let cell = (radius.min(CELL_RADIUS_CAP) / CELLS_PER_RADIUS).max(MIN_CELL);
        let cell_q = (cell * QUANTA_PER_METRE as f32).round().max(1.0) as i32;
        let cell = cell_q as f32 / QUANTA_PER_METRE as f32;
        // Level k reaches at least 2^k · LEVEL_HALF cells from the camera's (Chebyshev):
        // enough levels that the last one reaches the radius from anywhere in its cell.
        let mut levels = 1;
        while levels < MAX_LEVELS
            && (LEVEL_HALF as f32 * cell * (1u32 << levels) as f32) < radius + cell
        {
            levels += 1;
        }
        Some(Self {
            radius,
            cell_q,
            levels,
            card: (cell * CARD_WIDTH, field.height.max * CARD_HEIGHT),
            key: hash32(field.seed as u32 ^ 0xB111_B0A2 ^ hash32((field.seed >> 32) as u32)),
        })
    }

    /// The base cell's side in metres ([`BillboardLayout::cell_q`] converted from quanta).
    pub fn cell_size(&self) -> f32 {
        self.cell_q as f32 / QUANTA_PER_METRE as f32
    }

    /// Cards in the grids' index space (drawn or not).
    pub fn card_count(&self) -> u32 {
        self.levels * (level_side() * level_side()) as u32
    }

    /// The uniforms for a camera at `eye` with the blades' radius `max_distance`.
    pub fn params(
        &self,
        eye: Vec3,
        max_distance: f32,
        density: bool,
        spheres: u32,
        terrain_size: f32,
    ) -> BillboardParams {
        let cell = self.cell_size();
        // Far enough from the limits that the levels' cells (2^11 times larger) stay in i32.
        let cx = (eye.x / cell).floor().clamp(-1e8, 1e8) as i32;
        let cz = (eye.z / cell).floor().clamp(-1e8, 1e8) as i32;
        let fade_in = fade_in(max_distance);
        BillboardParams {
            cells: [cx, cz, level_side(), self.cell_q],
            fade: [fade_in.0, fade_in.1, FADE_OUT * self.radius, self.radius],
            eye_card: [eye.x, eye.z, self.card.0, self.card.1],
            info: [self.key, atlas::VARIANTS, u32::from(density), spheres],
            shape: [SWAY_GAIN, BEND_REACH, terrain_size, eye.y],
            albedo: [0.0; 4],
            levels: [self.levels, LEVEL_HALF as u32, level_side() as u32, 0],
        }
    }
}

/// The order the cull visits a level's cells in (`BillboardParams::levels` w, read by
/// `visit_order` in `billboard_cull.wgsl`), from the view direction `forward`: bit 0 walks
/// z downwards, bit 1 x downwards, bit 2 makes x the outer axis. The cull lists the cards
/// in the order it visits them (exactly, whatever order its workgroups run in), and the
/// draw draws them in that order: rows along
/// the view's main axis from the camera outwards, so the nearer cards come first and the
/// depth test rejects the hidden parts of the ones behind before they are shaded (the
/// cards are alpha-tested and overlap many times far out). Measured on llvmpipe at the
/// window's settled state (the default meadow at 468 × 360, d_max 13 m, cards to 64 m):
/// looking towards −z, which the rows used to be walked away from, the draw 54.0 / 56.3 ms
/// against 62.6 / 62.3 ms; looking towards +z the same (58–59 ms) either way.
pub fn visit_flags(forward: Vec3) -> u32 {
    let mut flags = 0;
    if forward.z < 0.0 {
        flags |= 1;
    }
    if forward.x < 0.0 {
        flags |= 2;
    }
    if forward.x.abs() > forward.z.abs() {
        flags |= 4;
    }
    flags
}

/// The cell the cull visits `i`-th (twin of `visit_order`): within each level of
/// `side × side` cells, rows along the outer axis in the order `flags` gives
/// ([`visit_flags`]).
pub fn visit_order(i: u32, side: u32, flags: u32) -> u32 {
    let per = side * side;
    let (level, j) = (i / per, i % per);
    let (outer, inner) = (j / side, j % side);
    let (mut x, mut z) = if flags & 4 != 0 {
        (outer, inner)
    } else {
        (inner, outer)
    };
    if flags & 1 != 0 {
        z = side - 1 - z;
    }
    if flags & 2 != 0 {
        x = side - 1 - x;
    }
    level * per + z * side + x
}

/// One card as the placement gives it (the twin of `card_at` in `billboard_place.wgsl`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Card {
    /// World position of the card's root (m): a hashed point in its cell, on the terrain.
    pub pos: Vec3,
    /// 0: outside the ring or outside its level (not drawn); else the fade factor in
    /// (0, 1].
    pub fade: f32,
    /// Its level: the card is 2^level base cards wide.
    pub level: u32,
    /// Which atlas strip (layer) the card shows, below [`atlas::VARIANTS`].
    pub variant: u32,
    /// Random size factor of the card, 0.8 to 1.2.
    pub scale: f32,
    /// +1 or −1 at random: whether the strip is drawn mirrored (+1 is sent as mirrored).
    pub mirror: f32,
    /// A value in [0, 1) that the density map must exceed at `pos` to keep the card.
    pub accept: f32,
}

fn rotl17(x: u32) -> u32 {
    x.rotate_left(17)
}

/// Card `i` of the grids: level `i / side²`, cell `i % side²` of that level's index space
/// (the children of the cells within `LEVEL_HALF − 1` of the camera's cell one level up).
pub fn place_card(p: &BillboardParams, terrain: &HeightField, i: u32) -> Card {
    let side = p.levels[2].max(1);
    let level = (i / (side * side)).min(31);
    let j = i % (side * side);
    let half = p.levels[1] as i32;
    // The camera's cell at this level and at the next (arithmetic shifts floor).
    let (cx0, cz0) = (p.cells[0] >> level, p.cells[1] >> level);
    let (px, pz) = (p.cells[0] >> (level + 1), p.cells[1] >> (level + 1));
    let cx = (px - (half - 1)) * 2 + (j % side) as i32;
    let cz = (pz - (half - 1)) * 2 + (j / side) as i32;
    // Level 0 keeps every cell; the others leave the hole the level inside fills.
    let inside = level > 0 && (cx - cx0).abs().max((cz - cz0).abs()) < half;
    let cell_q = p.cells[3].wrapping_shl(level);
    let h = hash32(
        p.info[0]
            ^ hash32(level.wrapping_mul(0x2545_F491))
            ^ hash32((cx as u32) ^ rotl17(hash32((cz as u32) ^ 0x68e3_1da4))),
    );
    let h1 = hash32(h.wrapping_add(0x9E37_79B9));
    let h2 = hash32(h.wrapping_add(0x3C6E_F372));
    let h3 = hash32(h.wrapping_add(0xDAA6_6D2B));
    let xq = cx
        .wrapping_mul(cell_q)
        .wrapping_add((h % cell_q as u32) as i32);
    let zq = cz
        .wrapping_mul(cell_q)
        .wrapping_add((h1 % cell_q as u32) as i32);
    let quantum = 1.0 / QUANTA_PER_METRE as f32;
    let (x, z) = (xq as f32 * quantum, zq as f32 * quantum);
    let unit = 1.0 / 16_777_216.0;
    let d = (Vec2::new(x, z) - Vec2::new(p.eye_card[0], p.eye_card[1])).length();
    let fade = if d >= p.fade[0] && d <= p.fade[3] && !inside {
        smoothstep(p.fade[0], p.fade[1], d) * (1.0 - smoothstep(p.fade[2], p.fade[3], d))
    } else {
        0.0
    };
    let pos = Vec3::new(x, terrain.height(x, z), z);
    // Seen from above, the far ground's canopy stands for the grass instead.
    let eye = Vec3::new(p.eye_card[0], p.shape[3], p.eye_card[1]);
    let fade = if fade > 0.0 {
        fade * (1.0 - crate::render::far_canopy::weight(pos, eye))
    } else {
        fade
    };
    Card {
        pos,
        fade,
        level,
        variant: h2 % p.info[1].max(1),
        scale: 0.8 + 0.4 * (h3 >> 8) as f32 * unit,
        mirror: if h2 & 0x100 != 0 { 1.0 } else { -1.0 },
        accept: (hash32(h3) >> 8) as f32 * unit,
    }
}

/// How far the top of a card of height `h` rooted at `root` moves (the twin of
/// `top_offset` in `billboard_sway.wgsl`): the wind the blades feel times the sway gain,
/// then away from and down under each sphere near it, and along and down by the bend of a
/// trail under it in the trail map `trails` (its words; empty: none); at most 0.9 h.
pub fn top_offset(
    p: &BillboardParams,
    sim: &SimParams,
    grid: &WindGrid,
    spheres: &[[f32; 4]],
    trails: &[u32],
    root: Vec3,
    h: f32,
) -> Vec3 {
    let top = root + Vec3::Y * h;
    let w = wind_at(top, h, sim, grid);
    let mut off = Vec3::new(w.x, 0.0, w.z) * p.shape[0] * h;
    for s in spheres.iter().take(p.info[3] as usize) {
        let reach = s[3] + h * p.shape[1];
        let d = Vec2::new(top.x - s[0], top.z - s[2]);
        let dist = d.length();
        if dist < reach && (top.y - s[1]).abs() < s[3] + h {
            let away = if dist > 1e-4 {
                d / dist.max(1e-4)
            } else {
                Vec2::X
            };
            let push = reach - dist;
            off += Vec3::new(away.x * push, -0.5 * push, away.y * push);
        }
    }
    let trail = crate::field::trails::sample(trails, root.x, root.z);
    if trail.x > 0.0 {
        let k = trail.x.min(1.0);
        off += Vec3::new(trail.y, -0.5, trail.z) * (k * h);
    }
    let len = off.length();
    if len > 0.9 * h {
        off *= 0.9 * h / len;
    }
    off
}

/// Cards the draw shows for `view_proj`: in the ring, kept by the density map, their
/// centre in the view (with a card's margin).
pub fn count_drawn(
    p: &BillboardParams,
    terrain: &HeightField,
    density: Option<&DensityMap>,
    view_proj: Mat4,
) -> u32 {
    drawn_cells(p, terrain, density, view_proj).len() as u32
}

/// The cells whose cards the draw shows, in cell order (the twin of `card_view` in
/// `billboard_cull.wgsl`, whose list holds the same cards in the order [`visit_order`]
/// visits their cells).
pub fn drawn_cells(
    p: &BillboardParams,
    terrain: &HeightField,
    density: Option<&DensityMap>,
    view_proj: Mat4,
) -> Vec<u32> {
    let side = p.levels[2];
    let mut kept = Vec::new();
    for i in 0..p.levels[0] * side * side {
        let c = place_card(p, terrain, i);
        if c.fade <= 0.0 || density.is_some_and(|m| c.accept >= m.sample(c.pos.x, c.pos.z)) {
            continue;
        }
        let centre = c.pos + Vec3::Y * (0.5 * p.eye_card[3] * c.scale);
        let clip = view_proj * centre.extend(1.0);
        let width = p.eye_card[2] * (1u32 << c.level) as f32;
        let margin = 1.0 + width / clip.w.max(1e-3);
        if clip.w > 0.0
            && clip.x.abs() <= clip.w * margin
            && clip.y.abs() <= clip.w * margin
            && clip.z <= clip.w
        {
            kept.push(i);
        }
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The levels reach the radius from anywhere in the camera's cell, and a radius past
    /// the cap keeps the base cell and adds levels instead.
    #[test]
    fn levels_reach_the_radius_and_the_base_cell_stops_growing() {
        let field = Field::default();
        let layout = |radius: f32| {
            let render = Render {
                billboard_distance: radius,
                ..Default::default()
            };
            BillboardLayout::from_scene(&render, &field).unwrap()
        };
        let near = layout(300.0);
        let far = layout(3000.0);
        assert!(
            (near.cell_size() - 1.5).abs() < 1e-3,
            "{}",
            near.cell_size()
        );
        assert_eq!(near.cell_q, far.cell_q);
        assert!(far.levels > near.levels, "{} {}", far.levels, near.levels);
        for l in [near, far, layout(40.0)] {
            let reach = LEVEL_HALF as f32 * l.cell_size() * (1u32 << l.levels) as f32;
            assert!(reach >= l.radius + l.cell_size(), "{l:?} reaches {reach}");
            let inner = LEVEL_HALF as f32 * l.cell_size() * (1u32 << (l.levels - 1)) as f32;
            assert!(
                l.levels == 1 || inner < l.radius + l.cell_size(),
                "{l:?}: one level too many"
            );
        }
        assert_eq!(
            far.card_count(),
            far.levels * (level_side() * level_side()) as u32
        );
    }
}
