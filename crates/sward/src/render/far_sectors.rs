//! The far levels' light gain by the direction of view (issue 27, point 1; CPU twins of
//! `shaders/far_sectors.wgsl`). The blades' light changes with the direction they are seen
//! from: on the prairie, the reference's blades at 28-45 m read about 25 levels brighter
//! on the right of the view (turned from the sun, along the wind) than on the left, and the
//! cards and the far ground, lit with one gain ([`super::far_gain`]), showed a third of
//! that: within 5 levels in every band's mean, but 16-39 levels off in an eighth of the
//! width. So the horizon around the camera is cut into [`SECTORS`] of azimuth, and each
//! keeps a multiplier of the light gain: what the far ring in that direction needs to show
//! the near ring's blades in the same direction, over what the whole ring needs.
//!
//! - A sector's value holds at its centre and goes linearly to its neighbours'
//!   ([`sector_pair`]); a measured pixel is shared between its two sectors with the same
//!   weights, so the gain has no step across the view.
//! - Directions of the world, not of the screen: turning the camera keeps what each
//!   direction measured, and a sector out of view keeps its value.
//! - The moved multipliers are scaled to keep their mean over the ring's pixels
//!   ([`next_sectors`]): the light gain carries the mean, the sectors only the spread, and
//!   the two do not drift against each other.
//!
//! The state's words [`SECTOR_WORD`].. hold the multipliers (0: not measured, 1).

use glam::{Vec2, Vec4};

use super::far_gain::{step, BLADES_RANGE, BLADES_STANDING};
use crate::error::Result;
use crate::gpu::Gpu;

/// Sectors of azimuth around the camera (22.5° each: four across the prairie's 85° view).
/// Four across the view resolve the spread measured by quarters of the screen; more would
/// leave each with fewer of the near ring's pixels (150-210 of the 8,192 samples at the
/// prairie's in-view sectors).
pub const SECTORS: usize = 16;

/// The far state's first sector word.
pub const SECTOR_WORD: usize = 12;

/// Words of the far state in all (twin of `FAR_STATE_WORDS`).
pub const STATE_WORDS: usize = SECTOR_WORD + SECTORS;

/// Sums per sector in a frame's measurement: the far ring's, then the near ring's.
pub const SECTOR_SUMS: usize = 2 * SECTORS;

/// The range a sector's multiplier is kept in (twin of `SECTOR_MIN`, `SECTOR_MAX`): the
/// spread of the light with the direction of view, not the light.
pub const SECTOR_RANGE: (f32, f32) = (0.6, 1.6);

/// The share of the measured sectors' mean response added to each one's in its move
/// (twin of `SECTOR_DAMPING`): a sector at the edge of the view answers its few pixels
/// weakly, and moved by its shortfall over that alone it swung with their noise (the
/// prairie's right edge from 1.6 to 1.05 in the first 64 frames); the well-seen sectors
/// move a fifth slower.
pub const SECTOR_DAMPING: f32 = 0.25;

/// The fewest pixels (weights) a sector's far ring needs to be measured, and its near ring
/// to give its own blades' ratio (twin of `SECTOR_MIN_SAMPLES`).
pub const SECTOR_MIN_SAMPLES: f32 = 8.0;

/// The two sectors whose centres the horizontal direction `d` (camera to point, x and z)
/// lies between, and the second's weight (twin of `sector_pair`): sector k's centre is at
/// azimuth (k + 0.5) 2π / [`SECTORS`] from +x towards +z. A zero or non-finite direction
/// takes sector 0 whole.
pub fn sector_pair(d: Vec2) -> (usize, usize, f32) {
    if !d.is_finite() || d.length_squared() < 1e-12 {
        return (0, 1, 0.0);
    }
    let u = d.y.atan2(d.x) / std::f32::consts::TAU * SECTORS as f32 - 0.5;
    let f = u.floor();
    let a = (f as i32 + 2 * SECTORS as i32) as usize % SECTORS;
    (a, (a + 1) % SECTORS, (u - f).clamp(0.0, 1.0))
}

/// A sector's multiplier from its stored value: 1 until measured (twin of `sector_value`).
pub fn sector_value(m: f32) -> f32 {
    if m > 0.0 && m.is_finite() {
        m
    } else {
        1.0
    }
}

/// The multiplier a card or the ground in direction `d` is lit with (twin of
/// `sector_gain`).
pub fn sector_gain(d: Vec2, multipliers: &[f32; SECTORS]) -> f32 {
    let (a, b, t) = sector_pair(d);
    let (ma, mb) = (sector_value(multipliers[a]), sector_value(multipliers[b]));
    ma + (mb - ma) * t
}

/// The blades' ratio to the model in a sector's near ring (twin of `sector_ratio`), from
/// its sums (shown and model luminance over the pixels standing on a blade, their count,
/// every pixel of the ring): `fallback` where too few were measured.
pub fn sector_ratio(near: Vec4, fallback: f32) -> f32 {
    let few = near.z < SECTOR_MIN_SAMPLES || near.z < BLADES_STANDING * near.w;
    if few || near.x <= 1e-6 || near.y <= 1e-6 {
        return fallback;
    }
    (near.x / near.y).clamp(BLADES_RANGE.0, BLADES_RANGE.1)
}

/// The sectors' multipliers after a frame's sums (twin of `next_sectors`). `sums[2k]`:
/// sector k's far ring, each pixel weighed by its weight w for the sector: the shown
/// luminance without the fog and the model's (both weighed by 1 − f), the response of the
/// first to the sector's multiplier (the sum of w² × shown / the multiplier it was lit
/// with), the weights; `sums[2k + 1]`: its near ring ([`sector_ratio`]'s). `previous`: the
/// multipliers (0: not measured); `n` and `blend` as `far_gain::next_gain`'s.
///
/// Each sector with [`SECTOR_MIN_SAMPLES`] of weight wants its far pixels to show its model
/// times its blades' ratio, over the whole ring's need (which the light gain meets), and is
/// moved by its shortfall over its response (damped by [`SECTOR_DAMPING`] of the mean
/// response): one step of Jacobi's method on the
/// interpolated field. A sector at the edge of the view shares its pixels with the next
/// and answers them weakly; moved by its own shown over its value, as first written, it
/// crept (the prairie's right edge 1.14 after 32 frames where it needed about 1.3). The
/// moves' sum weighed by the responses is zero, so the moved values are scaled back only
/// where a clamp broke that. Not finite: all kept.
pub fn next_sectors(
    sums: &[Vec4; SECTOR_SUMS],
    previous: &[f32; SECTORS],
    n: f32,
    blend: f32,
) -> [f32; SECTORS] {
    let shown: f32 = (0..SECTORS).map(|k| sums[2 * k].x).sum();
    let near: Vec4 = (0..SECTORS).map(|k| sums[2 * k + 1]).sum();
    let whole = sector_ratio(near, 1.0);
    let wanted: f32 = (0..SECTORS)
        .map(|k| sums[2 * k].y * sector_ratio(sums[2 * k + 1], whole))
        .sum();
    let need = wanted / shown;
    if !(need.is_finite() && shown.is_finite() && near.x.is_finite()) || shown <= 1e-6 || need <= 1e-6
    {
        return *previous;
    }
    let s = step(n, blend);
    let seen = |f: Vec4| f.w >= SECTOR_MIN_SAMPLES && f.x > 1e-6 && f.y > 1e-6 && f.z > 1e-6;
    let (responses, measured) = (0..SECTORS)
        .map(|k| sums[2 * k])
        .filter(|&f| seen(f))
        .fold((0.0, 0.0), |(r, m), f| (r + f.z, m + 1.0));
    let damping = SECTOR_DAMPING * responses / f32::max(measured, 1.0);
    let mut next = *previous;
    let mut moved = [false; SECTORS];
    let (mut before, mut after) = (0.0, 0.0);
    for k in 0..SECTORS {
        let f = sums[2 * k];
        if !seen(f) {
            continue;
        }
        let old = sector_value(previous[k]);
        let target = f.y * sector_ratio(sums[2 * k + 1], whole) / need;
        let raw = old + (target - f.x) / (f.z + damping);
        if !(raw.is_finite() && f.z.is_finite() && target.is_finite()) {
            return *previous;
        }
        let aim = raw.clamp(SECTOR_RANGE.0, SECTOR_RANGE.1);
        next[k] = old + (aim - old) * s;
        moved[k] = true;
        before += f.z * old;
        after += f.z * next[k];
    }
    if after <= 0.0 {
        return *previous;
    }
    let scale = before / after;
    for k in 0..SECTORS {
        if moved[k] {
            next[k] = (next[k] * scale).clamp(SECTOR_RANGE.0, SECTOR_RANGE.1);
        }
    }
    next
}

/// Where a measured pixel lies for the sectors' sums: the far ring, or the near ring
/// standing on a blade or not.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SectorRing {
    /// The far ring (the cards and the ground between them).
    Far,
    /// The near ring, on a blade (`true`) or on the ground between them.
    Near(bool),
}

/// Adds one pixel to a frame's sector sums (twin of the measuring pass's accumulation,
/// `far_gain_common.wgsl`): in direction `d` from the camera, its shown and model
/// luminance (fog taken off, weighed by 1 − f), in `ring`, the far ring's lit with
/// `multipliers` (the state's values) at its direction.
pub fn add_pixel(
    sums: &mut [Vec4; SECTOR_SUMS],
    d: Vec2,
    (shown, model): (f32, f32),
    ring: SectorRing,
    multipliers: &[f32; SECTORS],
) {
    let (a, b, t) = sector_pair(d);
    match ring {
        SectorRing::Far => {
            let lit = sector_gain(d, multipliers);
            let v = Vec4::new(shown, model, shown / lit, 1.0);
            sums[2 * a] += v * Vec4::new(1.0, 1.0, 1.0 - t, 1.0) * (1.0 - t);
            sums[2 * b] += v * Vec4::new(1.0, 1.0, t, 1.0) * t;
        }
        SectorRing::Near(standing) => {
            let v = if standing {
                Vec4::new(shown, model, 1.0, 1.0)
            } else {
                Vec4::new(0.0, 0.0, 0.0, 1.0)
            };
            sums[2 * a + 1] += v * (1.0 - t);
            sums[2 * b + 1] += v * t;
        }
    }
}

/// One direction the probe looks up: (x, z) and the stored values of its two sectors.
pub type ProbePoint = (Vec2, f32, f32);

/// What the probe returns: per point (a, b, t, multiplier), and the next multipliers.
pub type ProbeResult = (Vec<(usize, usize, f32, f32)>, [f32; SECTORS]);

/// Runs the WGSL sectors (`far_sectors_probe.wgsl`) on the GPU: [`sector_pair`] and
/// [`sector_gain`] at each point (the two words are its pair's sectors'), and
/// [`next_sectors`] once, for the test against the twins.
pub fn probe(
    gpu: &Gpu,
    points: &[ProbePoint],
    sums: &[Vec4; SECTOR_SUMS],
    previous: &[f32; SECTORS],
    (n, blend): (f32, f32),
) -> Result<ProbeResult> {
    let flat: Vec<[f32; 4]> = points
        .iter()
        .map(|(d, a, b)| [d.x, d.y, *a, *b])
        .collect();
    let mut state: Vec<[f32; 4]> = sums.iter().map(|v| v.to_array()).collect();
    state.extend(previous.chunks(4).map(|c| [c[0], c[1], c[2], c[3]]));
    state.push([n, blend, 0.0, 0.0]);
    let out = crate::gpu::run_vec4_probe(
        gpu,
        "sward.far_sectors_probe",
        "far_sectors_probe.wgsl",
        &[bytemuck::cast_slice(&flat), bytemuck::cast_slice(&state)],
        points.len() + 4,
    )?;
    let at = points.len();
    let pairs = out[..at]
        .iter()
        .map(|v| (v[0] as usize, v[1] as usize, v[2], v[3]))
        .collect();
    let mut next = [0.0; SECTORS];
    for (k, m) in next.iter_mut().enumerate() {
        *m = out[at + k / 4][k % 4];
    }
    Ok((pairs, next))
}

impl super::Renderer {
    /// Sets the sectors' multipliers the next frame lights its cards and far ground with
    /// (before its measurement moves them): a calibration carried over from another run,
    /// or a test of the lighting by direction. A value that is not finite or not positive
    /// is stored as not measured (read as 1); the others are kept in [`SECTOR_RANGE`].
    pub fn set_far_sectors(&self, gpu: &Gpu, multipliers: &[f32; SECTORS]) {
        let words = multipliers.map(|m| {
            if m.is_finite() && m > 0.0 {
                m.clamp(SECTOR_RANGE.0, SECTOR_RANGE.1)
            } else {
                0.0
            }
        });
        gpu.queue.write_buffer(
            self.draw.waves_buffer(),
            (SECTOR_WORD * 4) as u64,
            bytemuck::cast_slice(&words),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn direction(azimuth_deg: f32) -> Vec2 {
        let a = azimuth_deg.to_radians();
        Vec2::new(a.cos(), a.sin())
    }

    #[test]
    fn a_sector_holds_its_value_at_its_centre_and_goes_linearly_to_the_next() {
        let width = 360.0 / SECTORS as f32;
        let mut m = [1.0; SECTORS];
        m[3] = 1.3;
        let centre = (3.5) * width;
        assert!((sector_gain(direction(centre), &m) - 1.3).abs() < 1e-5);
        // Half way to sector 4's centre: half way to 1.
        assert!((sector_gain(direction(centre + 0.5 * width), &m) - 1.15).abs() < 1e-4);
        assert!((sector_gain(direction(centre - 0.25 * width), &m) - 1.225).abs() < 1e-4);
        assert!((sector_gain(direction(centre + width), &m) - 1.0).abs() < 1e-5);
    }

    #[test]
    fn the_sectors_wrap_round_the_horizon_without_a_step() {
        let mut m = [1.0; SECTORS];
        m[SECTORS - 1] = 1.4;
        m[0] = 0.8;
        // Just either side of azimuth 0 (between the last sector's centre and the first's).
        let below = sector_gain(direction(-1e-3), &m);
        let above = sector_gain(direction(1e-3), &m);
        assert!((below - above).abs() < 1e-4, "{below} {above}");
        assert!((below - 1.1).abs() < 1e-3);
        for az in [-180.0, -179.99, 179.99, 180.0, 359.9, 720.5] {
            let (a, b, t) = sector_pair(direction(az));
            assert!(a < SECTORS && b == (a + 1) % SECTORS && (0.0..=1.0).contains(&t));
        }
    }

    #[test]
    fn bad_directions_and_values_read_as_one() {
        let m = [0.0; SECTORS];
        assert_eq!(sector_gain(Vec2::new(3.0, -2.0), &m), 1.0);
        let mut m = [1.2; SECTORS];
        m[0] = f32::NAN;
        m[1] = -1.0;
        assert_eq!(sector_pair(Vec2::ZERO), (0, 1, 0.0));
        assert_eq!(sector_pair(Vec2::new(f32::NAN, 1.0)), (0, 1, 0.0));
        assert_eq!(sector_gain(Vec2::ZERO, &m), 1.0);
        assert_eq!(sector_value(f32::INFINITY), 1.0);
    }

    /// Sums where every sector's pixels (all at its centre) show `shown[k]` per pixel of
    /// model 1 over `pixels`, lit with `lit[k]`, with near-ring blades at `ratio[k]` of the
    /// model.
    fn sums_lit(
        shown: &[f32; SECTORS],
        ratio: &[f32; SECTORS],
        lit: &[f32; SECTORS],
        pixels: f32,
    ) -> [Vec4; SECTOR_SUMS] {
        let mut s = [Vec4::ZERO; SECTOR_SUMS];
        for k in 0..SECTORS {
            if pixels > 0.0 && shown[k] > 0.0 {
                let x = shown[k] * pixels;
                s[2 * k] = Vec4::new(x, pixels, x / sector_value(lit[k]), pixels);
                s[2 * k + 1] = Vec4::new(ratio[k] * pixels, pixels, pixels, pixels);
            }
        }
        s
    }

    fn sums(shown: &[f32; SECTORS], ratio: &[f32; SECTORS], pixels: f32) -> [Vec4; SECTOR_SUMS] {
        sums_lit(shown, ratio, &[1.0; SECTORS], pixels)
    }

    #[test]
    fn a_sector_whose_blades_read_brighter_gets_more_light_and_the_mean_is_kept() {
        let shown = [1.0; SECTORS];
        let mut ratio = [1.0; SECTORS];
        ratio[5] = 1.2;
        ratio[6] = 0.9;
        let next = next_sectors(&sums(&shown, &ratio, 40.0), &[0.0; SECTORS], 0.0, 0.25);
        assert!(next[5] > next[0] * 1.12, "{next:?}");
        assert!(next[6] < next[0] * 0.95, "{next:?}");
        let mean: f32 = next.iter().sum::<f32>() / SECTORS as f32;
        assert!((mean - 1.0).abs() < 1e-5, "{mean}");
        // The first measurement moves each sector by its shortfall over its response and
        // the damping (all alike here): 1 + (ratio / need - 1) / (1 + SECTOR_DAMPING).
        let need = (14.0 + 1.2 + 0.9) / 16.0;
        for (k, m) in next.iter().enumerate() {
            let want = 1.0 + (ratio[k] / need - 1.0) / (1.0 + SECTOR_DAMPING);
            assert!((m - want).abs() < 1e-5, "{k}: {m} against {want}");
        }
    }

    #[test]
    fn a_sector_already_lit_as_it_needs_stays() {
        // Sector 2's cards were lit 1.25 times and show it; its blades read 1.25: settled.
        let mut shown = [1.0; SECTORS];
        let mut ratio = [1.0; SECTORS];
        let mut previous = [1.0; SECTORS];
        shown[2] = 1.25;
        ratio[2] = 1.25;
        previous[2] = 1.25;
        let next = next_sectors(&sums_lit(&shown, &ratio, &previous, 40.0), &previous, 8.0, 0.25);
        for (k, m) in next.iter().enumerate() {
            assert!((m - previous[k]).abs() < 1e-4, "{k}: {m}");
        }
    }

    #[test]
    fn sectors_with_too_few_pixels_keep_their_value() {
        let mut shown = [0.0; SECTORS];
        let mut ratio = [1.0; SECTORS];
        shown[0] = 1.0;
        shown[1] = 0.8;
        ratio[1] = 1.1;
        let mut previous = [0.0; SECTORS];
        previous[9] = 1.3;
        let mut s = sums(&shown, &ratio, 40.0);
        // Sector 3: a few far pixels only.
        s[6] = Vec4::new(2.5, 5.0, 2.5, 5.0);
        let next = next_sectors(&s, &previous, 2.0, 0.25);
        assert_eq!(next[9], 1.3);
        assert_eq!(next[3], 0.0);
        assert!(next[1] > next[0]);
        // Nothing measured, or not finite: all kept.
        assert_eq!(next_sectors(&[Vec4::ZERO; SECTOR_SUMS], &previous, 2.0, 0.25), previous);
        let mut bad = sums(&[1.0; SECTORS], &[1.0; SECTORS], 40.0);
        bad[4].x = f32::INFINITY;
        assert_eq!(next_sectors(&bad, &previous, 2.0, 0.25), previous);
        bad[4].x = f32::NAN;
        assert_eq!(next_sectors(&bad, &previous, 2.0, 0.25), previous);
    }

    #[test]
    fn a_sector_without_its_own_blades_takes_the_whole_rings_ratio() {
        let shown = [1.0; SECTORS];
        let mut ratio = [1.2; SECTORS];
        ratio[7] = 2.0;
        let mut s = sums(&shown, &ratio, 40.0);
        // Sector 7's near ring: half its pixels on bare ground.
        s[15].w = 100.0;
        let next = next_sectors(&s, &[0.0; SECTORS], 0.0, 0.25);
        // The whole ring's blades, sector 7's standing ones among them: (15 x 1.2 + 2) / 16.
        let whole: f32 = (15.0 * 1.2 + 2.0) / 16.0;
        let need = (15.0 * 1.2 + whole) / 16.0;
        let moved = |r: f32| 1.0 + (r / need - 1.0) / (1.0 + SECTOR_DAMPING);
        assert!((next[7] / next[0] - moved(whole) / moved(1.2)).abs() < 1e-5, "{next:?}");
    }

    #[test]
    fn the_multipliers_stay_in_their_range() {
        let mut shown = [1.0; SECTORS];
        shown[0] = 0.01;
        shown[1] = 100.0;
        let next = next_sectors(&sums(&shown, &[1.0; SECTORS], 40.0), &[0.0; SECTORS], 0.0, 0.25);
        for m in next {
            assert!((SECTOR_RANGE.0..=SECTOR_RANGE.1).contains(&m), "{m}");
        }
    }

    /// A view of 85° (the prairie's) whose far ring needs a light rising by half from its
    /// left edge to its right (the blades there read so against the model), measured
    /// frame by frame as the pass does: the lit field reaches it across the view, at the
    /// edges too (where a sector shares its pixels with one out of view), within 2 %.
    #[test]
    fn the_field_settles_on_a_spread_across_the_view_edges_included() {
        let (left, right) = (272.0_f32, 357.0_f32);
        let azimuths: Vec<f32> = (0..600).map(|i| left + (right - left) * (i as f32 + 0.5) / 600.0).collect();
        let need = |az: f32| 0.8 + 0.4 * (az - left) / (right - left);
        let mut m = [0.0; SECTORS];
        let mut gain = 1.0;
        for frame in 0..40 {
            let mut sums = [Vec4::ZERO; SECTOR_SUMS];
            for &az in &azimuths {
                let d = direction(az);
                // The cards show the model (1) times the gain and the multiplier; the
                // blades in that direction read `need` against the model.
                let shown = gain * sector_gain(d, &m);
                add_pixel(&mut sums, d, (shown, 1.0), SectorRing::Far, &m);
                add_pixel(&mut sums, d, (need(az), 1.0), SectorRing::Near(true), &m);
            }
            // The light gain meets the whole ring's need (as `far_gain::next_gain`).
            let (shown, wanted) = azimuths.iter().fold((0.0, 0.0), |(s, w), &az| {
                (s + gain * sector_gain(direction(az), &m), w + need(az))
            });
            let n = frame.min(4) as f32;
            m = next_sectors(&sums, &m, n, 0.25);
            gain += (gain * wanted / shown - gain) * step(n, 0.25);
        }
        for &az in &azimuths {
            let lit = gain * sector_gain(direction(az), &m);
            assert!((lit / need(az) - 1.0).abs() < 0.02, "{az}: {lit} against {}", need(az));
        }
    }
}
