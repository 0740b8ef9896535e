//! MSAA of the 3D passes: the same still frame drawn with 1 and 4 samples per pixel, where
//! the 4× image must have the blended blade edges the 1× image lacks, with the grass lit
//! forward (per fragment) and deferred (once per pixel, `render::deferred`); and a sample
//! count the adapter cannot give falls back to the largest one below it, without a wgpu
//! error.

mod common;

use sward::render::camera::CameraView;
use sward::render::draw::DEPTH_FORMAT;
use sward::render::msaa::effective_samples;
use sward::render::target::{Target, COLOR_FORMAT};
use sward::session::Session;

const SIZE: (u32, u32) = (96, 64);

/// Sum of |difference| between horizontally and vertically adjacent pixels (RGB): hard
/// stair-stepped edges have more of it than edges blended over several pixels.
fn total_variation(image: &image::RgbaImage) -> u64 {
    let (w, h) = image.dimensions();
    let mut sum = 0u64;
    for y in 0..h {
        for x in 0..w {
            let p = image.get_pixel(x, y);
            for (nx, ny) in [(x + 1, y), (x, y + 1)] {
                if nx < w && ny < h {
                    let q = image.get_pixel(nx, ny);
                    sum += (0..3).map(|c| p[c].abs_diff(q[c]) as u64).sum::<u64>();
                }
            }
        }
    }
    sum
}

fn distinct_colours(image: &image::RgbaImage) -> usize {
    image
        .pixels()
        .map(|p| [p[0], p[1], p[2]])
        .collect::<std::collections::HashSet<_>>()
        .len()
}

#[test]
fn four_samples_blend_the_blade_edges() {
    let gpu = common::gpu();
    let camera = CameraView {
        eye: glam::Vec3::new(0.0, 1.0, 3.0),
        target: glam::Vec3::new(0.0, 0.2, 0.0),
        fov_y: 50.0,
        near: 0.05,
        far: 100.0,
    };
    let mut images = Vec::new();
    // One sample, then 4x lit forward and 4x lit deferred.
    for (msaa, deferred) in [(1, true), (4, false), (4, true)] {
        let mut scene = common::still_scene();
        scene.render.msaa = msaa;
        // Against one sample without any anti-aliasing.
        scene.render.taa = false;
        let session = Session::new(scene, Some(8192), Some(&gpu)).expect("field");
        let mut r = common::world(&gpu, &session);
        r.deferred_grass(deferred);
        assert_eq!(r.msaa_samples(), msaa, "4× is guaranteed by WebGPU");
        let target = Target::new(&gpu, SIZE.0, SIZE.1).expect("target");
        // Two frames: the second uses the first's grass for occlusion (the late passes).
        for _ in 0..2 {
            sward::commands::world_frame(&gpu, &mut r, 0.0, camera, &target).expect("frame");
        }
        gpu.check_errors().expect("no wgpu error");
        let drawn = r.cull.read_counters(&gpu).expect("counters").drawn();
        assert!(drawn > 500, "msaa {msaa}: only {drawn} blades drawn");
        assert_eq!(
            r.grass_deferred(),
            deferred,
            "msaa {msaa}: the path asked for"
        );
        images.push(target.read_image(&gpu).expect("read-back"));
    }
    let one = &images[0];
    let (tv1, c1) = (total_variation(one), distinct_colours(one));
    // Forward, each blade's fragment is lit and blended: measured 0.79 of the 1x total
    // variation. Deferred, each of a pixel's first two blades under its own light (on its
    // own albedo and height at each sample): measured 0.833; 0.912 when the pixel's first
    // grass sample lit every blade in it, which blended less.
    for (four, path, most) in [(&images[1], "forward", 0.9), (&images[2], "deferred", 0.9)] {
        let (tv4, c4) = (total_variation(four), distinct_colours(four));
        eprintln!(
            "{path}: total variation 1×: {tv1}, 4×: {tv4} ({:.3}); distinct colours 1×: {c1}, \
             4×: {c4}",
            tv4 as f64 / tv1 as f64
        );
        // Same frame, same blades: the 4× image differs only at edges, which it blends.
        assert!(
            (tv4 as f64) < most * tv1 as f64,
            "{path}: 4× is not smoother: {tv4} vs {tv1}"
        );
        assert!(c4 > c1, "{path}: 4× has no blended colours: {c4} vs {c1}");
        let mean = |i: &image::RgbaImage| i.pixels().map(|p| p[1] as f64).sum::<f64>() / 6144.0;
        assert!(
            (mean(one) - mean(four)).abs() < 8.0,
            "{path}: the images are not the same frame: mean green {} vs {}",
            mean(one),
            mean(four)
        );
    }
}

/// Whether the device can give `n` samples for both formats: the adapter's own counts,
/// when the device was opened with its adapter-specific format features.
fn adapter_has(gpu: &sward::gpu::Gpu, n: u32) -> bool {
    let specific = wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES;
    gpu.device.features().contains(specific)
        && [COLOR_FORMAT, DEPTH_FORMAT].iter().all(|&f| {
            gpu.adapter
                .as_ref()
                .expect("opened by sward")
                .get_texture_format_features(f)
                .flags
                .sample_count_supported(n)
        })
}

#[test]
fn an_unsupported_sample_count_falls_back_below() {
    let gpu = common::gpu();
    assert_eq!(effective_samples(&gpu, COLOR_FORMAT, 1), 1);
    assert_eq!(effective_samples(&gpu, COLOR_FORMAT, 4), 4);
    for (asked, below) in [(8, 4), (2, 1)] {
        let got = effective_samples(&gpu, COLOR_FORMAT, asked);
        let expected = if adapter_has(&gpu, asked) {
            asked
        } else {
            below
        };
        eprintln!("{}: {asked}× gives {got}×", gpu.info.name);
        assert_eq!(got, expected, "{asked}×");
    }
    // The renderer draws with what it got, without a wgpu validation error (lavapipe has
    // no 8×: this is the fallback path there).
    let mut scene = common::still_scene();
    scene.render.msaa = 8;
    let session = Session::new(scene, Some(2048), Some(&gpu)).expect("field");
    let mut r = common::world(&gpu, &session);
    assert_eq!(r.msaa_samples(), effective_samples(&gpu, COLOR_FORMAT, 8));
    let target = Target::new(&gpu, 32, 24).expect("target");
    let camera = CameraView::from_scene(&r.scene.camera);
    sward::commands::world_frame(&gpu, &mut r, 0.0, camera, &target).expect("frame");
    gpu.check_errors().expect("no wgpu error");
    // Switched live (the panel): pipelines and targets follow, the frame still draws.
    r.scene.render.msaa = 1;
    sward::commands::world_frame(&gpu, &mut r, 0.0, camera, &target).expect("frame");
    assert_eq!(r.msaa_samples(), 1);
    r.scene.render.msaa = 4;
    sward::commands::world_frame(&gpu, &mut r, 0.0, camera, &target).expect("frame");
    assert_eq!(r.msaa_samples(), 4);
    gpu.check_errors().expect("no wgpu error after switching");
}
