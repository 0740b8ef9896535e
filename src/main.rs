//! The `sward` command line: without a subcommand it opens the window (fly over the meadow,
//! edit the wind); `render` draws headless frames to PNG, `simulate` dumps blade states
//! as JSON and `bench` prints the paper's timing table.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use sward::commands::{render, simulate, RenderOptions, SimulateOptions, MAX_FRAMES};
use sward::gpu::AdapterChoice;
use sward_app::app::AppOptions;
use sward_app::bench::{bench, BenchOptions};

#[cfg(test)]
mod doc_commands;

#[derive(Parser)]
#[command(
    name = "sward",
    version,
    args_conflicts_with_subcommands = true,
    about = "Real-time grass: every blade simulated on the GPU"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    #[command(flatten)]
    adapter: AdapterArg,
    #[command(flatten)]
    window: WindowArgs,
}

/// Options of the window (no subcommand).
#[derive(Args, Clone)]
struct WindowArgs {
    /// Scene file (RON) to open; the built-in meadow when absent or when it fails to load
    /// (the error is shown in the panel). Save writes back to it.
    #[arg(long)]
    scene: Option<PathBuf>,
    #[command(flatten)]
    overrides: Overrides,
    /// Where Save writes, when not the --scene file.
    #[arg(long)]
    save_to: Option<PathBuf>,
    /// Window size, WIDTHxHEIGHT in physical pixels.
    #[arg(long, default_value = "1280x720", value_parser = parse_size, allow_hyphen_values = true)]
    size: (u32, u32),
    /// Present without waiting for the display's refresh.
    #[arg(long)]
    no_vsync: bool,
    /// Run N frames (1..=10000000), then exit: status 0, or 1 if anything failed (a Save
    /// included); --screenshot and --record are written only when the run succeeded.
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..=10_000_000), allow_hyphen_values = true)]
    exit_after_frames: Option<u64>,
    /// With --exit-after-frames: save the last frame (panel included) as PNG.
    #[arg(long, requires = "exit_after_frames")]
    screenshot: Option<PathBuf>,
    /// Play an input script (RON: frame-numbered clicks, drags, keys) instead of live input.
    #[arg(long)]
    replay: Option<PathBuf>,
    /// Record the session's input into a script that --replay plays back.
    #[arg(long)]
    record: Option<PathBuf>,
    /// Write every frame's GPU pass times as a Chrome trace (JSON; Perfetto opens it) when
    /// the window closes.
    #[arg(long, value_name = "FILE")]
    trace: Option<PathBuf>,
    /// Count every frame's work (shader invocations per pass, shown in the Stats section;
    /// adds a depth-only draw of the grass to each frame).
    #[arg(long)]
    count_work: bool,
    /// Hold this frame time (ms) by adapting distance culling; default 90 ms on a CPU
    /// adapter, off on a GPU.
    #[arg(long, value_parser = parse_frame_ms, allow_hyphen_values = true)]
    target_frame_ms: Option<f32>,
    /// Fixed simulation step per frame in seconds (default: the wall clock; 1/30 when
    /// replaying, so that a replay is repeatable).
    #[arg(long, value_parser = parse_dt, allow_hyphen_values = true)]
    dt: Option<f32>,
}

fn parse_frame_ms(s: &str) -> Result<f32, String> {
    let v: f32 = s.parse().map_err(|_| format!("{s:?} is not a number"))?;
    if !(1.0..=10_000.0).contains(&v) {
        return Err(format!("{v} is out of range: allowed 1..=10000 ms"));
    }
    Ok(v)
}

fn parse_dt(s: &str) -> Result<f32, String> {
    let v: f32 = s.parse().map_err(|_| format!("{s:?} is not a number"))?;
    if !(v > 0.0 && v <= 1.0) {
        return Err(format!("{v} is out of range: allowed 0 < dt <= 1 s"));
    }
    Ok(v)
}

#[derive(Args, Clone)]
struct AdapterArg {
    /// GPU adapter: auto, software (a CPU adapter such as lavapipe) or part of a name.
    #[arg(long, global = true, env = "SWARD_ADAPTER", default_value = "auto")]
    adapter: String,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate N steps, render every frame, save the last one as PNG.
    Render {
        /// Scene file (RON); the built-in meadow when absent.
        #[arg(long)]
        scene: Option<PathBuf>,
        #[command(flatten)]
        overrides: Overrides,
        /// Image size, WIDTHxHEIGHT.
        #[arg(long, default_value = "1280x720", value_parser = parse_size, allow_hyphen_values = true)]
        size: (u32, u32),
        /// Frames to simulate and render (1..=100000).
        #[arg(long, default_value_t = 90, value_parser = count, allow_hyphen_values = true)]
        frames: u32,
        /// Time step per frame in seconds (0 < dt <= 1).
        #[arg(long, default_value_t = 1.0 / 30.0, allow_hyphen_values = true)]
        dt: f32,
        /// Output PNG.
        #[arg(long, default_value = "meadow.png")]
        out: PathBuf,
        /// Print per-pass GPU times (timestamp queries) and cull counters.
        #[arg(long)]
        timings: bool,
        /// Write every frame's GPU pass times as a Chrome trace (JSON; Perfetto opens it).
        #[arg(long, value_name = "FILE")]
        trace: Option<PathBuf>,
        /// Draw the wind velocity (colour and arrows) and the AGC guides over the frame.
        #[arg(long)]
        wind_overlay: bool,
        #[command(flatten)]
        wind: WindArgs,
    },
    /// Run the blade update and dump the initial and final blades as JSON.
    Simulate {
        /// Scene file (RON); the built-in meadow when absent.
        #[arg(long)]
        scene: Option<PathBuf>,
        #[command(flatten)]
        overrides: Overrides,
        /// Update steps (1..=100000).
        #[arg(long, default_value_t = 60, value_parser = count, allow_hyphen_values = true)]
        steps: u32,
        /// Time step in seconds (0 < dt <= 1).
        #[arg(long, default_value_t = 1.0 / 60.0, allow_hyphen_values = true)]
        dt: f32,
        /// Output JSON: {"initial": [...], "final": [...]}.
        #[arg(long)]
        dump: PathBuf,
        /// Run the CPU twin instead of the GPU kernel.
        #[arg(long)]
        cpu: bool,
        /// Replace the field with about N blades on a flat square (1..=50000000).
        #[arg(long, allow_hyphen_values = true)]
        blades: Option<usize>,
        /// Also write the wind grid after the last step as JSON.
        #[arg(long)]
        dump_wind: Option<PathBuf>,
        #[command(flatten)]
        wind: WindArgs,
    },
    /// Write sward's walking figure (a rigged figure of boxes, nine joints, a looped
    /// one-second "walk") as one glTF 2.0 file with its buffer embedded.
    Figure {
        /// Output glTF file.
        #[arg(long)]
        out: PathBuf,
    },
    /// Time the paper's three configurations (all features, collisions off, culling off)
    /// on the same frames and print its table: FPS, frame time, blades drawn / culled per
    /// test, GPU ms of physics / visibility / rendering, colliders, memory.
    Bench {
        /// Scene file (RON); the built-in meadow when absent.
        #[arg(long)]
        scene: Option<PathBuf>,
        #[command(flatten)]
        overrides: Overrides,
        /// Frames measured per configuration, after the warm-up (1..=100000).
        #[arg(long, default_value = "60", allow_hyphen_values = true)]
        frames: String,
        /// Image size, WIDTHxHEIGHT (1..=16384 per side).
        #[arg(long, default_value = "1280x720", allow_hyphen_values = true)]
        size: String,
        /// Frames run first and left out of the statistics (0..=10000).
        #[arg(long, default_value = "5", allow_hyphen_values = true)]
        warmup: String,
        /// Also time the all-features configuration at these blade counts, increasing
        /// (e.g. 100000,200000,400000): the scene's density is scaled to each.
        #[arg(long, allow_hyphen_values = true)]
        sweep: Option<String>,
        /// Print one JSON object instead of the table.
        #[arg(long)]
        json: bool,
        /// Save the last all-features frame, the last culling-off frame and their
        /// difference (worst channel ×4, red) as PNGs in this existing folder; with
        /// --flight, every flight frame as frame_0000.png, frame_0001.png, …
        #[arg(long)]
        images: Option<PathBuf>,
        /// Fly the camera along a straight line (from the scene's eye, along its view, at
        /// 4 m/s and a constant height above the terrain) for --frames frames and report
        /// GPU and wall frame times (p50, p95), blades drawn, memory and the pop ratio
        /// (largest over median frame-to-frame difference).
        #[arg(long)]
        flight: bool,
        /// Write every measured frame's GPU pass times as a Chrome trace (JSON; Perfetto
        /// opens it), one track per configuration.
        #[arg(long, value_name = "FILE")]
        trace: Option<PathBuf>,
        /// Time the wind solver alone once per pressure solver (jacobi, multigrid;
        /// comma-separated) on the same frames: GPU ms of the pressure solve and RMS
        /// divergence before and after the projection.
        #[arg(long, value_name = "SOLVERS")]
        pressure_solvers: Option<String>,
        /// Time the collisions against N scattered spheres (increasing counts up to 16384,
        /// comma-separated, e.g. 100,1000,10000) as flat lists and through the colliders'
        /// hierarchy, exact and at the scene's precision, on the same frames: GPU ms of the
        /// update and the broad phase, ns per stepped blade, and the difference in the
        /// blades' final state.
        #[arg(long, value_name = "COUNTS", allow_hyphen_values = true)]
        colliders: Option<String>,
        /// Time the three blade models (Jahrmann, Verlet, Cwd: `physics.model`) on the
        /// same scene and frames: GPU ms and ns per blade of the physics and of the grass
        /// draw, and GPU bytes per blade.
        #[arg(long)]
        models: bool,
        /// Time what the light costs on the same scene and frames: the frame without sun
        /// shadows, with shadows but no grass casters, with the scene's shadows, and with
        /// no blade shading terms; GPU ms of the frame, the shadow cascades, the colour
        /// passes and the tone mapping, and each frame over the frame without shadows.
        #[arg(long)]
        light: bool,
        /// Compare the far levels with what they replace on the same scene and frames, in
        /// bands of 8 rows (mean luminance, 8x8 block contrast): the scene against blades
        /// out to 1.75 times its blade radius (at least 50 m) with no distance thinning, and
        /// against its billboards pushed out to the horizon; every band and the worst.
        #[arg(long)]
        far_field: bool,
        /// Compare no anti-aliasing, 4x MSAA and TAA on the same scene and frames: GPU and
        /// wall ms per frame, the work counted, and the flicker with the camera still and
        /// the wind on (mean frame-to-frame difference of the far field and of the frame).
        #[arg(long)]
        antialiasing: bool,
    },
}

/// Changes to the scene from the command line, validated like the file's own values.
#[derive(Args, Clone)]
struct Overrides {
    /// Set one scene field: PATH=VALUE, PATH as in the scene file (`field.density`,
    /// `wind.guides[0].strength`), VALUE in RON (`40`, `false`, `(1.0, 2.0, 3.0)`, `Flat`).
    /// Repeatable; checked with the same ranges and messages as the scene file.
    #[arg(long = "set", value_name = "PATH=VALUE", allow_hyphen_values = true)]
    sets: Vec<String>,
    /// Camera position X,Y,Z in metres (sets camera.eye).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true, value_parser = parse_xyz)]
    eye: Option<[f32; 3]>,
    /// Point the camera looks at, X,Y,Z in metres (sets camera.target).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true, value_parser = parse_xyz)]
    target: Option<[f32; 3]>,
}

impl Overrides {
    /// The `--set` list, with `--eye` / `--target` last as `camera.eye=(…)` /
    /// `camera.target=(…)`, so that they win over a `--set` of the same field.
    fn sets(&self) -> Vec<String> {
        let mut sets = self.sets.clone();
        for (field, v) in [("camera.eye", self.eye), ("camera.target", self.target)] {
            if let Some([x, y, z]) = v {
                sets.push(format!("{field}=({x:?}, {y:?}, {z:?})"));
            }
        }
        sets
    }

    /// An error about the camera set from `--eye` / `--target` names that flag, not the
    /// `--set` it became.
    fn explain(&self, e: sward::Error) -> sward::Error {
        if let sward::Error::Set { arg, message } = &e {
            for (flag, field, v) in [
                ("--eye", "camera.eye=", self.eye),
                ("--target", "camera.target=", self.target),
            ] {
                if let (Some([x, y, z]), true) = (v, arg.starts_with(field)) {
                    if !self.sets.contains(arg) {
                        return sward::Error::Invalid(format!("{flag} {x},{y},{z}: {message}"));
                    }
                }
            }
        }
        e
    }
}

/// `X,Y,Z`: three numbers (the scene's validation checks their range).
fn parse_xyz(s: &str) -> Result<[f32; 3], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let bad = || format!("{s:?} is not X,Y,Z: three numbers in metres, e.g. 0,2,10");
    if parts.len() != 3 {
        return Err(bad());
    }
    let mut v = [0.0f32; 3];
    for (slot, part) in v.iter_mut().zip(parts) {
        *slot = part.parse().map_err(|_| bad())?;
    }
    Ok(v)
}

/// Overrides of the scene's wind solver.
#[derive(Args, Clone)]
struct WindArgs {
    /// Jacobi pressure iterations of the wind solver, 0..=1000 (overrides the scene).
    #[arg(long, allow_hyphen_values = true)]
    pressure_iterations: Option<u32>,
    /// Wind grid resolution per side, 8..=2048 cells (overrides the scene).
    #[arg(long, allow_hyphen_values = true)]
    wind_resolution: Option<u32>,
}

/// A frame or step count: `1..=MAX_FRAMES`, with the range in the error.
fn count(s: &str) -> Result<u32, String> {
    let range = format!("allowed 1..={MAX_FRAMES}");
    let v: u64 = s
        .trim()
        .parse()
        .map_err(|_| format!("{s:?} is not a whole number: {range}"))?;
    if !(1..=u64::from(MAX_FRAMES)).contains(&v) {
        return Err(format!("{v} is out of range: {range}"));
    }
    Ok(v as u32)
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("{s:?} is not WIDTHxHEIGHT (e.g. 1280x720)"))?;
    let w: u32 = w
        .trim()
        .parse()
        .map_err(|_| format!("width {w:?} is not a number"))?;
    let h: u32 = h
        .trim()
        .parse()
        .map_err(|_| format!("height {h:?} is not a number"))?;
    if w == 0 || h == 0 || w > 16384 || h > 16384 {
        return Err(format!(
            "{w}x{h} is out of range: allowed 1..=16384 per side"
        ));
    }
    Ok((w, h))
}

/// `sward figure --out FILE`: the walker through a temporary file renamed into place.
fn write_figure(out: &std::path::Path) -> sward::Result<()> {
    let mut outputs = sward::output::Outputs::new();
    outputs.add("--out", out)?;
    outputs.write(out, sward::mesh::figure::walker_gltf().as_bytes())?;
    outputs.commit()?;
    println!("wrote {}", out.display());
    Ok(())
}

fn main() -> ExitCode {
    sward_app::runtime_env::ensure_runtime_dir();
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let cli = Cli::parse();
    let adapter: AdapterChoice = cli.adapter.adapter.parse().expect("infallible");
    let mut overrides = None;
    let result = match cli.command {
        None => {
            let w = cli.window;
            let sets = w.overrides.sets();
            overrides = Some(w.overrides);
            let fixed_dt = w.dt.or(w.replay.as_ref().map(|_| 1.0 / 30.0));
            sward_app::app::run(AppOptions {
                save_path: w.save_to.or_else(|| w.scene.clone()),
                scene: w.scene,
                sets,
                adapter,
                size: w.size,
                vsync: !w.no_vsync,
                exit_after_frames: w.exit_after_frames,
                screenshot: w.screenshot,
                replay: w.replay,
                record: w.record,
                trace: w.trace,
                target_frame_ms: w.target_frame_ms,
                fixed_dt,
                count_work: w.count_work,
            })
        }
        Some(Command::Render {
            scene,
            overrides: o,
            size,
            frames,
            dt,
            out,
            timings,
            trace,
            wind_overlay,
            wind,
        }) => render(&RenderOptions {
            scene,
            sets: overrides.insert(o).sets(),
            size,
            frames,
            dt,
            out,
            timings,
            trace,
            adapter,
            wind_overlay,
            pressure_iterations: wind.pressure_iterations,
            wind_resolution: wind.wind_resolution,
        }),
        Some(Command::Simulate {
            scene,
            overrides: o,
            steps,
            dt,
            dump,
            cpu,
            blades,
            dump_wind,
            wind,
        }) => simulate(&SimulateOptions {
            scene,
            sets: overrides.insert(o).sets(),
            steps,
            dt,
            dump,
            cpu,
            blades,
            adapter,
            dump_wind,
            pressure_iterations: wind.pressure_iterations,
            wind_resolution: wind.wind_resolution,
        }),
        Some(Command::Figure { out }) => write_figure(&out),
        // The values come in as text (negative numbers too) and are checked by the
        // library, so that a bad value ends like every other error: the flag, the allowed
        // range, exit status 1.
        Some(Command::Bench {
            scene,
            overrides: o,
            frames,
            size,
            warmup,
            sweep,
            json,
            images,
            flight,
            trace,
            pressure_solvers,
            colliders,
            models,
            light,
            far_field,
            antialiasing,
        }) => BenchOptions::parse(
            scene,
            &frames,
            &size,
            &warmup,
            sweep.as_deref(),
            json,
            adapter,
        )
        .map(|mut b| {
            b.sets = overrides.insert(o).sets();
            b.flight = flight;
            b.trace = trace;
            b.models = models;
            b.light = light;
            b.far_field = far_field;
            b.antialiasing = antialiasing;
            b
        })
        .and_then(|mut b| {
            if let Some(text) = &pressure_solvers {
                b.pressure_solvers = sward_app::bench::pressure::parse_pressure_solvers(text)?;
            }
            if let Some(text) = &colliders {
                b.colliders = sward_app::bench::colliders::parse_collider_counts(text)?;
            }
            Ok(b)
        })
        .and_then(|o| o.with_images(images))
        .and_then(|o| bench(&o)),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            let e = match &overrides {
                Some(o) => o.explain(e),
                None => e,
            };
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
