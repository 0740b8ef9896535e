//! `#[repr(C)]` Pod twins of the WGSL structs in `shaders/common.wgsl`. Every struct's size
//! is asserted at compile time so that a field added on one side only fails the build.

use bytemuck::{Pod, Zeroable};

pub use crate::field::blade::{Blade, BladeState, PatchBox, WORKGROUP_SIZE};

pub use crate::scene::limits::MAX_SPHERES;
/// Where the colliders' hierarchy starts in the spheres buffer, in `vec4`s: node k is the two
/// `vec4`s at `BVH_NODE_BASE + 2k` (`sim::bvh::encode`). One buffer for both keeps the cull
/// pass within the eight storage buffers per stage of the WebGPU defaults.
pub const BVH_NODE_BASE: usize = MAX_SPHERES;
/// Bytes of the spheres buffer: the spheres, then up to `2 · MAX_SPHERES` nodes.
pub const SPHERE_BUFFER_BYTES: u64 = (MAX_SPHERES * 16 + 2 * MAX_SPHERES * 32) as u64;
/// u32 slots per patch in the collision broad phase's lists: a count, then up to
/// `PATCH_SPHERE_STRIDE - 1` sphere indices. A longer flat list keeps its count in the first
/// slot and its start in the second, its indices in the shared pool of
/// [`PATCH_SPHERE_POOL`] entries after every patch's slots; when the pool is full the count
/// is `SPHERES_ALL` and the patch tests every sphere. With the hierarchy, a list of more
/// than `PATCH_SPHERE_STRIDE - 1` nodes is `SPHERES_ALL`: the blades walk from the root.
pub const PATCH_SPHERE_STRIDE: u32 = 64;
/// Entries of the broad phase's shared pool for flat lists longer than a patch's slots
/// (1 MiB: a thousand patches under a thousand-sphere packing, eight times the nature
/// scene's need).
pub const PATCH_SPHERE_POOL: u32 = 1 << 18;
/// `CullParams::collide[1]` bit: the blades walk the colliders' hierarchy (bit 0:
/// collisions on).
pub const COLLIDE_HIERARCHY: u32 = 2;

/// Blades per instance of the grass draw (`DRAW_BATCH` in `common.wgsl`). One instance per
/// blade costs a software rasteriser a whole pass through its vertex pipeline per blade
/// (llvmpipe: ~17 µs each, most of the grass draw); an instance of 32 blades amortises it.
/// Divides 64, so a level's region (a multiple of 64) holds whole batches.
pub const DRAW_BATCH: u32 = 32;
/// Blades per entry of the update list, one workgroup of the update (`CHUNK` in
/// `thin_order.wgsl`).
pub const UPDATE_CHUNK: u32 = 64;
/// An update list entry's rate bits (`cull.wgsl`): the chunk of a throttled patch, and a
/// thinned chunk of a patch stepped every frame.
pub const CHUNK_THROTTLED: u32 = 0x8000_0000;
/// See [`CHUNK_THROTTLED`].
pub const CHUNK_THINNED: u32 = 0x4000_0000;
/// Count value of a patch whose spheres did not fit its list.
pub const SPHERES_ALL: u32 = u32::MAX;

/// The Verlet blade's state beside the blade (`VerletState` in `common.wgsl`; only
/// allocated for `physics.model: Verlet`): P2, the cubic's second inner control point (P1
/// and P3 are the blade's v1 and v2), with the Δt of the last step (0: never stepped), and
/// the previous positions of P1, P2 and P3, whose w hold the root (x, y, z) the state
/// belongs to (a tile generated into the slot, or a carried root, is recognised by it).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct VerletState {
    /// xyz: the control point P2 (world metres), w: Δt of the last step in seconds (0: never
    /// stepped).
    pub p2_dt: [f32; 4],
    /// xyz: P1 (the blade's v1) at the previous step, w: the owning root's x.
    pub o1_x: [f32; 4],
    /// xyz: P2 at the previous step, w: the owning root's y.
    pub o2_y: [f32; 4],
    /// xyz: P3 (the blade's v2) at the previous step, w: the owning root's z.
    pub o3_z: [f32; 4],
}

/// Uniforms of the blade update (`shaders/update.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct SimParams {
    /// xyz: normalised gravity direction D, w: acceleration D_w.
    pub gravity_dir: [f32; 4],
    /// xyz: gravity centre C, w: acceleration C_w.
    pub gravity_center: [f32; 4],
    /// x, y: direction in the x/z plane, z: strength, w: gust amplitude (0 strength = off).
    pub wind_dir: [f32; 4],
    /// x: wave length, y: wave speed.
    pub wind_wave: [f32; 4],
    /// xyz: point source position, w: strength (0 = off).
    pub point_wind: [f32; 4],
    /// x: radius, y: pulse frequency.
    pub point_wind_shape: [f32; 4],
    /// Δt of this step in seconds (already clamped).
    pub dt: f32,
    /// Scene time in seconds; drives the analytic wind's gusts and the point source's pulse.
    pub time: f32,
    /// Blade mass m of Eq. 4 (scales the gravity force).
    pub mass: f32,
    /// Blend t of Eq. 4 between the gravity direction (0) and the gravity centre (1).
    pub gravity_blend: f32,
    /// Decrease a of the collision strength η per second (Eq. 2).
    pub collision_decay: f32,
    /// Blades in the blade buffer; invocations at or past it do nothing.
    pub blade_count: u32,
    /// Collision spheres uploaded this step.
    pub sphere_count: u32,
    /// 1 = sphere collisions on.
    pub collisions: u32,
    /// k of η += k d·d (Eq. 16).
    pub collision_gain: f32,
    /// Ceiling of η.
    pub max_eta: f32,
    /// Multiplies every blade's stiffness (the panel's "stiffness scale").
    pub stiffness_scale: f32,
    /// Δt of a throttled patch's update (it runs every `physics_throttle` frames).
    pub throttled_dt: f32,
    /// Wind grid: x, z of its corner, cell size, response (force per m/s of air speed).
    pub fluid_grid: [f32; 4],
    /// Wind grid: resolution, source mask (`WIND_ANALYTIC | WIND_FLUID`), 1 = per-cell
    /// sampling (CWD-Sim grouping), layers (1 = 2D).
    pub fluid_info: [u32; 4],
    /// Blades per patch (the update walks the patch list).
    pub patch_size: u32,
    /// Patches in the field (the update list starts at `patch_count + 1`).
    pub patch_count: u32,
    /// Wind grid: thickness of a layer in metres (3D grids).
    pub fluid_layer_height: f32,
    /// Eq. 20's n (`culling.distance_levels`, at least 1): the update steps each patch's
    /// blades in this class order (`sim::reference::thin_order`).
    pub distance_levels: u32,
    /// Collision hierarchy (`sim::bvh`): the camera's x, y, z and the distance within which
    /// the walk goes down to the colliders.
    pub bvh_camera: [f32; 4],
    /// Collision hierarchy: 1 = walk it (else the patch lists), nodes, the tree's depth,
    /// unused.
    pub bvh_info: [u32; 4],
    /// The blade model (`BladeModel::id`: 0 Jahrmann, 1 Verlet, 2 Cwd), the Verlet
    /// damping (1/s), the Cwd cell size (m) when the fluid is off, the Verlet wind gain.
    pub model: [f32; 4],
    /// CWD-Sim's k1, k2, λ and F (Eq. 11–13).
    pub cwd: [f32; 4],
    /// Grass-to-grass propagation's grid (`sim::propagation`): the x, z of its corner, the
    /// cell size, att.
    pub propagation: [f32; 4],
    /// Propagation: cells per side (0: off), generations, unused, unused.
    pub propagation_info: [u32; 4],
}

/// Source-mask bits of `SimParams::fluid_info[1]`.
pub const WIND_ANALYTIC: u32 = 1;
/// Source-mask bit of `SimParams::fluid_info[1]`: the blades feel the fluid grid's wind.
pub const WIND_FLUID: u32 = 2;

/// Number of level-of-detail buckets the cull pass sorts visible blades into.
pub const LOD_LEVELS: usize = 3;

/// Uniforms of the patch and cull passes (`shaders/cull.wgsl`), read by the grass vertex
/// shader too (its level-of-detail morph uses the same camera and thresholds).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct CullParams {
    /// View-projection matrix of the culling camera (world to clip, column-major).
    pub view_proj: [[f32; 4]; 4],
    /// xyz: camera position.
    pub camera_pos: [f32; 4],
    /// Blades in the blade buffer; invocations at or past it do nothing.
    pub blade_count: u32,
    /// Blades per patch (a multiple of 64, the workgroup size).
    pub patch_size: u32,
    /// `TEST_*` bits.
    pub tests: u32,
    /// Number of distance levels n of Eq. 20 (the distance test's thinning steps).
    pub distance_levels: u32,
    /// A blade is culled as edge-on when |view direction · width direction| exceeds this
    /// (Eq. 17; 0 to 1).
    pub orientation_threshold: f32,
    /// Tolerance t of Eq. 18, in clip-space units of w: how far outside the frustum a
    /// blade's points may be and still count as inside.
    pub frustum_tolerance: f32,
    /// d_max of Eq. 20 in metres: the distance test culls every blade beyond it.
    pub max_distance: f32,
    /// Patches in the field (the patch pass's invocations).
    pub patch_count: u32,
    /// Indices of each level's blade mesh (near, middle, far).
    pub lod_index_count: [u32; 4],
    /// First index of each level's mesh in the shared blade index buffer.
    pub lod_first_index: [u32; 4],
    /// Segments (rows of quads) of each level's mesh.
    pub lod_segments: [u32; 4],
    /// x: pixels per metre at 1 m (viewport height / (2 tan(fov/2))), y: projected blade
    /// height in pixels at and above which level 0 draws, z: the same for level 1, w: the
    /// morph band as a fraction of a threshold (a blade morphs towards the coarser mesh
    /// while its projected height falls from `threshold * (1 + w)` to `threshold`).
    pub lod: [f32; 4],
    /// Patches outside the view and beyond `physics_radius` are updated every
    /// `physics_throttle` frames (0 or 1: every frame).
    pub physics_throttle: u32,
    /// Frame number, picks which throttled patches update this frame.
    pub frame: u32,
    /// Metres around the camera where every patch updates every frame.
    pub physics_radius: f32,
    /// Occlusion bias as a fraction of the view distance.
    pub occlusion_bias: f32,
    /// Depth pyramid: width, height, mip levels, 1 = valid this frame.
    pub hiz: [u32; 4],
    /// x: near plane, y: far plane of the culling camera, z: the grass-occlusion test's
    /// bias (a fraction of the view distance, like `occlusion_bias`).
    pub clip: [f32; 4],
    /// Collision broad phase: sphere count; bit 0 collisions on, bit 1
    /// ([`COLLIDE_HIERARCHY`]) the blades walk the hierarchy; the tree's node count (0: no
    /// tree); its depth.
    pub collide: [u32; 4],
    /// The hierarchy's precision camera (xyz) and the distance within which it is exact
    /// (w), as `SimParams::bvh_camera`.
    pub bvh: [f32; 4],
}

/// `CullParams::tests` bit: cull whole patches whose box is outside the frustum, beyond the
/// distance test's reach (with [`TEST_DISTANCE`]) or hidden in the depth pyramid (with
/// [`TEST_OCCLUSION`]).
pub const TEST_PATCH: u32 = 1;
/// `CullParams::tests` bit: cull blades seen edge-on (Eq. 17).
pub const TEST_ORIENTATION: u32 = 2;
/// `CullParams::tests` bit: cull blades outside the view frustum (Eq. 18).
pub const TEST_FRUSTUM: u32 = 4;
/// `CullParams::tests` bit: thin out blades with distance from the camera (Eq. 19–20).
pub const TEST_DISTANCE: u32 = 8;
/// `CullParams::tests` bit: cull blades hidden behind opaque objects (terrain, colliders)
/// in the depth pyramid.
pub const TEST_OCCLUSION: u32 = 16;
/// Grass hides grass: blades not seen last frame wait for a late test against a pyramid
/// that includes the grass drawn early (needs first-instance indirect draws).
pub const TEST_GRASS_OCCLUSION: u32 = 32;

/// `BladeBuffers::seen` per blade: hidden or culled when last tested.
pub const SEEN_NO: u32 = 0;
/// Visible when last tested: drawn early next frame.
pub const SEEN_YES: u32 = 1;
/// Within a frame: drawn by the early draw, to be tested again by the late pass.
pub const SEEN_DRAWN_EARLY: u32 = 2;
/// Within a frame: passed the early tests but was not seen last frame; the late pass
/// draws it unless the grass drawn early hides it.
pub const SEEN_CANDIDATE: u32 = 3;

/// `dispatch_workgroups_indirect` arguments.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq, Eq)]
pub struct DispatchIndirect {
    /// Workgroups along x.
    pub x: u32,
    /// Workgroups along y.
    pub y: u32,
    /// Workgroups along z.
    pub z: u32,
}

/// The cull pass's output buffer: one `draw_indexed_indirect` argument block per level of
/// detail followed by the counters, all written with atomics (`CullOutput` in
/// `cull.wgsl`). An instance draws a batch of [`DRAW_BATCH`] blades; the blade counts are
/// `blades` and `late_blades`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq, Eq)]
pub struct CullCounters {
    /// The early draws (blades seen last frame, or every survivor with grass occlusion
    /// off): `blades[k]` blades in `ceil(blades[k] / DRAW_BATCH)` instances.
    pub draws: [DrawIndexedIndirect; LOD_LEVELS],
    /// The late draws: blades not seen last frame that no grass drawn early hides. Each
    /// starts in its level's region at the first whole batch after the early blades.
    pub late_draws: [DrawIndexedIndirect; LOD_LEVELS],
    /// Patches that passed the frustum and occlusion tests.
    pub visible_patches: u32,
    /// Patches whose blades were updated this frame (visible, near or on their turn).
    pub updated_patches: u32,
    /// Of those, patches updated at the throttled rate.
    pub throttled_patches: u32,
    /// Blades in patches outside the view frustum (the patch test).
    pub culled_patch: u32,
    /// Blades culled as seen edge-on (the orientation test).
    pub culled_orientation: u32,
    /// Blades culled by the per-blade frustum test.
    pub culled_frustum: u32,
    /// Blades culled by the distance test, whole patches beyond its reach included.
    pub culled_distance: u32,
    /// Blades culled as hidden: by opaque objects (whole patches or single blades) or by grass
    /// drawn early.
    pub culled_occlusion: u32,
    /// Blades in patches culled by occlusion (part of `culled_occlusion`).
    pub culled_occlusion_patch: u32,
    /// Patch-sphere pairs the update tests this frame, after the per-patch broad phase
    /// (times the patch size: blade-sphere tests).
    pub patch_sphere_pairs: u32,
    /// Blades hidden by grass drawn early (part of `culled_occlusion`).
    pub culled_occlusion_grass: u32,
    /// Blades in each level's early list.
    pub blades: [u32; LOD_LEVELS],
    /// Blades in each level's late list.
    pub late_blades: [u32; LOD_LEVELS],
    /// Entries of the broad phase's shared pool taken this frame (at most
    /// [`PATCH_SPHERE_POOL`] are used).
    pub pool_used: u32,
    /// Bit s set: sphere s is on some stepped patch's list.
    pub spheres_used: [u32; MAX_SPHERES / 32],
    /// The gusts' bend at the edge of the blades' reach, for the far levels' shading
    /// waves (`far_grass.wgsl`): the sum over the blades drawn early from half the blade
    /// radius out of `clamp(1.5 |v2 - rest tip| / h, 0, 1)` in 1/1024ths, and their count.
    pub wave_sum: u32,
    /// Blades summed into `wave_sum`.
    pub wave_blades: u32,
    /// Chunks of [`UPDATE_CHUNK`] blades the update stepped this frame.
    pub updated_chunks: u32,
    /// Of those, chunks stepped at the throttled rate: a throttled patch's, or a chunk of
    /// classes Eq. 20 thins out everywhere in a patch stepped every frame.
    pub throttled_chunks: u32,
    /// Chunks of [`UPDATE_CHUNK`] blades the blade cull tested: the visible patches' less
    /// the classes Eq. 20 culls in every blade of the patch (counted as distance whole).
    pub visible_chunks: u32,
    /// Of the update's chunks, those of patches whose broad phase found a collider near
    /// (stepped with collisions) and those of the others (stepped without).
    pub collide_chunks: u32,
    /// See [`CullCounters::collide_chunks`].
    pub free_chunks: u32,
}

/// The fixed point of [`CullCounters::wave_sum`]: each blade adds its bend in 1/1024ths
/// (twin of the 1024 in `count_wave`, cull.wgsl, and `mean_wave`, far_grass.wgsl).
pub const WAVE_QUANTA: f32 = 1024.0;

/// Byte offset of [`CullCounters::wave_sum`] (the draw copies the two wave words from
/// there into the far levels' buffer).
pub const WAVE_OFFSET: u64 = std::mem::offset_of!(CullCounters, wave_sum) as u64;

// Arrays of more than 32 have no derived Default.
impl Default for CullCounters {
    fn default() -> Self {
        Zeroable::zeroed()
    }
}

impl CullCounters {
    /// Where a level's late list starts in its region after `early` early blades: at the
    /// next whole batch, so that the late draw's instances are whole batches too.
    pub fn late_start(early: u32) -> u32 {
        early.div_ceil(DRAW_BATCH) * DRAW_BATCH
    }
    /// Blades that passed every test (early and late).
    pub fn drawn(&self) -> u32 {
        self.per_level().iter().sum()
    }
    /// Blades drawn at each level of detail (early and late).
    pub fn per_level(&self) -> [u32; LOD_LEVELS] {
        std::array::from_fn(|k| self.blades[k] + self.late_blades[k])
    }
    /// Blades drawn late (not seen last frame, not hidden by the grass drawn early).
    pub fn drawn_late(&self) -> u32 {
        self.late_blades.iter().sum()
    }
    /// Spheres on at least one stepped patch's collision list.
    pub fn spheres_considered(&self) -> u32 {
        self.spheres_used.iter().map(|w| w.count_ones()).sum()
    }
    /// Blades culled by any test.
    pub fn culled(&self) -> u32 {
        self.culled_patch
            + self.culled_orientation
            + self.culled_frustum
            + self.culled_distance
            + self.culled_occlusion
    }
}

/// The patch pass's indirect dispatches: the blade cull over visible patches and the
/// update over updated patches (2D, so that no dimension passes the 65,535 limit).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq, Eq)]
pub struct PatchDispatch {
    /// Workgroups of the blade cull over the visible patches.
    pub cull: DispatchIndirect,
    /// Workgroups of the blade update over the chunks stepped this frame whose patch has a
    /// collider near.
    pub update: DispatchIndirect,
    /// Workgroups of the blade update (its pipeline without collisions) over the chunks
    /// stepped this frame whose patch has no collider near.
    pub update_free: DispatchIndirect,
    /// Workgroups of the pass that puts the cull's drawn blades at their slots, one
    /// invocation per listed chunk (`cull_order.wgsl`).
    pub order: DispatchIndirect,
}

impl PatchDispatch {
    /// Byte offsets of the two update dispatches, in the order of the update's pipelines
    /// (`UPDATE_LIST` 0, with collisions, and 1, without): the update and the
    /// propagation's apply each walk both lists.
    pub const UPDATE_OFFSETS: [u64; 2] = [
        std::mem::offset_of!(PatchDispatch, update) as u64,
        std::mem::offset_of!(PatchDispatch, update_free) as u64,
    ];
}

/// Uniforms of every draw pass (`shaders/common.wgsl` `Frame`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct FrameUniforms {
    /// View-projection matrix of the camera (world to clip, column-major).
    pub view_proj: [[f32; 4]; 4],
    /// Inverse of `view_proj` (clip to world).
    pub inv_view_proj: [[f32; 4]; 4],
    /// xyz: camera position in world metres, w: 1.
    pub camera_pos: [f32; 4],
    /// xyz: direction towards the sun.
    pub sun_dir: [f32; 4],
    /// x, y: viewport in pixels; z: time; w: fog distance.
    pub viewport_time: [f32; 4],
    /// x: shape id, y: tip threshold τ, z: segments, w: 1 = 3D displacement.
    pub shape: [f32; 4],
    /// x: w_min, y: w_span (0 = off), z: terrain size.
    pub width_correction: [f32; 4],
    /// x: blade colour mode (0 natural, 1 by level of detail, 2 by patch), y: self-shadow
    /// mode (0 sward's height shading, 1 CWD-Sim Eq. 14, 2 off), z: the shadow radius of
    /// the grass in a cascade's shadow pass (0: a camera pass), w: blades per patch.
    pub debug: [f32; 4],
    /// CWD-Sim's Eq. 14 parameters: m_min, m_max, c1, c2.
    pub self_shadow: [f32; 4],
    /// Eq. 20's thinning as the cull applies it, so that the blades it keeps widen to keep
    /// the coverage of those it drops: xyz the culling camera, w the distance levels n (0:
    /// no thinning).
    pub thinning: [f32; 4],
    /// x: the thinning's d_max (m); y: the radius the billboards are drawn to (m; 0
    /// without them): the thinned blades they stand among are drawn from part way up
    /// (`render::thinning::root`); zw unused.
    pub thinning_reach: [f32; 4],
}

/// The light of the lit passes (`LightUniforms` in `shaders/light.wgsl`): the sun's
/// cascades, its colour and the sky's, Preetham's coefficients, exposure and tone mapping,
/// and the blade shading strengths (see the WGSL struct for each field).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct LightUniforms {
    /// Light-space view-projection of each shadow cascade (world to [-1, 1]² × [0, 1]).
    pub cascades: [[[f32; 4]; 4]; 4],
    /// Far distance of each cascade from the camera, in metres.
    pub splits: [f32; 4],
    /// World size in metres of one shadow-map texel of each cascade.
    pub texel_world: [f32; 4],
    /// x: 1 = shadows on, y: cascade count, z: filter radius (texels), w: bias (texels).
    pub shadow: [f32; 4],
    /// x: 1 / shadow-map resolution, y: the resolution, z: distance (m) where the shadows
    /// start to fade, w: unused.
    pub shadow_map: [f32; 4],
    /// rgb: the sun's radiance reaching the ground, w: the exposure multiplier 2^EV.
    pub sun: [f32; 4],
    /// rgb: the sky's irradiance on a horizontal surface over π, w: the tone mapper (0 ACES,
    /// 1 AgX, 2 clamp).
    pub ambient: [f32; 4],
    /// x: sky model (0 Preetham, 1 gradient), y: turbidity, z: cosine of the sun disk's
    /// radius, w: the sun disk's radiance over the sun's.
    pub sky: [f32; 4],
    /// Perez coefficients A to E (`perez_a` .. `perez_e`), each for luminance Y (x) and
    /// chromaticity x (y) and y (z).
    pub perez: [[f32; 4]; 5],
    /// The zenith's Y, x and y, each over its Perez F(0, θ_s); w: θ_s, the sun's zenith
    /// angle.
    pub zenith: [f32; 4],
    /// Blade shading strengths (`shading_a`, `shading_b`): rounded normal, translucency,
    /// specular, ambient occlusion; colour variation, wind waves, canopy leaf area (m²/m²),
    /// the shortest blade's height over the tallest's (the canopy's height spread,
    /// `render::light::canopy`).
    pub shading: [[f32; 4]; 2],
    /// The blades' widths (m) Eq. 24's share of quads is taken at (`drawn_quad_share` in
    /// far_grass.wgsl): x and y the quartiles of the field's widths; zw unused.
    pub canopy_widths: [f32; 4],
    /// The mean v at each depth into the canopy's leaf area (`render::light::canopy`,
    /// `drawn_canopy_v` in far_grass.wgsl), a vector per depth over the shares of quads.
    pub canopy: [[f32; 4]; 32],
}

/// `draw_indexed_indirect` arguments, as wgpu reads them.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq, Eq)]
pub struct DrawIndexedIndirect {
    /// Indices per instance: the level's mesh, which holds a batch of blade meshes.
    pub index_count: u32,
    /// Instances to draw, one per batch of [`DRAW_BATCH`] blades.
    pub instance_count: u32,
    /// First index of the level's mesh in the shared index buffer.
    pub first_index: u32,
    /// Added to each index before the vertex is fetched (the cull pass writes 0).
    pub base_vertex: i32,
    /// Instance index of the first batch (where the level's region starts; the late draws
    /// start after the early batches).
    pub first_instance: u32,
}

const _: () = assert!(std::mem::size_of::<Blade>() == 64);
const _: () = assert!(std::mem::size_of::<BladeState>() == 16);
const _: () = assert!(std::mem::size_of::<VerletState>() == 64);
const _: () = assert!(std::mem::size_of::<PatchBox>() == 32);
const _: () = assert!(std::mem::size_of::<SimParams>() == 288);
const _: () = assert!(std::mem::size_of::<CullParams>() == 256);
const _: () = assert!(std::mem::size_of::<CullCounters>() == 220 + MAX_SPHERES / 8);
// `DrawnBlades.head` in common.wgsl skips this many words.
const _: () = assert!(std::mem::offset_of!(CullCounters, blades) == 41 * 4);
const _: () = assert!(std::mem::size_of::<PatchDispatch>() == 48);
const _: () = assert!(std::mem::size_of::<FrameUniforms>() == 272);
const _: () = assert!(std::mem::size_of::<LightUniforms>() == 496 + 16 + 512);
const _: () = assert!(std::mem::size_of::<DrawIndexedIndirect>() == 20);

/// GPU bytes per blade: the blade, its state, its slot in each level's visible-index list,
/// its seen flag and the sun along it (two words).
pub const BYTES_PER_BLADE: usize = std::mem::size_of::<Blade>()
    + std::mem::size_of::<BladeState>()
    + LOD_LEVELS * std::mem::size_of::<u32>()
    + 3 * std::mem::size_of::<u32>();
