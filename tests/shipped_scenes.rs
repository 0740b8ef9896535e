//! Every scene sward ships under `assets/scenes/` loads, renders and steps: found by listing
//! the directory (a new scene is covered without editing this test), each is rendered for a
//! few frames at a small size and stepped, with no GPU error, no blade reset from a
//! non-finite state (a reset means a valid scene drove the update to NaN), grass drawn,
//! and a picture that is not flat. Each is built and drawn through the embedding API, from
//! its file (`GrassRenderer::new_world_on` with `SceneSource::File`, `render_world`).

mod common;

use sward::embed::{GrassRenderer, SceneSource, WorldDescriptor};
use sward::render::camera::CameraView;
use sward::render::target::{Target, COLOR_FORMAT};

const SIZE: (u32, u32) = (96, 54);

fn shipped() -> Vec<std::path::PathBuf> {
    let mut scenes: Vec<_> = std::fs::read_dir("assets/scenes")
        .expect("assets/scenes")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .collect();
    scenes.sort();
    scenes
}

#[test]
fn every_shipped_scene_loads_renders_and_steps() {
    let scenes = shipped();
    assert!(scenes.len() >= 16, "{scenes:?}");
    let gpu = common::gpu();
    for path in &scenes {
        let name = path.display();
        let desc = WorldDescriptor {
            color_format: COLOR_FORMAT,
            scene: SceneSource::File(path.clone()),
        };
        let mut r = GrassRenderer::new_world_on(&gpu, desc)
            .unwrap_or_else(|e| panic!("{name} does not load: {e}"));
        let target = Target::new(&gpu, SIZE.0, SIZE.1).expect("target");
        let camera = CameraView::from_scene(&r.scene().camera);
        for _ in 0..3 {
            sward::commands::world_frame(&gpu, &mut r, 1.0 / 30.0, camera, &target).expect("frame");
        }
        let counters = r.cull.read_counters(&gpu).expect("counters");
        let image = target.read_image(&gpu).expect("image");
        // Without drawing, as `simulate` steps.
        for _ in 0..3 {
            r.step(&gpu, 1.0 / 30.0);
        }
        gpu.check_errors()
            .unwrap_or_else(|e| panic!("{name}: GPU error {e}"));
        let resets = r.blades_reset_nonfinite(&gpu).expect("resets");
        assert_eq!(resets, 0, "{name}: blades reset from a non-finite state");
        let luma: Vec<f64> = image
            .pixels()
            .map(|p| 0.2126 * f64::from(p[0]) + 0.7152 * f64::from(p[1]) + 0.0722 * f64::from(p[2]))
            .collect();
        let mean = luma.iter().sum::<f64>() / luma.len() as f64;
        let spread =
            (luma.iter().map(|l| (l - mean).powi(2)).sum::<f64>() / luma.len() as f64).sqrt();
        eprintln!(
            "{name}: {} blades, {} drawn, mean luma {mean:.1}, spread {spread:.1}",
            r.buffers.count,
            counters.drawn()
        );
        assert!(counters.drawn() > 0, "{name}: no grass drawn");
        assert!(spread > 2.0, "{name}: a flat picture (spread {spread:.2})");
    }
}
