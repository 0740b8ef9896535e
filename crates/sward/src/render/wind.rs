//! The renderer's wind-side controls: the overlay of the air velocity and the guides
//! (`--wind-overlay`, the panel), and the rebuild of the wind solver when the scene's wind
//! changes in ways its settings cannot take live.

use super::grass_bind::ModelBuffers;
use super::{overlay, Renderer};
use crate::error::Result;
use crate::gpu::Gpu;
use crate::sim::agc;
use crate::sim::fluid::{FluidConfig, FluidSolver};
use crate::sim::update::UpdatePass;

impl Renderer {
    /// Turns the wind overlay on (velocity colour + glyphs + AGC arrows) for later frames.
    pub fn enable_overlay(&mut self, gpu: &Gpu, format: wgpu::TextureFormat) {
        let (velocity, resolution, origin, cell) = match &self.fluid {
            Some(f) => {
                let c = f.config();
                (f.velocity(), c.resolution, c.origin, c.cell_size)
            }
            None => (&self._dummy_grid, 1, [0.0, 0.0], self.scene.terrain.size),
        };
        let mut o = overlay::OverlayPass::new(
            gpu,
            format,
            // Drawn after tone mapping, into the single-sample output.
            1,
            self.draw.frame_buffer(),
            velocity,
            resolution,
            origin,
            cell,
            &self.terrain,
        );
        o.prepare(
            &gpu.queue,
            &agc::arrows_at(&self.scene.wind.guides, f32::INFINITY),
        );
        self.overlay = Some(o);
    }

    /// Rebuilds the wind solver for the scene's current wind settings (source switched
    /// between analytic and fluid, or a new grid resolution). The blades keep their state;
    /// the air starts at rest. On error the old solver stays.
    pub fn rebuild_wind(&mut self, gpu: &Gpu) -> Result<()> {
        let fluid = if self.scene.wind.source != crate::scene::WindSource::Analytic {
            let config = FluidConfig::from_scene(&self.scene.wind.fluid, self.scene.terrain.size);
            Some(FluidSolver::new(gpu, &config)?)
        } else {
            None
        };
        self.fluid = fluid;
        self.rebind_update(gpu);
        if self.overlay.is_some() {
            self.enable_overlay(gpu, self.format);
        }
        self.rebind_billboards(gpu);
        Ok(())
    }

    /// Makes the buffers of the scene's blade model (`physics.model`) exist: the Verlet
    /// states, allocated the first time a Verlet blade is asked for (from the panel), and
    /// the passes that bind them. An adapter that cannot hold them says so and the blades
    /// keep Jahrmann's update.
    pub fn apply_model(&mut self, gpu: &Gpu) -> Result<()> {
        if self.scene.physics.model == crate::scene::BladeModel::Verlet
            && self.buffers.ensure_verlet(gpu)?
        {
            self.rebind_update(gpu);
        }
        Ok(())
    }

    /// Makes the grass-to-grass propagation's buffers and passes match the scene's
    /// `physics.propagation` (built the first time it is turned on, rebuilt when its grid
    /// changes size). An adapter that cannot hold the grid says so; nothing changes then.
    pub fn apply_propagation(&mut self, gpu: &Gpu) -> Result<()> {
        let Some(p) = self.scene.physics.propagation.clone() else {
            return Ok(());
        };
        let n = crate::sim::propagation::cells_per_side(&p);
        if self.propagation.as_ref().is_some_and(|q| q.n == n) {
            return Ok(());
        }
        let reallocated = self.buffers.ensure_splat(gpu, n)?;
        if reallocated {
            self.rebind_update(gpu);
        }
        self.propagation = Some(crate::sim::propagation_pass::PropagationPass::new(
            gpu,
            &self.buffers,
            self.update.params_buffer(),
            &p,
        )?);
        Ok(())
    }

    /// Rebuilds the update pass and the grass draw's bindings over the current wind grid
    /// and Verlet states.
    fn rebind_update(&mut self, gpu: &Gpu) {
        let grid = self
            .fluid
            .as_ref()
            .map(|f| f.velocity())
            .unwrap_or(&self._dummy_grid);
        self.update = UpdatePass::new(gpu, &self.buffers, grid);
        // The propagation binds the update's uniforms: rebuilt over the new ones.
        if let (Some(prop), Some(p)) = (&self.propagation, &self.scene.physics.propagation) {
            if let Ok(pass) = crate::sim::propagation_pass::PropagationPass::new(
                gpu,
                &self.buffers,
                self.update.params_buffer(),
                p,
            ) {
                if pass.n == prop.n {
                    self.propagation = Some(pass);
                }
            }
        }
        self.draw.bind_model(
            &gpu.device,
            ModelBuffers {
                sim_params: self.update.params_buffer(),
                wind_grid: grid,
                verlet: &self.buffers.verlet,
            },
        );
    }

    /// The blade model the update steps: the scene's, except Verlet before its states
    /// exist ([`Renderer::apply_model`]), which steps as Jahrmann.
    pub fn stepped_model(&self) -> crate::scene::BladeModel {
        match self.scene.physics.model {
            crate::scene::BladeModel::Verlet if !self.buffers.has_verlet => {
                crate::scene::BladeModel::Jahrmann
            }
            m => m,
        }
    }

    /// Turns the wind overlay off.
    pub fn disable_overlay(&mut self) {
        self.overlay = None;
    }

    /// Whether the wind overlay is on.
    pub fn overlay_enabled(&self) -> bool {
        self.overlay.is_some()
    }

    /// Redraws the overlay's guide arrows from the scene (after the guides were edited).
    pub fn refresh_overlay_guides(&mut self, gpu: &Gpu) {
        if let Some(o) = &mut self.overlay {
            o.prepare(
                &gpu.queue,
                &agc::overlay_arrows(&self.scene.wind.guides, self.time),
            );
        }
    }
}
