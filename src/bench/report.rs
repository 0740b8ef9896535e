//! What a bench run reports: the blade counts, GPU times, memory and work of each
//! configuration, the ratios between them, the sweep's points and the whole report (the
//! JSON `--json` prints and the tables read).

use serde::Serialize;
use sward::render::work::WorkReport;
use sward::sim::layout::CullCounters;

/// Blade counts of one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct BladeCounts {
    pub total: u64,
    pub drawn: u64,
    /// Drawn at each level of detail (near, middle, far).
    pub drawn_per_level: [u64; 3],
    /// Culled by any test; the five below add up to it (a blade counts for the first test
    /// that culls it).
    pub culled: u64,
    pub culled_patch: u64,
    pub culled_orientation: u64,
    pub culled_frustum: u64,
    pub culled_distance: u64,
    /// By the occlusion test, of whole patches or blade by blade.
    pub culled_occlusion: u64,
    /// The part of `culled_occlusion` culled with its patch.
    pub culled_occlusion_patch: u64,
    /// The part of `culled_occlusion` hidden by grass drawn early (the late test).
    pub culled_occlusion_grass: u64,
    /// Drawn by the late draw (not seen last frame, not hidden now).
    pub drawn_late: u64,
    /// Patches that passed the patch tests.
    pub visible_patches: u64,
    /// Blade slots the update stepped this frame (its chunks of 64 in class order, empty
    /// slots of a partial patch included), and of those the ones stepped at the throttled
    /// rate (a throttled patch's, or classes Eq. 20 thins out everywhere in a patch in
    /// view).
    pub stepped: u64,
    pub stepped_throttled: u64,
}

impl BladeCounts {
    pub(super) fn new(total: u32, c: &CullCounters) -> Self {
        let blades = |chunks: u32| {
            (u64::from(chunks) * u64::from(sward::sim::layout::UPDATE_CHUNK)).min(total.into())
        };
        Self {
            total: total.into(),
            drawn: c.drawn().into(),
            drawn_per_level: c.per_level().map(u64::from),
            culled: c.culled().into(),
            culled_patch: c.culled_patch.into(),
            culled_orientation: c.culled_orientation.into(),
            culled_frustum: c.culled_frustum.into(),
            culled_distance: c.culled_distance.into(),
            culled_occlusion: c.culled_occlusion.into(),
            culled_occlusion_patch: c.culled_occlusion_patch.into(),
            culled_occlusion_grass: c.culled_occlusion_grass.into(),
            drawn_late: c.drawn_late().into(),
            visible_patches: c.visible_patches.into(),
            stepped: blades(c.updated_chunks),
            stepped_throttled: blades(c.throttled_chunks),
        }
    }

    /// Blades of the patches that passed the patch test: the ones tested one by one.
    pub fn in_visible_patches(&self) -> u64 {
        self.total.saturating_sub(self.culled_patch)
    }
}

/// Mean GPU milliseconds per frame, from timestamp queries.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct GpuMs {
    /// The paper's "physical model": blade update + wind solver.
    pub physics: f64,
    pub update: f64,
    /// All passes of the wind solver (0 when the scene's wind is analytic only).
    pub wind: f64,
    /// The paper's "visibility": the occluders' depth, the depth pyramids, the patch pass
    /// and the blade culls (early and late).
    pub visibility: f64,
    /// The paper's "rendering": the draw passes (terrain, colliders, grass, sky; the late
    /// grass) and the deferred grass's light.
    pub rendering: f64,
    /// What the paper's frame did not have: the sun's shadow cascades, the tone mapping,
    /// the billboards' cull and the generation of streamed tiles.
    pub shadows: f64,
    /// The tone mapping, with the TAA blend before it where `render.taa` is on.
    pub tone_map: f64,
    pub billboards: f64,
    pub tiles: f64,
    /// What is drawn over the scene (the wind overlay) and the window's upscale.
    pub overlays: f64,
    /// The far levels' gains measured on the lit frame (`render::far_gain`).
    pub far_gain: f64,
    /// The animated objects' skinning.
    pub skinning: f64,
}

impl GpuMs {
    /// The GPU frame time: every timed pass of the frame (the paper's three parts and
    /// the passes it did not have).
    pub fn frame(&self) -> f64 {
        self.physics
            + self.visibility
            + self.rendering
            + self.shadows
            + self.tone_map
            + self.billboards
            + self.tiles
            + self.overlays
            + self.far_gain
            + self.skinning
    }
}

/// GPU memory of the scene.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Memory {
    /// The layout's bytes per blade (`BYTES_PER_BLADE`: blade, state, visible slot).
    pub bytes_per_blade: u64,
    /// Bytes of the blade buffers (blades, states, patches, spheres, visible list, indirect
    /// arguments: `Renderer::gpu_bytes().0`) per blade.
    pub measured_bytes_per_blade: f64,
    pub blade_bytes: u64,
    /// Everything the renderer allocated (`Renderer::gpu_bytes().1`).
    pub gpu_bytes: u64,
    pub gpu_mib: f64,
}

/// One column of the table.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ConfigReport {
    pub name: String,
    /// 1000 / `frame_ms`.
    pub fps: f64,
    /// Mean GPU frame time (the sum of the passes); the wall clock when the adapter has no
    /// timestamp queries (`frame_time_source` says which).
    pub frame_ms: f64,
    pub frame_time_source: String,
    /// Mean wall-clock time per frame, submit to read-back.
    pub wall_ms: f64,
    /// Counters of the last measured frame.
    pub blades: BladeCounts,
    /// `None` without timestamp queries.
    pub gpu_ms: Option<GpuMs>,
    /// Colliding spheres in the scene (0 with collisions off).
    pub colliders: u64,
    /// Spheres on at least one stepped patch's broad-phase list in the last frame: the
    /// paper's "collision spheres considered".
    pub colliders_considered: u64,
    /// Blade-sphere tests of the last frame per stepped blade.
    pub sphere_tests_per_blade: f64,
    /// Blades the update reset to their rest pose because their new state was non-finite
    /// or absurd, since the start of this configuration (warm-up included).
    pub blades_reset_nonfinite: u64,
    pub memory: Memory,
    /// The work of one counted frame after the measured ones: invocations per stage and
    /// per pass, and the lit grass's fragments per covered pixel (`None` without
    /// pipeline-statistics queries).
    pub work: Option<WorkReport>,
}

/// The ratios the issue asks for, from this run (`None` where a divisor is zero or the
/// times are missing).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Ratios {
    /// Frame time with culling off ÷ with all features.
    pub culling_off_over_all_frame_time: Option<f64>,
    /// All features: blades culled one by one (orientation + frustum + distance) ÷ blades
    /// in visible patches (total − culled by the patch test). The paper: "almost
    /// three-fourths of all blades of grass of visible patches are culled".
    pub culled_over_visible_patch_blades: Option<f64>,
    /// All features: physics ms per stepped blade ÷ rendering ms per drawn blade.
    pub physics_per_blade_over_rendering_per_drawn_blade: Option<f64>,
    /// The last all-features frame against the last culling-off frame (same field, same
    /// steps), with the snapshot test's measure: mean per-channel difference (0–255) and
    /// share of pixels off by more than `compare::PIXEL_TOLERANCE`.
    pub culled_vs_unculled_mean_difference: Option<f64>,
    pub culled_vs_unculled_failing_pixels: Option<f64>,
    /// Whether that difference is within the snapshot tolerance (no visible bare ground).
    pub culled_render_within_snapshot_tolerance: Option<bool>,
}

/// One point of the sweep: the all-features configuration at another density.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SweepPoint {
    pub requested: u64,
    pub blades: u64,
    pub drawn: u64,
    pub fps: f64,
    pub frame_ms: f64,
    pub wall_ms: f64,
    pub gpu_ms: Option<GpuMs>,
    pub gpu_mib: f64,
    pub work: Option<WorkReport>,
}

/// Everything `sward bench` measured.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BenchReport {
    pub adapter: String,
    /// When the run started, UTC.
    pub date: String,
    pub scene: String,
    pub size: [u32; 2],
    pub frames: u32,
    pub warmup: u32,
    pub dt: f32,
    /// Whether the adapter has timestamp queries (GPU pass times).
    pub timestamps: bool,
    pub configurations: Vec<ConfigReport>,
    pub ratios: Ratios,
    pub sweep: Vec<SweepPoint>,
}
