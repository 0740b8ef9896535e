// The far levels' light gain, measured (far_gain_math.wgsl): one workgroup looks at a
// grid of the frame's pixels once its grass is lit (the resolved radiance, before TAA and
// the tone curve). A pixel whose point lies beyond the blades' reach, within `params.ring`
// (the far levels' first metres), on the ground or below the tallest blade's height over
// it (a card, or the far ground between the cards; not the sky, not a taller object),
// should show the far grass's light at the ground below it (`far_grass_light`, shadowed as
// the point is, without the gain). (Cards and ground are measured together: the terrain's
// mesh is coarse that far out, and its pixels stand above or below the height function by
// more than a card's root.) The sums are reduced across the workgroup and the gain written
// into the far state's words 4-7, which the next frame's billboards and far ground read.
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
    // x, y: the sample grid's columns and rows.
    grid: vec4<u32>,
}

@group(0) @binding(0) var<uniform> frame: Frame;
// Bindings 1 and 2: the terrain's parameters and grid (terrain_height.wgsl).
// The far state: words 0-1 the gusts' bend at the blades' edge, 4-7 the gain.
@group(0) @binding(3) var<storage, read_write> far_state: array<u32, 8>;
@group(0) @binding(4) var<uniform> params: GainParams;
@group(0) @binding(5) var scene_color: texture_2d<f32>;

const GAIN_THREADS: u32 = 256u;
// Per invocation: the sums (shown, model) and the pixels counted.
var<workgroup> sum_shown: array<vec3<f32>, 256>;
var<workgroup> sum_model: array<vec3<f32>, 256>;
var<workgroup> counts: array<f32, 256>;

// The world point pixel `p` of the frame shows at depth `z`.
fn world_at(p: vec2<u32>, z: f32) -> vec3<f32> {
    let size = frame.viewport_time.xy;
    let uv = (vec2<f32>(p) + 0.5) / size;
    let ndc = vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, z, 1.0);
    let w = frame.inv_view_proj * ndc;
    return w.xyz / w.w;
}

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

@compute @workgroup_size(256)
fn measure(@builtin(local_invocation_index) i: u32) {
    let wave = mean_wave(far_state[0], far_state[1]);
    let size = vec2<u32>(frame.viewport_time.xy);
    let cells = params.grid.x * params.grid.y;
    let zero = vec3<f32>(0.0);
    var shown = zero;
    var model = zero;
    var count = 0.0;
    for (var k = i; k < cells; k += GAIN_THREADS) {
        let cell = vec2<u32>(k % params.grid.x, k / params.grid.x);
        // The middle pixel of the grid's cell.
        let p = min((2u * cell + 1u) * size / (2u * params.grid.xy), size - 1u);
        let z = frame_depth(p);
        let world = world_at(p, z);
        let to_p = world - frame.camera_pos.xyz;
        let dist = length(to_p);
        let h = terrain_height(world.xz);
        let above = world.y - h.x;
        let far = z < 1.0 && dist >= params.ring.x && dist < params.ring.y
            && abs(above) <= params.ring.z;
        let n = normalize(vec3<f32>(-h.y, 1.0, -h.z));
        let l = far_grass_light(vec3<f32>(world.x, h.x, world.z), n, terrain.grass_albedo.rgb, wave);
        let should = l.ambient + sun_visibility(world) * l.sun;
        let sky = sky_radiance(to_p / max(dist, 1e-4));
        let f = clamp(1.0 - exp(-dist / max(frame.viewport_time.w, 1.0)), 0.0, 1.0);
        let t = gain_terms(textureLoad(scene_color, p, 0).rgb, sky, f, should);
        shown += select(zero, t.shown, far);
        model += select(zero, t.model, far);
        count += select(0.0, 1.0, far);
    }
    sum_shown[i] = shown;
    sum_model[i] = model;
    counts[i] = count;
    workgroupBarrier();
    for (var s = GAIN_THREADS / 2u; s > 0u; s = s / 2u) {
        if i < s {
            sum_shown[i] += sum_shown[i + s];
            sum_model[i] += sum_model[i + s];
            counts[i] += counts[i + s];
        }
        workgroupBarrier();
    }
    if i == 0u {
        store_gain(4u, next_gain(sum_shown[0], sum_model[0], counts[0], state_gain(4u), params.ring.w));
    }
}
