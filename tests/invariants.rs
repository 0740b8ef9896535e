//! Invariants of the blade model (Jahrmann & Wimmer Section 5), checked on the GPU kernel's
//! read-back and, where noted, on the CPU twin: curve length (Eq. 12) equals the height, v2
//! stays above the ground plane (Eq. 9), v1 − v0 is parallel to up (Eq. 11), the rest pose is
//! a fixed point, blades end outside a static sphere, and η fades and the blade recovers after
//! a collider leaves.

mod common;

use glam::Vec3;
use sward::commands::simulate_cpu;
use sward::scene::{Motion, Scene, Sphere};
use sward::session::Session;
use sward::sim::layout::{Blade, BladeState};
use sward::sim::reference::curve_length;

fn xyz(a: [f32; 4]) -> Vec3 {
    Vec3::new(a[0], a[1], a[2])
}

fn run_gpu(
    scene: Scene,
    blades: usize,
    steps: u32,
    dt: f32,
) -> (Session, Vec<Blade>, Vec<BladeState>) {
    let gpu = common::gpu();
    let session = Session::new(scene, Some(blades), Some(&gpu)).expect("field");
    let r = common::stepped(&gpu, &session, steps, dt);
    let (b, s) = r.buffers.read(&gpu).expect("read-back");
    (session, b, s)
}

/// Checks the three validation invariants on every blade.
fn assert_valid(blades: &[Blade], what: &str) {
    let mut worst_len = 0.0f32;
    for (i, b) in blades.iter().enumerate() {
        let (v0, v1, v2, up) = (
            xyz(b.v0_dir),
            xyz(b.v1_height),
            xyz(b.v2_width),
            xyz(b.up_stiffness),
        );
        let h = b.v1_height[3];
        let rel = (curve_length(v0, v1, v2) - h).abs() / h;
        worst_len = worst_len.max(rel);
        assert!(
            rel < 1e-3,
            "{what}: blade {i} length off by {:.3} %",
            rel * 100.0
        );
        assert!(
            up.dot(v2 - v0) >= -1e-5 * h,
            "{what}: blade {i} tip below its ground plane"
        );
        let side = (v1 - v0).cross(up).length();
        assert!(
            side < 1e-4 * h,
            "{what}: blade {i} v1 - v0 not parallel to up ({side})"
        );
    }
    println!(
        "{what}: worst curve-length error {:.2e} % over {} blades",
        worst_len * 100.0,
        blades.len()
    );
}

#[test]
fn validation_invariants_hold_under_wind_gravity_and_a_sphere() {
    let mut scene = Scene::default();
    scene
        .wind
        .directional
        .as_mut()
        .expect("default wind")
        .strength = 6.0;
    scene.colliders = vec![common::rolling_sphere(-3.0, 0.3, 0.5, 2.5)];
    let (session, blades, _) = run_gpu(scene.clone(), 1024, 60, 1.0 / 30.0);
    assert_valid(&session.field.blades, "initial field");
    assert_valid(&blades, "gpu after 60 steps");
    let session = Session::new(scene, Some(1024), None).expect("field");
    let cpu = simulate_cpu(&session, 60, 1.0 / 30.0).blades;
    assert_valid(&cpu, "cpu twin after 60 steps");
}

#[test]
fn rest_pose_is_a_fixed_point_without_forces() {
    let (session, blades, states) = run_gpu(common::still_scene(), 1024, 100, 1.0 / 30.0);
    let mut worst = 0.0f32;
    for (a, b) in session.field.blades.iter().zip(&blades) {
        worst = worst.max(xyz(a.v2_width).distance(xyz(b.v2_width)));
        worst = worst.max(xyz(a.v1_height).distance(xyz(b.v1_height)));
    }
    println!("rest pose: worst drift after 100 steps {worst:.2e} m");
    assert!(worst < 1e-5, "the rest pose drifted by {worst} m");
    assert!(states.iter().all(|s| s.rest_eta[3] == 0.0));
}

#[test]
fn blades_under_a_static_sphere_end_outside_it() {
    let mut scene = common::still_scene();
    scene.physics.gravity_acceleration = 9.81;
    let (c, r) = (Vec3::new(0.0, 0.45, 0.0), 0.4);
    scene.colliders = vec![Sphere {
        center: c.into(),
        radius: r,
        motion: Motion::Static,
    }];
    let (_, blades, states) = run_gpu(scene, 2048, 120, 1.0 / 30.0);
    let mut hit = 0;
    let mut worst = 0.0f32;
    for (b, s) in blades.iter().zip(&states) {
        let (v0, v1, v2) = (xyz(b.v0_dir), xyz(b.v1_height), xyz(b.v2_width));
        let m = 0.25 * v0 + 0.5 * v1 + 0.25 * v2;
        if s.rest_eta[3] > 0.0 {
            hit += 1;
        }
        worst = worst.max(r - v2.distance(c)).max(r - m.distance(c));
    }
    println!("static sphere: {hit} blades pressed, deepest point inside by {worst:.4} m");
    assert!(hit > 10, "the sphere must press some blades ({hit})");
    // Collide + validate rounds converge to the surface; a hair of rounding remains.
    assert!(
        worst < 0.005 * r,
        "a blade point ends {worst} m inside the sphere"
    );
}

#[test]
fn eta_fades_and_blades_recover_after_the_collider_leaves() {
    let mut scene = common::still_scene();
    scene.physics.gravity_acceleration = 9.81;
    scene.physics.collision_decay = 0.5;
    // Crosses the ~3.6 m wide field in 2 s, then rolls away.
    scene.colliders = vec![common::rolling_sphere(-3.0, 0.45, 0.4, 3.0)];
    let dt = 1.0 / 30.0;
    let mut control_scene = scene.clone();
    control_scene.colliders.clear();
    // After 0.7 s the sphere is in the middle of the field: blades behind it are pressed.
    let (_, _, pressed_eta) = run_gpu(scene.clone(), 1024, 20, dt);
    let hit = pressed_eta.iter().filter(|s| s.rest_eta[3] > 0.0).count();
    assert!(
        hit > 20,
        "the sphere must cross the field ({hit} blades hit)"
    );
    let (_, after, after_eta) = run_gpu(scene, 1024, 600, dt);
    let (_, control, _) = run_gpu(control_scene, 1024, 600, dt);
    let max_eta = after_eta.iter().map(|s| s.rest_eta[3]).fold(0.0, f32::max);
    let mut worst = 0.0f32;
    for (a, b) in after.iter().zip(&control) {
        worst = worst.max(xyz(a.v2_width).distance(xyz(b.v2_width)) / a.v1_height[3]);
    }
    println!("recovery: {hit} blades hit, max eta after 20 s {max_eta}, worst tip offset {:.3} % of height", worst * 100.0);
    assert_eq!(max_eta, 0.0, "eta must return to 0");
    assert!(
        worst < 0.01,
        "blades must return within 1 % of rest, worst {:.3} %",
        worst * 100.0
    );
}
