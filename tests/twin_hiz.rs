//! The GPU depth pyramid against its CPU twin: a real depth buffer (triangles rendered at
//! known depths, at odd and even sizes) goes through `DepthPyramid`; level 0 must equal the
//! depth read-back, every level must equal `build_pyramid` exactly (max does not round),
//! and every level must cover the depths below it. With MSAA the depth buffer is
//! multisampled: level 0 must be the farthest sample of each pixel (`farthest_samples` over
//! every sample, dumped by a compute pass since multisampled textures cannot be copied).

mod common;

use sward::gpu::Gpu;
use sward::render::hiz::DepthPyramid;
use sward::render::target::{depth_view, read_texels};
use sward::sim::reference::hiz::{build_pyramid, farthest_samples, level_size};

/// A sloped quad over the whole screen (depth 0.6 top-left .. 0.95 bottom-right, so the
/// farthest pixels sit in the last row and column: the ones an odd size folds in) and two
/// nearer triangles in front of it.
const SCENE_WGSL: &str = r"
const POSITIONS = array<vec3<f32>, 12>(
    vec3(-1.0, -1.0, 0.75), vec3(1.0, -1.0, 0.95), vec3(1.0, 1.0, 0.8),
    vec3(-1.0, -1.0, 0.75), vec3(1.0, 1.0, 0.8), vec3(-1.0, 1.0, 0.6),
    vec3(-0.8, -0.6, 0.2), vec3(0.1, -0.7, 0.3), vec3(-0.3, 0.5, 0.25),
    vec3(0.2, 0.1, 0.45), vec3(0.95, 0.3, 0.4), vec3(0.5, 0.9, 0.5),
);

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    var positions = POSITIONS;
    return vec4(positions[i], 1.0);
}
";

const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

fn depth_pipeline(gpu: &Gpu, samples: u32) -> wgpu::RenderPipeline {
    let module = gpu
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("sward.test.hiz_scene"),
            source: wgpu::ShaderSource::Wgsl(SCENE_WGSL.into()),
        });
    gpu.device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("sward.test.hiz_scene"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState {
                count: samples,
                ..Default::default()
            },
            // Depth only: no colour target, no fragment stage.
            fragment: None,
            multiview_mask: None,
            cache: None,
        })
}

/// Clears `depth` to 1 (far) and draws the scene into it.
fn render(gpu: &Gpu, pipeline: &wgpu::RenderPipeline, depth: &wgpu::TextureView) {
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("sward.test.hiz_scene"),
        });
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("sward.test.hiz_scene"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(pipeline);
        pass.draw(0..12, 0..1);
    }
    gpu.queue.submit([encoder.finish()]);
}

/// Copies a Depth32Float texture back, row-major (blocking).
fn read_depth(gpu: &Gpu, texture: &wgpu::Texture) -> Vec<f32> {
    let bytes = read_texels(
        gpu,
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::DepthOnly,
        },
        (texture.width(), texture.height()),
        "sward.test.depth_readback",
    )
    .expect("depth read-back");
    bytemuck::pod_collect_to_vec(&bytes)
}

fn build(gpu: &Gpu, pyramid: &DepthPyramid, depth: &wgpu::TextureView) -> Vec<Vec<f32>> {
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("sward.test.hiz"),
        });
    pyramid.encode(
        &gpu.device,
        &mut encoder,
        depth,
        sward::gpu::queries::PassQueries::NONE,
    );
    gpu.queue.submit([encoder.finish()]);
    pyramid.read_levels(gpu, depth).expect("pyramid read-back")
}

/// Renders the scene at `width` x `height`, builds the pyramid, checks it against the twin.
fn check(gpu: &Gpu, pipeline: &wgpu::RenderPipeline, width: u32, height: u32) {
    let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("sward.test.hiz_depth"),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: DEPTH_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = texture.create_view(&Default::default());
    render(gpu, pipeline, &view);
    let depth = read_depth(gpu, &texture);
    let at = format!("{width}x{height}");
    // The scene must reach the pyramid: several distinct depths, none left at the clear.
    assert!(depth.iter().all(|&d| d < 1.0), "{at}: quad does not cover");
    if width >= 8 && height >= 8 {
        assert!(
            depth.iter().any(|&d| d < 0.55),
            "{at}: near triangles missing"
        );
    }

    let pyramid = DepthPyramid::new(gpu, width, height);
    assert_eq!(pyramid.size(), (width, height));
    let expected_levels = 32 - width.max(height).leading_zeros();
    assert_eq!(pyramid.levels(), expected_levels, "{at}");
    // Level 0 is the depth buffer itself: the pyramid holds the levels above it.
    let bytes: u64 = (1..expected_levels)
        .map(|k| {
            let (w, h) = level_size(width, height, k);
            w as u64 * h as u64 * 4
        })
        .sum();
    assert_eq!(pyramid.gpu_bytes(), bytes, "{at}");

    let gpu_levels = build(gpu, &pyramid, &view);
    // (a) Level 0, as the cull reads it (the depth view bound as a float texture), is the
    // depth buffer, bit for bit.
    assert_eq!(
        gpu_levels[0], depth,
        "{at}: level 0 is not the depth buffer"
    );

    // (b) Every level equals the twin exactly.
    let cpu_levels = build_pyramid(&gpu_levels[0], width, height);
    assert_eq!(cpu_levels.len(), gpu_levels.len(), "{at}");
    for (k, (g, c)) in gpu_levels.iter().zip(&cpu_levels).enumerate() {
        let (w, h) = level_size(width, height, k as u32);
        assert_eq!(g.len(), (w * h) as usize, "{at}: level {k} size");
        if let Some(i) = (0..g.len()).find(|&i| g[i] != c[i]) {
            panic!(
                "{at}: level {k} ({w}x{h}) texel ({}, {}): GPU {} CPU {}",
                i as u32 % w,
                i as u32 / w,
                g[i],
                c[i]
            );
        }
    }

    // (c) Conservative: each level's texel over a pixel is at least that pixel's depth.
    for (k, level) in gpu_levels.iter().enumerate() {
        let (w, h) = level_size(width, height, k as u32);
        for y in 0..height {
            for x in 0..width {
                let (tx, ty) = ((x >> k).min(w - 1), (y >> k).min(h - 1));
                let d = depth[(y * width + x) as usize];
                let t = level[(ty * w + tx) as usize];
                assert!(
                    t >= d,
                    "{at}: level {k} texel ({tx}, {ty}) = {t} < depth {d} at ({x}, {y})"
                );
            }
        }
    }

    // (d) The 1x1 top is the farthest depth of all.
    let far = depth.iter().copied().fold(0.0, f32::max);
    assert_eq!(gpu_levels.last().expect("levels"), &vec![far], "{at}");

    // The renderer's own depth buffer (`target::depth_view`) is bindable, and the same
    // pyramid rebuilt from another view (level 0's bind group is per call) sees it.
    let target_depth = depth_view(&gpu.device, width, height);
    render(gpu, pipeline, &target_depth);
    assert_eq!(
        build(gpu, &pyramid, &target_depth),
        gpu_levels,
        "{at}: pyramid of target::depth_view differs"
    );
}

#[test]
fn pyramid_matches_twin_and_covers_the_depths() {
    let gpu = common::gpu();
    let pipeline = depth_pipeline(&gpu, 1);
    // Odd in both axes, even (a clean halving), tall and thin, a single pixel, and the
    // smallest pyramids the fused copy of levels 0 and 1 writes alone (one column; two
    // levels, the copy the only pass).
    for (w, h) in [(37, 23), (16, 8), (3, 29), (1, 1), (1, 5), (2, 1)] {
        check(&gpu, &pipeline, w, h);
    }
}

#[test]
fn reading_a_missing_level_is_an_error() {
    let gpu = common::gpu();
    let pyramid = DepthPyramid::new(&gpu, 8, 4);
    assert_eq!(pyramid.levels(), 4);
    assert!(pyramid.read_level(&gpu, 4).is_err());
    // Level 0 is the depth buffer, not the pyramid's: `read_levels` reads it from there.
    assert!(pyramid.read_level(&gpu, 0).is_err());
    assert!(pyramid.read_level(&gpu, 3).is_ok());
}

#[test]
fn multisampled_pyramid_keeps_the_farthest_sample() {
    let gpu = common::gpu();
    const SAMPLES: u32 = 4;
    let pipeline = depth_pipeline(&gpu, SAMPLES);
    for (width, height) in [(37, 23), (16, 8)] {
        let at = format!("{width}x{height} x{SAMPLES}");
        let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("sward.test.hiz_depth_ms"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: SAMPLES,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        render(&gpu, &pipeline, &view);
        let pyramid = DepthPyramid::with_samples(&gpu, width, height, SAMPLES);
        assert_eq!(pyramid.samples(), SAMPLES);
        let samples = pyramid
            .read_depth_samples(&gpu, &view)
            .expect("sample dump");
        assert_eq!(samples.len(), (width * height * SAMPLES) as usize, "{at}");
        // The edges of the near triangles cut through pixels: some pixels must hold
        // different depths in their samples, or the reduction would not be tested.
        let mixed = samples
            .chunks_exact(SAMPLES as usize)
            .filter(|s| s.iter().any(|&d| d != s[0]))
            .count();
        assert!(
            mixed > 10,
            "{at}: only {mixed} pixels with differing samples"
        );
        assert!(
            samples.iter().all(|&d| d < 1.0),
            "{at}: quad does not cover"
        );

        let gpu_levels = build(&gpu, &pyramid, &view);
        let level0 = farthest_samples(&samples, SAMPLES as usize);
        assert_eq!(
            gpu_levels[0], level0,
            "{at}: level 0 is not the farthest sample"
        );
        // Farther than the nearest sample where they differ: the max, not any sample.
        let nearest: Vec<f32> = samples
            .chunks_exact(SAMPLES as usize)
            .map(|s| s.iter().copied().fold(1.0, f32::min))
            .collect();
        assert!(
            level0.iter().zip(&nearest).filter(|(f, n)| f > n).count() == mixed,
            "{at}"
        );
        assert_eq!(
            build_pyramid(&level0, width, height),
            gpu_levels,
            "{at}: upper levels differ from the twin"
        );
    }
}
