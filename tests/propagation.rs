//! Grass-to-grass propagation (Qiu et al. §5.2, issue 15 point 3): the GPU passes against
//! the CPU twin, and the trail a ball leaves measured with and without propagation against
//! the ball's diameter (`cargo test --test propagation -- --nocapture` prints the figures).
//! GPU against twin, measured on lavapipe: 9.5e-7 with and without propagation; the
//! tolerance is 1e-5.

mod common;

use sward::commands::simulate_cpu;
use sward::scene::{Propagation, Scene};
use sward::session::Session;

/// Max |GPU − CPU| (metres, and η). The splat is fixed point (order-free), the generations
/// are the same f32 operations; the gap is the update's own rounding (see twin_update.rs).
const TOLERANCE: f32 = 1e-5;
/// η above which a blade counts as part of the trail.
const TRAIL_ETA: f32 = 0.05;

fn scene(propagation: bool) -> Scene {
    let path = std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/blade_models.ron"
    ));
    let mut s = sward::scene::load_scene_with_sets(path, &[]).expect("scene");
    // No wind: the trail alone bends the blades.
    s.wind.directional = None;
    s.physics.propagation = propagation.then(|| Propagation {
        extent: 12.0,
        ..Propagation::default()
    });
    s
}

/// The trail's width across the ball's path (z), over the blades whose root lies in the
/// middle metre of the path (x in [-2.5, -1.5]), from η.
fn trail_width(
    blades: &[sward::sim::layout::Blade],
    states: &[sward::sim::layout::BladeState],
) -> f32 {
    let zs: Vec<f32> = blades
        .iter()
        .zip(states)
        .filter(|(b, s)| (-2.5..=-1.5).contains(&b.v0_dir[0]) && s.rest_eta[3] > TRAIL_ETA)
        .map(|(b, _)| b.v0_dir[2])
        .collect();
    let lo = zs.iter().copied().fold(f32::INFINITY, f32::min);
    let hi = zs.iter().copied().fold(f32::NEG_INFINITY, f32::max);
    (hi - lo).max(0.0)
}

#[test]
fn gpu_propagation_matches_cpu_twin_and_widens_the_trail() {
    let gpu = common::gpu();
    let (steps, dt) = (75, 1.0 / 30.0);
    let mut widths = Vec::new();
    for on in [false, true] {
        let session = Session::new(scene(on), Some(16000), Some(&gpu)).expect("field");
        let cpu = simulate_cpu(&session, steps, dt);
        let r = common::stepped(&gpu, &session, steps, dt);
        let (blades, states) = r.buffers.read(&gpu).expect("read-back");
        let mut err = 0.0f32;
        for i in 0..blades.len() {
            for k in 0..3 {
                err = err.max((blades[i].v1_height[k] - cpu.blades[i].v1_height[k]).abs());
                err = err.max((blades[i].v2_width[k] - cpu.blades[i].v2_width[k]).abs());
            }
            err = err.max((states[i].rest_eta[3] - cpu.states[i].rest_eta[3]).abs());
        }
        let width = trail_width(&blades, &states);
        let diameter = 2.0 * session.scene.colliders[0].radius;
        println!(
            "propagation {}: {} blades, max |gpu - cpu| = {err:.3e}; trail {width:.3} m wide \
             = {:.2} × the ball's diameter of {diameter} m (blades with η > {TRAIL_ETA})",
            if on { "on " } else { "off" },
            blades.len(),
            width / diameter
        );
        assert!(err < TOLERANCE, "max error {err} exceeds {TOLERANCE}");
        assert!(
            width > 0.5 * diameter,
            "the ball must leave a trail ({width})"
        );
        assert_eq!(width, trail_width(&cpu.blades, &cpu.states), "twin's trail");
        widths.push(width);
    }
    assert!(
        widths[1] > widths[0] * 1.15,
        "propagation must widen the trail: {} against {}",
        widths[1],
        widths[0]
    );
}

/// Propagation with att = 0 passes nothing on: the run equals the run without it.
#[test]
fn att_zero_changes_nothing() {
    let session = Session::new(scene(false), Some(16000), None).expect("field");
    let off = simulate_cpu(&session, 60, 1.0 / 30.0);
    let mut s = scene(true);
    s.physics.propagation.as_mut().expect("on").att = 0.0;
    let session = Session::new(s, Some(16000), None).expect("field");
    let zero = simulate_cpu(&session, 60, 1.0 / 30.0);
    assert!(off.states.iter().any(|s| s.rest_eta[3] > 0.0));
    assert!(off.blades == zero.blades, "att = 0 changed the blades");
}
