//! `sward bench --antialiasing` (issue 27, point 5): the same scene and frames with no
//! anti-aliasing, with 4× MSAA and with TAA (`render.taa`), each from a fresh renderer.
//!
//! Reported per configuration:
//! - the frame's cost: GPU sum and wall clock per frame over the measured frames, and the
//!   work of one more frame, counted;
//! - the **flicker**: with the camera still and the wind on, the mean absolute
//!   frame-to-frame difference (0–255 per channel) of the pixels that see the far field
//!   (ground beyond half the blade radius, found by marching each block's view ray over the
//!   height function as `--flight` does), over as many frames again, each read back;
//! - the whole frame's flicker, and the last frame's mean difference from the 4× MSAA one
//!   (how far the anti-aliasing moves the picture from MSAA's: a smeared history shows
//!   here).

use serde::Serialize;

use super::flight::{band_differences, ground_classes, mean_abs_difference};
use super::measure::{count_frame, fresh_renderer, run_frames, FrameTimes};
use super::{BenchOptions, BENCH_DT};
use sward::commands::world_frame;
use sward::error::{Error, Result};
use sward::render::camera::CameraView;
use sward::render::target::Target;
use sward::render::work::WorkReport;
use sward::scene::Scene;
use sward::session::Session;

/// Where the far field starts, in blade radii from the camera.
pub const FAR_FROM: f32 = 0.5;

/// The compared configurations: name, `render.msaa`, `render.taa`.
pub const CONFIGURATIONS: [(&str, u32, bool); 3] =
    [("none", 1, false), ("msaa 4x", 4, false), ("taa", 1, true)];

/// One configuration's figures.
#[derive(Clone, Debug, Serialize)]
pub struct AntialiasConfig {
    pub name: String,
    /// Samples per pixel the 3D passes drew with.
    pub samples: u32,
    #[serde(flatten)]
    pub times: FrameTimes,
    /// GPU milliseconds of the TAA pass per frame (0 without it).
    pub taa_ms: f64,
    /// Mean frame-to-frame difference of the far-field pixels, and of the whole frame.
    pub far_flicker: f64,
    pub frame_flicker: f64,
    /// The last frame's mean difference from the 4× MSAA configuration's.
    pub difference_from_msaa: f64,
    pub work: Option<WorkReport>,
    pub gpu_bytes: u64,
}

/// The report.
#[derive(Clone, Debug, Serialize)]
pub struct AntialiasReport {
    pub adapter: String,
    pub date: String,
    pub scene: String,
    pub size: [u32; 2],
    pub frames: u32,
    pub warmup: u32,
    /// Pixels the far-field flicker is measured over.
    pub far_pixels: u64,
    pub configurations: Vec<AntialiasConfig>,
}

/// Refuses options that mean nothing here.
pub fn check_antialias_options(o: &BenchOptions) -> Result<()> {
    super::refuse_beside(o, "--antialiasing", "compares the anti-aliasing alone")?;
    if o.frames < 2 {
        return Err(Error::Invalid(format!(
            "--frames must be at least 2 with --antialiasing (got {}): the flicker needs \
             pairs of frames",
            o.frames
        )));
    }
    Ok(())
}

/// Runs the three configurations.
pub fn run_antialias(o: &BenchOptions) -> Result<AntialiasReport> {
    check_antialias_options(o)?;
    let date = super::utc_now();
    let super::Start {
        scene,
        scene_name,
        gpu,
        ..
    } = super::start(o, [])?;
    let target = Target::new(&gpu, o.size.0, o.size.1)?;
    let size = (target.width, target.height);
    let reach = super::far_field::blade_reach(&scene);
    let session = Session::new(scene.clone(), None, Some(&gpu))?;
    let camera = CameraView::from_scene(&session.scene.camera);
    let classes = ground_classes(
        &session.terrain,
        &camera,
        size,
        (FAR_FROM * reach, f32::INFINITY),
    );
    let mut out = Vec::new();
    let mut last_images = Vec::new();
    let mut far_pixels = 0;
    for (name, msaa, taa) in CONFIGURATIONS {
        eprintln!(
            "bench: {name} ({} warm-up + {} timed + {} read-back frames)",
            o.warmup, o.frames, o.frames
        );
        let mut s: Scene = scene.clone();
        s.render.msaa = msaa;
        s.render.taa = taa;
        let mut renderer = fresh_renderer(&gpu, &session, s)?;
        let mut taa_ms = 0.0;
        let times = run_frames(
            &gpu,
            &mut renderer,
            &camera,
            &target,
            (o.warmup, o.frames),
            |stats| {
                taa_ms += stats
                    .pass_ms
                    .map_or(0.0, |ms| ms[sward::render::timing::TAA]);
            },
        )?;
        let work = count_frame(&gpu, &mut renderer, &camera, &target)?;
        let (mut far, mut whole) = ((0u64, 0u64), 0.0);
        let mut previous: Option<image::RgbaImage> = None;
        for _ in 0..o.frames {
            world_frame(&gpu, &mut renderer, BENCH_DT, camera, &target)?;
            let image = target.read_image(&gpu)?;
            if let Some(p) = &previous {
                // Class 0 of the band: the far field.
                let [band, _] = band_differences(p, &image, &classes);
                far.0 += band.0;
                far.1 += band.1;
                whole += mean_abs_difference(p, &image);
            }
            previous = Some(image);
        }
        let pairs = f64::from(o.frames - 1);
        far_pixels = far.1 / u64::from(o.frames - 1);
        out.push(AntialiasConfig {
            name: name.into(),
            samples: renderer.samples(),
            times,
            taa_ms: taa_ms / f64::from(o.frames),
            far_flicker: far.0 as f64 / (3.0 * far.1.max(1) as f64),
            frame_flicker: whole / pairs,
            difference_from_msaa: 0.0,
            work,
            gpu_bytes: renderer.gpu_bytes().1,
        });
        last_images.push(previous.expect("at least two frames"));
    }
    let msaa = CONFIGURATIONS
        .iter()
        .position(|c| c.1 > 1)
        .expect("one configuration has MSAA");
    for (c, image) in out.iter_mut().zip(&last_images) {
        c.difference_from_msaa = mean_abs_difference(image, &last_images[msaa]);
    }
    Ok(AntialiasReport {
        adapter: gpu.describe(),
        date,
        scene: scene_name,
        size: [o.size.0, o.size.1],
        frames: o.frames,
        warmup: o.warmup,
        far_pixels,
        configurations: out,
    })
}

/// The report as a table.
pub fn format_antialias(r: &AntialiasReport) -> String {
    let mut s = format!(
        "sward bench --antialiasing: {}\nadapter: {}\ndate: {}\n{}x{}, {} warm-up + {} timed \
         frames, then {} frames read back (camera still, wind on)\nfar field: ground beyond \
         {FAR_FROM} of the blade radius, {} pixels\n\n| | samples | GPU ms | wall ms | TAA ms | \
         far flicker | frame flicker | from MSAA 4x | fragments |\n|---|---|---|---|---|---|---|---|---|\n",
        r.scene,
        r.adapter,
        r.date,
        r.size[0],
        r.size[1],
        r.warmup,
        r.frames,
        r.frames,
        r.far_pixels,
    );
    for c in &r.configurations {
        let gpu = c.times.gpu_ms.map_or("n/a".into(), |g| format!("{g:.1}"));
        let fragments = c
            .work
            .as_ref()
            .map_or("n/a".into(), |w| w.summary.fragment_invocations.to_string());
        s.push_str(&format!(
            "| {} | {} | {gpu} | {:.1} | {:.2} | {:.3} | {:.3} | {:.2} | {fragments} |\n",
            c.name,
            c.samples,
            c.times.wall_ms,
            c.taa_ms,
            c.far_flicker,
            c.frame_flicker,
            c.difference_from_msaa,
        ));
    }
    s
}
