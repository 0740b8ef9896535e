//! The interactive window: winit 0.30 + wgpu surface + egui panel, fly camera, AGC wind
//! editor, thrown balls, replayable input. Everything here that is logic rather than
//! windowing (camera, picking, editing, balls, replay scripts, frame budget) lives in its own
//! module and is unit-tested without a window.

pub mod adaptive;
pub mod balls;
pub mod camera;
pub mod editor;
pub mod input;
pub mod panel;
mod panel_light;
mod panel_models;
mod panel_work;
pub mod picking;
pub mod replay;
pub mod state;
pub mod surface;
pub mod ui_cache;
pub mod walker;
pub mod window;

use std::path::PathBuf;

use sward::gpu::AdapterChoice;

pub use window::run;

/// How `sward` (the window) starts.
#[derive(Clone, Debug)]
pub struct AppOptions {
    /// Scene file; the built-in meadow when None (and when it fails to load).
    pub scene: Option<PathBuf>,
    /// `--set PATH=VALUE` overrides of the scene (also applied to the built-in meadow).
    pub sets: Vec<String>,
    /// Where Save writes (defaults to `scene`, else `scene.ron`).
    pub save_path: Option<PathBuf>,
    pub adapter: AdapterChoice,
    /// Window size in physical pixels.
    pub size: (u32, u32),
    pub vsync: bool,
    /// Run this many frames, then exit 0.
    pub exit_after_frames: Option<u64>,
    /// Save the last frame (with the panel) as PNG.
    pub screenshot: Option<PathBuf>,
    /// Play this input script.
    pub replay: Option<PathBuf>,
    /// Record the input into this script.
    pub record: Option<PathBuf>,
    /// Write every frame's GPU pass times as a Chrome trace here at the end.
    pub trace: Option<PathBuf>,
    /// Hold this frame time by adapting distance culling (None: the adapter decides).
    pub target_frame_ms: Option<f32>,
    /// Fixed simulation step per frame (replays use it for repeatable runs).
    pub fixed_dt: Option<f32>,
    /// Count every frame's work from the start (the Stats section's switch).
    pub count_work: bool,
}
