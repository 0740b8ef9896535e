//! A frame keeps nothing it allocates. 300 headless frames (and 100 simulation steps) of
//! the default meadow with every pass of the frame on — streamed tiles, the fluid wind,
//! occlusion by objects and grass, billboards, sun shadows with grass casters, MSAA, tone
//! mapping, the work counter — at a small size (what leaked did not depend on the image size or the blade
//! count): after warm-up the live wgpu objects (`Instance::generate_report`) stay as they
//! were and resident memory grows by less than [`RSS_BOUND_KIB`].
//!
//! What leaked before (12 MB a frame on Mesa 22.3's lavapipe): the grass vertex shader, the
//! terrain and the blade cull read uniforms in their branches, and lavapipe recompiles such
//! a large shader with the uniform's value inlined at every draw or dispatch, keeping every
//! copy until the pipeline is destroyed. Those three bind read-only storage instead.

mod common;

use sward::gpu::Gpu;
use sward::render::camera::CameraView;
use sward::render::target::Target;
use sward::session::Session;

/// Resident memory may grow by this much from frame 50 to frame 300 (allocator noise and
/// caches that fill once; the leak was 12 MB a frame, 3 GB over this run).
const RSS_BOUND_KIB: i64 = 48 * 1024;

/// Resident memory of this process in KiB (Linux `/proc/self/status`).
fn resident_kib() -> i64 {
    let status = std::fs::read_to_string("/proc/self/status").expect("procfs");
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmRSS:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
        .expect("VmRSS line")
}

/// Live wgpu objects by kind (ids handed out and not released).
fn live(gpu: &Gpu) -> Vec<(&'static str, usize)> {
    let report = gpu
        .instance
        .as_ref()
        .expect("opened by sward")
        .generate_report()
        .expect("wgpu-core instance");
    let h = report.hub_report();
    vec![
        ("buffers", h.buffers.num_allocated),
        ("textures", h.textures.num_allocated),
        ("texture views", h.texture_views.num_allocated),
        ("bind groups", h.bind_groups.num_allocated),
        ("bind group layouts", h.bind_group_layouts.num_allocated),
        ("query sets", h.query_sets.num_allocated),
        ("samplers", h.samplers.num_allocated),
        ("shader modules", h.shader_modules.num_allocated),
        ("render pipelines", h.render_pipelines.num_allocated),
        ("compute pipelines", h.compute_pipelines.num_allocated),
        ("command buffers", h.command_buffers.num_allocated),
    ]
}

#[test]
fn frames_keep_nothing_they_allocate() {
    let gpu = common::gpu();
    // Every pass on, with a field small enough that 300 frames take seconds.
    let sets: Vec<String> = [
        "field.density=10",
        "wind.source=Both",
        "wind.fluid.resolution=32",
        "light.shadows.enabled=true",
        "culling.occlusion=true",
        "culling.grass_occlusion=true",
        "render.msaa=4",
        "colliders=[(center: (0.0, 0.4, 0.0), radius: 0.5, motion: Velocity((0.3, 0.0, 0.0)))]",
    ]
    .map(String::from)
    .to_vec();
    let scene = sward::commands::load(None, &sets).expect("scene");
    assert!(scene.field.tile_size > 0.0 && scene.render.billboard_distance > 0.0);
    let session = Session::new(scene, None, Some(&gpu)).expect("field");
    let mut r = common::world(&gpu, &session);
    // The work counter too: its queries, ring of read-back buffers and coverage pass.
    assert!(r.count_work(&gpu, true));
    let size = (48, 27);
    let target = Target::new(&gpu, size.0, size.1).expect("target");
    let mut camera = CameraView::from_scene(&session.scene.camera);
    let mut warm = (Vec::new(), 0);
    for f in 0..300u32 {
        // The camera flies, so tiles stream in and out.
        camera.eye.x += 0.2;
        camera.target.x += 0.2;
        sward::commands::world_frame(&gpu, &mut r, 1.0 / 30.0, camera, &target).expect("frame");
        gpu.check_errors().expect("no GPU error");
        if f == 50 {
            sward::gpu::wait_idle(&gpu.device).expect("idle");
            warm = (live(&gpu), resident_kib());
        }
    }
    for _ in 0..100 {
        r.step(&gpu, 1.0 / 30.0);
    }
    let image = target.read_image(&gpu).expect("read back");
    assert!(
        r.read_work(&gpu).expect("work").is_some(),
        "frames were counted"
    );
    sward::gpu::wait_idle(&gpu.device).expect("idle");
    let end = (live(&gpu), resident_kib());
    eprintln!("after warm-up (frame 50): {warm:?}\nafter 300 frames and 100 steps: {end:?}");
    assert_eq!(end.0, warm.0, "live wgpu objects grew");
    let grew = end.1 - warm.1;
    assert!(
        grew < RSS_BOUND_KIB,
        "resident memory grew by {grew} KiB from frame 50 to the end"
    );
    assert_eq!(image.dimensions(), size);
}
