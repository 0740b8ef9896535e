//! The 3D wind grid (`wind.fluid.layers` > 1, issue 13 point 3) on the GPU solver:
//! - the multigrid V-cycles (semi-coarsened, columns relaxed as lines) remove a random 3D
//!   field's divergence a hundredfold, with layers thinner than the cells, and far more than
//!   Jacobi in the same number of sweeps;
//! - the downwash pushes the air down under the rotor and the ground turns it outwards: a
//!   radial outflow near the ground, an inflow aloft;
//! - over rough ground the wind grows with the height (the ground drag), so a global wind
//!   blows faster at the top of the grid than at the grass roots;
//! - a ball in the wind makes the air rise in front of it and sink behind it, and a ball
//!   that rises pushes the air above it up;
//! - tall grass reaches faster air: with the same scene, the tall blades' bend relative to
//!   the short blades' is larger on the 3D grid than on the 2D one.
//!
//! The kernels against their CPU twins in 3D are in `tests/twin_fluid_mac.rs`.

mod common;
#[path = "common/fluid.rs"]
mod fluid_common;

use fluid_common::{config, gpu_step, random_faces_3d};
use sward::gpu::Gpu;
use sward::scene::{Boundary, GlobalWind, PressureSolver, Scene, WindSource};
use sward::session::Session;
use sward::sim::fluid::{FluidConfig, FluidSolver, FluidState};
use sward::sim::wind_layout::{FluidForces, ObstacleGpu};

fn layered(n: u32, side: f32, layers: u32, dy: f32, boundary: Boundary) -> FluidConfig {
    FluidConfig {
        layers,
        layer_height: dy,
        pressure_solver: PressureSolver::Multigrid,
        warm_start: true,
        dissipation: 0.1,
        ..config(n, side, boundary)
    }
}

fn run(
    gpu: &Gpu,
    cfg: &FluidConfig,
    steps: u32,
    forces: &dyn Fn(f32) -> FluidForces,
) -> FluidState {
    let mut solver = FluidSolver::new(gpu, cfg).expect("solver");
    let dt = 1.0 / 30.0;
    for s in 0..steps {
        gpu_step(gpu, &mut solver, dt, &forces(s as f32 * dt));
    }
    solver.read_state(gpu).expect("read-back")
}

/// Mean over the columns whose centre lies within (r0, r1) of (cx, cz) of
/// `f(i, j, direction from the centre)`.
fn ring_mean(
    s: &FluidState,
    (cx, cz): (f32, f32),
    (r0, r1): (f32, f32),
    f: &dyn Fn(u32, u32, [f32; 2]) -> f32,
) -> f32 {
    let (mut sum, mut count) = (0.0f32, 0u32);
    for j in 0..s.resolution {
        for i in 0..s.resolution {
            let x = s.origin[0] + (i as f32 + 0.5) * s.cell_size - cx;
            let z = s.origin[1] + (j as f32 + 0.5) * s.cell_size - cz;
            let r = (x * x + z * z).sqrt();
            if r > r0 && r < r1 {
                sum += f(i, j, [x / r, z / r]);
                count += 1;
            }
        }
    }
    assert!(count > 0, "no cells in the ring");
    sum / count as f32
}

#[test]
fn multigrid_removes_3d_divergence_a_hundredfold() {
    let gpu = common::gpu();
    for boundary in [Boundary::Open, Boundary::Closed] {
        // 0.5 m cells, 0.25 m layers: the layers couple four times as strongly.
        let mut rms = Vec::new();
        for (solver, iterations) in [(PressureSolver::Multigrid, 2), (PressureSolver::Jacobi, 40)] {
            let cfg = FluidConfig {
                pressure_solver: solver,
                multigrid_cycles: iterations.min(2),
                pressure_iterations: iterations,
                warm_start: false,
                dissipation: 0.0,
                ..layered(64, 32.0, 8, 0.25, boundary)
            };
            let mut gpu_solver = FluidSolver::new(&gpu, &cfg).expect("solver");
            let (u, v, w) = random_faces_3d(64, 8, boundary, 3, 2.0);
            gpu_solver.write_faces(&gpu.queue, &u, &v, &w);
            gpu_step(&gpu, &mut gpu_solver, 1e-4, &FluidForces::default());
            let s = gpu_solver.read_state(&gpu).expect("read-back");
            let (before, after) = (s.rms_divergence_before(), s.rms_divergence());
            let ms = gpu_solver.read_pass_ms(&gpu).expect("timestamps");
            let pressure_ms = ms.map_or(f64::NAN, |m| m[sward::sim::fluid::PRESSURE_PASS].1);
            println!(
                "3D 64²×8 {boundary:?}, {solver:?} ×{iterations}: RMS divergence {before:.3e} → \
                 {after:.3e} 1/s ({:.0}× lower), pressure pass {pressure_ms:.1} ms",
                before / after
            );
            rms.push((before, after));
        }
        let (before, multigrid) = rms[0];
        let jacobi = rms[1].1;
        assert!(
            multigrid < before / 100.0,
            "{boundary:?}: two V-cycles left {multigrid:e} of {before:e}"
        );
        assert!(
            multigrid < jacobi / 10.0,
            "{boundary:?}: multigrid {multigrid:e} is not far below 40 Jacobi iterations {jacobi:e}"
        );
    }
}

#[test]
fn the_downwash_pushes_down_then_out_along_the_ground() {
    let gpu = common::gpu();
    let cfg = layered(48, 24.0, 8, 0.5, Boundary::Open);
    let forces = |_| FluidForces {
        downwash: [0.0, 0.0, 4.0, 20.0],
        ..Default::default()
    };
    let s = run(&gpu, &cfg, 60, &forces);
    let centre = |k| ring_mean(&s, (0.0, 0.0), (0.0, 1.5), &|i, j, _| s.w_at(i, j, k));
    let radial = |k| {
        ring_mean(&s, (0.0, 0.0), (3.0, 6.0), &|i, j, d| {
            let v = s.at_layer(i, j, k);
            v[0] * d[0] + v[1] * d[1]
        })
    };
    let (w_mid, out_low, out_high) = (centre(4), radial(0), radial(7));
    println!(
        "3D downwash: w under the rotor (layer 4) {w_mid:.2} m/s; radial velocity 3–6 m out: \
         ground layer {out_low:.2} m/s, top layer {out_high:.2} m/s"
    );
    assert!(w_mid < -0.5, "the air under the rotor must sink ({w_mid})");
    assert!(
        out_low > 0.5,
        "near the ground the air must flow outwards ({out_low})"
    );
    assert!(
        out_high < out_low * 0.5,
        "the outflow must hug the ground: top {out_high}, ground {out_low}"
    );
}

#[test]
fn over_rough_ground_the_wind_grows_with_the_height() {
    let gpu = common::gpu();
    let cfg = FluidConfig {
        ground_drag: 3.0,
        ..layered(32, 16.0, 6, 0.5, Boundary::Periodic)
    };
    let forces = |_| FluidForces {
        global: [1.0, 0.0],
        ..Default::default()
    };
    let s = run(&gpu, &cfg, 90, &forces);
    let mean_u = |k| {
        ring_mean(&s, (0.0, 0.0), (0.0, 100.0), &|i, j, _| {
            s.at_layer(i, j, k)[0]
        })
    };
    let profile: Vec<f32> = (0..6).map(mean_u).collect();
    println!("3D wind profile over rough ground, layers 0–5 (0.5 m each): {profile:.2?} m/s");
    for k in 1..6 {
        assert!(
            profile[k] > profile[k - 1],
            "the wind must grow with the height: {profile:?}"
        );
    }
    assert!(
        profile[5] > 1.5 * profile[0],
        "the top must blow clearly faster than the ground: {profile:?}"
    );
}

#[test]
fn a_ball_makes_the_air_rise_in_front_and_pushes_it_up_as_it_rises() {
    let gpu = common::gpu();
    let cfg = layered(48, 24.0, 6, 0.5, Boundary::Open);
    // A ball of radius 1 on the ground in a wind along +x.
    let sitting = |_| FluidForces {
        global: [1.5, 0.0],
        obstacles: vec![ObstacleGpu {
            circle: [0.0, 0.0, 1.0, 0.5],
            velocity: [0.0; 4],
        }],
        ..Default::default()
    };
    let s = run(&gpu, &cfg, 60, &sitting);
    // w in layers 1–2 over a strip 1.5–2.5 m in front of and behind the centre.
    let strip = |x0: f32| {
        let mut sum = 0.0;
        let mut count = 0;
        for k in 1..3 {
            for j in 0..s.resolution {
                for i in 0..s.resolution {
                    let x = s.origin[0] + (i as f32 + 0.5) * s.cell_size;
                    let z = s.origin[1] + (j as f32 + 0.5) * s.cell_size;
                    if (x - x0).abs() < 0.5 && z.abs() < 0.75 {
                        sum += s.w_at(i, j, k);
                        count += 1;
                    }
                }
            }
        }
        sum / count as f32
    };
    let (front, behind) = (strip(-2.0), strip(2.0));
    println!("3D ball in the wind: w in front {front:.3} m/s, behind {behind:.3} m/s");
    assert!(front > 0.05, "the air must rise over the ball ({front})");
    assert!(behind < -0.02, "the air must sink behind it ({behind})");

    // A ball rising at 2 m/s through still air.
    let rising = |t: f32| FluidForces {
        obstacles: vec![ObstacleGpu {
            circle: [0.0, 0.0, 0.6, 0.7 + 2.0 * t],
            velocity: [0.0, 0.0, 2.0, 0.0],
        }],
        ..Default::default()
    };
    let s = run(&gpu, &cfg, 10, &rising);
    // The ball's top is at 1.9 m; the air of layer 5 (2.5–3 m), clear of it, is pushed up.
    let above = ring_mean(&s, (0.0, 0.0), (0.0, 0.5), &|i, j, _| s.w_at(i, j, 5));
    let aside = ring_mean(&s, (0.0, 0.0), (4.0, 6.0), &|i, j, _| s.w_at(i, j, 5));
    assert_eq!(
        s.solid[(5 * 48 + 24) * 48 + 24],
        0,
        "layer 5 above the ball is air"
    );
    println!("3D rising ball: w above it {above:.3} m/s, 4–6 m aside {aside:.3} m/s");
    assert!(
        above > 0.15,
        "the air above a rising ball must go up ({above})"
    );
    assert!(
        aside.abs() < above * 0.2,
        "far away the air barely moves ({aside})"
    );
}

/// Mean horizontal tip displacement from the rest pose of blades taller / shorter than the
/// field's middle height, after `steps` steps of `scene`.
fn tall_and_short_bend(scene: Scene, steps: u32) -> (f32, f32) {
    let gpu = common::gpu();
    let session = Session::new(scene, Some(4096), Some(&gpu)).expect("field");
    let r = common::stepped(&gpu, &session, steps, 1.0 / 30.0);
    let (blades, _) = r.buffers.read(&gpu).expect("read-back");
    let heights: Vec<f32> = session
        .field
        .blades
        .iter()
        .map(|b| b.v1_height[3])
        .collect();
    let mid = {
        let mut h = heights.clone();
        h.sort_by(f32::total_cmp);
        h[h.len() / 2]
    };
    let (mut tall, mut short) = ((0.0, 0), (0.0, 0));
    for (rest, now) in session.field.blades.iter().zip(&blades) {
        let d = ((now.v2_width[0] - rest.v2_width[0]).powi(2)
            + (now.v2_width[2] - rest.v2_width[2]).powi(2))
        .sqrt();
        let slot = if rest.v1_height[3] > mid {
            &mut tall
        } else {
            &mut short
        };
        slot.0 += d;
        slot.1 += 1;
    }
    (tall.0 / tall.1 as f32, short.0 / short.1 as f32)
}

#[test]
fn tall_grass_reaches_faster_air_on_a_3d_grid() {
    let mut scene = common::still_scene();
    scene.physics.gravity_acceleration = 9.81;
    scene.field.height = sward::scene::Range { min: 0.2, max: 1.4 };
    scene.wind.source = WindSource::Fluid;
    scene.wind.global = Some(GlobalWind {
        direction: (1.0, 0.0),
        strength: 1.5,
    });
    scene.wind.fluid.resolution = 32;
    scene.wind.fluid.boundary = Boundary::Periodic;
    let mut flat = scene.clone();
    flat.wind.fluid.layers = 1;
    scene.wind.fluid.layers = 6;
    scene.wind.fluid.layer_height = 0.3;
    scene.wind.fluid.ground_drag = 3.0;
    let (tall_3d, short_3d) = tall_and_short_bend(scene, 60);
    let (tall_2d, short_2d) = tall_and_short_bend(flat, 60);
    let (ratio_3d, ratio_2d) = (tall_3d / short_3d, tall_2d / short_2d);
    println!(
        "tip shift tall / short blades: 3D {tall_3d:.3} / {short_3d:.3} m = {ratio_3d:.2}, \
         2D {tall_2d:.3} / {short_2d:.3} m = {ratio_2d:.2}"
    );
    assert!(
        short_3d > 1e-3 && short_2d > 1e-3,
        "the wind must bend the grass"
    );
    assert!(
        ratio_3d > ratio_2d * 1.15,
        "tall grass must bend more, relative to short, in 3D ({ratio_3d}) than in 2D ({ratio_2d})"
    );
}
