//! The wind's behaviour against the papers' figures (issue 13, point 7), on the GPU solver:
//! - two guides pointing at each other meet and turn aside (CWD-Sim Fig. 10): the air that
//!   runs into the meeting point leaves it sideways, in opposite directions on the two
//!   sides, and the deflection is measured as an angle, not only as moving air;
//! - air goes around a static obstacle and is slower behind it than in the free stream;
//! - a ball rolling through the default meadow's wind (its fluid on, as the window turns it
//!   on for the first guide) leaves a wake: behind it the air differs from the same place
//!   in a run without the ball, dragged along the ball's path.

mod common;
#[path = "common/fluid.rs"]
mod fluid_common;

use fluid_common::{arrow, config, gpu_step};
use sward::scene::{Boundary, PressureSolver};
use sward::sim::fluid::{FluidConfig, FluidSolver};
use sward::sim::reference::fluid::sample_velocity;
use sward::sim::wind_layout::{FluidForces, ObstacleGpu};

fn speed(v: [f32; 2]) -> f32 {
    (v[0] * v[0] + v[1] * v[1]).sqrt()
}

/// The mean velocity over a box of sample points (x0..x1, z0..z1), every 0.25 m.
fn mean_velocity(s: &sward::sim::fluid::FluidState, x: (f32, f32), z: (f32, f32)) -> [f32; 2] {
    let (mut sum, mut n) = ([0.0f32; 2], 0.0f32);
    let mut xi = x.0;
    while xi <= x.1 {
        let mut zi = z.0;
        while zi <= z.1 {
            let v = sample_velocity(s, xi, zi);
            sum[0] += v[0];
            sum[1] += v[1];
            n += 1.0;
            zi += 0.25;
        }
        xi += 0.25;
    }
    [sum[0] / n, sum[1] / n]
}

#[test]
fn two_guides_pointing_at_each_other_meet_and_turn_aside() {
    let gpu = common::gpu();
    // `assets/scenes/two_winds.ron` on a 64² grid: two 8 m guides along x, 1.2 m apart
    // across, blowing at each other.
    let cfg = FluidConfig {
        vorticity: 10.7,
        dissipation: 0.4,
        pressure_solver: PressureSolver::Multigrid,
        multigrid_cycles: 2,
        warm_start: true,
        ..config(64, 24.0, Boundary::Open)
    };
    let mut solver = FluidSolver::new(&gpu, &cfg).expect("solver");
    let forces = FluidForces {
        arrows: vec![
            arrow([-10.5, -0.6], [-2.5, -0.6], 6.0, 1.8),
            arrow([10.5, 0.6], [2.5, 0.6], 6.0, 1.8),
        ],
        ..Default::default()
    };
    for _ in 0..90 {
        gpu_step(&gpu, &mut solver, 1.0 / 30.0, &forces);
    }
    let s = solver.read_state(&gpu).expect("read-back");
    // Along each guide the air runs towards the middle.
    let left = mean_velocity(&s, (-7.0, -5.0), (-1.0, -0.2));
    let right = mean_velocity(&s, (5.0, 7.0), (0.2, 1.0));
    // Beside the meeting point, 2 to 5 m off the guides' axis on either side.
    let above = mean_velocity(&s, (-1.5, 1.5), (2.0, 5.0));
    let below = mean_velocity(&s, (-1.5, 1.5), (-5.0, -2.0));
    let angle = |v: [f32; 2]| v[1].abs().atan2(v[0].abs()).to_degrees();
    println!(
        "two winds after 3 s: along the guides {left:?} / {right:?} m/s; beside the meeting \
         point {above:?} ({:.0}° off the guides' axis) / {below:?} ({:.0}°)",
        angle(above),
        angle(below)
    );
    assert!(
        left[0] > 0.5 && right[0] < -0.5,
        "the guides do not blow inwards"
    );
    assert!(
        speed(above) > 0.2 * speed(left) && speed(below) > 0.2 * speed(right),
        "little air leaves the meeting point"
    );
    // Turned aside: the flow beside the meeting point runs across the guides' axis, away
    // from it on each side.
    assert!(
        above[1] > 0.0 && below[1] < 0.0,
        "the air does not leave sideways"
    );
    assert!(
        angle(above) > 45.0 && angle(below) > 45.0,
        "deflected by only {:.0}° / {:.0}°",
        angle(above),
        angle(below)
    );
}

#[test]
fn air_goes_around_a_static_obstacle_and_is_slower_behind_it() {
    let gpu = common::gpu();
    let cfg = FluidConfig {
        pressure_solver: PressureSolver::Multigrid,
        warm_start: true,
        dissipation: 0.1,
        ..config(64, 32.0, Boundary::Periodic)
    };
    let r = 3.0;
    let forces = FluidForces {
        global: [2.0, 0.0],
        obstacles: vec![ObstacleGpu {
            circle: [0.0, 0.0, r, 0.0],
            velocity: [0.0; 4],
        }],
        ..Default::default()
    };
    let mut solver = FluidSolver::new(&gpu, &cfg).expect("solver");
    for _ in 0..60 {
        gpu_step(&gpu, &mut solver, 1.0 / 30.0, &forces);
    }
    let s = solver.read_state(&gpu).expect("read-back");
    let free = mean_velocity(&s, (-2.0, 2.0), (10.0, 13.0));
    let beside = mean_velocity(&s, (-1.0, 1.0), (r + 0.5, r + 2.0));
    let behind = mean_velocity(&s, (r + 0.5, r + 3.0), (-1.0, 1.0));
    println!(
        "static obstacle r = {r} m: free stream {free:?}, beside {beside:?}, behind {behind:?} m/s"
    );
    assert!(free[0] > 0.5, "no wind");
    assert!(beside[0] > free[0], "no speed-up beside the obstacle");
    assert!(
        speed(behind) < 0.7 * speed(free),
        "the air behind the obstacle is not slower ({behind:?} vs {free:?})"
    );
}

/// Runs the default meadow with its fluid switched on (as the window does when a guide is
/// added) under a global wind along the meadow's own wind direction, with a ball rolling
/// across it at 3 m/s or without one; returns the air velocity 1.5 m behind where the ball
/// ends, and the ball's last position.
fn meadow_wind_behind_a_ball(with_ball: bool) -> ([f32; 2], glam::Vec3) {
    use sward::render::camera::CameraView;
    use sward::render::target::Target;

    use sward::scene::{GlobalWind, WindSource};
    use sward::session::Session;
    let mut s = sward::commands::load(None, &[]).expect("the default scene");
    s.wind.source = WindSource::Both;
    s.wind.fluid.resolution = 64;
    s.wind.global = Some(GlobalWind {
        direction: (1.0, 0.35),
        strength: 1.0,
    });
    // A lighter field: the wind, not the grass, is under test.
    s.field.density = 20.0;
    s.culling.max_distance = 6.0;
    s.render.billboard_distance = 0.0;
    s.render.msaa = 1;
    s.colliders.clear();
    let gpu = common::gpu();
    let session = Session::new(s, None, Some(&gpu)).expect("session");
    let terrain = sward::field::HeightField::from_scene(&session.scene.terrain).unwrap();
    let mut r = common::world(&gpu, &session);
    let target = Target::new(&gpu, 64, 36).expect("target");
    let camera = CameraView::from_scene(&session.scene.camera);
    let radius = 0.6;
    let velocity = glam::Vec3::new(0.0, 0.0, 3.0);
    let mut centre = glam::Vec3::new(2.0, 0.0, -6.0);
    for _ in 0..75 {
        centre += velocity / 30.0;
        centre.y = terrain.height(centre.x, centre.z) + radius;
        // The ball is a collider handed to the frame, as a host's (or the window's balls).
        let ball = sward::Collider {
            center: centre,
            radius,
            velocity,
        };
        let colliders = if with_ball { vec![ball] } else { Vec::new() };
        sward::commands::world_frame_with(&gpu, &mut r, 1.0 / 30.0, camera, &colliders, &target)
            .expect("frame");
    }
    gpu.check_errors().expect("no GPU error");
    let state = r
        .fluid
        .as_ref()
        .expect("the fluid is on")
        .read_state(&gpu)
        .expect("read-back");
    (sample_velocity(&state, centre.x, centre.z - 1.5), centre)
}

#[test]
fn a_ball_rolling_through_the_default_meadows_wind_leaves_a_wake() {
    let (free, _) = meadow_wind_behind_a_ball(false);
    let (wake, ball) = meadow_wind_behind_a_ball(true);
    let d = [wake[0] - free[0], wake[1] - free[1]];
    println!(
        "ball at {ball}: air 1.5 m behind it {wake:?} m/s, the same place without the ball \
         {free:?} m/s, difference {:.3} m/s",
        speed(d)
    );
    assert!(speed(free) > 0.3, "no free stream ({free:?})");
    // The ball drags the air behind it along its path (+z) and shades it from the wind.
    assert!(speed(d) > 0.3, "no wake: {wake:?} vs {free:?}");
    assert!(
        wake[1] > free[1],
        "the air behind the ball is not dragged along"
    );
}
