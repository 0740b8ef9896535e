//! The far levels calibrated on the blades, by measurement (issue 27, point 1): the
//! billboards and the far ground stand for the blades beyond their reach and are lit with
//! the blades' own light model (`far_grass_light`, far_grass.wgsl, which a blade's shading
//! averaged over what a distant eye sees of a canopy), but through an atlas, card coverage
//! and a ground texture of their own, which need not average to it, and the model itself
//! is not the blades (the prairie's blades read 0.95-1.4 times it, more as the wind bends
//! them). Every frame, after its grass is lit, one workgroup
//! (`shaders/far_gain_common.wgsl`) looks at one pixel of each cell of a grid ([`GRID`], a
//! different pixel each frame) and compares, with what the model says at the same points
//! before the fog:
//! - what the blades show a little inside their reach ([`NEAR_RING`], where no card has
//!   faded in yet; the pixels standing on a blade): their ratio to the model;
//! - what the cards and the ground between them show just beyond it ([`RING`]).
//!
//! Two gains follow, both kept in the far state beside the gusts' bend
//! (`terrain::TerrainPass::waves`):
//! - **the light gain** (per colour channel, from word [`GAIN_WORD`]): the far levels should
//!   show the model times the blades' ratio to it (the blades, carried past their reach by
//!   the model's change with distance and view). Their radiance is proportional to the
//!   gain they were lit with, so a measurement corrects it in one step.
//! - **the contrast gain** (word [`CALIBRATION_WORD`] + 3, beside the blades' ratio): the
//!   cards move each texel's luminance from their mean that many times as far (bending
//!   towards black under a fifth of the mean, [`contrast_luma`]), so that the far ring's
//!   pixels vary about their mean (standard deviation of luminance over the mean) as the
//!   near ring's blades do about theirs.
//!
//! - **the far field's distance gain** (word [`DISTANCE_WORD`]): the light gain brings the
//!   ring to the aim, but the cards and the far ground do not change with distance as
//!   blades would (the cards' mip and contrast hand over to the far ground's look, their
//!   levels grow, the ground shows between them). The far field ([`FAR_BIN`]) is measured
//!   against the same aim, kept as a multiplier of the light gain in luminance
//!   ([`distance_gain`]); the ring itself is lit with the light gain alone.
//!
//! Each measurement enters a running mean until there are 1 / [`BLEND`] of them, then moves
//! the gains [`BLEND`] of the way: the jittered pixels average into the field's, and a
//! change of light settles in a few frames without flicker. Until measured both are 1. A
//! host's pass (`embed`, `prepare` / `render`) is not measured: its cards keep both at 1.
//!
//! The prairie (4x MSAA, lit deferred), at 480 x 270 after 4 frames, against blades to
//! 50 m (`sward bench --far-field`): before the gains the cards at 28-50 m read 20-24
//! levels brighter and 67 % flatter than the blades; on the model alone 8-16 levels
//! brighter; on the blades every band within 3.5 levels and 19 % of the blades' contrast
//! (`tests/far_field.rs`; after 30 frames 7.9 levels where the thinned blades stand in front
//! of the first cards).

use glam::{Vec2, Vec3};

use crate::error::Result;
use crate::gpu::Gpu;
use super::far_sectors::{SECTORS, SECTOR_WORD};
use super::light::sky::smoothstep;


/// Columns and rows of the frame's pixels the measurement looks at (8,192 samples: 64 per
/// invocation of its one workgroup), one pixel of each cell, a different one each frame.
/// With 2,048 the near ring's ratio to the model wandered by 6-12 % from frame to frame
/// (the ring holds a few hundred of them), and the gain's running mean with it: on the
/// prairie the worst band along 32 frames went from +4.1, −5.3, −9.2, +5.7 levels (after 4,
/// 8, 16, 32 frames) to +2.8, −4.9, −6.7, −6.2, and without wind from −5.3, −6.7, −6.6, −9.1
/// to −4.0, −5.1, −9.0, −9.9 (bands within 5 levels and 30 %: 248 of 264 to 254). The
/// model is evaluated only for the samples in a ring: the pass went from 1.4 to 2.8 ms of
/// a 1280 × 720 frame on llvmpipe.
pub const GRID: (u32, u32) = (128, 64);

/// How far a frame's measurement moves a gain (after the first, taken as it is).
pub const BLEND: f32 = 0.25;

/// The ring measured, as multiples of the blades' reach: the far levels' first metres.
pub const RING: (f32, f32) = (1.0, 1.5);

/// The ring where the blades are measured, as multiples of their reach: inside the band
/// where the cards fade in (from `billboard::FADE_IN`, half the reach). Only its pixels
/// standing on a blade are measured: the ground between the near blades is soil turning to
/// the far ground's grass (lit with the gain, which it would feed back), and a camera looking
/// down sees more of it there than a grazing view of the far field does. Its outer part,
/// not its first metres: once the fluid wind has bent the prairie the blades' ratio to the
/// model rises steeply within a third of the reach (1.56 at 5-9 m, 1.37 at 9-14 m, 1.29 at
/// 14-20 m and 1.23-1.26 at 28-50 m after 240 frames), and the far levels should show what
/// the blades would far out.
pub const NEAR_RING: (f32, f32) = (0.35, 0.5);

/// The near ring where the frame marks its blades (the deferred shading's alpha,
/// `deferred::BLADE_ALPHA`), as multiples of their reach: reaching past where the cards
/// begin to fade in (the marker tells the blades from them), where the blades' ratio to
/// the model has fallen to what they show farther out. The prairie's blades to 50 m
/// without wind after 8 frames, green over the model by ring: 0.837 at 10-14 m (inside
/// [`NEAR_RING`]), then 0.791, 0.826, 0.791, 0.813 and 0.808 at 14-20, 20-28, 28-35, 35-42
/// and 42-50 m. Aimed from 10-14 m the far levels stood about 5 % above the blades they
/// stand for, and only the cards' contrast hid it (the tone curve takes more off the mean
/// of a texture that varies more). Outer edges from 0.6 to 0.95 of the reach, where few
/// thinned blades stand, read 5-6 levels dark with wind after 64 frames; 0.40-0.60 left the
/// windless prairie's handover band 5.3 levels bright after 4 frames (`sward bench
/// --far-field`, docs/levels.md).
pub const NEAR_RING_MARKED: (f32, f32) = (0.45, 0.65);

/// The near ring looking down on the blades, as multiples of their reach: their outer
/// part. Seen from above the cards fade out (`far_canopy::weight`), so nothing stands among
/// the blades there, and the far levels start where the view's elevation is the blades'
/// outer edge's: the blades' ratio to the model rises with the elevation (the prairie from
/// 19 m up after 16 frames: 1.53 at 20-23 m, where the eye looks down at 60°, 1.30-1.44 at
/// 38-48 m, 25-30°), and a ring at the blades' near edge calibrated the far field on the
/// steepest view of them (+28 levels from 19 m up, its few pixels at the frame's edge).
pub const NEAR_RING_ABOVE: (f32, f32) = (0.85, 0.98);

/// The camera's height over the ground as the rings take it: 0 below the ground or when
/// not a number.
fn ground_height(height: f32) -> f32 {
    if height.is_finite() {
        height.max(0.0)
    } else {
        0.0
    }
}

/// The far ring (m from the camera) for the blades' reach `reach` with the camera
/// `height` metres above the ground under it: [`RING`] of the reach, or of the height when
/// that is larger. From 49 m up with a 28 m reach the ring of 28-42 m holds no ground, the
/// far levels were never measured (their gain 1, the light model's), and the prairie read
/// 12-19 levels darker than a frame whose 50 m reach put its ring on the ground.
pub fn far_ring(reach: f32, height: f32) -> (f32, f32) {
    let h = ground_height(height);
    (
        (RING.0 * reach).max(RING.0 * h),
        (RING.1 * reach).max(RING.1 * h),
    )
}

/// The near ring (m from the camera) for the blades' reach `reach` with the camera
/// `height` metres above the ground under it: [`NEAR_RING`] of the reach for a grazing view
/// of the blades' edge, going over to [`NEAR_RING_ABOVE`] as the view of it looks down (as
/// the cards hand over to the canopy, `far_canopy::weight`).
pub fn near_ring(reach: f32, height: f32) -> (f32, f32) {
    ring_towards_above(NEAR_RING, reach, height)
}

/// The near ring (m) where the frame marks its blades ([`NEAR_RING_MARKED`] of the reach
/// for a grazing view, going over to [`NEAR_RING_ABOVE`] as [`near_ring`] does).
pub fn near_ring_marked(reach: f32, height: f32) -> (f32, f32) {
    ring_towards_above(NEAR_RING_MARKED, reach, height)
}

/// `grazing` (multiples of the reach `reach`) going over to [`NEAR_RING_ABOVE`] as the
/// view of the blades' edge from `height` metres over the ground looks down, in metres.
fn ring_towards_above(grazing: (f32, f32), reach: f32, height: f32) -> (f32, f32) {
    let h = ground_height(height);
    let down = if reach > 0.0 {
        crate::render::far_canopy::weight_at(h / reach)
    } else {
        0.0
    };
    let inner = grazing.0 + (NEAR_RING_ABOVE.0 - grazing.0) * down;
    let outer = grazing.1 + (NEAR_RING_ABOVE.1 - grazing.1) * down;
    (inner * reach, outer * reach)
}

/// The far field's bin, as multiples of the blades' reach (twin of `FAR_BIN`): measured
/// against the aim the ring is brought to, kept as a multiplier of the light gain
/// ([`distance_gain`], [`next_distance_gain`]).
pub const FAR_BIN: (f32, f32) = (2.0, 5.0);

/// Where the multiplier goes over from 1 (the ring, lit with the light gain alone) to the
/// far field's (multiples of the reach; twin of `FAR_RAMP`).
pub const FAR_RAMP: (f32, f32) = (1.5, 2.0);

/// The range the far field's multiplier is kept in (twin of `DISTANCE_GAIN_MIN`,
/// `DISTANCE_GAIN_MAX`). It darkens the far field and never brightens it: the blades' own
/// ratio to the model falls with distance (the prairie unthinned after 64 frames, in
/// luminance: 1.22, 1.18, 1.16 at 10-14, 14-20 and 17.5-25 m with wind; 0.85, 0.83, 0.78
/// without), so cards and ground reading darker against the model than the ring do what
/// the blades would. Brought up to the ring (1.10 with wind, 1.07 without), the prairie's
/// horizon band read 9.5 levels above blades to 50 m; seen from above the field reads
/// bright and the multiplier takes it down (a band 7.8 levels off at 1).
pub const DISTANCE_GAIN_RANGE: (f32, f32) = (0.7, 1.0);

/// Words of the far state holding the cull's count of the gusts' bend at the edge of the
/// blades' reach: the sum of clamp(1.5 |v2 − rest tip| / h, 0, 1) in 1/1024ths, then the
/// blades counted (`count_wave` in cull.wgsl; `mean_wave` in far_grass.wgsl reads them).
pub const BEND_WORDS: usize = 0;

/// Word of the far state holding the far field's distance gain (0 before the first
/// measurement).
pub const DISTANCE_WORD: usize = 2;

/// The range kept of the blades' ratio to the model (twin of `BLADES_MIN`, `BLADES_MAX`).
pub const BLADES_RANGE: (f32, f32) = (0.5, 2.0);

/// The smallest and largest gain kept (twin of `GAIN_MIN`, `GAIN_MAX`).
pub const GAIN_RANGE: (f32, f32) = (0.25, 4.0);

/// The fewest pixels a measurement needs (twin of `GAIN_MIN_SAMPLES`).
pub const MIN_SAMPLES: f32 = 16.0;

/// Word of the far state where the gain starts (rgb, then 1 once measured).
pub const GAIN_WORD: usize = 4;

/// Word of the far state where the blades' ratio to the model (rgb: its running mean,
/// [`next_blades_mean`], 0 before the blades were measured) and the cards' contrast gain
/// (w, 0 before the first measurement) start.
pub const CALIBRATION_WORD: usize = 8;

/// Bytes of the far state.
pub const STATE_BYTES: u64 = 4 * super::far_sectors::STATE_WORDS as u64;

/// One pixel's terms: its radiance without the fog and the model's, both weighed by
/// (1 − f) (twin of `gain_terms`).
pub fn gain_terms(actual: Vec3, sky: Vec3, f: f32, model: Vec3) -> (Vec3, Vec3) {
    let clear = (1.0 - f).clamp(0.0, 1.0);
    ((actual - f * sky).max(Vec3::ZERO), model * clear)
}

/// Luminance weights (Rec. 709) of linear radiance (twin of `LUMA`).
pub const LUMA: Vec3 = Vec3::new(0.2126, 0.7152, 0.0722);

/// The smallest and largest contrast gain kept (twin of `CONTRAST_MIN`, `CONTRAST_MAX`).
pub const CONTRAST_RANGE: (f32, f32) = (0.5, 4.0);

/// The side of the block of texels whose luminance gives a measured pixel its local
/// contrast (twin of `CONTRAST_BLOCK`; [`block_contrast`]).
pub const CONTRAST_BLOCK: u32 = 4;

/// A pixel's local contrast (twin of `block_contrast`): the standard deviation of its
/// block's luminance over the block's mean without the fog, from the block's sum (x) and sum
/// of squares (y) of the frame's (fogged) luminance over [`CONTRAST_BLOCK`]² texels and
/// the fog's luminance `fog` there. The cards' contrast gain matches the contrast between
/// neighbouring pixels, which does not change with the frame's size as the spread of single
/// pixels across a ring does (docs/levels.md).
pub fn block_contrast(block: Vec2, fog: f32) -> f32 {
    // Not finite: kept so, and [`next_contrast`] measures nothing that frame.
    if !(block.is_finite() && fog.is_finite()) {
        return block.x + block.y;
    }
    let n = (CONTRAST_BLOCK * CONTRAST_BLOCK) as f32;
    let m = block.x / n;
    (block.y / n - m * m).max(0.0).sqrt() / (m - fog).max(1e-6)
}

/// A ring's sums: the radiance shown, the model's, the pixels measured, their local
/// contrasts' sum, and every pixel of the ring.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RingSums {
    /// Radiance shown, without the fog, weighed by (1 − f).
    pub shown: Vec3,
    /// The model's radiance, weighed the same.
    pub model: Vec3,
    /// Pixels measured (in the near ring, those standing on a blade).
    pub count: f32,
    /// The pixels' local contrasts ([`block_contrast`]), summed.
    pub contrast: f32,
    /// Every pixel of the ring, measured or not.
    pub pixels: f32,
}

impl RingSums {
    /// Adds one pixel of the ring, and its terms ([`gain_terms`]) and local contrast
    /// ([`block_contrast`]) where it is `measured`: every pixel of the far ring, the near
    /// ring's standing on a blade (above the ground by a tenth of the tallest blade).
    pub fn add(&mut self, terms: (Vec3, Vec3), contrast: f32, measured: bool) {
        self.pixels += 1.0;
        if !measured {
            return;
        }
        self.shown += terms.0;
        self.model += terms.1;
        self.count += 1.0;
        self.contrast += contrast;
    }

    fn measured(&self) -> bool {
        self.count >= MIN_SAMPLES
            && self.shown.min_element() > 1e-6
            && self.model.min_element() > 1e-6
    }

    /// The pixels' mean local contrast (as `next_contrast` takes it).
    pub fn local_contrast(&self) -> f32 {
        self.contrast / self.count.max(1.0)
    }
}

/// The share of the near ring's pixels that must stand on a blade for it to be measured
/// as blades (twin of `BLADES_STANDING`).
pub const BLADES_STANDING: f32 = 0.5;

/// What the blades show against the model in the near ring's pixels standing on a blade
/// (twin of `blades_ratio`): 1 where too few pixels were measured or too few of the ring's
/// stand on blades (bare ground, a hole in the density map, a field seen from outside).
pub fn blades_ratio(near: &RingSums) -> Vec3 {
    blades_measured(near).unwrap_or(Vec3::ONE)
}

/// The blades' ratio to the model in the near ring's sums, where they measured the blades
/// (twin of `blades_were_measured` and `blades_measured`).
fn blades_measured(near: &RingSums) -> Option<Vec3> {
    if !near.measured() || near.count < BLADES_STANDING * near.pixels {
        return None;
    }
    let r = near.shown / near.model;
    r.is_finite()
        .then(|| r.clamp(Vec3::splat(BLADES_RANGE.0), Vec3::splat(BLADES_RANGE.1)))
}

/// The blades' ratio to the model as the far state keeps it for the panel and `--timings`
/// (twin of `next_blades_mean`; the gain does not read it): averaged over the frames as
/// [`next_gain`] averages its aims, `n` the measurements before this one. One frame's near
/// ring is a few hundred pixels: its ratio wanders by several per cent from frame to
/// frame. `previous` is 0 before the first frame that measured the blades (taken as it
/// is); a frame that did not measure them keeps it.
pub fn next_blades_mean(near: &RingSums, previous: Vec3, n: f32, blend: f32) -> Vec3 {
    let Some(now) = blades_measured(near) else {
        return previous;
    };
    if !(previous.cmpgt(Vec3::ZERO).all() && previous.is_finite()) {
        return now;
    }
    previous.lerp(now, step(n, blend))
}

/// How far a measurement moves a value averaged over `n` measurements before it: a running
/// mean until there are 1 / `blend`, then `blend` of the way.
pub(crate) fn step(n: f32, blend: f32) -> f32 {
    (1.0 / (n + 1.0)).max(blend)
}

/// The gain after a frame's sums over the far and the near ring (twin of `next_gain`):
/// `previous` is (the gain the far pixels were lit with, the measurements it averages: 0
/// before the first). The far levels aim at the model times the blades' ratio to it.
pub fn next_gain(
    far: &RingSums,
    near: &RingSums,
    previous: (Vec3, f32),
    blend: f32,
) -> (Vec3, f32) {
    // An infinite pixel would drag the gain to its bound (a NaN reads as black).
    if !far.shown.is_finite() || !far.measured() {
        return previous;
    }
    let measured = previous.1 > 0.5;
    let old = if measured { previous.0 } else { Vec3::ONE };
    let target = far.model * blades_ratio(near);
    let raw = old * target / far.shown;
    // A frame whose radiance is not finite somewhere measures nothing.
    if !raw.is_finite() {
        return previous;
    }
    let aim = raw.clamp(Vec3::splat(GAIN_RANGE.0), Vec3::splat(GAIN_RANGE.1));
    let n = if measured { previous.1 } else { 0.0 };
    let cap = 1.0 / blend.max(1e-3);
    (old.lerp(aim, step(n, blend)), (n + 1.0).min(cap))
}

/// The light gain's multiplier at distance `d` (m) from the camera, for blades reaching
/// `reach`, from the far field's multiplier (0: not measured, 1) (twin of `distance_gain`):
/// 1 up to 1.5 times the reach (the ring), the far field's from twice it, smoothly between.
pub fn distance_gain(d: f32, reach: f32, far: f32) -> f32 {
    if !reach.is_finite() || !d.is_finite() || reach <= 0.0 {
        return 1.0;
    }
    let field = if far > 0.0 { far } else { 1.0 };
    1.0 + (field - 1.0) * smoothstep(FAR_RAMP.0 * reach, FAR_RAMP.1 * reach, d)
}

/// The far field's distance gain after a frame's sums (twin of `next_distance_gain`):
/// `shown` and `model` its luminance sums over `pixels`, `ring_need` the ring's model over shown
/// luminance in the same frame, `previous` the multiplier it was lit with (0 before the
/// first), `n` and `blend` as [`next_contrast`]'s. The field should need what the ring
/// needs (the blades' ratio cancels), so the multiplier moves by its need over the ring's.
pub fn next_distance_gain(
    (shown, model, pixels): (f32, f32, f32),
    ring_need: f32,
    previous: f32,
    n: f32,
    blend: f32,
) -> f32 {
    if pixels < MIN_SAMPLES || shown <= 1e-6 || model <= 1e-6 || ring_need <= 1e-6 {
        return previous;
    }
    let old = if previous > 0.0 { previous } else { 1.0 };
    let raw = old * model / shown / ring_need;
    if !raw.is_finite() || !ring_need.is_finite() {
        return previous;
    }
    let aim = raw.clamp(DISTANCE_GAIN_RANGE.0, DISTANCE_GAIN_RANGE.1);
    old + (aim - old) * step(n, blend)
}

/// Runs the WGSL distance gain on the GPU (`distance_gain_probe.wgsl`): per point,
/// (distance, reach, multiplier, unused) and the field's (shown, model, pixels, ring's need),
/// (previous, n, blend); returns ([`distance_gain`], [`next_distance_gain`])'s GPU values.
pub fn distance_probe(gpu: &Gpu, points: &[([f32; 4], [f32; 4], [f32; 3])]) -> Result<Vec<(f32, f32)>> {
    let at: Vec<[f32; 4]> = points.iter().map(|p| p.0).collect();
    let sums: Vec<[f32; 4]> = points.iter().map(|p| p.1).collect();
    let prev: Vec<[f32; 4]> = points.iter().map(|p| [p.2[0], p.2[1], p.2[2], 0.0]).collect();
    let out = crate::gpu::run_vec4_probe(
        gpu,
        "sward.distance_gain_probe",
        "distance_gain_probe.wgsl",
        &[
            bytemuck::cast_slice(&at),
            bytemuck::cast_slice(&sums),
            bytemuck::cast_slice(&prev),
        ],
        points.len(),
    )?;
    Ok(out.iter().map(|v| (v[0], v[1])).collect())
}

/// The cards' contrast gain after a frame's sums (twin of `next_contrast`): `previous` the
/// gain they were lit with (0 before the first measurement), `n` the measurements the
/// light gain averaged before this frame's.
pub fn next_contrast(far: &RingSums, near: &RingSums, previous: f32, n: f32, blend: f32) -> f32 {
    let (far_v, near_v) = (far.local_contrast(), near.local_contrast());
    if far.count < MIN_SAMPLES || near.count < MIN_SAMPLES || far_v <= 1e-4 || near_v <= 1e-4 {
        return previous;
    }
    let old = if previous > 0.0 { previous } else { 1.0 };
    let raw = old * near_v / far_v;
    // Not finite (a NaN or an infinity in the frame's radiance): kept out.
    if !(raw.is_finite() && far_v.is_finite() && near_v.is_finite()) {
        return previous;
    }
    let aim = raw.clamp(CONTRAST_RANGE.0, CONTRAST_RANGE.1);
    old + (aim - old) * step(n, blend)
}

/// The share of a card's mean luminance under which the contrast's line bends towards
/// black (twin of `CONTRAST_FLOOR`).
pub const CONTRAST_FLOOR: f32 = 0.2;

/// A card texel's luminance `l` shown with contrast gain `k` about the card's mean `m`
/// (twin of `contrast_luma`): moved `k` times as far from the mean (`y = m + k (l − m)`)
/// down to `t` = [`CONTRAST_FLOOR`] of the mean, then `t² / (2 t − y)`: at the line's
/// slope where they meet, and never black.
pub fn contrast_luma(l: f32, m: f32, k: f32) -> f32 {
    let y = m + k * (l - m);
    let t = CONTRAST_FLOOR * m.max(0.0);
    if y >= t {
        y
    } else {
        t * t / (2.0 * t - y).max(1e-12)
    }
}

/// Runs the WGSL contrast curve (`contrast_luma`) on the GPU at each (luminance, mean,
/// gain) of `points`, for the test against [`contrast_luma`].
pub fn contrast_probe(gpu: &Gpu, points: &[(f32, f32, f32)]) -> Result<Vec<f32>> {
    let flat: Vec<[f32; 4]> = points.iter().map(|&(l, m, k)| [l, m, k, 0.0]).collect();
    let out = crate::gpu::run_vec4_probe(
        gpu,
        "sward.contrast_probe",
        "contrast_probe.wgsl",
        &[bytemuck::cast_slice(&flat)],
        points.len(),
    )?;
    Ok(out.iter().map(|v| v[0]).collect())
}

impl super::Renderer {
    /// The far levels' light gain the last frame measured (rgb), `None` before the first
    /// measurement (blocking read-back; for statistics and tests).
    pub fn far_gain(&self, gpu: &Gpu) -> Result<Option<Vec3>> {
        let bytes = crate::gpu::read_buffer(gpu, self.draw.waves_buffer(), STATE_BYTES)?;
        let words: &[f32] = bytemuck::cast_slice(&bytes);
        let g = &words[GAIN_WORD..GAIN_WORD + 4];
        Ok((g[3] > 0.5).then(|| Vec3::new(g[0], g[1], g[2])))
    }

    /// The far levels' calibration as the last frame measured it (each 1 before
    /// measured, the sectors 0; blocking read-back, for statistics and tests).
    pub fn far_calibration(&self, gpu: &Gpu) -> Result<FarCalibration> {
        let bytes = crate::gpu::read_buffer(gpu, self.draw.waves_buffer(), STATE_BYTES)?;
        let words: &[f32] = bytemuck::cast_slice(&bytes);
        let g = &words[CALIBRATION_WORD..CALIBRATION_WORD + 4];
        // The blades' ratio is 0 until they were measured, the contrast gain until the
        // cards were.
        let mean = Vec3::new(g[0], g[1], g[2]);
        let ratio = if mean.cmpgt(Vec3::ZERO).all() {
            mean
        } else {
            Vec3::ONE
        };
        let contrast = if g[3] > 0.0 { g[3] } else { 1.0 };
        let m = words[DISTANCE_WORD];
        let distance = if m > 0.0 { m } else { 1.0 };
        let mut sectors = [0.0; SECTORS];
        sectors.copy_from_slice(&words[SECTOR_WORD..SECTOR_WORD + SECTORS]);
        let counts: &[u32] = bytemuck::cast_slice(&bytes);
        let (sum, blades) = (counts[BEND_WORDS], counts[BEND_WORDS + 1]);
        let bend = if blades > 0 {
            sum as f32 / (crate::sim::layout::WAVE_QUANTA * blades as f32)
        } else {
            0.0
        };
        Ok(FarCalibration {
            ratio,
            bend,
            contrast,
            distance,
            sectors,
        })
    }
}

/// What the far levels are calibrated with besides the light gain (`Renderer::far_calibration`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FarCalibration {
    /// The blades' ratio to the far light model in the near ring (rgb), averaged over the
    /// frames as the gain averages its aims ([`next_blades_mean`]).
    pub ratio: Vec3,
    /// The gusts' mean bend at the edge of the blades' reach ([`BEND_WORDS`]): 0 calm, 1
    /// where every blade there is bent two thirds of its height from its rest. The far
    /// levels' shading waves follow it.
    pub bend: f32,
    /// The cards' contrast gain.
    pub contrast: f32,
    /// The far field's distance gain (times the light gain, [`distance_gain`]).
    pub distance: f32,
    /// The multipliers of the light gain by the direction of view (`far_sectors`; 0 where
    /// not measured yet).
    pub sectors: [f32; SECTORS],
}

impl Default for FarCalibration {
    fn default() -> Self {
        Self {
            ratio: Vec3::ONE,
            bend: 0.0,
            contrast: 1.0,
            distance: 1.0,
            sectors: [0.0; SECTORS],
        }
    }
}

/// One pixel of the probe: its radiance, the fog's amount and colour, the model's, and
/// its ring.
#[derive(Clone, Copy, Debug)]
pub struct GainPixel {
    /// The frame's (fogged) radiance.
    pub actual: Vec3,
    /// The fog's colour.
    pub sky: Vec3,
    /// The fog's amount, 0 to 1.
    pub f: f32,
    /// The model's radiance (unfogged, without the gain).
    pub model: Vec3,
    /// In the near ring (the blades), not the far one.
    pub near: bool,
    /// Standing on a blade (above the ground): the near ring measures only these.
    pub standing: bool,
    /// Its block's (fogged) luminance, summed (x) and its squares summed (y), over
    /// [`CONTRAST_BLOCK`]² texels ([`block_contrast`]).
    pub block: Vec2,
}

impl GainPixel {
    /// Its local contrast ([`block_contrast`], the fog's luminance taken off its block's
    /// mean).
    pub fn contrast(&self) -> f32 {
        block_contrast(self.block, self.f * self.sky.dot(LUMA))
    }
}

/// What the probe returns: the far and the near ring's sums, the next gain and the
/// measurements it averages, the gain the level would light with (`far_gain`), and the
/// next contrast gain with the one the cards would be shown with (`contrast_gain`).
pub type ProbeResult = (RingSums, RingSums, (Vec3, f32), Vec3, (f32, f32), Vec3);

/// Runs the WGSL arithmetic (`far_gain_math.wgsl`) over `pixels` from `previous` (gain,
/// measurements), `contrast` (the previous contrast gain) and `ratio` (the blades' running
/// mean before), on the GPU, for the test against [`gain_terms`], [`next_gain`],
/// [`next_contrast`] and [`next_blades_mean`] (the last of the result).
pub fn probe(
    gpu: &Gpu,
    pixels: &[GainPixel],
    previous: (Vec3, f32),
    contrast: f32,
    ratio: Vec3,
    blend: f32,
) -> Result<ProbeResult> {
    let mut flat: Vec<[f32; 16]> = pixels
        .iter()
        .map(|s| {
            let near = if s.near { 1.0 } else { 0.0 };
            let standing = if s.standing { 1.0 } else { 0.0 };
            [
                s.actual.x, s.actual.y, s.actual.z, s.f, s.sky.x, s.sky.y, s.sky.z, near,
                s.model.x, s.model.y, s.model.z, standing, s.block.x, s.block.y, 0.0, 0.0,
            ]
        })
        .collect();
    // A binding is never empty: an empty list is one pixel the probe does not read.
    if flat.is_empty() {
        flat.push([0.0; 16]);
    }
    let prev: [f32; 12] = [
        previous.0.x,
        previous.0.y,
        previous.0.z,
        previous.1,
        blend,
        pixels.len() as f32,
        contrast,
        0.0,
        ratio.x,
        ratio.y,
        ratio.z,
        0.0,
    ];
    let out = crate::gpu::run_vec4_probe(
        gpu,
        "sward.far_gain_probe",
        "far_gain_probe.wgsl",
        &[bytemuck::cast_slice(&flat), bytemuck::cast_slice(&prev)],
        9,
    )?;
    let v = |a: [f32; 4]| Vec3::new(a[0], a[1], a[2]);
    let sums = |shown: [f32; 4], model: [f32; 4], contrast: f32| RingSums {
        shown: v(shown),
        model: v(model),
        count: shown[3],
        contrast,
        pixels: model[3],
    };
    let d = out[6];
    Ok((
        sums(out[0], out[1], d[0]),
        sums(out[2], out[3], d[1]),
        (v(out[4]), out[4][3]),
        v(out[5]),
        (out[7][0], out[7][1]),
        v(out[8]),
    ))
}
