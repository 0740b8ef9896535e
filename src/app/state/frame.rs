//! Recording the window's frame (`AppState::encode`): the world through the embedding
//! API, the guide arrows drawn into it, the upscale to the window; and the view region,
//! render size and Stats read-back the frame is drawn and measured with.

use std::time::Instant;

use glam::Vec3;

use super::{scaled_size, view_region, AppState, Mode, ShownStats};
use sward::embed::{Collider, FrameInputs, WorldTarget};
use sward::error::Result;
use sward::gpu::Gpu;
use sward::render::arrows::{ArrowMesh, ArrowPass};
use sward::render::camera::crop_x;
use sward::render::post::HDR_FORMAT;
use sward::render::timing;
use sward::scene::limits::MAX_SPHERES;

impl AppState {
    /// Records the frame: simulation step, cull, grass, then the guide arrows.
    ///
    /// # Errors
    ///
    /// What the embedding API refuses (`GrassRenderer::begin_world`): a frame too large
    /// for the device, a target that does not match the renderer.
    pub fn encode(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        dt: f32,
        output: &wgpu::TextureView,
        depth: &wgpu::TextureView,
    ) -> Result<()> {
        let color = output;
        let view = self.view();
        // Beside the panel or below scale 1 the 3D passes draw into a smaller target,
        // stretched over their region of `color` at the end; the panel is drawn after, at
        // the window's resolution.
        let size = self.render_size();
        let scaled = size != self.size;
        let crop = self.view_crop();
        let (color, depth) = if scaled {
            self.upscale.target(gpu, size)
        } else {
            (color, depth)
        };
        self.renderer.display_aspect = Some(self.size.0 as f32 / self.size.1.max(1) as f32);
        self.renderer.view_crop = crop;
        // The budget switches the anti-aliasing off without touching the scene (Save keeps
        // render.msaa and render.taa): MSAA by capping the samples, TAA outright.
        self.renderer
            .set_sample_cap(self.budget.msaa_off().then_some(1));
        self.renderer.taa_allowed = !self.budget.msaa_off();
        self.renderer.billboard_share = self.budget.billboards();
        self.renderer.grass_shadows = !self.budget.grass_shadows_off();
        self.renderer.lod_coarsen = self.budget.lod_coarsen();
        self.renderer.lod_morph = self.budget.lod_morph();
        self.renderer.fold = self.budget.fold();
        // The balls push the grass as a host's colliders do; a scene whose own spheres
        // leave less room keeps the newest balls that fit.
        let room = MAX_SPHERES.saturating_sub(self.renderer.scene_sphere_count());
        let mut colliders: Vec<Collider> = self
            .balls
            .spheres()
            .into_iter()
            .map(|(center, radius, velocity)| Collider {
                center,
                radius,
                velocity,
            })
            .collect();
        if colliders.len() > room {
            colliders.drain(..colliders.len() - room);
        }
        let inputs = FrameInputs {
            camera: view,
            size,
            dt,
            colliders: &colliders,
            depth: None,
            wind: None,
        };
        let target = WorldTarget { color, depth };
        self.renderer
            .begin_world(&gpu.device, &gpu.queue, encoder, &inputs, &target)?;
        // The arrows are drawn in the multisampled scene, before its resolve: they are
        // depth tested against the multisampled depth (the only one the scene wrote) and
        // their edges are anti-aliased like the grass.
        let samples = self.renderer.msaa_samples();
        if self.arrows.samples != samples {
            self.arrows = ArrowPass::new(gpu, HDR_FORMAT, samples);
        }
        let show_arrows = self.mode == Mode::Edit || self.renderer.overlay_enabled();
        let mesh = if show_arrows {
            ArrowMesh::build_at(
                self.editor.guides(),
                &self.renderer.terrain,
                self.editor.selection(),
                self.hover,
                Some(self.renderer.time),
            )
        } else {
            ArrowMesh::build(&[], &self.renderer.terrain, None, None)
        };
        let aspect = self.size.0 as f32 / self.size.1.max(1) as f32;
        let sun = Vec3::from(self.renderer.scene.render.sun_direction);
        self.arrows
            .prepare(gpu, &mesh, crop * view.view_proj(aspect), sun);
        let arrows = &self.arrows;
        // Timed only when drawn: a scope whose pass never ran reads the stale timestamps of
        // an earlier frame (the window's Stats showed 5-8 ms of "overlay" with no arrows).
        if let (false, Some(scene)) = (arrows.is_empty(), self.renderer.world_scene(&target)) {
            self.renderer
                .encode_timed(encoder, timing::OVERLAY, |e, q| {
                    arrows.encode(e, scene.color, scene.depth, q)
                });
        }
        self.renderer.finish_world(encoder, &target)?;
        if scaled {
            let upscale = &self.upscale;
            let region = self.view_region();
            self.renderer
                .encode_timed(encoder, timing::UPSCALE, |e, q| {
                    upscale.encode(e, output, region, q)
                });
        }
        self.frame += 1;
        Ok(())
    }

    /// Ends the frame's recording after the caller's own passes (the window's panel, timed
    /// as `timing::UI`): resolves the frame's timestamp and work queries.
    pub fn finish_frame(&mut self, encoder: &mut wgpu::CommandEncoder) {
        self.renderer.resolve_queries(encoder);
    }

    /// The size the 3D passes draw at: the view region's ([`AppState::view_region`]),
    /// scaled by the frame budget.
    pub fn render_size(&self) -> (u32, u32) {
        let [_, _, w, h] = self.view_region();
        scaled_size((w, h), self.budget.scale())
    }

    /// The window's pixels the 3D view is shown in, `[x, y, width, height]`: right of the
    /// panel, or the whole window where the panel leaves less than [`MIN_VIEW_PX`] (or
    /// there is none). Pixels under the opaque panel are not drawn at all.
    pub fn view_region(&self) -> [u32; 4] {
        view_region(self.size, self.panel_px)
    }

    /// The clip-space crop of the camera's view to [`AppState::view_region`]
    /// (`render::camera::crop_x`): the view keeps the whole window's projection, so what a
    /// pixel shows (and what a click there picks) does not depend on the panel.
    pub fn view_crop(&self) -> glam::Mat4 {
        let left = self.view_region()[0];
        crop_x(2.0 * left as f32 / self.size.0.max(1) as f32 - 1.0)
    }

    /// Reads the last frame's counters and GPU times for the Stats section (blocks until
    /// the frame is done, so the window calls it every few frames).
    pub fn read_stats(&mut self, gpu: &Gpu) {
        self.shown = ShownStats {
            frame_times: self.frame_times.iter().copied().collect(),
            budget: self.budget.status(),
        };
        match self.renderer.stats(gpu) {
            Ok(s) => {
                if let Some(t) = s.tiles {
                    let now = Instant::now();
                    if let Some((then, before)) = self.tile_mark {
                        let secs = now.duration_since(then).as_secs_f32();
                        if secs > 0.0 {
                            self.tile_rate = t.generated_total.saturating_sub(before) as f32 / secs;
                        }
                    }
                    self.tile_mark = Some((now, t.generated_total));
                }
                self.stats = s;
            }
            Err(e) => log::warn!("stats: {e}"),
        }
        match self.renderer.far_gain(gpu) {
            Ok(g) => self.far_gain = g,
            Err(e) => log::warn!("far gain: {e}"),
        }
        match self.renderer.far_calibration(gpu) {
            Ok(c) => self.far_calibration = c,
            Err(e) => log::warn!("far calibration: {e}"),
        }
    }
}
