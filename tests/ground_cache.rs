//! The ground's shadow depth kept between frames (`light::ground_cache`; issue 26, point
//! 4: static casters cached per cascade). Kept or drawn again, every cascade must hold
//! the same depth, so the pictures are compared byte for byte against drawing the ground
//! into every cascade every frame: with a still camera (the cache is used, and the
//! counted shadow pass must show the ground's fragments gone) and with a camera that
//! moves every frame (the cache must notice and draw again).

mod common;

use sward::render::camera::CameraView;
use sward::render::target::Target;
use sward::render::timing::SHADOWS;
use sward::scene::Scene;
use sward::session::Session;

const SIZE: (u32, u32) = (128, 72);
const FRAMES: usize = 5;

/// The default meadow: hills under a sun low enough for the ground to cast.
fn scene() -> Scene {
    let mut s = Scene::default();
    s.terrain.size = 12.0;
    s.render.msaa = 1;
    s
}

/// `FRAMES` frames, the camera moved `step` metres along x each frame; the last one
/// counted. The picture and the counted shadow pass's fragment invocations.
fn render(cache: bool, step: f32) -> (image::RgbaImage, u64) {
    let gpu = common::gpu();
    let session = Session::new(scene(), None, Some(&gpu)).expect("field");
    let (mut r, _) = common::draw_frames(&gpu, &session, SIZE, 0, false, |r| {
        r.cache_ground_shadows = cache;
    });
    let target = Target::new(&gpu, SIZE.0, SIZE.1).expect("target");
    let mut camera = CameraView::from_scene(&session.scene.camera);
    for k in 0..FRAMES {
        if k + 1 == FRAMES {
            assert!(r.count_work(&gpu, true), "lavapipe counts work");
        }
        camera.eye.x += step;
        camera.target.x += step;
        sward::commands::world_frame(&gpu, &mut r, 1.0 / 30.0, camera, &target).expect("frame");
    }
    gpu.check_errors().expect("no GPU error");
    let work = r.read_work(&gpu).expect("read").expect("counted");
    let image = target.read_image(&gpu).expect("image");
    (image, work.rows[SHADOWS].fragment_invocations)
}

fn differing(a: &image::RgbaImage, b: &image::RgbaImage) -> usize {
    a.pixels().zip(b.pixels()).filter(|(p, q)| p != q).count()
}

#[test]
fn a_still_camera_copies_the_ground_and_draws_the_same_shadows() {
    let (kept, kept_fragments) = render(true, 0.0);
    let (drawn, drawn_fragments) = render(false, 0.0);
    println!("shadow fragments: kept {kept_fragments}, drawn {drawn_fragments}");
    assert_eq!(
        differing(&kept, &drawn),
        0,
        "the kept ground shadows differently"
    );
    // The ground fills each cascade it casts into: keeping it must remove most of the
    // pass's fragments, or the cache was never used (or the ground never cast).
    assert!(
        kept_fragments * 2 < drawn_fragments,
        "the ground was drawn again: {kept_fragments} vs {drawn_fragments} fragments"
    );
}

#[test]
fn a_moving_camera_draws_the_ground_again_and_the_same_shadows() {
    let (kept, kept_fragments) = render(true, 0.37);
    let (drawn, drawn_fragments) = render(false, 0.37);
    println!("shadow fragments: cache on {kept_fragments}, off {drawn_fragments}");
    assert_eq!(
        differing(&kept, &drawn),
        0,
        "a stale ground shadow was kept"
    );
    assert_eq!(
        kept_fragments, drawn_fragments,
        "the camera moved: the ground must be drawn as without the cache"
    );
}
