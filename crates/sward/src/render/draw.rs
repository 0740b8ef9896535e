//! The draw pass: sky, terrain, colliders and the grass (one indexed indirect draw per level
//! of detail, whose instance counts — batches of `DRAW_BATCH` blades — the cull pass wrote;
//! one multi-draw where the adapter has first-instance support), depth tested, into any colour view. Before it, a depth-only
//! pass of the opaque objects (terrain, colliders) feeds the occlusion test's pyramid.

use wgpu::util::DeviceExt;

use super::camera::CameraView;
use super::grass_bind::{GrassBindings, ModelBuffers};
use super::mesh::{sphere_mesh, LodMeshes};

use super::grass_spec::GrassSpec;
use super::pipelines::{GrassPipelines, Pipelines, TerrainSpec};
use super::light::Casters;
use super::terrain::TerrainPass;
use crate::field::clumps::FieldTraits;
use crate::field::{DensityMap, HeightField};
use crate::gpu::queries::PassQueries;
use crate::gpu::Gpu;
use crate::sim::layout::{FrameUniforms, LOD_LEVELS};
use crate::sim::update::{uniform_entry, BladeBuffers};

/// Depth format of every pass.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

struct Mesh {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    count: u32,
}

/// Which of the uploaded collider spheres are drawn: all `count` but the `hidden` range
/// (the spheres packed into mesh objects, which the mesh itself shows).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SphereDraw {
    /// Spheres uploaded (instances available to the sphere draw).
    pub count: u32,
    /// Instance indices not drawn because a mesh object shows them; may be empty, and is
    /// clamped to `0..count`.
    pub hidden: std::ops::Range<u32>,
}

impl SphereDraw {
    /// The instance ranges to draw.
    pub fn drawn(&self) -> [std::ops::Range<u32>; 2] {
        let start = self.hidden.start.min(self.count);
        let end = self.hidden.end.clamp(start, self.count);
        [0..start, end..self.count]
    }

    /// Whether at least one sphere is left to draw once the hidden range is skipped.
    pub fn any_drawn(&self) -> bool {
        self.drawn().iter().any(|r| !r.is_empty())
    }
}

/// The draw pass: the frame uniforms, the sky, terrain, sphere, object and grass pipelines
/// for one sample count, and their bind groups.
pub struct DrawPass {
    frame: wgpu::Buffer,
    frame_group: wgpu::BindGroup,
    /// One group per level (each binds its region of the visible list), or one for all
    /// levels with multi-draw.
    grass_groups: Vec<wgpu::BindGroup>,
    spheres_group: wgpu::BindGroup,
    /// Kept to rebuild the pipelines for another sample count.
    frame_layout: wgpu::BindGroupLayout,
    /// The grass groups' layout and sources, kept to rebind the blade models' buffers.
    grass: GrassBindings,
    spheres_layout: wgpu::BindGroupLayout,
    format: wgpu::TextureFormat,
    pipelines: Pipelines,
    /// The field's species, clumps and flowers (the grass's uniform), for the grass
    /// pipelines' specialisation.
    traits: FieldTraits,
    /// Keeps the grass pipelines general (every path, as without constants): the test
    /// that specialising changes no pixel compares against this.
    pub general_grass: bool,
    /// The clipmap terrain's buffers and bind group.
    terrain_pass: TerrainPass,
    /// Whether the ground goes into the shadow maps under this frame's sun
    /// (`TerrainPass::casts_shadow`).
    terrain_casts: std::cell::Cell<bool>,
    sphere_mesh: Mesh,
    /// A coarse sphere for the occluder pass: its vertices lie on the sphere, so it is
    /// inside it and occludes no more than the sphere does (and the colour pass's finer
    /// sphere, in front of it, still passes the depth test).
    occluder_sphere: Mesh,
    blade_indices: wgpu::Buffer,
    /// The scene's mesh objects (`objects`).
    pub objects: Option<super::objects::ObjectsPass>,
}

/// Value of `draw_level.x` that makes the grass shader take the level from the instance.
const LEVEL_FROM_INSTANCE: u32 = u32::MAX;

pub(crate) fn read_storage(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: true },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

impl DrawPass {
    /// `cull_params` is the cull pass's uniform buffer (the grass morph reads it);
    /// `multi_draw` draws all levels with one multi-draw-indirect (the device must have
    /// `INDIRECT_FIRST_INSTANCE`, and the cull pass must write first instances);
    /// `density` shades the far ground.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        gpu: &Gpu,
        buffers: &BladeBuffers,
        terrain: &HeightField,
        density: Option<&DensityMap>,
        lod: &LodMeshes,
        cull_params: &wgpu::Buffer,
        cull_output: &wgpu::Buffer,
        multi_draw: bool,
        format: wgpu::TextureFormat,
        samples: u32,
        model: ModelBuffers,
        scene: &crate::scene::Scene,
    ) -> Self {
        let traits = FieldTraits::from_field(&scene.field);
        let device = &gpu.device;
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let frame = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.draw.frame"),
            size: std::mem::size_of::<FrameUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM
                | wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let frame_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.draw.frame_layout"),
            entries: &[uniform_entry(0, vf)],
        });
        let spheres_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.draw.spheres_layout"),
            entries: &[
                uniform_entry(0, vf),
                read_storage(1, wgpu::ShaderStages::VERTEX),
            ],
        });
        let frame_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sward.draw.frame_group"),
            layout: &frame_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: frame.as_entire_binding(),
            }],
        });
        // Without multi-draw each level binds its own region of the visible list (regions
        // are 256-byte aligned) and counts instances from 0.
        let region_bytes = buffers.region as u64 * 4;
        let levels: Vec<(u32, u64, Option<u64>)> = if multi_draw {
            vec![(LEVEL_FROM_INSTANCE, 0, None)]
        } else {
            (0..LOD_LEVELS as u32)
                .map(|k| (k, k as u64 * region_bytes, Some(region_bytes)))
                .collect()
        };
        let levels = levels
            .into_iter()
            .map(|(level, offset, size)| {
                let level_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("sward.draw.grass_level"),
                    contents: bytemuck::cast_slice(&[level, buffers.region, 0, 0]),
                    usage: wgpu::BufferUsages::UNIFORM,
                });
                (level_buffer, offset, size)
            })
            .collect();
        let grass = GrassBindings::new(
            device,
            &frame,
            buffers,
            cull_params,
            cull_output,
            levels,
            &traits,
        );
        let grass_groups = grass.groups(device, model);
        let spheres_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sward.draw.spheres_group"),
            layout: &spheres_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: frame.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: buffers.spheres.as_entire_binding(),
                },
            ],
        });

        let terrain_pass = TerrainPass::new(
            gpu,
            (terrain, &scene.field),
            density,
            &frame,
            &buffers.trails,
        );
        let pipelines = Pipelines::new(
            device,
            format,
            samples,
            [
                &frame_layout,
                &terrain_pass.layout,
                &spheres_layout,
                &grass.layout,
            ],
            GrassSpec::of(scene, &traits),
            TerrainSpec {
                trails: buffers.has_trail_map(),
                density_map: terrain_pass.has_density_map(),
            },
        );
        let sphere = |rings, sectors, label: &str| {
            let (sv, si) = sphere_mesh(rings, sectors);
            Mesh {
                vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(&format!("{label}.vertices")),
                    contents: bytemuck::cast_slice(&sv),
                    usage: wgpu::BufferUsages::VERTEX,
                }),
                indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(&format!("{label}.indices")),
                    contents: bytemuck::cast_slice(&si),
                    usage: wgpu::BufferUsages::INDEX,
                }),
                count: si.len() as u32,
            }
        };
        let sphere_mesh = sphere(16, 24, "sward.sphere");
        let occluder_sphere = sphere(6, 8, "sward.sphere_occluder");
        let blade_indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("sward.blade.indices"),
            contents: bytemuck::cast_slice(&lod.indices),
            usage: wgpu::BufferUsages::INDEX,
        });
        Self {
            frame,
            frame_group,
            grass_groups,
            spheres_group,
            frame_layout,
            grass,
            spheres_layout,
            format,
            pipelines,
            traits,
            general_grass: false,
            terrain_pass,
            terrain_casts: std::cell::Cell::new(true),
            sphere_mesh,
            occluder_sphere,
            blade_indices,
            objects: None,
        }
    }

    /// Bytes of the meshes and the frame uniforms.
    pub fn gpu_bytes(&self) -> u64 {
        [
            &self.frame,
            &self.sphere_mesh.vertices,
            &self.sphere_mesh.indices,
            &self.occluder_sphere.vertices,
            &self.occluder_sphere.indices,
            &self.blade_indices,
        ]
        .iter()
        .map(|b| b.size())
        .sum::<u64>()
            + self.terrain_pass.gpu_bytes()
    }

    /// The layout of the grass draw's group 0 (blades, states, frame, traits).
    pub(super) fn grass_layout(&self) -> &wgpu::BindGroupLayout {
        &self.grass.layout
    }

    /// MSAA samples per pixel the pipelines are built for (1 = no MSAA).
    pub fn samples(&self) -> u32 {
        self.pipelines.samples
    }

    /// Rebuilds the pipelines for targets of `samples` samples (the panel's MSAA setting);
    /// buffers and bind groups stay.
    pub fn set_samples(&mut self, device: &wgpu::Device, samples: u32) {
        if let Some(o) = &mut self.objects {
            o.set_samples(device, samples);
        }
        if samples == self.pipelines.samples {
            return;
        }
        self.pipelines = Pipelines::new(
            device,
            self.format,
            samples,
            [
                &self.frame_layout,
                &self.terrain_pass.layout,
                &self.spheres_layout,
                &self.grass.layout,
            ],
            self.pipelines.grass.spec,
            self.pipelines.terrain_spec,
        );
    }

    /// The grass pipelines' specialisation now.
    pub fn grass_spec(&self) -> GrassSpec {
        self.pipelines.grass.spec
    }

    /// Rebuilds the grass pipelines when `scene`'s switches (model, shape, colour view, sky
    /// model) no longer match their specialisation, and the sky pass's when the sky model
    /// changed; true when it did. Only on a change: the panel's edits, never per frame.
    /// `morph`: whether the renderer lets the blades morph between levels; `fold`: whether
    /// it lets them fold along their middle axis (the window's frame budget may not).
    pub fn sync_grass_spec(
        &mut self,
        device: &wgpu::Device,
        scene: &crate::scene::Scene,
        morph: bool,
        fold: bool,
    ) -> bool {
        let spec = if self.general_grass {
            GrassSpec::GENERAL
        } else {
            // The renderer's switches only ever take a path out of the scene's.
            let spec = GrassSpec::of(scene, &self.traits);
            GrassSpec {
                morph: morph && spec.morph,
                fold: fold && spec.fold,
                ..spec
            }
        };
        if spec == self.pipelines.grass.spec {
            return false;
        }
        if spec.sky != self.pipelines.grass.spec.sky {
            self.pipelines.sky = super::pipelines::sky_pipeline(
                device,
                (self.format, self.pipelines.samples),
                &self.frame_layout,
                spec,
            );
        }
        let start = std::time::Instant::now();
        self.pipelines.grass = GrassPipelines::new(
            device,
            self.format,
            self.pipelines.samples,
            &self.grass.layout,
            spec,
        );
        log::info!(
            "grass pipelines rebuilt for {spec:?} in {:.0} ms",
            start.elapsed().as_secs_f64() * 1e3
        );
        true
    }

    /// Binds the blade models' buffers anew (a new wind grid, the Verlet states allocated).
    pub fn bind_model(&mut self, device: &wgpu::Device, model: ModelBuffers) {
        self.grass_groups = self.grass.groups(device, model);
    }

    /// Whether the grass can be drawn as lines (the adapter supports line rasterisation).
    pub fn has_wireframe(&self) -> bool {
        self.pipelines.grass.grass_lines.is_some()
    }

    /// The frame-uniform buffer (the overlay reads it too).
    pub fn frame_buffer(&self) -> &wgpu::Buffer {
        &self.frame
    }

    /// Writes this frame's uniforms (made for `camera`) and places the terrain's levels
    /// around the camera (the viewport and fog distance are in `frame.viewport_time`).
    /// The terrain's height uniforms and grid (for the billboards).
    pub fn terrain_buffers(&self) -> (&wgpu::Buffer, &wgpu::Buffer) {
        self.terrain_pass.height_buffers()
    }

    /// The gusts' bend at the edge of the blades' reach, for the far levels' shading waves
    /// (the frame copies it from the cull's counters; the billboards read it too).
    pub fn waves_buffer(&self) -> &wgpu::Buffer {
        &self.terrain_pass.waves
    }

    /// The far ground's grass colour (`clipmap::far_albedo` of the field).
    pub fn set_far_albedo(&mut self, albedo: glam::Vec3) {
        self.terrain_pass.grass_albedo = albedo;
    }

    /// Says whether blades grow past the terrain square (see `TerrainPass::grass_everywhere`).
    pub fn set_grass_everywhere(&mut self, everywhere: bool) {
        self.terrain_pass.grass_everywhere = everywhere;
    }

    /// `projection`: the aspect the camera is projected with and the crop after it
    /// (`Renderer::view_proj`), which the terrain's eye-relative projection repeats;
    /// `reach`: the blades' culling distance this frame (the far ground's soil-to-grass
    /// blend follows it).
    pub fn prepare(
        &self,
        queue: &wgpu::Queue,
        frame: &FrameUniforms,
        camera: &CameraView,
        projection: (f32, glam::Mat4),
        reach: f32,
    ) {
        queue.write_buffer(&self.frame, 0, bytemuck::bytes_of(frame));
        self.terrain_casts
            .set(self.terrain_pass.casts_shadow(frame.sun_dir[1]));
        let fog = frame.viewport_time[3];
        self.terrain_pass.prepare(queue, camera, projection, fog, reach);
    }

    fn draw_terrain(&self, pass: &mut wgpu::RenderPass<'_>) {
        self.terrain_pass.draw(pass);
    }

    /// The key of the ground's depth in the shadow maps this frame
    /// (`TerrainPass::shadow_key`), or `None` when the ground casts no shadow.
    pub fn ground_shadow_key(&self) -> Option<u64> {
        self.terrain_casts
            .get()
            .then(|| self.terrain_pass.shadow_key())
    }

    fn draw_spheres(&self, pass: &mut wgpu::RenderPass<'_>, mesh: &Mesh, spheres: &SphereDraw) {
        pass.set_bind_group(0, &self.spheres_group, &[]);
        pass.set_vertex_buffer(0, mesh.vertices.slice(..));
        pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
        for range in spheres.drawn() {
            if !range.is_empty() {
                pass.draw_indexed(0..mesh.count, 0, range);
            }
        }
    }

    /// Records the occluder pass: the opaque objects' depth only, into `depth` (cleared),
    /// which the depth pyramid is then built from.
    pub fn encode_occluders(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        depth: &wgpu::TextureView,
        spheres: &SphereDraw,
        q: PassQueries,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("sward.draw.occluders"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: q.render_writes(),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        q.begin(&mut pass);
        if spheres.any_drawn() {
            pass.set_pipeline(&self.pipelines.spheres_depth);
            self.draw_spheres(&mut pass, &self.occluder_sphere, spheres);
        }
        if let Some(o) = &self.objects {
            o.draw(&mut pass, true);
        }
        pass.set_pipeline(&self.pipelines.terrain_depth);
        self.draw_terrain(&mut pass);
        q.end(&mut pass);
    }

    /// Records the render pass into `color` with `depth`; `depth_loaded` keeps the depth
    /// of the occluder pass instead of clearing it. With `vis` (the deferred path's
    /// visibility buffer, `render::deferred`) the grass is first drawn into it in a pass of
    /// its own, and the colour pass draws everything else.
    #[allow(clippy::too_many_arguments)]
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
        depth_loaded: bool,
        vis: Option<&wgpu::TextureView>,
        indirect: &wgpu::Buffer,
        spheres: &SphereDraw,
        wireframe: bool,
        billboards: Option<&super::billboard::BillboardPass>,
        light: &wgpu::BindGroup,
        q: PassQueries,
    ) {
        let mut depth_load = if depth_loaded {
            wgpu::LoadOp::Load
        } else {
            wgpu::LoadOp::Clear(1.0)
        };
        let deferred = vis.zip(self.deferred());
        // Multisampled, the visibility draws mark the colour's grass samples (the colour is
        // their second attachment, cleared here as the forward pass clears it) and the
        // colour pass loads it.
        let multisampled = deferred.is_some() && self.pipelines.samples > 1;
        if let Some((vis, pipelines)) = deferred {
            let clear = wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT);
            let targets = [
                (vis, clear),
                (color, wgpu::LoadOp::Clear(wgpu::Color::BLACK)),
            ];
            let mut pass = colour_pass(
                encoder,
                "sward.draw.grass_vis",
                &targets[..1 + usize::from(multisampled)],
                (depth, depth_load),
                q.render_writes_part(true, false),
            );
            q.begin(&mut pass);
            self.draw_grass(&mut pass, &pipelines.vis, indirect, 0);
            q.end(&mut pass);
            depth_load = wgpu::LoadOp::Load;
        }
        let writes = if deferred.is_some() {
            q.render_writes_part(false, true)
        } else {
            q.render_writes()
        };
        let load = if multisampled {
            wgpu::LoadOp::Load
        } else {
            wgpu::LoadOp::Clear(wgpu::Color::BLACK)
        };
        let mut pass = colour_pass(
            encoder,
            "sward.draw",
            &[(color, load)],
            (depth, depth_load),
            writes,
        );
        pass.set_bind_group(1, light, &[]);
        q.begin(&mut pass);
        if spheres.any_drawn() {
            pass.set_pipeline(&self.pipelines.spheres);
            self.draw_spheres(&mut pass, &self.sphere_mesh, spheres);
        }
        if let Some(o) = &self.objects {
            o.draw(&mut pass, false);
        }
        q.end(&mut pass);

        // The lit grass is counted apart: its fragments per covered pixel are the figure
        // the frame's shading cost is held to.
        if deferred.is_none() {
            let grass = q.row(super::work::LIT_GRASS);
            grass.begin(&mut pass);
            self.draw_grass(&mut pass, self.grass_pipeline(wireframe), indirect, 0);
            grass.end(&mut pass);
        }
        q.begin(&mut pass);
        if let Some(b) = billboards {
            b.draw(&mut pass);
        }

        // Front to back: what the grass covers of the ground and what the ground covers of
        // the sky is rejected by the depth test before it is shaded.
        pass.set_pipeline(&self.pipelines.terrain);
        self.draw_terrain(&mut pass);

        pass.set_pipeline(&self.pipelines.sky);
        pass.set_bind_group(0, &self.frame_group, &[]);
        pass.draw(0..3, 0..1);
        q.end(&mut pass);
    }

    /// The grass's level-of-detail draws whose arguments start at byte `offset` of
    /// `indirect` (one multi-draw, or one draw per level with its region bound).
    pub(super) fn draw_grass(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        pipeline: &wgpu::RenderPipeline,
        indirect: &wgpu::Buffer,
        offset: u64,
    ) {
        pass.set_pipeline(pipeline);
        pass.set_index_buffer(self.blade_indices.slice(..), wgpu::IndexFormat::Uint32);
        let stride = std::mem::size_of::<crate::sim::layout::DrawIndexedIndirect>() as u64;
        if let [all] = self.grass_groups.as_slice() {
            pass.set_bind_group(0, all, &[]);
            pass.multi_draw_indexed_indirect(indirect, offset, LOD_LEVELS as u32);
        } else {
            for (k, group) in self.grass_groups.iter().enumerate() {
                pass.set_bind_group(0, group, &[]);
                pass.draw_indexed_indirect(indirect, offset + k as u64 * stride);
            }
        }
    }

    /// The grass's colour pipeline: filled, or as lines where asked and supported.
    fn grass_pipeline(&self, wireframe: bool) -> &wgpu::RenderPipeline {
        let p = &self.pipelines.grass;
        match (&p.grass_lines, wireframe) {
            (Some(lines), true) => lines,
            _ => &p.grass,
        }
    }

    /// Records the sun's shadow casters into a cascade's pass (the frame buffer holds the
    /// cascade's view): the colliders, the objects, the terrain, and with `grass_args` the
    /// blades the cull kept, drawn with the coarsest level's mesh out to the frame's
    /// shadow radius (`grass.wgsl`); `casters` picks the terrain alone or all but it.
    pub fn draw_casters(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        spheres: &SphereDraw,
        grass_args: Option<(&wgpu::Buffer, u64)>,
        casters: Casters,
    ) {
        if casters == Casters::Ground {
            pass.set_pipeline(&self.pipelines.shadow_terrain);
            self.draw_terrain(pass);
            return;
        }
        if spheres.any_drawn() {
            // The colour pass's sphere: the shadow's outline is the drawn ball's.
            pass.set_pipeline(&self.pipelines.shadow_spheres);
            self.draw_spheres(pass, &self.sphere_mesh, spheres);
        }
        if let Some(o) = &self.objects {
            o.draw_shadow(pass);
        }
        if casters == Casters::All && self.terrain_casts.get() {
            pass.set_pipeline(&self.pipelines.shadow_terrain);
            self.draw_terrain(pass);
        }
        if let Some((args, offset)) = grass_args {
            self.draw_grass(pass, &self.pipelines.grass.shadow_grass, args, offset);
        }
    }

    /// Records the late grass draw of two-phase occlusion culling: the blades the late cull
    /// kept, over the frame the main draw left (colour and depth loaded). Needs
    /// multi-draw: the late lists start mid-region, at their draws' first instance.
    #[allow(clippy::too_many_arguments)]
    /// With `vis` (the deferred path) into the visibility buffer instead of `color`.
    #[allow(clippy::too_many_arguments)]
    pub fn encode_late(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
        vis: Option<&wgpu::TextureView>,
        indirect: &wgpu::Buffer,
        wireframe: bool,
        light: &wgpu::BindGroup,
        q: PassQueries,
    ) {
        let offset = std::mem::offset_of!(crate::sim::layout::CullCounters, late_draws) as u64;
        let deferred = vis.zip(self.deferred());
        let load = wgpu::LoadOp::Load;
        let both = [(vis.unwrap_or(color), load), (color, load)];
        let (targets, label) = match deferred {
            // Multisampled, the colour's grass samples are marked too.
            Some(_) if self.pipelines.samples > 1 => (&both[..], "sward.draw.late_vis"),
            Some(_) => (&both[..1], "sward.draw.late_vis"),
            None => (&both[1..], "sward.draw.late"),
        };
        let mut pass = colour_pass(
            encoder,
            label,
            targets,
            (depth, wgpu::LoadOp::Load),
            q.render_writes(),
        );
        q.begin(&mut pass);
        match deferred {
            Some((_, pipelines)) => self.draw_grass(&mut pass, &pipelines.vis, indirect, offset),
            None => {
                pass.set_bind_group(1, light, &[]);
                self.draw_grass(&mut pass, self.grass_pipeline(wireframe), indirect, offset);
            }
        }
        q.end(&mut pass);
    }

    /// The deferred shading's pipelines, when the grass pipelines' specialisation and
    /// sample count allow the path (`render::deferred`).
    pub(super) fn deferred(&self) -> Option<&super::deferred::DeferredPipelines> {
        self.pipelines.grass.deferred.as_ref()
    }

    /// The grass draw's groups 0, one for all levels or one per level (the deferred
    /// shading binds them: the blades, their states, the frame and the field's traits;
    /// the sun's pass walks each group's visible list).
    pub(super) fn grass_groups(&self) -> &[wgpu::BindGroup] {
        &self.grass_groups
    }
}

/// A render pass into `colors` and `depth` with the given loads, all stored: the main draw
/// (colour cleared) and the late grass draw (both loaded) differ only in those; the
/// multisampled visibility draws have the colour as a second attachment.
fn colour_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    colors: &[(&wgpu::TextureView, wgpu::LoadOp<wgpu::Color>)],
    depth: (&wgpu::TextureView, wgpu::LoadOp<f32>),
    timestamps: Option<wgpu::RenderPassTimestampWrites>,
) -> wgpu::RenderPass<'e> {
    let attachments: Vec<_> = colors
        .iter()
        .map(|&(view, load)| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load,
                    store: wgpu::StoreOp::Store,
                },
            })
        })
        .collect();
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &attachments,
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: depth.0,
            depth_ops: Some(wgpu::Operations {
                load: depth.1,
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: timestamps,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}
