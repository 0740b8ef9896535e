//! Recording a frame: the passes of [`Renderer::encode_scene`] in frame order (see the
//! module above), into the scene target (`post`) or the multisampled one (`msaa`), and the
//! frame's end ([`Renderer::frame_submitted`]).

use super::camera::CameraView;
use super::deferred::DeferredTargets;
use super::hiz::DepthPyramid;
use super::timing::{self, timed};
use super::{msaa, post, Renderer};
use crate::gpu::Gpu;
use crate::sim::layout::TEST_GRASS_OCCLUSION;

/// What [`Renderer::encode_before_draw`] decided for the draws after it.
pub(crate) struct Prepared {
    /// The cull tested against a depth pyramid.
    occlusion: bool,
    /// The grass takes the deferred path.
    deferred: bool,
    /// The cull's uniforms of this frame.
    cp: crate::sim::layout::CullParams,
}

impl Renderer {
    /// Whether this frame's grass takes the deferred path (`render::deferred`): asked for
    /// (`render.deferred_grass`), filled triangles, pipelines that allow it and buffers the
    /// adapter can hold; makes sure those buffers match a target of `size` at this sample
    /// count.
    fn ensure_deferred(&mut self, gpu: &Gpu, size: (u32, u32), wireframe: bool) -> bool {
        let samples = self.samples;
        let wanted = self.scene.render.deferred_grass
            && !wireframe
            && self.draw.deferred().is_some()
            && DeferredTargets::fits(gpu, size, samples);
        if !wanted {
            // Not held while unused (the panel switched it off, MSAA came back on).
            self.deferred = None;
            return false;
        }
        if self.deferred.as_ref().map(|d| (d.size(), d.samples())) != Some((size, samples)) {
            // Dropped first: the old buffers are not held beside the new ones.
            self.deferred = None;
            self.deferred = DeferredTargets::new(gpu, size, samples).ok();
        }
        self.deferred.is_some()
    }

    /// Makes sure the depth pyramid matches a target of `size` and is bound to the cull
    /// with `depth`, the depth buffer it is built from (its level 0).
    fn ensure_pyramid(&mut self, gpu: &Gpu, size: (u32, u32), depth: &wgpu::TextureView) {
        let samples = self.samples;
        let fits = self
            .pyramid
            .as_ref()
            .is_some_and(|p| p.size() == size && p.samples() == samples);
        if fits && self.pyramid_depth.as_ref() == Some(depth) {
            return;
        }
        if !fits {
            // Dropped first: the old levels are not held beside the new ones.
            self.pyramid = None;
            self.pyramid = Some(DepthPyramid::with_samples(gpu, size.0, size.1, samples));
        }
        if let Some(p) = &self.pyramid {
            self.cull
                .set_pyramid(&gpu.device, &self.buffers, p.level0_view(depth), p.view());
        }
        self.pyramid_depth = Some(depth.clone());
    }

    /// Records a frame up to its resolve (step by `dt`, cull, every draw); the 3D passes
    /// are left in [`Renderer::scene_views`] (the scene target, not the caller's colour:
    /// the resolve tone-maps into that), for the caller to add its own 3D passes (the
    /// window's guide arrows) and then [`Renderer::resolve`]. Frames are recorded through
    /// the embedding API (`embed::GrassRenderer::begin_world`), which checks their inputs
    /// first. `depth` is the caller's single-sample depth
    /// of `size`; with MSAA it is not touched.
    pub fn encode_scene(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        dt: f32,
        camera: &CameraView,
        depth: &wgpu::TextureView,
        size: (u32, u32),
    ) {
        self.sync_msaa(gpu);
        self.sync_taa(gpu, size);
        self.draw
            .sync_grass_spec(&gpu.device, &self.scene, self.lod_morph, self.fold);
        self.post
            .sync_mapper(&gpu.device, self.scene.light.tone_mapping);
        if self.samples > 1 {
            let fits = self.msaa.as_ref().is_some_and(|m| m.size == size);
            if !fits {
                self.msaa = Some(msaa::MsaaTarget::new(
                    gpu,
                    post::HDR_FORMAT,
                    self.samples,
                    size,
                ));
            }
        } else {
            self.msaa = None;
        }
        // The lit passes draw radiance into the scene target; `resolve` tone-maps it into
        // the caller's colour.
        let scene = self.post.view(gpu, size).clone();
        // Held outside `self` while the passes borrow it mutably.
        let target = self.msaa.take();
        let (color, pass_depth) = match &target {
            Some(m) => (&m.color, &m.depth),
            None => (&scene, depth),
        };
        let deferred = self.encode_passes(gpu, encoder, dt, camera, color, pass_depth, size);
        self.frame_depth = Some(pass_depth.clone());
        self.msaa = target;
        // Multisampled, the deferred grass is lit after the hardware resolve (`resolve`):
        // it reads the samples the window's arrows may still draw into.
        self.pending_grass_light = match (&self.deferred, &self.msaa) {
            (Some(d), Some(m)) if deferred && d.samples() > 1 => {
                Some(d.light_groups(&gpu.device, &m.color, &scene))
            }
            _ => None,
        };
        let now = super::taa::FrameViews {
            view_proj: self.view_crop * camera.view_proj_relative(self.aspect(size.0, size.1)),
            jitter: self.jitter,
            eye: camera.eye,
            // The list the frame uploaded, not computed again.
            spheres: if self.taa.as_ref().is_some_and(|t| t.active()) {
                self.uploaded_spheres.clone()
            } else {
                Vec::new()
            },
        };
        if let Some(t) = self.taa.as_mut().filter(|t| t.active()) {
            let vis = self.deferred.as_ref().map(|d| d.vis_view());
            let views = (&scene, depth, vis);
            t.prepare(gpu, &self.post, now, views, &self.buffers.blades, size);
        }
    }

    /// Starts or stops the temporal anti-aliasing with `render.taa` (it anti-aliases
    /// frames of one sample per pixel; the window's budget may switch it off) and sets
    /// this frame's jitter.
    fn sync_taa(&mut self, gpu: &Gpu, size: (u32, u32)) {
        if !(self.scene.render.taa && self.samples == 1 && self.taa_allowed) {
            // Not held while unused: the history and the blades' copy go.
            if let Some(t) = &mut self.taa {
                t.release();
            }
            self.jitter = glam::Mat4::IDENTITY;
            return;
        }
        let blades = &self.buffers.blades;
        let taa = self
            .taa
            .get_or_insert_with(|| super::taa::TaaPass::new(gpu, blades));
        taa.resume(&gpu.device, blades);
        taa.settings = self.taa_settings;
        self.jitter = taa.next_jitter(size);
    }

    /// The passes of [`Renderer::encode_scene`], into the views they draw into; whether the
    /// grass took the deferred path.
    #[allow(clippy::too_many_arguments)]
    fn encode_passes(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        dt: f32,
        camera: &CameraView,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
        size: (u32, u32),
    ) -> bool {
        let Prepared {
            occlusion,
            deferred,
            cp,
        } = self.encode_before_draw(gpu, encoder, dt, camera, Some(depth), size, true);
        let meters = self.meters();
        let wireframe = self.scene.render.wireframe;
        let vis = deferred
            .then(|| self.deferred.as_ref().map(|d| d.vis_view()))
            .flatten();
        timed(meters, encoder, timing::DRAW, |e, q| {
            self.draw.encode(
                e,
                color,
                depth,
                occlusion,
                vis,
                &self.cull.args,
                &self.sphere_draw(),
                wireframe,
                self.billboards.as_ref(),
                self.light.group(),
                q,
            )
        });
        // Two-phase occlusion: the depth now holds the opaque objects and the grass seen
        // last frame; the blades not seen then are drawn only where it does not hide them.
        let late = cp.tests & TEST_GRASS_OCCLUSION != 0;
        if late {
            if let Some(p) = &self.pyramid {
                // The late test reads level 0 alone (`DepthPyramid::encode_base`).
                timed(meters, encoder, timing::LATE_PYRAMID, |e, q| {
                    p.encode_base(&gpu.device, e, depth, q)
                });
            }
            timed(meters, encoder, timing::LATE_CULL, |e, q| {
                self.cull.encode_late(e, &self.buffers.dispatch, q)
            });
            timed(meters, encoder, timing::LATE_DRAW, |e, q| {
                self.draw.encode_late(
                    e,
                    color,
                    depth,
                    vis,
                    &self.cull.args,
                    wireframe,
                    self.light.group(),
                    q,
                )
            });
        }
        // The deferred path lights its grass pixels once the depth is final (with one
        // sample; multisampled, after the resolve).
        if let (Some(d), Some(p), true) = (&self.deferred, self.draw.deferred(), deferred) {
            if d.samples() == 1 {
                let groups = (self.draw.grass_groups(), self.light.group());
                let light = d.light_groups(&gpu.device, depth, color);
                timed(meters, encoder, timing::GRASS_LIGHT, |e, q| {
                    d.encode_light(e, p, groups, &light, (q.row(super::work::GRASS_PIXELS), q))
                });
            }
        }
        // A counted frame measures the pixels its grass covers (not timed: a measurement).
        if let Some(w) = &self.work {
            let q = crate::gpu::queries::PassQueries::new(None, Some((w, super::work::COVERAGE)));
            self.coverage.encode(
                &gpu.device,
                &self.draw,
                encoder,
                depth,
                (&self.cull.args, late),
                q,
            );
        }
        if self.overlay.is_some() && !self.scene.wind.guides.is_empty() {
            // The arrows' on/off state moves with the clock.
            self.refresh_overlay_guides(gpu);
        }
        if let (Some(o), Some(f)) = (&mut self.overlay, &self.fluid) {
            o.move_grid(&gpu.queue, f.origin());
        }
        deferred
    }

    /// Everything of a frame before its colour draws: the simulation step, the tiles, the
    /// cull (with occlusion against `depth` when given), the billboards' cull and the sun's
    /// shadow maps. With `own_draw` the renderer draws the frame itself (its occluders go
    /// into `depth` first, and the deferred path is prepared); without, a host draws the
    /// grass into its own pass and `depth` is the host's, only read.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn encode_before_draw(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        dt: f32,
        camera: &CameraView,
        depth: Option<&wgpu::TextureView>,
        size: (u32, u32),
        own_draw: bool,
    ) -> Prepared {
        if let Some(w) = &mut self.work {
            w.begin_frame();
        }
        // TAA's grass motion: the blades as the last frame drew them, before anything
        // this frame moves or streams them.
        if let Some(t) = self.taa.as_ref().filter(|t| t.active()) {
            let count = self.buffers.blades.size()
                / std::mem::size_of::<crate::sim::layout::Blade>() as u64;
            timed(self.meters(), encoder, timing::TAA, |e, q| {
                t.copy_blades(e, count, q)
            });
        }
        let dt = self.advance(gpu, dt);
        self.frame_count = self.frame_count.wrapping_add(1);
        // The animated objects take this frame's pose before anything draws them.
        if let Some(s) = &self.skinning {
            s.prepare(&gpu.queue, &self.scene.objects, self.time);
            timed(self.meters(), encoder, timing::SKINNING, |e, q| {
                s.encode(e, q)
            });
        }
        // A frozen culling camera sees other depths than the drawn view: no occlusion then.
        // Occlusion needs a depth to build the pyramid from (a host may give none).
        let occlusion = self.scene.culling.occlusion && self.cull_camera.is_none();
        let depth = depth.filter(|_| occlusion);
        let occlusion = depth.is_some();
        let hiz = if let Some(depth) = depth {
            self.ensure_pyramid(gpu, size, depth);
            let p = self.pyramid.as_ref().map_or((0, 0, 0), |p| {
                let (w, h) = p.size();
                (w, h, p.levels())
            });
            [p.0, p.1, p.2, 1]
        } else {
            [0; 4]
        };
        let cull_camera = self.cull_camera.unwrap_or(*camera);
        // The tiles follow the culling camera: a frozen one keeps its field.
        self.stream_tiles(gpu, encoder, cull_camera.eye);
        if let Some(c) = &self.carried {
            c.encode(encoder);
        }
        let cp = self.cull_uniforms(&cull_camera, size, hiz);
        self.cull.prepare(&gpu.queue, &cp);
        self.last_cull = cp;
        let frame = self.frame_uniforms(camera, size.0, size.1);
        self.draw.prepare(
            &gpu.queue,
            &frame,
            camera,
            (self.aspect(size.0, size.1), self.jitter * self.view_crop),
            self.scene.culling.max_distance,
        );
        self.light.prepare(
            gpu,
            &self.scene,
            camera,
            self.aspect(size.0, size.1),
            &frame,
            self.grass_shadows.then_some(super::light::GrassCasters {
                mesh: self.lod.caster,
                lod: cp.lod,
            }),
        );
        let ground = self.draw.ground_shadow_key();
        self.light
            .plan_ground(&gpu.device, ground.filter(|_| self.cache_ground_shadows));
        self.sync_billboards(gpu);
        let wireframe = self.scene.render.wireframe;
        let deferred = own_draw && self.ensure_deferred(gpu, size, wireframe);
        self.last_billboards = self.billboards.as_ref().map(|b| {
            let p = b.prepare(
                &gpu.queue,
                camera,
                &self.scene.culling,
                self.sphere_count,
                self.scene.terrain.size,
                self.billboard_share,
            );
            (p, self.view_proj(camera, size))
        });
        let meters = self.meters();
        if let Some(depth) = depth {
            if own_draw {
                timed(meters, encoder, timing::OCCLUDERS, |e, q| {
                    self.draw.encode_occluders(e, depth, &self.sphere_draw(), q)
                });
            }
            if let Some(p) = &self.pyramid {
                timed(meters, encoder, timing::PYRAMID, |e, q| {
                    p.encode(&gpu.device, e, depth, q)
                });
            }
        }
        timed(meters, encoder, timing::PATCHES, |e, q| {
            self.cull.encode_patches(e, q)
        });
        self.encode_update(gpu, encoder, dt, cull_camera.eye);
        let meters = self.meters();
        timed(meters, encoder, timing::CULL, |e, q| {
            self.cull.encode_blades(e, &self.buffers.dispatch, q)
        });
        // The far levels read the gusts' bend the cull measured at the blades' edge.
        encoder.copy_buffer_to_buffer(
            &self.cull.args,
            crate::sim::layout::WAVE_OFFSET,
            self.draw.waves_buffer(),
            0,
            8,
        );
        if let Some(b) = &self.billboards {
            timed(meters, encoder, timing::BILLBOARDS, |e, q| {
                b.encode_cull(e, self.light.group(), q)
            });
        }
        // The sun's shadow maps, after the cull (the grass casts with its visible lists)
        // and before every pass that receives them.
        if self.light.cascades() > 0 {
            let spheres = self.sphere_draw();
            let light = &self.light;
            let draw = &self.draw;
            let args = light.grass_args();
            timed(meters, encoder, timing::SHADOWS, |e, q| {
                light.encode(e, draw.frame_buffer(), &self.cull.args, q, |pass, grass, casters| {
                    draw.draw_casters(pass, &spheres, grass.map(|at| (args, at)), casters)
                })
            });
        }
        Prepared {
            occlusion,
            deferred,
            cp,
        }
    }

    /// Tells the renderer that the frame's commands were submitted as `index` (the window
    /// and `commands::world_frame` call it after their submit): it waits for the
    /// frame [`crate::gpu::MAX_FRAMES_IN_FLIGHT`] submits back, so the CPU never runs
    /// further ahead than that, and hands the frame to the GPU timer.
    pub fn frame_submitted(&mut self, gpu: &Gpu, index: wgpu::SubmissionIndex) {
        self.pacer.submitted(gpu, index);
        if let Some(t) = &mut self.timer {
            t.end_frame(gpu);
        }
        if let Some(w) = &mut self.work {
            w.end_frame();
        }
    }
}
