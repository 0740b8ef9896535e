//! The blade buffers on the GPU and the update pass that runs `shaders/update.wgsl` over
//! them every frame.

use crate::gpu::queries::PassQueries;
use wgpu::util::DeviceExt;

use super::bvh::BvhNode;
use super::layout::{
    Blade, BladeState, PatchBox, PatchDispatch, SimParams, VerletState, BVH_NODE_BASE, DRAW_BATCH,
    WIND_ANALYTIC, WIND_FLUID,
    LOD_LEVELS, MAX_SPHERES, PATCH_SPHERE_POOL, PATCH_SPHERE_STRIDE, SPHERE_BUFFER_BYTES,
    UPDATE_CHUNK, WORKGROUP_SIZE,
};
use crate::error::{Error, Result};
use crate::field::tiles::{empty_patch, TileLayout};
use crate::field::GeneratedField;
use crate::gpu::{read_buffer, Gpu};
use crate::shaders;

/// The per-blade data on the GPU, shared by the update, cull and draw passes.
pub struct BladeBuffers {
    /// One [`Blade`] per blade (control points, height, width, up, stiffness), `count`
    /// elements; the update moves v1 and v2.
    pub blades: wgpu::Buffer,
    /// One [`BladeState`] per blade: the rest tip and the collision strength η.
    pub states: wgpu::Buffer,
    /// One [`PatchBox`] per patch: the box that holds every pose of its blades (`min.w` 1:
    /// empty patch).
    pub patches: wgpu::Buffer,
    /// `vec4(centre, radius)` per collider, `MAX_SPHERES` slots, then from `BVH_NODE_BASE`
    /// the colliders' hierarchy (`sim::bvh::encode`), `2 · MAX_SPHERES` node slots.
    pub spheres: wgpu::Buffer,
    /// Visible blade indices written by the cull pass: `LOD_LEVELS` regions of `region`
    /// slots, one per level of detail.
    pub visible: wgpu::Buffer,
    /// Two lists of `patch_count + 1` slots: `[count, patch, ...]`, the patches that passed
    /// the patch tests (the blade cull's list), then `[count, patch | throttled bit, ...]`,
    /// the patches the update steps this frame.
    pub patch_lists: wgpu::Buffer,
    /// Collision broad phase: `PATCH_SPHERE_STRIDE` slots per patch, `[count, sphere, ...]`,
    /// then the pool of `PATCH_SPHERE_POOL` entries for longer lists (`layout`).
    pub patch_spheres: wgpu::Buffer,
    /// `PatchDispatch`: indirect dispatches of the blade cull and of the update.
    pub dispatch: wgpu::Buffer,
    /// One `SEEN_*` word per blade: whether the grass-occlusion test saw it last frame.
    pub seen: wgpu::Buffer,
    /// Two words per blade: the sun's visibility at 8 points along it, written for the
    /// drawn blades by the deferred shading (`blade_sun_points` in `grass_deferred.wgsl`).
    pub sun: wgpu::Buffer,
    /// One u32: blades the update reset to their rest pose because their new state was
    /// non-finite or absurd, counted since the start (never cleared).
    pub resets: wgpu::Buffer,
    /// `VerletState` per blade for `physics.model: Verlet` (allocated by
    /// [`BladeBuffers::ensure_verlet`] when a Verlet blade is first stepped; until then one
    /// unused element).
    pub verlet: wgpu::Buffer,
    /// Whether `verlet` holds a state per blade.
    pub has_verlet: bool,
    /// The trail map of a streamed field (`field::trails`): header, tile table, pages.
    /// Until [`BladeBuffers::ensure_trails`] sizes it, a zeroed header (no table: nothing
    /// is written or read).
    pub trails: wgpu::Buffer,
    /// Blades in `blades` and `states` (for a streamed field, the pool's slots plus the
    /// objects' blades).
    pub count: u32,
    /// Blades per patch (a multiple of [`WORKGROUP_SIZE`]).
    pub patch_size: u32,
    /// Patches in `patches`.
    pub patch_count: u32,
    /// Slots per level-of-detail region of `visible`: the blade count plus one draw batch
    /// (the late list starts at a whole batch), rounded up to 64, so every region starts at
    /// a 256-byte-aligned offset (bindable on its own).
    pub region: u32,
}

impl BladeBuffers {
    /// Bytes of GPU memory the blade buffers take for `count` blades and `patches` patches.
    pub fn bytes_for(count: u64, patches: u64, patch_size: u32) -> u64 {
        count * super::layout::BYTES_PER_BLADE as u64
            + patches * (std::mem::size_of::<PatchBox>() as u64 + PATCH_SPHERE_STRIDE as u64 * 4)
            + list_words(patches as u32, patch_size) * 4
            + PATCH_SPHERE_POOL as u64 * 4
            + SPHERE_BUFFER_BYTES
            + 8
            + std::mem::size_of::<PatchDispatch>() as u64
            + super::propagation_pass::update_out_bytes(0)
    }

    /// Uploads a generated field after checking that it fits the device.
    pub fn new(gpu: &Gpu, field: &GeneratedField) -> Result<Self> {
        Self::create(
            gpu,
            field.blades.len() as u64,
            field.patch_size,
            &field.patches,
            Some((&field.blades, &field.states)),
        )
    }

    /// An empty pool for a streamed field: `layout.slots` tiles of blades, every patch empty
    /// until the tile generation fills its slot; then `objects`' blades and patches (the
    /// grass grown on mesh objects, in patches of the pool's size), uploaded after the pool.
    pub fn new_pool(gpu: &Gpu, layout: &TileLayout, objects: &GeneratedField) -> Result<Self> {
        let mut patches =
            vec![empty_patch(); layout.slots as usize * layout.patches_per_tile() as usize];
        patches.extend_from_slice(&objects.patches);
        let pool = layout.pool_blades();
        let count = pool + objects.blades.len() as u64;
        let buffers = Self::create(gpu, count, layout.patch_size, &patches, None)?;
        if !objects.blades.is_empty() {
            let blade = std::mem::size_of::<Blade>() as u64;
            let state = std::mem::size_of::<BladeState>() as u64;
            gpu.queue.write_buffer(
                &buffers.blades,
                pool * blade,
                bytemuck::cast_slice(&objects.blades),
            );
            gpu.queue.write_buffer(
                &buffers.states,
                pool * state,
                bytemuck::cast_slice(&objects.states),
            );
        }
        Ok(buffers)
    }

    /// The buffers for `count` blades in patches of `patch_size`; `contents` uploads the
    /// blades and states, `None` leaves them zeroed (removed blades).
    fn create(
        gpu: &Gpu,
        count: u64,
        patch_size: u32,
        patches: &[PatchBox],
        contents: Option<(&[Blade], &[BladeState])>,
    ) -> Result<Self> {
        gpu.check_storage(
            &format!("a field of {count} blades"),
            count * std::mem::size_of::<Blade>() as u64,
        )?;
        // Blades are dispatched in 2D (no per-dimension limit); patches in one dimension.
        let patch_count = patches.len() as u32;
        gpu.check_dispatch(
            &format!("a field of {patch_count} patches"),
            patch_count.div_ceil(WORKGROUP_SIZE),
        )?;
        let region = (count as u32 + DRAW_BATCH).div_ceil(WORKGROUP_SIZE) * WORKGROUP_SIZE;
        gpu.check_storage(
            &format!("the visible lists of {count} blades"),
            LOD_LEVELS as u64 * region as u64 * 4,
        )?;
        let device = &gpu.device;
        let storage = wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST;
        // wgpu rejects zero-sized bindings: an empty field still gets one (unused) element.
        let zp = [PatchBox::default()];
        let patches: &[PatchBox] = if patches.is_empty() { &zp } else { patches };
        let buffer = |label: &str, bytes: &[u8], size: u64| match contents {
            Some(_) if !bytes.is_empty() => {
                device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents: bytes,
                    usage: storage,
                })
            }
            // Zeroed by wgpu: height 0, a removed blade.
            _ => device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: storage,
                mapped_at_creation: false,
            }),
        };
        let (blade_bytes, state_bytes): (&[u8], &[u8]) = match contents {
            Some((b, st)) => (bytemuck::cast_slice(b), bytemuck::cast_slice(st)),
            None => (&[], &[]),
        };
        let blades = buffer(
            "sward.blades",
            blade_bytes,
            count.max(1) * std::mem::size_of::<Blade>() as u64,
        );
        let states = buffer(
            "sward.blade_states",
            state_bytes,
            count.max(1) * std::mem::size_of::<BladeState>() as u64,
        );
        let patches = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("sward.patches"),
            contents: bytemuck::cast_slice(patches),
            usage: storage,
        });
        let spheres = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.spheres"),
            size: SPHERE_BUFFER_BYTES,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let visible = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.visible"),
            size: LOD_LEVELS as u64 * region as u64 * 4,
            usage: storage,
            mapped_at_creation: false,
        });
        let patch_lists = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.patch_lists"),
            size: list_words(patch_count, patch_size) * 4,
            usage: storage,
            mapped_at_creation: false,
        });
        let patch_spheres = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.patch_spheres"),
            size: (patch_count.max(1) as u64 * PATCH_SPHERE_STRIDE as u64
                + PATCH_SPHERE_POOL as u64)
                * 4,
            usage: storage,
            mapped_at_creation: false,
        });
        let dispatch = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.patch_dispatch"),
            size: std::mem::size_of::<PatchDispatch>() as u64,
            usage: storage | wgpu::BufferUsages::INDIRECT,
            mapped_at_creation: false,
        });
        // SEEN_YES: on the first frame every blade the tests keep is drawn early, so that
        // it casts its shadow (the grass casters are the early lists, drawn before the late
        // test); the late test then rechecks them against the grass drawn early.
        let seen = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.blades.seen"),
            size: count.max(1) * 4,
            usage: storage,
            mapped_at_creation: true,
        });
        // Mapped at creation the range is always there; were it not, the blades would start
        // unseen (SEEN_NO: drawn late, casting from their second frame).
        if let Ok(mut view) = seen.slice(..).get_mapped_range_mut() {
            let (mut words, _) = view.slice(..).into_chunks::<4>();
            words.fill(super::layout::SEEN_YES.to_le_bytes());
        }
        seen.unmap();
        let sun = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.blades.sun"),
            size: count.max(1) * 8,
            usage: storage,
            mapped_at_creation: false,
        });
        // The reset counter, then the propagation's splat (one unused cell until
        // `ensure_splat` grows it).
        let resets = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.update.resets"),
            size: super::propagation_pass::update_out_bytes(0),
            usage: storage,
            mapped_at_creation: false,
        });
        let verlet = verlet_buffer(device, 1);
        let trails = trails_buffer(device, crate::field::trails::HEADER_WORDS as u64 * 4);
        Ok(Self {
            blades,
            states,
            patches,
            spheres,
            visible,
            patch_lists,
            patch_spheres,
            dispatch,
            seen,
            sun,
            resets,
            verlet,
            has_verlet: false,
            trails,
            count: count as u32,
            patch_size: patch_size.max(1),
            patch_count,
            region,
        })
    }

    /// Allocates the Verlet states (zeroed: every blade starts at rest on its first step)
    /// unless they exist; true when it allocated (the passes that bind them must be
    /// rebuilt). Checked against the adapter's limits first.
    pub fn ensure_verlet(&mut self, gpu: &Gpu) -> Result<bool> {
        if self.has_verlet {
            return Ok(false);
        }
        let bytes = self.count.max(1) as u64 * std::mem::size_of::<VerletState>() as u64;
        gpu.check_storage(
            &format!("the Verlet states of {} blades", self.count),
            bytes,
        )?;
        self.verlet = verlet_buffer(&gpu.device, self.count.max(1) as u64);
        self.has_verlet = true;
        Ok(true)
    }

    /// Allocates the trail map of `layout` (zeroed: no trail anywhere), checked against the
    /// adapter's limits first. Call before the passes that bind it are built.
    pub fn ensure_trails(
        &mut self,
        gpu: &Gpu,
        layout: &crate::field::trails::TrailLayout,
    ) -> Result<()> {
        let bytes = layout.bytes();
        gpu.check_storage(
            &format!(
                "the trail map ({} pages of {}² texels)",
                layout.pages, layout.resolution
            ),
            bytes,
        )?;
        self.trails = trails_buffer(&gpu.device, bytes);
        Ok(())
    }

    /// Makes the update's output (the reset counter) hold the propagation's splat for a grid
    /// of `n` cells per side; true when it reallocated (the passes that bind it must be
    /// rebuilt). The reset count so far is carried over.
    pub fn ensure_splat(&mut self, gpu: &Gpu, n: u32) -> Result<bool> {
        let bytes = super::propagation_pass::update_out_bytes(n);
        if self.resets.size() >= bytes {
            return Ok(false);
        }
        gpu.check_storage("the propagation grid's pushes", bytes)?;
        let resets = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.update.resets"),
            size: bytes,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_SRC
                | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("sward.update.resets_copy"),
            });
        encoder.copy_buffer_to_buffer(&self.resets, 0, &resets, 0, 4);
        gpu.queue.submit([encoder.finish()]);
        self.resets = resets;
        Ok(true)
    }

    /// Reads the Verlet states back (empty when none were allocated).
    pub fn read_verlet(&self, gpu: &Gpu) -> Result<Vec<VerletState>> {
        if !self.has_verlet || self.count == 0 {
            return Ok(Vec::new());
        }
        let bytes = read_buffer(
            gpu,
            &self.verlet,
            self.count as u64 * std::mem::size_of::<VerletState>() as u64,
        )?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }

    /// Uploads the colliders of this frame (at most `MAX_SPHERES`; the rest are dropped
    /// with a warning, the scene loader already rejects more).
    pub fn upload_spheres(&self, queue: &wgpu::Queue, spheres: &[[f32; 4]]) -> u32 {
        let n = spheres.len().min(MAX_SPHERES);
        if n < spheres.len() {
            log::warn!("only the first {MAX_SPHERES} colliders are simulated");
        }
        if n > 0 {
            queue.write_buffer(&self.spheres, 0, bytemuck::cast_slice(&spheres[..n]));
        }
        n as u32
    }

    /// Uploads the colliders' hierarchy of this frame (built from the uploaded spheres).
    pub fn upload_bvh(&self, queue: &wgpu::Queue, nodes: &[BvhNode]) {
        let n = nodes.len().min(2 * MAX_SPHERES);
        if n > 0 {
            queue.write_buffer(
                &self.spheres,
                (BVH_NODE_BASE * 16) as u64,
                bytemuck::cast_slice(&super::bvh::encode(&nodes[..n])),
            );
        }
    }

    /// Reads the blades and their states back from the GPU.
    pub fn read(&self, gpu: &Gpu) -> Result<(Vec<Blade>, Vec<BladeState>)> {
        if self.count == 0 {
            return Ok((Vec::new(), Vec::new()));
        }
        let n = self.count as u64;
        let b = read_buffer(gpu, &self.blades, n * std::mem::size_of::<Blade>() as u64)?;
        let s = read_buffer(
            gpu,
            &self.states,
            n * std::mem::size_of::<BladeState>() as u64,
        )?;
        Ok((
            bytemuck::pod_collect_to_vec(&b),
            bytemuck::pod_collect_to_vec(&s),
        ))
    }

    /// Reads the patch boxes back (blocking).
    pub fn read_patches(&self, gpu: &Gpu) -> Result<Vec<PatchBox>> {
        let n = self.patch_count.max(1) as u64;
        let bytes = read_buffer(
            gpu,
            &self.patches,
            n * std::mem::size_of::<PatchBox>() as u64,
        )?;
        let mut boxes: Vec<PatchBox> = bytemuck::pod_collect_to_vec(&bytes);
        boxes.truncate(self.patch_count as usize);
        Ok(boxes)
    }

    /// Reads the seen flag of every blade back (blocking; `SEEN_*`).
    pub fn read_seen(&self, gpu: &Gpu) -> Result<Vec<u32>> {
        if self.count == 0 {
            return Ok(Vec::new());
        }
        let bytes = read_buffer(gpu, &self.seen, self.count as u64 * 4)?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }

    /// Reads the sun along every blade back (blocking): the two words the deferred
    /// shading's sun pass packs its 8 visibilities into (`render::deferred::sun_at`), as
    /// the last frame that drew the blade left them.
    pub fn read_sun(&self, gpu: &Gpu) -> Result<Vec<[u32; 2]>> {
        if self.count == 0 {
            return Ok(Vec::new());
        }
        let bytes = read_buffer(gpu, &self.sun, self.count as u64 * 8)?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }

    /// Blades reset to their rest pose since the start because the update found their new
    /// state non-finite or absurd (blocking read-back).
    pub fn read_resets(&self, gpu: &Gpu) -> Result<u32> {
        let bytes = read_buffer(gpu, &self.resets, 4)?;
        Ok(bytemuck::pod_read_unaligned(&bytes))
    }

    /// Whether [`BladeBuffers::ensure_trails`] gave the field a trail map (more than the
    /// zeroed header).
    pub fn has_trail_map(&self) -> bool {
        self.trails.size() > 4 * crate::field::trails::HEADER_WORDS as u64
    }

    /// Reads the trail map back, as words (blocks; for tests and the twin comparison).
    pub fn read_trails(&self, gpu: &Gpu) -> Result<Vec<u32>> {
        let bytes = read_buffer(gpu, &self.trails, self.trails.size())?;
        Ok(bytemuck::cast_slice(&bytes).to_vec())
    }

    /// Replaces the blades and states (tests and the CPU/GPU comparison).
    pub fn write(
        &self,
        queue: &wgpu::Queue,
        blades: &[Blade],
        states: &[BladeState],
    ) -> Result<()> {
        if blades.len() != self.count as usize || states.len() != self.count as usize {
            return Err(Error::Invalid(format!(
                "expected {} blades, got {} blades and {} states",
                self.count,
                blades.len(),
                states.len()
            )));
        }
        if self.count > 0 {
            queue.write_buffer(&self.blades, 0, bytemuck::cast_slice(blades));
            queue.write_buffer(&self.states, 0, bytemuck::cast_slice(states));
        }
        Ok(())
    }
}

/// Words of the patch lists: the blade cull's chunks `[count, chunk, ...]`, then the
/// update's two `[count, chunk | rate bits, ...]` (patches with a collider near, and
/// without), room for every [`UPDATE_CHUNK`] blades of each patch in each; then a word per
/// patch (the classes its listed chunks keep) and [`ORDER_STRIDE`] per chunk, which put
/// the cull's lists in a fixed order (`cull_order.wgsl`).
fn list_words(patch_count: u32, patch_size: u32) -> u64 {
    let chunks = list_chunks(patch_count, patch_size);
    3 * (chunks + 1) + u64::from(patch_count) + ORDER_STRIDE * chunks
}

/// Words per listed chunk in the patch lists' order section: its 64 lanes' levels, 2 bits
/// each, and its first slot in each level's list (`cull_order.wgsl`).
pub const ORDER_STRIDE: u64 = 8;

/// Chunks of [`UPDATE_CHUNK`] blades in `patch_count` patches of `patch_size`.
pub fn list_chunks(patch_count: u32, patch_size: u32) -> u64 {
    u64::from(patch_count) * u64::from(patch_size / UPDATE_CHUNK)
}

/// The trail map's buffer of `bytes` (zeroed).
fn trails_buffer(device: &wgpu::Device, bytes: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("sward.trails"),
        size: bytes,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

fn verlet_buffer(device: &wgpu::Device, count: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("sward.blades.verlet"),
        size: count * std::mem::size_of::<VerletState>() as u64,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// The blade update compute pass: one pipeline per blade model over the same bindings.
pub struct UpdatePass {
    /// The pipelines built so far, by (wind sources, blade model): Jahrmann's update, the
    /// Verlet update or CWD-Sim's pose (`BladeModel::id`), each for the wind sources it
    /// reads (`WIND_KINDS` in `wind_sample.wgsl`: a source the scene does not have is
    /// compiled out, since llvmpipe runs both sides of the uniform test for every blade).
    /// Built when a frame first needs one: at most 4 × 3. Each is a pair: the pipeline
    /// over the update list of patches with a collider near, and the one over the list of
    /// those without, compiled without the collisions (`COLLIDE` in `update.wgsl`).
    pipelines: Vec<((u32, u32), [wgpu::ComputePipeline; 2])>,
    /// Which of `pipelines` this frame's step takes (`prepare`).
    current: Option<usize>,
    pipeline_layout: wgpu::PipelineLayout,
    bind_group: wgpu::BindGroup,
    params: wgpu::Buffer,
    /// The patch pass's `PatchDispatch` (the update's arguments follow the cull's).
    dispatch: wgpu::Buffer,
    count: u32,
}

fn storage_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A uniform-buffer layout entry visible to the given stages.
pub fn uniform_entry(binding: u32, visibility: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A bind group entry binding the whole of `buffer`.
pub fn whole(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: buffer.as_entire_binding(),
    }
}

/// A compute-visible storage-buffer layout entry.
pub fn compute_storage_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    storage_entry(binding, read_only)
}

impl UpdatePass {
    /// The uniform buffer of the update's `SimParams` (the billboards read the same wind).
    pub fn params_buffer(&self) -> &wgpu::Buffer {
        &self.params
    }

    /// `wind_grid` is the fluid velocity grid the blades sample (a dummy when unused).
    pub fn new(gpu: &Gpu, buffers: &BladeBuffers, wind_grid: &wgpu::Buffer) -> Self {
        let device = &gpu.device;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.update.layout"),
            entries: &[
                uniform_entry(0, wgpu::ShaderStages::COMPUTE),
                storage_entry(1, false),
                storage_entry(2, false),
                storage_entry(3, true),
                storage_entry(4, true),
                storage_entry(5, true),
                storage_entry(6, true),
                storage_entry(7, false),
                storage_entry(8, false),
                storage_entry(9, false),
            ],
        });
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.update.params"),
            size: std::mem::size_of::<SimParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sward.update.bind_group"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: params.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: buffers.blades.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: buffers.states.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: buffers.spheres.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wind_grid.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 5,
                    resource: buffers.patch_lists.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 6,
                    resource: buffers.patch_spheres.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 7,
                    resource: buffers.resets.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 8,
                    resource: buffers.verlet.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 9,
                    resource: buffers.trails.as_entire_binding(),
                },
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sward.update.pipeline_layout"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        Self {
            pipelines: Vec::new(),
            current: None,
            pipeline_layout,
            bind_group,
            params,
            dispatch: buffers.dispatch.clone(),
            count: buffers.count,
        }
    }

    /// Writes this step's uniforms and makes ready the pipeline of blade model `model`
    /// (`BladeModel::id`) for the wind sources `params` enables.
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        params: &SimParams,
        model: u32,
    ) {
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(params));
        let key = (params.fluid_info[1] & (WIND_ANALYTIC | WIND_FLUID), model.min(2));
        let at = match self.pipelines.iter().position(|(k, _)| *k == key) {
            Some(at) => at,
            None => {
                let (file, name) = [
                    ("update.wgsl", "update"),
                    ("update_verlet.wgsl", "verlet"),
                    ("update_cwd.wgsl", "cwd"),
                ][key.1 as usize];
                let module = shaders::module(device, file);
                let wind = f64::from(key.0);
                // CWD-Sim's pose has no collisions to leave out.
                let collides = key.1 != 2;
                let pipeline = |list: u32| {
                    let kind = ["", "_free"][list as usize];
                    let label = format!("sward.update.{name}{kind}_pipeline.wind{}", key.0);
                    let collide = ("COLLIDE", f64::from(u32::from(list == 0)));
                    let constants = [("WIND_KINDS", wind), ("UPDATE_LIST", f64::from(list)), collide];
                    let n = if collides { 3 } else { 2 };
                    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                        label: Some(&label),
                        layout: Some(&self.pipeline_layout),
                        module: &module,
                        entry_point: Some("main"),
                        compilation_options: wgpu::PipelineCompilationOptions {
                            constants: &constants[..n],
                            ..Default::default()
                        },
                        cache: None,
                    })
                };
                let pipeline = [pipeline(0), pipeline(1)];
                self.pipelines.push((key, pipeline));
                self.pipelines.len() - 1
            }
        };
        self.current = Some(at);
    }

    /// Records the update with the pipeline `prepare` made ready (Verlet needs the
    /// buffers' Verlet states bound when this pass was built), dispatched indirectly over
    /// the patch pass's two update lists (the patch pass must be recorded before).
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, q: PassQueries) {
        let Some((_, pipelines)) = self.current.and_then(|at| self.pipelines.get(at)) else {
            return;
        };
        if self.count == 0 {
            return;
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("sward.update"),
            timestamp_writes: q.compute_writes(),
        });
        q.begin(&mut pass);
        pass.set_bind_group(0, &self.bind_group, &[]);
        for (pipeline, offset) in pipelines.iter().zip(PatchDispatch::UPDATE_OFFSETS) {
            pass.set_pipeline(pipeline);
            pass.dispatch_workgroups_indirect(&self.dispatch, offset);
        }
        q.end(&mut pass);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seven_million_blades_fit_in_one_gib() {
        // The bar (CWD-Sim's 7,000,000 blades): every per-blade and per-patch
        // buffer at the smallest patch size (64 blades, the most patches).
        let blades = 7_000_000u64;
        let bytes = BladeBuffers::bytes_for(blades, blades.div_ceil(64), 64);
        assert!(bytes < 1 << 30, "{bytes} bytes");
        assert_eq!(crate::sim::layout::BYTES_PER_BLADE, 104);
    }
}
