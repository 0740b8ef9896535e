//! Eq. 20's thinning as the blades are drawn (issue 27, point 1: thinning keeps the
//! coverage): the CPU twins of `shaders/thinning.wgsl`. The cull keeps `floor(n (1 − d /
//! d_max))` blades in `n` at distance `d`; the kept blades are drawn wider ([`widen`], as
//! Ghost of Tsushima's) so that they cover what was dropped, at most [`MAX_WIDEN`] times,
//! and past the distance where that no longer covers it (half the reach) each is drawn
//! from part way up ([`root`], up to [`CUT_MAX`] of the blade): a lone blade among the
//! cards fading in shows its shaded lower part, which the full field's neighbours hide from
//! a distant eye, and the cards stand for the canopy below (only where cards are drawn:
//! past their radius, or without them, each blade is drawn whole).

use crate::error::Result;
use crate::gpu::Gpu;

use super::billboard::FADE_OUT;
use super::light::sky::smoothstep;

/// The most a kept blade is widened (twin of `MAX_WIDEN`).
pub const MAX_WIDEN: f32 = 2.0;

/// How many times as wide a kept blade at distance `d` is drawn, for the reach `reach` and
/// `n` distance levels (0: no thinning) (twin of `thinning_widen_at`).
pub fn widen(d: f32, reach: f32, n: f32) -> f32 {
    if n < 0.5 {
        return 1.0;
    }
    let keep = (n * (1.0 - d / reach.max(1e-6))).floor();
    (n / keep.max(1.0)).min(MAX_WIDEN)
}

/// How fast the cut rises past half the reach, per reach (twin of `CUT_RATE`).
pub const CUT_RATE: f32 = 4.0;

/// The most of a kept blade the cut takes (twin of `CUT_MAX`): from 0.65 of the reach on
/// the kept blades show their top 40 %, the canopy's top a distant eye sees of the full
/// field (`thinned_root_at` has the measurements).
pub const CUT_MAX: f32 = 0.6;

/// Where a kept blade at distance `d` starts to be drawn, as its v (0: the root; twin of
/// `thinned_root_at`): `CUT_RATE (d / reach − 0.5)`, within 0 and [`CUT_MAX`], where the cards
/// (drawn to the radius `cards`, m; 0 without them) stand among the thinned blades for the
/// canopy below; going over to 0 (the whole blade) as the cards fade out, from 0.85 of
/// their radius to it.
pub fn root(d: f32, reach: f32, n: f32, cards: f32) -> f32 {
    if n < 0.5 || cards <= 0.0 || cards.is_nan() {
        return 0.0;
    }
    let cut = ((d / reach.max(1e-6) - 0.5) * CUT_RATE).clamp(0.0, CUT_MAX);
    cut * (1.0 - smoothstep(FADE_OUT * cards, cards, d))
}

/// Runs the WGSL twins on the GPU (`thinning_probe.wgsl`) at each (distance, reach,
/// levels, the cards' radius) of `points`: ([`widen`], [`root`]) as the GPU computes them.
pub fn probe(gpu: &Gpu, points: &[(f32, f32, f32, f32)]) -> Result<Vec<(f32, f32)>> {
    let flat: Vec<[f32; 4]> = points.iter().map(|&(d, r, n, c)| [d, r, n, c]).collect();
    let out = crate::gpu::run_vec4_probe(
        gpu,
        "sward.thinning_probe",
        "thinning_probe.wgsl",
        &[bytemuck::cast_slice(&flat)],
        points.len(),
    )?;
    Ok(out.iter().map(|v| (v[0], v[1])).collect())
}
