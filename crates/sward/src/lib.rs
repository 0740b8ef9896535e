//! sward: a real-time grass renderer. Every blade is a quadratic Bézier curve simulated on
//! the GPU (Jahrmann & Wimmer 2017), culled on the GPU and drawn with indirect draws; the
//! same frames render headless to PNG on a software adapter.
//!
//! A wgpu program embeds the grass through [`GrassRenderer`] (module [`embed`]): created
//! from the host's device, queue and target formats, [`GrassRenderer::prepare`] records a
//! frame's simulation, cull and shadow maps into the host's encoder and
//! [`GrassRenderer::render`] draws the blades into the host's render pass; made with
//! [`GrassRenderer::new_world`], [`GrassRenderer::render_world`] draws sward's whole world
//! (sky, terrain, far field, anti-aliasing, tone curve) into a texture of the host's, as the
//! `sward` application draws every frame. The crate's `examples/embed.rs` is a whole host. [`scene`] describes a field in code or in a RON
//! file. The other modules are the layers the `sward` application is built on (field,
//! simulation, rendering, headless commands; see the repository's `docs/layers.md`): they
//! are crate-private, and public only with the `internals` feature, which the application
//! and the tests enable; [`embed`] is the interface meant for hosts.
#![deny(missing_docs)]
// Without `internals` the layers below are the crate's own: what they export for the
// application and the tests (items, and re-exports gathering them) is unused here, and is
// not dead.
#![cfg_attr(not(feature = "internals"), allow(dead_code, unused_imports))]

/// Declares a layer module: public with the `internals` feature (the `sward` application
/// and the tests, which reach into the renderer, the simulation and their CPU twins),
/// crate-private without it (a host sees the embedding API and the scene types).
macro_rules! internal {
    ($($name:ident),* $(,)?) => {
        $(
            #[cfg(feature = "internals")]
            pub mod $name;
            #[cfg(not(feature = "internals"))]
            #[allow(unreachable_pub)]
            pub(crate) mod $name;
        )*
    };
}

pub mod embed;
pub mod error;
pub mod scene;

internal!(commands, compare, field, gpu, input, mesh, output, render, session, shaders, sim);

pub use embed::{
    Collider, ColorOutput, FrameInputs, GrassRenderer, GrassRendererDescriptor, SceneSource,
    ShadowCaster, ShadowReceiver, WindInput, WorldDescriptor, WorldScene, WorldTarget,
};
pub use error::{Error, Result};
pub use render::camera::CameraView;
pub use scene::ObjectPose;
