//! The scene file's data model: plain serde structs, every field with a default so that a
//! scene only states what it changes. Unknown fields are rejected (`deny_unknown_fields`)
//! so that a typo is an error, not a silently ignored setting.

use serde::{Deserialize, Serialize};

mod light;
mod render;
mod wind;
pub use light::*;
pub use render::*;
pub use wind::*;

/// A whole scene: what `sward render` / `sward simulate` load from a `.ron` file.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct Scene {
    /// The ground: its size, where its heights come from, the grass density map and whether
    /// it runs on to the horizon.
    pub terrain: Terrain,
    /// The grass: blade density, sizes, shapes, placement, species, clumps and flowers.
    pub field: Field,
    /// Spheres that press the grass down where they rest or move (`center`, `radius`,
    /// `motion`); empty by default.
    pub colliders: Vec<Sphere>,
    /// Meshes placed in the scene (OBJ or glTF), drawn lit and occluding the grass.
    pub objects: Vec<MeshObject>,
    /// The wind the blades feel: the paper's analytic waves and point source, and the fluid
    /// grid with its guides, global wind and downwash.
    pub wind: Wind,
    /// The blade update: gravity, collisions and trails, time step and the blade model.
    pub physics: Physics,
    /// Which blades are skipped before drawing (Section 6.2), the levels of detail, and how
    /// often patches far from the camera update.
    pub culling: Culling,
    /// The view the scene is rendered from: eye, target, field of view and clip planes.
    pub camera: Camera,
    /// How the grass is drawn: sun direction, blade displacement and width correction,
    /// self-shadow, debug colours, billboards and anti-aliasing.
    pub render: Render,
    /// The sun, the sky, shadows, tone mapping and the blade shading terms.
    pub light: Light,
    /// The file and text the scene was loaded from, for errors found after loading (an
    /// image that does not decode); never compared, never saved.
    #[serde(skip)]
    pub origin: super::origin::Origin,
}

/// Where the height of the ground comes from.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub enum HeightSource {
    /// Seeded fractal Brownian motion of value noise.
    /// Fields left out take the default terrain's values (seed 7, amplitude 2 m, the
    /// `noise_*` defaults below).
    Noise {
        /// Seed of the noise (any u64, default 7): the same seed gives the same hills.
        #[serde(default = "noise_seed")]
        seed: u64,
        /// Peak-to-peak amplitude in metres.
        #[serde(default = "noise_amplitude")]
        amplitude: f32,
        /// Size of the largest hills in metres.
        #[serde(default = "noise_wavelength")]
        wavelength: f32,
        /// Layers of noise summed, each finer and weaker than the last, 1 to 12 (default
        /// 4).
        #[serde(default = "noise_octaves")]
        octaves: u32,
    },
    /// A grey PNG: black = 0 m, white = `scale` metres.
    Png {
        /// The PNG file, relative to the scene file's directory.
        path: String,
        /// Height in metres of a white pixel, 0 to 1000 m.
        scale: f32,
    },
    /// A flat plane at height 0.
    Flat,
}

/// The ground: heights over the x/z plane; grass grows in the square of side `size`
/// centred on the origin, and the ground itself runs on past it when `unbounded`.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct Terrain {
    /// Side length in metres (x and z).
    pub size: f32,
    /// Grid vertices per side of the height field and the terrain mesh.
    pub resolution: u32,
    /// Where the heights come from: `Noise(..)` (the default), `Png(..)` or `Flat`.
    pub height: HeightSource,
    /// Optional grey PNG: white = full density, black = no grass.
    pub density_map: Option<String>,
    /// Whether the ground goes on past the square to the horizon (drawn around the camera
    /// out to the far plane); `false` draws only the square. Blades grow only inside the
    /// square either way.
    pub unbounded: bool,
}

fn noise_seed() -> u64 {
    7
}
fn noise_amplitude() -> f32 {
    2.0
}
fn noise_wavelength() -> f32 {
    30.0
}
fn noise_octaves() -> u32 {
    4
}

impl Default for Terrain {
    fn default() -> Self {
        Self {
            size: 40.0,
            resolution: 129,
            height: HeightSource::Noise {
                seed: noise_seed(),
                amplitude: noise_amplitude(),
                wavelength: noise_wavelength(),
                octaves: noise_octaves(),
            },
            density_map: None,
            unbounded: true,
        }
    }
}

/// The five blade shapes of the paper (Section 6.3).
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
pub enum Shape {
    /// Full width from the base to the tip.
    Quad,
    /// Narrows evenly from the full width at the base to a point at the tip.
    Triangle,
    /// Narrows to a point at the tip with the square of the height: one edge straight, the
    /// other curving in.
    Quadratic,
    /// Full width up to `tip_threshold` of the height, then narrowing to a point at the tip
    /// (the default).
    #[default]
    TriangleTip,
    /// A toothed leaf like a dandelion's: narrowing to the tip, its width swinging between
    /// teeth along the edges.
    Dandelion,
}

impl Shape {
    /// The id the shaders switch on.
    pub fn id(self) -> u32 {
        match self {
            Shape::Quad => 0,
            Shape::Triangle => 1,
            Shape::Quadratic => 2,
            Shape::TriangleTip => 3,
            Shape::Dandelion => 4,
        }
    }
}

/// A closed interval `[min, max]` for per-blade random attributes.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Range {
    /// Smallest value a blade can get (inclusive).
    pub min: f32,
    /// Largest value a blade can get (inclusive); must be at least `min`.
    pub max: f32,
}

impl Range {
    /// The interval from `min` to `max`.
    pub const fn new(min: f32, max: f32) -> Self {
        Self { min, max }
    }
    /// The value at `t` in `[0, 1]`.
    pub fn lerp(self, t: f32) -> f32 {
        self.min + (self.max - self.min) * t
    }
}

/// How blades are placed and what they look like.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct Field {
    /// Blades per square metre of ground.
    pub density: f32,
    /// Blade height in metres.
    pub height: Range,
    /// Blade width in metres (full width at the base).
    pub width: Range,
    /// Stiffness s of Eq. 3, in 1/s.
    pub stiffness: Range,
    /// Rest lean of the tip away from up, in degrees.
    pub bend: Range,
    /// Fraction of blades that grow in tufts (Poisson-disk tuft centres), the rest are single.
    pub tuft_fraction: f32,
    /// Radius of a tuft in metres.
    pub tuft_radius: f32,
    /// Outline of the blades: `Quad`, `Triangle`, `Quadratic`, `TriangleTip` (the default)
    /// or `Dandelion`.
    pub shape: Shape,
    /// Threshold τ of the triangle-tip shape.
    pub tip_threshold: f32,
    /// Blades per patch (a multiple of 64, the workgroup size).
    pub patch_size: u32,
    /// Segments along the blade's height in the drawn mesh.
    pub segments: u32,
    /// Seed of the blades' placement and random attributes (any u64, default 1): the same
    /// seed grows the same field.
    pub seed: u64,
    /// Side of the tiles the field is streamed in, in metres (rounded to whole patches):
    /// tiles within the blade radius (`culling.max_distance`) of the camera are generated
    /// on the GPU as the camera moves, so the grass goes on as far as the terrain does.
    /// 0: the whole field is generated at start (the papers' scenes).
    pub tile_size: f32,
    /// Species the field mixes (at most 8), each with its share of the blades; empty: one
    /// species with the field's own height, width, stiffness, shape and colour.
    pub species: Vec<Species>,
    /// Blades grow in clumps whose members face and lean together and share a tint (as in
    /// Ghost of Tsushima); a clump is one species. `None`: no clumps.
    pub clumps: Option<Clumps>,
    /// Flowers among the grass (Zhang's thesis §3.3–3.4): a share of the blades become
    /// flower stems, simulated and pressed like any blade, with a head drawn at the tip.
    pub flowers: Option<Flowers>,
}

/// Flowers: which blades are stems, how tall, and the kinds of head.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct Flowers {
    /// Share of the blades that are flowers (the terrain's density map thins them with the
    /// grass).
    pub fraction: f32,
    /// Stem height in metres (the thesis sets heads at about 0.65 of the grass height:
    /// choose it so the heads show among the blades).
    pub height: Range,
    /// Radius of a head in metres.
    pub head_size: f32,
    /// The kinds of flower (at most 4), each as likely.
    pub kinds: Vec<FlowerKind>,
}

/// One kind of flower head.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct FlowerKind {
    /// Petal colour (linear RGB, 0..1).
    pub petals: (f32, f32, f32),
    /// Colour of the head's centre.
    pub centre: (f32, f32, f32),
    /// Number of petals.
    pub petal_count: u32,
}

impl Default for FlowerKind {
    fn default() -> Self {
        Self {
            petals: (0.9, 0.9, 0.85),
            centre: (0.9, 0.65, 0.1),
            petal_count: 12,
        }
    }
}

impl Default for Flowers {
    fn default() -> Self {
        Self {
            fraction: 0.02,
            height: Range::new(0.45, 0.7),
            head_size: 0.035,
            kinds: vec![
                FlowerKind::default(),
                FlowerKind {
                    petals: (0.95, 0.78, 0.08),
                    centre: (0.8, 0.55, 0.05),
                    petal_count: 5,
                },
                FlowerKind {
                    petals: (0.55, 0.3, 0.8),
                    centre: (0.95, 0.85, 0.3),
                    petal_count: 6,
                },
            ],
        }
    }
}

/// One species of grass in a mixed field.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct Species {
    /// Relative share of the blades (the shares are normalised).
    pub share: f32,
    /// Blade height of this species in metres, each end 0.01 to 10 m.
    pub height: Range,
    /// Blade width of this species at the base in metres, each end above 0 and at most 1 m.
    pub width: Range,
    /// Stiffness s of Eq. 3 of this species, in 1/s, each end 0 to 1000.
    pub stiffness: Range,
    /// Base colour (linear RGB, 0..1) at mid-height.
    pub color: (f32, f32, f32),
    /// Outline of this species' blades (see [`Shape`]).
    pub shape: Shape,
}

impl Default for Species {
    fn default() -> Self {
        let f = Field::default();
        Self {
            share: 1.0,
            height: f.height,
            width: f.width,
            stiffness: f.stiffness,
            color: (0.16, 0.36, 0.07),
            shape: f.shape,
        }
    }
}

/// Clumps: a jittered grid of clump centres; a blade belongs to the nearest.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct Clumps {
    /// Spacing of the clump centres in metres.
    pub size: f32,
    /// How far a blade turns to face its clump's direction: 0 its own, 1 the clump's.
    pub align: f32,
    /// Extra lean of the whole clump towards its direction, in degrees.
    pub lean: f32,
    /// Brightness variation between clumps: each clump's colour is scaled within
    /// 1 ± variation / 2.
    pub color_variation: f32,
}

impl Default for Clumps {
    fn default() -> Self {
        Self {
            size: 0.6,
            align: 0.7,
            lean: 12.0,
            color_variation: 0.35,
        }
    }
}

impl Default for Field {
    fn default() -> Self {
        Self {
            density: 80.0,
            height: Range::new(0.35, 0.75),
            width: Range::new(0.025, 0.045),
            stiffness: Range::new(6.0, 12.0),
            bend: Range::new(0.0, 20.0),
            tuft_fraction: 0.4,
            tuft_radius: 0.12,
            shape: Shape::TriangleTip,
            tip_threshold: 0.5,
            patch_size: 1024,
            segments: 6,
            seed: 1,
            tile_size: 0.0,
            species: Vec::new(),
            clumps: None,
            flowers: None,
        }
    }
}

/// How a sphere collider moves.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub enum Motion {
    /// Does not move.
    Static,
    /// Constant velocity in m/s.
    Velocity((f32, f32, f32)),
    /// Rolls over the terrain along a polyline of (x, z) points at `speed` m/s, resting on
    /// the ground; `looped` closes the path.
    Path {
        /// The (x, z) points of the path in metres: at least 2, not all at one place, each
        /// coordinate within ±100000 m.
        points: Vec<(f32, f32)>,
        /// Speed along the path in m/s, 0 to 1000.
        speed: f32,
        /// Whether the path runs on from the last point back to the first and repeats;
        /// otherwise the mover stops at the last point.
        looped: bool,
    },
}

/// A sphere collider (the paper represents every object as spheres).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Sphere {
    /// Centre at t = 0 (for `Path`, y is an offset above the ground and x/z are ignored).
    pub center: (f32, f32, f32),
    /// Radius in metres, above 0 and at most 1000 m.
    pub radius: f32,
    /// How the sphere moves; `Static` when left out.
    #[serde(default = "default_motion")]
    pub motion: Motion,
}

fn default_motion() -> Motion {
    Motion::Static
}

/// Parameters of the physical model (Section 5).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct Physics {
    /// Gravity direction D.xyz (normalised on load).
    pub gravity_direction: (f32, f32, f32),
    /// Gravitational acceleration D.w in m/s².
    pub gravity_acceleration: f32,
    /// Gravity centre C.xyz.
    pub gravity_center: (f32, f32, f32),
    /// Acceleration towards the centre C.w in m/s².
    pub gravity_center_acceleration: f32,
    /// Blend t between direction (0) and centre (1), Eq. 4.
    pub gravity_blend: f32,
    /// Blade mass m of Eq. 4.
    pub mass: f32,
    /// Decrease a of the collision strength per second, Eq. 2.
    pub collision_decay: f32,
    /// Gain k on the collision strength of Eq. 16, η += k d·d, in 1/m². The paper adds d·d
    /// in its own scene units; in metres a push of a few centimetres would barely weaken
    /// the recovery, so k sets how hard a push cripples a blade (k = 100: a 10 cm push
    /// gives η = 1, a full trail).
    pub collision_gain: f32,
    /// Ceiling of η. Past 0.9 the recovery of Eq. 3 is already at its 0.1 floor; the ceiling
    /// bounds how long a blade stays down (η_max / a seconds) when a collider sits on it.
    pub max_collision_strength: f32,
    /// Multiplies every blade's stiffness s (Eq. 3): < 1 makes the whole meadow softer.
    pub stiffness_scale: f32,
    /// Largest time step the update takes; longer frames are clamped to it.
    pub max_dt: f32,
    /// Whether colliders (spheres and mesh objects) press the blades at all; `false` turns
    /// every collision off.
    pub collisions: bool,
    /// Qiu et al.'s hierarchy of the colliders (`sim::bvh`): each blade walks a tree of
    /// bounding spheres instead of its patch's list of nearby spheres.
    pub collision_hierarchy: bool,
    /// Metres from the camera within which a blade walks the hierarchy down to the
    /// colliders themselves; each doubling of the distance beyond (and a throttled patch)
    /// stops the walk one level higher, at a coarser bounding sphere.
    pub hierarchy_precision_distance: f32,
    /// Which paper's blade the update steps and the draw bends.
    pub model: BladeModel,
    /// The parameters of the `Verlet` model.
    pub verlet: VerletParams,
    /// The parameters of the `Cwd` model.
    pub cwd: CwdParams,
    /// Qiu et al.'s grass-to-grass propagation (§5.2): a blade pressed by a collider
    /// passes part of its bending to its neighbours, generation by generation. `None`: off.
    pub propagation: Option<Propagation>,
    /// The trail map of a streamed field (`field::trails`): where colliders pressed the
    /// grass, kept in world space, so a trail is still there when its tile leaves the blade
    /// radius and comes back, and the billboards and the far ground show it. It decays with
    /// η (`collision_decay`). `None`: trails live only in the blades. Ignored by a field
    /// generated whole (`field.tile_size: 0`), whose blades never leave.
    pub trails: Option<Trails>,
}

/// The sizes of the trail map (`physics.trails`).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct Trails {
    /// Texels along a tile's side, 4 to 128 (32 on 8 m tiles: 25 cm texels).
    pub resolution: u32,
    /// Tiles whose trail is kept after they left the blade radius, 0 to 65536, beyond the
    /// resident tiles: the map holds (resident slots + cache_tiles) pages of
    /// resolution² × 12 bytes. When it is full the trail that left longest ago goes.
    pub cache_tiles: u32,
}

impl Default for Trails {
    fn default() -> Self {
        Self {
            resolution: 32,
            cache_tiles: 256,
        }
    }
}

/// Grass-to-grass propagation (Qiu et al. §5.2, Eq. 4) over a grid of cells around the
/// camera: the pushes the colliders gave the blades of a cell this step (their mean, the
/// "force vector" of the ancestors) pass to the adjacent cells they point at, split into
/// their x and z parts and scaled by `att` per generation, while a cell's force exceeds
/// `threshold`; the blades of the reached cells are pushed by their cell's force, as if by
/// a collider. The trail grows wider and softer than the object.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct Propagation {
    /// The decay factor att of Eq. 4, in [0, 1].
    pub att: f32,
    /// The threshold L: a cell whose force (metres of push per step) is below it is in
    /// termination status and passes nothing on.
    pub threshold: f32,
    /// Most generations of children per step.
    pub generations: u32,
    /// Side of a cell in metres (about the spacing of the blades).
    pub cell_size: f32,
    /// Side of the square grid around the camera, in metres.
    pub extent: f32,
}

impl Default for Propagation {
    fn default() -> Self {
        Self {
            att: 0.6,
            threshold: 0.002,
            generations: 6,
            cell_size: 0.08,
            extent: 24.0,
        }
    }
}

/// The blade model: how a blade's shape follows the forces.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
pub enum BladeModel {
    /// Jahrmann & Wimmer 2017: a quadratic Bézier whose tip v2 moves under recovery,
    /// gravity, wind and collisions, then the state validation (Eq. 1–16).
    #[default]
    Jahrmann,
    /// Zhang's prairie thesis §3.2: a cubic Bézier whose control points P1..P3 are
    /// integrated with Verlet from the wind at each point and gravity, then pulled back to
    /// segments of a third of the height (the shape constraint of §3.2.4).
    Verlet,
    /// CWD-Sim (Choi & Sung 2024) §3.3: no state between frames; every vertex bent by the
    /// quadratic equations 11–13 from the wind at the blade's grid cell. No collisions and
    /// no trails.
    Cwd,
}

impl BladeModel {
    /// Every blade model, in the order of their ids.
    pub const ALL: [BladeModel; 3] = [BladeModel::Jahrmann, BladeModel::Verlet, BladeModel::Cwd];

    /// The id the shaders switch on (`MODEL_*` in `common.wgsl`).
    pub fn id(self) -> u32 {
        match self {
            BladeModel::Jahrmann => 0,
            BladeModel::Verlet => 1,
            BladeModel::Cwd => 2,
        }
    }

    /// The model's name as written in a scene file: `Jahrmann`, `Verlet` or `Cwd`.
    pub fn name(self) -> &'static str {
        match self {
            BladeModel::Jahrmann => "Jahrmann",
            BladeModel::Verlet => "Verlet",
            BladeModel::Cwd => "Cwd",
        }
    }
}

/// The Verlet blade (thesis §3.2.3–3.2.4). Its forces are Jahrmann's at each control point
/// (recovery towards the rest chain, gravity, the wind at the point), scaled by the blade's
/// stiffness s to an acceleration: a Verlet blade rests where a Jahrmann blade rests and
/// sways at ω = s rad/s.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct VerletParams {
    /// Velocity damping per second (the thesis has none: without it a blade sways forever).
    pub damping: f32,
    /// Multiplies the wind at each control point.
    pub wind_gain: f32,
}

impl Default for VerletParams {
    fn default() -> Self {
        Self {
            damping: 3.0,
            wind_gain: 1.0,
        }
    }
}

/// CWD-Sim's deformation (§3.3, Eq. 11–13), with the paper's k1 = 0.05, k2 = 0.1 and
/// λ = 0.2 (§4). Heights are in blade heights (the paper's model units).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct CwdParams {
    /// Eq. 11: how far gravity lowers a vertex, k1·Py².
    pub k1: f32,
    /// Eq. 11: how far gravity moves a vertex forward, k2·Py².
    pub k2: f32,
    /// Eq. 13: the weight λ of the gravity shape against the wind translation.
    pub lambda: f32,
    /// Eq. 12: F, the wind translation per m/s of wind, in blade heights.
    pub force: f32,
    /// Side of the cells whose blades share one wind value when the fluid is off (with the
    /// fluid, its grid's cells), in metres.
    pub cell_size: f32,
}

impl Default for CwdParams {
    fn default() -> Self {
        Self {
            k1: 0.05,
            k2: 0.1,
            lambda: 0.2,
            force: 0.1,
            cell_size: 1.0,
        }
    }
}

impl Default for Physics {
    fn default() -> Self {
        Self {
            gravity_direction: (0.0, -1.0, 0.0),
            gravity_acceleration: 9.81,
            gravity_center: (0.0, -1000.0, 0.0),
            gravity_center_acceleration: 9.81,
            gravity_blend: 0.0,
            mass: 0.08,
            collision_decay: 0.25,
            collision_gain: 100.0,
            max_collision_strength: 2.0,
            stiffness_scale: 1.0,
            max_dt: 0.05,
            collision_hierarchy: false,
            hierarchy_precision_distance: 10.0,
            collisions: true,
            model: BladeModel::Jahrmann,
            verlet: VerletParams::default(),
            cwd: CwdParams::default(),
            propagation: None,
            trails: Some(Trails::default()),
        }
    }
}

/// Parameters of the culling pass (Section 6.2). Each test can be switched off.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct Culling {
    /// Skip whole patches whose bounding box is outside the view (or, with `distance`,
    /// beyond `max_distance`, or, with `occlusion`, hidden by the opaque objects) before
    /// their blades are tested.
    pub patches: bool,
    /// Skip blades seen edge-on (Eq. 17); see `orientation_threshold`.
    pub orientation: bool,
    /// Cull when |dir_c · dir_b| exceeds this. The paper uses 0.9; the default 0.94 keeps
    /// the nature view within the snapshot tolerance of the unculled frame (at 0.9
    /// edge-on blades still show 0.44 of their width, and 1.2 % of the pixels differ).
    pub orientation_threshold: f32,
    /// Skip blades outside the view frustum (Eq. 18); see `frustum_tolerance`.
    pub frustum: bool,
    /// Tolerance t of Eq. 18, in clip-space units of w.
    pub frustum_tolerance: f32,
    /// Eq. 19–20: thins far grass, which shows (off by default; the window's frame
    /// budget switches it on when it must).
    pub distance: bool,
    /// Number of distance levels n of Eq. 20.
    pub distance_levels: u32,
    /// d_max of Eq. 20 in metres.
    pub max_distance: f32,
    /// Occlusion test against a depth pyramid of the opaque objects (terrain, colliders).
    pub occlusion: bool,
    /// Depth bias of the occlusion test, as a fraction of the view distance.
    pub occlusion_bias: f32,
    /// Grass hides grass (with `occlusion`): blades not seen last frame are tested again
    /// after the rest of the grass is drawn, against its depth, and drawn only if visible.
    pub grass_occlusion: bool,
    /// Depth bias of the grass-occlusion test, as a fraction of the view distance: a blade
    /// is hidden only where the grass in front of it is at least this much nearer.
    pub grass_occlusion_bias: f32,
    /// Levels of detail: off draws every blade with the full mesh.
    pub lod: bool,
    /// Projected blade height in pixels at and above which the full mesh draws.
    pub lod_near_px: f32,
    /// Projected blade height in pixels at and above which the middle mesh draws (below:
    /// the one-segment mesh).
    pub lod_far_px: f32,
    /// Width of the morph band above each threshold, as a fraction of it: blades morph
    /// towards the coarser mesh across it, so a level change moves no vertex.
    pub lod_morph: f32,
    /// Patches outside the view and beyond `physics_radius` update every this many frames
    /// with a Δt that many times longer (capped at `physics.max_dt`); patches beyond
    /// `max_distance` (whose blades no view shows) and `physics_radius` not at all. 1
    /// updates every patch every frame.
    pub physics_throttle: u32,
    /// Metres around the camera in which every patch updates every frame.
    pub physics_radius: f32,
}

impl Default for Culling {
    fn default() -> Self {
        Self {
            patches: true,
            orientation: true,
            orientation_threshold: 0.94,
            frustum: true,
            frustum_tolerance: 0.05,
            distance: false,
            distance_levels: 8,
            max_distance: 60.0,
            occlusion: true,
            occlusion_bias: 0.02,
            grass_occlusion: true,
            grass_occlusion_bias: 0.002,
            lod: true,
            lod_near_px: 24.0,
            lod_far_px: 8.0,
            lod_morph: 0.3,
            physics_throttle: 4,
            physics_radius: 8.0,
        }
    }
}

/// A perspective camera looking from `eye` at `target`.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct Camera {
    /// Where the camera is, in metres (each component within ±100000 m).
    pub eye: (f32, f32, f32),
    /// The point the camera looks at, in metres (each component within ±100000 m); must
    /// differ from `eye`.
    pub target: (f32, f32, f32),
    /// Vertical field of view in degrees.
    pub fov_y: f32,
    /// Distance of the near clip plane in metres, 0.001 to 1000 m.
    pub near: f32,
    /// Distance of the far clip plane in metres: beyond `near` and at most 1000000 m.
    pub far: f32,
    /// The camera behind a moving object (the prairie thesis's camera behind its walker):
    /// `eye` and `target` give way to a view from behind the object along the way it has
    /// come. `None`: the camera stays at `eye`.
    #[serde(default)]
    pub follow: Option<CameraFollow>,
}

/// The camera behind one of the scene's objects (`camera.follow`): every frame the eye is
/// `distance` behind the object's origin along the way it moved over the last 0.75 s (its
/// facing while it stands), `height` above it, looking at the point `look_height` above
/// the origin; never below the terrain.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct CameraFollow {
    /// Which of the scene's `objects`, counted from 0.
    pub object: u32,
    /// Metres behind it, 0.1 to 1000.
    pub distance: f32,
    /// Metres above its origin of the eye, −1000 to 1000.
    pub height: f32,
    /// Metres above its origin of the point looked at, −1000 to 1000.
    pub look_height: f32,
}

impl Default for CameraFollow {
    fn default() -> Self {
        Self {
            object: 0,
            distance: 4.5,
            height: 2.2,
            look_height: 1.2,
        }
    }
}

impl Default for Camera {
    fn default() -> Self {
        Self {
            eye: (-9.0, 4.0, 13.0),
            target: (2.0, 0.0, -2.0),
            fov_y: 50.0,
            near: 0.1,
            far: 300.0,
            follow: None,
        }
    }
}

/// A mesh placed in the scene (issue 14): an OBJ or glTF / GLB file, moved, turned and
/// scaled, drawn lit in one colour and an occluder of the grass behind it.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct MeshObject {
    /// The file (`.obj`, `.gltf`, `.glb`), relative to the scene file's directory.
    pub mesh: String,
    /// Where the mesh's origin goes, in metres.
    pub translation: (f32, f32, f32),
    /// Rotation in degrees about x, then y, then z (each applied in the world frame).
    pub rotation: (f32, f32, f32),
    /// Uniform scale from the file's units to metres.
    pub scale: f32,
    /// Linear RGB albedo.
    pub color: (f32, f32, f32),
    /// The collision shape sward builds from the mesh, which pushes the grass and (with
    /// `wind.fluid.obstacles`) blocks the air.
    pub collider: MeshCollider,
    /// How the object moves: `Static` at `translation`; `Velocity((x, y, z))` from it;
    /// `Path(..)`: its origin follows the (x, z) points at `speed`, `translation.y` above
    /// the ground under it. The mesh and its collider move together.
    pub motion: Motion,
    /// With `motion: Path`, the object rolls along it like a ball: it turns about the
    /// horizontal axis across its heading by the distance travelled over its rolling radius,
    /// `translation.y` (its origin's height above the ground, so a boulder centred on its
    /// origin rolls without slipping). Off: it slides, like a cart.
    pub rolls: bool,
    /// Grass grown on the object's surface (`crate::field::surface`), with the fields of
    /// the scene's `field` (density in blades per m² of surface; the shape, tip threshold,
    /// patch size, segments and tile size are the scene field's, one draw for all blades).
    /// Grown where the object stands at rest; it does not move with a moving object.
    pub grass: Option<Field>,
    /// The glTF animation the object plays, looped, by name (`Some("walk")`): the file is
    /// then read as a skinned mesh (`crate::mesh::skin`) and its vertices are posed by its
    /// joints on the GPU every frame. `None`: the mesh as the file places it.
    pub animation: Option<String>,
    /// With `animation` and `motion: Path`: the metres the object travels in one cycle of
    /// its animation, so that the animation plays at the pace of the ground it covers
    /// (a walk's feet do not slide). 0: the animation plays at the scene's clock.
    pub stride: f32,
    /// Where a program steering the object has put it this frame (the window's walk mode,
    /// an embedding host): it replaces `motion` and the animation's clock while set. Not
    /// part of the scene file: it is state of the running program.
    #[serde(skip)]
    pub pose: Option<ObjectPose>,
}

/// A steered object's place and pose, set each frame by the program that steers it
/// (`Renderer::pose_object`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObjectPose {
    /// Where the object's origin is in the world, in metres (a walker's origin between its
    /// feet: on the ground under it plus its `translation.y`).
    pub origin: glam::Vec3,
    /// Its turn about the vertical in radians, on top of its `rotation`: its +z then faces
    /// (sin yaw, 0, cos yaw), as a path walker faces its heading.
    pub yaw: f32,
    /// Seconds into its animation (a walk's phase: the distance walked over the stride,
    /// in cycles of the animation).
    pub animation_time: f32,
    /// Its velocity in m/s: the wind's obstacles move with it.
    pub velocity: glam::Vec3,
}

impl ObjectPose {
    /// Whether every number is finite (a pose with a NaN is refused, not drawn).
    pub fn is_finite(&self) -> bool {
        self.origin.is_finite()
            && self.yaw.is_finite()
            && self.animation_time.is_finite()
            && self.velocity.is_finite()
    }
}

/// A mesh object's collision shape.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub enum MeshCollider {
    /// The object does not touch the grass.
    #[default]
    None,
    /// Jahrmann & Wimmer's sphere packing, computed from the mesh (`crate::mesh::pack`).
    Spheres(SpherePacking),
    /// The same packing, walked through Qiu's hierarchy (`crate::sim::bvh`): it switches
    /// `physics.collision_hierarchy` on for the whole scene (the hierarchy holds every
    /// collider).
    Bvh(SpherePacking),
    /// For an object with an `animation`: one sphere per joint of its skeleton, around the
    /// vertices that joint moves most (their centroid; radius their root-mean-square
    /// distance from it), posed with the joint every frame — the prairie thesis's
    /// interaction spheres: the feet, legs and body press the grass as they move.
    Joints,
}

impl MeshCollider {
    /// The packing asked for, if any.
    pub fn packing(&self) -> Option<&SpherePacking> {
        match self {
            MeshCollider::None | MeshCollider::Joints => None,
            MeshCollider::Spheres(p) | MeshCollider::Bvh(p) => Some(p),
        }
    }
}

impl Scene {
    /// Whether the blades walk the colliders' hierarchy: `physics.collision_hierarchy`, or
    /// an object whose collider is `Bvh`.
    pub fn collision_hierarchy(&self) -> bool {
        self.physics.collision_hierarchy
            || self
                .objects
                .iter()
                .any(|o| matches!(o.collider, MeshCollider::Bvh(_)))
    }
}

/// How a mesh is packed with spheres.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct SpherePacking {
    /// Spheres to pack (largest first; fewer when they cover the mesh already).
    pub count: u32,
    /// Voxels along the longest side of the mesh's box for the inside test and distances.
    pub resolution: u32,
}

impl Default for SpherePacking {
    fn default() -> Self {
        Self {
            count: 100,
            resolution: crate::mesh::pack::DEFAULT_RESOLUTION,
        }
    }
}

impl Default for MeshObject {
    fn default() -> Self {
        Self {
            mesh: String::new(),
            translation: (0.0, 0.0, 0.0),
            rotation: (0.0, 0.0, 0.0),
            scale: 1.0,
            color: (0.6, 0.55, 0.5),
            collider: MeshCollider::None,
            motion: Motion::Static,
            rolls: false,
            grass: None,
            animation: None,
            stride: 0.0,
            pose: None,
        }
    }
}

impl MeshObject {
    /// The object-to-world transform at rest (at `translation`).
    pub fn transform(&self) -> glam::Mat4 {
        self.transform_at(self.translation.into())
    }

    /// The object-to-world transform with its origin at `origin`.
    pub fn transform_at(&self, origin: glam::Vec3) -> glam::Mat4 {
        let (rx, ry, rz) = self.rotation;
        let rotation = glam::Quat::from_euler(
            glam::EulerRot::ZYX,
            rz.to_radians(),
            ry.to_radians(),
            rx.to_radians(),
        );
        glam::Mat4::from_scale_rotation_translation(glam::Vec3::splat(self.scale), rotation, origin)
    }
}
