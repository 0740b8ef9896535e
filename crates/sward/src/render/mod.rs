//! Rendering: one frame on one command encoder, into any colour view (an off-screen texture
//! or a window surface), with per-pass GPU times:
//! occluder depth → depth pyramid → patch culling (+ which patches the physics steps) →
//! wind → blade update (indirect) → blade culling into levels of detail (indirect) → draw;
//! with grass occlusion then depth pyramid again → late blade culling → late draw.

pub mod arrows;
pub mod billboard;
pub mod camera;
mod carried;
pub mod clipmap;
mod coverage;
pub mod cull;
pub mod deferred;
pub mod draw;
pub mod far_canopy;
pub mod far_gain;
pub mod far_gain_pass;
pub mod far_sectors;
pub mod far_light;
pub mod far_texture;
mod frame;
pub mod grass_bind;
pub mod grass_spec;
pub mod hiz;
pub mod host;
mod levels;
pub mod light;
pub mod lod_chord;
pub mod mesh;
pub mod msaa;
pub mod objects;
pub mod overlay;
pub mod pipelines;
pub mod post;
pub mod ray;
pub mod skinning;
pub mod taa;
pub mod target;
pub mod terrain;
pub mod thinning;
pub mod tiles;
pub mod timing;
pub mod upscale;
mod wind;
pub mod work;

use glam::Vec3;

use crate::error::Result;
use crate::field::tiles::TileLayout;
use crate::field::{GeneratedField, HeightField};
use crate::gpu::queries::{PassQueries, WorkCounter, WorkFrame};
use crate::gpu::Gpu;
use crate::scene::Scene;
use crate::sim::agc;
use crate::sim::colliders::spheres_at;
use crate::sim::fluid::{FluidConfig, FluidSolver};
use crate::sim::layout::{CullCounters, CullParams, FrameUniforms, TEST_GRASS_OCCLUSION};
use crate::sim::params::{cull_params, sim_params, throttled_dt, CullInputs};
use crate::sim::update::{BladeBuffers, UpdatePass};
use crate::sim::wind_layout::{ObstacleGpu, MAX_OBSTACLES};
use camera::CameraView;
use cull::CullPass;
use draw::DrawPass;
use grass_bind::ModelBuffers;
use hiz::DepthPyramid;
use mesh::LodMeshes;
use tiles::TileStreamer;
use timing::{timed, GpuTimer, Meters};

/// What one frame did, read back from the GPU.
#[derive(Clone, Debug, Default)]
pub struct FrameStats {
    /// The cull's indirect draws and counters (visible patches and blades per level).
    pub counters: CullCounters,
    /// GPU milliseconds of each pass of `timing::PASSES`, when timestamps exist.
    pub pass_ms: Option<[f64; timing::PASSES.len()]>,
    /// GPU milliseconds of each wind-solver pass, when the fluid runs and timestamps exist.
    pub wind_ms: Option<Vec<(&'static str, f64)>>,
    /// Blades the update reset to their rest pose since the start because their new state
    /// was non-finite or absurd (`BladeBuffers::read_resets`).
    pub blades_reset_nonfinite: u32,
    /// The streamed field's tiles, when the scene streams (`field.tile_size > 0`).
    pub tiles: Option<TileStats>,
    /// Billboards drawn in the frame (`Renderer::billboards_drawn`).
    pub billboards_drawn: u32,
}

/// What the tile streaming did: tiles resident now, generated in the last frame and since
/// the start.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TileStats {
    /// Tiles resident now.
    pub resident: usize,
    /// Tile slots in the pool: the most tiles that can be resident at once.
    pub slots: u32,
    /// Tiles generated in the last frame.
    pub generated_last: usize,
    /// Tiles generated since the start.
    pub generated_total: u64,
    /// Side of a tile in metres and blades per tile.
    pub tile_size: f32,
    /// Blades generated into each tile.
    pub blades_per_tile: u32,
}

/// The distance over which the fog turns the ground into sky (`1 − e^(−d/fog)`): four
/// terrain sides, but at most a third of the far plane, so that what the far plane cuts is
/// 95 % sky and a prairie of kilometres fades into the horizon rather than ending at an
/// edge.
pub fn fog_distance(terrain_size: f32, far: f32) -> f32 {
    (terrain_size * 4.0).min(far / 3.0).max(1.0)
}

/// A sphere moved by the caller rather than by the scene (the window's thrown balls): it
/// collides with the grass and, as an obstacle, pushes the wind.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DynamicSphere {
    /// World position of the centre (m).
    pub center: Vec3,
    /// Radius (m).
    pub radius: f32,
    /// Velocity (m/s), which the wind solver sees as the obstacle's motion.
    pub velocity: Vec3,
}

/// Everything on the GPU for one scene, and the clock of its simulation.
pub struct Renderer {
    /// The blades' GPU buffers (blades, states, patches, visible lists, spheres).
    pub buffers: BladeBuffers,
    update: UpdatePass,
    /// The patch and blade cull passes and the indirect draws they write.
    pub cull: CullPass,
    draw: DrawPass,
    /// The wind solver, when the scene's wind source includes the fluid.
    pub fluid: Option<FluidSolver>,
    overlay: Option<overlay::OverlayPass>,
    /// Bound in place of the velocity grid when the fluid is off.
    _dummy_grid: wgpu::Buffer,
    timer: Option<GpuTimer>,
    /// Counts every pass's shader invocations while asked to ([`Renderer::count_work`]).
    work: Option<WorkCounter>,
    /// The counted frames' measurement of the pixels the grass covers.
    coverage: coverage::Coverage,
    /// Bounds the frames submitted and not yet finished (see [`crate::gpu::FramePacer`]).
    pacer: crate::gpu::FramePacer,
    /// The scene being rendered.
    pub scene: Scene,
    /// The scene's terrain height field (CPU side).
    pub terrain: HeightField,
    /// Simulated seconds since the start.
    pub time: f32,
    sphere_count: u32,
    lod: LodMeshes,
    /// Whether the levels of detail draw with one multi-draw (first-instance support).
    multi_draw: bool,
    /// The occlusion test's depth pyramid, sized to the last target.
    pyramid: Option<DepthPyramid>,
    /// The depth buffer the cull reads as the pyramid's level 0 (bound with the pyramid;
    /// a resized target brings a new one).
    pyramid_depth: Option<wgpu::TextureView>,
    /// The deferred grass shading's visibility buffer and pixel list, sized to the last
    /// target that took the path.
    deferred: Option<deferred::DeferredTargets>,
    /// The multisampled deferred light's bind groups for this frame, recorded by
    /// [`Renderer::resolve`] after the hardware resolve (taken there: one frame's only).
    pending_grass_light: Option<[wgpu::BindGroup; 2]>,
    /// The far levels' light gain, measured on the blades at the edge of their reach after
    /// each frame's grass is lit (`far_gain`).
    far_gain: far_gain_pass::FarGainPass,
    /// The depth the frame's 3D passes drew into (the multisampled one with MSAA), for the
    /// far gain's measurement in [`Renderer::resolve`]; `None` outside a frame.
    frame_depth: Option<wgpu::TextureView>,
    /// Frames drawn, for the physics throttle's round robin.
    frame_count: u32,
    /// The cull uniforms of the last frame drawn (tests replay them on the CPU twin).
    last_cull: CullParams,
    /// Spheres added to the scene's colliders each step (see [`DynamicSphere`]).
    pub dynamic_spheres: Vec<DynamicSphere>,
    /// The sphere packing of each mesh object (`None`: no collider), in its mesh's units;
    /// the spheres move with their object.
    packings: Vec<Option<crate::mesh::pack::Packing>>,
    /// This frame's hierarchy of the colliders (`Scene::collision_hierarchy`; else empty).
    bvh: Vec<crate::sim::bvh::BvhNode>,
    /// The grass of moving objects, carried with them (`None` when none moves).
    carried: Option<carried::CarriedGrass>,
    /// Grass-to-grass propagation (`physics.propagation`), once turned on.
    propagation: Option<crate::sim::propagation_pass::PropagationPass>,
    /// When set, culling runs from this camera instead of the drawing one ("freeze the
    /// culling camera" in the panel: fly out and look at what the frozen view keeps).
    pub cull_camera: Option<CameraView>,
    /// The aspect ratio of the image as shown, when the 3D passes draw at a scaled size
    /// (the window's frame budget): the projection keeps the window's shape, so a lower
    /// render scale stretches no blade and culls the same ones. `None`: the target's.
    pub display_aspect: Option<f32>,
    /// A crop of the camera's view in clip space, after its projection (`camera::crop_x`):
    /// the window draws only the part of its view beside its panel. Identity: all of it.
    pub view_crop: glam::Mat4,
    /// Colour format of the targets the pipelines were built for.
    format: wgpu::TextureFormat,
    /// The streamed field's residency and generation pass (`field.tile_size > 0`).
    tiles: Option<TileStreamer>,
    /// At most this many samples per pixel, whatever `render.msaa` says (the frame budget).
    sample_cap: Option<u32>,
    /// The billboards in the middle distance (`render.billboard_distance > 0`), and the
    /// uniforms and view of the last frame (the stats count the cards drawn with them).
    billboards: Option<billboard::BillboardPass>,
    last_billboards: Option<(billboard::BillboardParams, glam::Mat4)>,
    /// The share of `render.billboard_distance` drawn (the window's frame budget; 1: all).
    pub billboard_share: f32,
    /// Whether the blades cast sun shadows (within `light.shadows.grass_radius`): the
    /// window's frame budget switches them off without touching the scene.
    pub grass_shadows: bool,
    /// Whether the ground's shadow depth is kept between frames (`light::ground_cache`;
    /// on by default; the tests compare it with drawing the ground every frame).
    pub cache_ground_shadows: bool,
    /// Factor on `culling.lod_near_px` and `lod_far_px` (1: the scene's): the window's
    /// frame budget draws the blades with their coarser meshes without touching the scene.
    pub lod_coarsen: f32,
    /// Whether the blades morph between levels of detail (`culling.lod_morph`; the
    /// window's frame budget switches it off without touching the scene, and the grass
    /// pipelines are then built without the morph: `GrassSpec::morph`).
    pub lod_morph: bool,
    /// Whether the blades fold along their middle axis where the scene has the 3D
    /// displacement on (`render.displacement`, Eq. 23; the window's frame budget switches
    /// it off without touching the scene: the blades are then flat, and the finest level
    /// is drawn with two columns, `GrassSpec::fold`).
    pub fold: bool,
    /// The density map, kept for the billboards' CPU count.
    density: Option<crate::field::DensityMap>,
    /// `render.msaa` as last applied, and the sample count the adapter gave for it.
    requested_samples: u32,
    samples: u32,
    /// The multisampled colour + depth of the 3D passes (when `samples` > 1), sized to the
    /// last frame's target.
    msaa: Option<msaa::MsaaTarget>,
    /// The half-float scene target and the pass that tone-maps it into the output.
    post: post::ToneMap,
    /// The sun, the sky and the sun's shadow maps (`light`).
    light: light::LightPass,
    /// Temporal anti-aliasing and its history, while `render.taa` is on.
    taa: Option<taa::TaaPass>,
    /// The animated mesh objects' skinning (`objects[].animation`), when any plays.
    skinning: Option<skinning::SkinningPass>,
    /// The colliders of the last upload (`frame_spheres` at this frame's time): TAA moves
    /// the pixels on a moving ball with its centre.
    uploaded_spheres: Vec<[f32; 4]>,
    /// Whether `render.taa` may run: the window's frame budget switches anti-aliasing off
    /// (MSAA by its sample cap, TAA by this) without touching the scene.
    pub taa_allowed: bool,
    /// What the TAA pass does while `render.taa` is on (the shipped pass by default;
    /// measurements switch parts of it off).
    pub taa_settings: taa::TaaSettings,
    /// This frame's sub-pixel jitter in clip space (TAA; identity without it), applied
    /// after the projection and the crop.
    jitter: glam::Mat4,
}

impl Renderer {
    /// A renderer over a session's scene, terrain and field (which the session keeps).
    pub fn from_session(
        gpu: &Gpu,
        session: &crate::session::Session,
        format: wgpu::TextureFormat,
    ) -> Result<Self> {
        let mut r = Self::new(
            gpu,
            session.scene.clone(),
            session.terrain.clone(),
            &session.field,
            format,
        )?;
        r.set_objects(gpu, &session.meshes, &session.packings);
        r.set_skins(gpu, &session.skins);
        Ok(r)
    }

    /// Uploads the meshes of the scene's `objects` (read and checked by the session, in
    /// the same order) for the draw and the occluder pass, and takes their sphere
    /// packings as colliders.
    pub fn set_objects(
        &mut self,
        gpu: &Gpu,
        meshes: &[crate::mesh::Mesh],
        packings: &[Option<crate::mesh::pack::Packing>],
    ) {
        self.packings = packings.to_vec();
        self.draw.objects = (!self.scene.objects.is_empty()).then(|| {
            objects::ObjectsPass::new(
                &gpu.device,
                &self.scene.objects,
                meshes,
                self.draw.frame_buffer(),
                post::HDR_FORMAT,
                self.draw.samples(),
            )
        });
    }

    /// Builds the skinning of the objects that play an animation (`skins`, the session's,
    /// in the order of the scene's objects); call after [`Renderer::set_objects`].
    pub fn set_skins(
        &mut self,
        gpu: &Gpu,
        skins: &[Option<(crate::mesh::skin::SkinnedMesh, usize)>],
    ) {
        self.skinning = self
            .draw
            .objects
            .as_ref()
            .and_then(|o| skinning::SkinningPass::new(&gpu.device, skins, o));
    }

    /// Object `i`'s vertices as the last frame posed them (position, normal; blocks):
    /// the skinning pass's output, for its twin test.
    pub fn read_object_vertices(&self, gpu: &Gpu, i: usize) -> Result<Vec<[f32; 6]>> {
        let Some(buffer) = self.draw.objects.as_ref().and_then(|o| o.vertex_buffer(i)) else {
            return Ok(Vec::new());
        };
        let bytes = crate::gpu::read_buffer(gpu, buffer, buffer.size())?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }

    /// Uploads the field and builds every pass for colour targets of `format`.
    pub fn new(
        gpu: &Gpu,
        scene: Scene,
        terrain: HeightField,
        field: &GeneratedField,
        format: wgpu::TextureFormat,
    ) -> Result<Self> {
        // Limits were checked before; a device that still runs out of memory reports it here
        // as an error instead of wgpu's default panic.
        let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let fluid = if scene.wind.source != crate::scene::WindSource::Analytic {
            let config = FluidConfig::from_scene(&scene.wind.fluid, scene.terrain.size);
            // Found after loading: at the scene line of the grid's resolution.
            let solver = FluidSolver::new(gpu, &config)
                .map_err(|e| scene.error_at("wind.fluid.resolution", e.to_string()))?;
            Some(solver)
        } else {
            None
        };
        let dummy_grid = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.wind.dummy_grid"),
            size: 8,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let grid = fluid.as_ref().map(|f| f.velocity()).unwrap_or(&dummy_grid);
        let layout = TileLayout::from_scene(&scene.field, &scene.terrain, &scene.culling);
        let mut buffers = match &layout {
            Some(l) => BladeBuffers::new_pool(gpu, l, field)?,
            None => BladeBuffers::new(gpu, field)?,
        };
        if scene.physics.model == crate::scene::BladeModel::Verlet {
            buffers.ensure_verlet(gpu)?;
        }
        // The trail map of a streamed field: a page per slot of the pool plus the cache.
        let trail_layout = match (&layout, &scene.physics.trails) {
            (Some(l), Some(t)) => {
                let tile_q = l.tile_q().clamp(1, i32::MAX as i64) as i32;
                let pages = l.slots.saturating_add(t.cache_tiles);
                Some(crate::field::trails::TrailLayout::new(
                    t.resolution,
                    pages,
                    tile_q,
                ))
            }
            _ => None,
        };
        if let Some(t) = &trail_layout {
            buffers
                .ensure_trails(gpu, t)
                .map_err(|e| scene.error_at("physics.trails.cache_tiles", e.to_string()))?;
        }
        // A streamed field's object grass sits after the tile pool.
        let carried = match &layout {
            Some(l) => field.carried.shifted(
                l.pool_blades() as usize,
                (l.slots * l.patches_per_tile()) as usize,
            ),
            None => field.carried.clone(),
        };
        let density = crate::field::DensityMap::from_scene(&scene.terrain)?;
        let tiles = layout.map(|l| {
            TileStreamer::new(
                gpu,
                &buffers,
                &l,
                &scene.field,
                &terrain,
                density.as_ref(),
                trail_layout,
            )
        });
        let update = UpdatePass::new(gpu, &buffers, grid);
        let cull = CullPass::new(gpu, &buffers);
        let carried = carried::CarriedGrass::new(gpu, &buffers, &carried)?;
        let lod = mesh::lod_meshes(scene.field.segments);
        let multi_draw = gpu
            .device
            .features()
            .contains(wgpu::Features::INDIRECT_FIRST_INSTANCE);
        let requested_samples = scene.render.msaa;
        let samples = msaa::effective_samples(gpu, post::HDR_FORMAT, requested_samples);
        let draw = DrawPass::new(
            gpu,
            &buffers,
            &terrain,
            density.as_ref(),
            &lod,
            &cull.params,
            &cull.args,
            multi_draw,
            post::HDR_FORMAT,
            samples,
            ModelBuffers {
                sim_params: update.params_buffer(),
                wind_grid: grid,
                verlet: &buffers.verlet,
            },
            &scene,
        );
        if let Some(e) = crate::gpu::block_on(scope.pop()) {
            return Err(crate::Error::Gpu(format!(
                "{} ran out of memory for a field of {} blades: {e}",
                gpu.info.name, buffers.count
            )));
        }
        let light = light::LightPass::new(gpu, &scene)?;
        let post = post::ToneMap::new(gpu, format, &light::layout(&gpu.device));
        let mut draw = draw;
        draw.set_grass_everywhere(tiles.is_some() && terrain.unbounded);
        draw.set_far_albedo(clipmap::far_albedo(&scene.field));
        let mut r = Self {
            buffers,
            update,
            cull,
            draw,
            fluid,
            overlay: None,
            _dummy_grid: dummy_grid,
            timer: GpuTimer::new(gpu),
            work: None,
            coverage: coverage::Coverage::default(),
            pacer: crate::gpu::FramePacer::default(),
            scene,
            terrain,
            time: 0.0,
            sphere_count: 0,
            lod,
            multi_draw,
            pyramid: None,
            pyramid_depth: None,
            deferred: None,
            pending_grass_light: None,
            far_gain: far_gain_pass::FarGainPass::new(gpu),
            frame_depth: None,
            frame_count: 0,
            last_cull: CullParams::default(),
            dynamic_spheres: Vec::new(),
            packings: Vec::new(),
            bvh: Vec::new(),
            carried,
            propagation: None,
            display_aspect: None,
            view_crop: glam::Mat4::IDENTITY,
            cull_camera: None,
            format,
            tiles,
            sample_cap: None,
            billboards: None,
            last_billboards: None,
            billboard_share: 1.0,
            grass_shadows: true,
            cache_ground_shadows: true,
            lod_coarsen: 1.0,
            lod_morph: true,
            fold: true,
            density,
            requested_samples,
            samples,
            msaa: None,
            light,
            post,
            taa: None,
            skinning: None,
            taa_settings: taa::TaaSettings::default(),
            taa_allowed: true,
            uploaded_spheres: Vec::new(),
            jitter: glam::Mat4::IDENTITY,
        };
        r.upload_colliders(gpu);
        r.sync_billboards(gpu);
        r.apply_propagation(gpu)?;
        let eye = r
            .scene_camera(&CameraView::from_scene(&r.scene.camera), 0.0)
            .eye;
        if let Some(t) = &mut r.tiles {
            t.fill(gpu, eye.x, eye.z)?;
        }
        Ok(r)
    }

    /// The spheres of the current step: the scene's colliders at this time, the mesh
    /// objects' packed spheres, then the dynamic ones (what `upload_colliders` sends).
    pub fn frame_spheres(&self) -> Vec<[f32; 4]> {
        let mut spheres = spheres_at(&self.scene.colliders, &self.terrain, self.time);
        spheres.extend(crate::sim::colliders::object_spheres_at(
            &self.scene.objects,
            &self.packings,
            &self.terrain,
            self.time,
        ));
        spheres.extend(
            self.dynamic_spheres
                .iter()
                .map(|s| [s.center.x, s.center.y, s.center.z, s.radius]),
        );
        spheres
    }

    fn upload_colliders(&mut self, gpu: &Gpu) {
        let spheres = self.frame_spheres();
        self.sphere_count = self.buffers.upload_spheres(&gpu.queue, &spheres);
        // Built whenever the blades collide: the flat broad phase skips with it the patches
        // that no sphere is near.
        self.bvh = if self.scene.physics.collisions {
            crate::sim::bvh::build(&spheres[..self.sphere_count as usize])
        } else {
            Vec::new()
        };
        self.buffers.upload_bvh(&gpu.queue, &self.bvh);
        self.uploaded_spheres = spheres;
    }

    /// The spheres drawn: all but the objects' packed ones (which follow the colliders
    /// in `frame_spheres`).
    fn sphere_draw(&self) -> draw::SphereDraw {
        let first = self.scene.colliders.len() as u32;
        let packed: usize = self
            .packings
            .iter()
            .flatten()
            .map(|p| p.spheres.len())
            .sum();
        draw::SphereDraw {
            count: self.sphere_count,
            hidden: first..first + packed as u32,
        }
    }

    /// Advances the clock by `dt` (clamped to the scene's Δt limit) and moves the colliders;
    /// returns the clamped Δt.
    fn advance(&mut self, gpu: &Gpu, dt: f32) -> f32 {
        let dt = dt.clamp(0.0, self.scene.physics.max_dt);
        self.time += dt;
        self.upload_colliders(gpu);
        self.place_objects(gpu);
        if let Some(c) = &mut self.carried {
            c.advance(gpu, &self.buffers, &self.scene, &self.terrain, self.time);
        }
        dt
    }

    /// The camera to draw the next frame (a step of `dt` seconds) from, for a scene camera
    /// `base`: from behind the object it follows (`camera.follow`) where that object will
    /// be after the step, else `base` itself.
    pub fn scene_camera(&self, base: &CameraView, dt: f32) -> CameraView {
        match &self.scene.camera.follow {
            Some(f) => {
                let time = self.time + dt.clamp(0.0, self.scene.physics.max_dt);
                camera::follow_view(base, f, &self.scene.objects, &self.terrain, time)
            }
            None => *base,
        }
    }

    /// The length in seconds of the animation the scene's object `index` plays (`None`: it
    /// has no animation).
    pub fn animation_duration(&self, index: usize) -> Option<f32> {
        self.skinning.as_ref()?.duration(index)
    }

    /// Puts the scene's object `index` where a program steering it wants it from the next
    /// step on (`Some`), or hands it back to its scene `motion` (`None`). Refused, changing
    /// nothing, for an index past the scene's objects or a pose with a non-finite number.
    pub fn pose_object(
        &mut self,
        index: usize,
        pose: Option<crate::scene::ObjectPose>,
    ) -> Result<()> {
        let count = self.scene.objects.len();
        let Some(object) = self.scene.objects.get_mut(index) else {
            return Err(crate::error::Error::Invalid(format!(
                "object {index} cannot be posed: the scene has {count} objects (0 to {})",
                count.saturating_sub(1)
            )));
        };
        if let Some(p) = &pose {
            if !p.is_finite() {
                return Err(crate::error::Error::Invalid(format!(
                    "object {index} cannot be posed at {p:?}: every number must be finite"
                )));
            }
        }
        object.pose = pose;
        Ok(())
    }

    /// Moves the mesh objects that have a motion to where they are now.
    fn place_objects(&self, gpu: &Gpu) {
        let objects = &self.scene.objects;
        if objects
            .iter()
            .all(|o| o.motion == crate::scene::Motion::Static && o.pose.is_none())
        {
            return;
        }
        if let Some(pass) = &self.draw.objects {
            let models: Vec<glam::Mat4> = objects
                .iter()
                .map(|o| crate::sim::colliders::object_transform(o, &self.terrain, self.time))
                .collect();
            pass.set_transforms(&gpu.queue, &models);
        }
    }

    /// Records the wind step and the blade update over the patches the patch pass picked;
    /// a wind grid that follows the camera is centred on `eye` first.
    fn encode_update(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        dt: f32,
        eye: glam::Vec3,
    ) {
        // The wind moves first; the blades then read this step's air velocity.
        if let Some(fluid) = &mut self.fluid {
            // The wind's passes count into the frame's "wind" row.
            let wind_work = PassQueries::new(None, self.work.as_ref().map(|w| (w, work::WIND)));
            fluid.follow(&gpu.queue, encoder, [eye.x, eye.z], wind_work);
            let mut forces = agc::fluid_forces(&self.scene, &self.terrain, self.time);
            if self.scene.wind.fluid.obstacles {
                forces
                    .obstacles
                    .extend(crate::sim::colliders::object_obstacles(
                        &self.scene.objects,
                        &self.packings,
                        &self.terrain,
                        self.time,
                    ));
                forces
                    .obstacles
                    .extend(self.dynamic_spheres.iter().map(|s| ObstacleGpu {
                        circle: [
                            s.center.x,
                            s.center.z,
                            s.radius,
                            s.center.y - self.terrain.height(s.center.x, s.center.z),
                        ],
                        velocity: [s.velocity.x, s.velocity.z, s.velocity.y, 0.0],
                    }));
                forces.obstacles.truncate(MAX_OBSTACLES);
            }
            fluid.prepare(&gpu.queue, dt, &forces);
            fluid.encode(encoder, wind_work);
        }
        let mut params = sim_params(
            &self.scene.physics,
            &self.scene.wind,
            self.scene.terrain.size,
            dt,
            self.time,
            self.buffers.count,
            self.sphere_count,
        );
        params.patch_size = self.buffers.patch_size;
        params.patch_count = self.buffers.patch_count;
        // The class order the patch pass listed the chunks in (its `distance_levels`).
        params.distance_levels = self.scene.culling.distance_levels.max(1);
        crate::sim::bvh::fill_params(
            &mut params,
            &self.bvh,
            self.scene.collision_hierarchy(),
            eye,
        );
        // The grid's corner and cell now (a following grid moves; the blades and the
        // billboards must sample it where it is).
        if let Some(f) = &self.fluid {
            let o = f.origin();
            params.fluid_grid[0] = o[0];
            params.fluid_grid[1] = o[1];
            params.fluid_grid[2] = f.config().cell_size;
        }
        params.throttled_dt = throttled_dt(
            dt,
            self.scene.culling.physics_throttle,
            self.scene.physics.max_dt,
        );
        let model = self.stepped_model().id();
        params.model[0] = model as f32;
        // The propagation runs while its grid matches the scene's (`apply_propagation`).
        let propagation = self.scene.physics.propagation.as_ref().filter(|p| {
            self.propagation
                .as_ref()
                .is_some_and(|q| q.n == crate::sim::propagation::cells_per_side(p))
        });
        crate::sim::propagation::fill_params(&mut params, propagation, eye);
        self.update
            .prepare(&gpu.device, &gpu.queue, &params, model);
        if let (Some(pass), Some(p)) = (&self.propagation, propagation) {
            pass.clear(encoder);
            timed(self.meters(), encoder, timing::UPDATE, |e, q| {
                self.update.encode(e, q)
            });
            pass.encode(
                encoder,
                p.generations,
                model == crate::scene::BladeModel::Jahrmann.id(),
            );
        } else {
            timed(self.meters(), encoder, timing::UPDATE, |e, q| {
                self.update.encode(e, q)
            });
        }
    }

    /// Cull uniforms for a camera and viewport; `hiz` describes the depth pyramid (zeros:
    /// no occlusion test).
    fn cull_uniforms(&self, camera: &CameraView, size: (u32, u32), hiz: [u32; 4]) -> CullParams {
        // The meshes the grass pipelines are built for: flat at every level without the fold.
        let (lod_index_count, lod_first_index) = self.lod.levels(self.draw.grass_spec().fold);
        let mut p = cull_params(
            &self.scene.culling,
            &CullInputs {
                // Unjittered: the TAA jitter moves the picture, not what is in view (and
                // the cull's CPU twins see the camera's own view).
                view_proj: self.view_crop * camera.view_proj(self.aspect(size.0, size.1)),
                camera: camera.eye,
                fov_y: camera.fov_y,
                near: camera.near,
                far: camera.far,
                viewport_height: size.1,
                blade_count: self.buffers.count,
                patch_size: self.buffers.patch_size,
                patch_count: self.buffers.patch_count,
                lod_segments: self.lod.segments,
                lod_index_count,
                lod_first_index,
                frame: self.frame_count,
                hiz,
                sphere_count: self.sphere_count,
                collisions: self.scene.physics.collisions,
            },
        );
        // The broad phase cuts the same tree at the same precision as the update walks it.
        crate::sim::bvh::fill_cull_params(
            &mut p,
            &self.bvh,
            self.scene.collision_hierarchy(),
            camera.eye,
            self.scene.physics.hierarchy_precision_distance,
        );
        // With multi-draw each level's instances start at its region of the visible list.
        // The late draws start mid-region, which needs first-instance draws: without them
        // grass does not occlude grass.
        if self.multi_draw {
            p.lod_index_count[3] = self.buffers.region;
        } else {
            p.lod_index_count[3] = 0;
            p.tests &= !TEST_GRASS_OCCLUSION;
        }
        // The window's budget: each level's pixel heights scaled (finite and at least 1,
        // or the scene's).
        let coarsen = if self.lod_coarsen.is_finite() {
            self.lod_coarsen.max(1.0)
        } else {
            1.0
        };
        p.lod[1] *= coarsen;
        p.lod[2] *= coarsen;
        // The window's frame budget: the levels change without the morph band.
        if !self.lod_morph {
            p.lod[3] = 0.0;
        }
        p
    }

    /// One simulation step without drawing (`sward simulate`): every patch is stepped.
    pub fn step(&mut self, gpu: &Gpu, dt: f32) {
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("sward.step"),
            });
        let dt = self.advance(gpu, dt);
        // No camera: no patch is culled and none is throttled.
        let camera = self.scene_camera(&CameraView::from_scene(&self.scene.camera), 0.0);
        self.stream_tiles(gpu, &mut encoder, camera.eye);
        if let Some(c) = &self.carried {
            c.encode(&mut encoder);
        }
        let mut cp = self.cull_uniforms(&camera, (16, 9), [0; 4]);
        cp.tests = 0;
        cp.physics_throttle = 1;
        self.cull.prepare(&gpu.queue, &cp);
        self.last_cull = cp;
        self.cull
            .encode_patches(&mut encoder, crate::gpu::queries::PassQueries::NONE);
        self.encode_update(gpu, &mut encoder, dt, camera.eye);
        self.resolve_queries(&mut encoder);
        let index = gpu.queue.submit([encoder.finish()]);
        self.frame_submitted(gpu, index);
    }

    /// The view-projection the passes draw `camera` with into a target of `size`: the
    /// camera's for the display's aspect, cropped by [`Renderer::view_crop`] and moved by
    /// this frame's TAA jitter.
    pub(crate) fn view_proj(&self, camera: &CameraView, size: (u32, u32)) -> glam::Mat4 {
        self.jitter * self.view_crop * camera.view_proj(self.aspect(size.0, size.1))
    }

    /// The projection's aspect ratio for a target of `width` × `height`.
    fn aspect(&self, width: u32, height: u32) -> f32 {
        self.display_aspect
            .unwrap_or(width as f32 / height.max(1) as f32)
    }

    /// Uniforms of the draw pass for a camera and viewport.
    pub fn frame_uniforms(&self, camera: &CameraView, width: u32, height: u32) -> FrameUniforms {
        let view_proj = self.view_proj(camera, (width, height));
        let sun = light::sun::scene_sun(&self.scene);
        let f = &self.scene.field;
        FrameUniforms {
            view_proj: view_proj.to_cols_array_2d(),
            inv_view_proj: view_proj.inverse().to_cols_array_2d(),
            camera_pos: camera.eye.extend(1.0).into(),
            sun_dir: sun.extend(0.0).into(),
            viewport_time: [
                width as f32,
                height as f32,
                self.time,
                fog_distance(self.scene.terrain.size, camera.far),
            ],
            shape: [
                f.shape.id() as f32,
                f.tip_threshold,
                f.segments.max(1) as f32,
                u32::from(self.folds()) as f32,
            ],
            width_correction: [
                self.scene.render.width_min_px,
                self.scene.render.width_span_px,
                self.scene.terrain.size,
                0.0,
            ],
            debug: [
                self.scene.render.color_mode.id() as f32,
                self.scene.render.self_shadow.uniforms().0,
                0.0,
                self.buffers.patch_size as f32,
            ],
            self_shadow: self.scene.render.self_shadow.uniforms().1,
            thinning: {
                let c = &self.last_cull;
                let on = c.tests & crate::sim::layout::TEST_DISTANCE != 0 && c.max_distance > 0.0;
                let levels = if on {
                    c.distance_levels.max(1) as f32
                } else {
                    0.0
                };
                [c.camera_pos[0], c.camera_pos[1], c.camera_pos[2], levels]
            },
            thinning_reach: [self.last_cull.max_distance, self.cards_radius(), 0.0, 0.0],
        }
    }

    /// The radius the billboards are drawn to (m; 0 without them, as `BillboardPass`
    /// draws them): they stand for the canopy under the thinned blades within it
    /// (`render::thinning::root`), and past it each thinned blade is drawn whole.
    fn cards_radius(&self) -> f32 {
        self.billboards.as_ref().map_or(0.0, |b| {
            b.drawn_radius(self.billboard_share, self.last_cull.max_distance)
        })
    }

    /// The last TAA frame's inputs and outputs, read back (blocking; the twin's test).
    /// `None` while `render.taa` is off or before its first frame.
    pub fn read_taa_frame(&self, gpu: &Gpu) -> Result<Option<taa::reference::TaaFrame>> {
        match &self.taa {
            Some(t) => t.read_frame(gpu, &self.buffers.blades),
            None => Ok(None),
        }
    }

    /// The deferred light's table of the sky for the fog, read back (blocking; the twin's
    /// test): `None` unless the last frame's grass took the one-sample deferred path.
    pub fn read_sky_lut(&self, gpu: &Gpu) -> Option<Result<Vec<[f32; 3]>>> {
        let d = self.deferred.as_ref().filter(|d| d.samples() == 1)?;
        Some(d.read_sky_lut(gpu))
    }

    /// The sun, the sky and the shadow maps of the last frame.
    pub fn light(&self) -> &light::LightPass {
        &self.light
    }

    /// GPU memory held for the blades (blade, state, seen-flag, patch, sphere and
    /// visible-index buffers, the Verlet states, the trail map, plus the indirect
    /// arguments), and in all, wind solver, shadow map and the ground's cached shadow
    /// depth included. Meshes and
    /// uniforms are a few hundred KiB and counted in the total.
    pub fn gpu_bytes(&self) -> (u64, u64) {
        let b = &self.buffers;
        let blades = [
            &b.blades,
            &b.states,
            &b.patches,
            &b.spheres,
            &b.visible,
            &b.patch_lists,
            &b.patch_spheres,
            &b.dispatch,
            &b.seen,
            &b.sun,
            &b.resets,
            &b.verlet,
            &b.trails,
        ]
        .iter()
        .map(|x| x.size())
        .sum::<u64>()
            + self.cull.args.size();
        let fluid = self.fluid.as_ref().map_or(0, |f| f.gpu_bytes());
        let pyramid = self.pyramid.as_ref().map_or(0, |p| p.gpu_bytes())
            + self.deferred.as_ref().map_or(0, |d| d.gpu_bytes())
            + self.taa.as_ref().map_or(0, |t| t.gpu_bytes());
        // Multisampled half-float colour (8 bytes) and depth (4 bytes) per sample.
        let msaa = self.msaa.as_ref().map_or(0, |m| {
            m.size.0 as u64 * m.size.1 as u64 * m.samples as u64 * 12
        });
        (
            blades,
            blades
                + fluid
                + pyramid
                + msaa
                + self.post.gpu_bytes()
                + self.draw.gpu_bytes()
                + self.light.gpu_bytes(),
        )
    }

    /// Whether the blades fold now: the scene's `render.displacement`, unless the renderer's
    /// [`Renderer::fold`] is off.
    pub fn folds(&self) -> bool {
        self.fold && self.scene.render.displacement
    }

    /// Specialises the grass pipelines for the scene (the default) or keeps them general,
    /// every blade model, shape, flower and debug path compiled in and chosen by the
    /// uniforms (`render::grass_spec`); the pictures are the same, the general one slower.
    pub fn specialise_grass(&mut self, on: bool) {
        self.draw.general_grass = !on;
    }

    /// Lets the grass take the deferred shading path where it can (the default) or draws
    /// it forward (`render::deferred`); the pictures differ only by the light's sampling:
    /// per pixel on the blade's curve instead of interpolated between its vertices.
    /// The scene's `render.deferred_grass`.
    pub fn deferred_grass(&mut self, on: bool) {
        self.scene.render.deferred_grass = on;
    }

    /// Whether the last frame's grass took the deferred path.
    pub fn grass_deferred(&self) -> bool {
        self.deferred.is_some()
    }

    /// Builds the tone-mapping pass for the scene's curve alone (the default) or keeps
    /// every curve in it, the uniform choosing (`render::post`); the pictures are the same.
    pub fn specialise_tone_map(&mut self, on: bool) {
        self.post.general = !on;
    }

    /// The grass pipelines' specialisation in use.
    pub fn grass_spec(&self) -> grass_spec::GrassSpec {
        self.draw.grass_spec()
    }

    /// Whether the grass can be drawn as lines on this adapter.
    pub fn has_wireframe(&self) -> bool {
        self.draw.has_wireframe()
    }

    /// The cull uniforms of the last frame drawn.
    pub fn last_cull_params(&self) -> &CullParams {
        &self.last_cull
    }

    /// The occlusion test's depth pyramid of the last frame, if occlusion ran.
    pub fn pyramid(&self) -> Option<&DepthPyramid> {
        self.pyramid.as_ref()
    }

    /// Every level of the last frame's depth pyramid, level 0 (the depth buffer) included,
    /// read back (blocking; for tests). `None` before a frame with occlusion.
    pub fn read_pyramid(&self, gpu: &Gpu) -> Option<Result<Vec<Vec<f32>>>> {
        let (p, depth) = self.pyramid.as_ref().zip(self.pyramid_depth.as_ref())?;
        Some(p.read_levels(gpu, depth))
    }

    /// Keeps every frame's GPU scopes from now on, for [`Renderer::take_trace`]. Returns
    /// false when the device has no timestamp queries (the trace will have no events).
    pub fn record_trace(&mut self) -> bool {
        match &mut self.timer {
            Some(t) => {
                t.record_trace();
                true
            }
            None => false,
        }
    }

    /// The GPU scopes of every frame since [`Renderer::record_trace`] (blocks until the
    /// GPU is idle), for [`timing::chrome_trace`].
    pub fn take_trace(&mut self, gpu: &Gpu) -> Result<Vec<wgpu_profiler::GpuTimerQueryResult>> {
        match &mut self.timer {
            Some(t) => t.take_trace(gpu),
            None => Ok(Vec::new()),
        }
    }

    /// Blades reset to their rest pose since the start (non-finite or absurd state; blocks
    /// until the GPU is idle).
    pub fn blades_reset_nonfinite(&self, gpu: &Gpu) -> Result<u32> {
        self.buffers.read_resets(gpu)
    }

    /// The GPU timer and the work counter, for [`timing::timed`].
    pub(crate) fn meters(&self) -> Meters<'_> {
        Meters {
            timer: self.timer.as_ref(),
            work: self.work.as_ref(),
        }
    }

    /// Counts the work of every frame from now on (`true`) or of none (`false`): each
    /// pass's shader invocations (pipeline-statistics queries) and the pixels the grass
    /// covers (one more depth-only draw of the grass, `coverage`). Returns false when the
    /// device has no pipeline-statistics queries. Counting costs a little GPU time: time
    /// frames that are not counted.
    pub fn count_work(&mut self, gpu: &Gpu, on: bool) -> bool {
        if !on {
            self.work = None;
            return gpu.pipeline_statistics;
        }
        if self.work.is_none() {
            self.work = WorkCounter::new(gpu, work::WORK_ROWS.len());
        }
        self.work.is_some()
    }

    /// The work of the last counted frame that came back, by row of
    /// [`work::WORK_ROWS`] (blocks until the GPU is idle); `None` when not counting.
    pub fn read_work(&mut self, gpu: &Gpu) -> Result<Option<WorkFrame>> {
        match &mut self.work {
            Some(w) => w.read(gpu),
            None => Ok(None),
        }
    }

    /// Whether every frame's work is counted ([`Renderer::count_work`]).
    pub fn counting_work(&self) -> bool {
        self.work.is_some()
    }

    /// The last counted frame that came back, without waiting (the window's panel).
    pub fn last_work(&self) -> Option<&WorkFrame> {
        self.work.as_ref().and_then(|w| w.last())
    }

    /// The sample count of the frame's 3D targets (`render.msaa` as the adapter holds it).
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// Reads back the counters and pass times of the last frame (blocks until it is done).
    pub fn stats(&mut self, gpu: &Gpu) -> Result<FrameStats> {
        let counters = self.cull.read_counters(gpu)?;
        let pass_ms = match &mut self.timer {
            Some(t) => Some(t.read_ms(gpu)?),
            None => None,
        };
        let wind_ms = match &self.fluid {
            Some(f) => f.read_pass_ms(gpu)?,
            None => None,
        };
        Ok(FrameStats {
            counters,
            pass_ms,
            wind_ms,
            blades_reset_nonfinite: self.buffers.read_resets(gpu)?,
            tiles: self.tile_stats(),
            billboards_drawn: self.billboards_drawn(gpu)?,
        })
    }
}
