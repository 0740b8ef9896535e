//! The far grass's light (`far_grass_facings` in `shaders/far_grass.wgsl`, with the blades'
//! own `blade_light`), which lights the far ground and the billboards, against its CPU twin
//! (`render::far_light`), under a real frame's uniforms and light: the prairie at noon and
//! at evening (the sun low and behind the grass, where the translucency dominates), points
//! near and far, on flat and tilted ground, still and waving.

mod common;

use glam::Vec3;
use sward::render::camera::CameraView;
use sward::render::far_light::{far_grass_facings, probe_far_grass, FarPoint};
use sward::render::target::Target;
use sward::session::Session;

/// Largest difference allowed relative to 1 + the value: the GPU's exp, log, pow and
/// normalize against Rust's f32 ones (measured 1.8e-7).
const TOLERANCE: f32 = 1e-4;

fn check(scene: &str) -> f32 {
    let gpu = common::gpu();
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(scene);
    let scene = sward::scene::load_scene(&path).expect("scene");
    let session = Session::new(scene, None, Some(&gpu)).expect("session");
    let mut r = common::world(&gpu, &session);
    let camera = CameraView::from_scene(&session.scene.camera);
    let size = (64, 36);
    let target = Target::new(&gpu, size.0, size.1).expect("target");
    sward::commands::world_frame(&gpu, &mut r, 1.0 / 30.0, camera, &target).expect("frame");
    gpu.check_errors().expect("no GPU error");
    let frame = r.frame_uniforms(&camera, size.0, size.1);
    let light = *r.light().uniforms();
    let mut points = Vec::new();
    for k in 0..64 {
        let d = 5.0 * 1.08f32.powi(k);
        let angle = k as f32 * 2.399;
        let p = camera.eye + Vec3::new(angle.cos() * d, -camera.eye.y, angle.sin() * d);
        let tilt = (k % 5) as f32 * 0.15;
        points.push(FarPoint {
            p,
            normal: Vec3::new(tilt, 1.0, -0.5 * tilt).normalize(),
            albedo: Vec3::new(0.08, 0.2, 0.04) * (1.0 + (k % 3) as f32 * 0.2),
            wave: (k % 4) as f32 * 0.1,
        });
    }
    let gpu_values = probe_far_grass(&gpu, &r, &frame, &points).expect("probe");
    let mut worst = 0.0f32;
    for (q, (ambient, sun)) in points.iter().zip(&gpu_values) {
        let (cpu_ambient, cpu_sun) =
            far_grass_facings((&frame, &light), q.p, q.normal, q.albedo, q.wave);
        let rel = |a: Vec3, b: Vec3| ((a - b).abs() / (Vec3::ONE + b.abs())).max_element();
        worst = worst.max(rel(*ambient, cpu_ambient));
        for j in 0..4 {
            worst = worst.max(rel(sun[j], cpu_sun[j]));
        }
        assert!(cpu_sun.iter().any(|s| s.length() > 0.0) || cpu_ambient.length() > 0.0);
    }
    worst
}

#[test]
fn the_far_grass_light_matches_its_cpu_twin() {
    for scene in [
        "assets/scenes/prairie.ron",
        "assets/scenes/prairie_evening.ron",
    ] {
        let worst = check(scene);
        println!("{scene}: worst relative difference {worst:.2e}");
        assert!(worst <= TOLERANCE, "{scene}: {worst}");
    }
}
