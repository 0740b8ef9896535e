//! The staggered-grid wind solver on the test adapter against its CPU twin
//! (`sim::reference::fluid`): one step with each pass's work switched on in turn, for every
//! boundary mode, then fifty steps with everything on. Each comparison covers the grids the
//! solver exposes: the faces (u, v), the cell-centred velocity, the solid mask, the
//! divergence that entered the pressure solve and the pressure. The same on a 3D grid
//! (`wind.fluid.layers`), with w. Every measured figure is printed (`cargo test --release --test twin_fluid_mac -- --nocapture`).

mod common;
#[path = "common/fluid.rs"]
mod fluid_common;

use fluid_common::{
    arrow, config, flat, gpu_step, max_abs, max_diff, random_faces, random_faces_3d, BOUNDARIES,
};
use sward::gpu::Gpu;
use sward::scene::{Advection, PressureSolver};
use sward::sim::fluid::{FluidConfig, FluidSolver, FluidState, FLUID_PASSES};
use sward::sim::reference::fluid::FluidCpu;
use sward::sim::wind_layout::{FluidForces, ObstacleGpu};

/// One step's tolerance, relative to the largest magnitude of each compared grid. Kernel
/// and twin run the same f32 operations in the same order; the GPU may fuse a·b + c into
/// one rounding and round division and sqrt within a few ulps (~1e-7 relative per
/// operation), and one step chains some tens of operations (hundreds in a V-cycle, whose
/// smoothing damps them again). Measured on lavapipe: bit-identical (0) for every pass but
/// the confinement, ≤ 2.2e-7 there (its sqrt and division); a wrong index, border rule or
/// operand order shows up at 1e-2 and above. The tolerance is about ten times the figure.
const STEP_TOLERANCE: f32 = 2e-6;

/// Fifty steps without vorticity confinement, in m/s of any face: the solver is
/// dissipative and rounding does not grow (measured on lavapipe: 0, bit-identical, at peak
/// speeds of 7–9 m/s); the bound leaves room for one ulp of rounding at 10 m/s.
const RUN_TOLERANCE: f32 = 1e-5;

/// With confinement the same rounding is amplified by the dynamics (it feeds vorticity
/// back at a rate of ε h |∇|ω||/|ω| ~ ε, so a 1e-7 difference grows by e^(ε · 1.7 s) over
/// fifty steps). It is still rounding, so the bound is relative to the peak speed: measured
/// 3.2e-6 (3.7e-5 m/s at 11.7 m/s) on lavapipe; the bound is 3e-5.
const RUN_TOLERANCE_CONFINED: f32 = 3e-5;

/// The largest difference of each grid, relative to the larger of its magnitudes (1 for
/// grids that are all zero), and whether the solid masks agree.
struct Diff {
    faces: f32,
    velocity: f32,
    divergence: f32,
    pressure: f32,
    solid_equal: bool,
    /// Peak face speed of the CPU grid, m/s.
    peak: f32,
    /// Largest absolute face difference, m/s.
    faces_abs: f32,
}

fn relative(a: &[f32], b: &[f32]) -> f32 {
    let scale = max_abs(a).max(max_abs(b));
    max_diff(a, b) / if scale > 0.0 { scale } else { 1.0 }
}

fn compare(g: &FluidState, c: &FluidState) -> Diff {
    let gf: Vec<f32> = g.u.iter().chain(&g.v).chain(&g.w).copied().collect();
    let cf: Vec<f32> = c.u.iter().chain(&c.v).chain(&c.w).copied().collect();
    Diff {
        faces: relative(&gf, &cf),
        velocity: relative(&flat(&g.velocity), &flat(&c.velocity)),
        divergence: relative(&g.divergence, &c.divergence),
        pressure: relative(&g.pressure, &c.pressure),
        solid_equal: g.solid == c.solid,
        peak: max_abs(&cf),
        faces_abs: max_diff(&gf, &cf),
    }
}

fn forces(t: f32) -> FluidForces {
    FluidForces {
        // An AGC branch: a trunk along x and a branch turning up-right from its end.
        arrows: vec![
            arrow([-12.0, -6.0], [2.0, -6.0], 6.0, 3.0),
            arrow([2.0, -6.0], [8.0, 6.0], 5.0, 2.5),
        ],
        // A ball rolling along +x through the flow.
        obstacles: vec![ObstacleGpu {
            circle: [-10.0 + 4.0 * t, 5.0, 2.0, 0.0],
            velocity: [4.0, 0.0, 0.0, 0.0],
        }],
        global: [0.3, 0.1],
        downwash: [6.0, 8.0, 6.0, 8.0],
    }
}

/// Runs `steps` steps on both sides from `start` faces and compares.
fn run(
    gpu: &Gpu,
    cfg: &FluidConfig,
    start: &(Vec<f32>, Vec<f32>),
    steps: u32,
    forces_at: &dyn Fn(f32) -> FluidForces,
) -> (Diff, Option<Vec<(&'static str, f64)>>) {
    run3(gpu, cfg, (&start.0, &start.1, &[]), steps, forces_at)
}

/// [`run`] with w faces (empty: still).
fn run3(
    gpu: &Gpu,
    cfg: &FluidConfig,
    start: (&[f32], &[f32], &[f32]),
    steps: u32,
    forces_at: &dyn Fn(f32) -> FluidForces,
) -> (Diff, Option<Vec<(&'static str, f64)>>) {
    let dt = 1.0 / 30.0;
    let mut solver = FluidSolver::new(gpu, cfg).expect("64² fits any adapter");
    solver.write_faces(&gpu.queue, start.0, start.1, start.2);
    let mut cpu = FluidCpu::new(cfg);
    cpu.set_faces(start.0, start.1, start.2);
    for step in 0..steps {
        let f = forces_at(step as f32 * dt);
        gpu_step(gpu, &mut solver, dt, &f);
        cpu.step(dt, &f);
    }
    let g = solver.read_state(gpu).expect("read-back");
    let ms = solver.read_pass_ms(gpu).expect("timestamps");
    (compare(&g, &cpu.state()), ms)
}

#[test]
fn each_pass_matches_its_twin_after_one_step() {
    let gpu = common::gpu();
    let n = 64;
    let none = |_: f32| FluidForces::default();
    let with_forces = |t: f32| forces(t);
    let static_ball = |_: f32| FluidForces {
        obstacles: vec![ObstacleGpu {
            circle: [1.0, -2.0, 3.0, 0.0],
            velocity: [0.0; 4],
        }],
        ..Default::default()
    };
    for boundary in BOUNDARIES {
        let base = config(n, 32.0, boundary);
        // 8 m/s on a 0.5 m grid: traces of half a cell per step, across cell borders.
        let random = random_faces(n as usize, boundary, 11, 8.0);
        let still = (vec![0.0; base.layer_faces()], vec![0.0; base.layer_faces()]);
        type Case<'a> = (
            &'a str,
            FluidConfig,
            &'a (Vec<f32>, Vec<f32>),
            &'a dyn Fn(f32) -> FluidForces,
        );
        let cases: Vec<Case> = vec![
            (
                "advect: semi-Lagrangian",
                FluidConfig {
                    dissipation: 0.15,
                    ..base.clone()
                },
                &random,
                &none,
            ),
            (
                "advect: MacCormack",
                FluidConfig {
                    dissipation: 0.15,
                    advection: Advection::MacCormack,
                    ..base.clone()
                },
                &random,
                &none,
            ),
            (
                "splat: forces and a moving obstacle",
                base.clone(),
                &still,
                &with_forces,
            ),
            (
                "vorticity: ε = 10",
                FluidConfig {
                    vorticity: 10.0,
                    ..base.clone()
                },
                &random,
                &none,
            ),
            (
                "diffuse: 7 iterations",
                FluidConfig {
                    viscosity: 0.05,
                    diffusion_iterations: 7,
                    ..base.clone()
                },
                &random,
                &none,
            ),
            (
                "divergence, Jacobi ×21, gradient",
                FluidConfig {
                    pressure_iterations: 21,
                    ..base.clone()
                },
                &random,
                &none,
            ),
            (
                "multigrid ×2 around a static obstacle, gradient",
                FluidConfig {
                    pressure_solver: PressureSolver::Multigrid,
                    ..base.clone()
                },
                &random,
                &static_ball,
            ),
        ];
        for (name, cfg, start, f) in cases {
            let (d, _) = run(&gpu, &cfg, start, 1, f);
            println!(
                "one step {boundary:?}, {name}: max relative |gpu - cpu| faces {:.2e}, \
                 velocity {:.2e}, divergence {:.2e}, pressure {:.2e}; solid equal {} \
                 (tolerance {STEP_TOLERANCE:.0e})",
                d.faces, d.velocity, d.divergence, d.pressure, d.solid_equal
            );
            assert!(d.peak > 0.1, "{name}: nothing moved ({})", d.peak);
            assert!(d.solid_equal, "{boundary:?}, {name}: solid masks differ");
            for (what, e) in [
                ("faces", d.faces),
                ("velocity", d.velocity),
                ("divergence", d.divergence),
                ("pressure", d.pressure),
            ] {
                assert!(
                    e <= STEP_TOLERANCE,
                    "{boundary:?}, {name}: {what} differ by {e:e}"
                );
            }
        }
    }
}

#[test]
fn fifty_steps_match_the_twin_for_every_boundary() {
    let gpu = common::gpu();
    for boundary in BOUNDARIES {
        let base = FluidConfig {
            dissipation: 0.15,
            viscosity: 0.05,
            warm_start: true,
            ..config(64, 32.0, boundary)
        };
        // Odd and even counts of the Jacobi and diffusion ping-pongs, both advections and
        // both solvers, with and without confinement.
        let variants = [
            (
                "Jacobi ×21 (22: warm start), diffusion ×8, semi-Lagrangian",
                FluidConfig {
                    pressure_iterations: 21,
                    diffusion_iterations: 8,
                    ..base.clone()
                },
            ),
            (
                "multigrid ×2, diffusion ×7, MacCormack",
                FluidConfig {
                    pressure_solver: PressureSolver::Multigrid,
                    diffusion_iterations: 7,
                    advection: Advection::MacCormack,
                    ..base.clone()
                },
            ),
            (
                "multigrid ×1 (cold start), diffusion ×8, ε = 3",
                FluidConfig {
                    pressure_solver: PressureSolver::Multigrid,
                    multigrid_cycles: 1,
                    warm_start: false,
                    diffusion_iterations: 8,
                    vorticity: 3.0,
                    ..base.clone()
                },
            ),
        ];
        for (name, cfg) in variants {
            let still = (vec![0.0; cfg.layer_faces()], vec![0.0; cfg.layer_faces()]);
            let (d, ms) = run(&gpu, &cfg, &still, 50, &forces);
            let tolerance = if cfg.vorticity == 0.0 {
                RUN_TOLERANCE
            } else {
                RUN_TOLERANCE_CONFINED * d.peak
            };
            println!(
                "50 steps {boundary:?}, {name}: peak {:.2} m/s, max |gpu - cpu| faces {:.3e} \
                 m/s (tolerance {tolerance:.1e}), relative pressure {:.2e}",
                d.peak, d.faces_abs, d.pressure
            );
            if let Some(ms) = &ms {
                assert_eq!(ms.len(), FLUID_PASSES.len());
                let line: Vec<String> = ms.iter().map(|(n, t)| format!("{n} {t:.3}")).collect();
                println!("  GPU ms of the last step: {}", line.join(", "));
            }
            assert!(
                d.peak > 2.0,
                "the forces must have moved the air ({})",
                d.peak
            );
            assert!(d.solid_equal, "{boundary:?}, {name}: solid masks differ");
            assert!(
                d.faces_abs < tolerance,
                "{boundary:?}, {name}: GPU and CPU differ by {} m/s",
                d.faces_abs
            );
        }
    }
}

/// 3D forces: the same arrows and global push, a ball 1.2 m above the ground rising and
/// rolling through the layers, and the downwash pushing down.
fn forces_3d(t: f32) -> FluidForces {
    FluidForces {
        obstacles: vec![ObstacleGpu {
            circle: [-10.0 + 4.0 * t, 5.0, 2.0, 1.2 + 0.5 * t],
            velocity: [4.0, 0.0, 0.5, 0.0],
        }],
        ..forces(t)
    }
}

fn config_3d(boundary: sward::scene::Boundary) -> FluidConfig {
    FluidConfig {
        layers: 4,
        layer_height: 0.75,
        ground_drag: 2.0,
        ..config(32, 32.0, boundary)
    }
}

#[test]
fn each_pass_matches_its_twin_on_a_3d_grid() {
    let gpu = common::gpu();
    let none = |_: f32| FluidForces::default();
    let with_forces = |t: f32| forces_3d(t);
    for boundary in BOUNDARIES {
        let base = config_3d(boundary);
        let (u, v, w) = random_faces_3d(32, 4, boundary, 5, 6.0);
        let still_u = vec![0.0; u.len()];
        // (name, configuration, starts from the random field (else still air), forces)
        type Case<'a> = (&'a str, FluidConfig, bool, &'a dyn Fn(f32) -> FluidForces);
        let cases: Vec<Case> = vec![
            ("advect: semi-Lagrangian", base.clone(), true, &none),
            (
                "advect: MacCormack",
                FluidConfig {
                    advection: Advection::MacCormack,
                    ..base.clone()
                },
                true,
                &none,
            ),
            (
                "splat: forces, drag, a rising ball",
                base.clone(),
                false,
                &with_forces,
            ),
            (
                "vorticity: ε = 10",
                FluidConfig {
                    vorticity: 10.0,
                    ..base.clone()
                },
                true,
                &none,
            ),
            (
                "diffuse: 5 iterations",
                FluidConfig {
                    viscosity: 0.05,
                    diffusion_iterations: 5,
                    ..base.clone()
                },
                true,
                &none,
            ),
            (
                "divergence, Jacobi ×21, gradient",
                FluidConfig {
                    pressure_iterations: 21,
                    ..base.clone()
                },
                true,
                &none,
            ),
            (
                "multigrid ×2 around the ball, gradient",
                FluidConfig {
                    pressure_solver: PressureSolver::Multigrid,
                    ..base.clone()
                },
                true,
                &with_forces,
            ),
        ];
        for (name, cfg, moving, f) in cases {
            let start = if moving {
                (&u[..], &v[..], &w[..])
            } else {
                (&still_u[..], &still_u[..], &[][..])
            };
            let (d, _) = run3(&gpu, &cfg, start, 1, f);
            println!(
                "3D one step {boundary:?}, {name}: max relative |gpu - cpu| faces {:.2e}, \
                 velocity {:.2e}, divergence {:.2e}, pressure {:.2e}; solid equal {}",
                d.faces, d.velocity, d.divergence, d.pressure, d.solid_equal
            );
            assert!(d.peak > 0.1, "{name}: nothing moved ({})", d.peak);
            assert!(d.solid_equal, "{boundary:?}, {name}: solid masks differ");
            for (what, e) in [
                ("faces", d.faces),
                ("velocity", d.velocity),
                ("divergence", d.divergence),
                ("pressure", d.pressure),
            ] {
                assert!(
                    e <= STEP_TOLERANCE,
                    "3D {boundary:?}, {name}: {what} differ by {e:e}"
                );
            }
        }
    }
}

#[test]
fn thirty_steps_match_the_twin_on_a_3d_grid() {
    let gpu = common::gpu();
    for boundary in BOUNDARIES {
        let cfg = FluidConfig {
            pressure_solver: PressureSolver::Multigrid,
            warm_start: true,
            dissipation: 0.15,
            viscosity: 0.05,
            diffusion_iterations: 4,
            advection: Advection::MacCormack,
            ..config_3d(boundary)
        };
        let still = vec![0.0; cfg.layer_faces() * 4];
        let (d, ms) = run3(&gpu, &cfg, (&still, &still, &[]), 30, &forces_3d);
        println!(
            "3D 30 steps {boundary:?}: peak {:.2} m/s, max |gpu - cpu| faces {:.3e} m/s \
             (tolerance {RUN_TOLERANCE:.0e}), relative pressure {:.2e}",
            d.peak, d.faces_abs, d.pressure
        );
        if let Some(ms) = ms {
            let line: Vec<String> = ms.iter().map(|(n, t)| format!("{n} {t:.3}")).collect();
            println!("  GPU ms of the last 32²×4 step: {}", line.join(", "));
        }
        assert!(
            d.peak > 2.0,
            "the forces must have moved the air ({})",
            d.peak
        );
        assert!(d.solid_equal, "{boundary:?}: solid masks differ");
        assert!(
            d.faces_abs < RUN_TOLERANCE,
            "3D {boundary:?}: GPU and CPU differ by {} m/s",
            d.faces_abs
        );
    }
}
