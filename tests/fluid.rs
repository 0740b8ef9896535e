//! The staggered-grid wind solver (`src/sim/fluid/`, `shaders/fluid_*.wgsl`) on the physics
//! it must get right: a converged projection leaves only the solver's residual, multigrid
//! removes a random field's divergence a hundredfold where Jacobi cannot, a static obstacle
//! holds the air still inside and lets it pass on both sides, confinement scales with h,
//! advection keeps a uniform periodic flow uniform, an AGC arrow makes a jet along itself.
//! The GPU-vs-CPU comparisons of every pass are in `tests/twin_fluid_mac.rs`. Every
//! measured figure is printed (`cargo test --release --test fluid -- --nocapture`).

mod common;
#[path = "common/fluid.rs"]
mod fluid_common;

use fluid_common::{arrow, config, gpu_step, max_diff, random_faces, BOUNDARIES};
use sward::scene::{Advection, Boundary, PressureSolver};
use sward::sim::fluid::{FluidConfig, FluidSolver, FluidState};
use sward::sim::reference::fluid::{sample_velocity, FluidCpu};
use sward::sim::wind_layout::{FluidForces, ObstacleGpu};
use sward::Error;

fn speed(v: [f32; 2]) -> f32 {
    (v[0] * v[0] + v[1] * v[1]).sqrt()
}

/// A converged solve: the relative divergence left is the f32 residual floor (measured
/// ~1e-6 on the CPU and the GPU), far below this bound.
const CONVERGED: f64 = 1e-4;

/// Projects `field` with `cfg` on the CPU: divergence, pressure, gradient (a step's
/// projection). Static obstacles need the splat too: a step with Δt = 0 does exactly the
/// projection plus the obstacles (advection and forces move nothing in no time).
fn project_cpu(
    cfg: &FluidConfig,
    field: &(Vec<f32>, Vec<f32>),
    forces: &FluidForces,
) -> FluidState {
    let mut cpu = FluidCpu::new(cfg);
    cpu.set_faces(&field.0, &field.1, &[]);
    cpu.step(0.0, forces);
    cpu.state()
}

fn project_gpu(
    gpu: &sward::gpu::Gpu,
    cfg: &FluidConfig,
    field: &(Vec<f32>, Vec<f32>),
    forces: &FluidForces,
) -> FluidState {
    let mut solver = FluidSolver::new(gpu, cfg).expect("solver");
    solver.write_faces(&gpu.queue, &field.0, &field.1, &[]);
    gpu_step(gpu, &mut solver, 0.0, forces);
    solver.read_state(gpu).expect("read-back")
}

/// RMS divergence before ÷ after the projection.
fn reduction(s: &FluidState) -> f64 {
    s.rms_divergence_before() / s.rms_divergence()
}

fn ball(x: f32, z: f32, r: f32) -> FluidForces {
    FluidForces {
        obstacles: vec![ObstacleGpu {
            circle: [x, z, r, 0.0],
            velocity: [0.0; 4],
        }],
        ..Default::default()
    }
}

#[test]
fn converged_projection_leaves_only_the_residual() {
    let gpu = common::gpu();
    let n = 64;
    for boundary in BOUNDARIES {
        let cfg = FluidConfig {
            pressure_solver: PressureSolver::Multigrid,
            multigrid_cycles: 12,
            ..config(n, 32.0, boundary)
        };
        let field = random_faces(n as usize, boundary, 7, 1.0);
        for (what, forces) in [
            ("open field", FluidForces::default()),
            ("static ball", ball(2.0, -3.0, 4.0)),
        ] {
            let c = project_cpu(&cfg, &field, &forces);
            let g = project_gpu(&gpu, &cfg, &field, &forces);
            let (cpu_left, gpu_left) = (1.0 / reduction(&c), 1.0 / reduction(&g));
            println!(
                "converged projection {boundary:?}, {what}: rms divergence {:.4} → CPU {:.3e}, \
                 GPU {:.3e} 1/s (relative {cpu_left:.2e} / {gpu_left:.2e}, bound {CONVERGED:.0e})",
                c.rms_divergence_before(),
                c.rms_divergence(),
                g.rms_divergence()
            );
            assert!(
                cpu_left <= CONVERGED,
                "{boundary:?}, {what}: CPU left {cpu_left}"
            );
            assert!(
                gpu_left <= CONVERGED,
                "{boundary:?}, {what}: GPU left {gpu_left}"
            );
        }
    }
}

#[test]
fn multigrid_removes_a_random_fields_divergence_a_hundredfold() {
    let gpu = common::gpu();
    let n = 64;
    for boundary in BOUNDARIES {
        let field = random_faces(n as usize, boundary, 3, 1.0);
        let none = FluidForces::default();
        let mg = FluidConfig {
            pressure_solver: PressureSolver::Multigrid,
            multigrid_cycles: 2,
            ..config(n, 32.0, boundary)
        };
        let jacobi = FluidConfig {
            pressure_iterations: 40,
            ..config(n, 32.0, boundary)
        };
        let (mg_cpu, mg_gpu) = (
            reduction(&project_cpu(&mg, &field, &none)),
            reduction(&project_gpu(&gpu, &mg, &field, &none)),
        );
        let (j_cpu, j_gpu) = (
            reduction(&project_cpu(&jacobi, &field, &none)),
            reduction(&project_gpu(&gpu, &jacobi, &field, &none)),
        );
        println!(
            "random 64² field {boundary:?}: rms divergence reduced {mg_cpu:.0}x by 2 V-cycles \
             (GPU {mg_gpu:.0}x), {j_cpu:.1}x by 40 Jacobi iterations (GPU {j_gpu:.1}x)"
        );
        assert!(
            mg_cpu >= 100.0 && mg_gpu >= 100.0,
            "{boundary:?}: multigrid only {mg_cpu}x / {mg_gpu}x"
        );
        assert!(
            mg_cpu > 5.0 * j_cpu,
            "{boundary:?}: multigrid {mg_cpu}x, Jacobi {j_cpu}x"
        );
    }
}

/// Two V-cycles (cold) on a smooth jet, u = e^(−r²/9 m²) along x, on an n² grid over 24 m:
/// the RMS divergence before ÷ after.
fn smooth_jet_reduction(n: u32, boundary: Boundary) -> f64 {
    let cfg = FluidConfig {
        pressure_solver: PressureSolver::Multigrid,
        multigrid_cycles: 2,
        ..config(n, 24.0, boundary)
    };
    let (nn, h) = (n as usize, cfg.cell_size);
    let jet = |x: f32, z: f32| (-((x - 2.0).powi(2) + (z + 1.0).powi(2)) / 9.0).exp();
    let mut u: Vec<f32> = (0..nn * (nn + 1))
        .map(|k| {
            let (i, j) = ((k % (nn + 1)) as f32, (k / (nn + 1)) as f32);
            jet(-12.0 + i * h, -12.0 + (j + 0.5) * h)
        })
        .collect();
    let mut v = vec![0.0f32; nn * (nn + 1)];
    match boundary {
        Boundary::Closed => (0..nn).for_each(|j| {
            u[j * (nn + 1)] = 0.0;
            u[j * (nn + 1) + nn] = 0.0;
        }),
        Boundary::Periodic => sward::sim::reference::fluid::periodic_faces(&mut u, &mut v, nn),
        Boundary::Open => {}
    }
    reduction(&project_cpu(&cfg, &(u, v), &FluidForces::default()))
}

#[test]
fn multigrid_converges_alike_at_every_resolution() {
    // Smooth divergence is what Jacobi cannot remove and what the coarse levels are for; an
    // open border whose 0 pressure the coarse levels misplaced used to slow this down with
    // every level added (5.6x at 256², 1.2x at 1024²).
    for boundary in BOUNDARIES {
        let (coarse, fine) = (
            smooth_jet_reduction(32, boundary),
            smooth_jet_reduction(128, boundary),
        );
        println!(
            "smooth jet {boundary:?}: rms divergence reduced {coarse:.0}x at 32², {fine:.0}x \
             at 128² by 2 V-cycles"
        );
        assert!(
            coarse >= 100.0 && fine >= 100.0,
            "{boundary:?}: {coarse}x / {fine}x"
        );
        assert!(
            fine >= 0.7 * coarse,
            "{boundary:?}: {fine}x at 128² against {coarse}x at 32²"
        );
    }
}

#[test]
fn static_obstacle_holds_the_air_and_lets_it_pass_on_both_sides() {
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
        ..ball(0.0, 0.0, r)
    };
    let mut solver = FluidSolver::new(&gpu, &cfg).expect("solver");
    let mut cpu = FluidCpu::new(&cfg);
    for _ in 0..60 {
        gpu_step(&gpu, &mut solver, 1.0 / 30.0, &forces);
        cpu.step(1.0 / 30.0, &forces);
    }
    let s = solver.read_state(&gpu).expect("read-back");
    let inside = s
        .velocity
        .iter()
        .zip(&s.solid)
        .filter(|(_, &k)| k != 0)
        .map(|(v, _)| speed(*v))
        .fold(0.0, f32::max);
    let solid_cells = s.solid.iter().filter(|&&k| k != 0).count();
    let (above, below) = (
        sample_velocity(&s, 0.0, r + 1.5),
        sample_velocity(&s, 0.0, -r - 1.5),
    );
    let free = sample_velocity(&s, 0.0, 12.0);
    let front = sample_velocity(&s, -r - 0.5, 0.0);
    println!(
        "static ball r = {r} m in a periodic 2 m/s² wind, 2 s: {solid_cells} solid cells, max \
         speed inside {inside:.2e} m/s; beside it {:.3} / {:.3} m/s (u {:.3} / {:.3}), far \
         {:.3} m/s, in front {:.3} m/s; rms divergence {:.2e} 1/s; |gpu - cpu| {:.1e} m/s",
        speed(above),
        speed(below),
        above[0],
        below[0],
        speed(free),
        speed(front),
        s.rms_divergence(),
        max_diff(&s.u, &cpu.state().u)
    );
    assert!(
        solid_cells > 80,
        "the ball covers too few cells ({solid_cells})"
    );
    assert_eq!(inside, 0.0, "air moves inside the obstacle");
    assert!(above[0] > 0.5 && below[0] > 0.5, "no flow past the sides");
    // The flow squeezes past: faster beside the ball than far from it, slow in front.
    assert!(
        above[0] > free[0] && below[0] > free[0],
        "no speed-up beside the ball"
    );
    assert!(
        speed(front) < 0.5 * speed(free),
        "the air runs into the ball"
    );
}

#[test]
fn warm_started_solves_stay_stable_with_odd_counts() {
    // 21 Jacobi iterations or 1 V-cycle, warm-started, used to feed each solve's residual
    // back into the next and blow up within 2 s (see `FluidConfig::jacobi_iterations`).
    for (name, solver) in [
        ("Jacobi ×21", PressureSolver::Jacobi),
        ("multigrid ×1", PressureSolver::Multigrid),
    ] {
        let cfg = FluidConfig {
            pressure_solver: solver,
            pressure_iterations: 21,
            multigrid_cycles: 1,
            warm_start: true,
            vorticity: 3.0,
            dissipation: 0.15,
            ..config(64, 32.0, Boundary::Open)
        };
        let mut cpu = FluidCpu::new(&cfg);
        let mut worst: f64 = 0.0;
        let mut peak: f32 = 0.0;
        for step in 0..120 {
            let t = step as f32 / 30.0;
            let forces = FluidForces {
                obstacles: vec![ObstacleGpu {
                    circle: [-10.0 + 4.0 * t, 5.0, 2.0, 0.0],
                    velocity: [4.0, 0.0, 0.0, 0.0],
                }],
                downwash: [6.0, 8.0, 6.0, 8.0],
                ..Default::default()
            };
            cpu.step(1.0 / 30.0, &forces);
            let s = cpu.state();
            worst = worst.max(1.0 / reduction(&s));
            peak = peak
                .max(fluid_common::max_abs(&s.u))
                .max(fluid_common::max_abs(&s.v));
        }
        println!(
            "{name}, warm start, 4 s of a moving ball and a downwash: peak {peak:.2} m/s, \
             worst divergence left after a solve {:.1} % of what entered it",
            100.0 * worst
        );
        assert!(peak < 20.0, "{name}: the air ran away to {peak} m/s");
        assert!(
            worst < 1.0,
            "{name}: a solve raised the divergence ({worst}x)"
        );
    }
}

/// The mean confinement force magnitude of one vorticity pass (ε = 1, Δt = 1) on a smooth
/// vortex of core radius 2 m sampled on an n² grid over 16 m.
fn confinement_force(n: u32) -> f64 {
    let cfg = FluidConfig {
        vorticity: 1.0,
        ..config(n, 16.0, Boundary::Open)
    };
    let h = cfg.cell_size;
    let n = n as usize;
    // A Gaussian (Lamb–Oseen) vortex off the grid centre: u_θ = Γ / (2πr) (1 − e^(−r²/r0²)).
    let vortex = |x: f32, z: f32| {
        let (dx, dz) = (x - 1.3, z + 0.7);
        let r2 = dx * dx + dz * dz;
        let k = if r2 == 0.0 {
            0.0
        } else {
            20.0 / (2.0 * std::f32::consts::PI * r2) * (1.0 - (-r2 / 4.0).exp())
        };
        [-dz * k, dx * k]
    };
    let at = |x: f32, z: f32| vortex(-8.0 + x * h, -8.0 + z * h);
    let u: Vec<f32> = (0..n * (n + 1))
        .map(|k| at((k % (n + 1)) as f32, (k / (n + 1)) as f32 + 0.5)[0])
        .collect();
    let v: Vec<f32> = (0..n * (n + 1))
        .map(|k| at((k % n) as f32 + 0.5, (k / n) as f32)[1])
        .collect();
    let mut cpu = FluidCpu::new(&cfg);
    cpu.set_faces(&u, &v, &[]);
    cpu.vorticity(1.0);
    let s = cpu.state();
    let before = u.iter().chain(&v);
    let after = s.u.iter().chain(&s.v);
    let sum: f64 = after
        .zip(before)
        .map(|(a, b)| f64::from((a - b).abs()))
        .sum();
    sum / (2 * n * (n + 1)) as f64
}

#[test]
fn confinement_force_scales_with_the_cell_size() {
    let coarse = confinement_force(32);
    let fine = confinement_force(64);
    let ratio = fine / coarse;
    println!(
        "vorticity confinement on a smooth vortex, ε = 1: mean |force| {coarse:.4} m/s² at \
         h = 0.5 m, {fine:.4} at h = 0.25 m, ratio {ratio:.3} (ε h (N × ω): 0.5)"
    );
    assert!((ratio - 0.5).abs() < 0.05, "force ratio {ratio} is not h's");
}

#[test]
fn uniform_flow_stays_uniform_under_periodic_advection() {
    let gpu = common::gpu();
    for advection in [Advection::SemiLagrangian, Advection::MacCormack] {
        let cfg = FluidConfig {
            advection,
            pressure_solver: PressureSolver::Multigrid,
            ..config(32, 16.0, Boundary::Periodic)
        };
        let half = cfg.layer_faces();
        let (u, v) = (vec![1.3f32; half], vec![-0.7f32; half]);
        let mut solver = FluidSolver::new(&gpu, &cfg).expect("solver");
        solver.write_faces(&gpu.queue, &u, &v, &[]);
        let mut cpu = FluidCpu::new(&cfg);
        cpu.set_faces(&u, &v, &[]);
        let dt = 1.0 / 30.0;
        for _ in 0..40 {
            gpu_step(&gpu, &mut solver, dt, &FluidForces::default());
            cpu.step(dt, &FluidForces::default());
        }
        let g = solver.read_state(&gpu).expect("read-back");
        let c = cpu.state();
        let dev = |s: &FluidState| max_diff(&s.u, &u).max(max_diff(&s.v, &v));
        let (gpu_dev, cpu_dev) = (dev(&g), dev(&c));
        println!(
            "uniform periodic flow, {advection:?}, 40 steps: max deviation GPU {gpu_dev:.3e}, \
             CPU {cpu_dev:.3e} m/s"
        );
        assert!(gpu_dev < 1e-5, "GPU drifted by {gpu_dev}");
        assert!(cpu_dev < 1e-5, "CPU drifted by {cpu_dev}");
    }
}

#[test]
fn single_arrow_makes_a_jet_along_itself() {
    let gpu = common::gpu();
    let cfg = FluidConfig {
        vorticity: 3.0,
        dissipation: 0.15,
        pressure_solver: PressureSolver::Multigrid,
        warm_start: true,
        ..config(64, 32.0, Boundary::Open)
    };
    let mut solver = FluidSolver::new(&gpu, &cfg).expect("solver");
    let (from, to, radius) = ([-6.0f32, -3.0], [6.0f32, 3.0], 2.0);
    let forces = FluidForces {
        arrows: vec![arrow(from, to, 10.0, radius)],
        ..Default::default()
    };
    for _ in 0..30 {
        gpu_step(&gpu, &mut solver, 1.0 / 30.0, &forces);
    }
    let state = solver.read_state(&gpu).expect("read-back");
    let d = [to[0] - from[0], to[1] - from[1]];
    let len = speed(d);
    let dir = [d[0] / len, d[1] / len];
    let side = [-dir[1], dir[0]];
    let mid = [0.5 * (from[0] + to[0]), 0.5 * (from[1] + to[1])];
    let at_mid = sample_velocity(&state, mid[0], mid[1]);
    let cosine = (at_mid[0] * dir[0] + at_mid[1] * dir[1]) / speed(at_mid);
    let off = 2.0 * radius;
    let left = sample_velocity(&state, mid[0] + side[0] * off, mid[1] + side[1] * off);
    let right = sample_velocity(&state, mid[0] - side[0] * off, mid[1] - side[1] * off);
    let side_speed = speed(left).max(speed(right));
    println!(
        "arrow jet after 1 s: midpoint {:.3} m/s (cosine {cosine:.4}), at 2 radii to the side \
         {:.3} / {:.3} m/s ({:.1} % of the midpoint)",
        speed(at_mid),
        speed(left),
        speed(right),
        100.0 * side_speed / speed(at_mid)
    );
    assert!(speed(at_mid) > 0.5, "the arrow barely moved the air");
    assert!(cosine > 0.9, "flow at the midpoint points off the arrow");
    assert!(side_speed < 0.3 * speed(at_mid), "the jet is not confined");
}

#[test]
fn scene_grid_covers_the_terrain() {
    let fluid = sward::scene::Fluid::default();
    let cfg = FluidConfig::from_scene(&fluid, 40.0);
    assert_eq!(cfg.resolution, fluid.resolution);
    assert_eq!(cfg.origin, [-20.0, -20.0]);
    assert_eq!(cfg.cell_size * cfg.resolution as f32, 40.0);
    assert_eq!(cfg.boundary, fluid.boundary);
    assert_eq!(cfg.pressure_solver, PressureSolver::Multigrid);
    cfg.validate().expect("the default scene's grid is valid");
}

#[test]
fn multigrid_levels_halve_while_the_side_allows() {
    let levels = |n: u32, boundary| config(n, 32.0, boundary).multigrid_levels();
    assert_eq!(levels(256, Boundary::Open), [256, 128, 64, 32, 16, 8, 4]);
    assert_eq!(levels(100, Boundary::Closed), [100, 50, 25]);
    // Periodic levels stay even, so red-black colouring holds across the seam.
    assert_eq!(levels(100, Boundary::Periodic), [100, 50]);
    assert_eq!(levels(96, Boundary::Periodic), [96, 48, 24, 12, 6]);
    assert_eq!(levels(9, Boundary::Open), [9]);
}

#[test]
fn grids_out_of_range_are_refused_before_allocation() {
    let gpu = common::gpu();
    let odd_periodic = FluidConfig {
        pressure_solver: PressureSolver::Multigrid,
        ..config(33, 32.0, Boundary::Periodic)
    };
    let cases = [
        (
            config(4, 32.0, Boundary::Open),
            "wind.fluid.resolution = 4 is out of range",
        ),
        (
            config(4096, 32.0, Boundary::Open),
            "wind.fluid.resolution = 4096 is out of range",
        ),
        (odd_periodic, "wind.fluid.resolution = 33 is odd"),
        (
            FluidConfig {
                multigrid_cycles: 0,
                ..config(32, 32.0, Boundary::Open)
            },
            "wind.fluid.multigrid_cycles = 0 is out of range",
        ),
    ];
    for (cfg, expected) in cases {
        match FluidSolver::new(&gpu, &cfg) {
            Err(Error::Invalid(msg)) => {
                println!("{msg}");
                assert!(msg.starts_with(expected), "{msg}");
            }
            Err(e) => panic!("{expected}: unexpected error {e}"),
            Ok(_) => panic!("{expected}: accepted"),
        }
    }
}
