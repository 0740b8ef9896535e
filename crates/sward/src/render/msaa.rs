//! Multisample anti-aliasing of the 3D passes: the sample count the adapter can give for the
//! colour and depth formats, and the multisampled colour + depth textures the passes draw
//! into before they are resolved into the single-sample colour that follows (the window's
//! surface, the headless target, or the render-scale target stretched over the window).
//!
//! Thin blades cover a fraction of a pixel; with one sample per pixel each blade is either
//! drawn or not, and it flickers from frame to frame as the wind moves it. With several
//! samples the pixel takes the covered share of the blade's colour.

use super::draw::DEPTH_FORMAT;
use super::timing::{self, timed};
use super::Renderer;
use crate::gpu::Gpu;

pub use crate::scene::limits::SAMPLE_COUNTS;

/// Whether the device can render `format` with `samples` samples per pixel. Without the
/// adapter-specific format features the device validates against WebGPU's guaranteed ones
/// (1× and 4× for renderable formats), whatever the adapter itself could do.
pub(super) fn format_supports(gpu: &Gpu, format: wgpu::TextureFormat, samples: u32) -> bool {
    let device_features = gpu.device.features();
    // A host's device comes without its adapter: the guaranteed features then.
    let adapter = gpu.adapter.as_ref().filter(|_| {
        device_features.contains(wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES)
    });
    let features = match adapter {
        Some(a) => a.get_texture_format_features(format),
        None => format.guaranteed_format_features(device_features),
    };
    features.flags.sample_count_supported(samples)
}

/// The sample count to draw with when `requested` are asked for and the colour target is
/// `format`: `requested` where both it and the depth format support it, otherwise the
/// largest supported count below it (with a warning; 1 always works).
pub fn effective_samples(gpu: &Gpu, format: wgpu::TextureFormat, requested: u32) -> u32 {
    let fits = |n: u32| {
        n == 1 || (format_supports(gpu, format, n) && format_supports(gpu, DEPTH_FORMAT, n))
    };
    let effective = SAMPLE_COUNTS
        .iter()
        .copied()
        .rev()
        .filter(|&n| n <= requested.max(1))
        .find(|&n| fits(n))
        .unwrap_or(1);
    if effective != requested {
        log::warn!(
            "{} cannot draw {format:?} + {DEPTH_FORMAT:?} with {requested}× MSAA: using {effective}×",
            gpu.info.name
        );
    }
    effective
}

/// The multisampled colour and depth textures of the 3D passes at one size.
pub struct MsaaTarget {
    /// Samples per pixel of both textures (> 1).
    pub samples: u32,
    /// Width and height in pixels.
    pub size: (u32, u32),
    /// The colour texture's format (the depth is [`DEPTH_FORMAT`]).
    pub format: wgpu::TextureFormat,
    /// Drawn into, then resolved into the caller's colour (and read by the deferred grass
    /// light after the resolve).
    pub color: wgpu::TextureView,
    /// Kept between the passes of a frame (occluders → draw → late draw → arrows) and read
    /// by the depth pyramid (`texture_depth_multisampled_2d`).
    pub depth: wgpu::TextureView,
}

impl MsaaTarget {
    /// Allocates both textures (`samples` > 1; the caller checked the device supports it).
    pub fn new(gpu: &Gpu, format: wgpu::TextureFormat, samples: u32, size: (u32, u32)) -> Self {
        let texture = |label, format, usage| {
            gpu.device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: wgpu::Extent3d {
                        width: size.0.max(1),
                        height: size.1.max(1),
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: samples,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage,
                    view_formats: &[],
                })
                .create_view(&Default::default())
        };
        Self {
            samples,
            size,
            format,
            // Read by the deferred grass light, which resolves the grass pixels itself.
            color: texture(
                "sward.msaa.color",
                format,
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            ),
            depth: texture(
                "sward.msaa.depth",
                DEPTH_FORMAT,
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            ),
        }
    }

    /// Records the resolve of the multisampled colour into `output` (single-sample, same
    /// format and size): an empty pass whose colour attachment resolves at its end. `keep`:
    /// the samples are read afterwards (the deferred grass light); otherwise discarded.
    pub fn resolve(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        output: &wgpu::TextureView,
        keep: bool,
    ) {
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("sward.msaa.resolve"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &self.color,
                depth_slice: None,
                resolve_target: Some(output),
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: if keep {
                        wgpu::StoreOp::Store
                    } else {
                        wgpu::StoreOp::Discard
                    },
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
    }
}

/// The renderer's multisampling: the sample count in use, kept in step with `render.msaa`
/// and the frame budget's cap, and the views the 3D passes draw into.
impl Renderer {
    /// Caps the samples per pixel below `render.msaa` (the window's frame budget switching
    /// multisampling off) without changing the scene; `None` lifts the cap.
    pub fn set_sample_cap(&mut self, cap: Option<u32>) {
        self.sample_cap = cap;
    }

    /// The sample count the 3D passes draw with: `render.msaa`, or the largest count
    /// below it the adapter supports for the colour and depth formats.
    pub fn msaa_samples(&self) -> u32 {
        self.samples
    }

    /// Applies a changed `render.msaa` (the panel): the pipelines and targets are rebuilt
    /// for the new sample count before the next frame.
    pub(super) fn sync_msaa(&mut self, gpu: &Gpu) {
        let asked = self.scene.render.msaa;
        let wanted = self.sample_cap.map_or(asked, |cap| asked.min(cap));
        if wanted == self.requested_samples {
            return;
        }
        self.requested_samples = wanted;
        let samples = effective_samples(gpu, super::post::HDR_FORMAT, self.requested_samples);
        if samples == self.samples {
            return;
        }
        self.samples = samples;
        self.draw.set_samples(&gpu.device, samples);
        if let Some(b) = &mut self.billboards {
            b.set_samples(&gpu.device, samples);
        }
        self.msaa = None;
        // The pyramid's copy reads depth of the old sample count.
        self.pyramid = None;
    }

    /// The colour and depth views the 3D passes draw into for a frame whose caller gave
    /// `color` and `depth`: the multisampled pair with MSAA, else the caller's own. The
    /// window draws its arrows into these between [`Renderer::encode_scene`] and
    /// [`Renderer::resolve`].
    pub fn scene_views<'a>(
        &'a self,
        color: &'a wgpu::TextureView,
        depth: &'a wgpu::TextureView,
    ) -> (&'a wgpu::TextureView, &'a wgpu::TextureView) {
        match &self.msaa {
            Some(m) => (&m.color, &m.depth),
            None => (self.post.current().unwrap_or(color), depth),
        }
    }

    /// The scene target after the last frame: linear radiance and alpha per pixel,
    /// row-major (blocking; for tests: the deferred grass marks its share of each pixel in
    /// the alpha, `deferred::BLADE_ALPHA`). `None` before the first frame.
    pub fn read_scene(&self, gpu: &Gpu) -> Option<crate::error::Result<Vec<[f32; 4]>>> {
        self.post.read_target(gpu)
    }

    /// Ends the frame's drawing: resolves the multisampled scene into the scene target
    /// (and lights the deferred grass's pixels in it, `render::deferred`), tone-maps that
    /// into `color` (`post::ToneMap`) and draws the wind overlay over it in
    /// display colours. The frame's queries are resolved after it by
    /// [`Renderer::resolve_queries`], when the caller has added its own passes.
    pub fn resolve(&mut self, encoder: &mut wgpu::CommandEncoder, color: &wgpu::TextureView) {
        // The multisampled deferred grass: its pixels lit once and resolved again, from
        // the samples the resolve keeps.
        let light = self.pending_grass_light.take();
        if let (Some(m), Some(scene)) = (&self.msaa, self.post.current()) {
            m.resolve(encoder, scene, light.is_some());
        }
        if let (Some(light), Some(d), Some(p)) = (light, &self.deferred, self.draw.deferred()) {
            let groups = (self.draw.grass_groups(), self.light.group());
            timed(self.meters(), encoder, timing::GRASS_LIGHT, |e, q| {
                d.encode_light(e, p, groups, &light, (q.row(super::work::GRASS_PIXELS), q))
            });
        }
        // With TAA the tone mapping reads the history the frame was blended into.
        let source = self
            .taa
            .as_ref()
            .filter(|t| t.ready())
            .and_then(|t| timed(self.meters(), encoder, timing::TAA, |e, q| t.encode(e, q)))
            .cloned();
        // The far levels' gain, measured on this frame's lit blades for the next frame's:
        // the blades as shown, in the TAA's history where it blended the frame (it smooths
        // the swaying blades more than the still cards: measured before it, the far levels
        // were 11 levels off what the TAA showed).
        let shown = source
            .as_ref()
            .and(self.taa.as_ref().and_then(|t| t.written()))
            .cloned();
        self.measure_far_gain(encoder, shown);
        timed(self.meters(), encoder, timing::TONEMAP, |e, q| {
            self.post.encode(e, self.light.group(), color, source.as_ref(), q)
        });
        if let Some(t) = &mut self.taa {
            t.finish();
        }
        if let Some(o) = &self.overlay {
            timed(self.meters(), encoder, timing::OVERLAY, |e, q| {
                o.encode(e, color, q)
            });
        }
    }

    /// Records `f`, a pass the caller adds to the frame (the window's guide arrows and its
    /// upscale), inside the GPU timer's scope and the work counter's row of pass `index`
    /// of `timing::PASSES`, so the frame's sums see it. Before [`Renderer::resolve_queries`].
    pub fn encode_timed(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        index: usize,
        f: impl FnOnce(&mut wgpu::CommandEncoder, crate::gpu::queries::PassQueries),
    ) {
        timed(self.meters(), encoder, index, f);
    }

    /// Records the far gain's measurement (`far_gain`) over the frame's resolved radiance,
    /// `shown` (the TAA history it was blended into, if any: the blades are measured as
    /// shown) and the depth its passes drew, when the frame has both.
    fn measure_far_gain(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        shown: Option<wgpu::TextureView>,
    ) {
        let Some(depth) = self.frame_depth.take() else {
            return;
        };
        let Some(color) = self.post.current() else {
            return;
        };
        let tallest = super::light::blade_heights(&self.scene.field).1;
        let cards = self.billboards.is_some();
        // The deferred shading marks its blades' share of each pixel (`BLADE_ALPHA`).
        let marked = self.deferred.is_some();
        let eye = self.last_cull.camera_pos;
        let height = eye[1] - self.terrain.height(eye[0], eye[2]);
        let reach = (self.last_cull.max_distance, height);
        self.far_gain.prepare(reach, tallest, self.frame_count, (cards, marked));
        let inputs = super::far_gain_pass::GainInputs {
            frame: self.draw.frame_buffer(),
            terrain: self.draw.terrain_buffers(),
            state: self.draw.waves_buffer(),
            color,
            shown: shown.as_ref().unwrap_or(color),
            depth: &depth,
            samples: self.samples,
            light: self.light.group(),
        };
        let meters = super::timing::Meters {
            timer: self.timer.as_ref(),
            work: self.work.as_ref(),
        };
        let gain = &mut self.far_gain;
        timed(meters, encoder, timing::FAR_GAIN, |e, q| gain.encode(e, &inputs, q));
    }

    /// Records the resolve of the frame's timestamp and work queries (the last thing a
    /// frame records before `finish`).
    pub fn resolve_queries(&mut self, encoder: &mut wgpu::CommandEncoder) {
        if let Some(t) = &mut self.timer {
            t.resolve(encoder);
        }
        if let Some(w) = &mut self.work {
            w.resolve(encoder);
        }
    }
}
