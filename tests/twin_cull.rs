//! The GPU cull pass against the CPU predicate: the same blades (read back after a frame),
//! the same camera; the visible set and every counter must agree.

mod common;

use sward::render::camera::CameraView;
use sward::render::target::Target;
use sward::scene::Scene;
use sward::session::Session;
use sward::sim::layout::CullCounters;
use sward::sim::params::cull_params;
use sward::sim::reference::{cull_blade, CullOutcome};

/// Blades whose outcome may differ between GPU and CPU: only those within float rounding
/// of a threshold. Allowed: 1 in 1000, at least 2.
fn allowed_mismatch(n: usize) -> usize {
    (n / 1000).max(2)
}

fn run(scene: Scene, camera: CameraView) -> (usize, CullCounters) {
    let gpu = common::gpu();
    let session = Session::new(scene, Some(8192), Some(&gpu)).expect("field");
    let target = Target::new(&gpu, 96, 64).expect("target");
    let mut r = common::stepped(&gpu, &session, 0, 0.0);
    r.frame(
        &gpu,
        1.0 / 30.0,
        &camera,
        &target.color_view,
        &target.depth_view,
        (96, 64),
    );
    let counters = r.cull.read_counters(&gpu).expect("counters");
    let mut visible = r.cull.read_visible(&gpu, &r.buffers).expect("visible");
    visible.sort_unstable();
    let (blades, _) = r.buffers.read(&gpu).expect("blades");

    let cp = cull_params(
        &r.scene.culling,
        camera.view_proj(96.0 / 64.0),
        camera.eye,
        r.buffers.count,
        r.buffers.patch_size,
        r.scene.field.segments * 12,
    );
    let mut cpu = CullCounters::default();
    let mut cpu_visible = Vec::new();
    for (i, b) in blades.iter().enumerate() {
        let patch = &session.field.patches[i / session.field.patch_size as usize];
        match cull_blade(i as u32, b, patch, &cp) {
            CullOutcome::Drawn => cpu_visible.push(i as u32),
            CullOutcome::Patch => cpu.culled_patch += 1,
            CullOutcome::Orientation => cpu.culled_orientation += 1,
            CullOutcome::Frustum => cpu.culled_frustum += 1,
            CullOutcome::Distance => cpu.culled_distance += 1,
        }
    }
    let differ = visible
        .iter()
        .filter(|i| cpu_visible.binary_search(i).is_err())
        .count()
        + cpu_visible
            .iter()
            .filter(|i| visible.binary_search(i).is_err())
            .count();
    println!(
        "cull twin: gpu drawn {} / cpu drawn {}, gpu culled {:?} / cpu culled {:?}, visible sets differ in {differ}",
        counters.drawn(),
        cpu_visible.len(),
        [counters.culled_patch, counters.culled_orientation, counters.culled_frustum, counters.culled_distance],
        [cpu.culled_patch, cpu.culled_orientation, cpu.culled_frustum, cpu.culled_distance],
    );
    assert_eq!(counters.drawn() as usize, visible.len());
    assert_eq!(
        counters.drawn() + counters.culled(),
        blades.len() as u32,
        "every blade is counted once"
    );
    assert!(
        differ <= allowed_mismatch(blades.len()),
        "{differ} blades differ"
    );
    let close = |a: u32, b: u32| {
        (a as i64 - b as i64).unsigned_abs() as usize <= allowed_mismatch(blades.len())
    };
    assert!(close(counters.culled_patch, cpu.culled_patch));
    assert!(close(counters.culled_orientation, cpu.culled_orientation));
    assert!(close(counters.culled_frustum, cpu.culled_frustum));
    assert!(close(counters.culled_distance, cpu.culled_distance));
    (differ, counters)
}

#[test]
fn gpu_cull_matches_cpu_predicate_with_every_test_on() {
    let mut scene = Scene::default();
    scene.culling.max_distance = 6.0;
    scene.culling.distance_levels = 4;
    scene.field.patch_size = 256;
    // A camera in the middle of the field looking along +x: the patches behind it fail the
    // box test, blades at the sides the frustum test, far ones the distance test.
    let camera = CameraView {
        eye: glam::Vec3::new(0.0, 1.2, 0.0),
        target: glam::Vec3::new(4.0, 0.0, 1.0),
        fov_y: 50.0,
        near: 0.05,
        far: 100.0,
    };
    let (_, c) = run(scene, camera);
    // Each test must have culled something here, or this test checks less than it says.
    assert!(
        c.culled_patch > 0
            && c.culled_orientation > 0
            && c.culled_frustum > 0
            && c.culled_distance > 0,
        "{c:?}"
    );
    assert!(c.drawn() > 0);
}

#[test]
fn switching_every_test_off_draws_every_blade() {
    let mut scene = Scene::default();
    scene.culling.patches = false;
    scene.culling.orientation = false;
    scene.culling.frustum = false;
    scene.culling.distance = false;
    let camera = CameraView {
        eye: glam::Vec3::new(-4.0, 1.2, 0.0),
        target: glam::Vec3::new(0.0, 0.0, 1.0),
        fov_y: 50.0,
        near: 0.05,
        far: 100.0,
    };
    let (_, c) = run(scene, camera);
    assert_eq!(c.culled(), 0);
}
