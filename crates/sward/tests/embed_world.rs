//! sward's whole world in a host's texture (issue 28, point 2: the application's renderer
//! is built on the embedding API): `GrassRenderer::new_world` and `render_world`, and the
//! host's own 3D pass between `begin_world` and `finish_world`, depth-tested against the
//! world. Only the public API is used, as a host would.
//!
//! Measured at 128x72 on lavapipe: 6,662 blades drawn at 1x and 8,143 at 4x after three
//! frames; the top rows' mean colour is sky, (192, 200, 214) (blue over red: bound 10), the
//! bottom rows' grass, (63, 102, 46); a host triangle at the far plane turns all 1,152 sky
//! pixels of the top rows red and changes none of the ground's (1x and 4x alike).

#[allow(dead_code)]
#[path = "../examples/embed.rs"]
mod example;

use sward::embed::{
    FrameInputs, GrassRenderer, GrassRendererDescriptor, SceneSource, WorldDescriptor, WorldTarget,
    WORLD_DEPTH_FORMAT, WORLD_RADIANCE_FORMAT,
};

const SIZE: (u32, u32) = (128, 72);
const COLOR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// A small field seen from above its edge: sky in the top rows, grass below.
fn scene(msaa: u32) -> String {
    format!(
        "(terrain: (size: 10.0, height: Flat), field: (density: 150.0, height: (min: 0.4, \
         max: 0.6)), camera: (eye: (0.0, 1.2, 4.5), target: (0.0, 0.4, 0.0), fov_y: 60.0, \
         near: 0.05, far: 500.0), \
         render: (msaa: {msaa}))"
    )
}

fn texture(
    device: &wgpu::Device,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
    size: (u32, u32),
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("world-host.target"),
        size: wgpu::Extent3d {
            width: size.0,
            height: size.1,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// The host's textures for a world frame of `size`.
struct Host {
    device: wgpu::Device,
    queue: wgpu::Queue,
    color: wgpu::Texture,
    color_view: wgpu::TextureView,
    depth_view: wgpu::TextureView,
}

impl Host {
    fn new(size: (u32, u32)) -> Self {
        let (device, queue) = example::open().expect("device");
        let attach = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let color = texture(&device, COLOR, attach | wgpu::TextureUsages::COPY_SRC, size);
        let depth = texture(
            &device,
            WORLD_DEPTH_FORMAT,
            attach | wgpu::TextureUsages::TEXTURE_BINDING,
            size,
        );
        Self {
            color_view: color.create_view(&Default::default()),
            depth_view: depth.create_view(&Default::default()),
            device,
            queue,
            color,
        }
    }

    fn target(&self) -> WorldTarget<'_> {
        WorldTarget {
            color: &self.color_view,
            depth: &self.depth_view,
        }
    }
}

fn inputs(world: &GrassRenderer) -> FrameInputs<'static> {
    FrameInputs {
        camera: sward::CameraView::from_scene(&world.scene().camera),
        size: SIZE,
        dt: 1.0 / 30.0,
        colliders: &[],
        depth: None,
        wind: None,
    }
}

/// Mean colour of the rows `rows` of `image`.
fn mean(image: &image::RgbaImage, rows: std::ops::Range<u32>) -> [f64; 3] {
    let mut m = [0.0; 3];
    let mut n = 0.0;
    for y in rows {
        for x in 0..image.width() {
            let p = image.get_pixel(x, y).0;
            for c in 0..3 {
                m[c] += f64::from(p[c]);
            }
            n += 1.0;
        }
    }
    m.map(|v| v / n)
}

/// A red triangle over the whole view at the far plane, drawn into the world's radiance
/// and depth with `LessEqual`: it shows only where nothing nearer was drawn.
fn far_plane_pipeline(device: &wgpu::Device, samples: u32) -> wgpu::RenderPipeline {
    let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("world-host.far_plane"),
        source: wgpu::ShaderSource::Wgsl(
            "@vertex fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
                 let p = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u)) * 2.0 - 1.0;
                 return vec4<f32>(p, 1.0, 1.0);
             }
             @fragment fn fs() -> @location(0) vec4<f32> {
                 return vec4<f32>(2.0, 0.0, 0.0, 1.0);
             }"
            .into(),
        ),
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("world-host.far_plane"),
        layout: None,
        vertex: wgpu::VertexState {
            module: &shader,
            entry_point: Some("vs"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        fragment: Some(wgpu::FragmentState {
            module: &shader,
            entry_point: Some("fs"),
            compilation_options: Default::default(),
            targets: &[Some(WORLD_RADIANCE_FORMAT.into())],
        }),
        primitive: Default::default(),
        depth_stencil: Some(wgpu::DepthStencilState {
            format: WORLD_DEPTH_FORMAT,
            depth_write_enabled: Some(false),
            depth_compare: Some(wgpu::CompareFunction::LessEqual),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: wgpu::MultisampleState {
            count: samples,
            ..Default::default()
        },
        multiview_mask: None,
        cache: None,
    })
}

/// Renders `frames` world frames; with `far_plane`, the host draws its triangle at the far
/// plane into the world between `begin_world` and `finish_world` in the last one.
fn world_frames(msaa: u32, frames: u32, far_plane: bool) -> (image::RgbaImage, u64) {
    let host = Host::new(SIZE);
    let (device, queue) = (&host.device, &host.queue);
    let mut world = GrassRenderer::new_world(
        device,
        queue,
        WorldDescriptor {
            color_format: COLOR,
            scene: SceneSource::Ron(scene(msaa)),
        },
    )
    .expect("a world");
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    for k in 0..frames {
        let mut encoder = device.create_command_encoder(&Default::default());
        let target = host.target();
        let frame = inputs(&world);
        if far_plane && k + 1 == frames {
            world
                .begin_world(device, queue, &mut encoder, &frame, &target)
                .expect("begin");
            let scene = world.world_scene(&target).expect("a begun frame");
            let pipeline = far_plane_pipeline(device, scene.samples);
            {
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("world-host.far_plane"),
                    color_attachments: &[Some(example::attachment(scene.color, None))],
                    depth_stencil_attachment: Some(example::depth_attachment(scene.depth, false)),
                    ..Default::default()
                });
                pass.set_pipeline(&pipeline);
                pass.draw(0..3, 0..1);
            }
            world.finish_world(&mut encoder, &target).expect("finish");
        } else {
            world
                .render_world(device, queue, &mut encoder, &frame, &target)
                .expect("a world frame");
        }
        queue.submit([encoder.finish()]);
    }
    let error = pollster::block_on(scope.pop());
    assert!(error.is_none(), "device error: {error:?}");
    let drawn = world.drawn_blades().expect("counters");
    let image = example::read_back(device, queue, &host.color, SIZE).expect("read back");
    (image, drawn)
}

#[test]
fn a_world_frame_has_sky_and_grass() {
    for msaa in [1, 4] {
        let (image, drawn) = world_frames(msaa, 3, false);
        let sky = mean(&image, 0..SIZE.1 / 8);
        let ground = mean(&image, SIZE.1 * 3 / 4..SIZE.1);
        eprintln!("{msaa}x: {drawn} blades; sky {sky:.0?}, ground {ground:.0?}");
        assert!(drawn > 1000, "{msaa}x: {drawn} blades drawn");
        assert!(sky[2] > sky[0] + 10.0, "{msaa}x: sky {sky:?}");
        assert!(
            ground[1] > ground[0] && ground[1] > ground[2],
            "{msaa}x: ground {ground:?}"
        );
    }
}

#[test]
fn the_hosts_pass_between_begin_and_finish_is_depth_tested_with_the_world() {
    for msaa in [1, 4] {
        let (plain, _) = world_frames(msaa, 3, false);
        let (host, _) = world_frames(msaa, 3, true);
        // Redder than the frame without the host's pass (the tone curve turns a bright red
        // towards orange: compared by red over blue), and the same where the world is nearer.
        let warmth = |p: &image::Rgba<u8>| i32::from(p.0[0]) - i32::from(p.0[2]);
        let count = |rows: std::ops::Range<u32>, f: &dyn Fn(u32, u32) -> bool| {
            rows.flat_map(|y| (0..SIZE.0).map(move |x| (x, y)))
                .filter(|&(x, y)| f(x, y))
                .count()
        };
        let redder = |x, y| warmth(host.get_pixel(x, y)) > warmth(plain.get_pixel(x, y)) + 40;
        let changed = |x, y| differs(host.get_pixel(x, y), plain.get_pixel(x, y));
        let sky_px = (SIZE.0 * (SIZE.1 / 8)) as usize;
        let sky_red = count(0..SIZE.1 / 8, &redder);
        let ground_changed = count(SIZE.1 * 3 / 4..SIZE.1, &changed);
        eprintln!(
            "{msaa}x: the host's far plane turned {sky_red} of {sky_px} sky pixels red and \
             changed {ground_changed} of the ground's"
        );
        assert_eq!(
            sky_red, sky_px,
            "{msaa}x: the far plane shows through the whole sky"
        );
        assert_eq!(
            ground_changed, 0,
            "{msaa}x: the far plane drew over the ground"
        );
    }
}

fn differs(a: &image::Rgba<u8>, b: &image::Rgba<u8>) -> bool {
    a.0.iter().zip(b.0).any(|(x, y)| x.abs_diff(y) > 8)
}

#[test]
fn world_frames_refuse_what_does_not_fit() {
    let host = Host::new(SIZE);
    let (device, queue) = (&host.device, &host.queue);
    let small = "(terrain: (size: 8.0, height: Flat), field: (density: 20.0))";
    let mut world = GrassRenderer::new_world(
        device,
        queue,
        WorldDescriptor {
            color_format: COLOR,
            scene: SceneSource::Ron(small.into()),
        },
    )
    .expect("a world");
    let e = GrassRenderer::new_world(
        device,
        queue,
        WorldDescriptor {
            color_format: WORLD_DEPTH_FORMAT,
            scene: SceneSource::Ron(small.into()),
        },
    )
    .err()
    .expect("a depth colour format");
    assert!(e.to_string().contains("color_format"), "{e}");
    // A scene file that is not there is named.
    let e = GrassRenderer::new_world(
        device,
        queue,
        WorldDescriptor {
            color_format: COLOR,
            scene: SceneSource::File("no/such/scene.ron".into()),
        },
    )
    .err()
    .expect("a missing file");
    assert!(e.to_string().contains("no/such/scene.ron"), "{e}");
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let mut encoder = device.create_command_encoder(&Default::default());
    let good = inputs(&world);
    let target = host.target();
    let err = |r: sward::Result<()>| r.expect_err("refused").to_string();
    // An empty frame and one larger than any texture the device can make.
    for size in [(0, 72), (1 << 20, 72)] {
        let mut odd = inputs(&world);
        odd.size = size;
        let e = err(world.render_world(device, queue, &mut encoder, &odd, &target));
        assert!(
            e.contains("out of range") || e.contains("allowed"),
            "{size:?}: {e}"
        );
    }
    // A host-pass call on a world renderer, and finishing what was not begun.
    let e = err(world.prepare(device, queue, &mut encoder, &good));
    assert!(e.contains("new_world"), "{e}");
    let e = err(world.finish_world(&mut encoder, &target));
    assert!(e.contains("begin_world"), "{e}");
    assert!(world.world_scene(&target).is_none());
    // The host's depth belongs to a host pass.
    let mut with_depth = inputs(&world);
    with_depth.depth = Some(&host.depth_view);
    let e = err(world.render_world(device, queue, &mut encoder, &with_depth, &target));
    assert!(e.contains("FrameInputs::depth"), "{e}");
    // A frame size other than the target's, a depth in the colour's place.
    let mut bigger = inputs(&world);
    bigger.size = (SIZE.0 * 2, SIZE.1);
    let e = err(world.render_world(device, queue, &mut encoder, &bigger, &target));
    assert!(
        e.contains("WorldTarget::color") && e.contains("128x72"),
        "{e}"
    );
    let swapped = WorldTarget {
        color: &host.depth_view,
        depth: &host.color_view,
    };
    let e = err(world.render_world(device, queue, &mut encoder, &good, &swapped));
    assert!(e.contains("WorldTarget::color"), "{e}");
    // A camera at infinity.
    let mut far = inputs(&world);
    far.camera.far = f32::INFINITY;
    let e = err(world.render_world(device, queue, &mut encoder, &far, &target));
    assert!(e.contains("far"), "{e}");
    // A world call on a host-pass renderer.
    let mut grass = GrassRenderer::new(
        device,
        queue,
        GrassRendererDescriptor {
            color_format: COLOR,
            depth_format: WORLD_DEPTH_FORMAT,
            sample_count: 1,
            output: sward::ColorOutput::ToneMapped,
            scene: SceneSource::Ron(small.into()),
        },
    )
    .expect("a host-pass renderer");
    let e = err(grass.render_world(device, queue, &mut encoder, &good, &target));
    assert!(e.contains("GrassRenderer::new"), "{e}");
    // A frame finished into a target other than the one it was begun for: refused, and the
    // frame stays begun until finished right.
    let small = texture(
        device,
        COLOR,
        wgpu::TextureUsages::RENDER_ATTACHMENT,
        (SIZE.0 / 2, SIZE.1 / 2),
    )
    .create_view(&Default::default());
    world
        .begin_world(device, queue, &mut encoder, &good, &target)
        .expect("begin");
    let wrong = WorldTarget {
        color: &small,
        depth: &host.depth_view,
    };
    let e = err(world.finish_world(&mut encoder, &wrong));
    assert!(
        e.contains("WorldTarget::color") && e.contains("64x36"),
        "{e}"
    );
    assert!(
        world.world_scene(&target).is_some(),
        "the frame stays begun"
    );
    world
        .finish_world(&mut encoder, &target)
        .expect("finished right");
    // Nothing was recorded by the refusals: a good frame follows without a device error.
    world
        .render_world(device, queue, &mut encoder, &good, &target)
        .expect("a good frame");
    queue.submit([encoder.finish()]);
    let error = pollster::block_on(scope.pop());
    assert!(error.is_none(), "device error: {error:?}");
}
