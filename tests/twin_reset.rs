//! The safety net of the blade update: a blade whose new state is non-finite goes back to
//! its rest pose, on the GPU (`update.wgsl`) and in its CPU twin alike, and is counted.
//! Blades are corrupted before a step, or the scene pushes a non-finite force through
//! `SimParams`; both sides must reset the same blades, count the same, and end finite.

mod common;

use sward::commands::simulate_cpu_from;
use sward::render::target::COLOR_FORMAT;
use sward::render::Renderer;
use sward::scene::Scene;
use sward::session::Session;
use sward::sim::layout::{Blade, BladeState};

/// Max distance in metres between a reset blade's v1 / v2 and the rest pose the field
/// generator gave it. The reset re-validates the stored rest tip; the generator's pose is a
/// fixed point of the validation up to its 40-step bisection and f32 rounding (measured
/// 1.8e-7 m on lavapipe).
const REST_TOLERANCE: f32 = 2e-6;
/// Max |GPU − CPU| after the steps, as in `twin_update` (measured 1.2e-7).
const TWIN_TOLERANCE: f32 = 1e-6;
const DT: f32 = 1.0 / 30.0;

fn max_pose_diff(a: &Blade, b: &Blade) -> f32 {
    (0..3)
        .map(|k| {
            (a.v1_height[k] - b.v1_height[k])
                .abs()
                .max((a.v2_width[k] - b.v2_width[k]).abs())
        })
        .fold(0.0, f32::max)
}

fn all_finite(blades: &[Blade], states: &[BladeState]) -> bool {
    blades
        .iter()
        .zip(states)
        .all(|(b, s)| sward::sim::health::first_non_finite(b, s).is_none())
}

/// Blades in their rest pose (`rest`, within `REST_TOLERANCE`) with η = 0.
fn at_rest(blades: &[Blade], states: &[BladeState], rest: &[Blade]) -> Vec<usize> {
    (0..blades.len())
        .filter(|&i| {
            states[i].rest_eta[3] == 0.0 && max_pose_diff(&blades[i], &rest[i]) <= REST_TOLERANCE
        })
        .collect()
}

fn twin_diff(a: (&[Blade], &[BladeState]), b: (&[Blade], &[BladeState])) -> f32 {
    let mut d = 0.0f32;
    for i in 0..a.0.len() {
        d = d.max(max_pose_diff(&a.0[i], &b.0[i]));
        d = d.max((a.1[i].rest_eta[3] - b.1[i].rest_eta[3]).abs());
    }
    d
}

/// Runs `steps` GPU steps from `blades` / `states`; returns the blades, states and count.
fn gpu_run(
    gpu: &sward::gpu::Gpu,
    session: &Session,
    blades: &[Blade],
    states: &[BladeState],
    steps: u32,
) -> (Vec<Blade>, Vec<BladeState>, u32) {
    let mut r = Renderer::from_session(gpu, session, COLOR_FORMAT).expect("renderer");
    r.buffers
        .write(&gpu.queue, blades, states)
        .expect("write blades");
    for _ in 0..steps {
        r.step(gpu, DT);
    }
    gpu.check_errors().expect("no GPU error");
    let (b, s) = r.buffers.read(gpu).expect("read-back");
    (b, s, r.blades_reset_nonfinite(gpu).expect("reset count"))
}

#[test]
fn corrupted_blades_reset_to_their_rest_pose_on_gpu_and_cpu() {
    let gpu = common::gpu();
    // Gravity and wind on, no colliders: every sound blade leaves its rest pose at once.
    let scene = Scene {
        colliders: Vec::new(),
        ..Default::default()
    };
    let session = Session::new(scene, Some(1024), Some(&gpu)).expect("field");
    let rest = session.field.blades.clone();
    let n = rest.len();
    let (mut blades, mut states) = (rest.clone(), session.field.states.clone());
    let mut corrupted = Vec::new();
    for (k, i) in (3..n).step_by(37).enumerate() {
        match k % 6 {
            0 => blades[i].v2_width[0] = f32::NAN,
            1 => blades[i].v2_width[1] = f32::INFINITY,
            2 => states[i].rest_eta[3] = f32::NAN,
            3 => states[i].rest_eta[3] = f32::NEG_INFINITY,
            4 => states[i].rest_eta[3] = f32::INFINITY,
            _ => blades[i].v2_width[2] = f32::NEG_INFINITY,
        }
        corrupted.push(i);
    }
    assert!(corrupted.len() >= 20);

    // One step: exactly the corrupted blades are back at rest, on both sides.
    let (g_b, g_s, g_count) = gpu_run(&gpu, &session, &blades, &states, 1);
    let cpu = simulate_cpu_from(&session, blades.clone(), states.clone(), 1, DT);
    let g_reset = at_rest(&g_b, &g_s, &rest);
    let c_reset = at_rest(&cpu.blades, &cpu.states, &rest);
    let worst = corrupted
        .iter()
        .map(|&i| max_pose_diff(&g_b[i], &rest[i]))
        .fold(0.0, f32::max);
    println!(
        "reset: {} corrupted, GPU count {g_count}, CPU count {}, worst |reset - rest| on GPU {worst:.2e} m (tolerance {REST_TOLERANCE:.0e})",
        corrupted.len(),
        cpu.blades_reset_nonfinite
    );
    assert_eq!(g_reset, corrupted, "GPU: blades at rest after one step");
    assert_eq!(c_reset, corrupted, "CPU: blades at rest after one step");
    assert_eq!(g_count as usize, corrupted.len());
    assert_eq!(cpu.blades_reset_nonfinite, corrupted.len() as u64);
    assert!(all_finite(&g_b, &g_s) && all_finite(&cpu.blades, &cpu.states));
    let d = twin_diff((&g_b, &g_s), (&cpu.blades, &cpu.states));
    assert!(d < TWIN_TOLERANCE, "GPU vs CPU after one step: {d}");

    // Three steps: the reset blades move on like the others; nothing is reset again.
    let (g_b, g_s, g_count) = gpu_run(&gpu, &session, &blades, &states, 3);
    let cpu = simulate_cpu_from(&session, blades, states, 3, DT);
    assert_eq!(g_count as usize, corrupted.len());
    assert_eq!(cpu.blades_reset_nonfinite, corrupted.len() as u64);
    assert!(all_finite(&g_b, &g_s) && all_finite(&cpu.blades, &cpu.states));
    assert!(at_rest(&g_b, &g_s, &rest).is_empty());
    let d = twin_diff((&g_b, &g_s), (&cpu.blades, &cpu.states));
    println!("reset: max |gpu - cpu| after 3 steps = {d:.3e}");
    assert!(d < TWIN_TOLERANCE, "GPU vs CPU after three steps: {d}");
}

#[test]
fn a_non_finite_force_resets_every_blade_every_step() {
    let gpu = common::gpu();
    let mut scene = Scene {
        colliders: Vec::new(),
        ..Default::default()
    };
    // An infinite gravity makes the force NaN (0 · ∞ in the direction's zero components).
    scene.physics.gravity_acceleration = f32::INFINITY;
    let session = Session::new(scene, Some(512), Some(&gpu)).expect("field");
    let n = session.field.blades.len();
    let rest = session.field.blades.clone();
    let steps = 2;
    let (g_b, g_s, g_count) = gpu_run(
        &gpu,
        &session,
        &session.field.blades,
        &session.field.states,
        steps,
    );
    let cpu = simulate_cpu_from(
        &session,
        session.field.blades.clone(),
        session.field.states.clone(),
        steps,
        DT,
    );
    println!(
        "non-finite force: {n} blades, GPU count {g_count}, CPU count {}",
        cpu.blades_reset_nonfinite
    );
    assert_eq!(g_count as usize, n * steps as usize);
    assert_eq!(cpu.blades_reset_nonfinite, (n * steps as usize) as u64);
    assert!(all_finite(&g_b, &g_s) && all_finite(&cpu.blades, &cpu.states));
    let all: Vec<usize> = (0..n).collect();
    assert_eq!(at_rest(&g_b, &g_s, &rest), all);
    assert_eq!(at_rest(&cpu.blades, &cpu.states, &rest), all);
}

#[test]
fn a_blade_whose_rest_tip_is_lost_stands_straight_up() {
    let gpu = common::gpu();
    let scene = Scene {
        colliders: Vec::new(),
        ..Default::default()
    };
    let session = Session::new(scene, Some(256), Some(&gpu)).expect("field");
    let (mut blades, mut states) = (session.field.blades.clone(), session.field.states.clone());
    let i = 5;
    blades[i].v2_width[0] = f32::NAN;
    states[i].rest_eta[0] = f32::NAN;
    let (g_b, g_s, g_count) = gpu_run(&gpu, &session, &blades, &states, 1);
    let cpu = simulate_cpu_from(&session, blades.clone(), states.clone(), 1, DT);
    assert_eq!(g_count, 1);
    assert_eq!(cpu.blades_reset_nonfinite, 1);
    let b = &blades[i];
    let h = b.v1_height[3];
    for k in 0..3 {
        let top = b.v0_dir[k] + b.up_stiffness[k] * h;
        for got in [&g_b[i], &cpu.blades[i]] {
            assert!((got.v1_height[k] - top).abs() < REST_TOLERANCE, "{got:?}");
            assert!((got.v2_width[k] - top).abs() < REST_TOLERANCE, "{got:?}");
        }
    }
    assert_eq!(g_s[i].rest_eta[3], 0.0);
    assert_eq!(cpu.states[i].rest_eta[3], 0.0);
}
