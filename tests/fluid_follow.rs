//! A wind grid that follows the camera (issue 13, point 4; `wind.fluid.extent > 0`):
//! - the scroll kernel (`fluid_scroll.wgsl`) against its CPU twin (`scroll_grids`): exact,
//!   for shifts inside the grid, along both axes and farther than the grid (a teleport);
//! - after a scroll the faces at a world point hold what they held before (away from the
//!   entering edge), so the wind the blades sample does not jump;
//! - a guide stays anchored in the world while the grid follows a moving camera;
//! - the renderer moves the grid with the camera and the blades sample it where it is.

mod common;
#[path = "common/fluid.rs"]
mod fluid_common;

use fluid_common::{arrow, config, gpu_step, random_faces};
use sward::gpu::queries::PassQueries;
use sward::gpu::Gpu;
use sward::scene::{Boundary, PressureSolver};
use sward::sim::fluid::{FluidConfig, FluidSolver, FluidState};
use sward::sim::reference::fluid::scroll_grids;
use sward::sim::wind_layout::FluidForces;

fn following(n: u32, side: f32) -> FluidConfig {
    FluidConfig {
        follow: true,
        pressure_solver: PressureSolver::Multigrid,
        warm_start: true,
        ..config(n, side, Boundary::Open)
    }
}

/// Records `follow(eye)` in its own submission; returns the shift in cells.
fn follow(gpu: &Gpu, solver: &mut FluidSolver, eye: [f32; 2]) -> [i64; 2] {
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("sward.test.follow"),
        });
    let shift = solver.follow(&gpu.queue, &mut encoder, eye, PassQueries::NONE);
    gpu.queue.submit([encoder.finish()]);
    gpu.check_errors().expect("no GPU error");
    shift
}

/// The face velocity (u or v) of `s` at world (x, z) on the face nearest that point.
fn u_at(s: &FluidState, x: f32, z: f32) -> f32 {
    let n = s.resolution as i64;
    let i = ((x - s.origin[0]) / s.cell_size).round() as i64;
    let j = ((z - s.origin[1]) / s.cell_size - 0.5).round() as i64;
    s.u[(j.clamp(0, n - 1) * (n + 1) + i.clamp(0, n)) as usize]
}

#[test]
fn the_scroll_matches_its_twin_exactly_and_keeps_the_air_in_place() {
    scroll_matches_twin(1);
}

#[test]
fn a_3d_grid_scrolls_every_layer_exactly_as_its_twin() {
    scroll_matches_twin(3);
}

fn scroll_matches_twin(layers: u32) {
    let gpu = common::gpu();
    let n = 32u32;
    let cfg = FluidConfig {
        layers,
        ..following(n, 32.0)
    };
    let mut solver = FluidSolver::new(&gpu, &cfg).expect("solver");
    let (mut u, mut v) = (Vec::new(), Vec::new());
    for k in 0..layers {
        let (lu, lv) = random_faces(n as usize, Boundary::Open, 7 + u64::from(k), 2.0);
        u.extend(lu);
        v.extend(lv);
    }
    let w: Vec<f32> = if layers > 1 {
        fluid_common::random_values((n * n * (layers + 1)) as usize, 99)
    } else {
        Vec::new()
    };
    solver.write_faces(&gpu.queue, &u, &v, &w);
    // One step, so that the pressure is not zero either.
    gpu_step(&gpu, &mut solver, 1.0 / 30.0, &FluidForces::default());
    assert_eq!(
        follow(&gpu, &mut solver, [0.2, 0.3]),
        [0, 0],
        "the first call places"
    );
    let h = cfg.cell_size;
    let mut eye = [0.2f32, 0.3];
    for (dx, dz) in [(3i64, -2i64), (0, 5), (-7, 0), (45, -1), (-2, -60)] {
        let before = solver.read_state(&gpu).expect("read-back");
        eye = [eye[0] + dx as f32 * h, eye[1] + dz as f32 * h];
        let shift = follow(&gpu, &mut solver, eye);
        assert_eq!(
            shift,
            [dx, dz],
            "the grid moves by whole cells with the camera"
        );
        let after = solver.read_state(&gpu).expect("read-back");
        let expected = scroll_grids(
            n as usize,
            layers as usize,
            (&before.u, &before.v, &before.w),
            &before.pressure,
            [dx.clamp(-33, 33) as i32, dz.clamp(-33, 33) as i32],
        );
        assert!(
            expected.u == after.u && expected.v == after.v && expected.w == after.w,
            "faces differ from the twin ({dx}, {dz}), {layers} layers"
        );
        assert!(
            expected.pressure == after.pressure,
            "pressure differs from the twin ({dx}, {dz})"
        );
        let moved = [
            after.origin[0] - before.origin[0],
            after.origin[1] - before.origin[1],
        ];
        assert!(
            (moved[0] - dx as f32 * h).abs() < 1e-4 && (moved[1] - dz as f32 * h).abs() < 1e-4,
            "the corner moved by {moved:?}"
        );
        // The air at a world point that stays in both grids (two cells from every edge)
        // is what it was: nothing smears, nothing jumps.
        if dx.abs() < 10 && dz.abs() < 10 {
            let mut checked = 0;
            for k in 0..40 {
                let x = after.origin[0] + (2.0 + (k % 8) as f32 * 3.3) * h;
                let z = after.origin[1] + (2.5 + (k / 8) as f32 * 5.1) * h;
                let inside = |s: &FluidState, x: f32, z: f32| {
                    let lo = [s.origin[0] + 2.0 * h, s.origin[1] + 2.0 * h];
                    let hi = [lo[0] + (n as f32 - 4.0) * h, lo[1] + (n as f32 - 4.0) * h];
                    x > lo[0] && x < hi[0] && z > lo[1] && z < hi[1]
                };
                if inside(&before, x, z) && inside(&after, x, z) {
                    assert_eq!(u_at(&before, x, z), u_at(&after, x, z), "u at ({x}, {z})");
                    checked += 1;
                }
            }
            assert!(checked > 10, "{checked} points checked");
        }
    }
}

#[test]
fn a_guide_stays_anchored_in_the_world_while_the_grid_follows_the_camera() {
    let gpu = common::gpu();
    let cfg = FluidConfig {
        dissipation: 0.3,
        ..following(64, 48.0)
    };
    let mut solver = FluidSolver::new(&gpu, &cfg).expect("solver");
    // A guide from (-8, 3) to (4, 3), fixed in the world; the camera flies along x at
    // 6 m/s from x = -10, so the grid moves under the guide.
    let (from, to) = ([-8.0f32, 3.0], [4.0f32, 3.0]);
    let forces = FluidForces {
        arrows: vec![arrow(from, to, 10.0, 2.0)],
        ..Default::default()
    };
    let mut moved = 0;
    for step in 0..45 {
        let eye = [-10.0 + 6.0 * step as f32 / 30.0, -1.0];
        let s = follow(&gpu, &mut solver, eye);
        moved += s[0].abs() + s[1].abs();
        gpu_step(&gpu, &mut solver, 1.0 / 30.0, &forces);
    }
    let s = solver.read_state(&gpu).expect("read-back");
    let sample = |x: f32, z: f32| sward::sim::fluid::sample_velocity(&s, x, z);
    let mid = sample(-2.0, 3.0);
    let aside = sample(-2.0, 3.0 + 8.0);
    let speed = |v: [f32; 2]| (v[0] * v[0] + v[1] * v[1]).sqrt();
    println!(
        "guide under a grid that moved {moved} cells: at its midpoint {mid:?} m/s, 8 m aside \
         {aside:?} m/s; grid corner {:?}",
        s.origin
    );
    assert!(moved >= 10, "the grid did not follow ({moved} cells)");
    // The last eye is at x = -1.2 m: its cell is floor(-1.2 / 0.75) = -2, the corner 32
    // cells before it.
    assert_eq!(s.origin, [(-2.0 - 32.0) * 0.75, (-2.0 - 32.0) * 0.75]);
    assert!(speed(mid) > 1.0, "the guide does not blow where it is");
    assert!(
        mid[0] / speed(mid) > 0.9,
        "the jet does not run along the guide"
    );
    assert!(
        speed(aside) < 0.3 * speed(mid),
        "the jet is not where the guide is"
    );
}

#[test]
fn the_renderer_moves_the_grid_with_the_camera() {
    use sward::render::camera::CameraView;
    use sward::render::target::Target;

    use sward::scene::WindSource;
    use sward::session::Session;
    let mut s = common::still_scene();
    s.wind.source = WindSource::Fluid;
    s.wind.fluid.resolution = 32;
    s.wind.fluid.extent = 24.0;
    s.field.density = 10.0;
    s.render.msaa = 1;
    let gpu = common::gpu();
    let session = Session::new(s, None, Some(&gpu)).expect("session");
    let mut r = common::world(&gpu, &session);
    let target = Target::new(&gpu, 32, 18).expect("target");
    let mut corners = Vec::new();
    for x in [0.0f32, 0.2, 7.9] {
        let mut scene_camera = session.scene.camera.clone();
        scene_camera.eye.0 = x;
        scene_camera.target.0 = x + 5.0;
        let camera = CameraView::from_scene(&scene_camera);
        sward::commands::world_frame(&gpu, &mut r, 1.0 / 30.0, camera, &target).expect("frame");
        corners.push(r.fluid.as_ref().expect("fluid").origin());
    }
    gpu.check_errors().expect("no GPU error");
    // 0.75 m cells: the grid stays for a move inside the camera's cell and follows by
    // whole cells (7.9 m: 10 cells) otherwise.
    let h = 24.0 / 32.0;
    println!("grid corners along the camera's path: {corners:?}");
    assert_eq!(corners[0], corners[1]);
    assert_eq!(corners[2][0] - corners[0][0], 10.0 * h);
    assert_eq!(corners[2][1], corners[0][1]);
}
