//! sward: a real-time grass renderer. Every blade is a quadratic Bézier curve simulated on
//! the GPU (Jahrmann & Wimmer 2017), culled on the GPU and drawn with indirect draws; the
//! same frames render headless to PNG on a software adapter.
//!
//! A wgpu program embeds the grass through [`GrassRenderer`] (module [`embed`]): created
//! from the host's device, queue and target formats, [`GrassRenderer::prepare`] records a
//! frame's simulation, cull and shadow maps into the host's encoder and
//! [`GrassRenderer::render`] draws the blades into the host's render pass. The crate's
//! `examples/embed.rs` is a whole host. The other modules are the layers the `sward`
//! application is built on (scene, field, simulation, rendering, headless commands; see the
//! repository's `docs/layers.md`); they are public for it and for tools, and documented,
//! but [`embed`] is the interface meant for hosts.
#![deny(missing_docs)]

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
    ShadowCaster, ShadowReceiver, WindInput,
};
pub use error::{Error, Result};
pub use render::camera::CameraView;
pub use scene::ObjectPose;
