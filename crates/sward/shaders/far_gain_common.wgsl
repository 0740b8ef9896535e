// The far levels' light gain, measured (far_gain_math.wgsl): one workgroup looks at a
// grid of the frame's pixels once its grass is lit (the resolved radiance, before TAA and
// the tone curve). A pixel whose point lies on the ground or below the tallest blade's
// height over it (a blade, a card, or the ground between them; not the sky, not a taller
// object) is compared with the far grass's light at the ground below it
// (`far_grass_light`, shadowed as the point is, without the gain):
// - beyond the blades' reach, within `params.ring` (the far levels' first metres), for
//   the far ring's sums (cards and ground together: the terrain's mesh is coarse that far
//   out, and its pixels stand above or below the height function by more than a card's
//   root);
// - inside the reach, within `params.near`, for the near ring's, where only the pixels
//   standing on a blade are measured: told by the blades' share of the pixel that the
//   deferred shading marks in its alpha, or without it by their height (which cannot tell
//   a card from a blade: the ring then ends where the cards fade in). The ground between
//   the near blades is soil turning to the far ground's grass, lit with the gain: measured,
//   it fed the gain back into its own aim;
// - the blades' local contrast for the contrast gain within `params.contrast`, on the
//   pixels standing above the ground, and the far ring's (`block_contrast`: each measured
//   pixel's block of CONTRAST_BLOCK² texels, in this frame's radiance).
// The sums, and the local contrasts' sums, are reduced across the workgroup; the light
// gain is written into the far state's words 4-7, the blades' ratio (a running mean, for
// the panel: the gain takes this frame's) and the contrast gain into words 8-11
// (`render::far_gain`), and each sector's multiplier of the gain into words 12-27
// (far_sectors.wgsl), which the next frame's billboards and far ground read.
// The depth texture's binding and `frame_depth` come from the including file (one sample
// or multisampled).
//!include common.wgsl
//!include light.wgsl
//!include blade_shade.wgsl
//!include far_grass.wgsl
//!include terrain_height.wgsl
//!include far_gain_math.wgsl

struct GainParams {
    // x, y: the ring's inner and outer distance (m); z: the tallest blade (m); w: the blend
    // of a new measurement into a gain.
    ring: vec4<f32>,
    // x, y: the sample grid's columns and rows; z: the frame's number.
    grid: vec4<u32>,
    // x, y: the near ring's inner and outer distance (m); z: 1 when cards are drawn (the
    // contrast gain is theirs, and measured only then); w: 1 when the frame's grass was
    // lit deferred, which marks the blades' share of each pixel in its alpha
    // (`BLADE_ALPHA`): the near ring's blades are told from cards and ground by it.
    near: vec4<f32>,
    // x, y: the contrast's ring, inner and outer distance (m): the blades' variation is
    // measured there, on the pixels standing on a blade.
    contrast: vec4<f32>,
}

// The alpha the deferred shading leaves in a pixel all blades (twin of `BLADE_ALPHA` in
// grass_vis.wgsl, which this pass does not include).
const MARKED_ALPHA: f32 = 3.0;
// The share of a pixel's samples on blades for it to count as the blades' in the near
// ring: most of it, so that what lies behind them (cards lit with the gain, soil) weighs
// little.
const MARKED_SHARE: f32 = 0.5;

@group(0) @binding(0) var<uniform> frame: Frame;
// Bindings 1 and 2: the terrain's parameters and grid (terrain_height.wgsl).
// The far state: words 0-1 the gusts' bend at the blades' edge, 2 the far field's distance
// gain, 4-7 the gain, 8-10 the blades' ratio to the model (its running mean), 11 the
// contrast gain, 12-27 the sectors' multipliers.
@group(0) @binding(3) var<storage, read_write> far_state: array<u32, FAR_STATE_WORDS>;
@group(0) @binding(4) var<uniform> params: GainParams;
@group(0) @binding(5) var scene_color: texture_2d<f32>;
// What the frame shows: the TAA's history where it blended the frame, else `scene_color`
// itself. The near ring's blades are read there (the history smooths their sway, and the
// far levels should match the blades as shown); the far ring is read in this frame's
// radiance, which answers the gains at once (read in the history, which follows them over
// many frames, the gains overshot: the cards' contrast 83-99 % above the blades').
@group(0) @binding(7) var shown_color: texture_2d<f32>;

const GAIN_THREADS: u32 = 128u;
// Per invocation, for the far and the near ring: the radiance shown (rgb) with the pixels
// counted (w), and the model's radiance.
var<workgroup> far_shown: array<vec4<f32>, 128>;
var<workgroup> far_model: array<vec4<f32>, 128>;
var<workgroup> near_shown: array<vec4<f32>, 128>;
var<workgroup> near_model: array<vec4<f32>, 128>;
// Per invocation, for the far field's distance gain (`distance_gain`): the luminance shown
// and the model's (xy) and the pixels (z).
var<workgroup> far_field: array<vec4<f32>, 128>;
// Per invocation: the sums of the pixels' local contrasts (`block_contrast`), far ring (x)
// and the contrast ring (y).
var<workgroup> shown_d: array<vec4<f32>, 128>;

fn state_gain(at: u32) -> vec4<f32> {
    return bitcast<vec4<f32>>(vec4<u32>(far_state[at], far_state[at + 1u], far_state[at + 2u], far_state[at + 3u]));
}

fn store_gain(at: u32, g: vec4<f32>) {
    let w = bitcast<vec4<u32>>(g);
    far_state[at] = w.x;
    far_state[at + 1u] = w.y;
    far_state[at + 2u] = w.z;
    far_state[at + 3u] = w.w;
}

// Sums each invocation's entries of the workgroup's arrays into their first (invocation
// `i`; the rings' four arrays, and the contrast's and the far field's with `all`).
fn reduce_sums(i: u32, all: bool) {
    for (var s = GAIN_THREADS / 2u; s > 0u; s = s / 2u) {
        if i < s {
            far_shown[i] += far_shown[i + s];
            far_model[i] += far_model[i + s];
            near_shown[i] += near_shown[i + s];
            near_model[i] += near_model[i + s];
            if all {
                shown_d[i] += shown_d[i + s];
                far_field[i] += far_field[i + s];
            }
        }
        workgroupBarrier();
    }
}

// The luminance of `tex` over the block of CONTRAST_BLOCK² texels around `p` (clamped to
// the frame of `size`): its sum and sum of squares, for `block_contrast`.
fn block_luma(tex: texture_2d<f32>, p: vec2<u32>, size: vec2<u32>) -> vec2<f32> {
    var sums = vec2<f32>(0.0);
    let last = vec2<i32>(size) - 1;
    for (var y = 0; y < CONTRAST_BLOCK; y++) {
        for (var x = 0; x < CONTRAST_BLOCK; x++) {
            let at = vec2<i32>(p) + vec2<i32>(x, y) - CONTRAST_BLOCK / 2;
            let l = dot(textureLoad(tex, clamp(at, vec2<i32>(0), last), 0).rgb, LUMA);
            sums += vec2<f32>(l, l * l);
        }
    }
    return sums;
}

@compute @workgroup_size(128)
fn measure(@builtin(local_invocation_index) i: u32) {
    let wave = mean_wave(far_state[0], far_state[1]);
    let size = vec2<u32>(frame.viewport_time.xy);
    let cells = params.grid.x * params.grid.y;
    let zero = vec4<f32>(0.0);
    var shown_f = zero;
    var model_f = zero;
    var shown_n = zero;
    var model_n = zero;
    var disp = zero;
    var field = zero;
    // Per sector of the view's azimuth (far_sectors.wgsl), the far ring's and the near
    // ring's luminance sums (`next_sectors`), each pixel shared between the two sectors it
    // lies between.
    var sec: array<vec4<f32>, SECTOR_SUMS>;
    for (var k = i; k < cells; k += GAIN_THREADS) {
        let cell = vec2<u32>(k % params.grid.x, k / params.grid.x);
        // A pixel of the grid's cell, a different one each frame: the blades, cards and
        // gaps a fixed pixel would land on are a sample of the field, and the means of
        // `next_gain` average the frames' samples into the field's.
        let seed = hash32(k ^ hash32(params.grid.z));
        let jitter = vec2<f32>(f32(seed & 0xffffu), f32(seed >> 16u)) / 65536.0;
        let at = (vec2<f32>(cell) + jitter) * vec2<f32>(size) / vec2<f32>(params.grid.xy);
        let p = min(vec2<u32>(at), size - 1u);
        let z = frame_depth(p);
        let world = world_at(p, z);
        let to_p = world - frame.camera_pos.xyz;
        let dist = length(to_p);
        let h = terrain_height(world.xz);
        let above = world.y - h.x;
        let grass = z < 1.0 && abs(above) <= params.ring.z;
        let far = grass && dist >= params.ring.x && dist < params.ring.y;
        let in_near = grass && dist >= params.near.x && dist < params.near.y;
        let in_field = grass && dist >= FAR_BIN.x * params.ring.x && dist < FAR_BIN.y * params.ring.x;
        // Above the ground by a tenth of the tallest blade (the ground's mesh is fine near
        // the camera): a blade, or a card.
        let raised = above > 0.1 * params.ring.z;
        let in_contrast = grass && dist >= params.contrast.x && dist < params.contrast.y && raised;
        // The light model only where a sum takes it: most of the grid is sky, objects or
        // ground outside the rings (the model's 16 light evaluations and the shadow lookup
        // are the pass's cost).
        if !(far || in_near || in_field || in_contrast) {
            continue;
        }
        let n = normalize(vec3<f32>(-h.y, 1.0, -h.z));
        let l = far_grass_light(vec3<f32>(world.x, h.x, world.z), n, terrain.grass_albedo.rgb, wave);
        let should = l.ambient + sun_visibility(world) * l.sun;
        let sky = sky_radiance(to_p / max(dist, 1e-4));
        let f = clamp(1.0 - exp(-dist / max(frame.viewport_time.w, 1.0)), 0.0, 1.0);
        let frame_texel = textureLoad(scene_color, p, 0);
        let radiance = select(frame_texel.rgb, textureLoad(shown_color, p, 0).rgb, in_near || in_contrast);
        let t = gain_terms(radiance, sky, f, should);
        let shown = vec4<f32>(t.shown, 1.0);
        // The near ring measures the pixels standing on a blade: where the frame marks its
        // blades (deferred), most of the pixel's samples on them; else `raised`, which
        // cannot tell a card from a blade (the near ring then ends where the cards fade
        // in). The model's sums count in w every pixel of the ring.
        let share = clamp((frame_texel.a - 1.0) / (MARKED_ALPHA - 1.0), 0.0, 1.0);
        let near = in_near && select(raised, share >= MARKED_SHARE, params.near.w > 0.5);
        let model = vec4<f32>(t.model, 1.0);
        let d = dot(t.shown, LUMA);
        let pair = sector_pair(to_p.xz);
        // The multiplier the pixel's direction was lit with (the cards and ground read it
        // last frame).
        let lit = sector_gain(pair, far_state[SECTOR_WORD + pair.a], far_state[SECTOR_WORD + pair.b]);
        // The local contrasts (`block_contrast`), both rings' in this frame's radiance: the
        // cards' contrast gain answers at once, as the light gain does. With TAA, the far
        // ring's read in the history overshot (the prairie's cards 37 % above the blades'
        // contrast just past them at 240 × 136, 18.7 levels dark), and the near ring's
        // read there (smoothed) left them 39 % under it; both in the frame, 3 %. A block
        // holds one light: the view's spread of it across the sectors does not count, and
        // no multiplier needs taking off.
        var contrast = vec2<f32>(0.0);
        if far || in_contrast {
            let c = block_contrast(block_luma(scene_color, p, size), f * dot(sky, LUMA));
            contrast = select(vec2<f32>(0.0), vec2<f32>(c), vec2<bool>(far, in_contrast));
        }
        shown_f += select(zero, shown, far);
        model_f += select(zero, model, far);
        shown_n += select(zero, shown, near);
        model_n += select(zero, vec4<f32>(t.model, 0.0), near);
        model_n.w += select(0.0, 1.0, in_near);
        let model_l = dot(t.model, LUMA);
        field += select(zero, vec4<f32>(d, model_l, 1.0, 0.0), in_field);
        // w: the contrast ring's pixels (the sum of their local contrasts is `disp.y`).
        field.w += select(0.0, 1.0, in_contrast);
        let sec_far = select(zero, vec4<f32>(d, model_l, d / lit, 1.0), far);
        let wa = vec4<f32>(1.0, 1.0, 1.0 - pair.t, 1.0) * (1.0 - pair.t);
        let wb = vec4<f32>(1.0, 1.0, pair.t, 1.0) * pair.t;
        let sec_near = select(zero, vec4<f32>(select(vec3<f32>(0.0), vec3<f32>(d, model_l, 1.0), near), 1.0), in_near);
        sec[2u * pair.a] += wa * sec_far;
        sec[2u * pair.b] += wb * sec_far;
        sec[2u * pair.a + 1u] += (1.0 - pair.t) * sec_near;
        sec[2u * pair.b + 1u] += pair.t * sec_near;
        disp += vec4<f32>(contrast, 0.0, 0.0);
    }
    far_shown[i] = shown_f;
    far_model[i] = model_f;
    near_shown[i] = shown_n;
    near_model[i] = model_n;
    shown_d[i] = disp;
    far_field[i] = field;
    workgroupBarrier();
    reduce_sums(i, true);
    // The measurements the gain averaged before this frame (thread 0's).
    var n_before = 0.0;
    if i == 0u {
        let previous = state_gain(4u);
        let next = next_gain(far_shown[0], far_model[0].rgb, near_shown[0], near_model[0], previous, params.ring.w);
        let n = select(0.0, previous.w, previous.w > 0.5);
        n_before = n;
        var k = bitcast<f32>(far_state[11]);
        if params.near.z > 0.5 {
            k = next_contrast(shown_d[0].x, far_shown[0].w, shown_d[0].y, far_field[0].w, k, n, params.ring.w);
        }
        // The far field's distance gain, against the ring's need in this frame (its pixels
        // were lit with the light gain alone: the ramp starts past it).
        let ring_shown = dot(far_shown[0].rgb, LUMA);
        let ring_need = select(0.0, dot(far_model[0].rgb, LUMA) / ring_shown, far_shown[0].w >= GAIN_MIN_SAMPLES && ring_shown > 1e-6);
        far_state[2] = bitcast<u32>(next_distance_gain(far_field[0].xyz, ring_need, bitcast<f32>(far_state[2]), n, params.ring.w));
        store_gain(4u, next);
        let ratio_before = bitcast<vec3<f32>>(vec3<u32>(far_state[8], far_state[9], far_state[10]));
        let ratio = next_blades_mean(near_shown[0], near_model[0], ratio_before, n, params.ring.w);
        store_gain(8u, vec4<f32>(ratio, k));
    }
    // The sectors' sums, reduced four at a time in the rings' arrays (the workgroup's
    // memory holds no more), into thread 0's `sums`.
    var sums: array<vec4<f32>, SECTOR_SUMS>;
    for (var r = 0u; r < SECTOR_SUMS; r += 4u) {
        // Thread 0 has read the arrays' last sums.
        workgroupBarrier();
        far_shown[i] = sec[r];
        far_model[i] = sec[r + 1u];
        near_shown[i] = sec[r + 2u];
        near_model[i] = sec[r + 3u];
        workgroupBarrier();
        reduce_sums(i, false);
        sums[r] = far_shown[0];
        sums[r + 1u] = far_model[0];
        sums[r + 2u] = near_shown[0];
        sums[r + 3u] = near_model[0];
    }
    if i == 0u {
        var previous: array<f32, SECTORS>;
        for (var k = 0u; k < SECTORS; k++) {
            previous[k] = bitcast<f32>(far_state[SECTOR_WORD + k]);
        }
        let next = next_sectors(sums, previous, n_before, params.ring.w);
        for (var k = 0u; k < SECTORS; k++) {
            far_state[SECTOR_WORD + k] = bitcast<u32>(next[k]);
        }
    }
}
