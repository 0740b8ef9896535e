//! Drawing the grass into a host's render pass (`sward::embed`): the lit grass pipeline
//! built again for the host's colour format, depth format and sample count (and, for an
//! 8-bit target, with the scene's exposure and tone curve applied in the fragment shader:
//! `DISPLAY_OUTPUT` in `grass.wgsl`), and the draw that binds it over the visible lists
//! the renderer's cull wrote in `Renderer::encode_before_draw`; and the billboards (the far
//! level) with a pipeline for the same target.

use super::grass_spec::GrassSpec;
use super::pipelines::{pipeline_for, PipelineSpec};
use super::Renderer;

/// What a host's pass holds, as the grass pipeline must match it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HostTarget {
    /// The format of the host pass's colour attachment.
    pub color_format: wgpu::TextureFormat,
    /// The format of the host pass's depth attachment (the grass tests and writes it).
    pub depth_format: wgpu::TextureFormat,
    /// The host pass's samples per pixel.
    pub samples: u32,
    /// Display colour (tone-mapped) instead of linear radiance.
    pub display: bool,
}

/// The grass pipeline of one host target and one specialisation of the scene, and the
/// billboards' for the same target (the far level, where the scene has one).
pub struct HostPipelines {
    target: HostTarget,
    spec: GrassSpec,
    grass: wgpu::RenderPipeline,
    billboards: Option<wgpu::RenderPipeline>,
}

impl HostPipelines {
    /// Builds the lit grass pipeline for `target` and the renderer's current scene.
    pub fn new(device: &wgpu::Device, renderer: &Renderer, target: HostTarget) -> Self {
        let spec = renderer.draw.grass_spec();
        let mut constants = spec.constants().to_vec();
        constants.push(("DISPLAY_OUTPUT", if target.display { 1.0 } else { 0.0 }));
        let grass = pipeline_for(
            device,
            (target.color_format, target.depth_format),
            target.samples,
            PipelineSpec {
                label: "sward.host.grass",
                shader: "grass.wgsl",
                vertex: "vs_lit",
                layout: renderer.draw.grass_layout(),
                buffers: &[],
                depth_write: true,
                cull_back: false,
                lines: false,
                depth_only: false,
                constants: &constants,
            },
        );
        let billboards = renderer
            .billboards
            .as_ref()
            .map(|b| b.host_pipeline(device, target));
        Self {
            target,
            spec,
            grass,
            billboards,
        }
    }

    /// Rebuilds the pipeline when the scene's specialisation changed (a scene edited
    /// between frames); true when it did.
    pub fn sync(&mut self, device: &wgpu::Device, renderer: &Renderer) -> bool {
        if renderer.draw.grass_spec() == self.spec {
            return false;
        }
        *self = Self::new(device, renderer, self.target);
        true
    }

    /// The target this pipeline draws into.
    pub fn target(&self) -> HostTarget {
        self.target
    }
}

impl Renderer {
    /// The spheres the scene itself collides with every frame: its colliders and its
    /// objects' packed spheres (what [`Renderer::frame_spheres`] holds before the dynamic
    /// ones), counted without placing or posing them.
    pub fn scene_sphere_count(&self) -> usize {
        let packed: usize = self
            .packings
            .iter()
            .flatten()
            .map(|p| p.spheres.len())
            .sum();
        self.scene.colliders.len() + packed
    }

    /// What `encode_scene` brings up to date before a frame that a host's pass draws: the
    /// grass's specialisation for the scene as it now is.
    pub fn sync_for_host(&mut self, gpu: &crate::gpu::Gpu) {
        self.draw
            .sync_grass_spec(&gpu.device, &self.scene, self.lod_morph, self.fold);
    }

    /// Draws the blades the last `encode_before_draw` kept (every level of detail) into
    /// `pass`, lit by the scene's sun, sky and shadow maps, and the billboards its cull kept
    /// beyond them.
    pub fn draw_into_host(&self, pass: &mut wgpu::RenderPass<'_>, host: &HostPipelines) {
        pass.set_bind_group(1, self.light.group(), &[]);
        self.draw.draw_grass(pass, &host.grass, &self.cull.args, 0);
        if let (Some(b), Some(p)) = (&self.billboards, &host.billboards) {
            b.draw_with(pass, p);
        }
    }

    /// How many billboards the last frame's cull kept (blocking; 0 without any).
    pub fn billboards_kept(&self, gpu: &crate::gpu::Gpu) -> crate::error::Result<u32> {
        self.billboards.as_ref().map_or(Ok(0), |b| b.read_drawn(gpu))
    }
}
