//! `#[repr(C)]` Pod twins of the WGSL structs in `shaders/common.wgsl`. Every struct's size
//! is asserted at compile time so that a field added on one side only fails the build.

use bytemuck::{Pod, Zeroable};

/// Workgroup size of every per-blade compute pass; patches are a multiple of it.
pub const WORKGROUP_SIZE: u32 = 64;
/// Upper bound on sphere colliders uploaded per frame.
pub const MAX_SPHERES: usize = 1024;

/// One blade of grass: the paper's four 4D vectors (Section 4).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct Blade {
    /// v0 (root, fixed) and the direction angle in radians.
    pub v0_dir: [f32; 4],
    /// v1 (middle control point) and the height h.
    pub v1_height: [f32; 4],
    /// v2 (tip, moved by the forces) and the width w.
    pub v2_width: [f32; 4],
    /// Local up vector and the stiffness s.
    pub up_stiffness: [f32; 4],
}

/// Per-blade simulation state beside the blade: the rest tip I_v2 and the collision
/// strength η (the paper keeps η in the fourth channel of its force map).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct BladeState {
    pub rest_eta: [f32; 4],
}

/// A patch's bounding box, already grown by the tallest blade so that it holds every pose.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct PatchBox {
    pub min: [f32; 4],
    pub max: [f32; 4],
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
    pub dt: f32,
    pub time: f32,
    pub mass: f32,
    pub gravity_blend: f32,
    pub collision_decay: f32,
    pub blade_count: u32,
    pub sphere_count: u32,
    /// 1 = sphere collisions on.
    pub collisions: u32,
    /// k of η += k d·d (Eq. 16).
    pub collision_gain: f32,
    /// Ceiling of η.
    pub max_eta: f32,
    /// Multiplies every blade's stiffness (the panel's "stiffness scale").
    pub stiffness_scale: f32,
    pub _pad: f32,
    /// Wind grid: x, z of its corner, cell size, response (force per m/s of air speed).
    pub fluid_grid: [f32; 4],
    /// Wind grid: resolution, source mask (`WIND_ANALYTIC | WIND_FLUID`), 1 = per-cell
    /// sampling (CWD-Sim grouping), unused.
    pub fluid_info: [u32; 4],
}

/// Source-mask bits of `SimParams::fluid_info[1]`.
pub const WIND_ANALYTIC: u32 = 1;
pub const WIND_FLUID: u32 = 2;

/// Uniforms of the cull pass (`shaders/cull.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct CullParams {
    pub view_proj: [[f32; 4]; 4],
    /// xyz: camera position.
    pub camera_pos: [f32; 4],
    pub blade_count: u32,
    pub patch_size: u32,
    /// Bit 0 patches, 1 orientation, 2 frustum, 3 distance.
    pub tests: u32,
    pub distance_levels: u32,
    pub orientation_threshold: f32,
    pub frustum_tolerance: f32,
    pub max_distance: f32,
    /// Indices per blade in the grass mesh (written into the indirect arguments).
    pub index_count: u32,
}

pub const TEST_PATCH: u32 = 1;
pub const TEST_ORIENTATION: u32 = 2;
pub const TEST_FRUSTUM: u32 = 4;
pub const TEST_DISTANCE: u32 = 8;

/// The cull pass's output buffer: the `draw_indexed_indirect` arguments followed by the
/// per-test cull counters, all written with atomics (`DrawArgs` in `cull.wgsl`). The
/// instance count is the number of blades drawn.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq, Eq)]
pub struct CullCounters {
    pub draw: DrawIndexedIndirect,
    pub culled_patch: u32,
    pub culled_orientation: u32,
    pub culled_frustum: u32,
    pub culled_distance: u32,
    pub _pad: [u32; 7],
}

impl CullCounters {
    /// Blades that passed every test.
    pub fn drawn(&self) -> u32 {
        self.draw.instance_count
    }
    /// Blades culled by any test.
    pub fn culled(&self) -> u32 {
        self.culled_patch + self.culled_orientation + self.culled_frustum + self.culled_distance
    }
}

/// Uniforms of every draw pass (`shaders/common.wgsl` `Frame`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct FrameUniforms {
    pub view_proj: [[f32; 4]; 4],
    pub inv_view_proj: [[f32; 4]; 4],
    pub camera_pos: [f32; 4],
    /// xyz: direction towards the sun.
    pub sun_dir: [f32; 4],
    /// x, y: viewport in pixels; z: time; w: fog distance.
    pub viewport_time: [f32; 4],
    /// x: shape id, y: tip threshold τ, z: segments, w: 1 = 3D displacement.
    pub shape: [f32; 4],
    /// x: w_min, y: w_span (0 = off), z: terrain size.
    pub width_correction: [f32; 4],
    /// x: blade colour mode (0 natural, 1 by distance level, 2 by patch), y: distance
    /// levels n, z: d_max, w: blades per patch.
    pub debug: [f32; 4],
}

/// `draw_indexed_indirect` arguments, as wgpu reads them.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq, Eq)]
pub struct DrawIndexedIndirect {
    pub index_count: u32,
    pub instance_count: u32,
    pub first_index: u32,
    pub base_vertex: i32,
    pub first_instance: u32,
}

const _: () = assert!(std::mem::size_of::<Blade>() == 64);
const _: () = assert!(std::mem::size_of::<BladeState>() == 16);
const _: () = assert!(std::mem::size_of::<PatchBox>() == 32);
const _: () = assert!(std::mem::size_of::<SimParams>() == 176);
const _: () = assert!(std::mem::size_of::<CullParams>() == 112);
const _: () = assert!(std::mem::size_of::<CullCounters>() == 64);
const _: () = assert!(std::mem::size_of::<FrameUniforms>() == 224);
const _: () = assert!(std::mem::size_of::<DrawIndexedIndirect>() == 20);

/// GPU bytes per blade: the blade, its state and its slot in the visible-index list.
pub const BYTES_PER_BLADE: usize =
    std::mem::size_of::<Blade>() + std::mem::size_of::<BladeState>() + std::mem::size_of::<u32>();
