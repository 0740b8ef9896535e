//! `sward bench --flight`: the camera flies a straight line over the scene (from its eye,
//! along its view direction on the ground, at a constant height above the terrain, at
//! [`FLIGHT_SPEED`]), twice from the same start: once timed, frames back to back, and
//! once with every frame read back for the pop measurement (the reading and comparing
//! would otherwise sit between the timed frames and leave a GPU idle, see `timed_flight`).
//!
//! Reported: GPU and wall frame times (median and 95th percentile), blades drawn, GPU
//! memory, and the **pop ratio**: the largest mean absolute frame-to-frame difference
//! divided by the median one. A smooth flight changes every frame by about the same
//! amount; an object that pops in or out (a level of detail switching, grass appearing at a
//! culling distance) makes one frame differ much more than the rest, and the ratio spikes.
//! A streamed scene (`field.tile_size > 0`) also reports the tiles generated during the
//! flight and the GPU time of their generation pass.
//!
//! The **handover ratio** (issue 27, point 4) measures the pops where they would happen:
//! the mean frame-to-frame difference of the pixels whose ground lies in the band where
//! the blades thin out and the billboards fade in (from where the cards start fading in,
//! half of `culling.max_distance`, to the blades' reach), over that of the other ground
//! pixels. Which ground a pixel sees is
//! found by marching its view ray over the terrain's height function on the CPU, once per
//! block of [`HANDOVER_BLOCK`] pixels. A handover without popping changes no more than
//! the rest of the moving picture: a ratio of about 1 or less.

use std::time::Instant;

use glam::{Vec2, Vec3};
use serde::Serialize;

use super::{BenchOptions, BENCH_DT, MIB};
use sward::commands::world_frame;
use sward::embed::GrassRenderer;
use sward::error::{Error, Result};
use sward::field::HeightField;
use sward::gpu::Gpu;
use sward::output::Outputs;
use sward::render::camera::CameraView;
use sward::render::target::{Target, COLOR_FORMAT};
use sward::render::Renderer;
use sward::scene::Camera;
use sward::scene::Scene;
use sward::session::Session;

/// Flight speed in metres per second: a slow walk-to-jog, where pops are easiest to see.
pub const FLIGHT_SPEED: f32 = 4.0;
/// Side of the pixel blocks whose ground distance one view ray decides.
pub const HANDOVER_BLOCK: u32 = 16;
/// The handover band, in blade radii from the camera (the cards' fade-in and the blades'
/// last levels).
pub const HANDOVER_BAND: (f32, f32) = (sward::render::billboard::FADE_IN.0, 1.0);

/// The report of one flight (JSON keys as the issue names them).
#[derive(Clone, Debug, Serialize)]
pub struct FlightReport {
    pub adapter: String,
    pub date: String,
    pub scene: String,
    pub size: [u32; 2],
    pub frames: u32,
    pub warmup: u32,
    pub dt: f32,
    pub speed_m_per_s: f32,
    /// Whether the adapter had timestamp queries (else the `p50_ms` / `p95_ms` are wall).
    pub timestamps: bool,
    /// GPU frame time, median and 95th percentile (wall time without timestamps).
    pub p50_ms: f64,
    pub p95_ms: f64,
    /// Wall time of a frame (submit to finished), median and 95th percentile.
    pub wall_p50_ms: f64,
    pub wall_p95_ms: f64,
    /// Largest frame-to-frame mean absolute difference over the median one (0–255 scale
    /// per channel); `null` when fewer than three frames were measured.
    pub pop_ratio: Option<f64>,
    pub largest_difference: f64,
    pub median_difference: f64,
    /// Mean frame-to-frame difference of the pixels in the handover band over that of the
    /// other ground pixels (`None` without frame pairs or without pixels in either).
    pub handover_ratio: Option<f64>,
    /// The two means it divides (0–255 per channel).
    pub handover_difference: f64,
    pub elsewhere_difference: f64,
    /// Blades drawn in the last frame, and the mean over the flight.
    pub blades_drawn: u64,
    pub blades_drawn_mean: f64,
    /// Billboards drawn in the last frame.
    pub billboards_drawn: u64,
    /// Tiles of blades generated during the measured frames (0 for a scene that does not
    /// stream), the tiles resident at the end, and the GPU milliseconds of the generation
    /// pass: the mean per frame and per tile generated.
    pub tiles_generated: u64,
    pub tiles_resident: u64,
    pub tile_gen_ms_per_frame: f64,
    pub tile_gen_ms_per_tile: Option<f64>,
    pub gpu_bytes: u64,
    pub gpu_mib: f64,
    pub blades_reset_nonfinite: u64,
}

/// The camera `t` seconds into the flight: the scene camera moved along its view direction
/// projected on the ground, its eye kept at the same height above the terrain below it, the
/// target moved alongside.
pub fn flight_camera(scene: &Camera, terrain: &HeightField, t: f32) -> CameraView {
    let start = CameraView::from_scene(scene);
    let view = start.target - start.eye;
    let heading = Vec2::new(view.x, view.z).normalize_or(Vec2::NEG_Y);
    let offset = heading * FLIGHT_SPEED * t;
    let clearance = start.eye.y - terrain.height(start.eye.x, start.eye.z);
    let eye_xz = Vec2::new(start.eye.x, start.eye.z) + offset;
    let eye = Vec3::new(
        eye_xz.x,
        terrain.height(eye_xz.x, eye_xz.y) + clearance,
        eye_xz.y,
    );
    CameraView {
        eye,
        target: eye + view,
        ..start
    }
}

/// Mean absolute difference of the RGB channels of two images of one size (0–255).
pub fn mean_abs_difference(a: &image::RgbaImage, b: &image::RgbaImage) -> f64 {
    let mut sum = 0u64;
    let mut n = 0u64;
    for (p, q) in a.pixels().zip(b.pixels()) {
        for i in 0..3 {
            sum += u64::from(p[i].abs_diff(q[i]));
            n += 1;
        }
    }
    if n == 0 {
        0.0
    } else {
        sum as f64 / n as f64
    }
}

/// The value below which a fraction `q` of `values` lies (nearest rank; 0 when empty).
pub fn percentile(values: &[f64], q: f64) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let rank = (q.clamp(0.0, 1.0) * v.len() as f64).ceil() as usize;
    v[rank.clamp(1, v.len()) - 1]
}

/// Largest over median of the frame-to-frame differences; `None` with fewer than two
/// differences. A median of (almost) zero — a still picture — counts as 1/1000 so that
/// one change in a still flight still reads as a pop.
pub fn pop_ratio(differences: &[f64]) -> Option<f64> {
    if differences.len() < 2 {
        return None;
    }
    let largest = differences.iter().copied().fold(0.0, f64::max);
    let median = percentile(differences, 0.5).max(1e-3);
    Some(if largest <= 1e-3 {
        1.0
    } else {
        largest / median
    })
}

/// The PNG name of flight frame `i` in `--images DIR`.
pub fn frame_name(i: u32) -> String {
    format!("frame_{i:04}.png")
}

/// Flies the scene's camera for `o.warmup` frames in place, then `o.frames` frames along
/// the line, and reports.
pub fn run_flight(o: &BenchOptions) -> Result<FlightReport> {
    let date = super::utc_now();
    let super::Start {
        mut outputs,
        scene,
        scene_name,
        gpu,
    } = super::start(o, (0..o.frames).map(frame_name))?;
    let target = Target::new(&gpu, o.size.0, o.size.1)?;
    let timed = timed_flight(o, &gpu, &target, scene.clone(), &mut outputs)?;
    let seen = compared_flight(o, &gpu, &target, scene, &mut outputs)?;
    outputs.commit()?;
    let TimedFlight {
        gpu_ms,
        wall_ms,
        drawn,
        ..
    } = &timed;
    let timestamps = gpu_ms.len() == wall_ms.len() && !gpu_ms.is_empty();
    let frame_ms = if timestamps { gpu_ms } else { wall_ms };
    let differences = &seen.differences;
    let handover = seen.handover;
    Ok(FlightReport {
        adapter: gpu.describe(),
        date,
        scene: scene_name,
        size: [o.size.0, o.size.1],
        frames: o.frames,
        warmup: o.warmup,
        dt: BENCH_DT,
        speed_m_per_s: FLIGHT_SPEED,
        timestamps,
        p50_ms: percentile(frame_ms, 0.5),
        p95_ms: percentile(frame_ms, 0.95),
        wall_p50_ms: percentile(wall_ms, 0.5),
        wall_p95_ms: percentile(wall_ms, 0.95),
        pop_ratio: pop_ratio(differences),
        largest_difference: differences.iter().copied().fold(0.0, f64::max),
        median_difference: percentile(differences, 0.5),
        handover_ratio: {
            let m = handover.map(|(s, n)| (n > 0).then(|| s as f64 / (3.0 * n as f64)));
            m[0].zip(m[1]).map(|(a, b)| a / b.max(1e-3))
        },
        handover_difference: handover[0].0 as f64 / (3.0 * handover[0].1.max(1) as f64),
        elsewhere_difference: handover[1].0 as f64 / (3.0 * handover[1].1.max(1) as f64),
        blades_drawn: drawn.last().copied().unwrap_or(0),
        blades_drawn_mean: drawn.iter().sum::<u64>() as f64 / drawn.len().max(1) as f64,
        billboards_drawn: u64::from(timed.last_billboards),
        tiles_generated: timed.tiles_generated,
        tiles_resident: timed.tiles_resident,
        tile_gen_ms_per_frame: timed.tile_ms / f64::from(o.frames.max(1)),
        tile_gen_ms_per_tile: (timed.tiles_generated > 0)
            .then(|| timed.tile_ms / timed.tiles_generated as f64),
        gpu_bytes: timed.gpu_bytes,
        gpu_mib: timed.gpu_bytes as f64 / MIB,
        blades_reset_nonfinite: timed.resets.into(),
    })
}

/// What the timed flight measured.
#[derive(Default)]
struct TimedFlight {
    gpu_ms: Vec<f64>,
    wall_ms: Vec<f64>,
    drawn: Vec<u64>,
    resets: u32,
    last_billboards: u32,
    tiles_generated: u64,
    tiles_resident: u64,
    tile_ms: f64,
    gpu_bytes: u64,
}

/// What the compared flight measured: the frame-to-frame differences, and the sums of the
/// handover band's and the other ground's (`band_differences`).
#[derive(Default)]
struct ComparedFlight {
    differences: Vec<f64>,
    handover: [(u64, u64); 2],
}

/// Frame `i` of a flight after `warmup` frames: its index among the measured frames (0
/// through the warm-up) and its camera, the same in the timed and the compared flight.
fn frame_camera(session: &Session, i: u32, warmup: u32) -> (u32, CameraView) {
    let flying = i.saturating_sub(warmup);
    let t = flying as f32 * BENCH_DT;
    (
        flying,
        flight_camera(&session.scene.camera, &session.terrain, t),
    )
}

/// A fresh session and renderer of `scene` for one flight.
fn flight_renderer(gpu: &Gpu, scene: Scene) -> Result<(Session, GrassRenderer)> {
    let session = Session::new(scene, None, Some(gpu))?;
    let renderer = GrassRenderer::wrap_world(
        gpu,
        Renderer::from_session(gpu, &session, COLOR_FORMAT)?,
        COLOR_FORMAT,
    );
    gpu.check_errors()?;
    Ok((session, renderer))
}

/// The timed flight: frames back to back with nothing read back but the counters, as an
/// application renders them. The pictures are compared in a second flight
/// (`compared_flight`): reading every frame back and marching its view rays on the CPU
/// takes longer than a GPU's frame, and a GPU left idle that long between frames lowers
/// its clock, so timing those frames measured the clock (an NVIDIA H200 gave 74 ms for a
/// prairie frame it renders in 14).
fn timed_flight(
    o: &BenchOptions,
    gpu: &Gpu,
    target: &Target,
    scene: Scene,
    outputs: &mut Outputs,
) -> Result<TimedFlight> {
    let (session, mut renderer) = flight_renderer(gpu, scene)?;
    eprintln!(
        "bench: flight over {} blades, {} warm-up + {} frames at {FLIGHT_SPEED} m/s, timed",
        renderer.buffers.count, o.warmup, o.frames
    );
    let mut t = TimedFlight::default();
    let mut tiles_at_start = 0u64;
    for i in 0..o.warmup + o.frames {
        let (_, camera) = frame_camera(&session, i, o.warmup);
        if o.trace.is_some() && i == o.warmup {
            // The warm-up is left out of the trace as out of the statistics.
            renderer.record_trace();
        }
        let start = Instant::now();
        world_frame(gpu, &mut renderer, BENCH_DT, camera, target)?;
        let stats = renderer.stats(gpu)?;
        let wall = start.elapsed().as_secs_f64() * 1000.0;
        t.resets = stats.blades_reset_nonfinite;
        t.last_billboards = stats.billboards_drawn;
        let total = stats.tiles.map_or(0, |t| t.generated_total);
        if i < o.warmup {
            tiles_at_start = total;
            continue;
        }
        t.tiles_generated = total - tiles_at_start;
        t.tile_ms += stats
            .pass_ms
            .map_or(0.0, |ms| ms[sward::render::timing::TILES]);
        t.wall_ms.push(wall);
        if let Some(ms) = stats.pass_ms {
            let wind: f64 = stats.wind_ms.iter().flatten().map(|(_, m)| m).sum();
            t.gpu_ms.push(ms.iter().sum::<f64>() + wind);
        }
        t.drawn.push(u64::from(stats.counters.drawn()));
    }
    if let Some(path) = &o.trace {
        let tracks = [sward::render::timing::TraceTrack {
            name: "flight".into(),
            scopes: renderer.take_trace(gpu)?,
        }];
        sward::render::timing::write_trace(outputs, path, &tracks, gpu.timestamps)?;
    }
    t.tiles_resident = renderer.tile_stats().map_or(0, |t| t.resident as u64);
    t.gpu_bytes = renderer.gpu_bytes().1;
    Ok(t)
}

/// The compared flight: the same flight from a fresh start, every frame read back,
/// compared with the one before it (whole frame and per ground band) and saved with
/// `--images`.
fn compared_flight(
    o: &BenchOptions,
    gpu: &Gpu,
    target: &Target,
    scene: Scene,
    outputs: &mut Outputs,
) -> Result<ComparedFlight> {
    let (session, mut renderer) = flight_renderer(gpu, scene)?;
    eprintln!("bench: the flight again, each frame read back and compared with the last");
    let size = (target.width, target.height);
    let mut previous: Option<image::RgbaImage> = None;
    let mut seen = ComparedFlight::default();
    let band = {
        let d = session.scene.culling.max_distance;
        let d = if d.is_finite() { d.max(0.0) } else { 0.0 };
        (HANDOVER_BAND.0 * d, HANDOVER_BAND.1 * d)
    };
    for i in 0..o.warmup + o.frames {
        let (flying, camera) = frame_camera(&session, i, o.warmup);
        world_frame(gpu, &mut renderer, BENCH_DT, camera, target)?;
        if i < o.warmup {
            continue;
        }
        let image = target.read_image(gpu)?;
        if let Some(p) = &previous {
            seen.differences.push(mean_abs_difference(p, &image));
            let classes = ground_classes(&session.terrain, &camera, size, band);
            for (k, sum) in band_differences(p, &image, &classes)
                .into_iter()
                .enumerate()
            {
                seen.handover[k].0 += sum.0;
                seen.handover[k].1 += sum.1;
            }
        }
        if let Some(dir) = &o.images {
            outputs.write_png(&dir.join(frame_name(flying)), &image)?;
        }
        previous = Some(image);
    }
    Ok(seen)
}

/// The flight report as text.
pub fn format_flight(r: &FlightReport) -> String {
    let what = if r.timestamps { "GPU" } else { "wall" };
    let pop = r
        .pop_ratio
        .map_or("n/a (fewer than 3 frames)".into(), |p| format!("{p:.2}"));
    let handover = r.handover_ratio.map_or("n/a".into(), |h| format!("{h:.2}"));
    format!(
        "sward bench --flight: {}\nadapter: {}\ndate: {}\n{}x{}, {} frames after {} warm-up \
         frames, dt = 1/30 s, {} m/s\n{what} frame ms: p50 {:.2}, p95 {:.2}\nwall frame ms: \
         p50 {:.2}, p95 {:.2}\npop ratio (largest / median frame-to-frame difference): {pop} \
         ({:.3} / {:.3})\nhandover ratio (band where blades become billboards / other ground): \
         {handover} ({:.3} / {:.3})\nblades drawn: {} (last frame), {:.0} (mean)\nbillboards drawn: {}, \
         tiles generated: {} ({} resident; generation {:.2} GPU ms per frame{})\nGPU memory: \
         {:.1} MiB\nblades reset (non-finite state): {}\n",
        r.scene,
        r.adapter,
        r.date,
        r.size[0],
        r.size[1],
        r.frames,
        r.warmup,
        r.speed_m_per_s,
        r.p50_ms,
        r.p95_ms,
        r.wall_p50_ms,
        r.wall_p95_ms,
        r.largest_difference,
        r.median_difference,
        r.handover_difference,
        r.elsewhere_difference,
        r.blades_drawn,
        r.blades_drawn_mean,
        r.billboards_drawn,
        r.tiles_generated,
        r.tiles_resident,
        r.tile_gen_ms_per_frame,
        r.tile_gen_ms_per_tile
            .map_or(String::new(), |t| format!(", {t:.2} per tile")),
        r.gpu_mib,
        r.blades_reset_nonfinite,
    )
}

/// Which ground each block of [`HANDOVER_BLOCK`] pixels sees (row-major blocks): 0 the
/// handover band (`band`: horizontal distance from the camera, m), 1 other ground, 2 no
/// ground within the far plane (sky).
pub fn ground_classes(
    terrain: &HeightField,
    camera: &CameraView,
    size: (u32, u32),
    band: (f32, f32),
) -> Vec<u8> {
    let (bw, bh) = (
        size.0.div_ceil(HANDOVER_BLOCK),
        size.1.div_ceil(HANDOVER_BLOCK),
    );
    let aspect = size.0 as f32 / size.1.max(1) as f32;
    let inverse = camera.view_proj(aspect).inverse();
    let mut out = Vec::with_capacity((bw * bh) as usize);
    for by in 0..bh {
        for bx in 0..bw {
            let px = ((bx * HANDOVER_BLOCK + HANDOVER_BLOCK / 2).min(size.0 - 1) as f32 + 0.5)
                / size.0 as f32;
            let py = ((by * HANDOVER_BLOCK + HANDOVER_BLOCK / 2).min(size.1 - 1) as f32 + 0.5)
                / size.1 as f32;
            let ndc = glam::Vec4::new(2.0 * px - 1.0, 1.0 - 2.0 * py, 1.0, 1.0);
            let far = inverse * ndc;
            let dir = (far.truncate() / far.w - camera.eye).normalize_or_zero();
            out.push(match ray_ground(terrain, camera.eye, dir, camera.far) {
                Some(p) => {
                    let d = Vec2::new(p.x - camera.eye.x, p.z - camera.eye.z).length();
                    u8::from(!(band.0..=band.1).contains(&d))
                }
                None => 2,
            });
        }
    }
    out
}

/// Where a ray from `eye` along `dir` first meets the terrain within `far` metres: steps
/// of 2 % of the distance walked (at least 5 cm), then bisection.
fn ray_ground(terrain: &HeightField, eye: Vec3, dir: Vec3, far: f32) -> Option<Vec3> {
    let above = |p: Vec3| p.y - terrain.height(p.x, p.z);
    if dir == Vec3::ZERO || above(eye) < 0.0 {
        return None;
    }
    let mut t = 0.0f32;
    while t < far {
        let next = t + (0.02 * t).max(0.05);
        if above(eye + dir * next) < 0.0 {
            let (mut lo, mut hi) = (t, next);
            for _ in 0..12 {
                let mid = 0.5 * (lo + hi);
                if above(eye + dir * mid) < 0.0 {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            return Some(eye + dir * hi);
        }
        t = next;
    }
    None
}

/// Sums of the RGB channel differences and pixel counts of two frames per class of
/// [`ground_classes`]: the handover band and the other ground (the sky is left out).
pub fn band_differences(
    a: &image::RgbaImage,
    b: &image::RgbaImage,
    classes: &[u8],
) -> [(u64, u64); 2] {
    let mut out = [(0u64, 0u64); 2];
    let bw = a.width().div_ceil(HANDOVER_BLOCK);
    for (x, y, p) in a.enumerate_pixels() {
        let class = classes[((y / HANDOVER_BLOCK) * bw + x / HANDOVER_BLOCK) as usize];
        if class < 2 {
            let q = b.get_pixel(x, y);
            let d: u64 = (0..3).map(|i| u64::from(p[i].abs_diff(q[i]))).sum();
            out[class as usize].0 += d;
            out[class as usize].1 += 1;
        }
    }
    out
}

/// Refuses options that mean nothing in a flight.
pub fn check_flight_options(o: &BenchOptions) -> Result<()> {
    if !o.sweep.is_empty() {
        return Err(Error::Invalid(
            "--sweep and --flight do not go together: the sweep times a fixed camera".into(),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_and_the_pop_ratio() {
        let v = [5.0, 1.0, 3.0, 2.0, 4.0];
        assert_eq!(percentile(&v, 0.5), 3.0);
        assert_eq!(percentile(&v, 0.95), 5.0);
        assert_eq!(percentile(&[], 0.5), 0.0);
        assert_eq!(pop_ratio(&[1.0]), None);
        assert_eq!(pop_ratio(&[2.0, 2.0, 2.0]), Some(1.0));
        assert_eq!(pop_ratio(&[1.0, 1.0, 1.0, 9.0]), Some(9.0));
        assert_eq!(pop_ratio(&[0.0, 0.0, 0.0]), Some(1.0));
        assert_eq!(frame_name(7), "frame_0007.png");
    }

    #[test]
    fn the_flight_keeps_its_height_above_the_terrain_and_its_heading() {
        let terrain = HeightField::from_scene(&sward::scene::Terrain::default()).unwrap();
        let camera = Camera::default();
        let start = flight_camera(&camera, &terrain, 0.0);
        assert!((start.eye - Vec3::from(camera.eye)).length() < 1e-4);
        let later = flight_camera(&camera, &terrain, 1.0);
        let moved = Vec2::new(later.eye.x - start.eye.x, later.eye.z - start.eye.z);
        assert!((moved.length() - FLIGHT_SPEED).abs() < 1e-3);
        let clearance = |c: &CameraView| c.eye.y - terrain.height(c.eye.x, c.eye.z);
        assert!((clearance(&later) - clearance(&start)).abs() < 1e-3);
        assert!(((later.target - later.eye) - (start.target - start.eye)).length() < 1e-4);
    }

    #[test]
    fn ground_classes_follow_the_distance_on_flat_ground() {
        let terrain = HeightField::from_scene(&sward::scene::Terrain {
            height: sward::scene::types::HeightSource::Flat,
            ..Default::default()
        })
        .unwrap();
        let camera = CameraView {
            eye: Vec3::new(0.0, 2.0, 0.0),
            target: Vec3::new(0.0, 0.0, -10.0),
            fov_y: 60.0,
            near: 0.05,
            far: 500.0,
        };
        let classes = ground_classes(&terrain, &camera, (64, 64), (30.0, 45.0));
        let column: Vec<u8> = (0..4).map(|by| classes[by * 4 + 1]).collect();
        // Looking down 11.3° with a 60° view, the four block rows' centres look 12° above,
        // then 3.1°, 19.5° and 34.7° below the horizon: the sky, ground 37 m away (in the
        // band), then 5.6 and 2.9 m away.
        assert_eq!(column, [2, 0, 1, 1], "{classes:?}");
        // The differences are summed per class; the sky is left out.
        let a = image::RgbaImage::from_pixel(64, 64, image::Rgba([10, 10, 10, 255]));
        let b = image::RgbaImage::from_pixel(64, 64, image::Rgba([13, 10, 10, 255]));
        let sums = band_differences(&a, &b, &classes);
        let band = classes.iter().filter(|&&c| c == 0).count() as u64 * 256;
        assert_eq!(sums[0], (3 * band, band));
    }

    #[test]
    fn differences_are_per_channel_means() {
        let a = image::RgbaImage::from_pixel(2, 2, image::Rgba([10, 20, 30, 255]));
        let b = image::RgbaImage::from_pixel(2, 2, image::Rgba([13, 20, 27, 0]));
        assert_eq!(mean_abs_difference(&a, &b), 2.0);
        assert_eq!(mean_abs_difference(&a, &a), 0.0);
    }
}
