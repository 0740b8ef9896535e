//! The trail map (issue 29, point 4; `field::trails`, `shaders/trails.wgsl`): a ball rolls
//! through a streamed field and presses a trail; the camera flies 200 m away, so every tile
//! of the trail leaves the pool and its blades are gone, and comes back. With the map the
//! returning tiles' blades take their trail back: the same η less the decay of the time
//! away, bent as they were pressed; with a map too small to keep them (no cache) the trail
//! is dropped, as it was before the map.
//!
//! - The update's write (`trail_write`) against its twin's invariant: every pressed blade's
//!   texel holds at least the blade's η (the map keeps the strongest), and only texels the
//!   ball passed hold a trail.
//! - The generation's read (`trail_restore` in `tile_gen.wgsl`) against its CPU twin
//!   (`trails::restore` on the twin's fresh blade and the texel read back): η within 1e-6,
//!   v1 and v2 within 5e-3 m (the terrain in f32 against f64, as `tests/twin_tiles.rs`).

mod common;

use glam::Vec3;
use sward::field::tiles::generate_tile;
use sward::field::trails::{self, TrailLayout};
use sward::gpu::Gpu;
use sward::render::camera::CameraView;
use sward::render::target::Target;
use sward::scene::{HeightSource, Motion, Scene, Sphere, Trails};
use sward::session::Session;

const SIZE: (u32, u32) = (48, 32);
const DECAY: f32 = 0.1;

fn scene(cache_tiles: u32) -> Scene {
    let mut s = common::still_scene();
    s.terrain.height = HeightSource::Flat;
    s.terrain.size = 1000.0;
    s.field.tile_size = 4.0;
    s.field.density = 48.0;
    s.field.patch_size = 256;
    s.field.seed = 5;
    s.culling.max_distance = 9.0;
    s.culling.physics_throttle = 1;
    s.physics.gravity_acceleration = 9.81;
    s.physics.collision_decay = DECAY;
    s.physics.trails = Some(Trails {
        resolution: 16,
        cache_tiles,
    });
    // Along z = 1 at 2 m/s from x = -3: it leaves the tile at the origin after 3.7 s.
    s.colliders = vec![Sphere {
        center: (-3.0, 0.25, 1.0),
        radius: 0.35,
        motion: Motion::Velocity((2.0, 0.0, 0.0)),
    }];
    s.camera.eye = (0.0, 4.0, -6.0);
    s.camera.target = (0.0, 0.0, 1.0);
    s
}

struct Run {
    gpu: Gpu,
    session: Session,
    r: sward::embed::GrassRenderer,
    target: Target,
    camera: CameraView,
}

impl Run {
    fn new(scene: Scene) -> Self {
        let gpu = common::gpu();
        let session = Session::new(scene, None, Some(&gpu)).expect("session");
        let r = common::world(&gpu, &session);
        let target = Target::new(&gpu, SIZE.0, SIZE.1).expect("target");
        let camera = CameraView::from_scene(&session.scene.camera);
        Self {
            gpu,
            session,
            r,
            target,
            camera,
        }
    }

    fn frames(&mut self, n: usize, dt: f32) {
        for _ in 0..n {
            sward::commands::world_frame(&self.gpu, &mut self.r, dt, self.camera, &self.target)
                .expect("frame");
        }
        self.gpu.check_errors().expect("no GPU error");
    }

    fn layout(&self) -> TrailLayout {
        *self
            .r
            .tiles()
            .and_then(|t| t.trails.as_ref())
            .expect("a trail map")
            .layout()
    }

    /// The slot of `tile` and its blades' η.
    fn etas(&self, tile: (i32, i32)) -> Option<(usize, Vec<f32>)> {
        let t = self.r.tiles()?;
        let slot = t.residency.slot_of(tile)? as usize;
        let per = t.params().layout[3] as usize;
        let (_, states) = self.r.buffers.read(&self.gpu).expect("states");
        Some((
            slot,
            states[slot * per..(slot + 1) * per]
                .iter()
                .map(|s| s.rest_eta[3])
                .collect(),
        ))
    }
}

fn most(v: &[f32]) -> f32 {
    v.iter().copied().fold(0.0, f32::max)
}

/// The ball presses the grass for 5 s; then the camera is 200 m away for 40 frames (1.33 s).
fn press_and_leave(run: &mut Run) -> ((i32, i32), f32, f32) {
    run.frames(150, 1.0 / 30.0);
    let layout = run.layout();
    let (tile, _) = layout.locate(1.0, 1.0);
    let (_, etas) = run.etas(tile).expect("the tile at the trail is resident");
    let before = most(&etas);
    let left_at = run.r.time;
    assert!(before > 0.5, "the ball pressed the tile: most η {before}");
    run.camera.eye.x -= 200.0;
    run.camera.target.x -= 200.0;
    run.frames(40, 1.0 / 30.0);
    assert!(run.etas(tile).is_none(), "the tile left the pool");
    (tile, before, left_at)
}

#[test]
fn a_trail_outlives_its_tile_and_comes_back_decayed() {
    let mut run = Run::new(scene(256));
    // The update's writes, checked while the trail is fresh: after 3 s (the ball at x = 3).
    run.frames(90, 1.0 / 30.0);
    let layout = run.layout();
    let words = run.r.buffers.read_trails(&run.gpu).expect("trails");
    let (blades, states) = run.r.buffers.read(&run.gpu).expect("blades");
    let pages = run.r.tiles().and_then(|t| t.trails.as_ref()).unwrap();
    let now = run.r.time;
    let pool = run.r.tiles().unwrap().residency.layout().pool_blades() as usize;
    let mut pressed = 0;
    for (b, s) in blades.iter().zip(&states).take(pool) {
        let eta = s.rest_eta[3];
        if eta <= trails::MIN_ETA + 1e-3 {
            continue;
        }
        pressed += 1;
        let (tile, texel) = layout.locate(b.v0_dir[0], b.v0_dir[2]);
        let page = pages.page_of(tile).expect("a resident tile has a page");
        let stamp = f32::from_bits(words[layout.texel_word(page, texel)]);
        let kept = trails::eta_left(stamp, now, DECAY);
        assert!(
            kept >= eta - 1e-4,
            "blade at ({}, {}) has η {eta}, its texel keeps {kept}",
            b.v0_dir[0],
            b.v0_dir[2]
        );
    }
    assert!(pressed > 50, "{pressed} blades pressed");
    // Only where the ball went: every texel with a trail is near z = 1, x ≤ 3.5.
    let r = layout.resolution as usize;
    let texel_m = layout.tile_q as f32 / 1024.0 / r as f32;
    let mut trail_texels = 0;
    for tz in -4..4 {
        for tx in -4..4 {
            let Some(page) = pages.page_of((tx, tz)) else {
                continue;
            };
            for k in 0..r * r {
                let w = layout.texel_word(page, k as u32);
                if trails::eta_left(f32::from_bits(words[w]), now, DECAY) <= 0.0 {
                    continue;
                }
                trail_texels += 1;
                let tile_m = layout.tile_q as f32 / 1024.0;
                let x = tx as f32 * tile_m + ((k % r) as f32 + 0.5) * texel_m;
                let z = tz as f32 * tile_m + ((k / r) as f32 + 0.5) * texel_m;
                assert!(
                    (z - 1.0).abs() < 0.35 + 0.6 + texel_m && x < 3.0 + 0.95 + texel_m,
                    "a trail at ({x}, {z}), away from the ball's way"
                );
            }
        }
    }
    assert!(trail_texels > 8, "{trail_texels} texels hold a trail");
    far_ground_reads_the_map_as_its_twin(&run.gpu, &words, pages, &layout);

    run.frames(60, 1.0 / 30.0);
    let layout = run.layout();
    let (tile, _) = layout.locate(1.0, 1.0);
    let (_, etas) = run.etas(tile).expect("resident");
    let before = most(&etas);
    let left_at = run.r.time;
    run.camera.eye.x -= 200.0;
    run.camera.target.x -= 200.0;
    run.frames(40, 1.0 / 30.0);
    assert!(run.etas(tile).is_none(), "the tile left the pool");
    let away = run.r.time - left_at;
    let pages = run.r.tiles().and_then(|t| t.trails.as_ref()).unwrap();
    assert!(
        pages.page_of(tile).is_some(),
        "its trail stays in the cache"
    );
    assert_eq!(pages.evicted, 0);

    // The map as the generation will read it (the returning blades write their own bends
    // back into it once they are stepped).
    let words = run.r.buffers.read_trails(&run.gpu).expect("trails");
    // Back, with the clock stopped (dt = 0): the update moves nothing (the generation's
    // pose is a fixed point of its validation), so the blades are as the generation made
    // them.
    run.camera.eye.x += 200.0;
    run.camera.target.x += 200.0;
    run.frames(12, 0.0);
    let (slot, etas) = run.etas(tile).expect("the tile is back");
    let after = most(&etas);
    let expected = before - DECAY * away;
    eprintln!(
        "most η in the tile: {before:.3} when it left, {after:.3} after {away:.2} s away \
         (expected {expected:.3}); {} of its blades still pressed",
        etas.iter().filter(|&&e| e > 0.0).count()
    );
    assert!(
        (after - expected).abs() < 2e-3,
        "η came back as {after}, expected {expected}"
    );

    // The generation's read against its twin, blade by blade.
    let (blades, states) = run.r.buffers.read(&run.gpu).expect("blades");
    let streamer = run.r.tiles().unwrap();
    let pages = streamer.trails.as_ref().unwrap();
    let twin = generate_tile(
        streamer.params(),
        streamer.tufts(),
        &run.session.terrain,
        None,
        tile,
    );
    let per = streamer.params().layout[3] as usize;
    let now = run.r.time;
    let mut restored = 0;
    for (i, (b, s)) in twin.blades.iter().zip(&twin.states).enumerate() {
        if b.v1_height[3] <= 0.0 {
            continue;
        }
        let (mut b, mut s) = (*b, *s);
        let (t, texel) = layout.locate(b.v0_dir[0], b.v0_dir[2]);
        let page = pages.page_of(t).expect("page");
        let w = layout.texel_word(page, texel);
        trails::restore(
            &mut b,
            &mut s,
            [words[w], words[w + 1], words[w + 2]],
            now,
            DECAY,
            2.0,
        );
        let (g, gs) = (&blades[slot * per + i], &states[slot * per + i]);
        let v = |a: &[f32; 4]| Vec3::new(a[0], a[1], a[2]);
        assert!(
            (gs.rest_eta[3] - s.rest_eta[3]).abs() < 1e-5,
            "blade {i}: η {} vs twin {}",
            gs.rest_eta[3],
            s.rest_eta[3]
        );
        assert!(
            (v(&g.v2_width) - v(&b.v2_width)).length() < 5e-3
                && (v(&g.v1_height) - v(&b.v1_height)).length() < 5e-3,
            "blade {i}: v1 {} v2 {} vs twin {} {}",
            v(&g.v1_height),
            v(&g.v2_width),
            v(&b.v1_height),
            v(&b.v2_width)
        );
        restored += (s.rest_eta[3] > 0.0) as usize;
    }
    assert!(restored > 20, "{restored} blades took a trail back");
}

/// The map's largest stamp (the readers' early out) is the largest texel stamp the update
/// wrote, and the far ground's read of the map (`trail_wave_smooth` and `trail_at`, probed
/// on the GPU) is its CPU twin's (`trails::wave_smooth`, `trails::sample`) over the ball's
/// path and the tile borders it crosses (tiles of 4 m, texels of 0.25 m).
fn far_ground_reads_the_map_as_its_twin(
    gpu: &Gpu,
    words: &[u32],
    pages: &trails::TrailPages,
    layout: &TrailLayout,
) {
    let r = layout.resolution;
    let largest = (-4..4)
        .flat_map(|tx| (-4..4).map(move |tz| (tx, tz)))
        .filter_map(|t| pages.page_of(t))
        .flat_map(|page| (0..r * r).map(move |k| words[layout.texel_word(page, k)]))
        .max()
        .unwrap();
    assert_eq!(
        words[trails::MAX_STAMP_WORD],
        largest,
        "the map's largest stamp"
    );

    // Off the texel centres (where the clamped interpolation may step at a tile's edge).
    let points: Vec<glam::Vec2> = (0..220)
        .flat_map(|i| (0..40).map(move |j| (i, j)))
        .map(|(i, j)| glam::Vec2::new(-4.5 + i as f32 * 0.0371, 0.2 + j as f32 * 0.0413))
        .collect();
    let got = sward::render::far_texture::probe_trails(gpu, words, &points).expect("probe");
    let mut waving = 0;
    for (p, (wave, at)) in points.iter().zip(&got) {
        let want = trails::wave_smooth(words, p.x, p.y);
        assert!(
            (wave - want).abs() < 1e-4,
            "wave at {p}: GPU {wave}, twin {want}"
        );
        let t = trails::sample(words, p.x, p.y);
        assert!(
            (*at - t).abs().max_element() < 1e-6,
            "trail at {p}: GPU {at}, twin {t}"
        );
        waving += (want > 0.1) as usize;
    }
    assert!(waving > 200, "{waving} points show the trail");
    // A map with nothing alive reads nothing, wherever.
    let mut old = words.to_vec();
    old[5] = (1e6f32).to_bits();
    let none = sward::render::far_texture::probe_trails(gpu, &old, &points).expect("probe");
    assert!(none.iter().all(|(w, t)| *w == 0.0 && *t == Vec3::ZERO));
}

#[test]
fn without_room_in_the_cache_a_trail_is_dropped() {
    let mut run = Run::new(scene(0));
    let (tile, _, _) = press_and_leave(&mut run);
    let pages = run.r.tiles().and_then(|t| t.trails.as_ref()).unwrap();
    assert!(pages.evicted > 0 && pages.page_of(tile).is_none());
    run.camera.eye.x += 200.0;
    run.camera.target.x += 200.0;
    run.frames(12, 0.0);
    let (_, etas) = run.etas(tile).expect("the tile is back");
    assert_eq!(most(&etas), 0.0, "a dropped trail came back");
}

/// The billboards read the same map: over the ball's trail a card's top goes the way the
/// trail's blades were bent, and down, so a trail that the ring of cards reaches (the
/// camera moved on, issue 27 point 4) does not vanish there. The probe (`billboard_sway.wgsl` with the map read
/// back from the renderer) against the CPU twin (`billboard::top_offset` reading the same
/// words through `trails::sample`): every card's top within 1e-3 m; the cards rooted on
/// the trail are lower than without the map (where the trail is strong, by more than a
/// quarter of their height) and no other card moved.
#[test]
fn billboards_over_a_trail_lie_down_as_its_blades_did() {
    use sward::render::billboard::{probe::probe_cards, top_offset, BillboardLayout};
    use sward::sim::reference::WindGrid;
    let mut s = scene(256);
    s.render.billboard_distance = 40.0;
    let mut run = Run::new(s.clone());
    run.frames(150, 1.0 / 30.0);
    let words = run.r.buffers.read_trails(&run.gpu).expect("trails");
    let terrain = &run.session.terrain;
    let layout = BillboardLayout::from_scene(&s.render, &s.field).expect("billboards");
    // Seen from 7 m behind the trail with blades to 4 m: the trail lies in the ring of
    // cards, as a trail pressed near the blade radius does once the camera moves on.
    let params = layout.params(Vec3::new(0.5, 3.0, 8.0), 4.0, false, 0, s.terrain.size);
    let sim = sward::sim::params::sim_params(&s.physics, &s.wind, s.terrain.size, 0.0, 0.0, 0, 0);
    let got = probe_cards(&run.gpu, terrain, &params, &sim, &[], &[], &words).expect("probe");
    let grid = WindGrid {
        velocity: &[[0.0, 0.0]],
    };
    let mut on_trail = 0;
    let mut in_ring = 0;
    // The most a card on the trail went down, in card heights.
    let mut lowest: f32 = 0.0;
    for (i, g) in got.iter().enumerate() {
        let c = g.card;
        let h = params.eye_card[3] * c.scale;
        let top = top_offset(&params, &sim, &grid, &[], &words, c.pos, h);
        assert!(
            (g.top - top).length() <= 1e-3,
            "card {i}: top {} vs {top}",
            g.top
        );
        let plain = top_offset(&params, &sim, &grid, &[], &[], c.pos, h);
        if trails::sample(&words, c.pos.x, c.pos.z).x > 0.0 {
            on_trail += 1;
            assert!(
                top.y < plain.y,
                "card {i} on the trail at {}: top {top} vs {plain} without it",
                c.pos
            );
            lowest = lowest.max((plain.y - top.y) / h);
            in_ring += usize::from(c.fade > 0.0);
        } else {
            assert_eq!(top, plain, "card {i} off the trail moved");
        }
    }
    eprintln!(
        "{on_trail} of {} cards stand on the trail ({in_ring} of them drawn, in the ring); \
         the most one went down: {lowest:.2} of its height",
        got.len()
    );
    assert!(
        on_trail > 0 && in_ring > 0,
        "no card on the trail in the ring"
    );
    assert!(lowest > 0.25, "no card lies down on the trail ({lowest})");
}
