// Deferred grass shading with multisampling (issue 26, point 5 with MSAA; `render/deferred.rs`):
// the lit shading runs once per pixel the grass covers, the samples keep the coverage.
//
// 1. `vs_vis` / `fs_vis_ms`: the blades into a multisampled visibility buffer (blade index
//    + 1 in two 16-bit halves, 0 where none; u and v in 16 bits each), with the
//    multisampled depth; the fragment stage runs once per pixel and its output lands in the
//    samples the blade covers. It also writes alpha GRASS_ALPHA into the multisampled
//    colour, the main and the late draw alike. Its (u, v) are taken at the first covered
//    sample, not extrapolated to a pixel centre off the blade.
// 2. The colour pass draws everything else into the multisampled colour: every lit pass
//    writes alpha 1, the arrows 0 and the cards their coverage, so a sample still at
//    GRASS_ALPHA (negative) after all draws is grass that nothing covered later.
// 3. After the hardware resolve, `blade_sun_points` looks the sun up along the drawn
//    blades (grass_vis.wgsl, with `PerRow`), `grass_pixels_ms` lists the pixels with a
//    grass sample; `shade_pixels_ms` lights each distinct blade in the pixel once, at its
//    first sample's blade point (`vis_lit`), and resolves the pixel itself: in each grass
//    sample its blade's light on the sample's own albedo and height, the multisampled
//    colour in the others, averaged as the hardware resolve averages; the grass samples
//    with alpha BLADE_ALPHA, so the pixel's alpha tells the share the blades cover.
//!include grass_vis.wgsl

@group(2) @binding(0) var vis_ms: texture_multisampled_2d<u32>;
@group(2) @binding(1) var colour_ms: texture_multisampled_2d<f32>;
@group(2) @binding(2) var scene_out: texture_storage_2d<rgba16float, write>;
@group(2) @binding(3) var<storage, read_write> pixel_list: PixelList;
// Bound to the pixel pass only (as in grass_deferred.wgsl).
@group(2) @binding(4) var<storage, read_write> shade_args: ShadeArgs;

// The grass samples' colour alpha (`deferred::GRASS_ALPHA`): no pass writes a negative one.
const GRASS_ALPHA: f32 = -1.0;

struct VisMsOut {
    @location(0) vis: vec4<u32>,
    @location(1) colour: vec4<f32>,
}

// Samples per pixel of the multisampled target (`DeferredPipelines::new`).
override MSAA_SAMPLES: u32 = 4u;

// The standard position of sample `i` of `MSAA_SAMPLES` in the pixel (Vulkan's and
// WebGPU's standard sample locations), from the pixel's corner.
fn sample_position(i: u32) -> vec2<f32> {
    if MSAA_SAMPLES == 2u {
        return array<vec2<f32>, 2>(vec2<f32>(0.75, 0.75), vec2<f32>(0.25, 0.25))[i & 1u];
    }
    if MSAA_SAMPLES == 8u {
        return array<vec2<f32>, 8>(
            vec2<f32>(0.5625, 0.3125), vec2<f32>(0.4375, 0.6875), vec2<f32>(0.8125, 0.5625), vec2<f32>(0.3125, 0.1875),
            vec2<f32>(0.1875, 0.8125), vec2<f32>(0.0625, 0.4375), vec2<f32>(0.6875, 0.9375), vec2<f32>(0.9375, 0.0625),
        )[i & 7u];
    }
    return array<vec2<f32>, 4>(
        vec2<f32>(0.375, 0.125), vec2<f32>(0.875, 0.375), vec2<f32>(0.125, 0.625), vec2<f32>(0.625, 0.875),
    )[i & 3u];
}

@fragment
fn fs_vis_ms(in: VisOut, @builtin(sample_mask) covered: u32) -> VisMsOut {
    // (u, v) at the first sample the blade covers, not at the pixel's centre, which may lie
    // off a thin blade (where (u, v) run past its tip and edges): moved there along the
    // screen derivatives. Centroid interpolation would do it, but llvmpipe's is not
    // deterministic from run to run.
    let d = sample_position(countTrailingZeros(covered)) - 0.5;
    let at = in.uv + dpdx(in.uv) * d.x + dpdy(in.uv) * d.y;
    var on = clamp(at, vec2<f32>(0.0), vec2<f32>(1.0));
    on.y = lod_v(on.y, in.chord);
    let uv = vec2<u32>(round(on * 65535.0));
    let id = in.blade + 1u;
    return VisMsOut(vec4<u32>(id & 0xffffu, id >> 16u, uv.x, uv.y), vec4<f32>(0.0, 0.0, 0.0, GRASS_ALPHA));
}

// Sample `s` of pixel `px`: its multisampled colour, and from the visibility buffer the
// blade it shows (index + 1, 0 where none) and the (u, v) on it.
struct MsSample {
    colour: vec4<f32>,
    blade: u32,
    uv: vec2<f32>,
}

fn ms_sample(px: vec2<i32>, s: u32) -> MsSample {
    let vis = textureLoad(vis_ms, px, i32(s));
    return MsSample(textureLoad(colour_ms, px, i32(s)), vis.x | (vis.y << 16u), vec2<f32>(vis.zw) / 65535.0);
}

// Whether a sample is grass: marked in the colour, with a blade.
fn is_grass(m: MsSample) -> bool {
    return m.colour.a == GRASS_ALPHA && m.blade != 0u;
}

@compute @workgroup_size(8, 8)
fn grass_pixels_ms(@builtin(global_invocation_id) gid: vec3<u32>) {
    let size = textureDimensions(vis_ms);
    if gid.x >= size.x || gid.y >= size.y {
        return;
    }
    let px = vec2<i32>(gid.xy);
    let samples = textureNumSamples(colour_ms);
    var grass = false;
    for (var s = 0u; s < samples; s++) {
        grass = grass || is_grass(ms_sample(px, s));
    }
    if !grass {
        return;
    }
    let i = atomicAdd(&pixel_list.count, 1u);
    if i % SHADE_GROUP == 0u {
        atomicAdd(&shade_args.x, 1u);
    }
    // Multisampled targets are at most 16384 wide (`DeferredTargets::fits`): 14 bits each.
    pixel_list.pixels[i] = (gid.y << 14u) | gid.x;
}

// The light of one blade in a pixel, per unit of albedo and of its height terms
// (`blade_light`: the sky's part goes with the ambient occlusion, the sun's mostly with
// 0.55 + 0.45 of it), so that each of its samples, higher or lower on it, takes its own share.
struct PixelLight {
    ambient: vec3<f32>,
    sun: vec3<f32>,
    point: vec3<f32>,
    sky: vec3<f32>,
    ao: f32,
}

fn pixel_light(id: u32, uv: vec2<f32>) -> PixelLight {
    let lit = vis_lit(id, uv);
    let albedo = max(lit.albedo, vec3<f32>(1e-4));
    let ambient = lit.ambient / (albedo * max(lit.ao, 1e-3));
    let sun = lit.sun / (albedo * mix(0.55, 1.0, lit.ao));
    return PixelLight(ambient, sun, lit.point, lit.sky, lit.ao);
}

@compute @workgroup_size(256)
fn shade_pixels_ms(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= atomicLoad(&pixel_list.count) {
        return;
    }
    let packed = pixel_list.pixels[gid.x];
    let px = vec2<i32>(vec2<u32>(packed & 0x3fffu, (packed >> 14u) & 0x3fffu));
    // The pixel's first two distinct blades each take their own light, lit at the first
    // sample each covers, and give it to all of their samples; a third or fourth blade
    // (rare: a pixel's 4 samples on 3 blades) takes the first's. One light for the whole
    // pixel (its first grass sample's blade) made the pixel's light depend on which blade
    // that sample landed on, and so on how many blades share the pixel: thinning (Eq. 20)
    // darkened the blades seen turned from the sun by 6-10 % (docs/levels.md). A light per
    // sample cost the pass about twice; these two cost it about 1.2 times. In scalars, not
    // arrays: llvmpipe keeps an indexed array in memory, which cost as much as the light.
    let samples = textureNumSamples(colour_ms);
    var first = 0xffffffffu;
    var second = 0xffffffffu;
    var first_uv = vec2<f32>(0.0);
    var second_uv = vec2<f32>(0.0);
    for (var s = 0u; s < samples; s++) {
        let m = ms_sample(px, s);
        if is_grass(m) {
            let id = m.blade - 1u;
            if first == 0xffffffffu {
                first = id;
                first_uv = m.uv;
            } else if second == 0xffffffffu && id != first {
                second = id;
                second_uv = m.uv;
            }
        }
    }
    let light_first = pixel_light(first, first_uv);
    var light_second = light_first;
    if second != 0xffffffffu {
        light_second = pixel_light(second, second_uv);
    }
    var sum = vec4<f32>(0.0);
    for (var s = 0u; s < samples; s++) {
        let m = ms_sample(px, s);
        if !is_grass(m) {
            sum += m.colour;
            continue;
        }
        let id = m.blade - 1u;
        let uv = m.uv;
        var l = light_first;
        if id == second {
            l = light_second;
        }
        // The light's direction terms vary little along a blade within a pixel; the colour
        // along it, root to tip, and the occlusion do.
        let ao = vis_ao(uv.y, l.ao);
        let own = vis_albedo(id, uv) * (l.ambient * ao + l.sun * mix(0.55, 1.0, ao));
        sum += vec4<f32>(fog_towards(own, l.point, l.sky), BLADE_ALPHA);
    }
    textureStore(scene_out, px, sum / f32(samples));
}
