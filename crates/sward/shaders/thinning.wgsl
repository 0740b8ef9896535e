// Eq. 20's thinning as the blades are drawn (issue 27, point 1: thinning keeps the
// coverage), as pure functions of a blade's distance `d` from the culling camera (across
// its up axis), the reach `reach` (d_max), the distance levels `n` (0: no thinning) and,
// for the root, the radius the cards are drawn to (`cards`, m; 0 without cards).
// The twins are `render::thinning::widen` and `render::thinning::root`.

// At most this much wider: past it (from half the reach, where keep falls below 4 in 8) the
// blades read as broad leaves (at 3, the prairie's last levels at 960x540 were a band of
// bright blobs), and the billboards fading in there (from half the reach) fill the gaps.
const MAX_WIDEN: f32 = 2.0;

// How much wider a blade is drawn so that the blades Eq. 20 keeps cover what it dropped:
// at a distance where the cull keeps `keep` blades in n (cull.wgsl), each kept blade is n /
// keep times as wide (as Ghost of Tsushima's). Within the first level, and without
// thinning, 1.
fn thinning_widen_at(d: f32, reach: f32, n: f32) -> f32 {
    if n < 0.5 {
        return 1.0;
    }
    let keep = floor(n * (1.0 - d / max(reach, 1e-6)));
    return min(n / max(keep, 1.0), MAX_WIDEN);
}

// Where a kept blade starts to be drawn (its v; 0: from the root). Once the widened blades
// no longer cover what the cull dropped (from half the reach), each stands alone among the
// cards fading in, and a lone blade shows its shaded lower part, which the full field's
// neighbours hide from a distant eye: the eye sees deeper between the thinned blades. So
// the blade is drawn from part way up, and the cards stand for the canopy below: the cut
// grows by CUT_RATE per reach from half the reach and keeps the top 1 − CUT_MAX of the
// blade from 0.65 of the reach on. Measured on the prairie against the full field
// (`--set culling.distance=false`), one sample per pixel, 16 frames, the blades' pixels
// straight from the frame by their distance, with wind / without: a cut growing evenly to
// the whole blade at the reach (`1 − MAX_WIDEN (1 − d / reach)`) left them −4.0 / −3.8 %
// at 0.56-0.63 of the reach, −5.8 / −5.7 % at 0.63-0.69 and −4.7 / −7.1 % at 0.69-0.75
// (the blades' visible v 0.02-0.04 lower) and +4.5 / +19 % at 0.88-0.95 (the tips
// alone); this reads −3.3 / −2.3, −0.4 / +1.4, −0.5 / +3.9 and +1.1 / +6.3 % there, and
// within 3 % elsewhere. At most 0.5 left 0.75-0.88 3-6 % dark; rising by 5 instead of 4,
// the same within a per cent. Where no card stands (none drawn, or past the radius they
// are drawn to, fading out from 0.85 of it as the cards do) nothing would stand for the
// canopy below, and the blade is drawn whole, as the widening alone leaves it (cut without
// cards, the prairie's thinned field showed the bare ground under floating tips: band 64
// +5.7 levels and −27 % against the full field at 240x136).
const CUT_RATE: f32 = 4.0;
const CUT_MAX: f32 = 0.6;

fn thinned_root_at(d: f32, reach: f32, n: f32, cards: f32) -> f32 {
    if n < 0.5 || cards <= 0.0 {
        return 0.0;
    }
    let cut = clamp((d / max(reach, 1e-6) - 0.5) * CUT_RATE, 0.0, CUT_MAX);
    // 0.85: `billboard::FADE_OUT`, where the cards fade out.
    return cut * (1.0 - smoothstep(0.85 * cards, cards, d));
}
