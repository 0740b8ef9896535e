//! The egui side panel: one collapsible section per part of the pipeline (Field, Physics,
//! Wind, Culling, Rendering, Stats), the AGC editor's inspector, Save / Load, and the Help
//! window. Live settings write straight into the renderer's scene, which the next frame
//! reads; settings that need new GPU resources (the field, the wind grid) are applied by a
//! button or right away through a rebuild.

use egui::{Color32, RichText, Ui};

use super::camera::CameraMode;
use super::state::{AppState, Mode, Status};
use sward::gpu::Gpu;
use sward::render::timing::PASSES;
use sward::scene::{
    Advection, Boundary, ColorMode, PressureSolver, Range, SelfShadow, Shape, WindSource,
};
use sward::sim::fluid::{MAX_LAYERS, MAX_MULTIGRID_CYCLES};

/// Keyboard and mouse shortcuts, shown in the Help window (and listed in the README and docs/window.md).
pub const SHORTCUTS: &[(&str, &str)] = &[
    ("W A S D", "fly forward / left / back / right"),
    ("Q / E", "down / up"),
    ("Shift", "move 4× faster"),
    (
        "Right drag",
        "look around (orbit: rotate around the centre)",
    ),
    ("Wheel", "fly speed (orbit / follow: distance)"),
    ("O", "orbit camera on / off"),
    ("F", "follow the character ball on / off"),
    (
        "G",
        "walk mode on / off: the camera behind the animated character, W/S walk, A/D turn",
    ),
    ("Tab", "switch Play / Edit mode"),
    ("Space", "throw a ball where the camera looks"),
    ("Left click (Play)", "throw a ball at the cursor"),
    ("Arrow keys", "steer the character ball"),
    ("C", "clear thrown balls"),
    (
        "Left click (Edit)",
        "on the ground: new guide root; on a point: select it",
    ),
    (
        "Left drag (Edit)",
        "move the selected point over the terrain",
    ),
    (
        "Alt + left click (Edit)",
        "add a child arrow from the selected point (branching)",
    ),
    (
        "Delete (Edit)",
        "delete the selected point (a root deletes its guide)",
    ),
    ("Escape", "deselect"),
    (
        "Ctrl+Z / Ctrl+Y",
        "undo / redo guide edits (Ctrl+Shift+Z redoes too)",
    ),
    ("Ctrl+S", "save the scene to the path in the panel"),
    ("H or F1", "this help"),
];

fn range_ui(
    ui: &mut Ui,
    label: &str,
    r: &mut Range,
    limits: std::ops::RangeInclusive<f32>,
    unit: &str,
) {
    ui.horizontal(|ui| {
        ui.label(label);
        ui.add(
            egui::DragValue::new(&mut r.min)
                .range(limits.clone())
                .speed(0.01)
                .suffix(unit),
        );
        ui.label("to");
        ui.add(
            egui::DragValue::new(&mut r.max)
                .range(limits)
                .speed(0.01)
                .suffix(unit),
        );
    });
    if r.max < r.min {
        r.max = r.min;
    }
}

/// The whole panel; `gpu` serves the buttons that rebuild GPU resources. Its right edge
/// goes to `app.panel_px`: the 3D view is drawn beside it, not under it.
pub fn panel(ui: &mut Ui, app: &mut AppState, gpu: &Gpu) {
    let shown = egui::Panel::left("sward.panel")
        .resizable(true)
        .default_size(330.0)
        .show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                header(ui, app);
                ui.separator();
                editor_section(ui, app);
                scene_section(ui, app, gpu);
                field_section(ui, app, gpu);
                physics_section(ui, app, gpu);
                wind_section(ui, app, gpu);
                culling_section(ui, app);
                rendering_section(ui, app);
                let max_texture = gpu.device.limits().max_texture_dimension_2d;
                super::panel_light::light_section(ui, app, max_texture);
                camera_section(ui, app);
                stats_section(ui, app, gpu);
            });
        });
    let right = shown.response.rect.right() * ui.ctx().pixels_per_point();
    app.panel_px = right.ceil().max(0.0) as u32;
    help_window(ui.ctx(), app);
}

fn header(ui: &mut Ui, app: &mut AppState) {
    ui.horizontal(|ui| {
        ui.heading("sward");
        ui.selectable_value(&mut app.mode, Mode::Play, "Play");
        ui.selectable_value(&mut app.mode, Mode::Edit, "Edit wind");
        if ui.button("Help").clicked() {
            app.show_help = !app.show_help;
        }
    });
    ui.horizontal(|ui| {
        ui.checkbox(&mut app.paused, "Pause");
        if ui.button("Clear balls").clicked() {
            app.balls.clear();
        }
        ui.label(format!("{} balls", app.balls.thrown.len()));
    });
    match &app.status {
        Some(Status::Info(s)) => {
            ui.label(s.as_str());
        }
        Some(Status::Error(s)) => {
            ui.colored_label(Color32::from_rgb(255, 110, 90), s.as_str());
        }
        None => {}
    }
}

fn editor_section(ui: &mut Ui, app: &mut AppState) {
    egui::CollapsingHeader::new("Wind arrows (AGC editor)")
        .default_open(true)
        .show(ui, |ui| {
            if app.mode != Mode::Edit {
                ui.label("Tab or \"Edit wind\" to place arrows: click the ground for a root, Alt+click for a child arrow.");
            }
            ui.horizontal(|ui| {
                if ui.add_enabled(app.editor.can_undo(), egui::Button::new("Undo")).clicked() {
                    app.editor.undo();
                }
                if ui.add_enabled(app.editor.can_redo(), egui::Button::new("Redo")).clicked() {
                    app.editor.redo();
                }
                ui.label(format!("{} guide(s)", app.editor.guides().len()));
                let which = if app.editor.selection().is_some() {
                    "the selected guide's arrows switch off and come on again from its root"
                } else {
                    "every guide's arrows switch off and come on again from the roots"
                };
                if ui
                    .add_enabled(!app.editor.guides().is_empty(), egui::Button::new("Replay the sequence"))
                    .on_hover_text(which)
                    .clicked()
                {
                    app.editor.replay_sequence();
                }
            });
            ui.horizontal(|ui| {
                ui.label("New guides:");
                ui.add(egui::DragValue::new(&mut app.editor.new_strength).range(0.0..=100.0).speed(0.1).suffix(" m/s²"));
                ui.add(egui::DragValue::new(&mut app.editor.new_radius).range(0.1..=20.0).speed(0.05).suffix(" m"));
            });
            match app.editor.selection() {
                Some((g, p)) => {
                    ui.separator();
                    let what = if p == 0 { "root" } else { "point" };
                    ui.label(RichText::new(format!("Guide {g}, {what} {p}")).strong());
                    if let Some(mut s) = app.editor.strength_of_selected() {
                        ui.horizontal(|ui| {
                            ui.label("Strength");
                            let slider = ui.add(egui::Slider::new(&mut s, 0.0..=40.0).suffix(" m/s²"));
                            let number = ui.add(egui::DragValue::new(&mut s).range(0.0..=1000.0).speed(0.1));
                            if slider.changed() || number.changed() {
                                app.editor.set_strength(s);
                            }
                            // One undo step per drag of the slider, not one per frame.
                            if slider.drag_stopped() || number.drag_stopped() || number.lost_focus() {
                                app.editor.end_slider_edit();
                            }
                        });
                    }
                    if let Some(mut r) = app.editor.radius_of_selected() {
                        ui.horizontal(|ui| {
                            ui.label("Radius");
                            let slider = ui.add(egui::Slider::new(&mut r, 0.1..=20.0).suffix(" m"));
                            if slider.changed() {
                                app.editor.set_radius(r);
                            }
                            if slider.drag_stopped() {
                                app.editor.end_slider_edit();
                            }
                        });
                    }
                    ui.horizontal(|ui| {
                        if ui.button("Add child arrow").clicked() {
                            app.editor.add_child_of_selected();
                        }
                        if ui.button("Delete").clicked() {
                            app.editor.delete_selected();
                        }
                        if ui.button("Deselect").clicked() {
                            app.editor.select(None);
                        }
                    });
                }
                None => {
                    ui.label("No point selected.");
                }
            }
            if let Some(e) = &app.editor.error {
                ui.colored_label(Color32::from_rgb(255, 110, 90), e.as_str());
            }
        });
}

fn scene_section(ui: &mut Ui, app: &mut AppState, gpu: &Gpu) {
    egui::CollapsingHeader::new("Scene file").show(ui, |ui| {
        ui.horizontal(|ui| {
            ui.label("Path");
            if ui.text_edit_singleline(&mut app.scene_path).changed() {
                // Typing the path is picking it: Save may write there again.
                app.unsaveable = None;
            }
        });
        ui.horizontal(|ui| {
            if ui.button("Save").clicked() {
                app.save();
            }
            if ui.button("Load").clicked() {
                app.load(gpu);
            }
        });
    });
}

fn field_section(ui: &mut Ui, app: &mut AppState, gpu: &Gpu) {
    egui::CollapsingHeader::new("Field").show(ui, |ui| {
        let f = &mut app.field_draft;
        ui.add(
            egui::Slider::new(&mut f.density, 1.0..=400.0)
                .logarithmic(true)
                .text("density /m²"),
        );
        range_ui(ui, "height", &mut f.height, 0.01..=5.0, " m");
        range_ui(ui, "width", &mut f.width, 0.001..=0.5, " m");
        range_ui(ui, "stiffness", &mut f.stiffness, 0.1..=100.0, " 1/s");
        egui::ComboBox::new("sward.shape", "shape")
            .selected_text(format!("{:?}", f.shape))
            .show_ui(ui, |ui| {
                for s in [
                    Shape::Quad,
                    Shape::Triangle,
                    Shape::Quadratic,
                    Shape::TriangleTip,
                    Shape::Dandelion,
                ] {
                    ui.selectable_value(&mut f.shape, s, format!("{s:?}"));
                }
            });
        let mut streamed = f.tile_size > 0.0;
        ui.checkbox(&mut streamed, "stream in tiles around the camera")
            .on_hover_text("tiles within the blade radius (culling max distance) are generated on the GPU as you fly");
        if streamed && f.tile_size <= 0.0 {
            f.tile_size = 8.0;
        } else if !streamed {
            f.tile_size = 0.0;
        }
        if streamed {
            ui.add(egui::Slider::new(&mut f.tile_size, 0.5..=64.0).text("tile size m"));
        }
        match app.renderer.tile_stats() {
            Some(t) => ui.label(format!(
                "pool of {} blades: {} tiles of {} (now {} resident)",
                app.renderer.buffers.count, t.slots, t.blades_per_tile, t.resident
            )),
            None => {
                let size = app.renderer.scene.terrain.size;
                ui.label(format!(
                    "≈ {:.0} blades (now {})",
                    f.density as f64 * (size as f64).powi(2),
                    app.renderer.buffers.count
                ))
            }
        };
        super::panel_models::species_controls(ui, &mut app.field_draft);
        if ui.button("Regenerate").clicked() {
            app.regenerate(gpu);
        }
    });
}

fn physics_section(ui: &mut Ui, app: &mut AppState, gpu: &Gpu) {
    egui::CollapsingHeader::new("Physics").show(ui, |ui| {
        super::panel_models::model_controls(ui, app, gpu);
        super::panel_models::propagation_controls(ui, app, gpu);
        super::panel_models::trail_controls(ui, app, gpu);
        let p = &mut app.renderer.scene.physics;
        ui.add(egui::Slider::new(&mut p.gravity_acceleration, 0.0..=30.0).text("gravity m/s²"));
        ui.add(egui::Slider::new(&mut p.mass, 0.0..=1.0).text("mass"));
        ui.add(egui::Slider::new(&mut p.stiffness_scale, 0.05..=4.0).text("stiffness scale"));
        ui.add(egui::Slider::new(&mut p.collision_decay, 0.0..=5.0).text("η decay 1/s"));
        ui.add(egui::Slider::new(&mut p.max_dt, 0.001..=0.1).text("Δt clamp s"));
        ui.checkbox(&mut p.collisions, "collisions");
        ui.checkbox(
            &mut p.collision_hierarchy,
            "collider hierarchy (BVH, precision by distance)",
        );
        if p.collision_hierarchy {
            ui.add(
                egui::Slider::new(&mut p.hierarchy_precision_distance, 0.5..=200.0)
                    .logarithmic(true)
                    .text("exact within m"),
            );
        }
    });
}

fn wind_section(ui: &mut Ui, app: &mut AppState, gpu: &Gpu) {
    egui::CollapsingHeader::new("Wind").show(ui, |ui| {
        let mut rebuild = false;
        let wind = &mut app.renderer.scene.wind;
        ui.horizontal(|ui| {
            ui.label("source");
            for s in [WindSource::Analytic, WindSource::Fluid, WindSource::Both] {
                rebuild |= ui
                    .selectable_value(&mut wind.source, s, format!("{s:?}"))
                    .changed();
            }
        });
        let f = &mut wind.fluid;
        let mut resolution = f.resolution;
        egui::ComboBox::new("sward.grid", "grid resolution")
            .selected_text(format!("{resolution}²"))
            .show_ui(ui, |ui| {
                for r in [64, 128, 256, 512, 1024] {
                    ui.selectable_value(&mut resolution, r, format!("{r}²"));
                }
            });
        if resolution != f.resolution {
            f.resolution = resolution;
            rebuild = true;
        }
        // Layers change every grid's size: a new solver. Their height and the ground drag
        // are uniforms, taken live.
        let layers = f.layers;
        ui.add(egui::Slider::new(&mut f.layers, 1..=MAX_LAYERS).text("layers (1 = 2D)"));
        rebuild |= f.layers != layers;
        if f.layers > 1 {
            ui.add(
                egui::Slider::new(&mut f.layer_height, 0.05..=5.0)
                    .logarithmic(true)
                    .text("layer height m"),
            );
            ui.add(egui::Slider::new(&mut f.ground_drag, 0.0..=20.0).text("ground drag 1/s"));
        }
        ui.horizontal(|ui| {
            ui.label("pressure");
            for s in [PressureSolver::Multigrid, PressureSolver::Jacobi] {
                ui.selectable_value(&mut f.pressure_solver, s, format!("{s:?}"));
            }
        });
        match f.pressure_solver {
            PressureSolver::Jacobi => ui.add(
                egui::Slider::new(&mut f.pressure_iterations, 1..=200).text("Jacobi iterations"),
            ),
            PressureSolver::Multigrid => ui.add(
                egui::Slider::new(&mut f.multigrid_cycles, 1..=MAX_MULTIGRID_CYCLES)
                    .text("V-cycles"),
            ),
        };
        ui.checkbox(&mut f.warm_start, "warm start (last frame's pressure)");
        ui.horizontal(|ui| {
            ui.label("advection");
            for a in [Advection::SemiLagrangian, Advection::MacCormack] {
                ui.selectable_value(&mut f.advection, a, format!("{a:?}"));
            }
        });
        ui.add(egui::Slider::new(&mut f.vorticity, 0.0..=50.0).text("vorticity ε 1/s"));
        ui.add(egui::Slider::new(&mut f.dissipation, 0.0..=5.0).text("dissipation 1/s"));
        ui.add(egui::Slider::new(&mut f.response, 0.0..=10.0).text("blade response 1/s"));
        // A grid that follows the camera (unbounded terrains); it cannot wrap around.
        let mut follow = f.extent > 0.0;
        if ui
            .checkbox(&mut follow, "grid follows the camera")
            .changed()
        {
            f.extent = if follow { 128.0 } else { 0.0 };
            if follow && f.boundary == Boundary::Periodic {
                f.boundary = Boundary::Open;
            }
            rebuild = true;
        }
        if f.extent > 0.0 {
            let before = f.extent;
            ui.add(
                egui::Slider::new(&mut f.extent, 16.0..=4096.0)
                    .logarithmic(true)
                    .text("grid side m"),
            );
            rebuild |= f.extent != before;
        }
        ui.horizontal(|ui| {
            ui.label("boundary");
            for b in [Boundary::Open, Boundary::Closed, Boundary::Periodic] {
                if b != Boundary::Periodic || f.extent <= 0.0 {
                    ui.selectable_value(&mut f.boundary, b, format!("{b:?}"));
                }
            }
        });
        if let Some(d) = &mut wind.directional {
            ui.add(egui::Slider::new(&mut d.strength, 0.0..=20.0).text("directional m/s²"));
        }
        let mut overlay = app.renderer.overlay_enabled();
        if ui
            .checkbox(&mut overlay, "overlay (air velocity + guides)")
            .changed()
        {
            if overlay {
                app.renderer.enable_overlay(gpu, app.format);
            } else {
                app.renderer.disable_overlay();
            }
        }
        if rebuild {
            app.rebuild_wind(gpu);
        } else {
            // One borrow of the renderer behind the embedding API for the fluid and the
            // scene it reads.
            let r = &mut *app.renderer;
            let size = r.scene.terrain.size;
            let applied = match &mut r.fluid {
                Some(fluid) => fluid.apply_settings(&r.scene.wind.fluid, size),
                None => true,
            };
            if !applied {
                app.rebuild_wind(gpu);
            }
        }
    });
}

fn culling_section(ui: &mut Ui, app: &mut AppState) {
    egui::CollapsingHeader::new("Culling").show(ui, |ui| {
        let before = app.renderer.scene.culling.clone();
        let c = &mut app.renderer.scene.culling;
        ui.checkbox(&mut c.patches, "patch boxes");
        ui.checkbox(&mut c.orientation, "orientation");
        ui.add(
            egui::Slider::new(&mut c.orientation_threshold, 0.0..=1.0)
                .text("orientation threshold"),
        );
        ui.checkbox(&mut c.frustum, "view frustum");
        ui.add(egui::Slider::new(&mut c.frustum_tolerance, 0.0..=1.0).text("frustum tolerance"));
        ui.checkbox(&mut c.distance, "distance");
        ui.add(egui::Slider::new(&mut c.distance_levels, 1..=64).text("distance levels n"));
        ui.add(
            egui::Slider::new(&mut c.max_distance, 1.0..=500.0)
                .logarithmic(true)
                .text("d_max m"),
        );
        ui.checkbox(&mut c.occlusion, "occlusion (depth pyramid)");
        ui.add(egui::Slider::new(&mut c.occlusion_bias, 0.0..=0.2).text("occlusion bias"));
        ui.checkbox(&mut c.grass_occlusion, "grass hides grass (late test)");
        ui.add(
            egui::Slider::new(&mut c.grass_occlusion_bias, 0.0..=0.2).text("grass occlusion bias"),
        );
        ui.separator();
        ui.checkbox(&mut c.lod, "levels of detail");
        ui.add(
            egui::Slider::new(&mut c.lod_near_px, 1.0..=256.0)
                .logarithmic(true)
                .text("full mesh from px"),
        );
        ui.add(
            egui::Slider::new(&mut c.lod_far_px, 1.0..=128.0)
                .logarithmic(true)
                .text("middle mesh from px"),
        );
        ui.add(egui::Slider::new(&mut c.lod_morph, 0.0..=1.0).text("morph band"));
        // The middle level's morph band must end below the near threshold (the scene
        // loader refuses such a file; the sliders push the near threshold up instead).
        c.lod_near_px = c.lod_near_px.max(c.lod_far_px * (1.0 + c.lod_morph));
        ui.separator();
        ui.add(
            egui::Slider::new(&mut c.physics_throttle, 1..=16)
                .text("unseen patches step every n frames"),
        );
        ui.add(egui::Slider::new(&mut c.physics_radius, 0.0..=100.0).text("always step within m"));
        // A hand edit is the user's new ceiling for the frame budget.
        if *c != before {
            app.budget.rebase(&app.renderer.scene.culling);
        }
        let mut frozen = app.renderer.cull_camera.is_some();
        if ui
            .checkbox(&mut frozen, "freeze the culling camera")
            .changed()
        {
            app.set_cull_frozen(frozen);
        }
        ui.horizontal(|ui| {
            ui.label("target frame time");
            let mut on = app.budget.target_ms.is_some();
            ui.checkbox(&mut on, "");
            let mut ms = app.budget.target_ms.unwrap_or(100.0);
            ui.add_enabled(
                on,
                egui::DragValue::new(&mut ms)
                    .range(5.0..=1000.0)
                    .suffix(" ms"),
            );
            app.budget.target_ms = on.then_some(ms);
        });
        ui.label(&app.shown.budget);
    });
}

fn rendering_section(ui: &mut Ui, app: &mut AppState) {
    egui::CollapsingHeader::new("Rendering").show(ui, |ui| {
        let has_lines = app.renderer.has_wireframe();
        let samples = app.renderer.msaa_samples();
        let r = &mut app.renderer.scene.render;
        ui.add_enabled(
            has_lines,
            egui::Checkbox::new(&mut r.wireframe, "wireframe"),
        );
        if !has_lines {
            ui.label("(this adapter cannot draw lines)");
        }
        ui.checkbox(&mut r.deferred_grass, "deferred grass light")
            .on_hover_text(
                "Light the grass once per pixel after the draw (without MSAA, flowers or a \
                 colour view); off: lit as it is drawn",
            );
        // MSAA: the renderer rebuilds its pipelines and targets before the next frame.
        ui.horizontal(|ui| {
            ui.label("MSAA");
            for n in sward::render::msaa::SAMPLE_COUNTS {
                ui.selectable_value(&mut r.msaa, n, format!("{n}×"));
            }
        });
        ui.add_enabled(r.msaa == 1, egui::Checkbox::new(&mut r.taa, "TAA"))
            .on_hover_text(
                "Temporal anti-aliasing at MSAA 1×: a jittered projection blended with the \
                 last frames through each pixel's motion (the blade's own for grass)",
            );
        if samples != r.msaa {
            ui.label(format!("(this adapter gives {samples}× for {}×)", r.msaa));
        }
        ui.horizontal(|ui| {
            ui.label("colour");
            for m in [
                ColorMode::Natural,
                ColorMode::Lod,
                ColorMode::Patch,
                ColorMode::Trail,
            ] {
                let name = match m {
                    ColorMode::Natural => "natural",
                    ColorMode::Lod => "by LOD",
                    ColorMode::Patch => "by patch",
                    ColorMode::Trail => "by trail (η)",
                };
                ui.selectable_value(&mut r.color_mode, m, name);
            }
        });
        egui::ComboBox::new("sward.shape_live", "shape")
            .selected_text(format!("{:?}", app.renderer.scene.field.shape))
            .show_ui(ui, |ui| {
                for s in [
                    Shape::Quad,
                    Shape::Triangle,
                    Shape::Quadratic,
                    Shape::TriangleTip,
                    Shape::Dandelion,
                ] {
                    ui.selectable_value(&mut app.renderer.scene.field.shape, s, format!("{s:?}"));
                }
            });
        // While the time of day places the sun, `render.sun_direction` is not used: the
        // sliders are shown greyed out, saying what steers the sun instead.
        let by_time = app.renderer.scene.light.time_of_day.is_some();
        let r = &mut app.renderer.scene.render;
        // The sun as azimuth / elevation: easier to steer than a raw vector.
        let d = glam::Vec3::from(r.sun_direction).normalize_or(glam::Vec3::Y);
        let mut azimuth = d.z.atan2(d.x).to_degrees();
        let mut elevation = d.y.clamp(-1.0, 1.0).asin().to_degrees();
        const BY_TIME: &str = "the sun follows the time of day (Light and shadows); \
                               untick \"sun by time of day\" there to steer it here";
        let a = ui
            .add_enabled(
                !by_time,
                egui::Slider::new(&mut azimuth, -180.0..=180.0).text("sun azimuth °"),
            )
            .on_disabled_hover_text(BY_TIME);
        let e = ui
            .add_enabled(
                !by_time,
                egui::Slider::new(&mut elevation, 2.0..=90.0).text("sun elevation °"),
            )
            .on_disabled_hover_text(BY_TIME);
        if !by_time && (a.changed() || e.changed()) {
            let (az, el) = (azimuth.to_radians(), elevation.to_radians());
            r.sun_direction = (el.cos() * az.cos(), el.sin(), el.cos() * az.sin());
        }
        ui.checkbox(&mut r.displacement, "3D displacement (Eq. 23)");
        ui.add(egui::Slider::new(&mut r.width_span_px, 0.0..=8.0).text("width correction span px"));
        ui.add(
            egui::Slider::new(&mut r.billboard_distance, 0.0..=1000.0)
                .text("billboards to m (0 off)"),
        )
        .on_hover_text("cards of grass from the blades' radius out to this distance");
        self_shadow_ui(ui, &mut r.self_shadow);
    });
}

/// The self-shadow mode and, for CWD-Sim's Eq. 14, its four parameters.
fn self_shadow_ui(ui: &mut Ui, shadow: &mut SelfShadow) {
    let name = match shadow {
        SelfShadow::Height => "height (sward)",
        SelfShadow::Cwd { .. } => "CWD-Sim Eq. 14",
        SelfShadow::Off => "off",
    };
    egui::ComboBox::new("sward.self_shadow", "self-shadow")
        .selected_text(name)
        .show_ui(ui, |ui| {
            ui.selectable_value(shadow, SelfShadow::Height, "height (sward)");
            if ui
                .selectable_label(matches!(shadow, SelfShadow::Cwd { .. }), "CWD-Sim Eq. 14")
                .clicked()
                && !matches!(shadow, SelfShadow::Cwd { .. })
            {
                *shadow = SelfShadow::CWD;
            }
            ui.selectable_value(shadow, SelfShadow::Off, "off");
        });
    if let SelfShadow::Cwd { min, max, c1, c2 } = shadow {
        ui.add(egui::Slider::new(min, 0.0..=1.0).text("m_min"));
        ui.add(egui::Slider::new(max, *min..=2.0).text("m_max"));
        ui.add(egui::Slider::new(c1, 0.0..=3.0).text("c1 (bend)"));
        ui.add(egui::Slider::new(c2, -1.0..=1.0).text("c2 (offset)"));
    }
}

fn camera_section(ui: &mut Ui, app: &mut AppState) {
    egui::CollapsingHeader::new("Camera").show(ui, |ui| {
        ui.horizontal(|ui| {
            for (m, name) in [
                (CameraMode::Fly, "fly"),
                (CameraMode::Orbit, "orbit"),
                (CameraMode::Follow, "follow ball"),
            ] {
                if ui.selectable_label(app.camera.mode == m, name).clicked() {
                    let follow = app.followed();
                    app.camera.set_mode(m, follow);
                }
            }
            // Walk mode: behind the scene's animated character, W/S/A/D steer it.
            let walking = app.camera.mode == CameraMode::Behind;
            if ui
                .selectable_label(walking, "walk (G)")
                .on_hover_text(
                    "the camera behind the scene's animated character: W/S walk, A/D turn, \
                     Shift runs",
                )
                .clicked()
            {
                app.toggle_walk();
            }
        });
        if let Some(w) = &app.walker {
            ui.label(format!(
                "walker at ({:.1}, {:.1}), {:.1} m/s, heading {:.0}°",
                w.position.x,
                w.position.y,
                w.speed,
                w.heading.to_degrees()
            ));
        }
        ui.add(
            egui::Slider::new(&mut app.camera.speed, 0.5..=200.0)
                .logarithmic(true)
                .text("speed m/s"),
        );
        ui.add(egui::Slider::new(&mut app.camera.fov_y, 20.0..=100.0).text("fov °"));
        let e = app.camera.eye;
        ui.label(format!("eye ({:.1}, {:.1}, {:.1})", e.x, e.y, e.z));
    });
}

fn stats_section(ui: &mut Ui, app: &mut AppState, gpu: &Gpu) {
    egui::CollapsingHeader::new("Stats")
        .default_open(true)
        .show(ui, |ui| {
            // The figures of the last refresh (every few frames, with the GPU times).
            let times = &app.shown.frame_times;
            let last = times.last().copied().unwrap_or(0.0);
            let n = times.len().max(1) as f32;
            let mean = times.iter().sum::<f32>() / n;
            ui.label(format!(
                "{:.1} fps   frame {:.1} ms (mean {:.1} ms)",
                if mean > 0.0 { 1000.0 / mean } else { 0.0 },
                last,
                mean
            ));
            let c = &app.stats.counters;
            let [l0, l1, l2] = c.per_level();
            ui.label(format!(
                "blades {}   drawn {} (LOD {l0} / {l1} / {l2}; {} late)   billboards drawn {}",
                app.renderer.buffers.count,
                c.drawn(),
                c.drawn_late(),
                app.stats.billboards_drawn
            ));
            ui.label(format!(
                "culled: patch {}  orientation {}  frustum {}  distance {}  occlusion {} ({} by grass)",
                c.culled_patch,
                c.culled_orientation,
                c.culled_frustum,
                c.culled_distance,
                c.culled_occlusion,
                c.culled_occlusion_grass
            ));
            ui.label(format!(
                "patches: {} visible, {} stepped ({} throttled)",
                c.visible_patches, c.updated_patches, c.throttled_patches
            ));
            ui.label(format!(
                "blades stepped: {} ({} at the throttled rate)",
                u64::from(c.updated_chunks) * u64::from(sward::sim::layout::UPDATE_CHUNK),
                u64::from(c.throttled_chunks) * u64::from(sward::sim::layout::UPDATE_CHUNK)
            ));
            ui.label(format!(
                "blades reset (non-finite state, since start): {}",
                app.stats.blades_reset_nonfinite
            ));
            // The far levels' calibration on the blades (`render::far_gain`).
            ui.label(match app.far_gain {
                Some(g) => format!("far levels' light gain: {:.2} {:.2} {:.2}", g.x, g.y, g.z),
                None => "far levels' light gain: not measured yet".to_string(),
            });
            let far = app.far_calibration;
            ui.label(format!(
                "blades against the far light model: {:.2} {:.2} {:.2} (running mean); cards' \
                 contrast gain: {:.2}; far field's distance gain: {:.2}",
                far.ratio.x, far.ratio.y, far.ratio.z, far.contrast, far.distance
            ));
            ui.label(format!(
                "gusts' mean bend at the edge of the blades' reach: {:.2} (0 calm, 1 bent \
                 two thirds of the height)",
                far.bend
            ));
            // The sectors measured (`render::far_sectors`): the spread across directions.
            let measured: Vec<f32> = far.sectors.iter().copied().filter(|m| *m > 0.0).collect();
            ui.label(match (
                measured.iter().copied().reduce(f32::min),
                measured.iter().copied().reduce(f32::max),
            ) {
                (Some(lo), Some(hi)) => format!(
                    "far levels by direction: {lo:.2} to {hi:.2} times the gain ({} of {} \
                     sectors measured)",
                    measured.len(),
                    far.sectors.len()
                ),
                _ => "far levels by direction: not measured yet".to_string(),
            });
            match app.stats.pass_ms {
                Some(ms) => {
                    let text: Vec<String> = PASSES
                        .iter()
                        .zip(ms)
                        .map(|(name, t)| format!("{name} {t:.2}"))
                        .collect();
                    ui.label(format!("GPU ms: {}", text.join("  ")));
                }
                None => {
                    ui.label("GPU ms: no timestamp queries on this adapter");
                }
            }
            if let Some(t) = app.stats.tiles {
                ui.label(format!(
                    "tiles: {} resident of {} slots ({:.1} m, {} blades each); generated {} \
                     ({:.1}/s)",
                    t.resident,
                    t.slots,
                    t.tile_size,
                    t.blades_per_tile,
                    t.generated_total,
                    app.tile_rate
                ));
            }
            ui.label(format!("frame budget: {}", app.shown.budget));
            let (w, h) = app.render_size();
            ui.label(format!(
                "resolution scale {:.2}: 3D passes at {w}x{h} of {}x{}",
                app.budget.scale(),
                app.size.0,
                app.size.1
            ));
            if let Some(wind) = &app.stats.wind_ms {
                let total: f64 = wind.iter().map(|(_, t)| t).sum();
                ui.label(format!("wind solver GPU ms: {total:.2}"));
            }
            super::panel_work::work_counters(ui, app, gpu);
            frame_plot(ui, app);
        });
}

/// The last seconds of frame times as a line, with the budget's target as a dashed level.
fn frame_plot(ui: &mut Ui, app: &AppState) {
    let (response, painter) =
        ui.allocate_painter(egui::vec2(ui.available_width(), 70.0), egui::Sense::hover());
    let rect = response.rect;
    painter.rect_filled(rect, 2.0, Color32::from_gray(24));
    let times = &app.shown.frame_times;
    let top = times
        .iter()
        .copied()
        .fold(app.budget.target_ms.unwrap_or(16.7), f32::max)
        * 1.1;
    let y = |ms: f32| rect.bottom() - (ms / top).clamp(0.0, 1.0) * rect.height();
    let n = times.len();
    if n > 1 {
        let step = rect.width() / (super::state::PLOT_FRAMES - 1) as f32;
        let x0 = rect.right() - step * (n - 1) as f32;
        let points: Vec<egui::Pos2> = times
            .iter()
            .enumerate()
            .map(|(i, &ms)| egui::pos2(x0 + step * i as f32, y(ms)))
            .collect();
        painter.add(egui::Shape::line(
            points,
            egui::Stroke::new(1.5, Color32::from_rgb(120, 220, 120)),
        ));
    }
    if let Some(t) = app.budget.target_ms {
        let yt = y(t);
        painter.add(egui::Shape::dashed_line(
            &[egui::pos2(rect.left(), yt), egui::pos2(rect.right(), yt)],
            egui::Stroke::new(1.0, Color32::from_rgb(230, 180, 80)),
            4.0,
            3.0,
        ));
    }
    painter.text(
        rect.left_top() + egui::vec2(4.0, 2.0),
        egui::Align2::LEFT_TOP,
        format!("{top:.0} ms"),
        egui::FontId::monospace(10.0),
        Color32::GRAY,
    );
}

fn help_window(ctx: &egui::Context, app: &mut AppState) {
    let mut open = app.show_help;
    egui::Window::new("Help").open(&mut open).show(ctx, |ui| {
        egui::Grid::new("sward.help").striped(true).show(ui, |ui| {
            for (keys, what) in SHORTCUTS {
                ui.label(RichText::new(*keys).monospace());
                ui.label(*what);
                ui.end_row();
            }
        });
    });
    app.show_help = open;
}
