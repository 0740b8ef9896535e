//! sward inside another wgpu program: the host hands over its device, queue and target
//! formats, calls [`GrassRenderer::prepare`] once a frame (the simulation, the tiles, the
//! cull against the host's depth, the sun's shadow maps: compute and passes of sward's own,
//! recorded into the host's encoder) and [`GrassRenderer::render`] inside its own render
//! pass, where the blades are depth-tested against the host's world.
//!
//! ```no_run
//! # fn frame(device: &wgpu::Device, queue: &wgpu::Queue, color: &wgpu::TextureView,
//! #          depth: &wgpu::TextureView) -> sward::Result<()> {
//! use sward::embed::{ColorOutput, FrameInputs, GrassRenderer, GrassRendererDescriptor};
//! let mut grass = GrassRenderer::new(device, queue, GrassRendererDescriptor {
//!     color_format: wgpu::TextureFormat::Rgba8UnormSrgb,
//!     depth_format: wgpu::TextureFormat::Depth32Float,
//!     sample_count: 1,
//!     output: ColorOutput::ToneMapped,
//!     scene: sward::embed::SceneSource::Ron(sward::embed::MEADOW_SCENE.into()),
//! })?;
//! let camera = sward::CameraView {
//!     eye: glam::Vec3::new(0.0, 1.7, 6.0), target: glam::Vec3::ZERO,
//!     fov_y: 60.0, near: 0.1, far: 500.0,
//! };
//! let mut encoder = device.create_command_encoder(&Default::default());
//! // ... the host's opaque pass writes `depth` ...
//! grass.prepare(device, queue, &mut encoder, &FrameInputs {
//!     camera, size: (1280, 720), dt: 1.0 / 60.0, colliders: &[], depth: Some(depth), wind: None,
//! })?;
//! {
//!     let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
//!         label: Some("host.grass"),
//!         color_attachments: &[Some(wgpu::RenderPassColorAttachment {
//!             view: color, depth_slice: None, resolve_target: None,
//!             ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
//!         })],
//!         depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
//!             view: depth,
//!             depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store }),
//!             stencil_ops: None,
//!         }),
//!         ..Default::default()
//!     });
//!     grass.render(&mut pass);
//! }
//! queue.submit([encoder.finish()]);
//! # Ok(()) }
//! ```
//!
//! Conventions the host's camera and depth follow: a right-handed world with y up, wgpu's
//! depth from 0 (near) to 1 (far) compared with `LessEqual` (not reversed), the projection
//! of [`crate::CameraView::view_proj`] (the host should draw its own world with that matrix so
//! that the depths agree). The grass is sward's near level: every blade simulated, culled
//! by orientation, distance, frustum and the host's depth, with the billboards of the far
//! level beyond them; the far ground, sward's terrain and sky are not drawn: the host has
//! its own ground.
//!
//! A host that wants sward's whole world instead (sky, terrain, far ground, objects,
//! grass, anti-aliasing, tone mapping) in a texture of its own makes the renderer with
//! [`GrassRenderer::new_world`] and draws each frame with
//! [`GrassRenderer::render_world`] (module `world`'s example). sward's own window, `sward
//! render` and the bench draw their frames that way.
//!
//! Shadows: the grass receives the sun's shadows of the blades, of sward's terrain and of
//! the host's colliders (drawn into sward's shadow maps as spheres); the host's shaders
//! receive the same shadows through [`GrassRenderer::shadow_receiver`]. The host's own
//! meshes do not cast into sward's maps.

mod inputs;
mod world;

use std::path::Path;

use glam::Vec3;

use crate::error::{Error, Result};
use crate::gpu::Gpu;
use crate::render::host::{HostPipelines, HostTarget};
use crate::render::{DynamicSphere, Renderer};
use crate::scene::{DirectionalWind, ObjectPose, Scene, WindSource};
use crate::session::Session;
use inputs::{check_inputs, check_view};
pub use inputs::{Collider, FrameInputs, WindInput};
pub use world::{
    WorldDescriptor, WorldScene, WorldTarget, WORLD_DEPTH_FORMAT, WORLD_RADIANCE_FORMAT,
};

/// The features sward cannot work without: none beyond WebGPU's core (compute, storage
/// buffers, indirect draws).
pub const REQUIRED_FEATURES: wgpu::Features = wgpu::Features::empty();

/// Features sward uses when the device has them: one multi-draw for the levels of detail
/// (`INDIRECT_FIRST_INSTANCE`) and MSAA counts beyond 1 and 4
/// (`TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES`). Request
/// `adapter.features() & OPTIONAL_FEATURES` beside the host's own.
pub const OPTIONAL_FEATURES: wgpu::Features = wgpu::Features::INDIRECT_FIRST_INSTANCE
    .union(wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES);

/// The limits sward needs: WebGPU's defaults, with the storage buffers per shader stage
/// and the storage buffer binding size its blade update and cull bind, capped by what
/// `adapter` offers. A larger field needs larger buffers: a device with the adapter's own
/// limits holds the most.
pub fn required_limits(adapter: &wgpu::Limits) -> wgpu::Limits {
    let mut limits = wgpu::Limits::default();
    limits.max_storage_buffers_per_shader_stage = adapter
        .max_storage_buffers_per_shader_stage
        .min(MIN_STORAGE_BUFFERS_PER_STAGE.max(limits.max_storage_buffers_per_shader_stage));
    limits.max_storage_buffer_binding_size = adapter.max_storage_buffer_binding_size;
    limits.max_buffer_size = adapter.max_buffer_size;
    limits
}

/// The most storage buffers one of sward's shader stages binds (the blade update's).
pub const MIN_STORAGE_BUFFERS_PER_STAGE: u32 = 16;

/// The text of sward's default scene, the meadow (`assets/scenes/meadow.ron`): hills of
/// grass streamed in tiles around the camera, a ball rolling through it, wind from the
/// west and the sun.
pub const MEADOW_SCENE: &str = include_str!("../../scenes/meadow.ron");

/// Where the grass's scene (field, blades, wind, light) comes from.
#[derive(Clone, Debug)]
pub enum SceneSource {
    /// A scene file's text (RON, as in `assets/scenes/`); relative paths in it (density
    /// maps, meshes) resolve from the working directory.
    Ron(String),
    /// A scene file on disk.
    File(std::path::PathBuf),
    /// A scene built in code (checked as a file would be: it is written out and read back,
    /// so an error names the field and its allowed range).
    Scene(Box<Scene>),
}

/// What the grass's fragment shader writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColorOutput {
    /// Linear radiance, for a host that renders into a high-dynamic-range target and
    /// tone-maps it itself.
    Radiance,
    /// Display colour: the scene's exposure and tone curve (`light.tone_mapping`) applied,
    /// for an 8-bit target (an sRGB format encodes it).
    ToneMapped,
}

/// How to create a [`GrassRenderer`].
#[derive(Clone, Debug)]
pub struct GrassRendererDescriptor {
    /// The format of the host pass's colour attachment.
    pub color_format: wgpu::TextureFormat,
    /// The format of the host pass's depth attachment.
    pub depth_format: wgpu::TextureFormat,
    /// The host pass's sample count (1, or a count its attachments were made with).
    pub sample_count: u32,
    /// Radiance or display colour.
    pub output: ColorOutput,
    /// The grass to grow.
    pub scene: SceneSource,
}

/// What a host binds to receive sward's sun shadows ([`GrassRenderer::shadow_receiver`]).
pub struct ShadowReceiver<'a> {
    /// The layout of the light's group (uniforms, the cascades' depth array, the comparison
    /// sampler), for the host's pipeline layout.
    pub layout: &'a wgpu::BindGroupLayout,
    /// sward's light group; bind it at the group the shader's receiver WGSL names.
    pub group: &'a wgpu::BindGroup,
    /// The direction towards the sun (unit, world space): the scene's sun, which sward's
    /// shadow maps are drawn from.
    pub sun_direction: Vec3,
}

/// One of sward's sun shadow cascades drawn this frame, where a host draws its own shadow
/// casters ([`GrassRenderer::shadow_casters`]).
pub struct ShadowCaster<'a> {
    /// World to the cascade's clip space: the sun's orthographic view-projection (depth
    /// 0..1, nearer the sun smaller).
    pub view_proj: glam::Mat4,
    /// The cascade's layer of sward's shadow map ([`SHADOW_DEPTH_FORMAT`]), to draw into
    /// with `LoadOp::Load` and `StoreOp::Store` and a depth compare of `LessEqual`.
    pub depth: &'a wgpu::TextureView,
}

/// The format of sward's shadow maps: a host's caster pipeline writes this depth.
pub const SHADOW_DEPTH_FORMAT: wgpu::TextureFormat = crate::render::draw::DEPTH_FORMAT;

/// The depth bias sward's own casters draw with; a host's caster pipeline takes the same,
/// so that its surfaces and the grass do not shadow themselves.
pub const SHADOW_DEPTH_BIAS: wgpu::DepthBiasState = crate::render::pipelines::SHADOW_BIAS;

/// sward's grass in a host's frame. See the module's example.
pub struct GrassRenderer {
    gpu: Gpu,
    /// The renderer behind the API (the crate's own commands reach it; the application
    /// through `Deref` with the `internals` feature).
    pub(crate) renderer: Renderer,
    /// Where the frame goes: the host's pass, or sward's whole world into a host texture.
    kind: Kind,
    /// The layout of the light's group, for hosts that receive the shadows (made once).
    light_layout: wgpu::BindGroupLayout,
    /// The last prepared frame's size (the draw's lists were culled for it).
    prepared: Option<(u32, u32)>,
    /// The size of the world frame `begin_world` recorded and `finish_world` has not ended.
    world_begun: Option<(u32, u32)>,
    /// One line describing the grown field.
    field_line: String,
}

/// What a [`GrassRenderer`] draws into.
enum Kind {
    /// The host's render pass, with the grass pipelines built for it
    /// ([`GrassRenderer::new`]).
    HostPass(Box<HostPipelines>),
    /// sward's whole world into a host's colour texture of this format
    /// ([`GrassRenderer::new_world`]).
    World(wgpu::TextureFormat),
}

impl GrassRenderer {
    /// Grows the scene's field and builds the grass for the host's device and target.
    ///
    /// # Errors
    ///
    /// A scene that does not parse or is out of range ([`Error::Scene`] naming the field and
    /// the allowed range), a field too large for the device ([`Error::Limits`]), a sample
    /// count the device cannot draw, or a device error while building.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        desc: GrassRendererDescriptor,
    ) -> Result<Self> {
        if !desc.depth_format.is_depth_stencil_format() {
            return Err(Error::Invalid(format!(
                "depth_format {:?} is not a depth format",
                desc.depth_format
            )));
        }
        if desc.color_format.is_depth_stencil_format() {
            return Err(Error::Invalid(format!(
                "color_format {:?} is a depth format",
                desc.color_format
            )));
        }
        let counts = crate::scene::limits::SAMPLE_COUNTS;
        if !counts.contains(&desc.sample_count) {
            return Err(Error::Invalid(format!(
                "sample_count {} is out of range: allowed {counts:?}",
                desc.sample_count
            )));
        }
        let mut scene = load(&desc.scene)?;
        // The host's pass: its sample count; no TAA or grass-on-grass late pass (both need
        // passes of sward's own after the draw).
        scene.render.msaa = desc.sample_count;
        scene.render.taa = false;
        scene.culling.grass_occlusion = false;
        let gpu = Gpu::from_host(device, queue);
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let built = build(&gpu, scene, &desc);
        let error = crate::gpu::block_on(scope.pop());
        let (renderer, host, field_line) = built?;
        if let Some(e) = error {
            return Err(Error::Gpu(format!(
                "building the grass for the host failed: {e}"
            )));
        }
        if renderer.samples() != desc.sample_count {
            return Err(Error::Invalid(format!(
                "sample_count {} is not supported for {:?} on {} (it would draw with {})",
                desc.sample_count,
                desc.color_format,
                gpu.info.name,
                renderer.samples()
            )));
        }
        Ok(Self::assemble(
            gpu,
            renderer,
            Kind::HostPass(Box::new(host)),
            field_line,
        ))
    }

    fn assemble(gpu: Gpu, renderer: Renderer, kind: Kind, field_line: String) -> Self {
        Self {
            light_layout: crate::render::light::layout(&gpu.device),
            gpu,
            renderer,
            kind,
            prepared: None,
            world_begun: None,
            field_line,
        }
    }

    /// Checks this frame's inputs and hands them to the renderer: the host's colliders
    /// (with the scene's, within [`crate::scene::limits::MAX_SPHERES`]) and its wind.
    fn apply_inputs(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        inputs: &FrameInputs,
    ) -> Result<()> {
        if device != &self.gpu.device || queue != &self.gpu.queue {
            return Err(Error::Invalid(
                "the frame got another device or queue than the one the grass was built on".into(),
            ));
        }
        check_inputs(inputs, &self.gpu)?;
        let r = &mut self.renderer;
        // The scene's colliders and its objects' packed spheres (counted, not posed).
        let scene_spheres = r.scene_sphere_count();
        let max = crate::scene::limits::MAX_SPHERES;
        if scene_spheres + inputs.colliders.len() > max {
            return Err(Error::Invalid(format!(
                "{} colliders from the host with {} of the scene's: allowed at most {max} in all",
                inputs.colliders.len(),
                scene_spheres
            )));
        }
        r.dynamic_spheres = inputs
            .colliders
            .iter()
            .map(|c| DynamicSphere {
                center: c.center,
                radius: c.radius,
                velocity: c.velocity,
            })
            .collect();
        if let Some(w) = inputs.wind {
            let d = w.direction.normalize();
            let old = r.scene.wind.directional.clone().unwrap_or_default();
            r.scene.wind.directional = Some(DirectionalWind {
                direction: (d.x, d.y),
                strength: w.strength,
                ..old
            });
            if r.scene.wind.source == WindSource::Fluid {
                r.scene.wind.source = WindSource::Both;
            }
        }
        Ok(())
    }

    /// Records this frame's compute work and sward's own passes into `encoder`: the step of
    /// the simulation by `dt` with the host's colliders and wind, the tiles entering the
    /// field, the cull (against `inputs.depth`), and the sun's shadow maps. Call it after
    /// the host's opaque pass wrote the depth and before the pass that calls
    /// [`GrassRenderer::render`]; submit the encoder before that pass's.
    ///
    /// # Errors
    ///
    /// Inputs out of range (non-finite camera, zero size, a collider with a bad radius,
    /// too many colliders, wind out of range), or a device other than the renderer's.
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &FrameInputs,
    ) -> Result<()> {
        let Kind::HostPass(host) = &self.kind else {
            return Err(Error::Invalid(
                "prepare: this renderer was made with GrassRenderer::new_world and draws the \
                 whole world (render_world); a renderer for the host's pass is made with new"
                    .into(),
            ));
        };
        if let Some(depth) = inputs.depth {
            let samples = host.target().samples;
            check_view(
                "FrameInputs::depth",
                depth,
                inputs.size,
                samples,
                &[host.target().depth_format],
                wgpu::TextureUsages::TEXTURE_BINDING,
            )?;
        }
        self.apply_inputs(device, queue, inputs)?;
        let r = &mut self.renderer;
        r.sync_for_host(&self.gpu);
        if let Kind::HostPass(host) = &mut self.kind {
            host.sync(&self.gpu.device, r);
        }
        r.encode_before_draw(
            &self.gpu,
            encoder,
            inputs.dt,
            &inputs.camera,
            inputs.depth,
            inputs.size,
            false,
        );
        self.prepared = Some(inputs.size);
        Ok(())
    }

    /// Draws the blades [`GrassRenderer::prepare`] kept, and the billboards beyond them
    /// (`render.billboard_distance`), into the host's pass (a pass with the descriptor's
    /// colour and depth formats and sample count). Draws nothing before the first
    /// `prepare`.
    pub fn render(&self, pass: &mut wgpu::RenderPass<'_>) {
        if let (Some(_), Kind::HostPass(host)) = (self.prepared, &self.kind) {
            self.renderer.draw_into_host(pass, host);
        }
    }

    /// The scene as loaded and adjusted for the host (read it for the camera a scene file
    /// proposes, the terrain's size, the light).
    pub fn scene(&self) -> &Scene {
        &self.renderer.scene
    }

    /// The hook for the host's shaders to receive sward's sun shadows (the blades', the
    /// colliders' and sward's terrain's, from the shadow maps `prepare` drew): bind
    /// [`ShadowReceiver::group`] at a group of the host's pipeline made with
    /// [`ShadowReceiver::layout`], include [`GrassRenderer::shadow_receiver_wgsl`] for that
    /// group in the shader, and multiply the sun's light by
    /// `sward_sun_visibility(world, camera_eye, sun_direction)`.
    pub fn shadow_receiver(&self) -> ShadowReceiver<'_> {
        ShadowReceiver {
            layout: &self.light_layout,
            group: self.renderer.light().group(),
            sun_direction: crate::render::light::sun::scene_sun(&self.renderer.scene),
        }
    }

    /// The cascades of sward's sun shadows that the last [`GrassRenderer::prepare`] drew,
    /// for the host's own shadow casters: after `prepare` and before submitting its
    /// encoder, the host draws its meshes, depth only, into each cascade's layer with that
    /// cascade's `view_proj`, loading the depth sward drew (a pipeline of
    /// [`SHADOW_DEPTH_FORMAT`] and [`SHADOW_DEPTH_BIAS`]). The grass `render` draws then
    /// lies in their shadows, as does a host surface that receives them
    /// ([`GrassRenderer::shadow_receiver`]). Cascades sward did not draw again this frame
    /// (the far ones are redrawn every few frames) are not listed and keep what the host
    /// drew into them before. Empty when the scene has no sun shadows.
    pub fn shadow_casters(&self) -> Vec<ShadowCaster<'_>> {
        self.renderer
            .light()
            .caster_targets()
            .into_iter()
            .map(|(view_proj, depth)| ShadowCaster { view_proj, depth })
            .collect()
    }

    /// The WGSL a host's shader includes to receive sward's shadows with the bindings at
    /// `@group(group)`: `SwardLightUniforms`, `sward_light`, `sward_shadow_map`,
    /// `sward_shadow_sampler` and
    /// `fn sward_sun_visibility(world: vec3<f32>, camera: vec3<f32>, sun_dir: vec3<f32>) -> f32`
    /// (1 lit, 0 in shadow) — the lookup sward's own passes run.
    pub fn shadow_receiver_wgsl(group: u32) -> String {
        crate::render::light::receiver::receiver_wgsl(group)
    }

    /// The height of sward's ground at (x, z): where the host should put its own ground so
    /// that the blades stand on it.
    pub fn ground_height(&self, x: f32, z: f32) -> f32 {
        self.renderer.terrain.height(x, z)
    }

    /// Steers the scene's object `index` (a character the host moves): from the next
    /// `prepare` on it stands at `pose` — drawn there, posed at `pose.animation_time`, its
    /// colliders pressing the grass there — instead of following its scene `motion`; `None`
    /// hands it back. An index past the scene's objects or a non-finite pose is an error and
    /// changes nothing.
    pub fn pose_object(&mut self, index: usize, pose: Option<ObjectPose>) -> Result<()> {
        self.renderer.pose_object(index, pose)
    }

    /// The blades the last prepared frame drew, read back (blocks until the GPU is done;
    /// for tests and statistics, not for every frame).
    pub fn drawn_blades(&mut self) -> Result<u64> {
        let stats = self.renderer.stats(&self.gpu)?;
        Ok(u64::from(stats.counters.drawn()))
    }

    /// The billboards (the far level beyond the blades, `render.billboard_distance`) the
    /// last prepared frame drew, read back (blocks; for tests and statistics).
    pub fn drawn_billboards(&self) -> Result<u32> {
        self.renderer.billboards_kept(&self.gpu)
    }

    /// One line describing the grown field: its blades and patches, or its tiles and the
    /// pool that streams them.
    pub fn describe_field(&self) -> &str {
        &self.field_line
    }
}

/// The application (the `internals` feature) reaches through the embedding API into the
/// renderer it wraps: its panel edits the scene live, reads the counters and timers, and
/// draws its own passes (the guide arrows, the panel) timed like sward's.
#[cfg(feature = "internals")]
impl std::ops::Deref for GrassRenderer {
    type Target = Renderer;

    fn deref(&self) -> &Renderer {
        &self.renderer
    }
}

#[cfg(feature = "internals")]
impl std::ops::DerefMut for GrassRenderer {
    fn deref_mut(&mut self) -> &mut Renderer {
        &mut self.renderer
    }
}

/// The scene of `source`, checked.
fn load(source: &SceneSource) -> Result<Scene> {
    match source {
        SceneSource::Ron(text) => crate::scene::parse_scene(text, Path::new("<host scene>")),
        SceneSource::File(path) => crate::scene::load_scene(path),
        SceneSource::Scene(scene) => {
            let text = crate::scene::save::scene_to_string(scene)?;
            crate::scene::parse_scene(&text, Path::new("<host scene>"))
        }
    }
}

/// The renderer and the host's grass pipeline.
fn build(
    gpu: &Gpu,
    scene: Scene,
    desc: &GrassRendererDescriptor,
) -> Result<(Renderer, HostPipelines, String)> {
    let session = Session::new(scene, None, Some(gpu))?;
    let renderer = Renderer::from_session(gpu, &session, desc.color_format)?;
    let host = HostPipelines::new(
        &gpu.device,
        &renderer,
        HostTarget {
            color_format: desc.color_format,
            depth_format: desc.depth_format,
            samples: desc.sample_count,
            display: desc.output == ColorOutput::ToneMapped,
        },
    );
    Ok((renderer, host, session.describe_field()))
}
