// Probe: the far gain's arithmetic (far_gain_math.wgsl) over a list of pixels of one
// level, for the test that compares it with its CPU twin (`render::far_gain`). In: per
// pixel the radiance and f, the fog's colour, the model's radiance; then the previous gain
// and the blend. Out: the sums (shown, model), the pixels, the next gain and the gain the
// level would light with.
//!include far_gain_math.wgsl

struct GainPixel {
    actual_f: vec4<f32>,
    sky: vec4<f32>,
    model: vec4<f32>,
}

@group(0) @binding(0) var<storage, read> probe_pixels: array<GainPixel>;
@group(0) @binding(1) var<storage, read> probe_previous: array<vec4<f32>, 2>;
@group(0) @binding(2) var<storage, read_write> probe_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn probe(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x != 0u {
        return;
    }
    var shown = vec3<f32>(0.0);
    var model = vec3<f32>(0.0);
    // The count comes in: a buffer is never empty, so an empty list is one unread pixel.
    let n = u32(probe_previous[1].y);
    for (var k = 0u; k < n; k++) {
        let s = probe_pixels[k];
        let t = gain_terms(s.actual_f.rgb, s.sky.rgb, s.actual_f.w, s.model.rgb);
        shown += t.shown;
        model += t.model;
    }
    let next = next_gain(shown, model, f32(n), probe_previous[0], probe_previous[1].x);
    probe_out[0] = vec4<f32>(shown, f32(n));
    probe_out[1] = vec4<f32>(model, 0.0);
    probe_out[2] = next;
    probe_out[3] = vec4<f32>(far_gain(bitcast<vec4<u32>>(next)), 0.0);
}
