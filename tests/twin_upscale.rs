//! The upscale pass (the frame budget's lower render resolution, stretched over the window)
//! against its CPU twin: random sRGB images at several ratios, within 2/255 per channel
//! (the GPU filters with a few bits of sub-texel precision).

mod common;

use sward::render::target::{Target, COLOR_FORMAT};
use sward::render::upscale::{upscale_cpu, Upscale};

#[test]
fn the_gpu_upscale_matches_the_cpu_twin() {
    let gpu = common::gpu();
    let mut pass = Upscale::new(&gpu, COLOR_FORMAT);
    let mut seed = 12345u64;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 56) as u8
    };
    let mut worst = 0u8;
    // The last case stretches over part of the output (the window's view beside its panel):
    // the region matches the twin at the region's size, the rest is cleared to black.
    for (src, dst, left) in [
        ((5, 3), (13, 7), 0),
        ((16, 9), (32, 18), 0),
        ((7, 7), (10, 9), 0),
        ((9, 8), (24, 12), 7),
    ] {
        let image = image::RgbaImage::from_fn(src.0, src.1, |_, _| {
            image::Rgba([next(), next(), next(), 255])
        });
        pass.target(&gpu, src);
        let texture = pass.color_texture().expect("allocated");
        gpu.queue.write_texture(
            texture.as_image_copy(),
            image.as_raw(),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(4 * src.0),
                rows_per_image: None,
            },
            texture.size(),
        );
        let out = Target::new(&gpu, dst.0, dst.1).expect("target");
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("sward.test.upscale"),
            });
        pass.encode(
            &mut encoder,
            &out.color_view,
            [left, 0, dst.0 - left, dst.1],
            sward::gpu::queries::PassQueries::NONE,
        );
        gpu.queue.submit([encoder.finish()]);
        let gpu_image = out.read_image(&gpu).expect("read back");
        let cpu_image = upscale_cpu(&image, dst.0 - left, dst.1);
        for (x, y, g) in gpu_image.enumerate_pixels() {
            let c = if x >= left {
                *cpu_image.get_pixel(x - left, y)
            } else {
                image::Rgba([0, 0, 0, 255])
            };
            for i in 0..4 {
                worst = worst.max(g[i].abs_diff(c[i]));
            }
        }
    }
    eprintln!("upscale: largest GPU/CPU difference {worst}/255");
    assert!(worst <= 2, "GPU and CPU upscale differ by {worst}/255");
    gpu.check_errors().expect("no GPU error");
}
