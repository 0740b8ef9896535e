//! `sward bench --models`: the three blade models (`physics.model`: Jahrmann, Verlet, Cwd;
//! issue 15, point 1) timed on the same scene and frames in one process, each from a fresh
//! renderer, every patch in reach stepped every frame (`culling.physics_throttle` 1).
//!
//! Reported per model: the GPU milliseconds per frame of the blade update ("physics": the
//! model's compute pass; for Cwd the stateless pose the culling reads) and of the grass
//! draw (early and late; Cwd bends every vertex there), from timestamp queries; the blades
//! stepped and drawn per frame; nanoseconds per stepped blade and per drawn blade; and the
//! bytes of GPU memory each blade takes (blade, state, visibility, lists, and for Verlet its
//! 64-byte state). Ratios to Jahrmann's come from the same run on the same adapter.

use serde::Serialize;

use super::{opt, opt_ratio as ratio, utc_now, BenchOptions};
use sward::error::{Error, Result};
use sward::render::camera::CameraView;
use sward::render::target::Target;
use sward::render::timing;
use sward::scene::BladeModel;
use sward::session::Session;
use sward::sim::layout::{VerletState, BYTES_PER_BLADE};

/// Checks the flags that do not go with `--models`.
pub fn check_model_options(o: &BenchOptions) -> Result<()> {
    if o.flight
        || o.light
        || !o.sweep.is_empty()
        || o.images.is_some()
        || o.trace.is_some()
        || !o.pressure_solvers.is_empty()
        || !o.colliders.is_empty()
    {
        return Err(Error::Invalid(
            "--models times the blade models alone: it does not go with --flight, --light, \
             --sweep, --images, --trace, --pressure-solvers or --colliders"
                .into(),
        ));
    }
    Ok(())
}

/// One model's figures.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModelRun {
    /// `Jahrmann`, `Verlet` or `Cwd`.
    pub model: String,
    /// Mean GPU ms per frame of the blade update (`None` without timestamps).
    pub physics_ms: Option<f64>,
    /// Mean GPU ms per frame of the grass draws (early and late, with terrain and sky in
    /// the early pass as the frame records them).
    pub draw_ms: Option<f64>,
    pub stepped_blades: f64,
    pub drawn_blades: f64,
    pub ns_per_stepped_blade: Option<f64>,
    pub ns_per_drawn_blade: Option<f64>,
    /// GPU bytes per blade.
    pub bytes_per_blade: u64,
    /// `physics_ms` and `draw_ms` over Jahrmann's.
    pub physics_over_jahrmann: Option<f64>,
    pub draw_over_jahrmann: Option<f64>,
    /// The whole frame: GPU sum of every pass and wall clock.
    pub frame: super::measure::FrameTimes,
}

/// Everything `sward bench --models` measured.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModelBenchReport {
    pub adapter: String,
    pub date: String,
    pub scene: String,
    pub blades: u64,
    pub frames: u32,
    pub warmup: u32,
    pub size: (u32, u32),
    pub timestamps: bool,
    pub models: Vec<ModelRun>,
}

/// GPU bytes per blade of `model`.
pub fn bytes_per_blade(model: BladeModel) -> u64 {
    let verlet = match model {
        BladeModel::Verlet => std::mem::size_of::<VerletState>(),
        _ => 0,
    };
    (BYTES_PER_BLADE + verlet) as u64
}

/// Runs the three models.
pub fn run_model_bench(o: &BenchOptions) -> Result<ModelBenchReport> {
    check_model_options(o)?;
    let date = utc_now();
    let super::Start {
        scene,
        scene_name,
        gpu,
        ..
    } = super::start(o, [])?;
    let target = Target::new(&gpu, o.size.0, o.size.1)?;
    let mut base = scene;
    base.culling.physics_throttle = 1;
    let session = Session::new(base, None, Some(&gpu))?;
    eprintln!("{}", session.describe_field());
    let camera = CameraView::from_scene(&session.scene.camera);
    let mut runs: Vec<ModelRun> = Vec::new();
    let mut blades = 0;
    let mut timestamps = true;
    for model in BladeModel::ALL {
        eprintln!(
            "bench: {} ({} warm-up + {} frames)",
            model.name(),
            o.warmup,
            o.frames
        );
        let mut scene = session.scene.clone();
        scene.physics.model = model;
        let mut renderer = super::measure::fresh_renderer(&gpu, &session, scene)?;
        blades = u64::from(renderer.buffers.count);
        let (mut physics, mut draw, mut timed) = (0.0, 0.0, 0u32);
        let (mut stepped, mut drawn) = (0.0f64, 0.0f64);
        let frame = super::measure::run_frames(
            &gpu,
            &mut renderer,
            &camera,
            &target,
            (o.warmup, o.frames),
            |stats| {
                stepped += f64::from(stats.counters.updated_chunks)
                    * f64::from(sward::sim::layout::UPDATE_CHUNK);
                drawn += f64::from(stats.counters.drawn());
                if let Some(ms) = stats.pass_ms {
                    physics += ms[timing::UPDATE];
                    draw += ms[timing::DRAW] + ms[timing::LATE_DRAW] + ms[timing::GRASS_LIGHT];
                    timed += 1;
                }
            },
        )?;
        timestamps &= timed > 0;
        let n = f64::from(o.frames.max(1));
        let t = f64::from(timed.max(1));
        let physics_ms = (timed > 0).then_some(physics / t);
        let draw_ms = (timed > 0).then_some(draw / t);
        let per = |ms: Option<f64>, count: f64| {
            ms.filter(|_| count > 0.0).map(|ms| ms * 1e6 / (count / n))
        };
        let first = runs.first();
        runs.push(ModelRun {
            model: model.name().into(),
            physics_ms,
            draw_ms,
            stepped_blades: stepped / n,
            drawn_blades: drawn / n,
            ns_per_stepped_blade: per(physics_ms, stepped),
            ns_per_drawn_blade: per(draw_ms, drawn),
            bytes_per_blade: bytes_per_blade(model),
            physics_over_jahrmann: ratio(physics_ms, first.map_or(physics_ms, |f| f.physics_ms)),
            draw_over_jahrmann: ratio(draw_ms, first.map_or(draw_ms, |f| f.draw_ms)),
            frame,
        });
    }
    Ok(ModelBenchReport {
        adapter: gpu.describe(),
        date,
        scene: scene_name,
        blades,
        frames: o.frames,
        warmup: o.warmup,
        size: o.size,
        timestamps,
        models: runs,
    })
}

/// The report as a table.
pub fn format_models(r: &ModelBenchReport) -> String {
    let mut out = format!(
        "sward bench --models: {} on {} ({})\n{} blades, {} frames after {} warm-up at \
         {}x{}{}\n\n",
        r.scene,
        r.adapter,
        r.date,
        r.blades,
        r.frames,
        r.warmup,
        r.size.0,
        r.size.1,
        if r.timestamps {
            ""
        } else {
            " (no GPU timestamps: no times)"
        },
    );
    out.push_str(&format!(
        "{:<9} {:>12} {:>10} {:>10} {:>9} {:>10} {:>9} {:>11} {:>10} {:>8} {:>8} {:>6}\n",
        "model",
        "frame GPU ms",
        "wall ms",
        "physics ms",
        "draw ms",
        "stepped",
        "drawn",
        "ns/stepped",
        "ns/drawn",
        "phys/J",
        "draw/J",
        "B/blade"
    ));
    for m in &r.models {
        out.push_str(&format!(
            "{:<9} {:>12} {:>10.2} {:>10} {:>9} {:>10.0} {:>9.0} {:>11} {:>10} {:>8} {:>8} {:>6}\n",
            m.model,
            opt(m.frame.gpu_ms, 2),
            m.frame.wall_ms,
            opt(m.physics_ms, 2),
            opt(m.draw_ms, 2),
            m.stepped_blades,
            m.drawn_blades,
            opt(m.ns_per_stepped_blade, 1),
            opt(m.ns_per_drawn_blade, 1),
            opt(m.physics_over_jahrmann, 2),
            opt(m.draw_over_jahrmann, 2),
            m.bytes_per_blade
        ));
    }
    out
}
