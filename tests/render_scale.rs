//! The frame budget's first step, a lower render resolution, takes no grass away: the same
//! frame drawn at full size and at the smallest scale the budget sets, with every cull on
//! (occlusion by objects and by grass included), culls exactly the same blades by
//! orientation, frustum and distance, and the occlusion test, whose depth pyramid is
//! coarser (so more conservative) at a lower resolution, hides no blade the full-size frame
//! draws: a lower scale draws at least the full frame's blades and at most a measured band
//! more (on lavapipe: 1521 at full size, 1547 (+1.7 %) at 0.71, 1929 (+26.8 %) at the
//! budget's smallest scale).

mod common;

use sward::app::adaptive::MIN_SCALE;
use sward::render::camera::CameraView;
use sward::render::target::Target;
use sward::render::upscale::scaled_size;
use sward::session::Session;

const FULL: (u32, u32) = (320, 180);
/// At most this share more blades drawn at a lower scale than at full size (measured
/// 26.8 % at the smallest scale).
const DRAWN_BAND: f64 = 0.5;

#[test]
fn a_lower_render_scale_draws_the_same_blades() {
    let gpu = common::gpu();
    let scene = common::still_scene();
    assert!(scene.culling.occlusion && scene.culling.grass_occlusion);
    let session = Session::new(scene, Some(8192), Some(&gpu)).expect("field");
    let camera = CameraView {
        // Low over the grass: near blades hide far ones (grass occlusion).
        eye: glam::Vec3::new(0.0, 0.5, 6.0),
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
        // The grass hides grass from the second frame on (two-phase occlusion uses the
        // depth of the blades seen the frame before).
        for _ in 0..3 {
            r.frame(
                &gpu,
                0.0,
                &camera,
                &target.color_view,
                &target.depth_view,
                size,
            );
        }
        let c = r.cull.read_counters(&gpu).expect("counters");
        // Levels of detail depend on pixels; what is drawn at all must not.
        drawn.push((
            c.drawn(),
            c.culled_orientation,
            c.culled_frustum,
            c.culled_distance,
            c.culled_occlusion,
        ));
    }
    eprintln!("drawn, culled (orientation, frustum, distance, occlusion) per scale: {drawn:?}");
    let full = drawn[0];
    assert!(full.0 > 1000, "{drawn:?}");
    assert!(
        full.4 > 0,
        "the occlusion test hides blades in this view: {drawn:?}"
    );
    for d in &drawn {
        assert_eq!((d.1, d.2, d.3), (full.1, full.2, full.3), "{drawn:?}");
        assert!(d.0 >= full.0, "a lower scale hid blades: {drawn:?}");
        let more = (f64::from(d.0) - f64::from(full.0)) / f64::from(full.0);
        assert!(
            more < DRAWN_BAND,
            "drawn {} against {}: {drawn:?}",
            d.0,
            full.0
        );
    }
}
