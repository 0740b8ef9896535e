//! Tests of the tile layout, the residency and the CPU twin of the generation.

use super::*;
use crate::field::HeightField;
use crate::scene::Scene;

fn layout(tile_size: f32, radius: f32) -> TileLayout {
    let mut scene = Scene::default();
    scene.field.tile_size = tile_size;
    scene.field.density = 64.0;
    scene.field.patch_size = 256;
    scene.culling.max_distance = radius;
    TileLayout::from_scene(&scene.field, &scene.terrain, &scene.culling).unwrap()
}

#[test]
fn no_tiles_without_a_tile_size() {
    let scene = Scene::default();
    assert!(TileLayout::from_scene(&scene.field, &scene.terrain, &scene.culling).is_none());
}

#[test]
fn layout_keeps_the_density_and_whole_patches() {
    let l = layout(8.0, 20.0);
    // 256 blades at 64/m² is a 2 m patch: 4 patches along an 8 m tile.
    assert_eq!(l.patch_q, 2048);
    assert_eq!(l.grid, 4);
    assert_eq!(l.tile_size(), 8.0);
    assert_eq!(l.blades_per_tile(), 16 * 256);
    assert!((l.density() - 64.0).abs() < 1e-3);
    // A 40 m disk touches at most 6 × 6 tiles of 8 m.
    assert_eq!(l.slots, 36);
}

/// Every slot holds at most one tile, every resident tile is in exactly one slot, and every
/// tile within the radius is resident once the updates have caught up.
fn assert_consistent(r: &TileResidency, x: f32, z: f32) {
    let mut seen = std::collections::HashSet::new();
    for (slot, tile) in r.slots().iter().enumerate() {
        if let Some(t) = tile {
            assert!(seen.insert(*t), "tile {t:?} in two slots");
            assert_eq!(r.slot_of(*t), Some(slot as u32));
        }
    }
    assert_eq!(seen.len(), r.resident_count());
    for t in r.wanted(x, z) {
        assert!(r.slot_of(t).is_some(), "wanted tile {t:?} not resident");
    }
}

#[test]
fn residency_follows_the_camera_and_never_shares_a_slot() {
    let l = layout(8.0, 20.0);
    let mut r = TileResidency::new(l);
    let jobs = r.update(0.0, 0.0, usize::MAX);
    assert!(jobs.iter().all(|j| j.tile.is_some()));
    let first = r.resident_count();
    assert_eq!(jobs.len(), first);
    assert_consistent(&r, 0.0, 0.0);
    // Nothing changes while the camera stays.
    assert!(r.update(0.0, 0.0, usize::MAX).is_empty());
    // Fly along a curve, a few metres per update, with a limit on new tiles per update.
    let mut generated = r.generated();
    for step in 1..400 {
        let t = step as f32 * 0.05;
        let (x, z) = (t * 60.0, (t * 0.7).sin() * 80.0);
        let jobs = r.update(x, z, 24);
        let slots: std::collections::HashSet<u32> = jobs.iter().map(|j| j.slot).collect();
        assert_eq!(slots.len(), jobs.len(), "a slot twice in one update");
        generated += jobs.iter().filter(|j| j.tile.is_some()).count() as u64;
        assert_eq!(r.generated(), generated);
        // Catch up (the window does over the next frames) and check.
        while !r.update(x, z, 24).is_empty() {}
        assert_consistent(&r, x, z);
        assert!(r.resident_count() <= l.slots as usize);
    }
    assert!(
        r.generated() > first as u64 * 3,
        "the flight generated tiles"
    );
}

#[test]
fn nearest_tiles_come_first() {
    let l = layout(8.0, 20.0);
    let mut r = TileResidency::new(l);
    let jobs = r.update(3.0, 3.0, 1);
    assert_eq!(jobs.len(), 1);
    assert_eq!(jobs[0].tile, Some((0, 0)));
}

#[test]
fn a_bounded_terrain_has_no_tiles_past_its_edge() {
    let mut scene = Scene::default();
    scene.field.tile_size = 8.0;
    scene.terrain.size = 16.0;
    scene.terrain.unbounded = false;
    scene.culling.max_distance = 100.0;
    let l = TileLayout::from_scene(&scene.field, &scene.terrain, &scene.culling).unwrap();
    let r = TileResidency::new(l);
    let wanted = r.wanted(0.0, 0.0);
    assert!(!wanted.is_empty());
    let t = l.tile_size();
    let overlaps = |i: i32| (i as f32) * t < 8.0 && (i as f32 + 1.0) * t > -8.0;
    for tile in &wanted {
        assert!(
            overlaps(tile.0) && overlaps(tile.1),
            "{tile:?} is past the edge"
        );
    }
    let across = (-20..20).filter(|&i| overlaps(i)).count();
    assert_eq!(
        wanted.len(),
        across * across,
        "every tile on the square is wanted"
    );
}

fn gen_setup(seed: u64) -> (GenParams, TuftLayout, HeightField, TileLayout) {
    let mut scene = Scene::default();
    scene.field.tile_size = 4.0;
    scene.field.density = 64.0;
    scene.field.patch_size = 256;
    scene.field.seed = seed;
    scene.culling.max_distance = 10.0;
    let l = TileLayout::from_scene(&scene.field, &scene.terrain, &scene.culling).unwrap();
    let terrain = HeightField::from_scene(&scene.terrain).unwrap();
    let p = GenParams::new(&l, &scene.field, None);
    let tufts = p.tuft_layout(&l);
    (p, tufts, terrain, l)
}

#[test]
fn the_same_tile_gives_the_same_blades_and_other_tiles_differ() {
    let (p, tufts, terrain, l) = gen_setup(7);
    let a = generate_tile(&p, &tufts, &terrain, None, (3, -2));
    let b = generate_tile(&p, &tufts, &terrain, None, (3, -2));
    assert_eq!(a, b);
    assert_eq!(a.blades.len(), l.blades_per_tile() as usize);
    assert_eq!(a.patches.len(), l.patches_per_tile() as usize);
    let c = generate_tile(&p, &tufts, &terrain, None, (4, -2));
    assert_ne!(a.blades[0].v0_dir, c.blades[0].v0_dir);
    let (p2, tufts2, _, _) = gen_setup(8);
    let d = generate_tile(&p2, &tufts2, &terrain, None, (3, -2));
    assert_ne!(a.blades[0].v0_dir, d.blades[0].v0_dir);
}

#[test]
fn blades_stay_near_their_patch_with_attributes_in_range() {
    let (p, tufts, terrain, l) = gen_setup(3);
    let tile = (-5, 2);
    let t = generate_tile(&p, &tufts, &terrain, None, tile);
    let side = l.patch_q as f32 / QUANTA_PER_METRE as f32;
    // A tuft near the patch's edge reaches over it by at most the tuft radius.
    let reach = p.key[2] as f32 / QUANTA_PER_METRE as f32;
    let field = Scene::default().field;
    let mut tuft_blades = 0;
    for (i, b) in t.blades.iter().enumerate() {
        let patch = i as u32 / l.patch_size;
        let (px, pz) = (patch % l.grid, patch / l.grid);
        let x0 = tile.0 as f32 * l.tile_size() + px as f32 * side;
        let z0 = tile.1 as f32 * l.tile_size() + pz as f32 * side;
        let (x, z) = (b.v0_dir[0], b.v0_dir[2]);
        let m = if i as u32 % l.patch_size < p.key[1] {
            reach
        } else {
            0.0
        };
        assert!(
            x >= x0 - m && x < x0 + side + m && z >= z0 - m && z < z0 + side + m,
            "blade {i}"
        );
        let h = b.v1_height[3];
        assert!(h >= field.height.min && h <= field.height.max, "height {h}");
        let w = b.v2_width[3];
        assert!(w >= field.width.min && w <= field.width.max, "width {w}");
        assert!(b.v0_dir[3] >= 0.0 && b.v0_dir[3] < std::f32::consts::TAU);
        // The rest pose has the blade's length (the validation's fixed point).
        let v0 = glam::Vec3::from_slice(&b.v0_dir[..3]);
        let v1 = glam::Vec3::from_slice(&b.v1_height[..3]);
        let v2 = glam::Vec3::from_slice(&b.v2_width[..3]);
        let len = crate::field::blade::curve_length(v0, v1, v2);
        assert!(
            (len - h).abs() < 1e-3 * h.max(1.0),
            "blade {i}: length {len} vs {h}"
        );
        assert_eq!(t.states[i].rest_eta, [v2.x, v2.y, v2.z, 0.0]);
        tuft_blades += usize::from((i as u32 % l.patch_size) < p.key[1]);
    }
    // 40 % of each patch in tufts.
    assert_eq!(tuft_blades, (l.patches_per_tile() * p.key[1]) as usize);
    assert_eq!(p.key[1], (0.4f32 * 256.0).round() as u32);
    for (k, b) in t.patches.iter().enumerate() {
        let live = &t.blades[k * 256..(k + 1) * 256];
        assert_eq!(*b, patch_box(live));
        assert_eq!(b.min[3], 0.0);
    }
}

#[test]
fn a_density_map_thins_and_an_edge_removes() {
    let (mut p, tufts, terrain, _) = gen_setup(5);
    // Left half black, right half white over a 16 m square.
    let map = crate::field::DensityMap::from_values(16.0, 2, 1, vec![0.0, 1.0]).unwrap();
    p.map = [2, 1, generate::FLAG_DENSITY, 0];
    p.extent[1] = 16.0;
    let left = generate_tile(&p, &tufts, &terrain, Some(&map), (-2, 0));
    let right = generate_tile(&p, &tufts, &terrain, Some(&map), (1, 0));
    let live = |t: &TileBlades| t.blades.iter().filter(|b| b.v1_height[3] > 0.0).count();
    // x in [-8, -4]: density 0 to 0.25; x in [4, 8]: 0.75 to 1.
    let n = left.blades.len() as f32;
    assert!((live(&left) as f32) < 0.2 * n, "{}", live(&left));
    assert!((live(&right) as f32) > 0.8 * n, "{}", live(&right));
    // Bounded: a tile straddling the edge keeps only the blades inside.
    let (mut p, tufts, terrain, _) = gen_setup(5);
    p.map[2] = generate::FLAG_BOUNDED;
    p.extent[0] = 2.0;
    let t = generate_tile(&p, &tufts, &terrain, None, (0, 0));
    for b in &t.blades {
        if b.v1_height[3] > 0.0 {
            assert!(b.v0_dir[0] <= 2.0 && b.v0_dir[2] <= 2.0);
        } else {
            assert_eq!(*b, crate::field::blade::Blade::default());
        }
    }
    assert!(live(&t) > 0 && live(&t) < t.blades.len());
    let empty = generate_tile(&p, &tufts, &terrain, None, (5, 5));
    assert_eq!(live(&empty), 0);
    assert!(empty.patches.iter().all(|b| *b == empty_patch()));
}

/// Every tuft centre of the tiles in `tiles` (metres), with its tile.
fn centres(
    tufts: &TuftLayout,
    tiles: std::ops::RangeInclusive<i32>,
) -> Vec<((i32, i32), glam::Vec2)> {
    let q = 1.0 / QUANTA_PER_METRE as f32;
    let mut out = Vec::new();
    for tz in tiles.clone() {
        for tx in tiles.clone() {
            for pz in 0..tufts.grid {
                for px in 0..tufts.grid {
                    for t in 0..tufts.per_patch {
                        let (x, z) = tufts.centre((tx, tz), (px, pz), t);
                        out.push(((tx, tz), glam::Vec2::new(x as f32 * q, z as f32 * q)));
                    }
                }
            }
        }
    }
    out
}

#[test]
fn tuft_centres_keep_the_poisson_spacing_across_tile_and_period_borders() {
    for (seed, density, patch, tile) in [(3u64, 64.0, 256, 4.0), (17, 180.0, 1024, 8.0)] {
        let mut scene = Scene::default();
        scene.field.tile_size = tile;
        scene.field.density = density;
        scene.field.patch_size = patch;
        scene.field.seed = seed;
        scene.culling.max_distance = 10.0;
        let l = TileLayout::from_scene(&scene.field, &scene.terrain, &scene.culling).unwrap();
        let p = GenParams::new(&l, &scene.field, None);
        let tufts = p.tuft_layout(&l);
        assert_eq!(tufts.period, tufts::MAX_PERIOD);
        assert_eq!(p.tufts[0], tufts.period);
        assert_eq!(
            tufts.offsets.len(),
            (tufts.period * l.grid).pow(2) as usize * p.key[3] as usize
        );
        // The spacing is the dart throwing's first or second try: near the densest a random
        // sequential packing reaches (0.83 of the square root of the area per centre).
        let side = l.patch_q as f32 / QUANTA_PER_METRE as f32;
        let per_centre = (side * side / p.key[3] as f32).sqrt();
        assert!(
            tufts.min_distance >= 0.6 * per_centre,
            "spacing {} of {per_centre}",
            tufts.min_distance
        );
        // Tiles -1..=4 span one whole period and its borders on every side.
        let all = centres(&tufts, -1..=tufts.period as i32);
        let cell = tufts.min_distance;
        let mut grid: std::collections::HashMap<(i32, i32), Vec<usize>> = Default::default();
        for (k, (_, c)) in all.iter().enumerate() {
            grid.entry(((c.x / cell).floor() as i32, (c.y / cell).floor() as i32))
                .or_default()
                .push(k);
        }
        let (mut across, mut closest) = (0, f32::INFINITY);
        for (k, (tile, c)) in all.iter().enumerate() {
            let (gx, gz) = ((c.x / cell).floor() as i32, (c.y / cell).floor() as i32);
            for dz in -1..=1 {
                for dx in -1..=1 {
                    for &m in grid.get(&(gx + dx, gz + dz)).into_iter().flatten() {
                        if m <= k {
                            continue;
                        }
                        let d = c.distance(all[m].1);
                        closest = closest.min(d);
                        if all[m].0 != *tile && d < 2.0 * cell {
                            across += 1;
                        }
                    }
                }
            }
        }
        // Each pair measured to 1 quantum of rounding (the spacing is exact in quanta).
        assert!(
            closest >= cell - 1e-3,
            "seed {seed}: centres {closest} m apart, spacing {cell}"
        );
        // Neighbours across tile borders are as near as inside them: the layout has no
        // empty band along the borders.
        assert!(
            across > all.len() / 20,
            "{across} close pairs across borders of {}",
            all.len()
        );
        // Every patch holds its tufts' centres.
        for (tile, c) in &all {
            let (tx, tz) = l.tile_of(c.x, c.y);
            assert_eq!((tx, tz), *tile);
        }
    }
}

#[test]
fn the_tuft_layout_is_seeded_and_its_period_shrinks_for_crowded_tiles() {
    let (p, a, _, l) = gen_setup(7);
    assert_eq!(a, p.tuft_layout(&l));
    let (_, b, _, _) = gen_setup(8);
    assert_ne!(a.offsets, b.offsets);
    // 16 x 16 patches of 256 tufts: one tile is the period and holds 65,536 centres.
    assert_eq!(tufts::period_for(16, 256), 1);
    assert_eq!(tufts::period_for(3, 28), tufts::MAX_PERIOD);
    assert_eq!(tufts::period_for(16, 64), 2);
}
