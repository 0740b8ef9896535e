//! `sward bench --pressure-solvers jacobi,multigrid`: the wind solver alone, once per
//! pressure solver, in one process, on the same frames: the scene's `wind.fluid` grid
//! driven by the scene's forces (AGC guides, global wind, downwash, colliders) at the same
//! times with the same Δt = 1/30 s. Each solver gets a fresh [`FluidSolver`] and only
//! `wind.fluid.pressure_solver` differs between the runs.
//!
//! Per solver it reports the GPU milliseconds of the pressure pass per frame (timestamp
//! queries, [`FluidSolver::read_pass_ms`]) and the RMS divergence of the faces right after
//! the projection (over the fluid cells, on the solver's own stencil) beside the RMS
//! divergence that entered the solve, so the ratio says how much of it the solve removed.
//! Means over the measured frames, after `--warmup` frames.

use serde::Serialize;

use super::{utc_now, BenchOptions, BENCH_DT};
use sward::error::{Error, Result};
use sward::field::HeightField;
use sward::gpu::queries::PassQueries;
use sward::gpu::Gpu;
use sward::scene::{PressureSolver, Scene};
use sward::sim::agc;
use sward::sim::fluid::{FluidConfig, FluidSolver, FLUID_PASSES, PRESSURE_PASS};

/// `--pressure-solvers jacobi,multigrid`: solver names, each at most once.
pub fn parse_pressure_solvers(text: &str) -> Result<Vec<PressureSolver>> {
    let allowed = "allowed: jacobi, multigrid, comma-separated (e.g. --pressure-solvers \
                   jacobi,multigrid)";
    let mut out = Vec::new();
    for (i, item) in text.split(',').enumerate() {
        let solver = match item.trim().to_ascii_lowercase().as_str() {
            "jacobi" => PressureSolver::Jacobi,
            "multigrid" => PressureSolver::Multigrid,
            _ => {
                return Err(Error::Invalid(format!(
                    "--pressure-solvers entry {} ({:?}) is not a solver: {allowed}",
                    i + 1,
                    item.trim()
                )))
            }
        };
        if out.contains(&solver) {
            return Err(Error::Invalid(format!(
                "--pressure-solvers names {} twice: {allowed}",
                item.trim()
            )));
        }
        out.push(solver);
    }
    Ok(out)
}

/// One solver's figures.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SolverReport {
    /// `jacobi` or `multigrid`.
    pub name: String,
    /// What one solve runs: "40 iterations" or "2 V-cycles".
    pub work: String,
    /// Mean GPU milliseconds of the pressure pass per frame; `None` without timestamps.
    pub ms: Option<f64>,
    /// Mean GPU milliseconds of the whole wind step per frame.
    pub step_ms: Option<f64>,
    /// Mean wall-clock milliseconds of the step, submit to the end of the GPU's work (the
    /// divergence read-back is left out).
    pub wall_ms: f64,
    /// Mean RMS divergence (1/s) of the faces after the projection.
    pub rms_divergence: f64,
    /// Mean RMS divergence (1/s) that entered the pressure solve.
    pub rms_divergence_before: f64,
    /// `rms_divergence_before / rms_divergence`: how many times the solve reduced it.
    pub reduction: f64,
}

/// Everything `sward bench --pressure-solvers` measured.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PressureBenchReport {
    pub adapter: String,
    pub date: String,
    pub scene: String,
    pub resolution: u32,
    pub cell_size: f32,
    pub frames: u32,
    pub warmup: u32,
    pub dt: f32,
    pub timestamps: bool,
    pub pressure_solvers: Vec<SolverReport>,
}

/// Checks the flags that do not go with `--pressure-solvers`.
pub fn check_pressure_options(o: &BenchOptions) -> Result<()> {
    if o.flight || !o.sweep.is_empty() || o.images.is_some() || o.trace.is_some() {
        return Err(Error::Invalid(
            "--pressure-solvers times the wind solver alone: it does not go with --flight, \
             --sweep, --images or --trace"
                .into(),
        ));
    }
    Ok(())
}

fn name(solver: PressureSolver) -> &'static str {
    match solver {
        PressureSolver::Jacobi => "jacobi",
        PressureSolver::Multigrid => "multigrid",
    }
}

fn measure(
    gpu: &Gpu,
    scene: &Scene,
    terrain: &HeightField,
    solver: PressureSolver,
    o: &BenchOptions,
) -> Result<SolverReport> {
    let mut fluid = scene.wind.fluid.clone();
    fluid.pressure_solver = solver;
    let config = FluidConfig::from_scene(&fluid, scene.terrain.size);
    let work = match solver {
        PressureSolver::Jacobi => format!("{} iterations", config.jacobi_iterations()),
        PressureSolver::Multigrid => format!("{} V-cycles", config.v_cycles()),
    };
    eprintln!(
        "bench: pressure solver {} ({work}), {}² grid ({} warm-up + {} frames)",
        name(solver),
        config.resolution,
        o.warmup,
        o.frames
    );
    let mut wind = FluidSolver::new(gpu, &config)?;
    let (mut ms, mut step_ms, mut after, mut before) = (0.0, 0.0, 0.0, 0.0);
    let mut timed = true;
    let mut wall = 0.0;
    for frame in 0..o.warmup + o.frames {
        let start = std::time::Instant::now();
        let time = (frame + 1) as f32 * BENCH_DT;
        wind.prepare(
            &gpu.queue,
            BENCH_DT,
            &agc::fluid_forces(scene, terrain, time),
        );
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("sward.bench.pressure"),
            });
        wind.encode(&mut encoder, PassQueries::NONE);
        gpu.queue.submit([encoder.finish()]);
        sward::gpu::wait_idle(&gpu.device)?;
        let elapsed = start.elapsed().as_secs_f64() * 1000.0;
        gpu.check_errors()?;
        if frame < o.warmup {
            continue;
        }
        wall += elapsed;
        match wind.read_pass_ms(gpu)? {
            Some(passes) => {
                debug_assert_eq!(passes[PRESSURE_PASS].0, FLUID_PASSES[PRESSURE_PASS]);
                ms += passes[PRESSURE_PASS].1;
                step_ms += passes.iter().map(|(_, t)| t).sum::<f64>();
            }
            None => timed = false,
        }
        let state = wind.read_state(gpu)?;
        after += state.rms_divergence();
        before += state.rms_divergence_before();
    }
    let n = f64::from(o.frames);
    let (after, before) = (after / n, before / n);
    if before == 0.0 {
        eprintln!(
            "bench: the scene's forces left the air still: no divergence to remove (add \
             wind.guides, wind.global or wind.downwash)"
        );
    }
    Ok(SolverReport {
        name: name(solver).into(),
        work,
        ms: timed.then_some(ms / n),
        step_ms: timed.then_some(step_ms / n),
        wall_ms: wall / n,
        rms_divergence: after,
        rms_divergence_before: before,
        reduction: if after > 0.0 { before / after } else { 0.0 },
    })
}

/// Runs every solver of `o.pressure_solvers` on the same frames.
pub fn run_pressure_bench(o: &BenchOptions) -> Result<PressureBenchReport> {
    check_pressure_options(o)?;
    let date = utc_now();
    let super::Start {
        scene,
        scene_name,
        gpu,
        ..
    } = super::start(o, [])?;
    let terrain = HeightField::from_scene(&scene.terrain)?;
    let config = FluidConfig::from_scene(&scene.wind.fluid, scene.terrain.size);
    let pressure_solvers = o
        .pressure_solvers
        .iter()
        .map(|&s| measure(&gpu, &scene, &terrain, s, o))
        .collect::<Result<Vec<_>>>()?;
    Ok(PressureBenchReport {
        adapter: gpu.describe(),
        date,
        scene: scene_name,
        resolution: config.resolution,
        cell_size: config.cell_size,
        frames: o.frames,
        warmup: o.warmup,
        dt: BENCH_DT,
        timestamps: gpu.timestamps,
        pressure_solvers,
    })
}

/// The report as a table.
pub fn format_pressure(r: &PressureBenchReport) -> String {
    let ms = |m: Option<f64>| m.map_or("n/a".to_string(), |m| format!("{m:.2}"));
    let mut out = format!(
        "sward bench --pressure-solvers: {} ({}² wind grid, h = {} m), {} frames after {} \
         warm-up, Δt = {:.4} s\nadapter: {} — {}\n\n",
        r.scene, r.resolution, r.cell_size, r.frames, r.warmup, r.dt, r.adapter, r.date
    );
    out += &format!(
        "{:<10} {:<16} {:>12} {:>12} {:>12} {:>14} {:>14} {:>10}\n",
        "solver",
        "per solve",
        "pressure ms",
        "step ms",
        "wall ms",
        "rms div before",
        "rms div after",
        "reduction"
    );
    for s in &r.pressure_solvers {
        out += &format!(
            "{:<10} {:<16} {:>12} {:>12} {:>12.2} {:>14.3e} {:>14.3e} {:>9.1}x\n",
            s.name,
            s.work,
            ms(s.ms),
            ms(s.step_ms),
            s.wall_ms,
            s.rms_divergence_before,
            s.rms_divergence,
            s.reduction
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solver_lists_are_checked() {
        assert_eq!(
            parse_pressure_solvers("jacobi, Multigrid").unwrap(),
            [PressureSolver::Jacobi, PressureSolver::Multigrid]
        );
        let e = parse_pressure_solvers("jacobi,sor")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("--pressure-solvers entry 2 (\"sor\") is not a solver"),
            "{e}"
        );
        let e = parse_pressure_solvers("multigrid,multigrid")
            .unwrap_err()
            .to_string();
        assert!(e.contains("names multigrid twice"), "{e}");
    }
}
