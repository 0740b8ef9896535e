//! One configuration of `sward bench`: a fresh renderer over the session's field runs the
//! warm-up and the measured frames; the per-pass GPU times, wall time, counters, memory
//! and last image come back (and, with `--trace`, the measured frames' GPU scopes).

use std::time::Instant;

use super::{BladeCounts, GpuMs, BENCH_DT};
use sward::commands::world_frame;
use sward::embed::GrassRenderer;
use sward::error::Result;
use sward::gpu::Gpu;
use sward::render::camera::CameraView;
use sward::render::target::{Target, COLOR_FORMAT};
use sward::render::timing;
use sward::render::work::WorkReport;
use sward::render::Renderer;
use sward::scene::Scene;
use sward::session::Session;
use sward::sim::layout::CullCounters;

/// What one configuration's frames gave.
pub(super) struct Measured {
    pub(super) blades: BladeCounts,
    pub(super) gpu_ms: Option<GpuMs>,
    pub(super) wall_ms: f64,
    pub(super) gpu_bytes: (u64, u64),
    /// The last frame, to compare the culled render with the unculled one.
    pub(super) image: image::RgbaImage,
    /// Broad phase of the last frame: spheres on some list, blade-sphere tests.
    pub(super) spheres_considered: u64,
    pub(super) sphere_tests: u64,
    /// Blades reset to their rest pose since the renderer started (warm-up included).
    pub(super) resets: u64,
    /// The measured frames' GPU scopes, when tracing.
    pub(super) scopes: Vec<wgpu_profiler::GpuTimerQueryResult>,
    /// The work of one more frame after the measured ones, counted (`None` without
    /// pipeline-statistics queries).
    pub(super) work: Option<WorkReport>,
}

impl Measured {
    pub(super) fn frame_ms(&self) -> f64 {
        self.gpu_ms.map_or(self.wall_ms, |g| g.frame())
    }
}

/// A new renderer of `scene` over `session`'s field, terrain and mesh objects, drawn
/// through the embedding API (`GrassRenderer::render_world`, as the window and `render`).
pub(super) fn fresh_renderer(gpu: &Gpu, session: &Session, scene: Scene) -> Result<GrassRenderer> {
    let mut renderer = Renderer::new(
        gpu,
        scene,
        session.terrain.clone(),
        &session.field,
        COLOR_FORMAT,
    )?;
    renderer.set_objects(gpu, &session.meshes, &session.packings);
    renderer.set_skins(gpu, &session.skins);
    gpu.check_errors()?;
    Ok(GrassRenderer::wrap_world(gpu, renderer, COLOR_FORMAT))
}

/// Runs `warmup + frames` frames of `scene` over `session`'s field with a fresh renderer.
pub(super) fn measure(
    gpu: &Gpu,
    session: &Session,
    scene: Scene,
    target: &Target,
    warmup: u32,
    frames: u32,
    trace: bool,
) -> Result<Measured> {
    let camera = CameraView::from_scene(&scene.camera);
    let mut renderer = fresh_renderer(gpu, session, scene)?;
    let mut passes = [0.0f64; timing::PASSES.len()];
    let mut wind = 0.0f64;
    let mut timed = 0u32;
    let mut wall = 0.0f64;
    let mut last = CullCounters::default();
    let mut resets = 0;
    for i in 0..warmup + frames {
        if trace && i == warmup {
            // The warm-up is left out of the trace as out of the statistics.
            renderer.record_trace();
        }
        let start = Instant::now();
        let view = renderer.scene_camera(&camera, BENCH_DT);
        world_frame(gpu, &mut renderer, BENCH_DT, view, target)?;
        let stats = renderer.stats(gpu)?;
        let elapsed = start.elapsed().as_secs_f64() * 1000.0;
        resets = stats.blades_reset_nonfinite;
        if i < warmup {
            continue;
        }
        wall += elapsed;
        last = stats.counters;
        if let Some(ms) = stats.pass_ms {
            for (sum, m) in passes.iter_mut().zip(ms) {
                *sum += m;
            }
            wind += stats.wind_ms.iter().flatten().map(|(_, m)| m).sum::<f64>();
            timed += 1;
        }
    }
    let n = f64::from(frames.max(1));
    let view = renderer.scene_camera(&camera, BENCH_DT);
    let work = count_frame(gpu, &mut renderer, &view, target)?;
    // Every frame has timestamps or none does; a mix would mean a broken driver, and the
    // means over the timed frames are still right then.
    let gpu_ms = (timed > 0).then(|| {
        let t = f64::from(timed);
        let update = passes[timing::UPDATE] / t;
        let wind = wind / t;
        GpuMs {
            physics: update + wind,
            update,
            wind,
            // The occluder depth pass and the pyramids only feed the occlusion tests:
            // visibility work.
            visibility: [
                timing::OCCLUDERS,
                timing::PYRAMID,
                timing::PATCHES,
                timing::CULL,
                timing::LATE_PYRAMID,
                timing::LATE_CULL,
            ]
            .iter()
            .map(|&k| passes[k])
            .sum::<f64>()
                / t,
            // The deferred grass's light is the draw's shading, moved to compute.
            rendering: (passes[timing::DRAW]
                + passes[timing::LATE_DRAW]
                + passes[timing::GRASS_LIGHT])
                / t,
            shadows: passes[timing::SHADOWS] / t,
            // The TAA blend is the tone mapping's first step.
            tone_map: (passes[timing::TONEMAP] + passes[timing::TAA]) / t,
            billboards: passes[timing::BILLBOARDS] / t,
            tiles: passes[timing::TILES] / t,
            overlays: (passes[timing::OVERLAY] + passes[timing::UPSCALE]) / t,
            far_gain: passes[timing::FAR_GAIN] / t,
            skinning: passes[timing::SKINNING] / t,
        }
    });
    Ok(Measured {
        blades: BladeCounts::new(renderer.buffers.count, &last),
        gpu_ms,
        wall_ms: wall / n,
        gpu_bytes: renderer.gpu_bytes(),
        image: target.read_image(gpu)?,
        spheres_considered: last.spheres_considered().into(),
        sphere_tests: u64::from(last.patch_sphere_pairs) * u64::from(renderer.buffers.patch_size),
        resets: resets.into(),
        scopes: renderer.take_trace(gpu)?,
        work,
    })
}

/// Draws one more frame with the work counted (pipeline statistics and the grass's
/// coverage) and reads it back: counting adds a measurement pass, so the timed frames are
/// not counted. `None` when the adapter cannot count.
pub(super) fn count_frame(
    gpu: &Gpu,
    renderer: &mut GrassRenderer,
    camera: &CameraView,
    target: &Target,
) -> Result<Option<WorkReport>> {
    if !renderer.count_work(gpu, true) {
        return Ok(None);
    }
    world_frame(gpu, renderer, BENCH_DT, *camera, target)?;
    let work = renderer.read_work(gpu)?;
    renderer.count_work(gpu, false);
    Ok(work.map(|w| WorkReport::of(&w, renderer.samples())))
}

/// The whole frame as every bench mode reports it: the mean GPU sum of every timed pass
/// (the wind solver's included; `None` without timestamps) and the mean wall clock per
/// frame, submit to read-back.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct FrameTimes {
    pub gpu_ms: Option<f64>,
    pub wall_ms: f64,
}

/// Runs `warmup + frames` frames of `renderer` from `camera` into `target`, handing each
/// measured frame's stats to `each`, and returns the frame's times.
pub(super) fn run_frames(
    gpu: &Gpu,
    renderer: &mut GrassRenderer,
    camera: &CameraView,
    target: &Target,
    (warmup, frames): (u32, u32),
    mut each: impl FnMut(&sward::render::FrameStats),
) -> Result<FrameTimes> {
    let (mut wall, mut gpu_sum, mut timed) = (0.0, 0.0, 0u32);
    for i in 0..warmup + frames {
        let start = Instant::now();
        world_frame(gpu, renderer, BENCH_DT, *camera, target)?;
        let stats = renderer.stats(gpu)?;
        let elapsed = start.elapsed().as_secs_f64() * 1000.0;
        if i < warmup {
            continue;
        }
        wall += elapsed;
        if let Some(ms) = stats.pass_ms {
            let wind: f64 = stats.wind_ms.iter().flatten().map(|(_, m)| m).sum();
            gpu_sum += ms.iter().sum::<f64>() + wind;
            timed += 1;
        }
        each(&stats);
    }
    Ok(FrameTimes {
        gpu_ms: (timed > 0).then(|| gpu_sum / f64::from(timed)),
        wall_ms: wall / f64::from(frames.max(1)),
    })
}
