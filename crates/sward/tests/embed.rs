//! The embedding API (issue 28, points 2 and 3) through the example host
//! (`examples/embed.rs`, compiled in here): a wgpu program with its own device, ground and
//! box draws sward's grass into its own pass, and the billboards beyond the blades.
//!
//! Measured at 160x90 on lavapipe: 25,304 blades drawn after 12 frames, changing 81.5 % of
//! the near field's pixels (bound: 40 %) and none of the sky's; with the host's depth the
//! cull keeps 25,367 blades after 4 frames, without it 26,448 (the box, the ball and the
//! hills hide the rest); the host's world receiving sward's shadows: 820 pixels darker
//! (bound: 20), none brighter; the host's box casting into sward's shadow maps: 56 pixels
//! of grass darker at 480x270 (bound: 30), none brighter; two runs give the same picture.

#[allow(dead_code)]
#[path = "../examples/embed.rs"]
mod example;

use sward::embed::{ColorOutput, FrameInputs, GrassRenderer, GrassRendererDescriptor, SceneSource};

const SIZE: (u32, u32) = (160, 90);
const FRAMES: u32 = 12;

fn differs(a: &image::Rgba<u8>, b: &image::Rgba<u8>) -> bool {
    a.0.iter().zip(b.0).any(|(x, y)| x.abs_diff(y) > 8)
}

#[test]
fn the_host_draws_the_grass_into_its_own_pass() {
    let (with, drawn) = example::render_image(SIZE, FRAMES, |_| {}).expect("with grass");
    let (without, none) =
        example::render_image(SIZE, FRAMES, |h| h.grass_on = false).expect("host alone");
    assert!(drawn > 1000, "{drawn} blades drawn");
    // The cull still ran without the draw; the counts are the same frames'.
    assert_eq!(none, drawn, "the draw does not change the cull");
    let (w, h) = SIZE;
    // The top rows are the host's sky: sward draws nothing there.
    let sky = (0..w).flat_map(|x| (0..h / 5).map(move |y| (x, y)));
    let sky_changed = sky
        .filter(|&(x, y)| differs(with.get_pixel(x, y), without.get_pixel(x, y)))
        .count();
    assert_eq!(sky_changed, 0, "the grass drew over the host's sky");
    // The bottom third is the field seen close: mostly grass.
    let field: Vec<(u32, u32)> = (0..w)
        .flat_map(|x| (2 * h / 3..h).map(move |y| (x, y)))
        .collect();
    let changed = field
        .iter()
        .filter(|&&(x, y)| differs(with.get_pixel(x, y), without.get_pixel(x, y)))
        .count();
    let share = changed as f64 / field.len() as f64;
    eprintln!(
        "{drawn} blades drawn; the grass changed {:.1} % of the near field",
        100.0 * share
    );
    assert!(
        share > 0.4,
        "the grass covers only {:.1} % of the near field",
        100.0 * share
    );
    // Grass is green: the changed pixels' mean has more green than red and blue.
    let mean = field.iter().fold([0u64; 3], |mut m, &(x, y)| {
        let p = with.get_pixel(x, y).0;
        for c in 0..3 {
            m[c] += u64::from(p[c]);
        }
        m
    });
    assert!(
        mean[1] > mean[0] && mean[1] > mean[2],
        "mean colour {mean:?}"
    );
}

/// The far level in the host's pass (issue 28): the example's scene with the blades to
/// 5 m and billboards to 40 m. The cards the cull keeps beyond the blades are drawn into
/// the host's pass with its formats, and cover ground the blades-only frame leaves bare.
#[test]
fn the_host_draws_the_billboards_beyond_the_blades() {
    let scene = example::SCENE.replace(
        "render: (billboard_distance: 0.0),",
        "culling: (max_distance: 5.0), render: (billboard_distance: 40.0),",
    );
    assert_ne!(
        scene,
        example::SCENE,
        "the example's scene changed its render section"
    );
    let none = scene.replace("billboard_distance: 40.0", "billboard_distance: 0.0");
    let (with, _, cards) = example::render_scene(&scene, SIZE, FRAMES, |_| {}).expect("cards");
    let (without, _, no_cards) =
        example::render_scene(&none, SIZE, FRAMES, |_| {}).expect("no cards");
    assert_eq!(no_cards, 0);
    let (w, h) = SIZE;
    // The middle band: the field beyond 5 m, where only the cards stand.
    let band: Vec<(u32, u32)> = (0..w)
        .flat_map(|x| (h / 3..h / 2).map(move |y| (x, y)))
        .collect();
    let changed = band
        .iter()
        .filter(|&&(x, y)| differs(with.get_pixel(x, y), without.get_pixel(x, y)))
        .count();
    let share = changed as f64 / band.len() as f64;
    eprintln!(
        "{cards} billboards drawn; they changed {:.1} % of the far band",
        100.0 * share
    );
    assert!(cards > 50, "{cards} billboards drawn");
    assert!(
        share > 0.1,
        "the cards changed {:.1} % of the far band",
        100.0 * share
    );
}

#[test]
fn the_hosts_depth_culls_blades_behind_its_world() {
    let (_, occluded) = example::render_image(SIZE, 4, |_| {}).expect("with depth");
    let (_, open) = example::render_image(SIZE, 4, |h| h.occlusion = false).expect("no depth");
    eprintln!("blades drawn: {occluded} with the host's depth, {open} without");
    assert!(
        occluded < open,
        "{occluded} drawn with the host's depth, {open} without"
    );
}

#[test]
fn two_runs_give_the_same_picture() {
    let (a, _) = example::render_image(SIZE, 6, |_| {}).expect("first");
    let (b, _) = example::render_image(SIZE, 6, |_| {}).expect("second");
    assert!(a == b, "the embedded frames differ between runs");
}

#[test]
fn bad_descriptors_and_inputs_are_refused() {
    let (device, queue) = example::open().expect("device");
    let desc = |scene: &str| GrassRendererDescriptor {
        color_format: wgpu::TextureFormat::Rgba8UnormSrgb,
        depth_format: wgpu::TextureFormat::Depth32Float,
        sample_count: 1,
        output: ColorOutput::ToneMapped,
        scene: SceneSource::Ron(scene.into()),
    };
    let small = "(terrain: (size: 8.0, height: Flat), field: (density: 20.0))";
    let err = |r: sward::Result<GrassRenderer>| match r {
        Ok(_) => panic!("accepted"),
        Err(e) => e.to_string(),
    };
    let e = err(GrassRenderer::new(
        &device,
        &queue,
        desc("(field: (density: -3.0))"),
    ));
    assert!(e.contains("density"), "{e}");
    let mut d = desc(small);
    d.depth_format = wgpu::TextureFormat::Rgba8Unorm;
    assert!(err(GrassRenderer::new(&device, &queue, d)).contains("depth_format"));
    let mut d = desc(small);
    d.sample_count = 3;
    assert!(err(GrassRenderer::new(&device, &queue, d)).contains("sample_count"));
    let mut grass = GrassRenderer::new(&device, &queue, desc(small)).expect("a small field");
    let camera = sward::CameraView {
        eye: glam::Vec3::new(0.0, 2.0, 5.0),
        target: glam::Vec3::ZERO,
        fov_y: 60.0,
        near: 0.1,
        far: 100.0,
    };
    let mut encoder = device.create_command_encoder(&Default::default());
    let inputs = |camera, dt, colliders| FrameInputs {
        camera,
        size: (64, 64),
        dt,
        colliders,
        depth: None,
        wind: None,
    };
    let mut bad_camera = camera;
    bad_camera.eye.x = f32::NAN;
    for (what, i) in [
        ("camera", inputs(bad_camera, 0.01, &[][..])),
        ("dt", inputs(camera, -1.0, &[][..])),
        (
            "colliders[0]",
            inputs(
                camera,
                0.01,
                &[sward::Collider {
                    center: glam::Vec3::ZERO,
                    radius: 0.0,
                    velocity: glam::Vec3::ZERO,
                }][..],
            ),
        ),
    ] {
        let e = grass
            .prepare(&device, &queue, &mut encoder, &i)
            .expect_err(what)
            .to_string();
        assert!(e.contains(what), "{what}: {e}");
    }
    let mut wind = inputs(camera, 0.01, &[][..]);
    wind.wind = Some(sward::WindInput {
        direction: glam::Vec2::ZERO,
        strength: 1.0,
    });
    let e = grass
        .prepare(&device, &queue, &mut encoder, &wind)
        .expect_err("wind");
    assert!(e.to_string().contains("wind"), "{e}");
    // A good frame after the refusals.
    grass
        .prepare(
            &device,
            &queue,
            &mut encoder,
            &inputs(camera, 0.01, &[][..]),
        )
        .expect("a good frame");
    queue.submit([encoder.finish()]);
}

#[test]
fn the_hosts_world_receives_swards_shadows() {
    let (lit, _) = example::render_image(SIZE, 8, |h| h.shadows = false).expect("no receiver");
    let (shadowed, _) = example::render_image(SIZE, 8, |_| {}).expect("receiver");
    let luma = |p: &image::Rgba<u8>| p.0[..3].iter().map(|&c| u32::from(c)).sum::<u32>();
    let (mut darker, mut brighter) = (0, 0);
    for (a, b) in lit.pixels().zip(shadowed.pixels()) {
        let (a, b) = (luma(a), luma(b));
        if b + 12 < a {
            darker += 1;
        } else if a + 12 < b {
            brighter += 1;
        }
    }
    eprintln!("with sward's shadows received: {darker} pixels darker, {brighter} brighter");
    // Only the host's own pixels can change (the grass shades itself either way), and a
    // shadow only takes light away.
    assert!(darker > 20, "{darker} pixels in shadow");
    assert_eq!(brighter, 0);
}

/// The host's box casts into sward's sun shadows (`GrassRenderer::shadow_casters`): drawn
/// depth only into each cascade sward drew, it darkens the grass and the host's ground on
/// its far side from the sun, and lights nothing.
#[test]
fn the_hosts_box_casts_into_swards_shadows() {
    // The box is small in the view (10 m away): a larger picture sees its shadow.
    let size = (480, 270);
    let (open, _) = example::render_image(size, 8, |h| h.casts = false).expect("no caster");
    let (cast, _) = example::render_image(size, 8, |_| {}).expect("caster");
    let luma = |p: &image::Rgba<u8>| p.0[..3].iter().map(|&c| u32::from(c)).sum::<u32>();
    let (mut darker, mut brighter) = (0, 0);
    for (a, b) in open.pixels().zip(cast.pixels()) {
        let (a, b) = (luma(a), luma(b));
        if b + 12 < a {
            darker += 1;
        } else if a + 12 < b {
            brighter += 1;
        }
    }
    eprintln!("with the host's box casting: {darker} pixels darker, {brighter} brighter");
    assert!(darker > 30, "{darker} pixels in the box's shadow");
    assert!(brighter * 10 < darker, "{brighter} pixels brighter");
}

/// A host that draws with 4x MSAA: the grass pipeline is built for its sample count, the
/// occlusion pyramid reads its multisampled depth, and a frame records, submits and
/// resolves without a device error (wgpu's default handler would panic on one).
#[test]
fn a_multisampled_host_draws_the_grass() {
    let (device, queue) = example::open().expect("device");
    let format = wgpu::TextureFormat::Rgba8UnormSrgb;
    let depth_format = wgpu::TextureFormat::Depth32Float;
    let mut grass = GrassRenderer::new(
        &device,
        &queue,
        GrassRendererDescriptor {
            color_format: format,
            depth_format,
            sample_count: 4,
            output: ColorOutput::ToneMapped,
            scene: SceneSource::Ron(
                "(terrain: (size: 8.0, height: Flat), field: (density: 60.0))".into(),
            ),
        },
    )
    .expect("a 4x host");
    let size = (96u32, 54u32);
    let target = |format, samples, usage| {
        device
            .create_texture(&wgpu::TextureDescriptor {
                label: Some("msaa-host.target"),
                size: wgpu::Extent3d {
                    width: size.0,
                    height: size.1,
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
    let attach = wgpu::TextureUsages::RENDER_ATTACHMENT;
    let color = target(format, 4, attach);
    let resolved = target(format, 1, attach | wgpu::TextureUsages::COPY_SRC);
    let depth = target(
        depth_format,
        4,
        attach | wgpu::TextureUsages::TEXTURE_BINDING,
    );
    let camera = sward::CameraView {
        eye: glam::Vec3::new(0.0, 1.5, 4.0),
        target: glam::Vec3::ZERO,
        fov_y: 60.0,
        near: 0.05,
        far: 100.0,
    };
    for _ in 0..3 {
        let mut encoder = device.create_command_encoder(&Default::default());
        // The host's opaque pass: clears colour and depth.
        drop(encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("msaa-host.world"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &color,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLUE),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            ..Default::default()
        }));
        let inputs = FrameInputs {
            camera,
            size,
            dt: 1.0 / 30.0,
            colliders: &[],
            depth: Some(&depth),
            wind: None,
        };
        grass
            .prepare(&device, &queue, &mut encoder, &inputs)
            .expect("prepare");
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("msaa-host.grass"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &color,
                    depth_slice: None,
                    resolve_target: Some(&resolved),
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                ..Default::default()
            });
            grass.render(&mut pass);
        }
        queue.submit([encoder.finish()]);
    }
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .expect("idle");
    let drawn = grass.drawn_blades().expect("counters");
    eprintln!("4x MSAA host: {drawn} blades drawn");
    assert!(drawn > 100, "{drawn} blades drawn");
}
