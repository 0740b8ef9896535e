// The sun and the sky (issue 16), included by every lit pass after common.wgsl: the light's
// uniforms and the sun's cascaded shadow map (group 1), Preetham's analytic daylight sky
// (the sky pass and the fog share it), the shadow lookup with its percentage-closer filter,
// and exposure with the filmic tone mappers. `LightUniforms` is `sim::layout::LightUniforms`;
// `render::light` holds the CPU twins of the sky, the tone mappers and the cascades.

// sward:receiver begin
struct LightUniforms {
    // Light-space view-projection of each cascade (world -> [-1, 1]² x [0, 1]).
    cascades: array<mat4x4<f32>, 4>,
    // The far distance from the camera of each cascade (m).
    splits: vec4<f32>,
    // World size of one texel of each cascade (m).
    texel_world: vec4<f32>,
    // x: 1 shadows on, y: cascades, z: filter radius (texels), w: bias (texels).
    shadow: vec4<f32>,
    // x: 1 / resolution, y: resolution, z: where the shadows start to fade (m), w: unused.
    shadow_map: vec4<f32>,
    // The sun's radiance reaching the ground (rgb) and the exposure multiplier 2^EV.
    sun: vec4<f32>,
    // The sky's irradiance on a horizontal surface, divided by pi (rgb), and the tone
    // mapper (0 ACES, 1 AgX, 2 clamp).
    ambient: vec4<f32>,
    // x: sky model (0 Preetham, 1 gradient), y: turbidity, z: cos of the sun disk's radius,
    // w: the sun disk's radiance over the sun's.
    sky: vec4<f32>,
    // Perez coefficients A..E of luminance Y (x), chromaticity x (y) and y (z).
    perez_a: vec4<f32>,
    perez_b: vec4<f32>,
    perez_c: vec4<f32>,
    perez_d: vec4<f32>,
    perez_e: vec4<f32>,
    // The zenith's Y (scaled to scene radiance), x and y, each over its Perez F(0, theta_s);
    // w: theta_s, the sun's zenith angle.
    zenith: vec4<f32>,
    // Blade shading strengths: rounded normal, translucency, specular, ambient occlusion;
    // colour variation, wind waves, canopy leaf area (m²/m²), the shortest blade's height
    // over the tallest's (the canopy's height spread, `render::light::canopy`).
    shading_a: vec4<f32>,
    shading_b: vec4<f32>,
    // xy: the blades' widths (m) Eq. 24's share of quads is taken at (`drawn_quad_share`
    // in far_grass.wgsl), the quartiles of the field's; zw unused.
    canopy_widths: vec4<f32>,
    // The mean v at each depth into the canopy's leaf area (`drawn_canopy_v`), a vector
    // per depth over the shares of quads 0, 1/3, 2/3 and 1.
    canopy: array<vec4<f32>, 32>,
}
// sward:receiver end

@group(1) @binding(0) var<uniform> light: LightUniforms;
@group(1) @binding(1) var shadow_map: texture_depth_2d_array;
@group(1) @binding(2) var shadow_sampler: sampler_comparison;

// Perez et al.'s sky distribution for (Y, x, y) at once: (1 + A e^(B / cos theta)) (1 + C
// e^(D gamma) + E cos² gamma), theta the view's zenith angle, gamma its angle to the sun.
fn perez3(cos_theta: f32, gamma: f32, cos_gamma: f32) -> vec3<f32> {
    let a = light.perez_a.xyz;
    let b = light.perez_b.xyz;
    let c = light.perez_c.xyz;
    let d = light.perez_d.xyz;
    let e = light.perez_e.xyz;
    return (1.0 + a * exp(b / max(cos_theta, 0.01))) * (1.0 + c * exp(d * gamma) + e * cos_gamma * cos_gamma);
}

// CIE xyY to linear sRGB (Rec. 709 primaries, D65).
fn xyy_to_rgb(x: f32, y: f32, big_y: f32) -> vec3<f32> {
    let yy = max(y, 1e-4);
    let xyz = vec3<f32>(x * big_y / yy, big_y, (1.0 - x - y) * big_y / yy);
    let r = dot(vec3<f32>(3.2404542, -1.5371385, -0.4985314), xyz);
    let g = dot(vec3<f32>(-0.9692660, 1.8760108, 0.0415560), xyz);
    let b = dot(vec3<f32>(0.0556434, -0.2040259, 1.0572252), xyz);
    return max(vec3<f32>(r, g, b), vec3<f32>(0.0));
}

// The sky model a pipeline is built for (`GrassSpec::sky`: 0 Preetham, 1 the gradient), or
// ANY_SKY, the uniform's choice. llvmpipe runs both models wherever the choice is the
// uniform's; the grass's per-pixel light looks the sky up for its fog, so its pipelines
// fold the other model away.
const ANY_SKY: u32 = 0xffffffffu;
override SKY_MODEL: u32 = ANY_SKY;

// The sky's radiance along `dir` (no sun disk): Preetham's model above the horizon, the
// horizon's colour fading into a dim ground below it; or the old gradient.
fn sky_radiance(dir: vec3<f32>) -> vec3<f32> {
    let sun = frame.sun_dir.xyz;
    let h = clamp(dir.y, -1.0, 1.0);
    var gradient = light.sky.x > 0.5;
    if SKY_MODEL != ANY_SKY {
        gradient = SKY_MODEL == 1u;
    }
    if gradient {
        let zenith = vec3<f32>(0.22, 0.42, 0.78);
        let horizon = vec3<f32>(0.70, 0.80, 0.90);
        var c = mix(horizon, zenith, pow(max(h, 0.0), 0.55));
        if h < 0.0 {
            c = mix(horizon, vec3<f32>(0.45, 0.50, 0.45), min(-h * 3.0, 1.0));
        }
        let s = max(dot(dir, sun), 0.0);
        return c + vec3<f32>(1.0, 0.85, 0.6) * (pow(s, 600.0) * 4.0 + pow(s, 12.0) * 0.25);
    }
    // Below the horizon the sky is read at the horizon, then darkens towards the ground.
    let up = vec3<f32>(dir.x, max(h, 0.0), dir.z);
    let view = normalize(select(up, vec3<f32>(1.0, 0.0, 0.0), dot(up, up) < 1e-8));
    let cos_gamma = clamp(dot(view, sun), -1.0, 1.0);
    let f = perez3(max(view.y, 0.0), acos(cos_gamma), cos_gamma);
    let yxy = light.zenith.xyz * f;
    var c = xyy_to_rgb(yxy.y, yxy.z, yxy.x);
    if h < 0.0 {
        let ground = light.ambient.rgb * 0.35;
        c = mix(c, ground, min(-h * 3.0, 1.0));
    }
    return c;
}

// The sky with the sun's disk (the sky pass): limb-darkened, `sky.w` times the sun's
// radiance, so that it reads white after tone mapping.
fn sky_with_sun(dir: vec3<f32>) -> vec3<f32> {
    var c = sky_radiance(dir);
    let cos_a = dot(dir, frame.sun_dir.xyz);
    let edge = light.sky.z;
    if cos_a > edge && dir.y > -0.01 {
        let r = clamp((1.0 - cos_a) / max(1.0 - edge, 1e-7), 0.0, 1.0);
        let limb = 1.0 - 0.6 * (1.0 - sqrt(1.0 - r));
        c += light.sun.rgb * light.sky.w * limb;
    }
    return c;
}

// Aerial perspective: the surface fades into the sky seen behind it with distance
// (extinction and in-scattering along the view ray: e^(-d / fog distance)).
fn fog(color: vec3<f32>, world: vec3<f32>) -> vec3<f32> {
    let to_p = world - frame.camera_pos.xyz;
    return fog_towards(color, world, sky_radiance(to_p / max(length(to_p), 1e-4)));
}

// The world point pixel `p` of the frame shows at depth `z` (the frame's own, jittered,
// projection undone).
fn world_at(p: vec2<u32>, z: f32) -> vec3<f32> {
    let size = frame.viewport_time.xy;
    let uv = (vec2<f32>(p) + 0.5) / size;
    let ndc = vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, z, 1.0);
    let w = frame.inv_view_proj * ndc;
    return w.xyz / w.w;
}

// `fog` with the sky's radiance behind the point given (a pass that looks it up per vertex).
fn fog_towards(color: vec3<f32>, world: vec3<f32>, sky: vec3<f32>) -> vec3<f32> {
    let dist = distance(world, frame.camera_pos.xyz);
    let f = 1.0 - exp(-dist / max(frame.viewport_time.w, 1.0));
    return mix(color, sky, clamp(f, 0.0, 1.0));
}

// Stephen Hill's fit of the ACES RRT + ODT (sRGB input -> AP1 with the RRT's saturation,
// the curve, back to sRGB).
fn aces(c: vec3<f32>) -> vec3<f32> {
    let i0 = vec3<f32>(0.59719, 0.07600, 0.02840);
    let i1 = vec3<f32>(0.35458, 0.90834, 0.13383);
    let i2 = vec3<f32>(0.04823, 0.01566, 0.83777);
    let v = c.r * i0 + c.g * i1 + c.b * i2;
    let a = v * (v + 0.0245786) - 0.000090537;
    let b = v * (0.983729 * v + 0.4329510) + 0.238081;
    let w = a / b;
    let o0 = vec3<f32>(1.60475, -0.10208, -0.00327);
    let o1 = vec3<f32>(-0.53108, 1.10813, -0.07276);
    let o2 = vec3<f32>(-0.07367, -0.00605, 1.07602);
    return clamp(w.r * o0 + w.g * o1 + w.b * o2, vec3<f32>(0.0), vec3<f32>(1.0));
}

// AgX: the inset into its working space, log2 encoding over [-12.47, 4.03] EV, Benjamin
// Wrensch's polynomial fit of the base contrast curve, the outset back, linearised (the
// target's sRGB encoding is applied by the view).
fn agx(c: vec3<f32>) -> vec3<f32> {
    let i0 = vec3<f32>(0.842479062253094, 0.0423282422610123, 0.0423756549057051);
    let i1 = vec3<f32>(0.0784335999999992, 0.878468636469772, 0.0784336);
    let i2 = vec3<f32>(0.0792237451477643, 0.0791661274605434, 0.879142973793104);
    var v = c.r * i0 + c.g * i1 + c.b * i2;
    let lo = -12.47393;
    let hi = 4.026069;
    v = clamp(log2(max(v, vec3<f32>(1e-10))), vec3<f32>(lo), vec3<f32>(hi));
    v = (v - lo) / (hi - lo);
    let x2 = v * v;
    let x4 = x2 * x2;
    v = 15.5 * x4 * x2 - 40.14 * x4 * v + 31.96 * x4 - 6.868 * x2 * v + 0.4298 * x2 + 0.1191 * v - 0.00232;
    let o0 = vec3<f32>(1.19687900512017, -0.0528968517574562, -0.0529716355144438);
    let o1 = vec3<f32>(-0.0980208811401368, 1.15190312990417, -0.0980434501171241);
    let o2 = vec3<f32>(-0.0990297440797205, -0.0989611768448433, 1.15107367264116);
    v = v.r * o0 + v.g * o1 + v.b * o2;
    // The curve's output is display-encoded (gamma 2.2); the sRGB view encodes again.
    return pow(clamp(v, vec3<f32>(0.0), vec3<f32>(1.0)), vec3<f32>(2.2));
}

// The tone mapper a pipeline is built for (`render::post::ToneMap`): 0 ACES, 1 AgX, 2 the
// clamp, or GENERAL_TONE_MAPPER, the uniform's choice. llvmpipe runs every branch of an
// `if` for the whole SIMD batch, so a full-screen pass with all three curves paid for all
// three; the constant folds the others away.
const GENERAL_TONE_MAPPER: u32 = 3u;
override TONE_MAPPER: u32 = GENERAL_TONE_MAPPER;

// Exposure, then the scene's tone mapper: linear radiance in, linear display colour out.
fn tonemap(c: vec3<f32>) -> vec3<f32> {
    let x = max(c, vec3<f32>(0.0)) * light.sun.w;
    var mode = TONE_MAPPER;
    if mode == GENERAL_TONE_MAPPER {
        mode = u32(light.ambient.w);
    }
    if mode == 1u {
        return agx(x);
    }
    if mode == 2u {
        return clamp(x, vec3<f32>(0.0), vec3<f32>(1.0));
    }
    return aces(x);
}

// How much of the sun reaches `world` (1 lit, 0 in shadow): the cascade its distance from
// the camera falls in, read four times with the comparison sampler's bilinear filter
// (a percentage-closer filter; `shadow.z` spreads the taps), pushed `shadow.w` texels
// towards the sun against acne, and faded out at the shadows' end.
fn sun_visibility(world: vec3<f32>) -> f32 {
    return sun_visibility_from(world, frame.camera_pos.xyz, frame.sun_dir.xyz);
}

// `sun_visibility` seen from `camera` with the sun towards `sun_dir`: the part a host's
// shader includes to receive sward's shadows (`render::light::receiver_wgsl`, with its
// names prefixed `sward_`).
// sward:receiver begin
fn sun_visibility_from(world: vec3<f32>, camera: vec3<f32>, sun_dir: vec3<f32>) -> f32 {
    if light.shadow.x < 0.5 {
        return 1.0;
    }
    let count = u32(light.shadow.y);
    let d = distance(world, camera);
    let last = light.splits[count - 1u];
    if d >= last {
        return 1.0;
    }
    var k = 0u;
    for (var i = 0u; i + 1u < count; i++) {
        if d > light.splits[i] {
            k = i + 1u;
        }
    }
    // A far cascade may be kept from an earlier frame (render/light/schedule.rs): a point
    // its map does not cover is looked up in the next one.
    var c = vec4<f32>(0.0);
    var uv = vec2<f32>(-1.0);
    for (; k < count; k++) {
        let p = world + sun_dir * (light.shadow.w * light.texel_world[k]);
        c = light.cascades[k] * vec4<f32>(p, 1.0);
        uv = c.xy * vec2<f32>(0.5, -0.5) + 0.5;
        if all(uv >= vec2<f32>(0.0)) && all(uv <= vec2<f32>(1.0)) && c.z <= 1.0 {
            break;
        }
    }
    if k >= count {
        return 1.0;
    }
    // Four bilinear comparisons (each already weighs 2 x 2 texels) at +-(softness / 2 +
    // 1/4) texels: at the default 1.5 their footprints just touch, a flat-topped tent 4
    // texels wide. 16 depth texels are read instead of the 36 of a 3 x 3 grid of taps; this
    // lookup runs per ground and object pixel and per grass vertex.
    let o = vec2<f32>((0.5 * light.shadow.z + 0.25) * light.shadow_map.x);
    let lit = textureSampleCompareLevel(shadow_map, shadow_sampler, uv + vec2<f32>(-o.x, -o.y), k, c.z)
        + textureSampleCompareLevel(shadow_map, shadow_sampler, uv + vec2<f32>(o.x, -o.y), k, c.z)
        + textureSampleCompareLevel(shadow_map, shadow_sampler, uv + vec2<f32>(-o.x, o.y), k, c.z)
        + textureSampleCompareLevel(shadow_map, shadow_sampler, uv + o, k, c.z);
    let fade = smoothstep(light.shadow_map.z, last, d);
    return mix(lit / 4.0, 1.0, fade);
}
// sward:receiver end
