//! The interactive window: winit 0.30 + wgpu surface + egui panel, fly camera, AGC wind
//! editor, thrown balls, replayable input. Everything here that is logic rather than
//! windowing (camera, picking, editing, balls, replay scripts, frame budget) lives in its own
//! module and is unit-tested without a window.

pub mod adaptive;
pub mod balls;
pub mod camera;
pub mod editor;
pub mod picking;
pub mod replay;
