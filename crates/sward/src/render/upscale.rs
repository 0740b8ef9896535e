//! Render scale: the 3D passes (grass, terrain, sky, arrows) drawn into an off-screen
//! target smaller than the window, then stretched over it with bilinear filtering before the
//! panel is drawn at full resolution. The window's frame budget lowers the scale before it
//! takes any grass away (see `app::adaptive`): fewer pixels cost sharpness, not blades.
//!
//! [`upscale_cpu`] is the CPU twin of `shaders/upscale.wgsl` (sRGB decoded, filtered in
//! linear light, encoded again, as the GPU's sRGB texture and view do).

use crate::gpu::Gpu;
use crate::render::target::depth_view;

/// The smallest side of the scaled target, in pixels.
const MIN_SIDE: u32 = 1;

/// The size the 3D passes draw at for a window of `full` pixels at `scale` (each side
/// rounded, at least one pixel; `scale` ≥ 1 or not finite gives the full size).
pub fn scaled_size(full: (u32, u32), scale: f32) -> (u32, u32) {
    if !(scale.is_finite() && scale < 1.0) {
        return full;
    }
    let s = scale.max(0.0);
    let side = |n: u32| ((n as f32 * s).round() as u32).clamp(MIN_SIDE, n.max(MIN_SIDE));
    (side(full.0), side(full.1))
}

/// The off-screen colour + depth target of the scaled 3D passes and the pass that
/// stretches it over the window.
pub struct Upscale {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
    format: wgpu::TextureFormat,
    /// The target at its current size: (size, colour view, depth view, bind group).
    target: Option<Scaled>,
}

struct Scaled {
    size: (u32, u32),
    texture: wgpu::Texture,
    color: wgpu::TextureView,
    depth: wgpu::TextureView,
    bind_group: wgpu::BindGroup,
}

impl Upscale {
    /// The pass for colour targets of `format` (the window's surface format).
    pub fn new(gpu: &Gpu, format: wgpu::TextureFormat) -> Self {
        let device = &gpu.device;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.upscale.layout"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sward.upscale.pipeline_layout"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let module = crate::shaders::module(device, "upscale.wgsl");
        let pipeline = super::pipelines::fullscreen_pipeline(
            device,
            "sward.upscale.pipeline",
            &pipeline_layout,
            &module,
            ("vs_upscale", "fs_upscale"),
            format,
            None,
            &[],
        );
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("sward.upscale.sampler"),
            address_mode_u: wgpu::AddressMode::ClampToEdge,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        Self {
            pipeline,
            layout,
            sampler,
            format,
            target: None,
        }
    }

    /// The colour and depth views to draw the 3D passes into at `size`, (re)allocated when
    /// the size changed.
    pub fn target(
        &mut self,
        gpu: &Gpu,
        size: (u32, u32),
    ) -> (&wgpu::TextureView, &wgpu::TextureView) {
        if self.target.as_ref().map(|t| t.size) != Some(size) {
            self.target = Some(self.allocate(gpu, size));
        }
        let t = self.target.as_ref().expect("allocated above");
        (&t.color, &t.depth)
    }

    fn allocate(&self, gpu: &Gpu, size: (u32, u32)) -> Scaled {
        let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("sward.upscale.color"),
            size: wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: self.format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let color = texture.create_view(&Default::default());
        let bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sward.upscale.bind_group"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&color),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Sampler(&self.sampler),
                },
            ],
        });
        Scaled {
            size,
            texture,
            color,
            depth: depth_view(&gpu.device, size.0, size.1),
            bind_group,
        }
    }

    /// The off-screen colour texture, for tests that fill it directly.
    pub fn color_texture(&self) -> Option<&wgpu::Texture> {
        self.target.as_ref().map(|t| &t.texture)
    }

    /// Stretches the scaled image over `region` of `output` (x, y, width, height in pixels:
    /// all of it, or the window's view beside its panel; `output` is the window's view or
    /// any view of the pass's format) and clears the rest. Does nothing before the first
    /// [`Upscale::target`].
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        output: &wgpu::TextureView,
        region: [u32; 4],
        q: crate::gpu::queries::PassQueries,
    ) {
        let Some(t) = &self.target else {
            return;
        };
        let mut pass = super::pipelines::fullscreen_pass(encoder, "sward.upscale.pass", output, &q);
        q.begin(&mut pass);
        let [x, y, w, h] = region.map(|v| v as f32);
        pass.set_viewport(x, y, w, h, 0.0, 1.0);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &t.bind_group, &[]);
        pass.draw(0..3, 0..1);
        q.end(&mut pass);
    }
}

fn srgb_to_linear(c: u8) -> f32 {
    let c = c as f32 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

fn linear_to_srgb(c: f32) -> u8 {
    let c = c.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

/// CPU twin of the upscale pass for sRGB images: each output pixel centre maps to
/// `uv = (x + 0.5) / width`, sampled bilinearly (texel centres at half-integers, edges
/// clamped) in linear light; alpha is 1.
pub fn upscale_cpu(src: &image::RgbaImage, width: u32, height: u32) -> image::RgbaImage {
    let (sw, sh) = (src.width() as i64, src.height() as i64);
    let texel = |x: i64, y: i64| {
        let p = src.get_pixel(x.clamp(0, sw - 1) as u32, y.clamp(0, sh - 1) as u32);
        [
            srgb_to_linear(p[0]),
            srgb_to_linear(p[1]),
            srgb_to_linear(p[2]),
        ]
    };
    image::RgbaImage::from_fn(width, height, |x, y| {
        let u = (x as f32 + 0.5) / width as f32 * sw as f32 - 0.5;
        let v = (y as f32 + 0.5) / height as f32 * sh as f32 - 0.5;
        let (x0, y0) = (u.floor(), v.floor());
        let (fx, fy) = (u - x0, v - y0);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let (a, b) = (texel(x0, y0), texel(x0 + 1, y0));
        let (c, d) = (texel(x0, y0 + 1), texel(x0 + 1, y0 + 1));
        let mut out = [0u8; 4];
        for i in 0..3 {
            let top = a[i] + (b[i] - a[i]) * fx;
            let bottom = c[i] + (d[i] - c[i]) * fx;
            out[i] = linear_to_srgb(top + (bottom - top) * fy);
        }
        out[3] = 255;
        image::Rgba(out)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scaled_sizes_round_and_never_vanish() {
        assert_eq!(scaled_size((1280, 720), 1.0), (1280, 720));
        assert_eq!(scaled_size((1280, 720), 0.5), (640, 360));
        assert_eq!(scaled_size((1280, 720), 0.71), (909, 511));
        assert_eq!(scaled_size((3, 1), 0.1), (1, 1));
        assert_eq!(scaled_size((640, 360), f32::NAN), (640, 360));
        assert_eq!(scaled_size((640, 360), 2.0), (640, 360));
    }

    #[test]
    fn the_cpu_twin_keeps_flat_colours_and_interpolates_between_texels() {
        let flat = image::RgbaImage::from_pixel(3, 2, image::Rgba([40, 120, 200, 255]));
        let up = upscale_cpu(&flat, 7, 5);
        assert!(up.pixels().all(|p| p.0 == [40, 120, 200, 255]));
        // Black | white: the middle of a 2x upscale is half-way in linear light.
        let mut two = image::RgbaImage::new(2, 1);
        two.put_pixel(0, 0, image::Rgba([0, 0, 0, 255]));
        two.put_pixel(1, 0, image::Rgba([255, 255, 255, 255]));
        let up = upscale_cpu(&two, 4, 1);
        assert_eq!(up.get_pixel(0, 0)[0], 0);
        assert_eq!(up.get_pixel(3, 0)[0], 255);
        // u = 0.25 → weight 0.25 of white: sRGB(0.25) = 137.
        assert_eq!(up.get_pixel(1, 0)[0], 137);
    }
}
