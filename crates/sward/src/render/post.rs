//! Tone mapping after the 3D passes (issue 16, point 4). The lit passes draw linear
//! radiance into a half-float scene target ([`HDR_FORMAT`]); with MSAA the multisampled
//! target is resolved into it. One full-screen pass (`shaders/tonemap.wgsl`) then applies
//! the scene's exposure and filmic curve (`light.tone_mapping`: ACES, AgX or a clamp) into
//! the caller's 8-bit colour (the window's surface, the render-scale target or the headless
//! image). The wind overlay is drawn after it, in display colours.
//!
//! Why a separate pass rather than a curve at the end of every fragment shader: the curve
//! is not linear, so anti-aliasing must average radiance (what the camera's pixel gathers)
//! before it, and every pass then shares one exposure and one curve.

use crate::gpu::queries::PassQueries;
use crate::gpu::Gpu;
use crate::scene::ToneMapping;

/// The scene target's format: linear radiance with headroom above 1 for the sun's disk
/// and specular highlights (f16 holds up to 65504).
pub const HDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// `TONE_MAPPER` for the general pipeline (`GENERAL_TONE_MAPPER` in `light.wgsl`).
const GENERAL: u32 = 3;

/// The single-sample scene target of one size.
struct SceneTarget {
    size: (u32, u32),
    view: wgpu::TextureView,
    bind_group: wgpu::BindGroup,
}

/// The tone-mapping pass and the scene target it reads.
pub struct ToneMap {
    pipeline: wgpu::RenderPipeline,
    /// The shader's `TONE_MAPPER` constant `pipeline` is built with: a curve's id, or
    /// [`GENERAL`] (every curve compiled in, the uniform choosing).
    built: u32,
    /// Keep the general pipeline (the pictures are the same; the tests compare them).
    pub general: bool,
    format: wgpu::TextureFormat,
    pipeline_layout: wgpu::PipelineLayout,
    module: wgpu::ShaderModule,
    layout: wgpu::BindGroupLayout,
    target: Option<SceneTarget>,
}

impl ToneMap {
    /// The pass for output colour targets of `format`; `light_layout` is the light's
    /// group 1 (its uniforms hold the exposure and the curve).
    pub fn new(
        gpu: &Gpu,
        format: wgpu::TextureFormat,
        light_layout: &wgpu::BindGroupLayout,
    ) -> Self {
        let device = &gpu.device;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.tonemap.layout"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sward.tonemap.pipeline_layout"),
            bind_group_layouts: &[Some(&layout), Some(light_layout)],
            immediate_size: 0,
        });
        let module = crate::shaders::module(device, "tonemap.wgsl");
        let built = ToneMapping::default().id();
        let pipeline = tonemap_pipeline(device, &pipeline_layout, &module, format, built);
        Self {
            pipeline,
            built,
            general: false,
            format,
            pipeline_layout,
            module,
            layout,
            target: None,
        }
    }

    /// Rebuilds the pipeline for the scene's curve when it changed (the panel) or
    /// [`ToneMap::general`] did: never per frame.
    pub fn sync_mapper(&mut self, device: &wgpu::Device, mapper: ToneMapping) {
        let wanted = if self.general { GENERAL } else { mapper.id() };
        if wanted != self.built {
            self.pipeline = tonemap_pipeline(
                device,
                &self.pipeline_layout,
                &self.module,
                self.format,
                wanted,
            );
            self.built = wanted;
        }
    }

    /// The single-sample scene target at `size` (the 3D passes draw into it without MSAA,
    /// the resolve writes it with), allocated when the size changed.
    pub fn view(&mut self, gpu: &Gpu, size: (u32, u32)) -> &wgpu::TextureView {
        if self.target.as_ref().map(|t| t.size) != Some(size) {
            self.target = Some(self.allocate(gpu, size));
        }
        &self.target.as_ref().expect("allocated above").view
    }

    /// The scene target of the last [`ToneMap::view`], if any.
    pub fn current(&self) -> Option<&wgpu::TextureView> {
        self.target.as_ref().map(|t| &t.view)
    }

    /// The scene target's texels (linear radiance and alpha, row-major), read back
    /// (blocking; for tests), `None` before the first frame.
    pub fn read_target(&self, gpu: &Gpu) -> Option<crate::error::Result<Vec<[f32; 4]>>> {
        let t = self.target.as_ref()?;
        Some(super::target::read_rgba16f(
            gpu,
            t.view.texture(),
            t.size,
            "sward.tonemap.read_target",
        ))
    }

    /// Bytes of GPU memory the scene target holds.
    pub fn gpu_bytes(&self) -> u64 {
        self.target
            .as_ref()
            .map_or(0, |t| t.size.0 as u64 * t.size.1 as u64 * 8)
    }

    /// A bind group that makes the pass read `view` (an [`HDR_FORMAT`] texture of the
    /// output's size, such as the TAA history) instead of the scene target.
    pub fn bind_view(&self, device: &wgpu::Device, view: &wgpu::TextureView) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sward.tonemap.bind_group"),
            layout: &self.layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(view),
            }],
        })
    }

    fn allocate(&self, gpu: &Gpu, size: (u32, u32)) -> SceneTarget {
        let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("sward.tonemap.scene"),
            size: wgpu::Extent3d {
                width: size.0.max(1),
                height: size.1.max(1),
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: HDR_FORMAT,
            // Storage: the deferred grass shading writes its pixels (`render::deferred`).
            // Copied out: the TAA twin's test reads it back.
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        let bind_group = self.bind_view(&gpu.device, &view);
        SceneTarget {
            size,
            view,
            bind_group,
        }
    }

    /// Records the pass: the scene target (or what `source`, a [`ToneMap::bind_view`]
    /// group, reads) through the light's exposure and curve into `output` (same size).
    /// Does nothing before the first [`ToneMap::view`].
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        light: &wgpu::BindGroup,
        output: &wgpu::TextureView,
        source: Option<&wgpu::BindGroup>,
        q: PassQueries,
    ) {
        let Some(t) = &self.target else {
            return;
        };
        let group = source.unwrap_or(&t.bind_group);
        let mut pass = super::pipelines::fullscreen_pass(encoder, "sward.tonemap", output, &q);
        q.begin(&mut pass);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.set_bind_group(1, light, &[]);
        pass.draw(0..3, 0..1);
        q.end(&mut pass);
    }
}

/// The full-screen pass into `format` with `mapper` (a curve's id or [`GENERAL`]) as the
/// shader's `TONE_MAPPER`.
fn tonemap_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    format: wgpu::TextureFormat,
    mapper: u32,
) -> wgpu::RenderPipeline {
    let constants = [("TONE_MAPPER", f64::from(mapper))];
    super::pipelines::fullscreen_pipeline(
        device,
        "sward.tonemap.pipeline",
        layout,
        module,
        ("vs_tonemap", "fs_tonemap"),
        format,
        None,
        &constants,
    )
}
