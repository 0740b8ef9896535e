//! The far grass's light (`far_grass_facings` in `shaders/far_grass.wgsl`, with the blades'
//! own `blade_light`), which lights the far ground and the billboards, against its CPU twin
//! (`render::far_light`), under a real frame's uniforms and light: the prairie at noon and
//! at evening (the sun low and behind the grass, where the translucency dominates), points
//! near and far, on flat and tilted ground, still and waving; in a small frame, where every
//! blade is drawn as a quad (Eq. 24), and in a large one, where the near blades keep their
//! outline (the share of quads, `drawn_quad_share`, goes from 0 to 1 across the points).

mod common;

use glam::Vec3;
use sward::render::camera::CameraView;
use sward::render::far_light::{drawn_quad_share, far_grass_facings, probe_far_grass, FarPoint};
use sward::render::target::Target;
use sward::session::Session;

/// Largest difference allowed relative to 1 + the value: the GPU's exp, log, pow and
/// normalize against Rust's f32 ones (measured 1.8e-7).
const TOLERANCE: f32 = 1e-4;

/// The worst relative difference at 64 points, under the frame's uniforms for a frame of
/// `frame_size` (the probe takes them as given), and the range of the shares of quads the
/// points' facings saw.
fn check(scene: &str, frame_size: (u32, u32)) -> (f32, (f32, f32)) {
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
    let frame = r.frame_uniforms(&camera, frame_size.0, frame_size.1);
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
    let mut shares = (1.0f32, 0.0f32);
    for (q, (ambient, sun)) in points.iter().zip(&gpu_values) {
        // The shares of the points 2 m or more in front of the camera (behind it, or in its
        // plane, a blade's width in pixels has no meaning; the GPU and the twin still agree
        // there).
        let vp = glam::Mat4::from_cols_array_2d(&frame.view_proj);
        if (vp * q.p.extend(1.0)).w > 2.0 {
            for side in [Vec3::X, Vec3::Z, Vec3::new(1.0, 0.0, 1.0).normalize()] {
                let s = drawn_quad_share((&frame, &light), q.p, side);
                shares = (shares.0.min(s), shares.1.max(s));
            }
        }
        let (cpu_ambient, cpu_sun) =
            far_grass_facings((&frame, &light), q.p, q.normal, q.albedo, q.wave);
        let rel = |a: Vec3, b: Vec3| ((a - b).abs() / (Vec3::ONE + b.abs())).max_element();
        worst = worst.max(rel(*ambient, cpu_ambient));
        for j in 0..4 {
            worst = worst.max(rel(sun[j], cpu_sun[j]));
        }
        assert!(cpu_sun.iter().any(|s| s.length() > 0.0) || cpu_ambient.length() > 0.0);
    }
    (worst, shares)
}

#[test]
fn the_far_grass_light_matches_its_cpu_twin() {
    for scene in [
        "assets/scenes/prairie.ron",
        "assets/scenes/prairie_evening.ron",
    ] {
        for size in [(64, 36), (3840, 2160)] {
            let (worst, (lo, hi)) = check(scene, size);
            println!("{scene} {size:?}: worst relative difference {worst:.2e}, quads {lo}-{hi}");
            assert!(worst <= TOLERANCE, "{scene} {size:?}: {worst}");
            // The far points' blades are quads at both sizes; in the large frame the near
            // ones keep their outline.
            assert_eq!(hi, 1.0, "{scene} {size:?}");
            if size.0 > 100 {
                assert!(lo < 0.05, "{scene} {size:?}: {lo}-{hi}");
            }
        }
    }
}
