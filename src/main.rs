//! The `sward` command line: `render` (headless frames to PNG) and `simulate` (blade states
//! to JSON). Without a subcommand it renders the default meadow to `meadow.png` (the window
//! comes in a later release).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use sward::commands::{render, simulate, RenderOptions, SimulateOptions};
use sward::gpu::AdapterChoice;

#[derive(Parser)]
#[command(
    name = "sward",
    version,
    about = "Real-time grass: every blade simulated on the GPU"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    #[command(flatten)]
    adapter: AdapterArg,
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
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let cli = Cli::parse();
    let adapter: AdapterChoice = cli.adapter.adapter.parse().expect("infallible");
    let result = match cli.command {
        None => render(&RenderOptions::default_meadow(adapter)),
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
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
