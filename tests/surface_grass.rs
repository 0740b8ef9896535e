//! Grass grown on a mesh's surface (issue 14, point 2) on the test adapter:
//! - on a box standing above the ground, blades on the top stand up, blades on the sides
//!   hang down under world-down gravity, blades under the box hang below their roots;
//! - the GPU update of surface blades (their up is the surface normal, not the terrain's)
//!   matches the CPU twin (measured 1.0e-6 m at the tips on lavapipe; tolerance 1e-5 m);
//! - a grassy object on a streamed field: its blades follow the tile pool on the GPU and
//!   match the twin (roots exactly, tips measured 8.0e-7 m; tolerance 1e-5 m);
//! - a density that would make too many blades is refused naming the field, before
//!   anything is generated.

mod common;

use std::path::{Path, PathBuf};

use glam::Vec3;
use sward::commands::simulate_cpu;
use sward::scene::{Field, MeshObject, Range, Scene};
use sward::session::Session;
use sward::sim::layout::Blade;

/// A 1 m cube as OBJ, each face its own four corners (flat normals), in a scratch folder:
/// a file of its own per call, since the tests run in parallel and one rewriting a shared
/// file while another loads it left the loader an empty one ("no triangles").
fn cube_obj() -> PathBuf {
    static CALLS: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);
    let dir = std::env::temp_dir().join(format!("sward-surface-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch");
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let path = dir.join(format!("cube-{call}.obj"));
    let mut text = String::new();
    let quads: [[[f32; 3]; 4]; 6] = [
        [[0., 0., 0.], [0., 0., 1.], [0., 1., 1.], [0., 1., 0.]],
        [[1., 0., 0.], [1., 1., 0.], [1., 1., 1.], [1., 0., 1.]],
        [[0., 0., 0.], [1., 0., 0.], [1., 0., 1.], [0., 0., 1.]],
        [[0., 1., 0.], [0., 1., 1.], [1., 1., 1.], [1., 1., 0.]],
        [[0., 0., 0.], [0., 1., 0.], [1., 1., 0.], [1., 0., 0.]],
        [[0., 0., 1.], [1., 0., 1.], [1., 1., 1.], [0., 1., 1.]],
    ];
    for q in quads {
        for v in q {
            text += &format!("v {} {} {}\n", v[0] - 0.5, v[1] - 0.5, v[2] - 0.5);
        }
    }
    for f in 0..6 {
        let b = f * 4 + 1;
        text += &format!("f {} {} {}\nf {} {} {}\n", b, b + 1, b + 2, b, b + 2, b + 3);
    }
    std::fs::write(&path, text).expect("write cube");
    path
}

fn grassy_cube_scene() -> Scene {
    let mut scene = common::still_scene();
    scene.physics.gravity_acceleration = 9.81;
    scene.objects = vec![MeshObject {
        mesh: cube_obj().display().to_string(),
        // A 2 m cube whose bottom is 1 m above the flat ground.
        scale: 2.0,
        translation: (0.0, 2.0, 0.0),
        grass: Some(Field {
            density: 120.0,
            height: Range { min: 0.3, max: 0.5 },
            stiffness: Range { min: 3.0, max: 5.0 },
            tuft_fraction: 0.0,
            ..Field::default()
        }),
        ..Default::default()
    }];
    scene
}

fn tip(b: &Blade) -> Vec3 {
    Vec3::new(b.v2_width[0], b.v2_width[1], b.v2_width[2])
}

fn root(b: &Blade) -> Vec3 {
    Vec3::new(b.v0_dir[0], b.v0_dir[1], b.v0_dir[2])
}

fn up(b: &Blade) -> Vec3 {
    Vec3::new(b.up_stiffness[0], b.up_stiffness[1], b.up_stiffness[2])
}

#[test]
fn blades_stand_on_top_hang_on_the_sides_and_under_the_box_and_match_the_twin() {
    let gpu = common::gpu();
    let session = Session::new(grassy_cube_scene(), Some(4096), Some(&gpu)).expect("field");
    // The flat field's 4,096 blades come first; the cube's follow.
    let blades = &session.field.blades;
    let on_cube: Vec<usize> = (0..blades.len())
        .filter(|&i| root(&blades[i]).y > 0.5)
        .collect();
    // 6 faces of 4 m² at 120 blades/m², rounded up to whole patches.
    assert!(
        on_cube.len() >= 2880,
        "{} blades on the cube",
        on_cube.len()
    );
    let steps = 60;
    let r = common::stepped(&gpu, &session, steps, 1.0 / 30.0);
    let (gpu_blades, _) = r.buffers.read(&gpu).expect("read-back");
    let (mut top, mut side, mut under) = (Vec::new(), Vec::new(), Vec::new());
    for &i in &on_cube {
        let (b, g) = (&blades[i], &gpu_blades[i]);
        let rise = (tip(g).y - root(b).y) / b.v1_height[3];
        match up(b).y {
            y if y > 0.9 => top.push(rise),
            y if y < -0.9 => under.push(rise),
            _ => side.push(rise),
        }
    }
    let mean = |v: &[f32]| v.iter().sum::<f32>() / v.len() as f32;
    let (t, s, u) = (mean(&top), mean(&side), mean(&under));
    println!(
        "tip height above the root over the blade height: top {t:.2} ({} blades), sides \
         {s:.2} ({}), under {u:.2} ({})",
        top.len(),
        side.len(),
        under.len()
    );
    assert!(t > 0.6, "blades on the top must stand ({t})");
    assert!(s < -0.1, "blades on the sides must hang down ({s})");
    assert!(
        u < -0.6,
        "blades under the box must hang below their roots ({u})"
    );

    let cpu = simulate_cpu(&session, steps, 1.0 / 30.0).blades;
    let err = on_cube
        .iter()
        .map(|&i| tip(&cpu[i]).distance(tip(&gpu_blades[i])))
        .fold(0.0f32, f32::max);
    println!("surface blades, GPU against the CPU twin: max tip distance {err:.2e} m");
    assert!(err < 1e-5, "GPU and CPU differ by {err} m");
}

#[test]
fn grass_on_an_object_in_a_streamed_field_follows_the_pool_and_matches_the_twin() {
    let mut scene = grassy_cube_scene();
    scene.field.tile_size = 8.0;
    // A small blade radius keeps the pool small.
    scene.culling.max_distance = 12.0;
    let gpu = common::gpu();
    let session = Session::new(scene.clone(), None, Some(&gpu)).expect("streamed field");
    let layout = session.tiles.expect("streamed");
    let pool = layout.pool_blades() as usize;
    let on_cube = session.field.blades.len();
    assert!(on_cube >= 2880, "{on_cube} blades on the cube");
    let steps = 30;
    let r = common::stepped(&gpu, &session, steps, 1.0 / 30.0);
    let (gpu_blades, _) = r.buffers.read(&gpu).expect("read-back");
    assert_eq!(
        gpu_blades.len(),
        pool + on_cube,
        "the object's grass follows the pool"
    );
    // The CPU twin of the same run: the pool filled around the camera, then the cube's
    // grass, stepped.
    let mut twin = Session::new(scene, None, Some(&gpu)).expect("streamed field");
    twin.fill_tiles_cpu().expect("pool");
    assert_eq!(twin.field.blades.len(), pool + on_cube);
    let cpu = simulate_cpu(&twin, steps, 1.0 / 30.0).blades;
    let (mut roots, mut tips) = (0.0f32, 0.0f32);
    for i in pool..pool + on_cube {
        roots = roots.max(root(&cpu[i]).distance(root(&gpu_blades[i])));
        tips = tips.max(tip(&cpu[i]).distance(tip(&gpu_blades[i])));
    }
    // Gravity pulls them: they moved, the same on both sides.
    let hanging = (pool..pool + on_cube)
        .filter(|&i| tip(&gpu_blades[i]).y < root(&gpu_blades[i]).y)
        .count();
    println!(
        "a grassy cube in a streamed field: {on_cube} blades after a pool of {pool}; GPU against the twin: roots {roots:.2e} m, tips {tips:.2e} m; {hanging} tips below their roots"
    );
    assert_eq!(roots, 0.0);
    assert!(tips < 1e-5, "GPU and CPU differ by {tips} m");
    assert!(
        hanging > 500,
        "the grass on the sides and underneath hangs ({hanging})"
    );
}

#[test]
fn grass_too_dense_is_refused() {
    let mut scene = grassy_cube_scene();
    if let Some(g) = &mut scene.objects[0].grass {
        g.density = -1.0;
    }
    let text = ron::ser::to_string(&scene).expect("ron");
    let e = sward::scene::parse_scene(&text, Path::new("s.ron"))
        .expect_err("refused")
        .to_string();
    assert!(
        e.contains("objects[0].grass.density = -1 is out of range"),
        "{e}"
    );

    let gpu = common::gpu();
    let mut scene = grassy_cube_scene();
    scene.objects[0].scale = 1000.0;
    if let Some(g) = &mut scene.objects[0].grass {
        g.density = 1000.0;
    }
    let e = Session::new(scene, Some(1024), Some(&gpu))
        .err()
        .expect("too many blades")
        .to_string();
    println!("{e}");
    assert!(
        e.contains("objects[0].grass.density") && e.contains("lower objects[0].grass.density"),
        "{e}"
    );
}
