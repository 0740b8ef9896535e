//! The renderer's far levels: the streamed field's tiles (the residency moving with the
//! camera and the generation of the entering tiles) and the billboards of the middle
//! distance (built, rebound and counted). Split from `mod.rs`, whose frame order calls them.

use glam::Vec3;

use super::tiles::TileStreamer;
use super::timing::{self, timed, Meters};
use super::{billboard, Renderer, TileStats};
use crate::error::Result;
use crate::gpu::Gpu;

impl Renderer {
    /// Moves a streamed field's tiles with the camera at `eye` and records the generation
    /// of the entering ones (before the patch pass reads their boxes).
    pub(super) fn stream_tiles(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        eye: Vec3,
    ) {
        let Some(tiles) = &mut self.tiles else {
            return;
        };
        let meters = Meters {
            timer: self.timer.as_ref(),
            work: self.work.as_ref(),
        };
        let p = &self.scene.physics;
        tiles.write_trail_header(
            &gpu.queue,
            self.time,
            p.collision_decay,
            p.max_collision_strength,
        );
        let jobs = tiles.plan(eye.x, eye.z);
        if jobs.is_empty() {
            return;
        }
        timed(meters, encoder, timing::TILES, |e, q| {
            tiles.encode(&gpu.queue, e, &jobs, q)
        });
    }

    /// The streamed field's tile counts, when the scene streams.
    pub fn tile_stats(&self) -> Option<TileStats> {
        self.tiles.as_ref().map(|t| {
            let r = &t.residency;
            TileStats {
                resident: r.resident_count(),
                slots: r.layout().slots,
                generated_last: t.last_generated,
                generated_total: r.generated(),
                tile_size: r.layout().tile_size(),
                blades_per_tile: r.layout().blades_per_tile(),
            }
        })
    }

    /// The streamed field's residency and generation uniforms (tests compare the pool with
    /// the CPU twin).
    pub fn tiles(&self) -> Option<&TileStreamer> {
        self.tiles.as_ref()
    }

    /// The wind grid the update reads (the fluid's velocity, or the dummy).
    pub(super) fn wind_grid(&self) -> &wgpu::Buffer {
        self.fluid
            .as_ref()
            .map(|f| f.velocity())
            .unwrap_or(&self._dummy_grid)
    }

    /// Builds, rebuilds or drops the billboard pass to match `render.billboard_distance`
    /// (the panel may change it between frames).
    pub(super) fn sync_billboards(&mut self, gpu: &Gpu) {
        let layout = billboard::BillboardLayout::from_scene(&self.scene.render, &self.scene.field);
        if self.billboards.as_ref().map(|b| b.layout) == layout {
            return;
        }
        self.billboards = layout.map(|layout| {
            let (terrain_params, terrain_grid) = self.draw.terrain_buffers();
            billboard::BillboardPass::new(
                gpu,
                layout,
                &self.scene.field,
                self.density.as_ref(),
                &billboard::Inputs {
                    frame: self.draw.frame_buffer(),
                    terrain_params,
                    terrain_grid,
                    spheres: &self.buffers.spheres,
                    sim_params: self.update.params_buffer(),
                    wind_grid: self.wind_grid(),
                    waves: self.draw.waves_buffer(),
                    trails: &self.buffers.trails,
                },
                super::post::HDR_FORMAT,
                self.samples,
            )
        });
    }

    /// Rebinds the billboards to the current update and wind buffers.
    pub(super) fn rebind_billboards(&mut self, gpu: &Gpu) {
        if let Some(mut b) = self.billboards.take() {
            let (terrain_params, terrain_grid) = self.draw.terrain_buffers();
            b.rebind(
                &gpu.device,
                &billboard::Inputs {
                    frame: self.draw.frame_buffer(),
                    terrain_params,
                    terrain_grid,
                    spheres: &self.buffers.spheres,
                    sim_params: self.update.params_buffer(),
                    wind_grid: self.wind_grid(),
                    waves: self.draw.waves_buffer(),
                    trails: &self.buffers.trails,
                },
            );
            self.billboards = Some(b);
        }
    }

    /// Billboards drawn in the last frame, as the GPU cull counted them (blocks until the
    /// frame is done). `billboard::count_drawn` is its CPU twin.
    pub fn billboards_drawn(&self, gpu: &Gpu) -> Result<u32> {
        match &self.billboards {
            Some(b) if self.last_billboards.is_some() => b.read_drawn(gpu),
            _ => Ok(0),
        }
    }

    /// The billboards' uniforms and the view-projection of the last frame (what the cull
    /// read), when the scene has billboards.
    pub fn billboard_frame(&self) -> Option<(billboard::BillboardParams, glam::Mat4)> {
        self.last_billboards
    }

    /// The billboard pass, when the scene has billboards.
    pub fn billboards(&self) -> Option<&billboard::BillboardPass> {
        self.billboards.as_ref()
    }
}
