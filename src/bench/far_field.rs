//! `sward bench --far-field`: how the levels that stand for far blades read against what
//! they replace (issue 27, point 1), in bands of 8 rows (`compare::compare_bands`: mean
//! luminance of the 8-bit values and mean 8×8-block contrast), on the same scene, camera
//! and frames, each configuration from a fresh renderer:
//!
//! - `levels`: the scene as it is (blades thinned by Eq. 20, billboards, far ground);
//! - `blades`: blades out to [`blade_reach`] with no distance thinning (the reference of
//!   `levels`: where `levels` shows thinned blades, billboards or ground, it shows blades);
//! - `billboards to the horizon`: the billboard radius pushed out to the camera's far plane
//!   (the reference of `levels` where `levels` shows the far ground).
//!
//! `--frames` frames are rendered per configuration after `--warmup`; the last one is
//! compared. Reported: every band of each comparison and its worst band, the worst block
//! of a band's rows across an eighth of the width (`compare::compare_blocks`: a band's mean
//! can hide one side of the view brighter and the other darker), and the worst
//! band of `levels` against `blades` along the run ([`checkpoints`]: after 4, 8, 16, …
//! frames): the far levels follow gains measured frame by frame while the wind bends the
//! field from rest, so one frame count is not a settled state.

use serde::Serialize;

use super::band_ground::{band_ground_distances, format_ground};
use super::{utc_now, BenchOptions, BENCH_DT};
use sward::commands::world_frame;
use sward::compare::{
    bands, compare_bands, compare_blocks, diff_bands, differing_pixels, worst_band, worst_block,
    Band, BandDiff, BlockDiff, BAND_LUMINANCE_TOLERANCE,
};
use sward::error::Result;
use sward::render::camera::CameraView;
use sward::render::target::Target;
use sward::scene::Scene;
use sward::session::Session;

/// Checks the flags that do not go with `--far-field`.
pub fn check_far_field_options(o: &BenchOptions) -> Result<()> {
    super::refuse_beside(o, "--far-field", "compares the far levels alone")
}

/// How far the reference draws blades: 1.75 times the scene's blade radius, at least 50 m
/// (the prairie's 28 m gives the 50 m).
pub fn blade_reach(scene: &Scene) -> f32 {
    let d = scene.culling.max_distance;
    if d.is_finite() && d > 0.0 {
        (1.75 * d).max(50.0)
    } else {
        50.0
    }
}

/// One comparison: an image's bands against a reference's.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BandComparison {
    pub image: String,
    pub reference: String,
    /// The reference's bands (luminance, contrast) top to bottom.
    pub reference_bands: Vec<Band>,
    /// The image's difference per band.
    pub diffs: Vec<BandDiff>,
    pub worst: Option<BandDiff>,
    /// Bands within the 5 levels and 30 %.
    pub within: usize,
    /// The block (a band's rows across an eighth of the width, `compare::compare_blocks`)
    /// whose luminance differs most: what the bands' means can hide.
    pub worst_block: Option<BlockDiff>,
    /// Blocks within 5 levels, and all of them.
    pub blocks_within: (usize, usize),
    /// Pixels whose colour differs between the two frames: 0 when the configurations drew
    /// the same frame, and the comparison measured nothing (`compare::differing_pixels`).
    pub differing_pixels: usize,
}

/// The worst band of `levels` against `blades` after `frames` frames (warm-up included).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SeriesPoint {
    pub frames: u32,
    pub worst: Option<BandDiff>,
    /// Bands within the 5 levels and 30 %.
    pub within: usize,
}

/// The frame counts the series compares at, for a run of `total` frames: 4, 8, 16, …
/// below `total`, and `total`.
pub fn checkpoints(total: u32) -> Vec<u32> {
    let mut at: Vec<u32> = std::iter::successors(Some(4u32), |k| k.checked_mul(2))
        .take_while(|&k| k < total)
        .collect();
    at.push(total);
    at
}

/// Everything `sward bench --far-field` measured.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FarFieldReport {
    pub adapter: String,
    pub date: String,
    pub scene: String,
    pub frames: u32,
    pub warmup: u32,
    pub size: (u32, u32),
    /// The reference's blade radius (m).
    pub blade_reach: f32,
    pub comparisons: Vec<BandComparison>,
    /// `levels` against `blades` along the run, at [`checkpoints`].
    pub series: Vec<SeriesPoint>,
    /// The median distance (m) from the camera to the ground each band shows, top to
    /// bottom (`band_ground::band_ground_distances`; `None`: mostly sky).
    pub band_ground: Vec<Option<f32>>,
}

impl FarFieldReport {
    /// The ground distance of the band starting at row `top`, as the tables print it.
    fn ground_at(&self, top: u32) -> String {
        let band = (top / sward::compare::BAND_ROWS) as usize;
        format_ground(self.band_ground.get(band).copied().flatten())
    }
}

/// The configurations, by name.
pub fn configurations(scene: &Scene) -> Vec<(&'static str, Scene)> {
    let mut blades = scene.clone();
    blades.culling.max_distance = blade_reach(scene);
    blades.culling.distance = false;
    let mut horizon = scene.clone();
    horizon.render.billboard_distance = scene.camera.far.max(scene.render.billboard_distance);
    vec![
        ("levels", scene.clone()),
        ("blades", blades),
        ("billboards to the horizon", horizon),
    ]
}

/// Renders the configurations and compares them.
pub fn run_far_field(o: &BenchOptions) -> Result<FarFieldReport> {
    check_far_field_options(o)?;
    let date = utc_now();
    let super::Start {
        scene,
        scene_name,
        gpu,
        ..
    } = super::start(o, [])?;
    let target = Target::new(&gpu, o.size.0, o.size.1)?;
    let reach = blade_reach(&scene);
    let configs = configurations(&scene);
    let total = o.warmup + o.frames;
    let at = checkpoints(total);
    let mut images = Vec::new();
    // The bands of `levels` and `blades` at each checkpoint (their images would hold a
    // frame each).
    let mut along: [Vec<Vec<Band>>; 2] = Default::default();
    let mut band_ground = Vec::new();
    for (k, (name, scene)) in configs.into_iter().enumerate() {
        eprintln!("bench: {name} ({} warm-up + {} frames)", o.warmup, o.frames);
        let session = Session::new(scene.clone(), None, Some(&gpu))?;
        let mut renderer = super::measure::fresh_renderer(&gpu, &session, scene)?;
        let camera = CameraView::from_scene(&session.scene.camera);
        if k == 0 {
            band_ground = band_ground_distances(&camera, o.size, &session.terrain, camera.far);
        }
        for frame in 1..=total {
            world_frame(&gpu, &mut renderer, BENCH_DT, camera, &target)?;
            if k < 2 && frame < total && at.contains(&frame) {
                along[k].push(bands(&target.read_image(&gpu)?));
            }
        }
        let image = target.read_image(&gpu)?;
        if k < 2 {
            along[k].push(bands(&image));
        }
        images.push((name, image));
    }
    let compare = |a: usize, b: usize| -> BandComparison {
        let (image, reference) = (&images[a], &images[b]);
        let diffs = compare_bands(&image.1, &reference.1, 0..o.size.1).unwrap_or_default();
        let blocks = compare_blocks(&image.1, &reference.1, 0..o.size.1).unwrap_or_default();
        let blocks_within = blocks
            .iter()
            .filter(|d| d.luminance.abs() <= BAND_LUMINANCE_TOLERANCE)
            .count();
        BandComparison {
            differing_pixels: differing_pixels(&image.1, &reference.1).unwrap_or(0),
            worst_block: worst_block(&blocks),
            blocks_within: (blocks_within, blocks.len()),
            image: image.0.into(),
            reference: reference.0.into(),
            reference_bands: bands(&reference.1),
            worst: worst_band(&diffs),
            within: diffs.iter().filter(|d| d.within_tolerance()).count(),
            diffs,
        }
    };
    let series = at
        .iter()
        .zip(along[0].iter().zip(&along[1]))
        .map(|(&frames, (image, reference))| {
            let diffs = diff_bands(image, reference, 0..o.size.1);
            SeriesPoint {
                frames,
                worst: worst_band(&diffs),
                within: diffs.iter().filter(|d| d.within_tolerance()).count(),
            }
        })
        .collect();
    Ok(FarFieldReport {
        adapter: gpu.describe(),
        date,
        scene: scene_name,
        frames: o.frames,
        warmup: o.warmup,
        size: o.size,
        blade_reach: reach,
        comparisons: vec![compare(0, 1), compare(0, 2)],
        series,
        band_ground,
    })
}

/// The report as tables, one per comparison.
pub fn format_far_field(r: &FarFieldReport) -> String {
    let mut out = format!(
        "sward bench --far-field: {} on {} ({})\n{} frames after {} warm-up at {}x{}; the \
         reference's blades reach {:.1} m\n",
        r.scene, r.adapter, r.date, r.frames, r.warmup, r.size.0, r.size.1, r.blade_reach
    );
    for c in &r.comparisons {
        out += &format!(
            "\n{} against {} (8-row bands: luminance 0-255, 8x8 block contrast)\n",
            c.image, c.reference
        );
        out += "| band | ground (m) | reference luminance | difference | reference contrast | difference |\n";
        out += "|---|---|---|---|---|---|\n";
        for (d, b) in c.diffs.iter().zip(&c.reference_bands) {
            out += &format!(
                "| {} | {} | {:.1} | {:+.1}{} | {:.1} | {:+.0} % |\n",
                d.top,
                r.ground_at(d.top),
                b.luminance,
                d.luminance,
                if d.within_tolerance() { "" } else { " *" },
                b.contrast,
                100.0 * d.contrast
            );
        }
        if let Some(w) = c.worst {
            out += &format!(
                "worst band: rows {}-{} (ground {} m): {:+.1} levels, contrast {:+.0} %; {} of \
                 {} bands within 5 levels and 30 %\n",
                w.top,
                w.top + sward::compare::BAND_ROWS - 1,
                r.ground_at(w.top),
                w.luminance,
                100.0 * w.contrast,
                c.within,
                c.diffs.len()
            );
        }
        if c.differing_pixels == 0 {
            out += &format!(
                "the two frames are the same in every pixel: {} adds nothing this view shows \
                 (its ground lies behind nearer ground, or the levels reach it already), so \
                 this comparison measures nothing here; look from higher up (--set camera.eye=...) to see it\n",
                c.reference
            );
        }
        if let Some(b) = c.worst_block {
            out += &format!(
                "worst block (8 rows by an eighth of the width): rows {}-{}, eighth {} from the \
                 left: {:+.1} levels; {} of {} blocks within 5 levels\n",
                b.top,
                b.top + sward::compare::BAND_ROWS - 1,
                b.sector + 1,
                b.luminance,
                c.blocks_within.0,
                c.blocks_within.1
            );
        }
    }
    if let Some(c) = r.comparisons.first() {
        out += &format!(
            "\n{} against {} along the run (the worst band after each count of frames)\n\
             | frames | worst band | ground (m) | luminance | contrast | bands within 5 levels and 30 % |\n\
             |---|---|---|---|---|---|\n",
            c.image, c.reference
        );
        for p in &r.series {
            match p.worst {
                Some(w) => {
                    out += &format!(
                        "| {} | rows {}-{} | {} | {:+.1} | {:+.0} % | {} of {} |\n",
                        p.frames,
                        w.top,
                        w.top + sward::compare::BAND_ROWS - 1,
                        r.ground_at(w.top),
                        w.luminance,
                        100.0 * w.contrast,
                        p.within,
                        c.diffs.len()
                    )
                }
                None => out += &format!("| {} | – | – | – | – | – |\n", p.frames),
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::checkpoints;

    #[test]
    fn the_series_doubles_from_four_frames_and_ends_at_the_run() {
        assert_eq!(checkpoints(1), [1]);
        assert_eq!(checkpoints(4), [4]);
        assert_eq!(checkpoints(5), [4, 5]);
        assert_eq!(checkpoints(30), [4, 8, 16, 30]);
        assert_eq!(checkpoints(64), [4, 8, 16, 32, 64]);
        assert_eq!(*checkpoints(u32::MAX).last().unwrap(), u32::MAX);
    }
}
