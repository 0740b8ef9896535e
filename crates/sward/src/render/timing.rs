//! Per-pass GPU times through `wgpu-profiler`: each timed pass is a profiler scope whose
//! two timestamps are the pass's own timestamp writes (so `TIMESTAMP_QUERY` alone is
//! enough). After a frame is submitted, [`GpuTimer::end_frame`] hands it to the profiler;
//! its results come back once the GPU has finished it, as the last frame's per-pass times
//! (`FrameStats::pass_ms`) and, while a trace is recorded, as every frame's scopes for the
//! Chrome trace of `--trace` ([`chrome_trace`], which Perfetto and chrome://tracing open).

use wgpu_profiler::{GpuProfiler, GpuProfilerQuery, GpuProfilerSettings, GpuTimerQueryResult};

use crate::error::{Error, Result};
use crate::gpu::queries::{PassQueries, WorkCounter};
use crate::gpu::{Gpu, MAX_FRAMES_IN_FLIGHT};

/// The passes that are timed, by scope name: the occluders' depth pass, the depth pyramid,
/// the patch pass, the blade update, the blade cull and the draw; then, with grass
/// occlusion, the pyramid again, the late cull and the late draw; and the generation of the
/// tiles entering a streamed field, the billboards' cull, the sun's shadow maps, the
/// tone mapping, the overlays and the window's upscale; the deferred grass shading (its
/// pixel list and its light, one scope); the window's panel (egui); the temporal
/// anti-aliasing; the animated objects' skinning; and the far levels' light gain measured
/// on the lit blades. A pass that did not run in a frame reads 0.
pub const PASSES: [&str; 20] = [
    "occluders",
    "pyramid",
    "patches",
    "update",
    "cull",
    "draw",
    "late pyramid",
    "late cull",
    "late draw",
    "tiles",
    "billboards",
    "shadows",
    "tone map",
    "overlay",
    "upscale",
    "grass light",
    "ui",
    "taa",
    "skinning",
    "far gain",
];
/// Indices into [`PASSES`].
pub const OCCLUDERS: usize = 0;
/// The depth pyramid built from the occluders' depth ("pyramid").
pub const PYRAMID: usize = 1;
/// The patch pass: patch boxes culled, indirect dispatches written ("patches").
pub const PATCHES: usize = 2;
/// The blade update (physics step) ("update").
pub const UPDATE: usize = 3;
/// The blade cull ("cull").
pub const CULL: usize = 4;
/// The main draw: sky, terrain, colliders and the grass ("draw").
pub const DRAW: usize = 5;
/// With grass occlusion, the pyramid rebuilt over the grass drawn early ("late pyramid").
pub const LATE_PYRAMID: usize = 6;
/// With grass occlusion, the late cull of the blades not seen last frame ("late cull").
pub const LATE_CULL: usize = 7;
/// With grass occlusion, the draw of the late cull's blades ("late draw").
pub const LATE_DRAW: usize = 8;
/// Generation of the tiles entering a streamed field ("tiles").
pub const TILES: usize = 9;
/// The billboards' cull ("billboards").
pub const BILLBOARDS: usize = 10;
/// The sun's shadow cascades (all of them, one scope).
pub const SHADOWS: usize = 11;
/// Tone mapping the scene target into the output (`post::ToneMap`).
pub const TONEMAP: usize = 12;
/// What is drawn over the scene: the wind overlay, the window's guide arrows.
pub const OVERLAY: usize = 13;
/// The window's upscale of the 3D passes' scaled image to its size.
pub const UPSCALE: usize = 14;
/// The deferred grass shading's two compute passes (`render::deferred`): the grass pixels
/// listed, then lit. With the deferred path the draw scopes draw the visibility buffer.
pub const GRASS_LIGHT: usize = 15;
/// The window's panel: egui's render pass over the upscaled frame.
pub const UI: usize = 16;
/// Temporal anti-aliasing: the frame blended with its history (`render::taa`).
pub const TAA: usize = 17;
/// The animated mesh objects' skinning (`render::skinning`).
pub const SKINNING: usize = 18;
/// The far levels' light gain measured on the lit blades (`far_gain`).
pub const FAR_GAIN: usize = 19;

/// Frames the profiler may hold before their results are read: a trace keeps every frame,
/// so this covers the window's few frames in flight with room to spare (beyond it the
/// profiler drops the newest frame, never blocks).
const PENDING_FRAMES: usize = 16;

/// The profiler and what came back from it.
pub struct GpuTimer {
    profiler: GpuProfiler,
    /// Milliseconds per pass of the last finished frame.
    last: Option<[f64; PASSES.len()]>,
    /// Every finished frame's scopes (seconds on the GPU clock), while recording a trace.
    trace: Option<Vec<GpuTimerQueryResult>>,
    /// Frames handed to the profiler whose results were not taken yet.
    pending: usize,
}

impl GpuTimer {
    /// `None` when the device has no timestamp queries.
    pub fn new(gpu: &Gpu) -> Option<Self> {
        if !gpu.timestamps {
            return None;
        }
        let settings = GpuProfilerSettings {
            enable_timer_queries: true,
            // Debug groups would need the same encoder at both ends of a pass scope.
            enable_debug_groups: false,
            max_num_pending_frames: PENDING_FRAMES,
        };
        let profiler = GpuProfiler::new(&gpu.device, settings)
            .map_err(|e| log::warn!("GPU timing is off: {e}"))
            .ok()?;
        Some(Self {
            profiler,
            last: None,
            trace: None,
            pending: 0,
        })
    }

    /// Opens the scope of pass `index` of [`PASSES`]; its timestamp writes go on the pass
    /// ([`GpuProfilerQuery::compute_pass_timestamp_writes`] or the render one), and
    /// [`GpuTimer::end`] closes it after the pass.
    pub fn begin(&self, encoder: &mut wgpu::CommandEncoder, index: usize) -> GpuProfilerQuery {
        self.profiler.begin_pass_query(PASSES[index], encoder)
    }

    /// Closes a scope opened by [`GpuTimer::begin`].
    pub fn end(&self, encoder: &mut wgpu::CommandEncoder, query: GpuProfilerQuery) {
        self.profiler.end_query(encoder, query);
    }

    /// Records the resolve of this frame's queries; call after the timed passes, before
    /// `finish`.
    pub fn resolve(&mut self, encoder: &mut wgpu::CommandEncoder) {
        self.profiler.resolve_queries(encoder);
    }

    /// Ends the profiler's frame: call once its command buffer was submitted and the
    /// frame pacer has waited (`gpu::FramePacer::submitted`). The frames the pacer has
    /// waited for are collected; the [`MAX_FRAMES_IN_FLIGHT`] newest stay pending even when
    /// they happen to be finished already, so the profiler holds the same number of query
    /// pools whatever the GPU's speed (3: two pending, one recording). Collecting whatever
    /// had finished made that number depend on the load of the machine (2 or 3 pools), and
    /// the memory test could not tell a bounded pool from a leak.
    pub fn end_frame(&mut self, gpu: &Gpu) {
        match self.profiler.end_frame() {
            Ok(()) => self.pending += 1,
            Err(e) => log::warn!("GPU timing of this frame is lost: {e}"),
        }
        // A trace keeps every frame: waiting here keeps the profiler from dropping frames
        // whose results are not back yet (the pass times themselves are unaffected).
        if self.trace.is_some() {
            if let Err(e) = crate::gpu::wait_idle(&gpu.device) {
                log::warn!("GPU timing: {e}");
            }
            self.collect(gpu, 0);
        } else {
            self.collect(gpu, MAX_FRAMES_IN_FLIGHT);
        }
    }

    /// Takes finished frames' results from the profiler, oldest first, until `keep` frames
    /// are left pending (or the oldest is not finished).
    fn collect(&mut self, gpu: &Gpu, keep: usize) {
        let period = gpu.queue.get_timestamp_period();
        while self.pending > keep {
            let Some(frame) = self.profiler.process_finished_frame(period) else {
                break;
            };
            self.pending -= 1;
            self.last = Some(pass_ms(&frame));
            if let Some(trace) = &mut self.trace {
                trace.extend(frame);
            }
        }
    }

    /// Milliseconds per pass of the last submitted frame (blocks until the GPU is idle);
    /// 0 for passes that did not run in it.
    pub fn read_ms(&mut self, gpu: &Gpu) -> Result<[f64; PASSES.len()]> {
        crate::gpu::wait_idle(&gpu.device)?;
        self.collect(gpu, 0);
        Ok(self.last.unwrap_or_default())
    }

    /// Starts keeping every frame's scopes for a trace (from the next finished frame on).
    pub fn record_trace(&mut self) {
        self.trace.get_or_insert_with(Vec::new);
    }

    /// The recorded scopes of every frame finished so far (blocks until the GPU is idle).
    pub fn take_trace(&mut self, gpu: &Gpu) -> Result<Vec<GpuTimerQueryResult>> {
        crate::gpu::wait_idle(&gpu.device)?;
        self.collect(gpu, 0);
        Ok(self.trace.replace(Vec::new()).unwrap_or_default())
    }
}

/// Milliseconds per pass of one frame's scopes (a pass timed twice adds up).
fn pass_ms(frame: &[GpuTimerQueryResult]) -> [f64; PASSES.len()] {
    let mut out = [0.0; PASSES.len()];
    for scope in frame {
        if let (Some(i), Some(t)) = (PASSES.iter().position(|p| *p == scope.label), &scope.time) {
            out[i] += (t.end - t.start).max(0.0) * 1000.0;
        }
    }
    out
}

/// Writes `tracks` as a Chrome trace to `path` through `outputs` (staged: renamed into
/// place with the run's other outputs). `timestamps`: whether the device had them; without,
/// the trace is still written, with no GPU events, and a note says why.
pub fn write_trace(
    outputs: &mut crate::output::Outputs,
    path: &std::path::Path,
    tracks: &[TraceTrack],
    timestamps: bool,
) -> Result<()> {
    if !timestamps {
        eprintln!(
            "--trace {}: this adapter has no timestamp queries, so the trace has no GPU events",
            path.display()
        );
    }
    outputs.write(path, &chrome_trace(tracks)?)
}

/// What measures the frame's passes: the GPU timer and the work counter, either absent.
#[derive(Clone, Copy, Default)]
pub(crate) struct Meters<'a> {
    pub timer: Option<&'a GpuTimer>,
    pub work: Option<&'a WorkCounter>,
}

/// Runs `f` (which records one pass) inside the GPU timer's scope of pass `index` of
/// [`PASSES`], its work counted into the row of the same index; `f` gets the pass's
/// queries (neither, without timer and counter).
pub(crate) fn timed<R>(
    meters: Meters,
    encoder: &mut wgpu::CommandEncoder,
    index: usize,
    f: impl FnOnce(&mut wgpu::CommandEncoder, PassQueries) -> R,
) -> R {
    let query = meters.timer.map(|t| t.begin(encoder, index));
    let out = f(
        encoder,
        PassQueries::new(query.as_ref(), meters.work.map(|w| (w, index))),
    );
    if let (Some(t), Some(q)) = (meters.timer, query) {
        t.end(encoder, q);
    }
    out
}

/// One row of a trace: a name (a benchmark configuration, a run) and its frames' scopes.
pub struct TraceTrack {
    /// The track's thread name in the trace (a configuration or run label).
    pub name: String,
    /// The profiler's scopes of every recorded frame, in frame order; nested scopes
    /// become nested events, and scopes without a time are skipped.
    pub scopes: Vec<GpuTimerQueryResult>,
}

/// A Chrome trace (JSON object format: complete "X" events in microseconds of the GPU
/// clock, one thread per track, named by a metadata event) that Perfetto and
/// chrome://tracing open. The events are those `wgpu_profiler::chrometrace` writes; it
/// only writes to a path, and outputs go through `crate::output` as bytes. Without
/// timestamp queries there are no scopes: the trace is valid and has no pass events.
pub fn chrome_trace(tracks: &[TraceTrack]) -> Result<Vec<u8>> {
    let mut events = Vec::new();
    for (tid, track) in tracks.iter().enumerate() {
        events.push(serde_json::json!({
            "ph": "M", "pid": 0, "tid": tid, "name": "thread_name",
            "args": { "name": track.name },
        }));
        // In frame order (a stack, so pushed reversed).
        let mut stack: Vec<&GpuTimerQueryResult> = track.scopes.iter().rev().collect();
        while let Some(scope) = stack.pop() {
            if let Some(t) = &scope.time {
                events.push(serde_json::json!({
                    "ph": "X", "pid": 0, "tid": tid, "name": scope.label,
                    "ts": t.start * 1e6, "dur": (t.end - t.start).max(0.0) * 1e6,
                }));
            }
            stack.extend(scope.nested_queries.iter().rev());
        }
    }
    let trace = serde_json::json!({ "traceEvents": events, "displayTimeUnit": "ms" });
    serde_json::to_vec_pretty(&trace).map_err(|e| Error::Invalid(format!("trace: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scope(label: &str, start: f64, end: f64) -> GpuTimerQueryResult {
        GpuTimerQueryResult {
            label: label.into(),
            pid: 0,
            tid: std::thread::current().id(),
            time: Some(start..end),
            nested_queries: Vec::new(),
        }
    }

    #[test]
    fn pass_times_add_up_by_name() {
        let frame = [
            scope("cull", 1.0, 1.002),
            scope("draw", 1.002, 1.010),
            scope("unknown", 0.0, 5.0),
        ];
        let ms = pass_ms(&frame);
        assert!((ms[CULL] - 2.0).abs() < 1e-9);
        assert!((ms[DRAW] - 8.0).abs() < 1e-9);
        assert_eq!(ms[UPDATE], 0.0);
    }

    #[test]
    fn trace_is_chrome_json() {
        let tracks = [TraceTrack {
            name: "render".into(),
            scopes: vec![scope("cull", 1.0, 1.5)],
        }];
        let v: serde_json::Value = serde_json::from_slice(&chrome_trace(&tracks).unwrap()).unwrap();
        let events = v["traceEvents"].as_array().unwrap();
        assert_eq!(events[0]["args"]["name"], "render");
        assert_eq!(events[1]["name"], "cull");
        assert_eq!(events[1]["ph"], "X");
        assert_eq!(events[1]["dur"], 500000.0);
        let empty: serde_json::Value = serde_json::from_slice(&chrome_trace(&[]).unwrap()).unwrap();
        assert!(empty["traceEvents"].as_array().unwrap().is_empty());
    }
}
