// Temporal anti-aliasing (issue 27, point 5; `render/taa.rs`). The 3D passes draw one sample
// per pixel through a projection jittered by a different sub-pixel offset every frame; this
// full-screen pass blends each pixel of that frame with the history (the last frames'
// result) found where the pixel's surface was one frame ago:
//
// - the surface point comes from the depth buffer and this frame's jittered view;
// - a grass pixel (the visibility buffer names its blade, and the grass is still the
//   nearest surface there) moves with its blade: the point's offset along the blade's
//   quadratic curve (Eq. 21) is the change of the control points since the last frame,
//   2 v (1 - v) (v1' - v1) + v^2 (v2' - v2), so swaying blades do not smear;
// - a point on a moving collider (a ball's sphere) moves with its centre;
// - the last frame's unjittered view places it, and the history is read that far from
//   the pixel's centre (the motion between the two unjittered views; this frame's jitter
//   is added back, so a still view reads the history at the pixel's centre);
// - the history is clamped to the box of the pixel's 3 x 3 neighbourhood in this frame
//   (what it shows where it was occluded or has changed is thrown away), compared in a
//   compressed space, c / (1 + max(c)), so a bright sun glint does not stretch the box,
//   and blended in linear radiance, as MSAA's resolve averages.
//
// A pixel without a history (the first frame, off the last frame's view, a blade newly
// streamed into its slot) takes this frame's sample alone.
//
// Twin: `render::taa::reference` (CPU), checked in tests/taa.rs.

//!include common.wgsl

struct TaaUniforms {
    // This frame's jittered view-projection relative to its eye, inverted.
    inv_view_proj: mat4x4<f32>,
    // The last frame's unjittered view-projection relative to its eye.
    prev_view_proj: mat4x4<f32>,
    // This eye minus the last one; w: 1 where a history exists.
    eye_shift: vec4<f32>,
    // The blend weight of this frame, 1 with a visibility buffer, the target's size.
    params: vec4<f32>,
    // xy: this frame's jitter in normalised device coordinates; z: 1 to clamp the
    // history to the neighbourhood and weigh the new frame up where the pixel moved (0:
    // measurements only, `taa::TaaSettings`); w: how many of `moving` are used.
    jitter: vec4<f32>,
    // The colliders that moved since the last frame, in pairs: the centre now relative to
    // this eye and the radius, then the centre then (twin: `taa::MAX_MOVING`).
    moving: array<vec4<f32>, 16>,
}

// How far from a moving collider's sphere (relative to its radius) a surface point still
// moves with it.
const ON_SPHERE: f32 = 0.05;

@group(0) @binding(0) var<uniform> taa: TaaUniforms;
@group(0) @binding(1) var scene: texture_2d<f32>;
@group(0) @binding(2) var history: texture_2d<f32>;
@group(0) @binding(3) var history_sampler: sampler;
@group(0) @binding(4) var depth: texture_depth_2d;
@group(0) @binding(5) var vis: texture_2d<u32>;
@group(0) @binding(6) var<storage, read> blades: array<Blade>;
@group(0) @binding(7) var<storage, read> prev_blades: array<PrevBlade>;
// The weight of this frame where the pixel moved MOVING_PIXELS or more since the last.
const MOVING_BLEND: f32 = 0.3;
const MOVING_PIXELS: f32 = 2.0;


@vertex
fn vs_taa(@builtin(vertex_index) vid: u32) -> @builtin(position) vec4<f32> {
    let xy = vec2<f32>(f32((vid << 1u) & 2u), f32(vid & 2u)) * 2.0 - 1.0;
    return vec4<f32>(xy, 0.0, 1.0);
}

fn squash(c: vec3<f32>) -> vec3<f32> {
    return c / (1.0 + max(c.r, max(c.g, c.b)));
}

fn unsquash(c: vec3<f32>) -> vec3<f32> {
    return c / max(1.0 - max(c.r, max(c.g, c.b)), 1e-4);
}

// Where the surface seen at pixel `px` (centre `centre`, in pixels) was in the last frame,
// as a history texture coordinate; z = 0 where it has no history there.
fn history_uv(px: vec2<i32>, centre: vec2<f32>) -> vec3<f32> {
    if taa.eye_shift.w < 0.5 {
        return vec3<f32>(0.0);
    }
    let size = taa.params.zw;
    let d = textureLoad(depth, px, 0);
    let ndc = vec2<f32>(centre.x / size.x * 2.0 - 1.0, 1.0 - centre.y / size.y * 2.0);
    let w = taa.inv_view_proj * vec4<f32>(ndc, d, 1.0);
    var p = w.xyz / w.w;
    // A point on a moving collider (a ball) moves with its centre; its spin is left out.
    for (var i = 0u; i < u32(taa.jitter.w); i++) {
        let now = taa.moving[2u * i];
        if abs(distance(p, now.xyz) - now.w) <= ON_SPHERE * now.w {
            p += taa.moving[2u * i + 1u].xyz - now.xyz;
            break;
        }
    }
    if taa.params.y > 0.5 {
        let v = textureLoad(vis, px, 0);
        if v.w == 1u && bitcast<f32>(v.z) == d {
            let b = blades[v.x];
            let pb = prev_blades[v.x];
            if any(b.v0_dir != pb.v0_dir) {
                // A blade streamed into this slot since the last frame.
                return vec3<f32>(0.0);
            }
            let t = unpack2x16unorm(v.y).y;
            p += 2.0 * t * (1.0 - t) * (pb.v1_height.xyz - b.v1_height.xyz)
                + t * t * (pb.v2_width.xyz - b.v2_width.xyz);
        }
    }
    let c = taa.prev_view_proj * vec4<f32>(p + taa.eye_shift.xyz, 1.0);
    if c.w <= 0.0 {
        return vec3<f32>(0.0);
    }
    // The pixel's motion between the unjittered views, from its own centre: the history
    // is read where the same jittered sample lay, so a still view reads it at the pixel's
    // centre, unblurred by the resampling.
    let ndc_then = c.xy / c.w + taa.jitter.xy;
    let uv = vec2<f32>(ndc_then.x * 0.5 + 0.5, 0.5 - ndc_then.y * 0.5);
    let inside = all(uv >= vec2<f32>(0.0)) && all(uv <= vec2<f32>(1.0));
    return vec3<f32>(uv, select(0.0, 1.0, inside));
}

// The history at `uv` through a Catmull-Rom filter (the 4 x 4 texels around it, as five
// bilinear reads without the corners): a bilinear read blurs the history a little more
// every frame it moves, a cubic one keeps its detail.
fn history_cubic(uv: vec2<f32>) -> vec3<f32> {
    let size = taa.params.zw;
    let p = uv * size;
    let tc = floor(p - 0.5) + 0.5;
    let f = p - tc;
    let w0 = f * (-0.5 + f * (1.0 - 0.5 * f));
    let w1 = 1.0 + f * f * (-2.5 + 1.5 * f);
    let w2 = f * (0.5 + f * (2.0 - 1.5 * f));
    let w3 = f * f * (-0.5 + 0.5 * f);
    let w12 = w1 + w2;
    let t0 = (tc - 1.0) / size;
    let t3 = (tc + 2.0) / size;
    let t12 = (tc + w2 / w12) / size;
    let weights = array<f32, 5>(w12.x * w0.y, w0.x * w12.y, w12.x * w12.y, w3.x * w12.y, w12.x * w3.y);
    let at = array<vec2<f32>, 5>(
        vec2<f32>(t12.x, t0.y),
        vec2<f32>(t0.x, t12.y),
        t12,
        vec2<f32>(t3.x, t12.y),
        vec2<f32>(t12.x, t3.y),
    );
    var sum = vec3<f32>(0.0);
    var total = 0.0;
    for (var i = 0u; i < 5u; i++) {
        sum += textureSampleLevel(history, history_sampler, at[i], 0.0).rgb * weights[i];
        total += weights[i];
    }
    return max(sum / total, vec3<f32>(0.0));
}

@fragment
fn fs_taa(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let px = vec2<i32>(pixel.xy);
    let last = vec2<i32>(taa.params.zw) - 1;
    let current = textureLoad(scene, px, 0);
    let now = squash(max(current.rgb, vec3<f32>(0.0)));
    // The neighbourhood's box, narrowed to its mean +- one standard deviation (variance
    // clipping): the box of a pixel among thin blades spans nearly every colour there.
    var lo = now;
    var hi = now;
    var m1 = vec3<f32>(0.0);
    var m2 = vec3<f32>(0.0);
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let q = clamp(px + vec2<i32>(dx, dy), vec2<i32>(0), last);
            let c = squash(max(textureLoad(scene, q, 0).rgb, vec3<f32>(0.0)));
            lo = min(lo, c);
            hi = max(hi, c);
            m1 += c;
            m2 += c * c;
        }
    }
    let mean = m1 / 9.0;
    let sigma = sqrt(max(m2 / 9.0 - mean * mean, vec3<f32>(0.0)));
    lo = max(lo, mean - sigma);
    hi = min(hi, mean + sigma);
    let h = history_uv(px, pixel.xy);
    var blend = 1.0;
    var past = now;
    if h.z > 0.5 {
        past = squash(history_cubic(h.xy));
        blend = taa.params.x;
        if taa.jitter.z > 0.5 {
            past = clamp(past, lo, hi);
            // A moving pixel's history has been resampled once per frame it moved, each
            // time a little softer: it keeps less of it.
            let moved = length(h.xy * taa.params.zw - pixel.xy);
            blend = mix(blend, MOVING_BLEND, clamp(moved / MOVING_PIXELS, 0.0, 1.0));
        }
    }
    // The blend itself in linear radiance, as MSAA's resolve averages: averaging in the
    // compressed space would weigh the dark gaps between far blades up and leave the far
    // field darker than the blades' mean (5 to 12 levels on the prairie).
    return vec4<f32>(mix(unsquash(past), max(current.rgb, vec3<f32>(0.0)), blend), current.a);
}
