//! Shared test setup: the GPU (a CPU adapter unless SWARD_ADAPTER says otherwise, like
//! egui_kittest) and small scenes.
#![allow(dead_code)]

pub mod shapes;

use sward::embed::GrassRenderer;
use sward::gpu::{AdapterChoice, Gpu};
use sward::render::target::COLOR_FORMAT;
use sward::render::Renderer;
use sward::scene::{MeshCollider, MeshObject, Motion, Scene, Sphere, SpherePacking, Wind};
use sward::session::Session;

/// Opens the test adapter. Fails (never skips) when none exists: CI installs lavapipe.
pub fn gpu() -> Gpu {
    let choice: AdapterChoice = std::env::var("SWARD_ADAPTER")
        .unwrap_or_else(|_| "software".into())
        .parse()
        .expect("infallible");
    Gpu::new(&choice).unwrap_or_else(|e| panic!("tests need a GPU adapter: {e}"))
}

/// A renderer over `session`, advanced by `steps` update steps of `dt` seconds.
pub fn stepped(gpu: &Gpu, session: &Session, steps: u32, dt: f32) -> Renderer {
    let mut r = Renderer::from_session(gpu, session, COLOR_FORMAT).expect("renderer");
    for _ in 0..steps {
        r.step(gpu, dt);
    }
    r
}

/// A renderer over `session` that draws its frames through the embedding API
/// (`GrassRenderer::render_world` in `sward::commands::world_frame`), as the window and
/// `sward render` draw theirs.
pub fn world(gpu: &Gpu, session: &Session) -> GrassRenderer {
    let r = Renderer::from_session(gpu, session, COLOR_FORMAT).expect("renderer");
    GrassRenderer::wrap_world(gpu, r, COLOR_FORMAT)
}

/// One frame of `scene` (a whole-field session, one step of 1/30 s) from its camera, at
/// `size`, read back.
pub fn render_frame(scene: Scene, size: (u32, u32)) -> image::RgbaImage {
    render_frames(scene, size, 1, |_| {}).0
}

/// `frames` frames of `scene` (a whole-field session, steps of 1/30 s) from its camera, at
/// `size`, by a renderer `setup` has configured first: the last frame read back, and the
/// renderer.
pub fn render_frames(
    scene: Scene,
    size: (u32, u32),
    frames: usize,
    setup: impl FnOnce(&mut Renderer),
) -> (image::RgbaImage, GrassRenderer) {
    let gpu = gpu();
    let session = Session::new(scene, None, Some(&gpu)).expect("field");
    let (r, target) = draw_frames(&gpu, &session, size, frames, false, setup);
    (target.read_image(&gpu).expect("image"), r)
}

/// The prairie (`assets/scenes/prairie.ron`) with `sets` applied (as `--set` takes them).
pub fn prairie_scene(sets: &[&str]) -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/prairie.ron");
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    sward::scene::load_scene_with_sets(&path, &sets).expect("prairie")
}

/// Prints every band of a comparison (`compare::compare_bands`): the reference's luminance
/// and contrast, and the difference.
pub fn print_bands(diffs: &[sward::compare::BandDiff], reference: &image::RgbaImage) {
    for (d, b) in diffs.iter().zip(sward::compare::bands(reference)) {
        println!(
            "band {:3}: luminance {:6.1} ({:+6.1}), contrast {:5.1} ({:+4.0} %)",
            d.top,
            b.luminance,
            d.luminance,
            b.contrast,
            100.0 * d.contrast
        );
    }
}

/// The prairie with `sets`, its last frame of `frames` at `size` (`render_frames`).
pub fn prairie_frame(sets: &[&str], size: (u32, u32), frames: usize) -> image::RgbaImage {
    render_frames(prairie_scene(sets), size, frames, |_| {}).0
}

/// `frames` frames of `session`'s scene (steps of 1/30 s) from its camera, at `size`, by a
/// renderer `setup` has configured first; with `count_last`, the last frame's work is
/// counted (pipeline statistics: lavapipe has them, so the count must start). The renderer
/// (a counted frame ready for `read_work`) and the target the frames were drawn into.
pub fn draw_frames(
    gpu: &Gpu,
    session: &Session,
    size: (u32, u32),
    frames: usize,
    count_last: bool,
    setup: impl FnOnce(&mut Renderer),
) -> (GrassRenderer, sward::render::target::Target) {
    draw_frames_each(gpu, session, size, frames, setup, |k, r| {
        if count_last && k + 1 == frames {
            assert!(
                r.count_work(gpu, true),
                "lavapipe has pipeline-statistics queries: the frame must be counted"
            );
        }
    })
}

/// `draw_frames` with `before(k, renderer)` called before each frame k (a scene edited
/// between frames, as the panel edits it).
pub fn draw_frames_each(
    gpu: &Gpu,
    session: &Session,
    size: (u32, u32),
    frames: usize,
    setup: impl FnOnce(&mut Renderer),
    mut before: impl FnMut(usize, &mut GrassRenderer),
) -> (GrassRenderer, sward::render::target::Target) {
    let mut r = sward::embed::GrassRenderer::wrap_world(
        gpu,
        Renderer::from_session(gpu, session, COLOR_FORMAT).expect("renderer"),
        COLOR_FORMAT,
    );
    setup(&mut r);
    let camera = sward::render::camera::CameraView::from_scene(&session.scene.camera);
    let target = sward::render::target::Target::new(gpu, size.0, size.1).expect("target");
    for k in 0..frames {
        before(k, &mut r);
        sward::commands::world_frame(gpu, &mut r, 1.0 / 30.0, camera, &target).expect("frame");
    }
    gpu.check_errors().expect("no GPU error");
    (r, target)
}

/// A scene with no forces at all: no gravity, no wind, no colliders.
pub fn still_scene() -> Scene {
    let mut s = Scene::default();
    s.physics.gravity_acceleration = 0.0;
    s.physics.gravity_center_acceleration = 0.0;
    s.wind = Wind {
        directional: None,
        point: None,
        ..Wind::default()
    };
    s.colliders.clear();
    s
}

/// Still grass under gravity with the Stanford bunny at `scale`, packed with `count`
/// collision spheres, and a ball rolling towards it; every patch stepped every frame (the
/// CPU twin has no throttle). The collision tests' scene.
pub fn packed_bunny_scene(scale: f32, count: u32) -> Scene {
    let mut scene = still_scene();
    scene.physics.gravity_acceleration = 9.81;
    scene.culling.physics_throttle = 1;
    scene.colliders = vec![rolling_sphere(-4.0, 0.3, 0.35, 2.0)];
    scene.objects = vec![MeshObject {
        mesh: std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("assets/models/bunny.obj")
            .display()
            .to_string(),
        scale,
        collider: MeshCollider::Spheres(SpherePacking {
            count,
            ..Default::default()
        }),
        ..Default::default()
    }];
    scene
}

/// A sphere of radius `r` crossing the field along x at `speed` m/s, its centre `height`
/// above the ground, starting at x = `x0`.
pub fn rolling_sphere(x0: f32, height: f32, r: f32, speed: f32) -> Sphere {
    Sphere {
        center: (x0, height, 0.0),
        radius: r,
        motion: Motion::Velocity((speed, 0.0, 0.0)),
    }
}
