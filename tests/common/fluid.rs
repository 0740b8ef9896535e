//! Helpers of the wind solver tests (`tests/fluid.rs`, `tests/twin_fluid_mac.rs`): small
//! configurations, seeded face fields, one GPU step.
#![allow(dead_code)]

use sward::gpu::queries::PassQueries;
use sward::gpu::Gpu;
use sward::scene::{Advection, Boundary, PressureSolver};
use sward::sim::fluid::{FluidConfig, FluidSolver};
use sward::sim::reference::fluid::periodic_faces;
use sward::sim::wind_layout::{ArrowGpu, FluidForces};

pub const BOUNDARIES: [Boundary; 3] = [Boundary::Closed, Boundary::Open, Boundary::Periodic];

/// A square grid of `size` metres centred on 0 with every effect off and the pressure solve
/// off (Jacobi, 0 iterations, cold); tests switch on what they exercise.
pub fn config(resolution: u32, size: f32, boundary: Boundary) -> FluidConfig {
    FluidConfig {
        resolution,
        cell_size: size / resolution as f32,
        origin: [-0.5 * size, -0.5 * size],
        pressure_solver: PressureSolver::Jacobi,
        pressure_iterations: 0,
        multigrid_cycles: 2,
        warm_start: false,
        vorticity: 0.0,
        dissipation: 0.0,
        viscosity: 0.0,
        diffusion_iterations: 0,
        boundary,
        advection: Advection::SemiLagrangian,
        follow: false,
        layers: 1,
        layer_height: 1.0,
        ground_drag: 0.0,
    }
}

pub fn gpu_step(gpu: &Gpu, solver: &mut FluidSolver, dt: f32, forces: &FluidForces) {
    solver.prepare(&gpu.queue, dt, forces);
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("sward.test.fluid"),
        });
    solver.encode(&mut encoder, PassQueries::NONE);
    gpu.queue.submit([encoder.finish()]);
    gpu.check_errors()
        .expect("the fluid step records without a GPU error");
}

pub fn arrow(from: [f32; 2], to: [f32; 2], strength: f32, radius: f32) -> ArrowGpu {
    ArrowGpu {
        segment: [from[0], from[1], to[0], to[1]],
        strength,
        radius,
        activation: 1.0,
        _pad: 0.0,
    }
}

/// SplitMix64 in [-1, 1): values that are the same on every run and platform.
pub fn random_values(count: usize, seed: u64) -> Vec<f32> {
    let mut state = seed;
    (0..count)
        .map(|_| {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^= z >> 31;
            (z >> 40) as f32 / (1u64 << 23) as f32 - 1.0
        })
        .collect()
}

/// Seeded random face velocities (u, v) of an n² grid in [-amplitude, amplitude) m/s, with
/// closed walls at 0 and periodic seams equal, as the solver keeps them.
pub fn random_faces(
    n: usize,
    boundary: Boundary,
    seed: u64,
    amplitude: f32,
) -> (Vec<f32>, Vec<f32>) {
    let half = n * (n + 1);
    let mut u: Vec<f32> = random_values(half, seed)
        .iter()
        .map(|x| x * amplitude)
        .collect();
    let mut v: Vec<f32> = random_values(half, seed ^ 0xABCD)
        .iter()
        .map(|x| x * amplitude)
        .collect();
    match boundary {
        Boundary::Periodic => periodic_faces(&mut u, &mut v, n),
        Boundary::Closed => {
            for j in 0..n {
                u[j * (n + 1)] = 0.0;
                u[j * (n + 1) + n] = 0.0;
            }
            for i in 0..n {
                v[i] = 0.0;
                v[n * n + i] = 0.0;
            }
        }
        Boundary::Open => {}
    }
    (u, v)
}

/// Largest |a − b| over two equally long lists.
pub fn max_diff(a: &[f32], b: &[f32]) -> f32 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f32::max)
}

/// Largest |x| of a list.
pub fn max_abs(a: &[f32]) -> f32 {
    a.iter().map(|x| x.abs()).fold(0.0, f32::max)
}

/// Flattens cell-centred vectors into components.
pub fn flat(v: &[[f32; 2]]) -> Vec<f32> {
    v.iter().flat_map(|x| *x).collect()
}

/// Seeded faces of a grid of `layers` layers: each layer's u, v as [`random_faces`], and w
/// on the planes between layers (the ground and the top 0, as the solver keeps them).
pub fn random_faces_3d(
    n: usize,
    layers: usize,
    boundary: Boundary,
    seed: u64,
    amplitude: f32,
) -> (Vec<f32>, Vec<f32>, Vec<f32>) {
    let (mut u, mut v) = (Vec::new(), Vec::new());
    for k in 0..layers {
        let (lu, lv) = random_faces(n, boundary, seed + 31 * k as u64, amplitude);
        u.extend(lu);
        v.extend(lv);
    }
    let plane = n * n;
    let mut w: Vec<f32> = random_values(plane * (layers + 1), seed ^ 0x5EED)
        .iter()
        .map(|x| x * amplitude * 0.5)
        .collect();
    w[..plane].fill(0.0);
    w[plane * layers..].fill(0.0);
    (u, v, w)
}
