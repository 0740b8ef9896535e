//! The frame's work, counted: which row of the work counter (`gpu::queries`) each pass
//! counts into, the figures built from the rows (the whole frame, the lit grass's
//! fragments per covered pixel), and the table `render --timings` and the bench print.

use super::timing::{GRASS_LIGHT, LATE_DRAW, PASSES};
use crate::gpu::queries::{Work, WorkFrame};

/// The rows the work counter counts into: a row per timed pass (the same indices), then
/// the wind solver's passes, the lit grass of the main draw (counted apart from the rest
/// of the draw pass, whose row is the ground, sky, objects and billboards), the coverage
/// pass that measures the pixels the grass covers (a measurement, not part of the frame:
/// [`frame_work`] leaves it out), and the deferred shading's pixel list (counted apart
/// from its light, whose row is [`GRASS_LIGHT`]'s).
pub const WORK_ROWS: [&str; PASSES.len() + 4] = {
    let mut rows = [""; PASSES.len() + 4];
    let mut i = 0;
    while i < PASSES.len() {
        rows[i] = PASSES[i];
        i += 1;
    }
    rows[WIND] = "wind";
    rows[LIT_GRASS] = "lit grass";
    rows[COVERAGE] = "coverage";
    rows[GRASS_PIXELS] = "grass pixels";
    rows
};
/// Row of the wind solver's passes ("wind").
pub const WIND: usize = PASSES.len();
/// Row of the main draw's lit grass, counted apart from the rest of the draw pass
/// ("lit grass").
pub const LIT_GRASS: usize = PASSES.len() + 1;
/// Row of the coverage pass that measures the pixels the grass covers; left out of the
/// frame's work ("coverage").
pub const COVERAGE: usize = PASSES.len() + 2;
/// Row of the deferred shading's pixel list ("grass pixels"); its light counts in
/// [`GRASS_LIGHT`]'s row.
pub const GRASS_PIXELS: usize = PASSES.len() + 3;

/// The work of a whole frame: every row but the coverage measurement.
pub fn frame_work(rows: &[Work]) -> Work {
    let mut sum = Work::default();
    for (i, w) in rows.iter().enumerate() {
        if i != COVERAGE {
            sum += *w;
        }
    }
    sum
}

/// The lit grass shading's invocations: drawn forward, the main and late draws' grass
/// fragments; deferred (the pixel list was made), the light's compute invocations (the
/// late draw then writes the visibility buffer, no light). `None` if a row is missing.
pub fn lit_shading(rows: &[Work]) -> Option<u64> {
    let deferred = rows.get(GRASS_PIXELS)?.compute_invocations > 0;
    let late = if deferred {
        0
    } else {
        rows.get(LATE_DRAW)?.fragment_invocations
    };
    Some(
        rows.get(LIT_GRASS)?.fragment_invocations
            + late
            + rows.get(GRASS_LIGHT)?.compute_invocations,
    )
}

/// The lit grass shading's invocations ([`lit_shading`]) per pixel the grass covers: over
/// the coverage pass's samples (per pixel: over `samples`). `None` without a coverage count
/// or with no grass on screen.
pub fn lit_fragments_per_pixel(
    rows: &[Work],
    coverage_samples: Option<u64>,
    samples: u32,
) -> Option<f64> {
    let covered = coverage_samples? as f64 / samples.max(1) as f64;
    let lit = lit_shading(rows)?;
    (covered >= 1.0).then(|| lit as f64 / covered)
}

/// The figures of a counted frame that reports and tests quote: the whole frame's
/// invocations and the lit grass's fragments per covered pixel.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct WorkSummary {
    /// Vertex-shader invocations of the whole frame ([`frame_work`]).
    pub vertex_invocations: u64,
    /// Primitives the clipper let through to rasterisation, whole frame.
    pub primitives: u64,
    /// Fragment-shader invocations (helper lanes included), whole frame.
    pub fragment_invocations: u64,
    /// Compute-shader invocations, whole frame.
    pub compute_invocations: u64,
    /// The lit grass shading's invocations ([`lit_shading`]: forward, the main and late
    /// draws' grass fragments; deferred, the light's compute invocations).
    pub lit_fragments: u64,
    /// Pixels the grass covers in the finished frame.
    pub grass_pixels: u64,
    /// [`lit_fragments_per_pixel`]: lit grass shading invocations per covered pixel;
    /// `None` without a coverage count or with no grass on screen.
    pub lit_fragments_per_pixel: Option<f64>,
}

impl WorkSummary {
    /// The summary of a counted `frame` drawn with `samples` MSAA samples per pixel.
    pub fn of(frame: &WorkFrame, samples: u32) -> Self {
        let all = frame_work(&frame.rows);
        let lit = lit_shading(&frame.rows).unwrap_or(0);
        Self {
            vertex_invocations: all.vertex_invocations,
            primitives: all.primitives,
            fragment_invocations: all.fragment_invocations,
            compute_invocations: all.compute_invocations,
            lit_fragments: lit,
            grass_pixels: frame.coverage_samples.unwrap_or(0) / samples.max(1) as u64,
            lit_fragments_per_pixel: lit_fragments_per_pixel(
                &frame.rows,
                frame.coverage_samples,
                samples,
            ),
        }
    }
}

/// A counted frame as the bench reports it: the summary's figures, and every row that
/// did any work, by name.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct WorkReport {
    /// The whole frame's figures, flattened into the report's top level when serialised.
    #[serde(flatten)]
    pub summary: WorkSummary,
    /// The counts of every row of [`WORK_ROWS`] that did any work, by row name.
    pub passes: std::collections::BTreeMap<&'static str, Work>,
}

impl WorkReport {
    /// The report of a counted `frame` drawn with `samples` MSAA samples per pixel.
    pub fn of(frame: &WorkFrame, samples: u32) -> Self {
        Self {
            summary: WorkSummary::of(frame, samples),
            passes: WORK_ROWS
                .iter()
                .zip(&frame.rows)
                .filter(|(_, w)| **w != Work::default())
                .map(|(n, w)| (*n, *w))
                .collect(),
        }
    }
}

/// The work table: one line per row that did any work, then the frame's total and the lit
/// grass's fragments per covered pixel.
pub fn table(frame: &WorkFrame, samples: u32) -> Vec<String> {
    let mut lines = vec![format!(
        "{:<15} {:>12} {:>12} {:>12} {:>12}",
        "work", "vertex", "primitives", "fragment", "compute"
    )];
    let row = |name: &str, w: &Work| {
        format!(
            "{name:<15} {:>12} {:>12} {:>12} {:>12}",
            w.vertex_invocations, w.primitives, w.fragment_invocations, w.compute_invocations
        )
    };
    for (name, w) in WORK_ROWS.iter().zip(&frame.rows) {
        if *w != Work::default() {
            lines.push(row(name, w));
        }
    }
    lines.push(row("frame", &frame_work(&frame.rows)));
    let s = WorkSummary::of(frame, samples);
    lines.push(match s.lit_fragments_per_pixel {
        Some(r) => format!(
            "lit grass: {} fragments over {} covered pixels = {r:.3} per pixel",
            s.lit_fragments, s.grass_pixels
        ),
        None => "lit grass: no grass on screen".to_string(),
    });
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frag(n: u64) -> Work {
        Work {
            fragment_invocations: n,
            ..Work::default()
        }
    }

    #[test]
    fn lit_fragments_are_the_grass_rows_over_covered_pixels() {
        let mut rows = vec![Work::default(); WORK_ROWS.len()];
        rows[LIT_GRASS] = frag(300);
        rows[LATE_DRAW] = frag(100);
        rows[super::super::timing::DRAW] = frag(5000);
        rows[COVERAGE] = frag(7);
        // 4x MSAA: 800 samples are 200 pixels.
        let r = lit_fragments_per_pixel(&rows, Some(800), 4).unwrap();
        assert!((r - 2.0).abs() < 1e-12);
        assert_eq!(lit_fragments_per_pixel(&rows, Some(0), 1), None);
        assert_eq!(lit_fragments_per_pixel(&rows, None, 1), None);
        // The coverage measurement is not part of the frame.
        assert_eq!(frame_work(&rows).fragment_invocations, 5400);
    }
}
