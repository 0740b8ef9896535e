//! The window's panel cache (`app::ui_cache`): egui drawn once into a texture and
//! composited over each frame must give the picture egui draws straight over the frame,
//! must be drawn again only when egui's output changes, and must composite only the pixels
//! egui drew.

mod common;

use egui::epaint::{ClippedPrimitive, Mesh, Primitive};
use sward::gpu::Gpu;
use sward_app::app::ui_cache::{self, painted_bounds, UiCache};

const SIZE: (u32, u32) = (320, 180);
const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// The frame under the panel: a colour of its own in every pixel, so a composite that
/// covered too much or too little shows.
const BACKGROUND: wgpu::Color = wgpu::Color {
    r: 0.2,
    g: 0.6,
    b: 0.3,
    a: 1.0,
};

/// A panel like the window's (a side panel of labels and a button) and a half-transparent
/// window over the frame, tessellated at `ppp`; `text` changes one label.
fn frame(
    ctx: &egui::Context,
    text: &str,
    ppp: f32,
) -> (Vec<ClippedPrimitive>, egui::TexturesDelta) {
    let input = egui::RawInput {
        screen_rect: Some(egui::Rect::from_min_size(
            egui::Pos2::ZERO,
            egui::vec2(SIZE.0 as f32 / ppp, SIZE.1 as f32 / ppp),
        )),
        ..Default::default()
    };
    ctx.set_pixels_per_point(ppp);
    let out = ctx.run_ui(input, |ui| {
        egui::Panel::left("test.panel")
            .default_size(90.0)
            .show(ui, |ui| {
                ui.heading("sward");
                ui.label(text);
                let _ = ui.button("Clear balls");
            });
        egui::Window::new("help")
            .default_pos(egui::pos2(150.0, 60.0))
            .frame(egui::Frame::new().fill(egui::Color32::from_black_alpha(160)))
            .show(ui.ctx(), |ui| {
                ui.label("half transparent");
            });
    });
    let jobs = ctx.tessellate(out.shapes, out.pixels_per_point);
    (jobs, out.textures_delta)
}

fn target(gpu: &Gpu, label: &str) -> wgpu::Texture {
    gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: SIZE.0,
            height: SIZE.1,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

/// The frame (the background) with egui drawn over it: straight (`cache` None), or into
/// the cache and composited.
fn draw(
    gpu: &Gpu,
    egui: &mut egui_wgpu::Renderer,
    jobs: &[ClippedPrimitive],
    textures: &egui::TexturesDelta,
    ppp: f32,
    cache: Option<&mut UiCache>,
) -> image::RgbaImage {
    for (id, deltas) in &textures.set {
        for delta in deltas {
            egui.update_texture(&gpu.device, &gpu.queue, *id, delta);
        }
    }
    let screen = egui_wgpu::ScreenDescriptor {
        size_in_pixels: [SIZE.0, SIZE.1],
        pixels_per_point: ppp,
    };
    let out = target(gpu, "test.ui_cache.frame");
    let view = out.create_view(&Default::default());
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    let extra = egui.update_buffers(&gpu.device, &gpu.queue, &mut encoder, jobs, &screen);
    drop(ui_cache::pass(
        &mut encoder,
        "test.background",
        &view,
        wgpu::LoadOp::Clear(BACKGROUND),
        None,
    ));
    match cache {
        None => {
            let pass = ui_cache::pass(&mut encoder, "test.egui", &view, wgpu::LoadOp::Load, None);
            egui.render(&mut pass.forget_lifetime(), jobs, &screen);
        }
        Some(cache) => {
            assert!(cache.stale(&gpu.device, jobs, false, SIZE, ppp));
            let clear = wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT);
            let pass = ui_cache::pass(&mut encoder, "test.egui", cache.view(), clear, None);
            egui.render(&mut pass.forget_lifetime(), jobs, &screen);
            let mut pass = ui_cache::pass(
                &mut encoder,
                "test.composite",
                &view,
                wgpu::LoadOp::Load,
                None,
            );
            cache.composite(&mut pass);
        }
    }
    gpu.queue
        .submit(extra.into_iter().chain([encoder.finish()]));
    sward::render::target::read_texture(gpu, &out).expect("read back")
}

#[test]
fn the_cached_panel_is_the_panel_egui_draws() {
    let gpu = common::gpu();
    let ctx = egui::Context::default();
    let ppp = 1.25;
    // The font atlas comes with the first frame; the frame compared is a settled one, the
    // half-transparent window faded in.
    let (_, textures) = frame(&ctx, "6.1 fps", ppp);
    for _ in 0..30 {
        let _ = frame(&ctx, "6.1 fps", ppp);
    }
    let (jobs, _) = frame(&ctx, "6.1 fps", ppp);
    let mut egui = egui_wgpu::Renderer::new(&gpu.device, FORMAT, Default::default());
    let straight = draw(&gpu, &mut egui, &jobs, &textures, ppp, None);
    let mut cache = UiCache::new(&gpu.device, FORMAT, SIZE);
    let cached = draw(&gpu, &mut egui, &jobs, &textures, ppp, Some(&mut cache));
    let mut worst = 0u8;
    let mut off = 0usize;
    for (a, b) in straight.pixels().zip(cached.pixels()) {
        let d = (0..3).map(|c| a[c].abs_diff(b[c])).max().unwrap_or(0);
        worst = worst.max(d);
        off += usize::from(d > 1);
    }
    // Premultiplied "over" is associative: drawn over transparent and then over the frame
    // is drawn over the frame, but for the cache's 8-bit rounding (measured: at most 1
    // level per channel, on the half-transparent window's pixels).
    assert!(worst <= 2, "worst channel difference {worst}");
    assert_eq!(off, 0, "{off} pixels differ by more than one level");
    // The panel is drawn, and the frame outside what egui drew is untouched.
    let bg = [51u8, 153, 77];
    let far = cached.get_pixel(SIZE.0 - 2, SIZE.1 - 2);
    assert!((0..3).all(|c| far[c].abs_diff(bg[c]) <= 1), "{far:?}");
    let panel = cached.get_pixel(4, SIZE.1 - 4);
    assert!(panel[1] < 100, "no dark panel at the left edge: {panel:?}");
}

#[test]
fn the_cache_is_drawn_again_only_when_egui_output_changes() {
    let gpu = common::gpu();
    let ctx = egui::Context::default();
    let mut cache = UiCache::new(&gpu.device, FORMAT, SIZE);
    // egui settles over its first frames: a new window is sized invisibly, then fades
    // in (about ten frames of its 1/60 s steps).
    for _ in 0..30 {
        let _ = frame(&ctx, "6.1 fps", 1.0);
    }
    let (jobs, _) = frame(&ctx, "6.1 fps", 1.0);
    assert!(
        cache.stale(&gpu.device, &jobs, false, SIZE, 1.0),
        "first frame"
    );
    let (again, _) = frame(&ctx, "6.1 fps", 1.0);
    assert!(
        !cache.stale(&gpu.device, &again, false, SIZE, 1.0),
        "same panel"
    );
    // A texture update (the font atlas growing) may change the same meshes' pixels.
    assert!(cache.stale(&gpu.device, &again, true, SIZE, 1.0));
    assert!(!cache.stale(&gpu.device, &again, false, SIZE, 1.0));
    let (other, _) = frame(&ctx, "6.2 fps", 1.0);
    assert!(
        cache.stale(&gpu.device, &other, false, SIZE, 1.0),
        "a label changed"
    );
    // A resize or another scale: drawn again.
    assert!(cache.stale(&gpu.device, &other, false, (SIZE.0, SIZE.1 + 1), 1.0));
    assert!(cache.stale(&gpu.device, &other, false, (SIZE.0, SIZE.1 + 1), 2.0));
}

#[test]
fn painted_bounds_cover_the_meshes_inside_their_clip_rectangles() {
    let quad = |min: (f32, f32), max: (f32, f32)| {
        let mut mesh = Mesh::default();
        mesh.add_colored_rect(
            egui::Rect::from_min_max(egui::pos2(min.0, min.1), egui::pos2(max.0, max.1)),
            egui::Color32::WHITE,
        );
        mesh
    };
    let job = |clip: egui::Rect, mesh: Mesh| ClippedPrimitive {
        clip_rect: clip,
        primitive: Primitive::Mesh(mesh),
    };
    let everything = egui::Rect::EVERYTHING;
    // Points to pixels at 1.5, rounded outwards.
    let one = [job(everything, quad((10.0, 20.0), (110.3, 70.0)))];
    assert_eq!(
        painted_bounds(&one, 1.5, (1000, 1000)),
        Some([15, 30, 166, 105])
    );
    // Clipped, and clamped to the window.
    let clip = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(50.0, 50.0));
    let two = [
        job(clip, quad((10.0, 20.0), (110.0, 70.0))),
        job(everything, quad((-5.0, 90.0), (20.0, 400.0))),
    ];
    assert_eq!(
        painted_bounds(&two, 1.0, (200, 300)),
        Some([0, 20, 50, 300])
    );
    // Nothing visible: nothing to composite.
    let hidden = [job(clip, quad((60.0, 60.0), (70.0, 70.0)))];
    assert_eq!(painted_bounds(&hidden, 1.0, (200, 300)), None);
    assert_eq!(painted_bounds(&[], 1.0, (200, 300)), None);
}
