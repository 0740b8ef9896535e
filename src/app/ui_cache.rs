//! The panel drawn once, shown every frame. egui's render pass cost the window 10.8 ms of
//! GPU time per frame at 1280x720 on llvmpipe (issue 26, point 7), though the panel's
//! picture changes only when the user touches it or the Stats refresh. egui now draws into
//! a cache texture of the window's size and format only when its tessellated output (each
//! job's clip rectangle and mesh), its textures, the window's size or its scale changed;
//! every frame one full-screen triangle, scissored to the pixels egui drew, copies the
//! cache over the frame with egui's own premultiplied blending (`shaders/ui_composite.wgsl`),
//! so the picture is the one egui would have drawn there directly.

use egui::epaint::{ClippedPrimitive, Mesh, Primitive};

/// The last output drawn into the cache: each job's clip rectangle and mesh, and the
/// pixels per point it was tessellated at.
#[derive(Default)]
struct Painted {
    jobs: Vec<(egui::Rect, Mesh)>,
    pixels_per_point: f32,
}

impl Painted {
    /// Whether `jobs` at `ppp` are what the cache holds. A paint callback is never the
    /// same (it draws what it likes).
    fn holds(&self, jobs: &[ClippedPrimitive], ppp: f32) -> bool {
        self.pixels_per_point == ppp
            && self.jobs.len() == jobs.len()
            && self.jobs.iter().zip(jobs).all(|((rect, mesh), job)| {
                *rect == job.clip_rect && matches!(&job.primitive, Primitive::Mesh(m) if m == mesh)
            })
    }

    fn of(jobs: &[ClippedPrimitive], ppp: f32) -> Self {
        Self {
            jobs: jobs
                .iter()
                .filter_map(|j| match &j.primitive {
                    Primitive::Mesh(m) => Some((j.clip_rect, m.clone())),
                    Primitive::Callback(_) => None,
                })
                .collect(),
            pixels_per_point: ppp,
        }
    }
}

/// The pixels `jobs` cover, `[x0, y0, x1, y1]` (end exclusive) within a window of `size`:
/// each mesh's vertices' bounds inside its clip rectangle, in points times `ppp`, rounded
/// outwards. `None` when nothing is drawn.
pub fn painted_bounds(jobs: &[ClippedPrimitive], ppp: f32, size: (u32, u32)) -> Option<[u32; 4]> {
    let mut all = egui::Rect::NOTHING;
    for job in jobs {
        let rect = match &job.primitive {
            Primitive::Mesh(m) => m.calc_bounds().intersect(job.clip_rect),
            Primitive::Callback(c) => c.rect.intersect(job.clip_rect),
        };
        if rect.is_positive() {
            all = all.union(rect);
        }
    }
    if !all.is_positive() {
        return None;
    }
    let clamp = |v: f32, max: u32| (v.max(0.0) as u32).min(max);
    let x0 = clamp((all.min.x * ppp).floor(), size.0);
    let y0 = clamp((all.min.y * ppp).floor(), size.1);
    let x1 = clamp((all.max.x * ppp).ceil(), size.0);
    let y1 = clamp((all.max.y * ppp).ceil(), size.1);
    (x1 > x0 && y1 > y0).then_some([x0, y0, x1, y1])
}

/// The cache texture, what it holds, and the pass that composites it.
pub struct UiCache {
    format: wgpu::TextureFormat,
    size: (u32, u32),
    view: wgpu::TextureView,
    group: wgpu::BindGroup,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    /// What the cache holds; `None` until drawn (and after a resize).
    painted: Option<Painted>,
    /// The pixels the cached output covers.
    bounds: Option<[u32; 4]>,
}

impl UiCache {
    /// A cache for a window of `size` whose egui pass draws `format` (the surface's format
    /// without its sRGB suffix: egui blends in gamma space, and so does the composite).
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat, size: (u32, u32)) -> Self {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.window.ui_cache.layout"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            }],
        });
        let module = sward::shaders::module(device, "ui_composite.wgsl");
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sward.window.ui_cache.pipeline_layout"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        // egui's own blending: premultiplied colour over the frame.
        let pipeline = sward::render::pipelines::fullscreen_pipeline(
            device,
            "sward.window.ui_composite",
            &pipeline_layout,
            &module,
            ("vs_composite", "fs_composite"),
            format,
            Some(wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING),
            &[],
        );
        let (view, group) = Self::texture(device, format, size, &layout);
        Self {
            format,
            size,
            view,
            group,
            layout,
            pipeline,
            painted: None,
            bounds: None,
        }
    }

    fn texture(
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        size: (u32, u32),
        layout: &wgpu::BindGroupLayout,
    ) -> (wgpu::TextureView, wgpu::BindGroup) {
        let view = device
            .create_texture(&wgpu::TextureDescriptor {
                label: Some("sward.window.ui_cache"),
                size: wgpu::Extent3d {
                    width: size.0.max(1),
                    height: size.1.max(1),
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            })
            .create_view(&Default::default());
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sward.window.ui_cache.group"),
            layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&view),
            }],
        });
        (view, group)
    }

    /// Takes this frame's egui output: whether the cache must be drawn again (then egui
    /// draws into [`UiCache::view`], cleared to transparent), because the jobs, the window's
    /// `size` or its scale `ppp` changed or `textures_changed` (a font atlas or image
    /// update, which can change the same meshes' pixels). A resize makes a new texture.
    pub fn stale(
        &mut self,
        device: &wgpu::Device,
        jobs: &[ClippedPrimitive],
        textures_changed: bool,
        size: (u32, u32),
        ppp: f32,
    ) -> bool {
        if size != self.size {
            // Dropped first: the old texture is not held beside the new one.
            self.painted = None;
            self.size = size;
            (self.view, self.group) = Self::texture(device, self.format, size, &self.layout);
        }
        let same = !textures_changed && self.painted.as_ref().is_some_and(|p| p.holds(jobs, ppp));
        if same {
            return false;
        }
        self.painted = Some(Painted::of(jobs, ppp));
        self.bounds = painted_bounds(jobs, ppp, size);
        true
    }

    /// The cache texture, egui's target when [`UiCache::stale`] said so.
    pub fn view(&self) -> &wgpu::TextureView {
        &self.view
    }

    /// Draws the cache over the frame in `pass` (a pass into the window's colour, loaded),
    /// within the pixels egui drew; nothing when it drew nothing.
    pub fn composite(&self, pass: &mut wgpu::RenderPass<'_>) {
        let Some([x0, y0, x1, y1]) = self.bounds else {
            return;
        };
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.group, &[]);
        pass.set_scissor_rect(x0, y0, x1 - x0, y1 - y0);
        pass.draw(0..3, 0..1);
    }
}

/// A render pass into `view` alone, loaded with `load` and stored: the panel's two passes
/// (egui into the cache, the cache over the frame).
pub fn pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    view: &wgpu::TextureView,
    load: wgpu::LoadOp<wgpu::Color>,
    timestamps: Option<wgpu::RenderPassTimestampWrites>,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load,
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: None,
        timestamp_writes: timestamps,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}
