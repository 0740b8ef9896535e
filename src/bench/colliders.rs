//! `sward bench --colliders 100,1000,10000`: what the colliders' hierarchy (Qiu et al.;
//! `physics.collision_hierarchy`) saves against the flat lists, measured in one process on
//! the same frames (issue 14, point 3b).
//!
//! For each count N the scene's colliders are replaced by N static spheres scattered over a
//! disk around the camera's target (seeded; radii chosen so that they cover a fifth of the
//! disk whatever N is, each sunk to 40 % of its radius into the ground, so that every count
//! presses the same share of the grass), the mesh objects' packings are dropped, and the
//! same frames run three times from the same start with a fresh renderer, every patch in
//! reach stepped every frame (`culling.physics_throttle` 1, so that all three step the
//! same blades):
//! - `flat`: each stepped patch's broad-phase list of nearby spheres (every sphere when more
//!   than 63 are near), tested by each of its blades;
//! - `hierarchy_exact`: the hierarchy walked down to the colliders by every blade;
//! - `hierarchy`: the hierarchy at the scene's `hierarchy_precision_distance` (coarser far
//!   from the camera).
//!
//! Reported per run: the GPU milliseconds of the blade update and of the patch pass (which
//! holds the broad phase) per frame from timestamp queries, the blades stepped per frame, the
//! update's nanoseconds per stepped blade, the broad phase's list entries per stepped patch,
//! the blades the colliders crushed, and how far the final tips lie from the flat run's.

use glam::Vec3;
use serde::Serialize;

use super::{opt, utc_now, BenchOptions};
use sward::error::{Error, Result};
use sward::gpu::Gpu;
use sward::render::camera::CameraView;
use sward::render::target::Target;
use sward::render::timing;
use sward::scene::{MeshCollider, Motion, Scene, Sphere};
use sward::session::Session;
use sward::sim::layout::{Blade, MAX_SPHERES};

/// Share of the disk the spheres' footprints cover.
const COVER: f32 = 0.2;
/// How deep a sphere sits: its centre this many radii above the ground.
const SINK: f32 = 0.4;
/// The disk's radius at most (metres), and at most the blade radius.
const DISK: f32 = 15.0;

/// `--colliders 100,1000,10000`: increasing counts, each 1 ..= `MAX_SPHERES`.
pub fn parse_collider_counts(text: &str) -> Result<Vec<usize>> {
    let allowed = format!(
        "allowed: whole numbers from 1 to {MAX_SPHERES}, increasing, comma-separated (e.g. \
         --colliders 100,1000,10000)"
    );
    let mut out: Vec<usize> = Vec::new();
    for (i, item) in text.split(',').enumerate() {
        let n = item
            .trim()
            .parse::<usize>()
            .ok()
            .filter(|n| (1..=MAX_SPHERES).contains(n))
            .ok_or_else(|| {
                Error::Invalid(format!(
                    "--colliders entry {} ({:?}) is not a sphere count: {allowed}",
                    i + 1,
                    item.trim()
                ))
            })?;
        if out.last().is_some_and(|&last| n <= last) {
            return Err(Error::Invalid(format!(
                "--colliders entry {} ({n}) does not increase: {allowed}",
                i + 1
            )));
        }
        out.push(n);
    }
    Ok(out)
}

/// Checks the flags that do not go with `--colliders`.
pub fn check_collider_options(o: &BenchOptions) -> Result<()> {
    if o.flight
        || !o.sweep.is_empty()
        || o.images.is_some()
        || o.trace.is_some()
        || !o.pressure_solvers.is_empty()
    {
        return Err(Error::Invalid(
            "--colliders times the collisions alone: it does not go with --flight, --sweep, \
             --images, --trace or --pressure-solvers"
                .into(),
        ));
    }
    Ok(())
}

/// One run's figures.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ColliderRun {
    /// `flat`, `hierarchy_exact` or `hierarchy`.
    pub name: String,
    /// Mean GPU ms of the blade update per frame (`None` without timestamps).
    pub update_ms: Option<f64>,
    /// Mean GPU ms of the patch pass (patch culling and the broad phase) per frame.
    pub patches_ms: Option<f64>,
    /// Mean blade slots stepped per frame (the update's chunks of 64).
    pub stepped_blades: f64,
    /// `update_ms` per stepped blade, in nanoseconds.
    pub ns_per_stepped_blade: Option<f64>,
    /// Mean broad-phase list entries per stepped patch (spheres, or the hierarchy's nodes;
    /// a list that overflowed counts every sphere or node).
    pub list_entries_per_patch: f64,
    /// Blades whose collision strength η is above zero at the end.
    pub crushed: u64,
    /// Largest and mean distance of the final tips from the flat run's (metres).
    pub max_tip_difference: f64,
    pub mean_tip_difference: f64,
    /// Blades whose final tip lies more than 1 cm from the flat run's.
    pub tips_apart_1cm: u64,
    /// The whole frame: GPU sum of every pass and wall clock.
    pub frame: super::measure::FrameTimes,
}

/// The runs at one sphere count.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ColliderCount {
    pub spheres: usize,
    /// The spheres' radius (metres).
    pub radius: f32,
    /// Levels of the hierarchy below its root.
    pub hierarchy_depth: u32,
    pub runs: Vec<ColliderRun>,
}

/// Everything `sward bench --colliders` measured.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ColliderBenchReport {
    pub adapter: String,
    pub date: String,
    pub scene: String,
    pub blades: u64,
    pub frames: u32,
    pub warmup: u32,
    pub size: (u32, u32),
    /// The disk the spheres lie in: centre (x, z) and radius.
    pub disk: (f32, f32, f32),
    pub precision_distance: f32,
    pub timestamps: bool,
    pub collider_costs: Vec<ColliderCount>,
}

/// splitmix64: the spheres' seeded positions.
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

fn unit(k: u64) -> f32 {
    (mix(k) >> 40) as f32 / (1u64 << 24) as f32
}

/// `n` static spheres over the disk (centre, radius) on `session`'s terrain.
pub fn scattered_spheres(session: &Session, n: usize, disk: (f32, f32, f32)) -> Vec<Sphere> {
    let (cx, cz, big) = disk;
    let r = (COVER * big * big / n as f32).sqrt();
    (0..n as u64)
        .map(|k| {
            // Uniform over the disk: the radius as the square root of a uniform number.
            let d = big * unit(2 * k).sqrt();
            let a = std::f32::consts::TAU * unit(2 * k + 1);
            let (x, z) = (cx + d * a.cos(), cz + d * a.sin());
            Sphere {
                center: (x, session.terrain.height(x, z) + SINK * r, z),
                radius: r,
                motion: Motion::Static,
            }
        })
        .collect()
}

struct Mode {
    name: &'static str,
    hierarchy: bool,
    exact: bool,
}

const MODES: [Mode; 3] = [
    Mode {
        name: "flat",
        hierarchy: false,
        exact: false,
    },
    Mode {
        name: "hierarchy_exact",
        hierarchy: true,
        exact: true,
    },
    Mode {
        name: "hierarchy",
        hierarchy: true,
        exact: false,
    },
];

fn tip(b: &Blade) -> Vec3 {
    Vec3::new(b.v2_width[0], b.v2_width[1], b.v2_width[2])
}

struct RunResult {
    run: ColliderRun,
    blades: Vec<Blade>,
    /// Blades on the GPU (the whole field, or a streamed field's pool).
    count: u64,
}

fn run_mode(
    gpu: &Gpu,
    session: &Session,
    scene: Scene,
    target: &Target,
    o: &BenchOptions,
    mode: &Mode,
) -> Result<RunResult> {
    let camera = CameraView::from_scene(&scene.camera);
    let mut renderer = super::measure::fresh_renderer(gpu, session, scene)?;
    let (mut update, mut patches, mut timed) = (0.0, 0.0, 0u32);
    let (mut stepped, mut entries, mut patches_stepped) = (0.0f64, 0.0f64, 0.0f64);
    let frame = super::measure::run_frames(
        gpu,
        &mut renderer,
        &camera,
        target,
        (o.warmup, o.frames),
        |stats| {
            let c = &stats.counters;
            stepped += f64::from(c.updated_chunks) * f64::from(sward::sim::layout::UPDATE_CHUNK);
            patches_stepped += f64::from(c.updated_patches);
            entries += f64::from(c.patch_sphere_pairs);
            if let Some(ms) = stats.pass_ms {
                update += ms[timing::UPDATE];
                patches += ms[timing::PATCHES];
                timed += 1;
            }
        },
    )?;
    let n = f64::from(o.frames.max(1));
    let t = f64::from(timed.max(1));
    let (blades, states) = renderer.buffers.read(gpu)?;
    let update_ms = (timed > 0).then_some(update / t);
    let run = ColliderRun {
        name: mode.name.into(),
        update_ms,
        patches_ms: (timed > 0).then_some(patches / t),
        stepped_blades: stepped / n,
        ns_per_stepped_blade: update_ms
            .filter(|_| stepped > 0.0)
            .map(|ms| ms * 1e6 / (stepped / n)),
        list_entries_per_patch: if patches_stepped > 0.0 {
            entries / patches_stepped
        } else {
            0.0
        },
        crushed: states.iter().filter(|s| s.rest_eta[3] > 0.0).count() as u64,
        max_tip_difference: 0.0,
        mean_tip_difference: 0.0,
        tips_apart_1cm: 0,
        frame,
    };
    let count = u64::from(renderer.buffers.count);
    Ok(RunResult { run, blades, count })
}

/// Runs the three modes at every count of `counts`.
pub fn run_collider_bench(o: &BenchOptions, counts: &[usize]) -> Result<ColliderBenchReport> {
    check_collider_options(o)?;
    let date = utc_now();
    let super::Start {
        scene,
        scene_name,
        gpu,
        ..
    } = super::start(o, [])?;
    let target = Target::new(&gpu, o.size.0, o.size.1)?;
    let mut base = scene;
    base.physics.collisions = true;
    // Every patch in reach steps every frame, so that the three walks step the same blades
    // and the exact walk is exact everywhere (a throttled patch walks one level coarser).
    base.culling.physics_throttle = 1;
    for object in &mut base.objects {
        object.collider = MeshCollider::None;
    }
    let session = Session::new(base, None, Some(&gpu))?;
    eprintln!("{}", session.describe_field());
    let target_point = session.scene.camera.target;
    let big = DISK.min(session.scene.culling.max_distance.max(1.0));
    let disk = (target_point.0, target_point.2, big);
    let precision = session.scene.physics.hierarchy_precision_distance;
    let mut costs = Vec::new();
    let mut timestamps = true;
    let mut blade_count = 0;
    for &n in counts {
        let spheres = scattered_spheres(&session, n, disk);
        let radius = spheres[0].radius;
        let mut scene = session.scene.clone();
        scene.colliders = spheres;
        let depth = sward::sim::bvh::depth(&sward::sim::bvh::build(
            &sward::sim::colliders::spheres_at(&scene.colliders, &session.terrain, 0.0),
        ));
        let mut runs: Vec<RunResult> = Vec::new();
        for mode in &MODES {
            eprintln!(
                "bench: {n} spheres of {radius:.3} m, {} ({} warm-up + {} frames)",
                mode.name, o.warmup, o.frames
            );
            let mut s = scene.clone();
            s.physics.collision_hierarchy = mode.hierarchy;
            if mode.exact {
                s.physics.hierarchy_precision_distance = 1e6;
            }
            let mut r = run_mode(&gpu, &session, s, &target, o, mode)?;
            blade_count = r.count;
            timestamps &= r.run.update_ms.is_some();
            if let Some(flat) = runs.first() {
                let d: Vec<f32> = flat
                    .blades
                    .iter()
                    .zip(&r.blades)
                    .map(|(a, b)| tip(a).distance(tip(b)))
                    .collect();
                r.run.max_tip_difference = d.iter().copied().fold(0.0f32, f32::max).into();
                r.run.mean_tip_difference =
                    d.iter().map(|&x| f64::from(x)).sum::<f64>() / d.len().max(1) as f64;
                r.run.tips_apart_1cm = d.iter().filter(|&&x| x > 0.01).count() as u64;
            }
            runs.push(r);
        }
        costs.push(ColliderCount {
            spheres: n,
            radius,
            hierarchy_depth: depth,
            runs: runs.into_iter().map(|r| r.run).collect(),
        });
    }
    Ok(ColliderBenchReport {
        adapter: gpu.describe(),
        date,
        scene: scene_name,
        blades: blade_count,
        frames: o.frames,
        warmup: o.warmup,
        size: o.size,
        disk,
        precision_distance: precision,
        timestamps,
        collider_costs: costs,
    })
}

/// The report as a table.
pub fn format_colliders(r: &ColliderBenchReport) -> String {
    let mut out = format!(
        "sward bench --colliders: {} on {} ({})\n{} blades, {} frames after {} warm-up at \
         {}x{}; spheres over a disk of {:.1} m around ({:.1}, {:.1}); hierarchy precision \
         distance {} m{}\n\n",
        r.scene,
        r.adapter,
        r.date,
        r.blades,
        r.frames,
        r.warmup,
        r.size.0,
        r.size.1,
        r.disk.2,
        r.disk.0,
        r.disk.1,
        r.precision_distance,
        if r.timestamps {
            ""
        } else {
            " (no GPU timestamps: no times)"
        },
    );
    out.push_str(&format!(
        "{:>7} {:>8} {:<16} {:>10} {:>10} {:>10} {:>9} {:>9} {:>8} {:>9} {:>9} {:>8} {:>12} {:>9}\n",
        "spheres",
        "radius",
        "walk",
        "update ms",
        "patches ms",
        "stepped",
        "ns/blade",
        "entries",
        "crushed",
        "max diff",
        "mean diff",
        ">1 cm",
        "frame GPU ms",
        "wall ms"
    ));
    for c in &r.collider_costs {
        for run in &c.runs {
            out.push_str(&format!(
                "{:>7} {:>8.3} {:<16} {:>10} {:>10} {:>10.0} {:>9} {:>9.1} {:>8} {:>9.4} {:>9.5} {:>8} {:>12} {:>9.2}\n",
                c.spheres,
                c.radius,
                run.name,
                opt(run.update_ms, 2),
                opt(run.patches_ms, 2),
                run.stepped_blades,
                opt(run.ns_per_stepped_blade, 1),
                run.list_entries_per_patch,
                run.crushed,
                run.max_tip_difference,
                run.mean_tip_difference,
                run.tips_apart_1cm,
                opt(run.frame.gpu_ms, 2),
                run.frame.wall_ms,
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_parse_and_bad_ones_name_the_entry() {
        assert_eq!(
            parse_collider_counts("100,1000,10000").unwrap(),
            vec![100, 1000, 10000]
        );
        for (bad, what) in [
            ("0", "entry 1"),
            ("10,x", "entry 2"),
            ("100,50", "does not increase"),
            ("100000", "16384"),
            ("", "entry 1"),
        ] {
            let e = parse_collider_counts(bad).unwrap_err().to_string();
            assert!(e.contains(what) && e.contains("--colliders"), "{bad}: {e}");
        }
    }
}
