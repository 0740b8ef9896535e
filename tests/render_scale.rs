//! The frame budget's first step, a lower render resolution, takes no grass away: the same
//! frame drawn at full size and at the smallest scale the budget sets culls exactly the same
//! blades (occlusion off: a coarser depth pyramid may hide a few more or fewer blades, which
//! is the occlusion test's own business, not the budget's).

mod common;

use sward::app::adaptive::MIN_SCALE;
use sward::render::camera::CameraView;
use sward::render::target::Target;
use sward::render::upscale::scaled_size;
use sward::session::Session;

const FULL: (u32, u32) = (320, 180);

#[test]
fn a_lower_render_scale_draws_the_same_blades() {
    let gpu = common::gpu();
    let mut scene = common::still_scene();
    scene.culling.occlusion = false;
    scene.culling.grass_occlusion = false;
    let session = Session::new(scene, Some(8192), Some(&gpu)).expect("field");
    let camera = CameraView {
        eye: glam::Vec3::new(0.0, 1.2, 6.0),
        target: glam::Vec3::new(0.0, 0.0, 0.0),
        fov_y: 50.0,
        near: 0.05,
        far: 100.0,
    };
    let mut drawn = Vec::new();
    for scale in [1.0, 0.71, MIN_SCALE] {
        let size = scaled_size(FULL, scale);
        let target = Target::new(&gpu, size.0, size.1).expect("target");
        let mut r = common::stepped(&gpu, &session, 0, 0.0);
        // As the window does: the projection keeps the window's shape.
        r.display_aspect = Some(FULL.0 as f32 / FULL.1 as f32);
        r.frame(
            &gpu,
            0.0,
            &camera,
            &target.color_view,
            &target.depth_view,
            size,
        );
        let c = r.cull.read_counters(&gpu).expect("counters");
        // Levels of detail depend on pixels; what is drawn at all must not.
        drawn.push((
            c.drawn(),
            c.culled_orientation,
            c.culled_frustum,
            c.culled_distance,
        ));
    }
    eprintln!("drawn, culled (orientation, frustum, distance) per scale: {drawn:?}");
    assert!(drawn[0].0 > 1000, "{drawn:?}");
    assert!(drawn.iter().all(|d| *d == drawn[0]), "{drawn:?}");
}
