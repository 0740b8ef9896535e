//! What a counted pass records besides its commands: its timestamp writes (a
//! `wgpu-profiler` scope) and its work, counted by pipeline-statistics queries
//! ([`WorkCounter`]): vertex-shader, clipper, primitive, fragment-shader and
//! compute-shader invocations. Times depend on the machine and its load; the invocation
//! counts depend only on what the frame asked the GPU to do, so they are the measure of
//! cost that tests can hold a frame to.
//!
//! Each pass takes a [`PassQueries`]: its timestamp writes go into the pass descriptor,
//! and [`PassQueries::begin`] / [`PassQueries::end`] bracket the commands that are
//! counted, into a row of the counter (the renderer's passes; the rows mean nothing here).
//! A pass may count several stretches, into different rows (the draw pass counts its lit
//! grass apart from the ground and sky).
//!
//! Counting is asked for ([`WorkCounter::begin_frame`]), not always on: the bench counts
//! its own frames apart from the timed ones, and a frame that is not counted records no
//! query. The results come back through a small ring of mapped buffers, without stalling
//! the frame that follows.

use std::cell::{Cell, RefCell};
use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::Arc;

use wgpu_profiler::GpuProfilerQuery;

use super::Gpu;
use crate::error::Result;

/// The statistics every counted stretch records, in the order a resolve writes them.
pub const STATISTICS: wgpu::PipelineStatisticsTypes = wgpu::PipelineStatisticsTypes::all();
/// `u64`s per counted stretch (one per statistic).
const VALUES: usize = 5;
/// Stretches a frame may count: the renderer's passes, a pyramid level each, a shadow
/// cascade each, and the draw pass's pieces, with room to spare. Beyond it a stretch is
/// not counted and a warning says so once.
pub const CAPACITY: u32 = 128;
/// Counted frames whose results may be on their way back at once.
const RING: usize = 3;

/// The work of one pass (or of all of them, added up).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct Work {
    /// Vertex-shader invocations (after the vertex cache, for indexed draws).
    pub vertex_invocations: u64,
    /// Primitives the vertex stage handed to the clipper.
    pub clipper_invocations: u64,
    /// Primitives the clipper let through to rasterisation.
    pub primitives: u64,
    /// Fragment-shader invocations (2x2 quads: helpers included).
    pub fragment_invocations: u64,
    /// Compute-shader invocations (workgroups times their size).
    pub compute_invocations: u64,
}

impl Work {
    fn from_values(v: &[u64]) -> Self {
        Self {
            vertex_invocations: v[0],
            clipper_invocations: v[1],
            primitives: v[2],
            fragment_invocations: v[3],
            compute_invocations: v[4],
        }
    }

    /// Every invocation of every stage.
    pub fn invocations(&self) -> u64 {
        self.vertex_invocations + self.fragment_invocations + self.compute_invocations
    }
}

impl std::ops::AddAssign for Work {
    fn add_assign(&mut self, o: Self) {
        self.vertex_invocations += o.vertex_invocations;
        self.clipper_invocations += o.clipper_invocations;
        self.primitives += o.primitives;
        self.fragment_invocations += o.fragment_invocations;
        self.compute_invocations += o.compute_invocations;
    }
}

/// One counted frame: the work of each row, and the samples the coverage query passed
/// (`None` when the frame ran none).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WorkFrame {
    /// The work of each row of the counter, the sum of the stretches counted into it.
    pub rows: Vec<Work>,
    /// Samples the coverage pass's occlusion query passed; `None` when the frame ran none.
    pub coverage_samples: Option<u64>,
}

/// A pass whose commands can be counted (render and compute passes).
pub trait CountedPass {
    /// Starts a pipeline-statistics query into `index` of `set`.
    fn begin_statistics(&mut self, set: &wgpu::QuerySet, index: u32);
    /// Ends the open pipeline-statistics query.
    fn end_statistics(&mut self);
}

impl CountedPass for wgpu::RenderPass<'_> {
    fn begin_statistics(&mut self, set: &wgpu::QuerySet, index: u32) {
        self.begin_pipeline_statistics_query(set, index);
    }
    fn end_statistics(&mut self) {
        self.end_pipeline_statistics_query();
    }
}

impl CountedPass for wgpu::ComputePass<'_> {
    fn begin_statistics(&mut self, set: &wgpu::QuerySet, index: u32) {
        self.begin_pipeline_statistics_query(set, index);
    }
    fn end_statistics(&mut self) {
        self.end_pipeline_statistics_query();
    }
}

/// A readback buffer of the ring and where it stands.
struct Readback {
    buffer: wgpu::Buffer,
    /// [`FREE`], [`RECORDED`], [`MAPPING`], [`MAPPED`] or [`FAILED`].
    state: Arc<AtomicU8>,
    /// The row of each stretch the frame counted, in slot order.
    rows: Vec<usize>,
    coverage: bool,
    /// The counted frame's number: the newest frame read back wins.
    frame: u64,
}

const FREE: u8 = 0;
const RECORDED: u8 = 1;
const MAPPING: u8 = 2;
const MAPPED: u8 = 3;
const FAILED: u8 = 4;

/// The frame being recorded: its ring entry, and the stretches counted so far.
#[derive(Default)]
struct Recording {
    entry: Option<usize>,
    rows: Vec<usize>,
    /// A stretch is open (between `begin` and `end`): statistics queries do not nest.
    open: bool,
    coverage: bool,
    overflowed: bool,
}

/// Pipeline-statistics queries over a frame's passes, and an occlusion query for the
/// samples a coverage pass finds (see the renderer's lit-fragments-per-pixel figure).
pub struct WorkCounter {
    statistics: wgpu::QuerySet,
    coverage: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    ring: Vec<Readback>,
    recording: RefCell<Recording>,
    warned: Cell<bool>,
    rows: usize,
    last: Option<WorkFrame>,
    /// Frames resolved so far, and the number of the one in `last`.
    frames: u64,
    last_frame: u64,
}

/// Bytes of a ring buffer: every slot's values, then the coverage sample count.
const BYTES: u64 = (CAPACITY as u64 * VALUES as u64 + 1) * 8;

impl WorkCounter {
    /// `None` when the device has no pipeline-statistics queries. `rows`: how many rows
    /// the frame's stretches are counted into.
    pub fn new(gpu: &Gpu, rows: usize) -> Option<Self> {
        if !gpu.pipeline_statistics {
            return None;
        }
        let device = &gpu.device;
        let statistics = device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("sward.work.statistics"),
            ty: wgpu::QueryType::PipelineStatistics(STATISTICS),
            count: CAPACITY,
        });
        let coverage = device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("sward.work.coverage"),
            ty: wgpu::QueryType::Occlusion,
            count: 1,
        });
        let resolve = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.work.resolve"),
            size: BYTES,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let ring = (0..RING)
            .map(|k| Readback {
                buffer: device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(&format!("sward.work.readback{k}")),
                    size: BYTES,
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }),
                state: Arc::new(AtomicU8::new(FREE)),
                rows: Vec::new(),
                coverage: false,
                frame: 0,
            })
            .collect();
        Some(Self {
            statistics,
            coverage,
            resolve,
            ring,
            recording: RefCell::default(),
            warned: Cell::new(false),
            rows,
            last: None,
            frames: 0,
            last_frame: 0,
        })
    }

    /// Starts counting a frame: the passes recorded until [`WorkCounter::resolve`] are
    /// counted. When every ring buffer still waits for the GPU, the frame is not counted.
    pub fn begin_frame(&mut self) {
        let entry = self
            .ring
            .iter()
            .position(|r| r.state.load(Ordering::Acquire) == FREE);
        *self.recording.borrow_mut() = Recording {
            entry,
            ..Recording::default()
        };
    }

    /// Whether the frame being recorded is counted.
    pub fn counting(&self) -> bool {
        self.recording.borrow().entry.is_some()
    }

    /// A slot for a stretch counted into `row`; `None` when the frame is not counted or
    /// full.
    fn open(&self, row: usize) -> Option<u32> {
        let mut r = self.recording.borrow_mut();
        r.entry?;
        debug_assert!(!r.open, "work counter: a counted stretch was not ended");
        if r.open || row >= self.rows {
            return None;
        }
        if r.rows.len() as u32 >= CAPACITY {
            r.overflowed = true;
            if !self.warned.replace(true) {
                log::warn!("work counter: more than {CAPACITY} counted passes in a frame");
            }
            return None;
        }
        r.rows.push(row);
        r.open = true;
        Some(r.rows.len() as u32 - 1)
    }

    /// Closes the open stretch; false when none was open.
    fn close(&self) -> bool {
        std::mem::replace(&mut self.recording.borrow_mut().open, false)
    }

    /// The occlusion query set a coverage pass binds (`occlusion_query_set`) while the
    /// frame is counted; its query 0 is read back as `WorkFrame::coverage_samples`.
    pub fn coverage_set(&self) -> Option<&wgpu::QuerySet> {
        let mut r = self.recording.borrow_mut();
        r.entry?;
        r.coverage = true;
        Some(&self.coverage)
    }

    /// Records the resolve of the frame's queries and the copy into its ring buffer; call
    /// after the counted passes, before `finish`.
    pub fn resolve(&mut self, encoder: &mut wgpu::CommandEncoder) {
        let mut r = self.recording.take();
        let Some(entry) = r.entry else { return };
        if r.open || r.overflowed {
            // Half a frame's counts would read as a cheaper frame.
            log::warn!("work counter: this frame's counts are incomplete and dropped");
            return;
        }
        let n = r.rows.len() as u32;
        if n > 0 {
            encoder.resolve_query_set(&self.statistics, 0..n, &self.resolve, 0);
        }
        if r.coverage {
            let at = CAPACITY as u64 * VALUES as u64 * 8;
            encoder.resolve_query_set(&self.coverage, 0..1, &self.resolve, at);
        }
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.ring[entry].buffer, 0, BYTES);
        self.frames += 1;
        let ring = &mut self.ring[entry];
        ring.frame = self.frames;
        ring.rows = std::mem::take(&mut r.rows);
        ring.coverage = r.coverage;
        ring.state.store(RECORDED, Ordering::Release);
    }

    /// Call once the frame's commands were submitted: its ring buffer is mapped when the
    /// GPU is done with it, and the frames already back are read (without waiting).
    pub fn end_frame(&mut self) {
        for ring in &self.ring {
            if ring
                .state
                .compare_exchange(RECORDED, MAPPING, Ordering::AcqRel, Ordering::Acquire)
                .is_ok()
            {
                let state = ring.state.clone();
                ring.buffer
                    .slice(..)
                    .map_async(wgpu::MapMode::Read, move |result| {
                        let next = if result.is_ok() { MAPPED } else { FAILED };
                        state.store(next, Ordering::Release);
                    });
            }
        }
        self.collect();
    }

    /// Reads every mapped ring buffer and keeps the newest frame among them and `last`.
    fn collect(&mut self) {
        for ring in &mut self.ring {
            match ring.state.load(Ordering::Acquire) {
                MAPPED => {
                    let values: Option<Vec<u64>> =
                        ring.buffer.slice(..).get_mapped_range().ok().map(|bytes| {
                            bytes
                                .chunks_exact(8)
                                .map(|c| u64::from_le_bytes(c.try_into().expect("8 bytes")))
                                .collect()
                        });
                    ring.buffer.unmap();
                    ring.state.store(FREE, Ordering::Release);
                    let Some(values) = values else { continue };
                    if ring.frame < self.last_frame {
                        continue;
                    }
                    self.last_frame = ring.frame;
                    let mut rows = vec![Work::default(); self.rows];
                    for (slot, &row) in ring.rows.iter().enumerate() {
                        rows[row] += Work::from_values(&values[slot * VALUES..(slot + 1) * VALUES]);
                    }
                    self.last = Some(WorkFrame {
                        rows,
                        coverage_samples: ring.coverage.then(|| values[CAPACITY as usize * VALUES]),
                    });
                }
                FAILED => ring.state.store(FREE, Ordering::Release),
                _ => {}
            }
        }
    }

    /// The last counted frame's work (waits for the GPU to finish what was submitted).
    pub fn read(&mut self, gpu: &Gpu) -> Result<Option<WorkFrame>> {
        super::wait_idle(&gpu.device)?;
        self.collect();
        Ok(self.last.clone())
    }

    /// The last counted frame that came back, without waiting.
    pub fn last(&self) -> Option<&WorkFrame> {
        self.last.as_ref()
    }
}

/// The queries of one pass: its timestamp writes (when timed) and the counter row its
/// stretches go into (when counted). Copy it into the functions that record the pass.
#[derive(Clone, Copy, Default)]
pub struct PassQueries<'a> {
    time: Option<&'a GpuProfilerQuery>,
    work: Option<(&'a WorkCounter, usize)>,
}

impl<'a> PassQueries<'a> {
    /// Neither timed nor counted.
    pub const NONE: PassQueries<'static> = PassQueries {
        time: None,
        work: None,
    };

    /// Queries timed by the profiler scope `time` (if any) and counted into row `work.1` of
    /// the counter `work.0` (if any).
    pub fn new(time: Option<&'a GpuProfilerQuery>, work: Option<(&'a WorkCounter, usize)>) -> Self {
        Self { time, work }
    }

    /// The same timer scope, counted into `row` instead.
    pub fn row(self, row: usize) -> Self {
        Self {
            work: self.work.map(|(w, _)| (w, row)),
            ..self
        }
    }

    /// The compute pass's timestamp writes.
    pub fn compute_writes(&self) -> Option<wgpu::ComputePassTimestampWrites<'a>> {
        self.time.and_then(|q| q.compute_pass_timestamp_writes())
    }

    /// The render pass's timestamp writes.
    pub fn render_writes(&self) -> Option<wgpu::RenderPassTimestampWrites<'a>> {
        self.time.and_then(|q| q.render_pass_timestamp_writes())
    }

    /// The timestamp writes of part of a scope recorded as several compute passes: the
    /// first part writes the beginning, the last the end.
    pub fn compute_writes_part(
        &self,
        first: bool,
        last: bool,
    ) -> Option<wgpu::ComputePassTimestampWrites<'a>> {
        self.compute_writes().and_then(|t| {
            let begin = t.beginning_of_pass_write_index.filter(|_| first);
            let end = t.end_of_pass_write_index.filter(|_| last);
            (begin.is_some() || end.is_some()).then_some(wgpu::ComputePassTimestampWrites {
                query_set: t.query_set,
                beginning_of_pass_write_index: begin,
                end_of_pass_write_index: end,
            })
        })
    }

    /// [`PassQueries::compute_writes_part`] for render passes.
    pub fn render_writes_part(
        &self,
        first: bool,
        last: bool,
    ) -> Option<wgpu::RenderPassTimestampWrites<'a>> {
        self.render_writes().and_then(|t| {
            let begin = t.beginning_of_pass_write_index.filter(|_| first);
            let end = t.end_of_pass_write_index.filter(|_| last);
            (begin.is_some() || end.is_some()).then_some(wgpu::RenderPassTimestampWrites {
                query_set: t.query_set,
                beginning_of_pass_write_index: begin,
                end_of_pass_write_index: end,
            })
        })
    }

    /// Starts counting `pass`'s commands (nothing when the frame is not counted).
    pub fn begin(&self, pass: &mut impl CountedPass) {
        if let Some((w, row)) = self.work {
            if let Some(slot) = w.open(row) {
                pass.begin_statistics(&w.statistics, slot);
            }
        }
    }

    /// Ends the stretch [`PassQueries::begin`] started in `pass`.
    pub fn end(&self, pass: &mut impl CountedPass) {
        if let Some((w, _)) = self.work {
            if w.close() {
                pass.end_statistics();
            }
        }
    }

    /// The coverage occlusion query set, when the frame is counted.
    pub fn coverage_set(&self) -> Option<&'a wgpu::QuerySet> {
        self.work.and_then(|(w, _)| w.coverage_set())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn work_adds_up_field_by_field() {
        let mut a = Work::from_values(&[1, 2, 3, 4, 5]);
        a += Work::from_values(&[10, 20, 30, 40, 50]);
        assert_eq!(a, Work::from_values(&[11, 22, 33, 44, 55]));
        assert_eq!(a.invocations(), 11 + 44 + 55);
    }
}
