// Probe: the far gain's arithmetic (far_gain_math.wgsl) over a list of pixels, for the
// test that compares it with its CPU twin (`render::far_gain`). In: per pixel the radiance
// and f, the fog's colour and the ring (w: 1 near, 0 far), the model's radiance and
// whether the pixel stands on a blade (w; the near ring measures only those), its block's
// luminance sum and sum of squares (xy, `block_contrast`); then the previous gain with its
// measurements, the blend, the pixels and the previous contrast gain, then the blades'
// running mean before. Out: the far ring's sums (shown with the count, model), the near
// ring's, the next gain, the gain the level would light with, the local contrasts' sums
// (far, near), the next contrast gain with the one the cards would be shown with, and the
// blades' next running mean.
//!include common.wgsl
//!include far_gain_math.wgsl

struct GainPixel {
    actual_f: vec4<f32>,
    sky_near: vec4<f32>,
    model: vec4<f32>,
    block: vec4<f32>,
}

@group(0) @binding(0) var<storage, read> probe_pixels: array<GainPixel>;
@group(0) @binding(1) var<storage, read> probe_previous: array<vec4<f32>, 3>;
@group(0) @binding(2) var<storage, read_write> probe_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn probe(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x != 0u {
        return;
    }
    var far_shown = vec4<f32>(0.0);
    var far_model = vec4<f32>(0.0);
    var near_shown = vec4<f32>(0.0);
    var near_model = vec4<f32>(0.0);
    var d = vec4<f32>(0.0);
    // The count comes in: a buffer is never empty, so an empty list is one unread pixel.
    let count = u32(probe_previous[1].y);
    for (var k = 0u; k < count; k++) {
        let s = probe_pixels[k];
        let t = gain_terms(s.actual_f.rgb, s.sky_near.rgb, s.actual_f.w, s.model.rgb);
        let c = block_contrast(s.block.xy, s.actual_f.w * dot(s.sky_near.rgb, LUMA));
        if s.sky_near.w > 0.5 {
            // model.w: 1 for a pixel standing on a blade, the only ones measured here.
            if s.model.w > 0.5 {
                near_shown += vec4<f32>(t.shown, 1.0);
                near_model += vec4<f32>(t.model, 0.0);
                d.y += c;
            }
            near_model.w += 1.0;
        } else {
            far_shown += vec4<f32>(t.shown, 1.0);
            far_model += vec4<f32>(t.model, 1.0);
            d.x += c;
        }
    }
    let previous = probe_previous[0];
    let next = next_gain(far_shown, far_model.rgb, near_shown, near_model, previous, probe_previous[1].x);
    let n = select(0.0, previous.w, previous.w > 0.5);
    let k = next_contrast(d.x, far_shown.w, d.y, near_shown.w, probe_previous[1].z, n, probe_previous[1].x);
    probe_out[0] = far_shown;
    probe_out[1] = far_model;
    probe_out[2] = near_shown;
    probe_out[3] = near_model;
    probe_out[4] = next;
    probe_out[5] = vec4<f32>(far_gain(bitcast<vec4<u32>>(next)), 0.0);
    probe_out[6] = d;
    probe_out[7] = vec4<f32>(k, contrast_gain(bitcast<u32>(k)), 0.0, 0.0);
    probe_out[8] = vec4<f32>(next_blades_mean(near_shown, near_model, probe_previous[2].xyz, n, probe_previous[1].x), 0.0);
}
