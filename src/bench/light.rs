//! `sward bench --light`: what the light of issue 16 costs, timed on the same scene and
//! frames in one process, each configuration from a fresh renderer:
//!
//! - `no shadows`: the scene with `light.shadows.enabled` off (the reference of the ratios);
//! - `shadows, no grass casters`: the sun's shadow maps with the terrain, objects and balls
//!   casting but not the blades (`grass_radius` 0);
//! - `shadows`: the scene's shadows as they are (the blades casting within `grass_radius`);
//! - `shadows, no blade terms`: as `shadows` with every blade shading term at 0.
//!
//! Reported per configuration, from timestamp queries: the mean GPU milliseconds per frame
//! of the whole frame, of the shadow cascades, of the colour passes (the early and late
//! draws: terrain, sky, grass, billboards, objects) and of the tone-mapping pass, and the
//! whole frame over the frame without shadows; the wall clock per frame (submit to
//! read-back) and its ratio; and the work of one counted frame (fragment invocations, the
//! lit grass's fragments per covered pixel).

use serde::Serialize;

use super::{opt, opt_ratio as ratio, utc_now, BenchOptions, BENCH_DT};
use sward::commands::world_frame;
use sward::error::{Error, Result};
use sward::render::camera::CameraView;
use sward::render::target::Target;
use sward::render::timing;
use sward::scene::{Scene, Shading};
use sward::session::Session;

/// Checks the flags that do not go with `--light`.
pub fn check_light_options(o: &BenchOptions) -> Result<()> {
    if o.flight
        || o.models
        || !o.sweep.is_empty()
        || o.images.is_some()
        || o.trace.is_some()
        || !o.pressure_solvers.is_empty()
        || !o.colliders.is_empty()
    {
        return Err(Error::Invalid(
            "--light times the light's configurations alone: it does not go with --flight, \
             --models, --sweep, --images, --trace, --pressure-solvers or --colliders"
                .into(),
        ));
    }
    Ok(())
}

/// One configuration's figures.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LightRun {
    pub config: String,
    /// Mean GPU ms per frame of every timed pass (`None` without timestamps).
    pub frame_ms: Option<f64>,
    /// The sun's shadow cascades.
    pub shadows_ms: Option<f64>,
    /// The colour passes (early and late draws, and the deferred grass's light).
    pub draw_ms: Option<f64>,
    /// Tone mapping into the output.
    pub tonemap_ms: Option<f64>,
    /// `frame_ms` over the `no shadows` configuration's.
    pub frame_over_no_shadows: Option<f64>,
    /// Mean wall-clock ms per frame, submit to read-back.
    pub wall_ms: f64,
    /// `wall_ms` over the `no shadows` configuration's.
    pub wall_over_no_shadows: Option<f64>,
    /// One counted frame after the measured ones (`None` without pipeline statistics).
    pub work: Option<sward::render::work::WorkReport>,
}

/// Everything `sward bench --light` measured.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LightBenchReport {
    pub adapter: String,
    pub date: String,
    pub scene: String,
    pub blades: u64,
    pub frames: u32,
    pub warmup: u32,
    pub size: (u32, u32),
    pub timestamps: bool,
    pub configs: Vec<LightRun>,
}

/// The configurations, by name, as changes to the scene.
pub fn configurations(scene: &Scene) -> Vec<(&'static str, Scene)> {
    let mut off = scene.clone();
    off.light.shadows.enabled = false;
    let mut on = scene.clone();
    on.light.shadows.enabled = true;
    let mut no_grass = on.clone();
    no_grass.light.shadows.grass_radius = 0.0;
    let mut flat = on.clone();
    for name in Shading::NAMES {
        if let Some(v) = flat.light.shading.term_mut(name) {
            *v = 0.0;
        }
    }
    vec![
        ("no shadows", off),
        ("shadows, no grass casters", no_grass),
        ("shadows", on),
        ("shadows, no blade terms", flat),
    ]
}

/// Runs the configurations.
pub fn run_light_bench(o: &BenchOptions) -> Result<LightBenchReport> {
    check_light_options(o)?;
    let date = utc_now();
    let super::Start {
        scene,
        scene_name,
        gpu,
        ..
    } = super::start(o, [])?;
    let target = Target::new(&gpu, o.size.0, o.size.1)?;
    let session = Session::new(scene, None, Some(&gpu))?;
    eprintln!("{}", session.describe_field());
    let camera = CameraView::from_scene(&session.scene.camera);
    let mut runs: Vec<LightRun> = Vec::new();
    let mut blades = 0;
    let mut timestamps = true;
    for (name, scene) in configurations(&session.scene) {
        eprintln!("bench: {name} ({} warm-up + {} frames)", o.warmup, o.frames);
        let mut renderer = super::measure::fresh_renderer(&gpu, &session, scene)?;
        blades = u64::from(renderer.buffers.count);
        // Sums of the frame, shadows, draw and tone-map milliseconds.
        let mut sums = [0.0f64; 4];
        let mut timed = 0u32;
        let mut wall = 0.0;
        for i in 0..o.warmup + o.frames {
            let start = std::time::Instant::now();
            world_frame(&gpu, &mut renderer, BENCH_DT, camera, &target)?;
            let stats = renderer.stats(&gpu)?;
            let elapsed = start.elapsed().as_secs_f64() * 1000.0;
            if i < o.warmup {
                continue;
            }
            wall += elapsed;
            if let Some(ms) = stats.pass_ms {
                let wind: f64 = stats.wind_ms.iter().flatten().map(|(_, m)| m).sum();
                sums[0] += ms.iter().sum::<f64>() + wind;
                sums[1] += ms[timing::SHADOWS];
                sums[2] += ms[timing::DRAW] + ms[timing::LATE_DRAW] + ms[timing::GRASS_LIGHT];
                sums[3] += ms[timing::TONEMAP];
                timed += 1;
            }
        }
        timestamps &= timed > 0;
        let mean = |k: usize| (timed > 0).then(|| sums[k] / f64::from(timed));
        let frame_ms = mean(0);
        let reference = runs.first().map_or(frame_ms, |r| r.frame_ms);
        let wall_ms = wall / f64::from(o.frames.max(1));
        let wall_reference = runs.first().map_or(wall_ms, |r| r.wall_ms);
        let work = super::measure::count_frame(&gpu, &mut renderer, &camera, &target)?;
        runs.push(LightRun {
            config: name.into(),
            frame_ms,
            shadows_ms: mean(1),
            draw_ms: mean(2),
            tonemap_ms: mean(3),
            frame_over_no_shadows: ratio(frame_ms, reference),
            wall_ms,
            wall_over_no_shadows: ratio(Some(wall_ms), Some(wall_reference)),
            work,
        });
    }
    Ok(LightBenchReport {
        adapter: gpu.describe(),
        date,
        scene: scene_name,
        blades,
        frames: o.frames,
        warmup: o.warmup,
        size: o.size,
        timestamps,
        configs: runs,
    })
}

/// The report as a table.
pub fn format_light(r: &LightBenchReport) -> String {
    let mut out = format!(
        "sward bench --light: {} on {} ({})\n{} blades, {} frames after {} warm-up at \
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
        "{:<26} {:>9} {:>10} {:>9} {:>11} {:>14} {:>9} {:>14} {:>14} {:>10}\n",
        "configuration",
        "GPU ms",
        "shadows ms",
        "draw ms",
        "tone map ms",
        "/ no shadows",
        "wall ms",
        "/ no shadows",
        "fragments",
        "lit/pixel"
    ));
    for c in &r.configs {
        let work = c.work.as_ref().map(|w| &w.summary);
        out.push_str(&format!(
            "{:<26} {:>9} {:>10} {:>9} {:>11} {:>14} {:>9.2} {:>14} {:>14} {:>10}\n",
            c.config,
            opt(c.frame_ms, 2),
            opt(c.shadows_ms, 2),
            opt(c.draw_ms, 2),
            opt(c.tonemap_ms, 3),
            opt(c.frame_over_no_shadows, 3),
            c.wall_ms,
            opt(c.wall_over_no_shadows, 3),
            work.map_or_else(
                || "n/a".into(),
                |w| super::table::thousands(w.fragment_invocations)
            ),
            opt(work.and_then(|w| w.lit_fragments_per_pixel), 2),
        ));
    }
    out
}
