//! The panel's "Light and shadows" section (`light`): the sun by time of day or fixed, the
//! sky, exposure and tone mapping, the sun's shadow maps and the blade shading terms. The
//! renderer reads the scene's light every frame, so every control acts on the next frame;
//! a shadow map of another size or cascade count is reallocated then.

use egui::Ui;

use super::state::AppState;
use sward::scene::{BladeShadowLookup, Shading, SkyModel, ToneMapping};

/// Shadow map sizes offered, up to the adapter's largest texture.
const RESOLUTIONS: [u32; 4] = [512, 1024, 2048, 4096];

pub fn light_section(ui: &mut Ui, app: &mut AppState, max_texture: u32) {
    egui::CollapsingHeader::new("Light and shadows").show(ui, |ui| {
        let l = &mut app.renderer.scene.light;
        let mut by_time = l.time_of_day.is_some();
        ui.checkbox(&mut by_time, "sun by time of day");
        if by_time != l.time_of_day.is_some() {
            l.time_of_day = by_time.then_some(17.0);
        }
        if let Some(hours) = &mut l.time_of_day {
            ui.add(egui::Slider::new(hours, 0.0..=24.0).text("time of day h"));
            ui.add(egui::Slider::new(&mut l.latitude, -89.0..=89.0).text("latitude °"));
            ui.add(egui::Slider::new(&mut l.day_of_year, 1..=366).text("day of year"));
            ui.add(egui::Slider::new(&mut l.north, -180.0..=180.0).text("north °"));
        }
        ui.horizontal(|ui| {
            ui.label("sky");
            ui.selectable_value(&mut l.sky, SkyModel::Preetham, "Preetham");
            ui.selectable_value(&mut l.sky, SkyModel::Gradient, "gradient");
        });
        ui.add(egui::Slider::new(&mut l.turbidity, 1.7..=10.0).text("turbidity"));
        ui.add(egui::Slider::new(&mut l.exposure, -4.0..=4.0).text("exposure EV"));
        ui.horizontal(|ui| {
            ui.label("tone mapping");
            ui.selectable_value(&mut l.tone_mapping, ToneMapping::Aces, "ACES");
            ui.selectable_value(&mut l.tone_mapping, ToneMapping::Agx, "AgX");
            ui.selectable_value(&mut l.tone_mapping, ToneMapping::Clamp, "clamp");
        });
        ui.separator();
        let s = &mut l.shadows;
        ui.checkbox(&mut s.enabled, "sun shadows (cascaded shadow maps)");
        ui.add_enabled_ui(s.enabled, |ui| {
            ui.add(egui::Slider::new(&mut s.cascades, 1..=4).text("cascades"));
            ui.horizontal(|ui| {
                ui.label("texels");
                for r in RESOLUTIONS.into_iter().filter(|r| *r <= max_texture) {
                    ui.selectable_value(&mut s.resolution, r, r.to_string());
                }
            });
            ui.add(
                egui::Slider::new(&mut s.distance, 5.0..=500.0)
                    .logarithmic(true)
                    .text("distance m"),
            );
            ui.add(
                egui::Slider::new(&mut s.grass_radius, 0.0..=100.0).text("grass casts within m"),
            );
            ui.add(egui::Slider::new(&mut s.softness, 0.0..=8.0).text("softness texels"));
            ui.add(egui::Slider::new(&mut s.bias, 0.0..=16.0).text("bias texels"));
            ui.horizontal(|ui| {
                ui.label("on the blades");
                ui.selectable_value(
                    &mut s.blade_lookup,
                    BladeShadowLookup::PerPixel,
                    "per pixel",
                )
                .on_hover_text("the shadows of a blade's neighbours fall across it");
                ui.selectable_value(&mut s.blade_lookup, BladeShadowLookup::PerRow, "per row")
                    .on_hover_text(
                        "looked up at each blade's rows of vertices and interpolated along it: \
                         cheaper, the shadows across a blade lost",
                    );
            });
        });
        ui.separator();
        ui.label("blade shading (0 off, 1 sward's look)");
        for name in Shading::NAMES {
            if let Some(v) = l.shading.term_mut(name) {
                ui.add(egui::Slider::new(v, 0.0..=2.0).text(name.replace('_', " ")));
            }
        }
    });
}
