//! Colliders built from meshes and objects that move (issue 14, points 1 and 3a):
//! - a bunny with `collider: Spheres((count: N))` pushes the grass: blades inside its
//!   footprint are pressed (their tips lie outside every packed sphere after the run, and
//!   far more of them moved than without the collider);
//! - the GPU run matches the CPU twin (`simulate --cpu`'s path) with the packed spheres
//!   (measured 5.4e-7 m at the tips on lavapipe; tolerance 5e-6 m);
//! - an object on a path carries its mesh and its spheres along: the spheres move exactly
//!   with the object's origin, stay on the ground, and the grass on the path is pressed
//!   after it passed;
//! - the packed spheres are not drawn (the mesh shows the object) while the scene's own
//!   colliders are;
//! - packings that do not fit the update pass, or bad counts, are refused with the field.

mod common;

use std::path::Path;

use glam::Vec3;
use sward::commands::simulate_cpu;
use sward::scene::{MeshCollider, MeshObject, Motion, Scene, SpherePacking};
use sward::session::Session;
use sward::sim::colliders::{object_origin, object_spheres_at};
use sward::sim::layout::Blade;

fn bunny_object(count: u32) -> MeshObject {
    MeshObject {
        mesh: Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("assets/models/bunny.obj")
            .display()
            .to_string(),
        // 1.9 m tall, 1.9 m long, standing on the flat ground at the field's centre.
        scale: 0.2,
        translation: (0.0, 0.0, 0.0),
        collider: MeshCollider::Spheres(SpherePacking {
            count,
            ..Default::default()
        }),
        ..Default::default()
    }
}

fn scene_with(object: MeshObject) -> Scene {
    let mut scene = common::still_scene();
    scene.physics.gravity_acceleration = 9.81;
    scene.objects = vec![object];
    scene
}

fn tip(b: &Blade) -> Vec3 {
    Vec3::new(b.v2_width[0], b.v2_width[1], b.v2_width[2])
}

/// Blades whose rest tip lies inside some sphere, and of those the share whose tip is
/// outside every sphere (pressed out) after the run.
fn pressed(rest: &[Blade], now: &[Blade], spheres: &[[f32; 4]]) -> (usize, f32) {
    let inside = |p: Vec3, slack: f32| {
        spheres
            .iter()
            .any(|s| p.distance(Vec3::new(s[0], s[1], s[2])) < s[3] - slack)
    };
    let hit: Vec<usize> = (0..rest.len())
        .filter(|&i| inside(tip(&rest[i]), 0.0))
        .collect();
    let out = hit.iter().filter(|&&i| !inside(tip(&now[i]), 0.02)).count();
    (hit.len(), out as f32 / hit.len().max(1) as f32)
}

#[test]
fn a_packed_bunny_presses_the_grass_as_its_twin_does() {
    let gpu = common::gpu();
    let session =
        Session::new(scene_with(bunny_object(300)), Some(16384), Some(&gpu)).expect("field");
    let packing = session.packings[0].as_ref().expect("packed");
    println!(
        "bunny packing: {} spheres, coverage {:.3}",
        packing.spheres.len(),
        packing.coverage
    );
    assert_eq!(packing.spheres.len(), 300);
    let spheres = object_spheres_at(
        &session.scene.objects,
        &session.packings,
        &session.terrain,
        0.0,
    );
    // Every sphere lies in the bunny's box (scaled 0.2: x, z within ±1 m, y 0–1.93 m).
    for s in &spheres {
        assert!(
            s[0].abs() < 1.05 && s[2].abs() < 0.8 && s[1] > -0.05 && s[1] < 1.95,
            "{s:?}"
        );
    }
    let steps = 30;
    let r = common::stepped(&gpu, &session, steps, 1.0 / 30.0);
    let (gpu_blades, _) = r.buffers.read(&gpu).expect("read-back");
    let (hit, share) = pressed(&session.field.blades, &gpu_blades, &spheres);
    println!("{hit} blades had their tip inside the bunny; {share:.3} were pressed out");
    assert!(hit > 50, "the bunny must stand in the grass ({hit})");
    assert!(
        share > 0.9,
        "the packed spheres must press the grass out ({share})"
    );

    let cpu = simulate_cpu(&session, steps, 1.0 / 30.0).blades;
    let err = cpu
        .iter()
        .zip(&gpu_blades)
        .map(|(c, g)| tip(c).distance(tip(g)))
        .fold(0.0f32, f32::max);
    println!("GPU against the CPU twin with the packed bunny: max tip distance {err:.2e} m");
    assert!(err < 5e-6, "GPU and CPU differ by {err} m");

    // Without a collider nothing presses the grass.
    let mut none = bunny_object(300);
    none.collider = MeshCollider::None;
    let session = Session::new(scene_with(none), Some(16384), Some(&gpu)).expect("field");
    assert!(session.packings[0].is_none());
    let r = common::stepped(&gpu, &session, steps, 1.0 / 30.0);
    let (still, _) = r.buffers.read(&gpu).expect("read-back");
    let (_, share_none) = pressed(&session.field.blades, &still, &spheres);
    println!("without a collider {share_none:.3} were out");
    assert!(share_none < 0.2, "{share_none}");
}

#[test]
fn an_object_on_a_path_carries_its_spheres_and_presses_a_trail() {
    let gpu = common::gpu();
    let mut object = bunny_object(120);
    object.scale = 0.12;
    object.motion = Motion::Path {
        points: vec![(-3.0, 0.0), (3.0, 0.0)],
        speed: 3.0,
        looped: false,
    };
    let session = Session::new(scene_with(object), Some(16384), Some(&gpu)).expect("field");
    let objects = &session.scene.objects;
    let at = |t: f32| object_spheres_at(objects, &session.packings, &session.terrain, t);
    let (a, b) = (at(0.0), at(1.0));
    let (oa, ob) = (
        object_origin(&objects[0], &session.terrain, 0.0),
        object_origin(&objects[0], &session.terrain, 1.0),
    );
    assert!((oa - Vec3::new(-3.0, 0.0, 0.0)).length() < 1e-5, "{oa}");
    assert!((ob - Vec3::new(0.0, 0.0, 0.0)).length() < 1e-5, "{ob}");
    for (sa, sb) in a.iter().zip(&b) {
        let moved = Vec3::new(sb[0] - sa[0], sb[1] - sa[1], sb[2] - sa[2]);
        assert!(
            (moved - (ob - oa)).length() < 1e-4,
            "a sphere moved by {moved}"
        );
        assert_eq!(sa[3], sb[3]);
    }
    // After 2 s the object is at the path's end (x = 3); the grass it crossed at x ≈ -1
    // to 1 was pressed (trails persist: η).
    let r = common::stepped(&gpu, &session, 60, 1.0 / 30.0);
    let (_, states) = r.buffers.read(&gpu).expect("read-back");
    let blades = &session.field.blades;
    let (mut on_path, mut crushed) = (0, 0);
    for (b, s) in blades.iter().zip(&states) {
        let p = tip(b);
        if p.x.abs() < 1.0 && p.z.abs() < 0.2 {
            on_path += 1;
            if s.rest_eta[3] > 0.0 {
                crushed += 1;
            }
        }
    }
    println!("trail of a moving bunny: {crushed} of {on_path} blades on its path crushed");
    assert!(on_path > 50);
    assert!(
        crushed as f32 > 0.5 * on_path as f32,
        "{crushed} of {on_path}"
    );
}

#[test]
fn packings_that_do_not_fit_are_refused_naming_the_field() {
    let check = |object: MeshObject, colliders: usize| -> String {
        let mut scene = scene_with(object);
        scene.colliders = (0..colliders)
            .map(|k| sward::scene::Sphere {
                center: (k as f32, 0.0, 0.0),
                radius: 0.1,
                motion: Motion::Static,
            })
            .collect();
        let text = ron::ser::to_string(&scene).expect("ron");
        sward::scene::parse_scene(&text, Path::new("test.ron"))
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default()
    };
    let e = check(bunny_object(16000), 400);
    println!("{e}");
    assert!(
        e.contains("objects[0].collider") && e.contains("16400") && e.contains("16384"),
        "{e}"
    );
    let e = check(bunny_object(0), 0);
    assert!(
        e.contains("objects[0].collider: count = 0 is out of range"),
        "{e}"
    );
    let mut fine = bunny_object(10);
    fine.collider = MeshCollider::Spheres(SpherePacking {
        count: 10,
        resolution: 4,
    });
    let e = check(fine, 0);
    assert!(
        e.contains("objects[0].collider: resolution = 4 is out of range"),
        "{e}"
    );
    assert_eq!(check(bunny_object(1000), 24), "", "1,024 spheres fit");
}

#[test]
fn packed_spheres_are_not_drawn_but_the_scenes_colliders_are() {
    use sward::render::draw::SphereDraw;
    // 2 colliders, 300 packed spheres, 3 thrown balls.
    let d = SphereDraw {
        count: 305,
        hidden: 2..302,
    };
    assert_eq!(d.drawn(), [0..2, 302..305]);
    assert!(d.any_drawn());
    // Only packed spheres: nothing to draw.
    let d = SphereDraw {
        count: 300,
        hidden: 0..300,
    };
    assert!(!d.any_drawn());
    // The update pass dropped spheres past its limit: the ranges stay within the count.
    let d = SphereDraw {
        count: 100,
        hidden: 50..300,
    };
    assert_eq!(d.drawn(), [0..50, 100..100]);
}

#[test]
fn a_rolling_object_turns_by_the_distance_over_its_radius_and_pushes_the_wind() {
    use sward::sim::colliders::object_transform;
    let gpu = common::gpu();
    let r = 0.5f32;
    let mut object = bunny_object(40);
    object.translation = (0.0, r, 0.0);
    object.rolls = true;
    object.motion = Motion::Path {
        points: vec![(-4.0, 0.0), (20.0, 0.0)],
        speed: 1.0,
        looped: false,
    };
    let mut scene = scene_with(object);
    scene.wind.source = sward::scene::WindSource::Fluid;
    scene.wind.fluid.resolution = 64;
    scene.wind.fluid.obstacles = true;
    let session = Session::new(scene, Some(8192), Some(&gpu)).expect("field");
    let o = &session.scene.objects[0];
    let at = |t: f32, p: Vec3| object_transform(o, &session.terrain, t).transform_point3(p);
    // A point on top of the object's origin (in the file's units: / scale) ends at the
    // bottom after half a turn (π r travelled) and back on top after a whole one.
    let top = Vec3::new(0.0, r / o.scale, 0.0);
    let start = at(0.0, top);
    let half = at(std::f32::consts::PI * r, top);
    let whole = at(std::f32::consts::TAU * r, top);
    println!("rolling: top {start} → half a turn {half} → a whole turn {whole}");
    assert!(
        (start - Vec3::new(-4.0, 2.0 * r, 0.0)).length() < 1e-3,
        "{start}"
    );
    assert!(
        (half - Vec3::new(-4.0 + std::f32::consts::PI * r, 0.0, 0.0)).length() < 1e-3,
        "{half}"
    );
    assert!(
        (whole - Vec3::new(-4.0 + std::f32::consts::TAU * r, 2.0 * r, 0.0)).length() < 1e-3,
        "{whole}"
    );

    // Still air, no forces: only the moving object stirs it.
    let mut renderer = common::stepped(&gpu, &session, 1, 1.0 / 30.0);
    for _ in 0..40 {
        renderer.step(&gpu, 1.0 / 30.0);
    }
    let state = renderer
        .fluid
        .as_ref()
        .expect("the fluid runs")
        .read_state(&gpu)
        .expect("read-back");
    let speed = state.max_speed();
    println!("air stirred by the rolling object: peak {speed:.2} m/s");
    assert!(speed > 0.3, "the moving object must push the air ({speed})");
}
