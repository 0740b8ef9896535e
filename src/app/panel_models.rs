//! The panel's "Blade model" controls inside the Physics section: which paper's blade the
//! update steps and the draw bends (`physics.model`), and that model's parameters. The
//! Verlet states are allocated the first time Verlet is picked.

use egui::Ui;

use super::state::{AppState, Status};
use crate::gpu::Gpu;
use crate::scene::BladeModel;

pub fn model_controls(ui: &mut Ui, app: &mut AppState, gpu: &Gpu) {
    let before = app.renderer.scene.physics.model;
    ui.horizontal(|ui| {
        ui.label("blade model");
        for m in BladeModel::ALL {
            ui.selectable_value(&mut app.renderer.scene.physics.model, m, m.name());
        }
    });
    if app.renderer.scene.physics.model != before {
        if let Err(e) = app.renderer.apply_model(gpu) {
            app.status = Some(Status::Error(format!(
                "Verlet blades need memory the adapter lacks: {e}"
            )));
            app.renderer.scene.physics.model = before;
        }
    }
    let p = &mut app.renderer.scene.physics;
    match p.model {
        BladeModel::Jahrmann => {}
        BladeModel::Verlet => {
            ui.add(egui::Slider::new(&mut p.verlet.damping, 0.0..=20.0).text("damping 1/s"));
            ui.add(egui::Slider::new(&mut p.verlet.wind_gain, 0.0..=5.0).text("wind gain"));
        }
        BladeModel::Cwd => {
            let c = &mut p.cwd;
            ui.add(egui::Slider::new(&mut c.k1, 0.0..=0.5).text("k1 (Eq. 11, sag)"));
            ui.add(egui::Slider::new(&mut c.k2, 0.0..=1.0).text("k2 (Eq. 11, lean)"));
            ui.add(egui::Slider::new(&mut c.lambda, 0.0..=1.0).text("λ (Eq. 13)"));
            ui.add(egui::Slider::new(&mut c.force, 0.0..=1.0).text("F s/m (Eq. 12)"));
            ui.add(
                egui::Slider::new(&mut c.cell_size, 0.1..=10.0)
                    .logarithmic(true)
                    .text("cell m (no fluid)"),
            );
            ui.label("no state: no collisions, no trails");
        }
    }
}
