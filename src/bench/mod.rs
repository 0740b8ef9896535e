//! `sward bench`: the measurements of Jahrmann & Wimmer 2017 (Tables 1–3) and a blade-count
//! sweep in the manner of CWD-Sim (Choi & Sung 2024, Table 2), taken in one process.
//!
//! The paper compares three configurations on "frames having the exact same input data
//! from a fixed reference viewpoint": all features, collision detection disabled, culling
//! disabled. Here each configuration gets a fresh [`sward::render::Renderer`] over the same [`Session`]
//! (same field, same terrain), starts at t = 0 and steps the same frames with the same
//! Δt = 1/30 s and the scene's camera, so the three columns differ only in the feature
//! switched off. After every frame [`sward::render::Renderer::stats`] blocks until the GPU is done and
//! returns the cull counters and the per-pass GPU times (timestamp queries); the first
//! `--warmup` frames are left out of the means (pipeline caches, first-touch allocations,
//! blades settling out of the colliders).
//!
//! Frame time is the sum of the GPU passes (update, cull, draw, plus the wind solver when
//! the scene runs it). The wall-clock time per frame (submit to read-back) is reported
//! beside it and labelled as such: on a software adapter timestamps can miss work that
//! the driver defers, and without timestamp queries it is the only time there is.
//!
//! The blade counts of a column are those of its last frame (one frame's counters, as in
//! the paper, so that drawn + culled = total holds exactly); times are means over the
//! measured frames.

use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use serde::Serialize;

use measure::measure;
use sward::commands::{load, DEFAULT_SCENE_PATH};
use sward::error::{Error, Result};
use sward::gpu::{AdapterChoice, Gpu};
use sward::output::Outputs;
use sward::render::target::Target;
use sward::render::timing;
use sward::scene::Scene;
use sward::session::{check_blade_count, Session, MAX_BLADES};
use sward::sim::layout::{BYTES_PER_BLADE, MAX_SPHERES, WORKGROUP_SIZE};

pub mod antialias;
pub mod band_ground;
pub mod colliders;
pub mod far_field;
pub mod flight;
pub mod gpu_tables;
pub mod light;
mod measure;
pub mod models;
pub mod pressure;
mod report;
mod table;

pub use report::*;
pub use table::{format_report, thousands};

/// Time step of every benchmarked frame (the paper's scenes run at a fixed step too).
pub const BENCH_DT: f32 = 1.0 / 30.0;
/// Largest `--frames`.
pub const MAX_FRAMES: u32 = 100_000;
/// Largest `--warmup`.
pub const MAX_WARMUP: u32 = 10_000;
/// `--warmup` when not given.
pub const DEFAULT_WARMUP: u32 = 5;
/// Largest image side of `--size`.
pub const MAX_SIDE: u32 = 16384;

pub(crate) const MIB: f64 = 1024.0 * 1024.0;

/// What `sward bench` runs, already checked.
#[derive(Clone, Debug)]
pub struct BenchOptions {
    /// Scene file; the built-in meadow when `None`.
    pub scene: Option<PathBuf>,
    /// `--set PATH=VALUE` overrides of the scene.
    pub sets: Vec<String>,
    /// Frames measured per configuration (after the warm-up).
    pub frames: u32,
    /// Frames run before the measured ones and left out of the statistics.
    pub warmup: u32,
    pub size: (u32, u32),
    /// Print one JSON object instead of the table.
    pub json: bool,
    /// Blade counts of the sweep, increasing; empty for no sweep.
    pub sweep: Vec<usize>,
    pub adapter: AdapterChoice,
    /// Folder to save the last all-features frame, the last culling-off frame and their
    /// difference in (`all.png`, `unculled.png`, `difference.png`).
    pub images: Option<PathBuf>,
    /// `--flight`: fly the camera along a line and report frame-time percentiles and pops
    /// instead of the three configurations.
    pub flight: bool,
    /// `--trace FILE`: a Chrome trace of the measured frames' GPU passes.
    pub trace: Option<PathBuf>,
    /// `--pressure-solvers jacobi,multigrid`: time the wind solver alone once per pressure
    /// solver instead of the three configurations (empty: not asked for).
    pub pressure_solvers: Vec<sward::scene::PressureSolver>,
    /// `--colliders 100,1000,10000`: time the collisions against that many spheres, flat
    /// and through the hierarchy, instead of the three configurations (empty: not asked).
    pub colliders: Vec<usize>,
    /// `--models`: time the three blade models on the same frames instead of the three
    /// configurations.
    pub models: bool,
    /// `--light`: time the light's configurations (shadows off and on, with and without
    /// grass casters and blade shading terms) instead of the three configurations.
    pub light: bool,
    /// `--far-field`: compare the far levels with what they replace (8-row bands) instead
    /// of timing the three configurations.
    pub far_field: bool,
    /// `--antialiasing`: compare no anti-aliasing, 4× MSAA and TAA (cost and flicker)
    /// instead of timing the three configurations.
    pub antialiasing: bool,
}

impl BenchOptions {
    /// Checks the flags as typed on the command line. Every error names the flag and the
    /// allowed range.
    pub fn parse(
        scene: Option<PathBuf>,
        frames: &str,
        size: &str,
        warmup: &str,
        sweep: Option<&str>,
        json: bool,
        adapter: AdapterChoice,
    ) -> Result<Self> {
        Ok(Self {
            scene,
            sets: Vec::new(),
            frames: parse_count("--frames", frames, 1, MAX_FRAMES)?,
            warmup: parse_count("--warmup", warmup, 0, MAX_WARMUP)?,
            size: parse_size(size)?,
            json,
            sweep: match sweep {
                Some(s) => parse_sweep(s)?,
                None => Vec::new(),
            },
            adapter,
            images: None,
            flight: false,
            trace: None,
            pressure_solvers: Vec::new(),
            colliders: Vec::new(),
            models: false,
            light: false,
            far_field: false,
            antialiasing: false,
        })
    }

    /// The flags that choose a mode or shape its frames, and whether each is set: what a
    /// mode that runs alone refuses beside it (`refuse_beside`).
    pub fn mode_flags(&self) -> [(&'static str, bool); 10] {
        [
            ("--flight", self.flight),
            ("--models", self.models),
            ("--light", self.light),
            ("--far-field", self.far_field),
            ("--antialiasing", self.antialiasing),
            ("--sweep", !self.sweep.is_empty()),
            ("--images", self.images.is_some()),
            ("--trace", self.trace.is_some()),
            ("--pressure-solvers", !self.pressure_solvers.is_empty()),
            ("--colliders", !self.colliders.is_empty()),
        ]
    }

    /// `--images DIR`: where to save the compared frames; the folder must exist.
    pub fn with_images(mut self, dir: Option<PathBuf>) -> Result<Self> {
        if let Some(d) = &dir {
            if !d.is_dir() {
                return Err(Error::Invalid(format!(
                    "--images {}: not an existing folder",
                    d.display()
                )));
            }
        }
        self.images = dir;
        Ok(self)
    }
}

/// A whole number for `flag` in `lo..=hi`.
pub fn parse_count(flag: &str, text: &str, lo: u32, hi: u32) -> Result<u32> {
    let range = format!("allowed {lo}..={hi}");
    let value: u64 = text
        .trim()
        .parse()
        .map_err(|_| Error::Invalid(format!("{flag} {text:?} is not a whole number: {range}")))?;
    if value < u64::from(lo) || value > u64::from(hi) {
        return Err(Error::Invalid(format!(
            "{flag} {value} is out of range: {range}"
        )));
    }
    Ok(value as u32)
}

/// `--size WIDTHxHEIGHT`, each side in `1..=MAX_SIDE`.
pub fn parse_size(text: &str) -> Result<(u32, u32)> {
    let bad = || {
        Error::Invalid(format!(
            "--size {text:?} is not WIDTHxHEIGHT (e.g. 1280x720): allowed 1..={MAX_SIDE} pixels \
             per side"
        ))
    };
    let (w, h) = text.split_once(['x', 'X']).ok_or_else(bad)?;
    let w: u64 = w.trim().parse().map_err(|_| bad())?;
    let h: u64 = h.trim().parse().map_err(|_| bad())?;
    let side = 1..=u64::from(MAX_SIDE);
    if !side.contains(&w) || !side.contains(&h) {
        return Err(Error::Invalid(format!(
            "--size {w}x{h} is out of range: allowed 1..={MAX_SIDE} pixels per side"
        )));
    }
    Ok((w as u32, h as u32))
}

/// `--sweep N1,N2,…`: blade counts in `1..=MAX_BLADES`, strictly increasing.
pub fn parse_sweep(text: &str) -> Result<Vec<usize>> {
    let allowed = format!(
        "allowed: blade counts 1..={MAX_BLADES}, comma-separated, increasing \
         (e.g. --sweep 100000,200000,400000)"
    );
    if text.trim().is_empty() {
        return Err(Error::Invalid(format!("--sweep is empty: {allowed}")));
    }
    let mut counts: Vec<usize> = Vec::new();
    for (i, item) in text.split(',').enumerate() {
        let item = item.trim();
        // Digit groups are common in blade counts: 100_000 reads as 100000.
        let digits = item.replace('_', "");
        let n: usize = digits.parse().map_err(|_| {
            Error::Invalid(format!(
                "--sweep entry {} ({item:?}) is not a whole number: {allowed}",
                i + 1
            ))
        })?;
        if n == 0 || n > MAX_BLADES {
            return Err(Error::Invalid(format!(
                "--sweep entry {} ({n}) is out of range: {allowed}",
                i + 1
            )));
        }
        if let Some(&last) = counts.last() {
            if n <= last {
                return Err(Error::Invalid(format!(
                    "--sweep entry {} ({n}) is not larger than the one before ({last}): \
                     {allowed}",
                    i + 1
                )));
            }
        }
        counts.push(n);
    }
    Ok(counts)
}

/// The paper's three configurations.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Config {
    /// Collisions and every culling test on.
    All,
    /// `physics.collisions = false`.
    NoCollisions,
    /// Every test of `culling` off.
    NoCulling,
}

impl Config {
    pub const COLUMNS: [Config; 3] = [Config::All, Config::NoCollisions, Config::NoCulling];

    /// Column heading, as in the paper.
    pub fn name(self) -> &'static str {
        match self {
            Config::All => "all features",
            Config::NoCollisions => "collisions off",
            Config::NoCulling => "culling off",
        }
    }

    /// The scene of this configuration. "All features" switches on every test that keeps
    /// the picture, whatever the file says, so that the columns compare like with like.
    /// The distance test (Eq. 20) thins far grass on purpose, which shows; it stays as the
    /// scene says (off by default) and is off with culling off.
    pub fn apply(self, scene: &Scene) -> Scene {
        let mut s = scene.clone();
        let on = self != Config::NoCulling;
        s.physics.collisions = self != Config::NoCollisions;
        s.culling.patches = on;
        s.culling.orientation = on;
        s.culling.frustum = on;
        s.culling.distance = on && scene.culling.distance;
        s.culling.occlusion = on;
        s.culling.grass_occlusion = on;
        // Throttling the physics of unseen patches is culling too; the levels of detail are
        // not (the paper's tessellation stays on with culling off) and stay as the scene
        // says.
        if !on {
            s.culling.physics_throttle = 1;
        }
        s
    }
}

fn fps(frame_ms: f64) -> f64 {
    if frame_ms > 0.0 {
        1000.0 / frame_ms
    } else {
        0.0
    }
}

fn ratio(a: f64, b: f64) -> Option<f64> {
    (b > 0.0 && a.is_finite() && b.is_finite()).then(|| a / b)
}

/// `a / b` where both were measured (the mode reports' ratios to their first row).
fn opt_ratio(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    match (a, b) {
        (Some(a), Some(b)) if b > 0.0 => Some(a / b),
        _ => None,
    }
}

/// A measured figure with `digits` decimals, or "-" where none was measured.
fn opt(v: Option<f64>, digits: usize) -> String {
    v.map_or("-".into(), |x| format!("{x:.digits$}"))
}

fn memory(blades: u64, (blade_bytes, gpu_bytes): (u64, u64)) -> Memory {
    Memory {
        bytes_per_blade: BYTES_PER_BLADE as u64,
        measured_bytes_per_blade: if blades > 0 {
            blade_bytes as f64 / blades as f64
        } else {
            0.0
        },
        blade_bytes,
        gpu_bytes,
        gpu_mib: gpu_bytes as f64 / MIB,
    }
}

/// The sweep's scene: `base` with its density scaled so that the field holds about `count`
/// blades, and a patch size small enough that rounding up to whole patches adds at most
/// 2 % (or one workgroup). Returns the scene and the blade count it generates.
pub fn sweep_scene(base: &Scene, count: usize) -> (Scene, usize) {
    let mut scene = base.clone();
    // A sweep times fields of given blade counts: a streamed field's count follows its
    // radius, not its density × area, so the sweep generates whole fields.
    scene.field.tile_size = 0.0;
    let area = f64::from(scene.terrain.size).powi(2);
    let mut density = (count as f64 / area) as f32;
    // The generator rounds density · size² up: nudge the f32 density down until that
    // product is not above the count, or one extra blade would add a whole patch.
    while f64::from(density) * area > count as f64 && density > 0.0 {
        density = density.next_down();
    }
    scene.field.density = density;
    let wanted = (f64::from(density) * area).ceil().max(1.0) as usize;
    let group = WORKGROUP_SIZE as usize;
    let mut patch = sward::field::effective_patch_size(scene.field.patch_size) as usize;
    let total = |p: usize| wanted.div_ceil(p) * p;
    while patch > group && total(patch) as f64 > wanted as f64 * 1.02 {
        patch -= group;
    }
    scene.field.patch_size = patch as u32;
    (scene, total(patch))
}

/// Colliders in the scene that collide (0 with collisions off).
fn colliders(scene: &Scene) -> u64 {
    if scene.physics.collisions {
        scene.colliders.len().min(MAX_SPHERES) as u64
    } else {
        0
    }
}

/// The files `--images DIR` writes: the all-features frame, the culling-off frame and
/// their difference.
const IMAGE_NAMES: [&str; 3] = ["all.png", "unculled.png", "difference.png"];

/// What every bench run begins with.
pub(super) struct Start {
    /// `--images DIR`'s files, checked (nothing is written yet).
    pub(super) outputs: Outputs,
    /// The scene with its `--set` overrides, and the name the report gives it.
    pub(super) scene: Scene,
    pub(super) scene_name: String,
    pub(super) gpu: Gpu,
}

/// Checks the outputs (`image_names` in `--images DIR`) before any work, loads the scene
/// and opens the adapter.
pub(super) fn start(
    o: &BenchOptions,
    image_names: impl IntoIterator<Item = String>,
) -> Result<Start> {
    let mut outputs = Outputs::new();
    if let Some(scene) = &o.scene {
        outputs.input("--scene", scene)?;
    }
    if let Some(dir) = &o.images {
        for name in image_names {
            outputs.add("--images", &dir.join(name))?;
        }
    }
    if let Some(path) = &o.trace {
        outputs.add("--trace", path)?;
    }
    let scene = load(o.scene.as_deref(), &o.sets)?;
    let scene_name = o
        .scene
        .as_deref()
        .unwrap_or(Path::new(DEFAULT_SCENE_PATH))
        .display()
        .to_string();
    let gpu = Gpu::new(&o.adapter)?;
    eprintln!("adapter: {}", gpu.describe());
    // Every mode draws at --size: refused here, before any target is allocated.
    sward::render::target::Target::check_size(&gpu, "--size", o.size, scene.render.msaa)?;
    Ok(Start {
        outputs,
        scene,
        scene_name,
        gpu,
    })
}

/// Runs the benchmark and returns its report (progress goes to stderr).
pub fn run_bench(o: &BenchOptions) -> Result<BenchReport> {
    let date = utc_now();
    // The three images are checked before any frame and renamed into place together.
    let Start {
        mut outputs,
        scene,
        scene_name,
        gpu,
    } = start(o, IMAGE_NAMES.map(String::from))?;
    // Every count is vetted before the first frame, so a sweep that cannot fit fails now
    // rather than after minutes of measuring.
    for &n in &o.sweep {
        let (_, total) = sweep_scene(&scene, n);
        check_blade_count(&gpu, total as f64).map_err(|e| match e {
            Error::Limits(m) => Error::Limits(format!("--sweep {n}: {m}")),
            other => other,
        })?;
    }
    let target = Target::new(&gpu, o.size.0, o.size.1)?;
    let session = Session::new(scene, None, Some(&gpu))?;
    eprintln!("{}", session.describe_field());
    let mut configurations = Vec::new();
    let mut images = Vec::new();
    let mut tracks = Vec::new();
    let trace = o.trace.is_some();
    for config in Config::COLUMNS {
        eprintln!(
            "bench: {} ({} warm-up + {} frames)",
            config.name(),
            o.warmup,
            o.frames
        );
        let scene = config.apply(&session.scene);
        let spheres = colliders(&scene);
        let mut m = measure(&gpu, &session, scene, &target, o.warmup, o.frames, trace)?;
        let frame_ms = m.frame_ms();
        configurations.push(ConfigReport {
            name: config.name().to_string(),
            fps: fps(frame_ms),
            frame_ms,
            frame_time_source: if m.gpu_ms.is_some() {
                "gpu"
            } else {
                "wall clock"
            }
            .into(),
            wall_ms: m.wall_ms,
            blades: m.blades,
            gpu_ms: m.gpu_ms,
            colliders: spheres,
            colliders_considered: m.spheres_considered,
            sphere_tests_per_blade: if m.blades.stepped > 0 {
                m.sphere_tests as f64 / m.blades.stepped as f64
            } else {
                0.0
            },
            blades_reset_nonfinite: m.resets,
            memory: memory(m.blades.total, m.gpu_bytes),
            work: m.work.take(),
        });
        tracks.push(timing::TraceTrack {
            name: config.name().to_string(),
            scopes: std::mem::take(&mut m.scopes),
        });
        images.push((config, m.image));
    }
    let mut ratios = ratios(&configurations);
    let image = |c: Config| images.iter().find(|(k, _)| *k == c).map(|(_, i)| i);
    if let (Some(all), Some(off)) = (image(Config::All), image(Config::NoCulling)) {
        if let Some(d) = sward::compare::compare(all, off) {
            if let Some(dir) = &o.images {
                for (name, image) in IMAGE_NAMES.iter().zip([all, off, &d.image]) {
                    outputs.write_png(&dir.join(name), image)?;
                }
            }
            ratios.culled_vs_unculled_mean_difference = Some(d.mean);
            ratios.culled_vs_unculled_failing_pixels = Some(d.failing);
            ratios.culled_render_within_snapshot_tolerance = Some(d.within_tolerance());
        }
    }
    let mut sweep = Vec::new();
    let base = Config::All.apply(&session.scene);
    drop(session);
    for &n in &o.sweep {
        let (scene, _) = sweep_scene(&base, n);
        let session = Session::new(scene, None, Some(&gpu))?;
        eprintln!(
            "bench: sweep {n}: {} blades ({} warm-up + {} frames)",
            session.field.blades.len(),
            o.warmup,
            o.frames
        );
        let mut m = measure(
            &gpu,
            &session,
            session.scene.clone(),
            &target,
            o.warmup,
            o.frames,
            trace,
        )?;
        tracks.push(timing::TraceTrack {
            name: format!("sweep {n}"),
            scopes: std::mem::take(&mut m.scopes),
        });
        let frame_ms = m.frame_ms();
        sweep.push(SweepPoint {
            requested: n as u64,
            blades: m.blades.total,
            drawn: m.blades.drawn,
            fps: fps(frame_ms),
            frame_ms,
            wall_ms: m.wall_ms,
            gpu_ms: m.gpu_ms,
            gpu_mib: m.gpu_bytes.1 as f64 / MIB,
            work: m.work.take(),
        });
    }
    if let Some(path) = &o.trace {
        timing::write_trace(&mut outputs, path, &tracks, gpu.timestamps)?;
    }
    // Last, so that a failed sweep leaves no image either; fails (and writes none) if an
    // image could not be made.
    outputs.commit()?;
    Ok(BenchReport {
        adapter: gpu.describe(),
        date,
        scene: scene_name,
        size: [o.size.0, o.size.1],
        frames: o.frames,
        warmup: o.warmup,
        dt: BENCH_DT,
        timestamps: gpu.timestamps,
        configurations,
        ratios,
        sweep,
    })
}

fn ratios(configs: &[ConfigReport]) -> Ratios {
    let find = |c: Config| configs.iter().find(|r| r.name == c.name());
    let (Some(all), Some(off)) = (find(Config::All), find(Config::NoCulling)) else {
        return Ratios::default();
    };
    let b = &all.blades;
    let per_blade = b.culled.saturating_sub(b.culled_patch);
    Ratios {
        culling_off_over_all_frame_time: ratio(off.frame_ms, all.frame_ms),
        culled_over_visible_patch_blades: ratio(per_blade as f64, b.in_visible_patches() as f64),
        physics_per_blade_over_rendering_per_drawn_blade: all.gpu_ms.and_then(|g| {
            let physics = ratio(g.physics, b.stepped as f64)?;
            let rendering = ratio(g.rendering, b.drawn as f64)?;
            ratio(physics, rendering)
        }),
        ..Default::default()
    }
}

/// Refuses mode `flag` beside any other of `o`'s [`BenchOptions::mode_flags`] that is
/// set: "`flag` `what`: it does not go with …", naming every other flag.
pub(super) fn refuse_beside(o: &BenchOptions, flag: &str, what: &str) -> Result<()> {
    let others: Vec<(&str, bool)> = o
        .mode_flags()
        .into_iter()
        .filter(|(name, _)| *name != flag)
        .collect();
    if !others.iter().any(|(_, set)| *set) {
        return Ok(());
    }
    let names: Vec<&str> = others.iter().map(|(name, _)| *name).collect();
    let (last, rest) = names.split_last().expect("other flags");
    Err(Error::Invalid(format!(
        "{flag} {what}: it does not go with {} or {last}",
        rest.join(", ")
    )))
}

/// Runs `sward bench` and prints the table (or the JSON object with `--json`) to stdout.
pub fn bench(o: &BenchOptions) -> Result<()> {
    if o.antialiasing {
        return print_report(
            o.json,
            &antialias::run_antialias(o)?,
            antialias::format_antialias,
        );
    }
    if o.far_field {
        return print_report(
            o.json,
            &far_field::run_far_field(o)?,
            far_field::format_far_field,
        );
    }
    if o.light {
        return print_report(o.json, &light::run_light_bench(o)?, light::format_light);
    }
    if o.models {
        return print_report(o.json, &models::run_model_bench(o)?, models::format_models);
    }
    if !o.colliders.is_empty() {
        return print_report(
            o.json,
            &colliders::run_collider_bench(o, &o.colliders)?,
            colliders::format_colliders,
        );
    }
    if !o.pressure_solvers.is_empty() {
        return print_report(
            o.json,
            &pressure::run_pressure_bench(o)?,
            pressure::format_pressure,
        );
    }
    if o.flight {
        flight::check_flight_options(o)?;
        return print_report(o.json, &flight::run_flight(o)?, flight::format_flight);
    }
    print_report(o.json, &run_bench(o)?, format_report)
}

/// Prints `report` to stdout: one JSON object with `--json`, else the table `table` makes.
fn print_report<T: Serialize>(json: bool, report: &T, table: fn(&T) -> String) -> Result<()> {
    if json {
        let text = serde_json::to_string_pretty(report)
            .map_err(|e| Error::Invalid(format!("cannot encode the report as JSON: {e}")))?;
        println!("{text}");
    } else {
        print!("{}", table(report));
    }
    Ok(())
}

/// The current date and time in UTC, `YYYY-MM-DD HH:MM UTC` (no time-zone database needed).
pub fn utc_now() -> String {
    let secs = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let (y, m, d) = civil_from_days((secs / 86_400) as i64);
    let rem = secs % 86_400;
    format!(
        "{y:04}-{m:02}-{d:02} {:02}:{:02} UTC",
        rem / 3600,
        rem % 3600 / 60
    )
}

/// The proleptic Gregorian date of a day count since 1970-01-01: shift the epoch to
/// 0000-03-01 so that leap days fall at the end of a year, then split into 400-year eras,
/// years of the era and days of the year.
fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let day_of_era = z.rem_euclid(146_097);
    let year_of_era =
        (day_of_era - day_of_era / 1460 + day_of_era / 36_524 - day_of_era / 146_096) / 365;
    let day_of_year = day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
    // Months counted from March: 0 = March … 11 = February.
    let month_from_march = (5 * day_of_year + 2) / 153;
    let day = day_of_year - (153 * month_from_march + 2) / 5 + 1;
    let month = if month_from_march < 10 {
        month_from_march + 3
    } else {
        month_from_march - 9
    };
    let year = year_of_era + era * 400 + i64::from(month <= 2);
    (year, month as u32, day as u32)
}

#[cfg(test)]
mod tests;
