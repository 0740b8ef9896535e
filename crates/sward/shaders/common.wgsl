// Shared structs and helpers, included by the entry files with `//!include common.wgsl`.
// Every struct has a #[repr(C)] twin in src/sim/layout.rs with a size assertion.

struct Blade {
    v0_dir: vec4<f32>,        // root v0, direction angle
    v1_height: vec4<f32>,     // middle control point v1, height h
    v2_width: vec4<f32>,      // tip v2, width w
    up_stiffness: vec4<f32>,  // local up, stiffness s
}

// A blade's control points as the last frame drew them (TAA's grass motion, `taa.wgsl`;
// copied by `taa_prev.wgsl`): v0 (and the direction, which tells a new blade in the slot),
// v1 and v2.
struct PrevBlade {
    v0_dir: vec4<f32>,
    v1_height: vec4<f32>,
    v2_width: vec4<f32>,
}

struct BladeState {
    rest_eta: vec4<f32>,      // rest tip I_v2, collision strength eta
}

// min.w: 1 for an empty patch; max.w: the smallest up.y of its blades.
struct PatchBox {
    min: vec4<f32>,
    max: vec4<f32>,
}

struct SimParams {
    gravity_dir: vec4<f32>,
    gravity_center: vec4<f32>,
    wind_dir: vec4<f32>,
    wind_wave: vec4<f32>,
    point_wind: vec4<f32>,
    point_wind_shape: vec4<f32>,
    dt: f32,
    time: f32,
    mass: f32,
    gravity_blend: f32,
    collision_decay: f32,
    blade_count: u32,
    sphere_count: u32,
    collisions: u32,
    collision_gain: f32,
    max_eta: f32,
    stiffness_scale: f32,
    throttled_dt: f32,
    fluid_grid: vec4<f32>,
    fluid_info: vec4<u32>,
    patch_size: u32,
    patch_count: u32,
    fluid_layer_height: f32,
    // Eq. 20's n: the update steps each patch's blades in its class order (thin_order.wgsl).
    distance_levels: u32,
    // Collision hierarchy: camera x, y, z, exact-walk distance; on, nodes, depth, unused.
    bvh_camera: vec4<f32>,
    bvh_info: vec4<u32>,
    // Blade model id (MODEL_*), Verlet damping, Cwd cell size, Verlet wind gain.
    model: vec4<f32>,
    // CWD-Sim's k1, k2, lambda, F.
    cwd: vec4<f32>,
    // Propagation grid: corner x, z, cell size, att; cells per side (0: off), generations.
    propagation: vec4<f32>,
    propagation_info: vec4<u32>,
}

// The Verlet blade's state beside the blade (`sim::layout::VerletState`): P2, the cubic's
// second inner control point (P1 and P3 are the blade's v1 and v2), with the Δt of the
// last step (0: never stepped), and the previous positions of P1, P2 and P3, whose w hold
// the root (x, y, z) the state belongs to.
struct VerletState {
    p2_dt: vec4<f32>,
    o1_x: vec4<f32>,
    o2_y: vec4<f32>,
    o3_z: vec4<f32>,
}

// Whether a Verlet state belongs to the blade rooted at v0 and has been stepped.
fn verlet_owned(s: VerletState, v0: vec3<f32>) -> bool {
    return s.p2_dt.w > 0.0 && all(vec3<f32>(s.o1_x.w, s.o2_y.w, s.o3_z.w) == v0);
}

// `SimParams::model.x`: the blade model (`BladeModel::id`).
const MODEL_JAHRMANN: u32 = 0u;
const MODEL_VERLET: u32 = 1u;
const MODEL_CWD: u32 = 2u;

struct CullParams {
    view_proj: mat4x4<f32>,
    camera_pos: vec4<f32>,
    blade_count: u32,
    patch_size: u32,
    tests: u32,
    distance_levels: u32,
    orientation_threshold: f32,
    frustum_tolerance: f32,
    max_distance: f32,
    patch_count: u32,
    lod_index_count: vec4<u32>,
    lod_first_index: vec4<u32>,
    lod_segments: vec4<u32>,
    // x: px per metre at 1 m, y: level-0 threshold px, z: level-1 threshold px, w: morph band.
    lod: vec4<f32>,
    physics_throttle: u32,
    frame: u32,
    physics_radius: f32,
    occlusion_bias: f32,
    // Depth pyramid: width, height, levels, valid.
    hiz: vec4<u32>,
    // x: near, y: far.
    clip: vec4<f32>,
    // Collision broad phase: x sphere count, y bit 0 collisions on and bit 1
    // (COLLIDE_HIERARCHY) the blades walk the hierarchy, z the tree's node count (0: no
    // tree), w its depth.
    collide: vec4<u32>,
    // The hierarchy's precision camera (xyz) and exact distance (w).
    bvh: vec4<f32>,
}

// Slots per patch in the broad phase's sphere lists (count + indices; a longer flat list
// has its count here, its start in the shared pool in the next slot), the pool's entries
// after the slots, and the count of a patch whose list found the pool full (it tests every
// sphere; with the hierarchy, a list of more than PATCH_SPHERE_STRIDE - 1 nodes: the
// blades walk from the root). PATCH_SPHERE_STRIDE, PATCH_SPHERE_POOL in Rust.
const PATCH_SPHERE_STRIDE: u32 = 64u;
const PATCH_SPHERE_POOL: u32 = 262144u;
const SPHERES_ALL: u32 = 0xffffffffu;
// CullParams.collide.y: the blades walk the colliders' hierarchy (COLLIDE_HIERARCHY in Rust).
const COLLIDE_HIERARCHY: u32 = 2u;
// Words of CullCounters.spheres_used (MAX_SPHERES / 32) and where the hierarchy's nodes
// start in the spheres buffer (BVH_NODE_BASE in Rust).
const SPHERE_WORDS: u32 = 512u;
const BVH_NODE_BASE: u32 = 16384u;

// Blades per instance of the grass draw (DRAW_BATCH in Rust): each level's mesh is this
// many copies of its blade mesh. A level's visible region is a multiple of it.
const DRAW_BATCH: u32 = 32u;
// Vertices per blade of the shadow casters' mesh: the root's corners and the tip
// (`mesh::CASTER_VERTICES` in Rust).
const CASTER_VERTICES: u32 = 3u;

// A blade's `seen` state (SEEN_* in Rust): the cull's two-phase occlusion test keeps it,
// the tile generation starts a new tile's blades at SEEN_YES.
const SEEN_NO: u32 = 0u;
const SEEN_YES: u32 = 1u;
const SEEN_DRAWN_EARLY: u32 = 2u;
const SEEN_CANDIDATE: u32 = 3u;

// What the grass draw reads of the cull's output (the whole buffer, bound read-only): how
// many blades each level's early and late lists hold (`CullOutput.blades`, `late_blades`),
// so that the slots past a list's end in its last batch draw nothing.
struct DrawnBlades {
    // CullOutput's draw arguments and counters before the blade counts
    // (offset_of!(CullCounters, blades) / 4 in Rust).
    head: array<u32, 41>,
    early: array<u32, 3>,
    late: array<u32, 3>,
}

// Where a level's late list starts in its region after `early` early blades: at the next
// whole batch (CullCounters::late_start in Rust).
fn late_start(early: u32) -> u32 {
    return (early + DRAW_BATCH - 1u) / DRAW_BATCH * DRAW_BATCH;
}

// a / b, exactly, for a + 1/2 < 2^23 and b > 0, in float: a software rasteriser has no
// vector integer division and divides lane by lane, where a float vector divides in one
// instruction. (a + 1/2) / b lies at least 1 / (2b) from the nearest integers, and the
// float quotient's rounding error, at most (a + 1/2) / b times 2^-24, is smaller than that
// while a + 1/2 < 2^23, so truncating it gives the integer quotient.
fn div_small(a: u32, b: u32) -> u32 {
    return u32((f32(a) + 0.5) / f32(b));
}

// Projected height in pixels of a blade of `height` whose root is at `v0`: the measure the
// level of detail is chosen by (cull) and morphed by (grass vertex shader).
fn projected_height(v0: vec3<f32>, height: f32, p: CullParams) -> f32 {
    let d = max(distance(v0, p.camera_pos.xyz), 1e-3);
    return height * p.lod.x / d;
}

// Level of detail for a projected height: 0 at and above lod.y, 1 at and above lod.z, else 2.
fn lod_level(h_px: f32, p: CullParams) -> u32 {
    if h_px >= p.lod.y {
        return 0u;
    }
    if h_px >= p.lod.z {
        return 1u;
    }
    return 2u;
}

struct Frame {
    view_proj: mat4x4<f32>,
    inv_view_proj: mat4x4<f32>,
    camera_pos: vec4<f32>,
    sun_dir: vec4<f32>,
    viewport_time: vec4<f32>,
    shape: vec4<f32>,
    width_correction: vec4<f32>,
    debug: vec4<f32>,
    // CWD-Sim Eq. 14: m_min, m_max, c1, c2 (debug.y = 1).
    self_shadow: vec4<f32>,
    // Eq. 20's thinning as the cull applies it: xyz the culling camera, w the distance
    // levels n (0: no thinning); thinning_reach.x its d_max, y the radius the cards are
    // drawn to (m; 0 without cards: `thinned_root_at`).
    thinning: vec4<f32>,
    thinning_reach: vec4<f32>,
}

const TAU: f32 = 6.283185307179586;

// Luminance weights (Rec. 709) of linear radiance.
const LUMA: vec3<f32> = vec3<f32>(0.2126, 0.7152, 0.0722);

// Width direction and front direction of a blade from its up vector and direction angle;
// the twin of `reference::blade_frame`.
fn blade_frame(up: vec3<f32>, angle: f32) -> array<vec3<f32>, 2> {
    var reference = vec3<f32>(0.0, 0.0, 1.0);
    if abs(up.z) > 0.99 {
        reference = vec3<f32>(1.0, 0.0, 0.0);
    }
    let tx = normalize(cross(up, reference));
    let tz = cross(tx, up);
    let width_dir = tx * cos(angle) + tz * sin(angle);
    let front = cross(width_dir, up);
    return array<vec3<f32>, 2>(width_dir, front);
}

// Integer hash -> [0, 1); used for per-blade colour variation (same value every frame).
fn hash01(x: u32) -> f32 {
    var h = x * 747796405u + 2891336453u;
    h = ((h >> ((h >> 28u) + 4u)) ^ h) * 277803737u;
    h = (h >> 22u) ^ h;
    return f32(h) / 4294967296.0;
}

// A 32-bit integer hash (PCG's output permutation, Jarzynski & Olano 2020); the twin of
// `field::noise::hash32`.
fn hash32(x: u32) -> u32 {
    let state = x * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

fn rotl17(x: u32) -> u32 {
    return (x << 17u) | (x >> 15u);
}
