// The far levels' light gains (issue 27, point 1), the arithmetic shared by the measuring
// pass (far_gain_common.wgsl) and its probe. The billboards and the far ground stand for
// the blades beyond their reach and are lit with the blades' own light model
// (`far_grass_light`), but through textures and card coverage of their own, which need not
// average to it, and the model itself only approximates what the blades show. Each frame
// measures, against the model at the same points, what the blades show a little inside
// their reach (the near ring, where no card stands yet) and what the cards and the ground
// between them show just beyond it (the far ring), and keeps as the gain each far level is
// lit with, per colour channel, what makes the far ring show the blades' ratio. The far
// ring's radiance is proportional to the gain it was lit with, so a measurement corrects
// it in one step and is not fed back; the blades are not lit with the gain.
//
// Per pixel: the radiance `actual` (fogged, as the frame holds it), the fog's colour `sky`
// and amount `f` there, and the model's radiance `model` (unfogged, without the gain). The
// fog is taken off the actual radiance; both are weighed by (1 − f), so that a pixel deep
// in the fog, which shows little of the grass, weighs little.
//!include far_sectors.wgsl

// What one pixel adds to its level's sums.
struct GainTerms {
    // The actual radiance without the fog, times (1 − f).
    shown: vec3<f32>,
    // The model's radiance times (1 − f).
    model: vec3<f32>,
}

fn gain_terms(actual: vec3<f32>, sky: vec3<f32>, f: f32, model: vec3<f32>) -> GainTerms {
    let clear = clamp(1.0 - f, 0.0, 1.0);
    return GainTerms(max(actual - f * sky, vec3<f32>(0.0)), model * clear);
}

// The smallest and largest gain kept, the fewest pixels a measurement needs, and the
// range kept of the blades' own ratio to the model.
const GAIN_MIN: f32 = 0.25;
const GAIN_MAX: f32 = 4.0;
const GAIN_MIN_SAMPLES: f32 = 16.0;
const BLADES_MIN: f32 = 0.5;
const BLADES_MAX: f32 = 2.0;

// Whether every component of `v` is finite, read from its bits (an implementation may
// assume that no float is NaN and fold a comparison of one with itself away).
fn finite3(v: vec3<f32>) -> bool {
    let e = bitcast<vec3<u32>>(v) & vec3<u32>(0x7f800000u);
    return all(e != vec3<u32>(0x7f800000u));
}

// The share of the near ring's pixels that must stand above the ground (on a blade) for
// it to be measured as blades.
const BLADES_STANDING: f32 = 0.5;

// What the blades show against the model, measured in the near ring's pixels standing on a
// blade (their sums, rgb, and count, w; the model's sums over the same pixels, rgb, and
// every pixel of the ring, w): 1 where too few pixels were measured, or too few of the
// ring's stand on blades (bare ground, a density map's hole, a field seen from outside),
// so that nothing but blades sets the far levels.
fn blades_ratio(shown: vec4<f32>, model: vec4<f32>) -> vec3<f32> {
    return select(vec3<f32>(1.0), blades_measured(shown, model), blades_were_measured(shown, model));
}

// Whether the near ring's sums measured the blades (`blades_ratio` is 1 where not).
fn blades_were_measured(shown: vec4<f32>, model: vec4<f32>) -> bool {
    let few = shown.w < GAIN_MIN_SAMPLES || shown.w < BLADES_STANDING * model.w;
    if few || any(shown.rgb <= vec3<f32>(1e-6)) || any(model.rgb <= vec3<f32>(1e-6)) {
        return false;
    }
    return finite3(shown.rgb / model.rgb);
}

// The blades' ratio to the model from sums `blades_were_measured` accepts.
fn blades_measured(shown: vec4<f32>, model: vec4<f32>) -> vec3<f32> {
    return clamp(shown.rgb / max(model.rgb, vec3<f32>(1e-6)), vec3<f32>(BLADES_MIN), vec3<f32>(BLADES_MAX));
}

// The blades' ratio to the model as the far state keeps it for the panel and `--timings`
// (words 8-10; the gain does not read it): averaged over the frames as the gain averages
// its aims (`next_gain`: a running mean over the `n` measurements before this one until
// there are 1 / `blend` of them, then `blend` of the way), since one frame's near ring is a
// few hundred pixels and its ratio wanders by several per cent. `previous` is 0 before the
// first frame that measured the blades, taken as it is; a frame that did not measure them
// keeps it.
fn next_blades_mean(shown: vec4<f32>, model: vec4<f32>, previous: vec3<f32>, n: f32, blend: f32) -> vec3<f32> {
    if !blades_were_measured(shown, model) {
        return previous;
    }
    let now = blades_measured(shown, model);
    if !all(previous > vec3<f32>(0.0)) || !finite3(previous) {
        return now;
    }
    return mix(previous, now, max(1.0 / (n + 1.0), blend));
}

// The gain after a frame's sums: `far_shown` / `far_model` over the far ring's pixels
// (rgb, and their count in w), `near_shown` / `near_model` over the near ring's pixels
// standing on blades (not lit with the gain; every pixel of the ring counted in
// `near_model.w`). The far levels should show what the model says times
// what the blades show against the model (`blades_ratio`): the blades, carried out past
// their reach by the model's change with distance and view. `previous` is the gain the far
// pixels were lit with (rgb) and the measurements it averages (w, 0 before the first):
// each frame's aim enters as into a running mean until there are 1 / `blend` of them, then
// moves the gain `blend` of the way (the pixels measured move between frames, so the mean
// settles on the field's, and a change of light settles in a few frames without flicker);
// fewer than GAIN_MIN_SAMPLES far pixels (the level out of view) keep it.
fn next_gain(far_shown: vec4<f32>, far_model: vec3<f32>, near_shown: vec4<f32>, near_model: vec4<f32>, previous: vec4<f32>, blend: f32) -> vec4<f32> {
    // An infinite pixel (a NaN reads as black: `gain_terms` takes the fog off with a max)
    // would drag the gain to its bound: such a frame measures nothing.
    if !finite3(far_shown.rgb) {
        return previous;
    }
    if far_shown.w < GAIN_MIN_SAMPLES || any(far_shown.rgb <= vec3<f32>(1e-6)) || any(far_model <= vec3<f32>(1e-6)) {
        return previous;
    }
    let measured = previous.w > 0.5;
    let old = select(vec3<f32>(1.0), previous.rgb, measured);
    let wanted = far_model * blades_ratio(near_shown, near_model);
    let aim = clamp(old * wanted / far_shown.rgb, vec3<f32>(GAIN_MIN), vec3<f32>(GAIN_MAX));
    // A frame whose radiance is not finite somewhere (a NaN fails every comparison, so it
    // passed the tests above, and a clamp may turn it into either bound) measures nothing.
    if !finite3(old * wanted / far_shown.rgb) {
        return previous;
    }
    let n = select(0.0, previous.w, measured);
    let cap = 1.0 / max(blend, 1e-3);
    return vec4<f32>(mix(old, aim, max(1.0 / (n + 1.0), blend)), min(n + 1.0, cap));
}

// The smallest and largest contrast gain kept.
const CONTRAST_MIN: f32 = 0.5;
const CONTRAST_MAX: f32 = 4.0;

// The texels around a measured pixel whose luminance gives its local contrast
// (`block_contrast`): a square of CONTRAST_BLOCK on a side, from CONTRAST_BLOCK / 2 left of
// and above it (twin: `far_gain::CONTRAST_BLOCK`).
const CONTRAST_BLOCK: i32 = 4;

// A pixel's local contrast: the standard deviation of its block's luminance over the
// block's mean without the fog, from the block's sum (x) and sum of squares (y) of the
// frame's (fogged) luminance over CONTRAST_BLOCK² texels and the fog's luminance there
// (`fog`: its colour's times its amount). The contrast the cards should show is the one
// the eye sees between neighbouring pixels (what the bands' 8 × 8 blocks measure), not the
// spread of single pixels across the ring: that grows with the frame's size as the near
// blades are resolved (the prairie's contrast gain after 4 frames was 1.58, 1.71 and 1.89
// at 480 × 270, 960 × 540 and 1920 × 1080, the cards' bands up to 24 % above the blades'
// contrast at the larger two; from the blocks 1.41, 1.38 and 1.36, within 15 %), and
// cards of too much contrast read dark in the tone-mapped frame (its curve is concave):
// 7-11 levels at 29-50 m at 960 × 540, 3-8 from the blocks.
fn block_contrast(block: vec2<f32>, fog: f32) -> f32 {
    // A block with a texel that is not finite stays so, and keeps `next_contrast` from
    // measuring the frame (its arithmetic could otherwise turn it into any number).
    if !finite3(vec3<f32>(block, fog)) {
        return block.x + block.y;
    }
    let n = f32(CONTRAST_BLOCK * CONTRAST_BLOCK);
    let m = block.x / n;
    return sqrt(max(block.y / n - m * m, 0.0)) / max(m - fog, 1e-6);
}

// The cards' contrast gain after a frame's sums (issue 27, point 1: texture of the same
// contrast): the cards show the atlas's texels around its mean this many times as far as
// lit, so that the far ring's pixels (`far_c`, the sum of their local contrasts,
// `block_contrast`, over `far_n` pixels) vary against their neighbours as much as the near
// ring's blades do (`near_c` over `near_n`). `previous` is the gain they were lit with (0
// before the first measurement), `n` the measurements the light gain averages before this
// one (the two settle together, as `next_gain`); either ring with too few pixels keeps it.
fn next_contrast(far_c: f32, far_n: f32, near_c: f32, near_n: f32, previous: f32, n: f32, blend: f32) -> f32 {
    let far_v = far_c / max(far_n, 1.0);
    let near_v = near_c / max(near_n, 1.0);
    if far_n < GAIN_MIN_SAMPLES || near_n < GAIN_MIN_SAMPLES || far_v <= 1e-4 || near_v <= 1e-4 {
        return previous;
    }
    let old = select(1.0, previous, previous > 0.0);
    // Not finite (a NaN or an infinity in the frame's radiance, whose block contrast stays
    // so): kept out, as `next_gain` does.
    if !finite3(vec3<f32>(far_v, near_v, old * near_v / far_v)) {
        return previous;
    }
    let aim = clamp(old * near_v / far_v, CONTRAST_MIN, CONTRAST_MAX);
    return mix(old, aim, max(1.0 / (n + 1.0), blend));
}

// The share of a card's mean luminance under which the contrast's line bends towards black
// (`contrast_luma`).
const CONTRAST_FLOOR: f32 = 0.2;

// A card texel's luminance `l` shown with contrast gain `k` about the card's mean `m`:
// moved k times as far from the mean (`y = m + k (l − m)`, which keeps the mean), down to
// a fifth of the mean (`t`); below that, `t² / (2 t − y)`, which leaves the line at its
// slope and nears black without reaching it. The line clamped at zero took every texel
// under 0.7-0.75 of the mean to black at the gain of 3-4 the near ring asks for on a short
// reach (the window's meadow after its budget had cut the reach to 11 m: cards of black
// blades). A curve from black to the mean (`x / (x + k (1 − x))`) kept the texels
// lighter, but raised the cards' mean with the gain, faster than the light gain follows
// while the two settle: 12.9 levels bright after 4 frames (`tests/far_field.rs`).
fn contrast_luma(l: f32, m: f32, k: f32) -> f32 {
    let y = m + k * (l - m);
    let t = CONTRAST_FLOOR * max(m, 0.0);
    return select(t * t / max(2.0 * t - y, 1e-12), y, y >= t);
}

// A contrast gain from its state word: 1 until measured.
fn contrast_gain(word: u32) -> f32 {
    let k = bitcast<f32>(word);
    return select(1.0, k, k > 0.0);
}

// A gain from the state's words: 1 until measured.
fn far_gain(words: vec4<u32>) -> vec3<f32> {
    let g = bitcast<vec4<f32>>(words);
    return select(vec3<f32>(1.0), g.rgb, g.w > 0.5);
}

// The far field's distance gain (issue 27, point 1): the light gain brings the far ring
// (`ring`, the far levels' first metres) to the blades' aim, but the cards and the far
// ground do not change with distance as the blades would (the cards' mip and contrast hand
// over to the far ground's look, their levels grow, more ground shows between them), and
// past the ring the prairie's far levels read 2-6 levels darker than the ring. So the far
// field (FAR_BIN, multiples of the reach) is measured against the same aim and kept as a
// multiplier of the light gain (luminance), lit from twice the reach on, going over from 1
// (the ring, lit with the light gain alone) from 1.5 times it (FAR_RAMP).
const FAR_BIN: vec2<f32> = vec2<f32>(2.0, 5.0);
const FAR_RAMP: vec2<f32> = vec2<f32>(1.5, 2.0);
// The range the multiplier is kept in: it corrects how the far levels change with
// distance, not their light (the light gain's), and only darkens them (the blades' own
// ratio to the model falls with distance; `far_gain::DISTANCE_GAIN_RANGE`).
const DISTANCE_GAIN_MIN: f32 = 0.7;
const DISTANCE_GAIN_MAX: f32 = 1.0;

// The light gain's multiplier at distance `d` (m) from the camera with the blades' reach
// `reach`, from the far field's state word (0: not measured, 1).
fn distance_gain(d: f32, reach: f32, far: u32) -> f32 {
    // No reach (no blades, or every blade drawn): nothing was measured.
    if !finite3(vec3<f32>(reach, d, 0.0)) || reach <= 0.0 {
        return 1.0;
    }
    let m = bitcast<f32>(far);
    let field = select(1.0, m, m > 0.0);
    return mix(1.0, field, smoothstep(FAR_RAMP.x * reach, FAR_RAMP.y * reach, d));
}

// The far field's multiplier after a frame's sums: the luminance shown and the model's
// (`sums`, xy) over its pixels (z), and `ring` the ring's model over shown luminance in the
// same frame: the field should need what the ring needs (the blades' ratio, in both,
// cancels), so the multiplier moves by the field's need over the ring's. `previous` is the
// multiplier it was lit with (0 before the first measurement), `n` and `blend` as
// `next_contrast`'s; too few pixels, or a frame that is not finite, keep it.
fn next_distance_gain(sums: vec3<f32>, ring: f32, previous: f32, n: f32, blend: f32) -> f32 {
    if sums.z < GAIN_MIN_SAMPLES || sums.x <= 1e-6 || sums.y <= 1e-6 || ring <= 1e-6 {
        return previous;
    }
    let old = select(1.0, previous, previous > 0.0);
    let raw = old * sums.y / sums.x / ring;
    if !finite3(vec3<f32>(raw, ring, 0.0)) {
        return previous;
    }
    let aim = clamp(raw, DISTANCE_GAIN_MIN, DISTANCE_GAIN_MAX);
    return mix(old, aim, max(1.0 / (n + 1.0), blend));
}
