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
// neighbours hide from a distant eye: measured on the prairie, those blades read 4-8
// levels darker than the full field there, and the band where they stand among the first
// cards 6-12 levels darker. So the blade is drawn from the share of its height the lost
// coverage stands for, `1 - MAX_WIDEN (1 - d / reach)` (0 at half the reach, all of it at
// the reach), and the cards stand for the canopy below. Where no card stands (none drawn,
// or past the radius they are drawn to, fading out from 0.85 of it as the cards do)
// nothing would stand for it, and the blade is drawn whole, as the widening alone leaves
// it (cut without cards, the prairie's thinned field showed the bare ground under
// floating tips: band 64 +5.7 levels and −27 % against the full field at 240x136).
fn thinned_root_at(d: f32, reach: f32, n: f32, cards: f32) -> f32 {
    if n < 0.5 || cards <= 0.0 {
        return 0.0;
    }
    let cut = clamp(1.0 - MAX_WIDEN * (1.0 - d / max(reach, 1e-6)), 0.0, 1.0);
    // 0.85: `billboard::FADE_OUT`, where the cards fade out.
    return cut * (1.0 - smoothstep(0.85 * cards, cards, d));
}
