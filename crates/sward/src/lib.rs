#![warn(missing_docs)]
//! sward: a real-time grass renderer. Every blade is a quadratic Bézier curve simulated on
//! the GPU (Jahrmann & Wimmer 2017), culled on the GPU and drawn with indirect draws; the
//! same frames render headless to PNG on a software adapter.

pub mod commands;
pub mod compare;
pub mod embed;
pub mod error;
pub mod field;
pub mod gpu;
pub mod input;
pub mod mesh;
pub mod output;
pub mod render;
pub mod scene;
pub mod session;
pub mod shaders;
pub mod sim;

pub use embed::{
    Collider, ColorOutput, FrameInputs, GrassRenderer, GrassRendererDescriptor, SceneSource,
    WindInput,
};
pub use error::{Error, Result};
pub use render::camera::CameraView;
