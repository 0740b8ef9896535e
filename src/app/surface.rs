//! The window's wgpu surface and its depth buffer: configuration (sRGB format, vsync on or
//! off, COPY_SRC when the platform allows it so `--screenshot` can read the frame back),
//! resizing (a zero size while minimised is kept out of the configuration), and every
//! status `get_current_texture` can return.

use sward::error::{Error, Result};
use sward::gpu::Gpu;
use sward::render::target::depth_view;

/// What acquiring the next frame gave.
pub enum Acquired {
    Frame(wgpu::SurfaceTexture),
    /// No frame this time (timeout, occluded, minimised, just reconfigured): try the next.
    Skip,
}

/// The surface, its configuration and the matching depth buffer.
pub struct SurfaceState {
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    depth: wgpu::TextureView,
    /// The window is minimised (size 0): frames are skipped until it comes back.
    minimised: bool,
    /// Reconfigure before the next frame (the last texture was suboptimal).
    stale: bool,
}

impl SurfaceState {
    /// Configures `surface` for `gpu` at `size` (physical pixels).
    pub fn new(
        gpu: &Gpu,
        surface: wgpu::Surface<'static>,
        size: (u32, u32),
        vsync: bool,
    ) -> Result<Self> {
        let caps =
            surface.get_capabilities(gpu.adapter.as_ref().ok_or_else(|| {
                sward::Error::Gpu("the window needs the adapter it opened".into())
            })?);
        // The renderer's lighting ends in linear values: an sRGB target encodes them.
        let format = caps
            .formats
            .iter()
            .copied()
            .find(|f| f.is_srgb())
            .or_else(|| caps.formats.first().copied())
            .ok_or_else(|| {
                Error::Gpu(format!(
                    "{} cannot present to this window (no surface formats)",
                    gpu.info.name
                ))
            })?;
        let mut usage = wgpu::TextureUsages::RENDER_ATTACHMENT;
        if caps.usages.contains(wgpu::TextureUsages::COPY_SRC) {
            usage |= wgpu::TextureUsages::COPY_SRC;
        }
        let present_mode = if vsync {
            wgpu::PresentMode::AutoVsync
        } else {
            wgpu::PresentMode::AutoNoVsync
        };
        let (width, height) = (size.0.max(1), size.1.max(1));
        let config = wgpu::SurfaceConfiguration {
            usage,
            format,
            width,
            height,
            present_mode,
            desired_maximum_frame_latency: 2,
            alpha_mode: caps
                .alpha_modes
                .first()
                .copied()
                .unwrap_or(wgpu::CompositeAlphaMode::Auto),
            // egui blends in gamma space and wants a non-sRGB view of the same texture.
            view_formats: vec![format.remove_srgb_suffix()],
            color_space: wgpu::SurfaceColorSpace::Auto,
        };
        gpu.check_texture("the window", width, height)?;
        surface.configure(&gpu.device, &config);
        Ok(Self {
            depth: depth_view(&gpu.device, width, height),
            surface,
            config,
            minimised: size.0 == 0 || size.1 == 0,
            stale: false,
        })
    }

    pub fn format(&self) -> wgpu::TextureFormat {
        self.config.format
    }

    /// The format egui draws in: the surface's without the sRGB encoding.
    pub fn ui_format(&self) -> wgpu::TextureFormat {
        self.config.format.remove_srgb_suffix()
    }

    /// Whether frames can be read back (`--screenshot`).
    pub fn can_read_back(&self) -> bool {
        self.config.usage.contains(wgpu::TextureUsages::COPY_SRC)
    }

    /// Current size in physical pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.config.width, self.config.height)
    }

    pub fn depth(&self) -> &wgpu::TextureView {
        &self.depth
    }

    /// Follows the window's size. A zero size (minimised) only marks the surface so that
    /// frames are skipped; sizes the device cannot hold are clamped to its limit.
    pub fn resize(&mut self, gpu: &Gpu, size: (u32, u32)) {
        if size.0 == 0 || size.1 == 0 {
            self.minimised = true;
            return;
        }
        self.minimised = false;
        let max = gpu.device.limits().max_texture_dimension_2d;
        let (w, h) = (size.0.min(max), size.1.min(max));
        if (w, h) == (self.config.width, self.config.height) && !self.stale {
            return;
        }
        self.config.width = w;
        self.config.height = h;
        self.reconfigure(gpu);
    }

    fn reconfigure(&mut self, gpu: &Gpu) {
        self.surface.configure(&gpu.device, &self.config);
        self.depth = depth_view(&gpu.device, self.config.width, self.config.height);
        self.stale = false;
    }

    /// The next frame's texture, or `Skip` after handling whatever status came instead.
    pub fn acquire(&mut self, gpu: &Gpu) -> Acquired {
        if self.minimised {
            return Acquired::Skip;
        }
        if self.stale {
            self.reconfigure(gpu);
        }
        match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t) => Acquired::Frame(t),
            wgpu::CurrentSurfaceTexture::Suboptimal(t) => {
                // Usable now; reconfigure before the next one.
                self.stale = true;
                Acquired::Frame(t)
            }
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {
                Acquired::Skip
            }
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                // Lost on the same device: configuring again recreates the swapchain.
                log::info!("surface outdated or lost: reconfiguring");
                self.reconfigure(gpu);
                Acquired::Skip
            }
            wgpu::CurrentSurfaceTexture::Validation => {
                log::warn!("surface validation error while acquiring a frame: skipping it");
                Acquired::Skip
            }
        }
    }
}
