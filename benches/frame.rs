//! Criterion bench of one whole headless frame on the GPU: blade update, cull and draw of
//! the small bench scene (8,192 blades, four spheres) into a 256×144 off-screen target,
//! waiting until the GPU is done. It times what `sward bench` times per frame, but with
//! criterion's statistics, so that a change to a pass shows up as a regression.
//!
//! Runs on the adapter `SWARD_ADAPTER` names (the software one when unset, like the tests):
//! `SWARD_ADAPTER=auto cargo bench --bench frame` times the machine's GPU.

use std::path::Path;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use sward::commands::world_frame;
use sward::embed::GrassRenderer;
use sward::gpu::{wait_idle, AdapterChoice, Gpu};
use sward::render::camera::CameraView;
use sward::render::target::{Target, COLOR_FORMAT};
use sward::render::Renderer;
use sward::scene::load_scene;
use sward::session::Session;

fn frame(c: &mut Criterion) {
    let choice: AdapterChoice = std::env::var("SWARD_ADAPTER")
        .unwrap_or_else(|_| "software".into())
        .parse()
        .expect("infallible");
    let gpu = Gpu::new(&choice).expect("the frame bench needs a GPU adapter");
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes/bench_small.ron");
    let scene = load_scene(&path).expect("bench scene loads");
    let session = Session::new(scene, None, Some(&gpu)).expect("field fits the adapter");
    let (width, height) = (256, 144);
    let target = Target::new(&gpu, width, height).expect("target");
    let camera = CameraView::from_scene(&session.scene.camera);
    let renderer = Renderer::from_session(&gpu, &session, COLOR_FORMAT).expect("renderer");
    // Drawn through the embedding API, as the window and `sward render` draw.
    let mut renderer = GrassRenderer::wrap_world(&gpu, renderer, COLOR_FORMAT);
    let name = format!(
        "frame {} blades {width}x{height} on {}",
        session.field.blades.len(),
        gpu.info.name
    );
    c.bench_function(&name, |b| {
        b.iter(|| {
            // The same dt as `sward bench`; the clock keeps running across iterations, so
            // the balls roll on and the blades keep moving as in a real session.
            world_frame(&gpu, &mut renderer, 1.0 / 30.0, camera, &target).expect("frame");
            wait_idle(&gpu.device).expect("frame finishes");
        })
    });
}

criterion_group! {
    name = benches;
    // A software frame takes tens of milliseconds: fewer, longer samples keep the bench
    // under a minute on two cores.
    config = Criterion::default()
        .sample_size(20)
        .warm_up_time(Duration::from_secs(2))
        .measurement_time(Duration::from_secs(8));
    targets = frame
}
criterion_main!(benches);
