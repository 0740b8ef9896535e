//! The panel's "Blade model" controls inside the Physics section: which paper's blade the
//! update steps and the draw bends (`physics.model`), and that model's parameters. The
//! Verlet states are allocated the first time Verlet is picked; and the grass-to-grass
//! propagation (`physics.propagation`); the field's species, clumps and flowers.

use egui::Ui;

use super::state::{AppState, Status};
use sward::gpu::Gpu;
use sward::scene::BladeModel;

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

/// Qiu et al.'s grass-to-grass propagation (`physics.propagation`): on/off and its
/// parameters; the grid is (re)built when it is turned on or changes size.
pub fn propagation_controls(ui: &mut Ui, app: &mut AppState, gpu: &Gpu) {
    let p = &mut app.renderer.scene.physics;
    let mut on = p.propagation.is_some();
    let before = p.propagation.clone();
    ui.checkbox(&mut on, "grass-to-grass propagation (Qiu Eq. 4)");
    if on != p.propagation.is_some() {
        p.propagation = on.then(sward::scene::Propagation::default);
    }
    if let Some(q) = &mut p.propagation {
        ui.add(egui::Slider::new(&mut q.att, 0.0..=1.0).text("att (decay)"));
        ui.add(
            egui::Slider::new(&mut q.threshold, 0.0..=0.05)
                .logarithmic(true)
                .text("threshold L m"),
        );
        ui.add(
            egui::Slider::new(
                &mut q.generations,
                1..=sward::sim::propagation::MAX_GENERATIONS,
            )
            .text("generations"),
        );
        ui.add(egui::Slider::new(&mut q.cell_size, 0.02..=0.5).text("cell m"));
        ui.add(egui::Slider::new(&mut q.extent, 2.0..=64.0).text("grid m"));
        // The scene file's limit: at most 2048 cells per side.
        q.cell_size = q.cell_size.max(q.extent / 2048.0);
    }
    if app.renderer.scene.physics.propagation != before {
        if let Err(e) = app.renderer.apply_propagation(gpu) {
            app.status = Some(Status::Error(format!("propagation not changed: {e}")));
            app.renderer.scene.physics.propagation = before;
        }
    }
}

/// The trail map (`physics.trails`): on or off, its texels per tile and its cache, applied
/// by rebuilding the field; what it holds now.
pub fn trail_controls(ui: &mut Ui, app: &mut AppState, gpu: &Gpu) {
    let mut on = app.trails_draft.is_some();
    ui.checkbox(&mut on, "trail map: trails outlive their tiles");
    if on != app.trails_draft.is_some() {
        app.trails_draft = on.then(sward::scene::Trails::default);
    }
    if let Some(t) = &mut app.trails_draft {
        ui.add(egui::Slider::new(&mut t.resolution, 4..=128).text("texels per tile side"));
        ui.add(
            egui::Slider::new(&mut t.cache_tiles, 0..=65536)
                .logarithmic(true)
                .text("tiles kept after they leave"),
        );
    }
    if app.trails_draft != app.renderer.scene.physics.trails
        && ui.button("Apply (rebuilds the field)").clicked()
    {
        app.apply_trails(gpu);
    }
    match app.renderer.tiles() {
        Some(t) => match &t.trails {
            Some(p) => {
                let l = p.layout();
                ui.label(format!(
                    "{} pages of {}² texels ({:.2} MB); {} trails of tiles that left kept, {} \
                     dropped",
                    l.pages,
                    l.resolution,
                    l.bytes() as f64 / 1e6,
                    p.cached_count(),
                    p.evicted
                ));
            }
            None => {
                ui.label("no trail map: a trail goes with its tile's blades");
            }
        },
        None => {
            ui.label("the field is generated whole: its blades keep their trails");
        }
    }
}

/// The field draft's species, clumps and flowers (applied by the Field section's
/// Regenerate): each species' share and colour, adding and removing species, the clumps'
/// settings, and the flowers' share, head size and kinds' colours.
pub fn species_controls(ui: &mut Ui, f: &mut sward::scene::Field) {
    ui.label("species (empty: the field's own ranges)");
    let mut remove = None;
    for (k, s) in f.species.iter_mut().enumerate() {
        ui.horizontal(|ui| {
            ui.label(format!("{k}: {:?}", s.shape));
            ui.add(egui::Slider::new(&mut s.share, 0.01..=10.0).text("share"));
            let mut c = [s.color.0, s.color.1, s.color.2];
            if ui.color_edit_button_rgb(&mut c).changed() {
                s.color = (c[0], c[1], c[2]);
            }
            if ui.small_button("✕").clicked() {
                remove = Some(k);
            }
        });
    }
    if let Some(k) = remove {
        f.species.remove(k);
    }
    if f.species.len() < sward::field::clumps::MAX_SPECIES && ui.button("add species").clicked() {
        f.species.push(sward::scene::Species {
            height: f.height,
            width: f.width,
            stiffness: f.stiffness,
            shape: f.shape,
            ..Default::default()
        });
    }
    let mut on = f.clumps.is_some();
    ui.checkbox(&mut on, "clumps");
    if on != f.clumps.is_some() {
        f.clumps = on.then(sward::scene::Clumps::default);
    }
    if let Some(c) = &mut f.clumps {
        ui.add(egui::Slider::new(&mut c.size, 0.05..=5.0).text("clump size m"));
        ui.add(egui::Slider::new(&mut c.align, 0.0..=1.0).text("align"));
        ui.add(egui::Slider::new(&mut c.lean, -30.0..=30.0).text("lean °"));
        ui.add(egui::Slider::new(&mut c.color_variation, 0.0..=1.0).text("colour variation"));
    }
    let mut flowers = f.flowers.is_some();
    ui.checkbox(&mut flowers, "flowers");
    if flowers != f.flowers.is_some() {
        f.flowers = flowers.then(sward::scene::Flowers::default);
    }
    if let Some(fl) = &mut f.flowers {
        ui.add(egui::Slider::new(&mut fl.fraction, 0.0..=0.3).text("share of blades"));
        ui.add(egui::Slider::new(&mut fl.head_size, 0.01..=0.15).text("head radius m"));
        for kind in &mut fl.kinds {
            ui.horizontal(|ui| {
                let mut p = [kind.petals.0, kind.petals.1, kind.petals.2];
                if ui.color_edit_button_rgb(&mut p).changed() {
                    kind.petals = (p[0], p[1], p[2]);
                }
                let mut c = [kind.centre.0, kind.centre.1, kind.centre.2];
                if ui.color_edit_button_rgb(&mut c).changed() {
                    kind.centre = (c[0], c[1], c[2]);
                }
                ui.add(egui::Slider::new(&mut kind.petal_count, 3..=16).text("petals"));
            });
        }
    }
}
