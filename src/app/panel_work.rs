//! The Stats section's work counters: a switch that counts every frame's work
//! (pipeline-statistics queries and the grass's coverage, `Renderer::count_work`) and the
//! last counted frame's table: invocations per pass and stage, and the lit grass's
//! fragments per covered pixel. Off by default: counting adds a depth-only draw of the
//! grass to every frame.

use egui::{RichText, Ui};

use super::state::AppState;
use sward::gpu::Gpu;

pub(super) fn work_counters(ui: &mut Ui, app: &mut AppState, gpu: &Gpu) {
    if !gpu.pipeline_statistics {
        ui.label("work counters: no pipeline-statistics queries on this adapter");
        return;
    }
    let mut on = app.renderer.counting_work();
    if ui
        .checkbox(&mut on, "count the work (shader invocations per pass)")
        .changed()
    {
        app.renderer.count_work(gpu, on);
    }
    if !on {
        return;
    }
    match app.renderer.last_work() {
        Some(work) => {
            let lines = sward::render::work::table(work, app.renderer.samples());
            ui.label(RichText::new(lines.join("\n")).monospace().small());
        }
        None => {
            ui.label("counting: the first counted frame is on its way back");
        }
    }
}
