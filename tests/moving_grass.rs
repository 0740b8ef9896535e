//! Grass on a moving object travels with it (issue 14, point 2; `sim::carry`):
//! - the GPU's carry pass and update against the CPU twin, on an object sliding with a
//!   velocity and on one rolling along a path;
//! - every carried root stays where the object's transform puts its rest root, every up
//!   vector turns with the object, and the moved patch boxes hold every blade;
//! - a static object's grass is not carried (nothing changes for it).

mod common;

use glam::{Mat4, Vec3};
use sward::commands::simulate_cpu;
use sward::gpu::read_buffer;
use sward::scene::{Field, MeshObject, Motion, Range, Scene};
use sward::session::Session;
use sward::sim::colliders::object_transform;
use sward::sim::layout::{Blade, PatchBox};

fn scene(motion: Motion, rolls: bool) -> Scene {
    let path = common::shapes::write_obj(&common::shapes::icosphere(2), "moving-grass");
    let mut scene = common::still_scene();
    scene.physics.gravity_acceleration = 9.81;
    scene.culling.physics_throttle = 1;
    scene.objects = vec![MeshObject {
        mesh: path.display().to_string(),
        scale: 0.6,
        translation: (0.0, 0.6, 0.0),
        motion,
        rolls,
        grass: Some(Field {
            density: 250.0,
            height: Range { min: 0.1, max: 0.2 },
            ..Field::default()
        }),
        ..Default::default()
    }];
    scene
}

fn sliding() -> Scene {
    scene(Motion::Velocity((1.5, 0.0, -0.5)), false)
}

fn rolling() -> Scene {
    scene(
        Motion::Path {
            points: vec![(-3.0, 0.0), (3.0, 1.0)],
            speed: 2.0,
            looped: false,
        },
        true,
    )
}

fn v(a: [f32; 4]) -> Vec3 {
    Vec3::new(a[0], a[1], a[2])
}

const STEPS: u32 = 30;
const DT: f32 = 1.0 / 30.0;

struct Run {
    session: Session,
    blades: Vec<Blade>,
    boxes: Vec<PatchBox>,
    /// The object's M(t) at the end: rest world space to where it is.
    model: Mat4,
    /// Index of the first blade and patch of the object.
    first: usize,
}

fn run(scene: Scene) -> Run {
    let gpu = common::gpu();
    let session = Session::new(scene, Some(4096), Some(&gpu)).expect("field");
    let r = common::stepped(&gpu, &session, STEPS, DT);
    let (blades, _) = r.buffers.read(&gpu).expect("read-back");
    let bytes = read_buffer(&gpu, &r.buffers.patches, r.buffers.patches.size()).expect("boxes");
    let boxes: Vec<PatchBox> = bytemuck::pod_collect_to_vec(&bytes);
    let object = &session.scene.objects[0];
    let model = object_transform(object, &session.terrain, r.time) * object.transform().inverse();
    let first = session.field.carried.blades[0].blade as usize;
    Run {
        session,
        blades,
        boxes,
        model,
        first,
    }
}

#[test]
fn the_carry_and_update_match_the_twin_sliding_and_rolling() {
    for (name, scene) in [("sliding", sliding()), ("rolling", rolling())] {
        let r = run(scene);
        let cpu = simulate_cpu(&r.session, STEPS, DT).blades;
        let err = |f: fn(&Blade) -> [f32; 4]| {
            cpu.iter()
                .zip(&r.blades)
                .map(|(c, g)| v(f(c)).distance(v(f(g))))
                .fold(0.0f32, f32::max)
        };
        let (roots, tips, ups) = (
            err(|b| b.v0_dir),
            err(|b| b.v2_width),
            err(|b| b.up_stiffness),
        );
        println!(
            "{name}: GPU against the twin: roots {roots:.2e} m, tips {tips:.2e} m, ups {ups:.2e}"
        );
        assert!(roots < 1e-4 && tips < 1e-4 && ups < 1e-4, "{name}");
    }
}

#[test]
fn carried_roots_follow_the_object_and_the_boxes_hold_the_blades() {
    for (name, scene) in [("sliding", sliding()), ("rolling", rolling())] {
        let r = run(scene);
        let rest = &r.session.field.blades;
        let carried = &r.session.field.carried;
        assert_eq!(carried.objects.len(), 1);
        let (mut worst_root, mut worst_up, mut travelled) = (0.0f32, 0.0f32, 0.0f32);
        for c in &carried.blades {
            let (now, then) = (&r.blades[c.blade as usize], &rest[c.blade as usize]);
            let expected = r.model.transform_point3(v(then.v0_dir));
            worst_root = worst_root.max(expected.distance(v(now.v0_dir)));
            let up = r.model.transform_vector3(v(then.up_stiffness)).normalize();
            worst_up = worst_up.max(up.angle_between(v(now.up_stiffness)).to_degrees());
            travelled = travelled.max(v(now.v0_dir).distance(v(then.v0_dir)));
            // Every blade's curve is still its height long (the update validated it where the
            // object put it).
            let h = now.v1_height[3];
            let (v0, v1, v2) = (v(now.v0_dir), v(now.v1_height), v(now.v2_width));
            let len = (2.0 * v0.distance(v2) + v0.distance(v1) + v1.distance(v2)) / 3.0;
            assert!(
                (len - h).abs() < 1e-3 * h,
                "{name}: length {len} for height {h}"
            );
        }
        // The boxes of the object's patches hold every root grown by its blade's height.
        let patch = r.session.field.patch_size as usize;
        let mut outside = 0;
        for (k, b) in r.blades.iter().enumerate().skip(r.first) {
            let bx = &r.boxes[k / patch];
            let (p, h) = (v(b.v0_dir), b.v1_height[3]);
            for a in 0..3 {
                if p[a] - h < bx.min[a] - 1e-4 || p[a] + h > bx.max[a] + 1e-4 {
                    outside += 1;
                }
            }
            // The lean bound never exceeds the blade's own up.y.
            if b.up_stiffness[1] < bx.max[3] - 1e-4 {
                outside += 1;
            }
        }
        println!(
            "{name}: {} carried blades travelled up to {travelled:.2} m; roots within \
             {worst_root:.2e} m of the transformed rest roots, ups within {worst_up:.3}°; \
             {outside} box violations",
            carried.blades.len()
        );
        assert!(
            travelled > 1.0,
            "{name}: the grass must move with the object"
        );
        // Measured 2.5e-7 (sliding) and 2.8e-7 m (rolling) on lavapipe.
        assert!(worst_root < 3e-6, "{name}: a root is {worst_root} m off");
        assert!(worst_up < 0.05, "{name}: an up vector is {worst_up}° off");
        assert_eq!(outside, 0, "{name}: a moved patch box misses its blades");
    }
}

#[test]
fn a_static_objects_grass_is_not_carried() {
    let gpu = common::gpu();
    let session =
        Session::new(scene(Motion::Static, false), Some(4096), Some(&gpu)).expect("field");
    assert!(session.field.carried.is_empty());
    assert!(session.field.blades.len() > 4096, "the object has grass");
}

/// In a streamed field the object's grass follows the tile pool in the GPU's buffers; the
/// carry pass finds it there.
#[test]
fn carried_grass_in_a_streamed_field_follows_the_object() {
    let mut scene = sliding();
    scene.field.tile_size = 8.0;
    scene.culling.max_distance = 12.0;
    let gpu = common::gpu();
    let session = Session::new(scene, None, Some(&gpu)).expect("streamed field");
    let pool = session.tiles.as_ref().expect("streamed").pool_blades() as usize;
    let r = common::stepped(&gpu, &session, STEPS, DT);
    let (blades, _) = r.buffers.read(&gpu).expect("read-back");
    let object = &session.scene.objects[0];
    let model = object_transform(object, &session.terrain, r.time) * object.transform().inverse();
    let worst = session
        .field
        .carried
        .blades
        .iter()
        .map(|c| {
            let rest = &session.field.blades[c.blade as usize];
            let now = &blades[pool + c.blade as usize];
            model
                .transform_point3(v(rest.v0_dir))
                .distance(v(now.v0_dir))
        })
        .fold(0.0f32, f32::max);
    println!("streamed field: carried roots within {worst:.2e} m of the object's transform");
    // Measured 2.5e-7 m on lavapipe.
    assert!(worst < 3e-6, "a carried root is {worst} m off");
}
