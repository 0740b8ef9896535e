//! sward's whole world in a host's texture: a [`GrassRenderer`] made with
//! [`GrassRenderer::new_world`] draws the sky, its terrain and far ground, the scene's
//! objects, the grass at every level (blades, billboards), the sun's shadows, fog, the
//! scene's anti-aliasing (MSAA or TAA) and tone mapping into a colour texture of the host
//! (an editor's preview, a game that wants a grass backdrop, sward's own window, `sward
//! render` and the bench). The frame takes the same [`FrameInputs`] as a host pass's.
//!
//! One call ([`GrassRenderer::render_world`]) or two with the host's own 3D passes between
//! them: [`GrassRenderer::begin_world`] records everything up to the resolve,
//! [`GrassRenderer::world_scene`] names the radiance and depth the host may draw into
//! (depth-tested against the grass, anti-aliased with it), and
//! [`GrassRenderer::finish_world`] resolves, lights the deferred grass, tone-maps into the
//! host's colour and ends the frame.
//!
//! ```no_run
//! # fn frame(device: &wgpu::Device, queue: &wgpu::Queue, color: &wgpu::TextureView,
//! #          depth: &wgpu::TextureView) -> sward::Result<()> {
//! use sward::embed::{FrameInputs, GrassRenderer, SceneSource, WorldDescriptor, WorldTarget};
//! let mut world = GrassRenderer::new_world(device, queue, WorldDescriptor {
//!     color_format: wgpu::TextureFormat::Rgba8UnormSrgb,
//!     scene: SceneSource::Ron(sward::embed::MEADOW_SCENE.into()),
//! })?;
//! let camera = sward::CameraView::from_scene(&world.scene().camera);
//! let mut encoder = device.create_command_encoder(&Default::default());
//! world.render_world(device, queue, &mut encoder, &FrameInputs {
//!     camera, size: (1280, 720), dt: 1.0 / 60.0, colliders: &[], depth: None, wind: None,
//! }, &WorldTarget { color, depth })?;
//! queue.submit([encoder.finish()]);
//! # Ok(()) }
//! ```

use super::inputs::check_view;
use super::{load, FrameInputs, GrassRenderer, Kind, SceneSource};
use crate::error::{Error, Result};
use crate::gpu::Gpu;
use crate::render::Renderer;
use crate::session::Session;

/// How to create a [`GrassRenderer`] that draws sward's whole world.
#[derive(Clone, Debug)]
pub struct WorldDescriptor {
    /// The format of the host's colour texture the frame is tone-mapped into (an 8-bit
    /// format; an sRGB one encodes the display colour).
    pub color_format: wgpu::TextureFormat,
    /// The world to grow: field, terrain, objects, wind, light and the scene's
    /// anti-aliasing (`render.msaa`, `render.taa`).
    pub scene: SceneSource,
}

/// The host's textures a world frame is drawn into.
pub struct WorldTarget<'a> {
    /// The colour (the descriptor's format, `RENDER_ATTACHMENT` usage, one sample, the
    /// frame's size) the tone-mapped frame is written to.
    pub color: &'a wgpu::TextureView,
    /// A depth of [`WORLD_DEPTH_FORMAT`], one sample, the frame's size, with
    /// `RENDER_ATTACHMENT | TEXTURE_BINDING` usage (the occlusion cull reads it). Without
    /// MSAA the frame's depth stays in it; with MSAA sward draws into a multisampled depth
    /// of its own ([`GrassRenderer::world_scene`]).
    pub depth: &'a wgpu::TextureView,
}

/// The depth format of [`WorldTarget::depth`].
pub const WORLD_DEPTH_FORMAT: wgpu::TextureFormat = crate::render::draw::DEPTH_FORMAT;

/// The format of the radiance a world frame is lit in, before its tone mapping
/// ([`WorldScene::color`]).
pub const WORLD_RADIANCE_FORMAT: wgpu::TextureFormat = crate::render::post::HDR_FORMAT;

/// What a host may draw into between [`GrassRenderer::begin_world`] and
/// [`GrassRenderer::finish_world`]: the frame's linear radiance and its depth, both with
/// [`WorldScene::samples`] samples per pixel. A pass over them with `LoadOp::Load` draws in
/// the world: depth-tested against the grass (`LessEqual`) and anti-aliased with it.
pub struct WorldScene<'a> {
    /// The radiance ([`WORLD_RADIANCE_FORMAT`]).
    pub color: &'a wgpu::TextureView,
    /// The depth ([`WORLD_DEPTH_FORMAT`]).
    pub depth: &'a wgpu::TextureView,
    /// Samples per pixel of both (the scene's MSAA, or 1).
    pub samples: u32,
}

impl GrassRenderer {
    /// Grows the scene's world for the host's device, to be drawn whole into the host's
    /// textures with [`GrassRenderer::render_world`].
    ///
    /// # Errors
    ///
    /// As [`GrassRenderer::new`]: a scene that does not parse or is out of range, a field
    /// too large for the device, a colour format that is a depth format, a device error.
    pub fn new_world(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        desc: WorldDescriptor,
    ) -> Result<Self> {
        Self::world_on(Gpu::from_host(device, queue), desc)
    }

    /// [`GrassRenderer::new_world`] on a device sward opened itself (the application's
    /// window and commands, whose [`Gpu`] keeps the device's errors, timers and counters).
    pub(crate) fn world_on(gpu: Gpu, desc: WorldDescriptor) -> Result<Self> {
        let scene = load(&desc.scene)?;
        Self::world_of(gpu, scene, desc.color_format)
    }

    /// A world renderer of a scene already checked (loaded from a file with its `--set`
    /// overrides, or edited in the window's panel and checked there): its errors keep
    /// naming where each value came from.
    pub(crate) fn world_of(
        gpu: Gpu,
        scene: crate::scene::Scene,
        color_format: wgpu::TextureFormat,
    ) -> Result<Self> {
        if color_format.is_depth_stencil_format() {
            return Err(Error::Invalid(format!(
                "color_format {color_format:?} is a depth format"
            )));
        }
        let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let built = Session::new(scene, None, Some(&gpu)).and_then(|session| {
            let line = session.describe_field();
            Renderer::from_session(&gpu, &session, color_format).map(|r| (r, line))
        });
        let error = crate::gpu::block_on(scope.pop());
        let (renderer, field_line) = built?;
        if let Some(e) = error {
            return Err(Error::Gpu(format!("building the world failed: {e}")));
        }
        Ok(Self::assemble(
            gpu,
            renderer,
            Kind::World(color_format),
            field_line,
        ))
    }

    /// [`GrassRenderer::new_world`] on the application's device (its `Gpu`) for a scene it
    /// has checked itself.
    #[cfg(feature = "internals")]
    pub fn world_of_checked(
        gpu: &Gpu,
        scene: crate::scene::Scene,
        color_format: wgpu::TextureFormat,
    ) -> Result<Self> {
        Self::world_of(gpu.clone(), scene, color_format)
    }

    /// A world renderer around a renderer built elsewhere (the bench, which grows one
    /// field and renders it in many configurations), for the colour format the renderer
    /// was built for.
    #[cfg(feature = "internals")]
    pub fn wrap_world(gpu: &Gpu, renderer: Renderer, color_format: wgpu::TextureFormat) -> Self {
        let line = format!("field: {} blades", renderer.buffers.count);
        Self::assemble(gpu.clone(), renderer, Kind::World(color_format), line)
    }

    /// [`GrassRenderer::new_world`] on the application's own device (its `Gpu`).
    #[cfg(feature = "internals")]
    pub fn new_world_on(gpu: &Gpu, desc: WorldDescriptor) -> Result<Self> {
        Self::world_on(gpu.clone(), desc)
    }

    /// One whole world frame into `target`: [`GrassRenderer::begin_world`] and
    /// [`GrassRenderer::finish_world`] with nothing of the host's between them.
    ///
    /// # Errors
    ///
    /// As [`GrassRenderer::begin_world`].
    pub fn render_world(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &FrameInputs,
        target: &WorldTarget,
    ) -> Result<()> {
        self.begin_world(device, queue, encoder, inputs, target)?;
        self.finish_world(encoder, target)?;
        self.renderer.resolve_queries(encoder);
        Ok(())
    }

    /// Records a world frame up to its resolve: the step of the simulation by `dt` with the
    /// host's colliders and wind, the tiles, the cull (against the frame's own depth), the
    /// shadow maps and every draw. The host may then draw into
    /// [`GrassRenderer::world_scene`] and must call [`GrassRenderer::finish_world`] with
    /// the same target before submitting `encoder`.
    ///
    /// # Errors
    ///
    /// A renderer made with [`GrassRenderer::new`] (it draws into the host's pass), inputs
    /// out of range (as [`GrassRenderer::prepare`]; `inputs.depth` must be `None`: the
    /// world draws its own depth into `target.depth`), a target whose textures do not
    /// match the descriptor and the frame's size, a frame too large for the device, or a
    /// device other than the renderer's.
    pub fn begin_world(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &FrameInputs,
        target: &WorldTarget,
    ) -> Result<()> {
        let Kind::World(color_format) = self.kind else {
            return Err(Error::Invalid(
                "begin_world: this renderer was made with GrassRenderer::new and draws into \
                 the host's pass (prepare, render); a world renderer is made with new_world"
                    .into(),
            ));
        };
        if inputs.depth.is_some() {
            return Err(Error::Invalid(
                "FrameInputs::depth must be None in a world frame: the world draws its own \
                 depth into WorldTarget::depth"
                    .into(),
            ));
        }
        let size = inputs.size;
        self.gpu
            .check_frame_size("the world's target", size, self.renderer.samples())?;
        check_color(target, size, color_format)?;
        check_view(
            "WorldTarget::depth",
            target.depth,
            size,
            1,
            &[WORLD_DEPTH_FORMAT],
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        )?;
        self.apply_inputs(device, queue, inputs)?;
        self.renderer.encode_scene(
            &self.gpu,
            encoder,
            inputs.dt,
            &inputs.camera,
            target.depth,
            size,
        );
        self.world_begun = Some(size);
        Ok(())
    }

    /// The radiance and depth of the world frame [`GrassRenderer::begin_world`] began, for
    /// the host's own 3D passes before [`GrassRenderer::finish_world`] (`target` is the
    /// frame's); `None` outside a begun frame.
    pub fn world_scene<'a>(&'a self, target: &WorldTarget<'a>) -> Option<WorldScene<'a>> {
        self.world_begun?;
        let (color, depth) = self.renderer.scene_views(target.color, target.depth);
        Some(WorldScene {
            color,
            depth,
            samples: self.renderer.msaa_samples(),
        })
    }

    /// Ends the world frame [`GrassRenderer::begin_world`] began: resolves the samples,
    /// lights the deferred grass, blends the TAA history and tone-maps into
    /// `target.color`. (A frame begun and never finished, its encoder dropped, is simply
    /// left behind: the next `begin_world` starts afresh.)
    ///
    /// # Errors
    ///
    /// No frame was begun, or `target.color` is not a colour texture of the frame's size and
    /// the descriptor's format (the frame stays begun: finish it with the right target).
    pub fn finish_world(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        target: &WorldTarget,
    ) -> Result<()> {
        let (Some(size), Kind::World(color_format)) = (self.world_begun, &self.kind) else {
            return Err(Error::Invalid(
                "finish_world without begin_world: no world frame is being recorded".into(),
            ));
        };
        check_color(target, size, *color_format)?;
        self.world_begun = None;
        self.renderer.resolve(encoder, target.color);
        Ok(())
    }
}

/// Refuses a world target whose colour is not a one-sample render attachment of the frame's
/// `size` and the descriptor's `format` (what `begin_world` and `finish_world` draw into).
fn check_color(target: &WorldTarget, size: (u32, u32), format: wgpu::TextureFormat) -> Result<()> {
    check_view(
        "WorldTarget::color",
        target.color,
        size,
        1,
        &[format],
        wgpu::TextureUsages::RENDER_ATTACHMENT,
    )
}
