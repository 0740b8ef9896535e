//! The `sward` command line: without a subcommand it opens the window (fly over the meadow,
//! edit the wind); `render` draws headless frames to PNG, `simulate` dumps blade states
//! as JSON and `bench` prints the paper's timing table.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use sward::app::AppOptions;
use sward::bench::{bench, BenchOptions};
use sward::commands::{render, simulate, RenderOptions, SimulateOptions};
use sward::gpu::AdapterChoice;

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
    /// Where Save writes, when not the --scene file.
    #[arg(long)]
    save_to: Option<PathBuf>,
    /// Window size, WIDTHxHEIGHT in physical pixels.
    #[arg(long, default_value = "1280x720", value_parser = parse_size)]
    size: (u32, u32),
    /// Present without waiting for the display's refresh.
    #[arg(long)]
    no_vsync: bool,
    /// Run N frames, then exit with status 0.
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..=10_000_000))]
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
    /// Hold this frame time (ms) by adapting distance culling; default 90 ms on a CPU
    /// adapter, off on a GPU.
    #[arg(long, value_parser = parse_frame_ms)]
    target_frame_ms: Option<f32>,
    /// Fixed simulation step per frame in seconds (default: the wall clock; 1/30 when
    /// replaying, so that a replay is repeatable).
    #[arg(long, value_parser = parse_dt)]
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
        /// Image size, WIDTHxHEIGHT.
        #[arg(long, default_value = "1280x720", value_parser = parse_size)]
        size: (u32, u32),
        /// Frames to simulate and render.
        #[arg(long, default_value_t = 90)]
        frames: u32,
        /// Time step per frame in seconds.
        #[arg(long, default_value_t = 1.0 / 30.0)]
        dt: f32,
        /// Output PNG.
        #[arg(long, default_value = "meadow.png")]
        out: PathBuf,
        /// Print per-pass GPU times (timestamp queries) and cull counters.
        #[arg(long)]
        timings: bool,
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
        /// Update steps.
        #[arg(long, default_value_t = 60)]
        steps: u32,
        /// Time step in seconds.
        #[arg(long, default_value_t = 1.0 / 60.0)]
        dt: f32,
        /// Output JSON: {"initial": [...], "final": [...]}.
        #[arg(long)]
        dump: PathBuf,
        /// Run the CPU twin instead of the GPU kernel.
        #[arg(long)]
        cpu: bool,
        /// Replace the field with about N blades on a flat square.
        #[arg(long)]
        blades: Option<usize>,
        /// Also write the wind grid after the last step as JSON.
        #[arg(long)]
        dump_wind: Option<PathBuf>,
        #[command(flatten)]
        wind: WindArgs,
    },
    /// Time the paper's three configurations (all features, collisions off, culling off)
    /// on the same frames and print its table: FPS, frame time, blades drawn / culled per
    /// test, GPU ms of physics / visibility / rendering, colliders, memory.
    Bench {
        /// Scene file (RON); the built-in meadow when absent.
        #[arg(long)]
        scene: Option<PathBuf>,
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
        /// difference (worst channel ×4, red) as PNGs in this existing folder.
        #[arg(long)]
        images: Option<PathBuf>,
    },
}

/// Overrides of the scene's wind solver.
#[derive(Args, Clone)]
struct WindArgs {
    /// Jacobi pressure iterations of the wind solver (overrides the scene).
    #[arg(long)]
    pressure_iterations: Option<u32>,
    /// Wind grid resolution per side (overrides the scene).
    #[arg(long)]
    wind_resolution: Option<u32>,
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

fn main() -> ExitCode {
    sward::runtime_env::ensure_runtime_dir();
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let cli = Cli::parse();
    let adapter: AdapterChoice = cli.adapter.adapter.parse().expect("infallible");
    let result = match cli.command {
        None => {
            let w = cli.window;
            let fixed_dt = w.dt.or(w.replay.as_ref().map(|_| 1.0 / 30.0));
            sward::app::run(AppOptions {
                save_path: w.save_to.or_else(|| w.scene.clone()),
                scene: w.scene,
                adapter,
                size: w.size,
                vsync: !w.no_vsync,
                exit_after_frames: w.exit_after_frames,
                screenshot: w.screenshot,
                replay: w.replay,
                record: w.record,
                target_frame_ms: w.target_frame_ms,
                fixed_dt,
            })
        }
        Some(Command::Render {
            scene,
            size,
            frames,
            dt,
            out,
            timings,
            wind_overlay,
            wind,
        }) => render(&RenderOptions {
            scene,
            size,
            frames,
            dt,
            out,
            timings,
            adapter,
            wind_overlay,
            pressure_iterations: wind.pressure_iterations,
            wind_resolution: wind.wind_resolution,
        }),
        Some(Command::Simulate {
            scene,
            steps,
            dt,
            dump,
            cpu,
            blades,
            dump_wind,
            wind,
        }) => simulate(&SimulateOptions {
            scene,
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
        // The values come in as text (negative numbers too) and are checked by the
        // library, so that a bad value ends like every other error: the flag, the allowed
        // range, exit status 1.
        Some(Command::Bench {
            scene,
            frames,
            size,
            warmup,
            sweep,
            json,
            images,
        }) => BenchOptions::parse(
            scene,
            &frames,
            &size,
            &warmup,
            sweep.as_deref(),
            json,
            adapter,
        )
        .and_then(|o| o.with_images(images))
        .and_then(|o| bench(&o)),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
