//! An off-screen colour + depth target and its read-back to an RGBA image: the headless path
//! renders into this exactly what the window renders into its surface.

use crate::error::Result;
use crate::gpu::{map_and_read, Gpu};

use super::draw::DEPTH_FORMAT;

/// Colour format of headless renders (sRGB, like a typical surface).
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// Off-screen colour and depth textures.
pub struct Target {
    /// The colour texture ([`COLOR_FORMAT`], single-sampled), copied out by
    /// [`Target::read_image`].
    pub color: wgpu::Texture,
    /// View of the whole colour texture, to render into.
    pub color_view: wgpu::TextureView,
    /// View of the matching [`DEPTH_FORMAT`] depth texture ([`depth_view`]).
    pub depth_view: wgpu::TextureView,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
}

/// Creates a depth texture view of the given size (shared with the window path).
pub fn depth_view(device: &wgpu::Device, width: u32, height: u32) -> wgpu::TextureView {
    let depth = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("sward.target.depth"),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: DEPTH_FORMAT,
        // Copied out: the TAA twin's test reads it back.
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    depth.create_view(&Default::default())
}

impl Target {
    /// Checks, before anything is allocated, that frames of `size` fit the adapter with the
    /// samples it gives for `render.msaa` = `requested_msaa` (`flag` names what set the
    /// size in the error).
    pub fn check_size(gpu: &Gpu, flag: &str, size: (u32, u32), requested_msaa: u32) -> Result<()> {
        let samples = crate::render::msaa::effective_samples(
            gpu,
            crate::render::post::HDR_FORMAT,
            requested_msaa,
        );
        gpu.check_frame_size(flag, size, samples)
    }

    /// Allocates the colour and depth textures of `width` × `height` pixels; fails when the
    /// device cannot hold a texture that size.
    pub fn new(gpu: &Gpu, width: u32, height: u32) -> Result<Self> {
        gpu.check_texture("an image", width, height)?;
        let color = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("sward.target.color"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: COLOR_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let color_view = color.create_view(&Default::default());
        let depth_view = depth_view(&gpu.device, width, height);
        Ok(Self {
            color,
            color_view,
            depth_view,
            width,
            height,
        })
    }

    /// Copies the colour texture back into an RGBA image (blocking).
    pub fn read_image(&self, gpu: &Gpu) -> Result<image::RgbaImage> {
        read_texture(gpu, &self.color)
    }
}

/// Copies one 4-byte-per-texel image of a texture (a mip level, an aspect) back, row-major
/// and tightly packed, blocking: the copy goes through a staging buffer whose rows are
/// padded to wgpu's 256-byte alignment, and the padding is dropped.
pub fn read_texels(
    gpu: &Gpu,
    source: wgpu::TexelCopyTextureInfo,
    size: (u32, u32),
    label: &str,
) -> Result<Vec<u8>> {
    read_texels_sized(gpu, source, size, 4, label)
}

/// [`read_texels`] for texels of `texel_bytes` bytes (8 for a half-float RGBA target, 16
/// for the visibility buffer).
pub fn read_texels_sized(
    gpu: &Gpu,
    source: wgpu::TexelCopyTextureInfo,
    (width, height): (u32, u32),
    texel_bytes: u32,
    label: &str,
) -> Result<Vec<u8>> {
    let row = width * texel_bytes;
    // Buffer rows must be 256-byte aligned for texture copies.
    let padded =
        row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let staging = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: padded as u64 * height as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) });
    encoder.copy_texture_to_buffer(
        source,
        wgpu::TexelCopyBufferInfo {
            buffer: &staging,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(height),
            },
        },
        wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
    );
    gpu.queue.submit([encoder.finish()]);
    let data = map_and_read(gpu, &staging)?;
    let mut out = Vec::with_capacity((row * height) as usize);
    for y in 0..height as usize {
        let start = y * padded as usize;
        out.extend_from_slice(&data[start..start + row as usize]);
    }
    Ok(out)
}

/// Copies a half-float RGBA texture's first mip level (`post::HDR_FORMAT`, the sky's
/// table) of `size` back as f32 texels, row-major, blocking.
pub fn read_rgba16f(
    gpu: &Gpu,
    texture: &wgpu::Texture,
    size: (u32, u32),
    label: &str,
) -> Result<Vec<[f32; 4]>> {
    let source = wgpu::TexelCopyTextureInfo {
        texture,
        mip_level: 0,
        origin: wgpu::Origin3d::ZERO,
        aspect: wgpu::TextureAspect::All,
    };
    let bytes = read_texels_sized(gpu, source, size, 8, label)?;
    let half = |t: &[u8], i: usize| {
        super::taa::reference::f16_to_f32(u16::from_le_bytes([t[2 * i], t[2 * i + 1]]))
    };
    Ok(bytes
        .chunks_exact(8)
        .map(|t| [half(t, 0), half(t, 1), half(t, 2), half(t, 3)])
        .collect())
}

/// Copies an 8-bit RGBA or BGRA colour texture (with COPY_SRC usage) back into an RGBA
/// image, blocking. The window uses it for `--screenshot` on its surface texture, which is
/// often BGRA.
pub fn read_texture(gpu: &Gpu, texture: &wgpu::Texture) -> Result<image::RgbaImage> {
    use wgpu::TextureFormat as F;
    let bgra = match texture.format() {
        F::Rgba8Unorm | F::Rgba8UnormSrgb => false,
        F::Bgra8Unorm | F::Bgra8UnormSrgb => true,
        other => {
            return Err(crate::Error::Gpu(format!(
                "cannot read back a texture of format {other:?}: only 8-bit RGBA/BGRA"
            )))
        }
    };
    let (width, height) = (texture.width(), texture.height());
    let mut pixels = read_texels(
        gpu,
        texture.as_image_copy(),
        (width, height),
        "sward.target.readback",
    )?;
    if bgra {
        for px in pixels.chunks_exact_mut(4) {
            px.swap(0, 2);
        }
    }
    Ok(image::RgbaImage::from_raw(width, height, pixels)
        .expect("buffer size matches the image size by construction"))
}
