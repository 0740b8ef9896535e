//! The GPU blade update against its CPU twin (`sim::reference`): 2048 blades, 60 steps, wind
//! and a moving sphere. Both start from the same field; the largest difference of any control
//! point or η is printed and must stay under the tolerance: measured on lavapipe 8.6e-7
//! (60 steps) and 1.8e-7 on a 3D wind grid (40 steps); the tolerance is 1e-5.

mod common;

use sward::commands::simulate_cpu;
use sward::scene::Scene;
use sward::session::Session;

/// Max |GPU − CPU| in metres after 60 steps. Both sides run the same f32 operations; the
/// gap is rounding (fused multiply-adds, sin/cos/sqrt implementations) amplified a little
/// by the length correction, far below a tenth of a millimetre (measured: about 4e-7 on lavapipe).
const TOLERANCE: f32 = 1e-5;

#[test]
fn gpu_update_matches_cpu_twin() {
    let gpu = common::gpu();
    // The flat square of 2048 blades at density 80 is about 5 m wide, centred on 0.
    let scene = Scene {
        colliders: vec![common::rolling_sphere(-3.0, 0.35, 0.4, 2.0)],
        ..Default::default()
    };
    let session = Session::new(scene, Some(2048), Some(&gpu)).expect("field");
    assert!(session.field.blades.len() >= 1024);
    let steps = 60;
    let dt = 1.0 / 30.0;
    let run = simulate_cpu(&session, steps, dt);
    let (cpu_blades, cpu_states) = (run.blades, run.states);

    let r = common::stepped(&gpu, &session, steps, dt);
    let (gpu_blades, gpu_states) = r.buffers.read(&gpu).expect("read-back");

    let mut max_err = 0.0f32;
    let mut moved = 0;
    for i in 0..cpu_blades.len() {
        let (c, g) = (&cpu_blades[i], &gpu_blades[i]);
        for k in 0..3 {
            max_err = max_err.max((c.v1_height[k] - g.v1_height[k]).abs());
            max_err = max_err.max((c.v2_width[k] - g.v2_width[k]).abs());
        }
        max_err = max_err.max((cpu_states[i].rest_eta[3] - gpu_states[i].rest_eta[3]).abs());
        if gpu_states[i].rest_eta[3] > 0.0 {
            moved += 1;
        }
    }
    println!("update twin: {} blades, {steps} steps, max |gpu - cpu| = {max_err:.3e} (tolerance {TOLERANCE:.0e})", cpu_blades.len());
    assert!(
        moved > 20,
        "the sphere must have hit blades for the test to mean anything ({moved})"
    );
    assert!(
        max_err < TOLERANCE,
        "max error {max_err} exceeds {TOLERANCE}"
    );
}

/// The blade update reading a 3D wind grid (`wind.fluid.layers` > 1): each blade samples the
/// layers around its own height. GPU and CPU step the same solver (bit-identical grids, see
/// `tests/twin_fluid_mac.rs`) and the same blades.
#[test]
fn gpu_update_matches_cpu_twin_on_a_3d_wind_grid() {
    let gpu = common::gpu();
    let mut scene = Scene {
        colliders: vec![common::rolling_sphere(-3.0, 0.35, 0.4, 2.0)],
        ..Default::default()
    };
    scene.wind.source = sward::scene::WindSource::Fluid;
    scene.wind.global = Some(sward::scene::GlobalWind {
        direction: (1.0, 0.3),
        strength: 2.0,
    });
    scene.field.height = sward::scene::Range { min: 0.2, max: 1.5 };
    let fluid = &mut scene.wind.fluid;
    fluid.resolution = 32;
    fluid.layers = 5;
    fluid.layer_height = 0.3;
    fluid.ground_drag = 3.0;
    // Confinement feeds the GPU's rounding back into the flow (see tests/twin_fluid_mac.rs,
    // where it has its own relative bound); without it the two grids are bit-identical and
    // this test sees only the blades' own sampling of the layers.
    fluid.vorticity = 0.0;
    let session = Session::new(scene, Some(2048), Some(&gpu)).expect("field");
    let steps = 40;
    let dt = 1.0 / 30.0;
    let cpu = simulate_cpu(&session, steps, dt).blades;
    let r = common::stepped(&gpu, &session, steps, dt);
    let (gpu_blades, _) = r.buffers.read(&gpu).expect("read-back");
    let mut max_err = 0.0f32;
    let mut moved = 0.0f32;
    for ((c, g), rest) in cpu.iter().zip(&gpu_blades).zip(&session.field.blades) {
        for k in 0..3 {
            max_err = max_err.max((c.v1_height[k] - g.v1_height[k]).abs());
            max_err = max_err.max((c.v2_width[k] - g.v2_width[k]).abs());
        }
        moved = moved.max((g.v2_width[0] - rest.v2_width[0]).abs());
    }
    println!(
        "update twin on a 32²×5 wind grid: {} blades, {steps} steps, largest tip shift {moved:.3} \
         m, max |gpu - cpu| = {max_err:.3e} (tolerance {TOLERANCE:.0e})",
        cpu.len()
    );
    assert!(moved > 0.05, "the wind must bend the blades ({moved})");
    assert!(
        max_err < TOLERANCE,
        "max error {max_err} exceeds {TOLERANCE}"
    );
}
