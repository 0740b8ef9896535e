//! The trail map (issue 29, point 4): where colliders pressed the grass of a streamed field,
//! kept in world space so that a trail outlives the blades that show it. A tile leaving the
//! blade radius loses its blades, not its trail: the tile's *page* of the map stays in a
//! bounded cache, and when the tile comes back its new blades take their collision strength
//! η and their bend from it. The billboards and the far ground read the same pages.
//!
//! A page covers one tile with `resolution`² texels of three words each:
//! - a *stamp* `η + a·t` (a the collision decay, t the time it was written): η decays by
//!   `a` per second (Eq. 2), so what is left at time t′ is `stamp − a·t′` whichever push
//!   wrote it, and the strongest remaining trail is the largest stamp. Stamps are never
//!   negative, so the GPU keeps the largest with an `atomicMax` on the float's bits;
//! - the bend of the last blade that wrote: its tip's displacement from its rest tip over its
//!   height, x and z.
//!
//! The GPU buffer is one array of words: a header ([`HEADER_WORDS`]), an open-addressing
//! table from tile to page (`capacity` entries of four words: tile x, tile z, page + 1, 0;
//! linear probing from [`table_slot`]), then the pages. Which tile has which page is decided
//! here on the CPU ([`TrailPages`]) when tiles enter and leave; pages are the tile pool's
//! slots plus `cache_tiles`, so the memory is bounded whatever the flight. This module is
//! also the CPU twin of the WGSL (`shaders/trails.wgsl`).

use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};

use glam::Vec3;

use crate::field::blade::{rest_pose, validate, Blade, BladeState};
use crate::field::noise::hash32;

/// Words of the header: see [`TrailLayout::header`].
pub const HEADER_WORDS: u32 = 16;
/// The header word holding the largest stamp ever written into the map (raised by the
/// update's writes, never lowered): while it has decayed to nothing, no reader probes the
/// table at all. Past the words the CPU uploads ([`CPU_HEADER_WORDS`]).
pub const MAX_STAMP_WORD: usize = 12;
/// The header words the CPU writes every step ([`TrailLayout::header`]'s first words): the
/// rest belong to the GPU.
pub const CPU_HEADER_WORDS: usize = 12;
/// Words per texel: stamp, bend x, bend z.
pub const TEXEL_WORDS: u32 = 3;
/// Blades with a smaller η leave no trail (a breath of contact is not a path).
pub const MIN_ETA: f32 = 0.02;
/// Quanta per metre: blade roots sit on a grid of 1/1024 m (`field::tiles`).
const QUANTA: f32 = 1024.0;

/// The sizes of one trail map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TrailLayout {
    /// Texels along a page's side.
    pub resolution: u32,
    /// Pages in the map: the tile pool's slots plus the cache.
    pub pages: u32,
    /// Entries of the tile → page table (a power of two, at least twice the pages).
    pub capacity: u32,
    /// A tile's side in quanta (1/1024 m).
    pub tile_q: i32,
}

impl TrailLayout {
    /// The layout of `pages` pages of `resolution`² texels for tiles `tile_q` quanta wide.
    pub fn new(resolution: u32, pages: u32, tile_q: i32) -> Self {
        Self {
            resolution: resolution.max(1),
            pages,
            capacity: (2 * pages.max(1)).next_power_of_two(),
            tile_q: tile_q.max(1),
        }
    }

    /// The word where the pages start (aligned to 256 bytes, so the pages can be bound on
    /// their own).
    pub fn texel_base(&self) -> u64 {
        (HEADER_WORDS as u64 + 4 * self.capacity as u64).div_ceil(64) * 64
    }

    /// Words of one page.
    pub fn page_words(&self) -> u64 {
        self.resolution as u64 * self.resolution as u64 * TEXEL_WORDS as u64
    }

    /// Bytes of the whole map (header, table, pages).
    pub fn bytes(&self) -> u64 {
        4 * (self.texel_base() + self.pages as u64 * self.page_words())
    }

    /// Byte range of page `page` in the buffer.
    pub fn page_range(&self, page: u32) -> (u64, u64) {
        let words = self.page_words();
        (4 * (self.texel_base() + page as u64 * words), 4 * words)
    }

    /// The word of texel `texel` of page `page`.
    pub fn texel_word(&self, page: u32, texel: u32) -> usize {
        (self.texel_base() + page as u64 * self.page_words() + (texel * TEXEL_WORDS) as u64)
            as usize
    }

    /// The tile and texel under world point (x, z): the twin of `trail_locate`.
    pub fn locate(&self, x: f32, z: f32) -> ((i32, i32), u32) {
        let q = |v: f32| (v * QUANTA).round().clamp(-2.0e9, 2.0e9) as i32;
        let (xq, zq) = (q(x), q(z));
        let t = self.tile_q;
        let tile = (xq.div_euclid(t), zq.div_euclid(t));
        let r = self.resolution as i64;
        let u = (xq.rem_euclid(t) as i64 * r / t as i64) as u32;
        let v = (zq.rem_euclid(t) as i64 * r / t as i64) as u32;
        (tile, v * self.resolution + u)
    }

    /// The header the shaders read: capacity, resolution, first page word, the blades of the
    /// tile pool (only they write), the tile side in quanta; the time, the decay and the
    /// ceiling of η; the tiles the pages cover (min x, min z, max x, max z; an empty box
    /// when none). Word [`MAX_STAMP_WORD`] is the GPU's and is left 0: upload only the
    /// first [`CPU_HEADER_WORDS`].
    pub fn header(
        &self,
        pool_blades: u32,
        now: f32,
        decay: f32,
        max_eta: f32,
        bounds: [i32; 4],
    ) -> [u32; HEADER_WORDS as usize] {
        let mut h = [0u32; HEADER_WORDS as usize];
        h[0] = self.capacity;
        h[1] = self.resolution;
        h[2] = self.texel_base() as u32;
        h[3] = pool_blades;
        h[4] = self.tile_q as u32;
        h[5] = now.to_bits();
        h[6] = decay.to_bits();
        h[7] = max_eta.to_bits();
        for (w, b) in h[8..12].iter_mut().zip(bounds) {
            *w = b as u32;
        }
        h
    }
}

/// The first table entry probed for `tile`: the twin of `trail_slot`.
pub fn table_slot(tile: (i32, i32), capacity: u32) -> u32 {
    hash32(tile.0 as u32 ^ hash32(tile.1 as u32).rotate_left(17)) & (capacity.max(1) - 1)
}

/// The page `table` (the words of the table: `capacity` entries of tile x, tile z, page +
/// 1, 0) gives `tile`, probing linearly from [`table_slot`] as the shaders' `trail_page`
/// does; `None` at the first empty entry or when the table is shorter.
pub fn find_page(table: &[u32], capacity: u32, tile: (i32, i32)) -> Option<u32> {
    let word = |i: usize| table.get(i).copied().unwrap_or(0);
    let mut s = table_slot(tile, capacity);
    for _ in 0..capacity {
        let e = 4 * s as usize;
        if word(e + 2) == 0 {
            return None;
        }
        if (word(e) as i32, word(e + 1) as i32) == tile {
            return Some(word(e + 2) - 1);
        }
        s = (s + 1) & (capacity.max(1) - 1);
    }
    None
}

/// The stamp of η written at time `now`.
pub fn stamp(eta: f32, now: f32, decay: f32) -> f32 {
    eta + decay * now
}

/// What is left at time `now` of a texel's stamp (≤ 0: no trail).
pub fn eta_left(stamp: f32, now: f32, decay: f32) -> f32 {
    stamp - decay * now
}

/// Which tile holds which page, and which pages hold the trails of tiles that left.
#[derive(Clone, Debug)]
pub struct TrailPages {
    layout: TrailLayout,
    page_of: HashMap<(i32, i32), u32>,
    resident: HashSet<(i32, i32)>,
    /// Cached (not resident) tiles by when they left, oldest first: the next to go.
    cached: BTreeMap<u64, (i32, i32)>,
    left_at: HashMap<(i32, i32), u64>,
    free: BTreeSet<u32>,
    clock: u64,
    /// Pages handed out since the last [`TrailPages::take_fresh`]: their old trail must be
    /// cleared before anything reads them.
    fresh: Vec<u32>,
    /// Whether the table changed since the last [`TrailPages::table`].
    changed: bool,
    /// Pages whose trail was dropped to make room (evictions), since the start.
    pub evicted: u64,
}

impl TrailPages {
    /// Every page free.
    pub fn new(layout: TrailLayout) -> Self {
        Self {
            layout,
            page_of: HashMap::new(),
            resident: HashSet::new(),
            cached: BTreeMap::new(),
            left_at: HashMap::new(),
            free: (0..layout.pages).collect(),
            clock: 0,
            fresh: Vec::new(),
            changed: true,
            evicted: 0,
        }
    }

    /// The map's sizes.
    pub fn layout(&self) -> &TrailLayout {
        &self.layout
    }

    /// The page holding `tile`'s trail, resident or cached.
    pub fn page_of(&self, tile: (i32, i32)) -> Option<u32> {
        self.page_of.get(&tile).copied()
    }

    /// Pages holding a trail of a tile that is not resident.
    pub fn cached_count(&self) -> usize {
        self.cached.len()
    }

    /// Makes the pages follow the resident tiles: tiles that left keep their page in the
    /// cache (newest kept longest); tiles that entered get their cached page back, or a
    /// free one, or the page of the tile that left longest ago (its trail is dropped). A
    /// tile gets no page only when every page is held by a resident tile, which the pool's
    /// size rules out.
    pub fn sync<'a>(&mut self, resident: impl IntoIterator<Item = &'a (i32, i32)>) {
        let now: HashSet<(i32, i32)> = resident.into_iter().copied().collect();
        let mut left: Vec<(i32, i32)> = self.resident.difference(&now).copied().collect();
        left.sort_unstable();
        for tile in left {
            self.resident.remove(&tile);
            self.clock += 1;
            self.cached.insert(self.clock, tile);
            self.left_at.insert(tile, self.clock);
        }
        let mut entered: Vec<(i32, i32)> = now.difference(&self.resident).copied().collect();
        entered.sort_unstable();
        for tile in entered {
            if let Some(when) = self.left_at.remove(&tile) {
                self.cached.remove(&when);
                self.resident.insert(tile);
                continue;
            }
            let page = match self.free.pop_first() {
                Some(p) => p,
                None => match self.cached.pop_first() {
                    Some((_, old)) => {
                        self.left_at.remove(&old);
                        self.evicted += 1;
                        self.page_of.remove(&old).expect("a cached tile has a page")
                    }
                    None => continue,
                },
            };
            self.page_of.insert(tile, page);
            self.resident.insert(tile);
            self.fresh.push(page);
            self.changed = true;
        }
    }

    /// The pages handed to new tiles since the last call (to clear before use).
    pub fn take_fresh(&mut self) -> Vec<u32> {
        std::mem::take(&mut self.fresh)
    }

    /// The table the shaders probe (`capacity` entries of tile x, tile z, page + 1, 0), if
    /// it changed since the last call.
    pub fn table(&mut self) -> Option<Vec<u32>> {
        if !std::mem::take(&mut self.changed) {
            return None;
        }
        let cap = self.layout.capacity;
        let mut words = vec![0u32; 4 * cap as usize];
        let mut tiles: Vec<_> = self.page_of.iter().collect();
        tiles.sort_unstable();
        for (&(tx, tz), &page) in tiles {
            let mut s = table_slot((tx, tz), cap);
            // At most half full: an empty entry is always found.
            while words[4 * s as usize + 2] != 0 {
                s = (s + 1) & (cap - 1);
            }
            let e = 4 * s as usize;
            words[e..e + 4].copy_from_slice(&[tx as u32, tz as u32, page + 1, 0]);
        }
        Some(words)
    }

    /// The tiles the pages cover: (min x, min z, max x, max z); an empty box (min > max)
    /// when no page is in use.
    pub fn bounds(&self) -> [i32; 4] {
        let mut b = [i32::MAX, i32::MAX, i32::MIN, i32::MIN];
        for &(x, z) in self.page_of.keys() {
            b = [b[0].min(x), b[1].min(z), b[2].max(x), b[3].max(z)];
        }
        b
    }
}

/// The trail at world point (x, z) read from a whole map's `words` as the shaders read it
/// (the twin of `trail_at`: the header's time, decay and ceiling, the table's probe): (η
/// left, bend x, bend z), zero where no page covers the point or nothing is left. An empty
/// or zeroed map has no trail anywhere.
pub fn sample(words: &[u32], x: f32, z: f32) -> Vec3 {
    let word = |i: usize| words.get(i).copied().unwrap_or(0);
    let capacity = word(0);
    if capacity == 0 || !capacity.is_power_of_two() {
        return Vec3::ZERO;
    }
    let layout = TrailLayout {
        resolution: word(1).max(1),
        pages: 0,
        capacity,
        tile_q: (word(4) as i32).max(1),
    };
    let (tile, texel) = layout.locate(x, z);
    let b = [word(8), word(9), word(10), word(11)].map(|w| w as i32);
    if tile.0 < b[0] || tile.1 < b[1] || tile.0 > b[2] || tile.1 > b[3] {
        return Vec3::ZERO;
    }
    let table = words.get(HEADER_WORDS as usize..).unwrap_or(&[]);
    let page = find_page(table, capacity, tile);
    let Some(page) = page else {
        return Vec3::ZERO;
    };
    let r = layout.resolution as u64;
    let w = (word(2) as u64
        + page as u64 * r * r * TEXEL_WORDS as u64
        + (texel * TEXEL_WORDS) as u64) as usize;
    let f = |i: usize| f32::from_bits(word(i));
    let eta = (f(w) - f(6) * f(5)).min(f(7));
    // A NaN is no trail either.
    if eta.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return Vec3::ZERO;
    }
    Vec3::new(eta, f(w + 1), f(w + 2))
}

/// The CPU twin of a pressed blade's write (`trail_write`): into `words` (the whole map),
/// at its root (x, z), η and its tip's displacement over its height.
pub fn write(
    words: &mut [u32],
    pages: &TrailPages,
    root: Vec3,
    eta: f32,
    bend: [f32; 2],
    now: f32,
    decay: f32,
) {
    if eta <= MIN_ETA {
        return;
    }
    let l = pages.layout();
    let (tile, texel) = l.locate(root.x, root.z);
    let Some(page) = pages.page_of(tile) else {
        return;
    };
    let w = l.texel_word(page, texel);
    let s = stamp(eta, now, decay);
    let old = f32::from_bits(words[w]);
    // The strongest trail keeps its bend (a weaker blade in the texel does not turn it).
    if s >= old {
        words[w] = s.to_bits();
        words[w + 1] = bend[0].to_bits();
        words[w + 2] = bend[1].to_bits();
        let max = &mut words[MAX_STAMP_WORD];
        *max = (*max).max(s.to_bits());
    }
}

/// The shading wave of the blades a trail `t` ([`sample`]) left (`trail_wave`): bent by
/// |bend| of their height, while the trail cripples them (η up to 1).
pub fn wave(t: Vec3) -> f32 {
    (1.5 * glam::Vec2::new(t.y, t.z).length()).clamp(0.0, 1.0) * t.x.clamp(0.0, 1.0)
}

/// [`wave`] at world point (x, z), interpolated bilinearly between the four texel centres
/// around it, the others clamped into the tile of the lower corner (along a tile's last
/// texel the value holds): the twin of `trail_wave_smooth`, the far ground's trail. Each
/// texel is read through [`sample`] at its centre, with the quantised locate.
pub fn wave_smooth(words: &[u32], x: f32, z: f32) -> f32 {
    let word = |i: usize| words.get(i).copied().unwrap_or(0);
    if word(0) == 0 {
        return 0.0;
    }
    let r = word(1).max(1) as f32;
    let texel = word(4) as f32 / (QUANTA * r);
    let g = glam::Vec2::new(x, z) / texel - 0.5;
    let base = g.floor();
    let f = g - base;
    let tile = ((base + 0.5) / r).floor();
    let uv = base - tile * r;
    let centre = |du: f32, dv: f32| {
        let u = (uv.x + du).min(r - 1.0);
        let v = (uv.y + dv).min(r - 1.0);
        let at = (tile * r + glam::Vec2::new(u, v) + 0.5) * texel;
        wave(sample(words, at.x, at.y))
    };
    let (a, b) = (centre(0.0, 0.0), centre(1.0, 0.0));
    let (d, e) = (centre(0.0, 1.0), centre(1.0, 1.0));
    let lerp = |p: f32, q: f32, t: f32| p + (q - p) * t;
    lerp(lerp(a, b, f.x), lerp(d, e, f.x), f.y)
}

/// The pose of a blade bent by a trail: leaning towards its rest tip moved by `bend` times
/// its height, at the tip distance where the validated curve has the blade's length (as
/// [`rest_pose`]: a fixed point of the validation, so the update takes it as it is).
pub fn bent_pose(v0: Vec3, up: Vec3, rest: Vec3, bend: [f32; 2], height: f32) -> (Vec3, Vec3) {
    let dir = rest + Vec3::new(bend[0], 0.0, bend[1]) * height - v0;
    let along = dir.dot(up);
    let across = dir - up * along;
    let side = across.length();
    if side < 1e-6 * height {
        return validate(v0, rest, up, height);
    }
    rest_pose(v0, up, across / side, height, side.atan2(along))
}

/// The CPU twin of a generated blade taking its trail back (`trail_restore` in
/// `tile_gen.wgsl`): from the texel words `[stamp, bend x, bend z]` under its root, the η
/// left at `now` (at most `max_eta`) and the pose bent towards its tip moved by the bend
/// ([`bent_pose`]). Nothing changes where no trail is left.
pub fn restore(
    blade: &mut Blade,
    state: &mut BladeState,
    texel: [u32; 3],
    now: f32,
    decay: f32,
    max_eta: f32,
) {
    let height = blade.v1_height[3];
    let eta = eta_left(f32::from_bits(texel[0]), now, decay).min(max_eta);
    if eta.is_nan() || eta <= 0.0 || height.is_nan() || height <= 0.0 {
        return;
    }
    let v0 = Vec3::from_slice(&blade.v0_dir[..3]);
    let up = Vec3::from_slice(&blade.up_stiffness[..3]);
    let rest = Vec3::from_slice(&state.rest_eta[..3]);
    let bend = [f32::from_bits(texel[1]), f32::from_bits(texel[2])];
    let (v1, v2) = bent_pose(v0, up, rest, bend, height);
    if !(v1.is_finite() && v2.is_finite()) {
        return;
    }
    blade.v1_height = [v1.x, v1.y, v1.z, height];
    blade.v2_width = [v2.x, v2.y, v2.z, blade.v2_width[3]];
    state.rest_eta[3] = eta;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layout(pages: u32) -> TrailLayout {
        TrailLayout::new(8, pages, 8192)
    }

    #[test]
    fn a_point_lands_in_its_tile_and_texel_on_both_sides_of_zero() {
        let l = layout(4);
        // 8 m tiles of 8 texels: 1 m texels.
        assert_eq!(l.locate(0.5, 0.5), ((0, 0), 0));
        assert_eq!(l.locate(7.99, 1.2), ((0, 0), 8 + 7));
        assert_eq!(l.locate(-0.5, -0.5), ((-1, -1), 7 * 8 + 7));
        assert_eq!(l.locate(-8.0, 16.0), ((-1, 2), 0));
        // Far away and non-finite points still land somewhere (clamped), without a panic.
        let _ = l.locate(f32::NAN, 1e30);
    }

    #[test]
    fn a_stamp_decays_as_eta_does_and_the_strongest_trail_wins() {
        let (a, t0) = (0.25, 10.0);
        let s = stamp(1.5, t0, a);
        assert!((eta_left(s, t0 + 2.0, a) - 1.0).abs() < 1e-5);
        // A weaker push later does not replace a stronger one that is still stronger now.
        let later = stamp(0.4, t0 + 2.0, a);
        assert!(s.max(later) == s);
        // Past η / a seconds nothing is left.
        assert!(eta_left(s, t0 + 6.01, a) <= 0.0);
    }

    #[test]
    fn pages_follow_the_tiles_and_the_oldest_cached_trail_goes_first() {
        let mut p = TrailPages::new(layout(3));
        p.sync(&[(0, 0), (1, 0)]);
        assert_eq!(p.take_fresh().len(), 2);
        let first = p.page_of((0, 0)).unwrap();
        // (0, 0) leaves: its page stays, cached.
        p.sync(&[(1, 0)]);
        assert_eq!(p.page_of((0, 0)), Some(first));
        assert_eq!(p.cached_count(), 1);
        // (2, 0) takes the free page; (0, 0) keeps its own.
        p.sync(&[(1, 0), (2, 0)]);
        assert_eq!(p.page_of((0, 0)), Some(first));
        // (3, 0) needs a page: (0, 0)'s trail, the only cached one, is dropped.
        p.sync(&[(1, 0), (2, 0), (3, 0)]);
        assert_eq!(p.page_of((0, 0)), None);
        assert_eq!(p.page_of((3, 0)), Some(first));
        assert_eq!(p.evicted, 1);
        assert_eq!(p.take_fresh(), vec![2, first]);
        // Coming back with its page still cached returns it, and no page is fresh.
        p.sync(&[(1, 0), (2, 0)]);
        p.sync(&[(1, 0), (2, 0), (3, 0)]);
        assert!(p.take_fresh().is_empty());
        assert_eq!(p.page_of((3, 0)), Some(first));
    }

    #[test]
    fn the_table_finds_every_page_and_no_other_tile() {
        let l = layout(40);
        let mut p = TrailPages::new(l);
        let tiles: Vec<(i32, i32)> = (-3..3).flat_map(|x| (-3..3).map(move |z| (x, z))).collect();
        p.sync(&tiles[..36]);
        let table = p.table().expect("changed");
        assert!(p.table().is_none(), "unchanged since");
        for &t in &tiles {
            assert_eq!(find_page(&table, l.capacity, t), p.page_of(t), "{t:?}");
        }
        assert_eq!(find_page(&table, l.capacity, (10, 10)), None);
        assert_eq!(p.bounds(), [-3, -3, 2, 2]);
    }

    #[test]
    fn a_written_trail_comes_back_decayed_with_its_bend() {
        let l = layout(2);
        let mut p = TrailPages::new(l);
        p.sync(&[(0, 0)]);
        let mut words = vec![0u32; (l.bytes() / 4) as usize];
        let root = Vec3::new(2.3, 0.0, 4.7);
        write(&mut words, &p, root, 1.2, [0.5, -0.25], 3.0, 0.25);
        // A weaker blade in the same texel changes neither the trail nor its bend.
        write(&mut words, &p, root, 0.3, [0.1, 0.0], 3.0, 0.25);
        let (_, texel) = l.locate(root.x, root.z);
        let w = l.texel_word(p.page_of((0, 0)).unwrap(), texel);
        let texel = [words[w], words[w + 1], words[w + 2]];
        let h = 0.6;
        let mut blade = Blade {
            v0_dir: [root.x, 0.0, root.z, 0.0],
            v1_height: [root.x, 0.3, root.z, h],
            v2_width: [root.x, h, root.z, 0.03],
            up_stiffness: [0.0, 1.0, 0.0, 8.0],
        };
        let mut state = BladeState {
            rest_eta: [root.x, h, root.z, 0.0],
        };
        restore(&mut blade, &mut state, texel, 5.0, 0.25, 2.0);
        // 1.2 written at t = 3, 2 s of decay at 0.25/s.
        assert!(
            (state.rest_eta[3] - 0.7).abs() < 1e-5,
            "{:?}",
            state.rest_eta
        );
        // The tip leans along the strongest blade's bend, (0.5, −0.25) of the height.
        let tip = Vec3::from_slice(&blade.v2_width[..3]) - root;
        assert!(tip.x > 0.0 && (tip.z / tip.x + 0.5).abs() < 1e-3, "{tip}");
        assert!((Vec3::from_slice(&blade.v1_height[..3]) - root).length() < h);
        // Past the trail's life nothing changes.
        let mut b2 = blade;
        let mut s2 = BladeState {
            rest_eta: [root.x, h, root.z, 0.0],
        };
        restore(&mut b2, &mut s2, texel, 30.0, 0.25, 2.0);
        assert_eq!((b2, s2.rest_eta[3]), (blade, 0.0));
    }

    proptest::proptest! {
        /// Whatever the tiles do, every resident tile has a page of its own, no two tiles
        /// share one, a tile that stays keeps its page, and the table finds each tile's
        /// page.
        #[test]
        fn pages_stay_consistent_under_any_flight(
            steps in proptest::collection::vec(
                proptest::collection::btree_set((-6i32..6, -6i32..6), 0..9),
                1..40,
            ),
            cache in 0u32..6,
        ) {
            let l = TrailLayout::new(4, 9 + cache, 4096);
            let mut p = TrailPages::new(l);
            let mut held: HashMap<(i32, i32), u32> = HashMap::new();
            let mut table = Vec::new();
            for resident in &steps {
                p.sync(resident);
                let _ = p.take_fresh();
                let mut used = HashSet::new();
                for t in resident {
                    let page = p.page_of(*t);
                    proptest::prop_assert!(page.is_some(), "{t:?} has no page");
                    let page = page.unwrap();
                    proptest::prop_assert!(page < l.pages);
                    proptest::prop_assert!(used.insert(page), "page {page} shared");
                    // A tile that stays keeps its page (its trail).
                    if let Some(&before) = held.get(t) {
                        proptest::prop_assert_eq!(before, page);
                    }
                }
                proptest::prop_assert!(p.cached_count() as u32 <= l.pages);
                if let Some(t) = p.table() {
                    table = t;
                }
                if !table.is_empty() {
                    for t in resident {
                        proptest::prop_assert_eq!(
                            find_page(&table, l.capacity, *t),
                            p.page_of(*t)
                        );
                    }
                }
                held = resident.iter().map(|t| (*t, p.page_of(*t).unwrap())).collect();
            }
        }
    }
}
