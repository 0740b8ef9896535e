// The far levels' light gains (issue 27, point 1), the arithmetic shared by the measuring
// pass (far_gain_common.wgsl) and its probe. The billboards and the far ground stand for
// the blades beyond their reach and are lit with the blades' own light model
// (`far_grass_light`), but through textures and card coverage of their own, which need not
// average to it. Each frame compares what the cards, and the ground between them, show
// just beyond the reach with what the model says for the same points, and keeps the ratio
// as the gain each is lit with, per colour channel. Their radiance is proportional to the
// gain they were lit with, so a measurement corrects it in one step and is not fed back.
//
// Per pixel: the radiance `actual` (fogged, as the frame holds it), the fog's colour `sky`
// and amount `f` there, and the model's radiance `model` (unfogged, without the gain). The
// fog is taken off the actual radiance; both are weighed by (1 − f), so that a pixel deep
// in the fog, which shows little of the grass, weighs little.

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

// The smallest and largest gain kept, and the fewest pixels a measurement needs.
const GAIN_MIN: f32 = 0.25;
const GAIN_MAX: f32 = 4.0;
const GAIN_MIN_SAMPLES: f32 = 16.0;

// The gain after a frame's sums over `count` pixels, from `previous` (rgb the gain the
// pixels were lit with, w 1 once measured): the first measurement is taken as it is, later
// ones move the gain `blend` of the way (a change of light settles in a few frames without
// flicker); fewer than GAIN_MIN_SAMPLES pixels (the level out of view) keep it.
fn next_gain(shown: vec3<f32>, model: vec3<f32>, count: f32, previous: vec4<f32>, blend: f32) -> vec4<f32> {
    if count < GAIN_MIN_SAMPLES || any(shown <= vec3<f32>(1e-6)) || any(model <= vec3<f32>(1e-6)) {
        return previous;
    }
    let old = select(vec3<f32>(1.0), previous.rgb, previous.w > 0.5);
    let aim = clamp(old * model / shown, vec3<f32>(GAIN_MIN), vec3<f32>(GAIN_MAX));
    if previous.w < 0.5 {
        return vec4<f32>(aim, 1.0);
    }
    return vec4<f32>(mix(old, aim, blend), 1.0);
}

// A gain from the state's words: 1 until measured.
fn far_gain(words: vec4<u32>) -> vec3<f32> {
    let g = bitcast<vec4<f32>>(words);
    return select(vec3<f32>(1.0), g.rgb, g.w > 0.5);
}
