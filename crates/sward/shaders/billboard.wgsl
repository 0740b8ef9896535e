// Billboards in the middle distance (issue 12; Qiu et al.'s middle level, the prairie
// thesis's far plants): one camera-facing card per cell of a grid around the camera
// (`billboard_place.wgsl`); the cull (`billboard_cull.wgsl`) keeps the cards in the ring and
// in view, with their sway and bending, and this draw shows them without instancing:
// vertex i belongs to kept card i / 6. A card shows a tuft from the atlas sward renders from
// its own blades at start-up, lit by the same sun as the far ground, swaying with the wind
// the blades read (analytic and fluid) and bent away from the colliders and balls (Qiu's
// billboard bending). It fades in over the band where the blades thin out and out towards
// the billboard radius: dithered (alpha test) or through alpha-to-coverage with MSAA.
//!include common.wgsl
//!include light.wgsl
//!include terrain_height.wgsl
//!include billboard_place.wgsl
//!include far_gain_math.wgsl
//!include card_profile.wgsl

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(3) var<uniform> bb: BillboardParams;
@group(0) @binding(4) var atlas: texture_2d_array<f32>;
@group(0) @binding(5) var atlas_sampler: sampler;
// Which of the four facings each texel's blades have (weights adding up to one).
@group(0) @binding(6) var facing_atlas: texture_2d_array<f32>;
// Each layer's height profile, `PROFILE_ROWS` row bands per layer (`card_profile.wgsl`).
@group(0) @binding(7) var<storage, read> profile: array<ProfileRow>;
@group(0) @binding(10) var<storage, read> cards: array<DrawnCard>;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(1) uv: vec2<f32>,
    @location(2) @interpolate(flat) layer: u32,
    @location(3) @interpolate(flat) fade: f32,
    // The sky's light on the card (rgb) and the fog over it: the sky's radiance behind it
    // (rgb) and the fog's share (w). Once per card, not per fragment: a card is a sliver of
    // the view far from the camera, where the sun's shadow and the fog do not change
    // across it, and a CPU adapter (llvmpipe) runs the shadow lookup and the Perez sky
    // for every fragment of every card whether it would return early or not.
    @location(4) @interpolate(flat) light_rgb: vec3<f32>,
    @location(5) @interpolate(flat) fog_sky: vec4<f32>,
    // The sun's part of the light for each blade facing, shadowed (rgb).
    @location(6) @interpolate(flat) sun0: vec3<f32>,
    @location(7) @interpolate(flat) sun1: vec3<f32>,
    @location(8) @interpolate(flat) sun2: vec3<f32>,
    @location(9) @interpolate(flat) sun3: vec3<f32>,
    // The contrast gain the card's texels are shown with (`far_gain`).
    @location(10) @interpolate(flat) contrast: f32,
    // The mip bias of the card's texels (`CARD_SHARPEN`, handed over as the contrast is,
    // by the cull).
    @location(11) @interpolate(flat) sharpen: f32,
    // The mean the texels are moved from by the contrast gain: the card's lit mean at each
    // row band of its layer's profile, the upper four and the lower four.
    @location(12) @interpolate(flat) profile_top: vec4<f32>,
    @location(13) @interpolate(flat) profile_bottom: vec4<f32>,
}

// How far a card is turned off facing the camera, at most (radians; `billboard::CARD_TURN`).
const CARD_TURN: f32 = 0.35;

@vertex
fn vs_main(@builtin(vertex_index) vi: u32) -> VertexOut {
    var out: VertexOut;
    let c = cards[vi / 6u];
    let pos = c.pos_fade.xyz;
    let k = vi % 6u;
    let u = select(0.0, 1.0, k == 1u || k == 2u || k == 4u);
    let v = select(0.0, 1.0, k == 2u || k == 4u || k == 5u);
    var to_eye = frame.camera_pos.xz - pos.xz;
    if length(to_eye) < 1e-4 {
        to_eye = vec2<f32>(0.0, 1.0);
    }
    // Turned a little off the camera, by a hash of its cell, so that the cards of a row
    // do not line up into one sheet (issue 27, point 2).
    let turn = (f32(hash32(c.info.x ^ 0x5f356495u) >> 8u) * BB_UNIT - 0.5) * 2.0 * CARD_TURN;
    let e = normalize(to_eye);
    let cs = cos(turn);
    let sn = sin(turn);
    let right = vec3<f32>(-e.y * cs - e.x * sn, 0.0, e.x * cs - e.y * sn);
    // A level-k card is 2^k base cards wide and shows the strip 2^k times (the sampler
    // repeats it across), so its blades keep their width; it is as tall as the blades.
    let repeats = f32(1u << c.info.w);
    let w = bb.eye_card.z * repeats * c.top_scale.w;
    let h = bb.eye_card.w * c.top_scale.w;
    // The root row sits a little into the ground so the card meets it on slopes.
    var p = pos + right * ((u - 0.5) * w) + vec3<f32>(0.0, v * 1.05 * h - 0.05 * h, 0.0);
    if v > 0.5 {
        p += c.top_scale.xyz;
    }
    out.clip = frame.view_proj * vec4<f32>(p, 1.0);
    out.uv = vec2<f32>(select(1.0 - u, u, c.info.z == 1u) * repeats, 1.0 - v);
    out.layer = c.info.y;
    out.fade = c.pos_fade.w;
    // The blades' own light averaged over what a distant eye sees of them (the cull's
    // `far_grass_light`, per unit of albedo), as the far ground has it: cards and the
    // ground between them read as one, and as the blades they stand for. The shadows of
    // what stands between the card and the sun fall on it too, looked up at its middle.
    let middle = pos + vec3<f32>(0.0, 0.5 * h, 0.0) + 0.5 * c.top_scale.xyz;
    let lit = sun_visibility(middle);
    out.light_rgb = c.light_ambient.rgb;
    out.sun0 = lit * c.light_sun[0].rgb;
    out.sun1 = lit * c.light_sun[1].rgb;
    out.sun2 = lit * c.light_sun[2].rgb;
    out.sun3 = lit * c.light_sun[3].rgb;
    // The contrast and the mip bias, handed over to the far ground's by the cull.
    out.sharpen = c.light_sun[0].w;
    out.contrast = c.light_ambient.w;
    let sun = array<vec3<f32>, 4>(out.sun0, out.sun1, out.sun2, out.sun3);
    var rows: array<f32, 8>;
    for (var r = 0u; r < PROFILE_ROWS; r++) {
        rows[r] = profile_luma(profile[c.info.y * PROFILE_ROWS + r], out.light_rgb, sun);
    }
    out.profile_top = vec4<f32>(rows[0], rows[1], rows[2], rows[3]);
    out.profile_bottom = vec4<f32>(rows[4], rows[5], rows[6], rows[7]);
    let to_p = middle - frame.camera_pos.xyz;
    let dist = length(to_p);
    let f = 1.0 - exp(-dist / max(frame.viewport_time.w, 1.0));
    out.fog_sky = vec4<f32>(sky_radiance(to_p / max(dist, 1e-4)), clamp(f, 0.0, 1.0));
    return out;
}

// 4×4 ordered dither in [0, 1): the screen-door fade of the single-sample path.
fn bayer(p: vec2<f32>) -> f32 {
    let x = u32(p.x) % 4u;
    let y = u32(p.y) % 4u;
    let m = array<u32, 16>(0u, 8u, 2u, 10u, 12u, 4u, 14u, 6u, 3u, 11u, 1u, 9u, 15u, 7u, 13u, 5u);
    return (f32(m[y * 4u + x]) + 0.5) / 16.0;
}

// Display colour (the scene's exposure and tone curve applied) instead of radiance: a
// host's 8-bit target (`render::host`, as `grass.wgsl`'s).
override DISPLAY_OUTPUT: bool = false;

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    // Three mip levels sharper than the card's footprint: a pixel shows a few of the
    // strip's blades, as a pixel of the blades themselves shows one, and not their average
    // (the mip the footprint asks for left the cards 67 % flatter than the blades at
    // 28-50 m; the level-0 texels, 36 % flatter, sparkled 19 % more with the wind on).
    // Far out, where a pixel spans half a card, the footprint's own mip, as the far ground.
    let tex = textureSampleBias(atlas, atlas_sampler, in.uv, in.layer, in.sharpen);
    // Alpha test, with the fade as a dither: a card fading in shows more of its texels
    // frame by frame, never a half-transparent sheet (no sorting needed). With MSAA the
    // alpha also drives alpha-to-coverage, which smooths the cut.
    if tex.a < 0.5 || in.fade < bayer(in.clip.xy) {
        discard;
    }
    // Each blade of the strip lit as a blade turned its way (its facing's weights).
    let f = textureSampleBias(facing_atlas, atlas_sampler, in.uv, in.layer, in.sharpen);
    let sun = (f.r * in.sun0 + f.g * in.sun1 + f.b * in.sun2 + f.a * in.sun3) / max(f.r + f.g + f.b + f.a, 1e-3);
    let c = tex.rgb * (in.light_rgb + sun);
    // The texel's luminance moved from the mean of its row band as many times as far as the
    // contrast gain `far_gain` measured, so that the cards vary about their mean as the
    // blades do about theirs; the texel keeps its hue. (The ratio to the mean raised to
    // the gain, per channel or on the luminance, costs a logarithm and an exponential per
    // power and fragment, about 10 ms of the prairie's draw at 1280x720 on llvmpipe; after
    // 4 frames it left one band 7.4 levels bright where this leaves none past 3.5, after
    // 30 frames it was 2 levels closer.)
    // The mean is the card's at the texel's height (`card_profile.wgsl`), not the card's
    // own: moved from that, the shown texels' mean rose with the gain, 13 % at a gain of 2
    // and 28 % at 3 (the light gain the far ring settles on, windless prairie, 480 x 270,
    // 16 frames). Moved from the mean of the 8 x 8 texels around each (two more samples),
    // 8 % at 3, and the prairie's draw took 8 % longer at 1280 x 720.
    let ml = profile_at(in.profile_top, in.profile_bottom, in.uv.y);
    let l = max(dot(c, LUMA), 1e-8);
    let lit = c * (contrast_luma(l, ml, in.contrast) / l);
    let color = mix(lit, in.fog_sky.rgb, in.fog_sky.w);
    if DISPLAY_OUTPUT {
        return vec4<f32>(tonemap(color), tex.a);
    }
    return vec4<f32>(color, tex.a);
}
