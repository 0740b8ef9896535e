//! The blades' reach changed on a living renderer (the window's frame budget shortens
//! `culling.max_distance` frame by frame, and the panel's slider sets it) draws what a
//! renderer built with that reach draws: the far ground's turn from soil to grass follows
//! the reach of the frame, not the one the renderer was built with. (It did not: after the
//! budget had cut the window's meadow from 30 to 11 m, the ground from 11 to 30 m stayed
//! half soil, the far gain's near ring saw bare ground, and the cards turned black.)

mod common;

use sward::scene::Scene;

const SIZE: (u32, u32) = (160, 90);
const FRAMES: usize = 3;
/// The reach the scene is built with, and the one the frames are drawn with.
const BUILT: f32 = 60.0;
const DRAWN: f32 = 15.0;

/// The paper's nature scene (a whole field of 64 m: the same blades whatever the reach).
fn scene(reach: f32) -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/nature.ron");
    let mut s = sward::scene::load_scene(&path).expect("nature");
    s.culling.max_distance = reach;
    s
}

#[test]
fn a_reach_changed_while_running_draws_as_one_built_with_it() {
    let (built, _) = common::render_frames(scene(DRAWN), SIZE, FRAMES, |_| {});
    let (changed, _) = common::render_frames(scene(BUILT), SIZE, FRAMES, |r| {
        r.scene.culling.max_distance = DRAWN;
    });
    let (kept, _) = common::render_frames(scene(BUILT), SIZE, FRAMES, |_| {});
    let differing = |a: &image::RgbaImage, b: &image::RgbaImage| {
        a.pixels().zip(b.pixels()).filter(|(p, q)| p != q).count()
    };
    // The reach does change the picture (the test would prove nothing otherwise) ...
    let by_reach = differing(&built, &kept);
    assert!(
        by_reach > (SIZE.0 * SIZE.1 / 20) as usize,
        "a reach of {DRAWN} m against {BUILT} m changed only {by_reach} pixels"
    );
    // ... and changed on the running renderer, it draws exactly what a renderer built
    // with it draws.
    assert_eq!(
        differing(&built, &changed),
        0,
        "the reach changed while running draws otherwise than one built with it"
    );
}
