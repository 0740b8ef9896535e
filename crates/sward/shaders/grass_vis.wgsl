// The visibility buffer's shared half (`grass_deferred.wgsl` with one sample per pixel,
// `grass_deferred_msaa.wgsl` with several): the blades' geometry for the visibility draw,
// the pixel list, the sun along the drawn blades (`blade_sun_points`, dispatched first in
// the light's pixel pass) and the shading of one blade point. Expects group 2's bindings
// of the including file.
//!include grass.wgsl

// Where the shading takes the sun's visibility from (`BladeShadowLookup`): looked up at
// each pixel (the shadows of a blade's neighbours fall across it), or interpolated from
// `blade_sun`, looked up at the blade's rows by `blade_sun_points`.
override SUN_PER_PIXEL: bool = true;

// The sun's visibility along each drawn blade (`blade_sun`, read by the shading):
// SUN_POINTS values of 8 bits from root to tip, four to a word, indexed by blade. Bound
// in the grass group to the compute stage only.
@group(0) @binding(11) var<storage, read_write> blade_sun: array<vec2<u32>>;

// The grass pixels, packed (y << 16 | x), and how many; `count` is cleared every frame.
struct PixelList {
    count: atomic<u32>,
    pixels: array<u32>,
}

// The shading's `dispatch_workgroups_indirect` arguments: x (cleared every frame) grows
// by one workgroup per SHADE_GROUP listed pixels; y and z stay 1.
struct ShadeArgs {
    x: atomic<u32>,
    y: u32,
    z: u32,
    pad: u32,
}

// Invocations per workgroup of `shade_pixels` (twin: `deferred::SHADE_GROUP`): 256, the
// most every adapter allows, so a 4K frame's grass needs at most 32,400 workgroups, under
// the 65,535 a dispatch may have along x.
const SHADE_GROUP: u32 = 256u;

// The alpha the deferred shading leaves in the scene target for each grass sample it
// lights (twin: `deferred::BLADE_ALPHA`): above the 1 of every other lit pass, so that a
// pixel's alpha 1 + (BLADE_ALPHA − 1) s tells the share s of it the blades cover (the far
// gain's measurement takes its blades there: `far_gain_common.wgsl`). The tone mapping
// reads any alpha of 1 or more as radiance.
const BLADE_ALPHA: f32 = 3.0;

struct VisOut {
    // Invariant: the same depth as the lit pass and the coverage measurement.
    @builtin(position) @invariant clip: vec4<f32>,
    // At the pixel's centre; the multisampled draw moves it to a sample the blade covers
    // (`fs_vis_ms`).
    @location(0) uv: vec2<f32>,
    @location(1) @interpolate(flat) blade: u32,
    // The blade's chord (`lod_v`): the coarse levels' v is mapped onto the curve's.
    @location(2) @interpolate(flat) chord: vec2<f32>,
}

@vertex
fn vs_vis(@builtin(vertex_index) batch_vid: u32, @builtin(instance_index) inst: u32) -> VisOut {
    let b = blade_vertex(batch_vid, inst);
    var out: VisOut;
    out.clip = b.out.clip;
    out.uv = b.out.uv;
    out.blade = b.index;
    out.chord = b.out.chord;
    return out;
}

// Blade `index` lit at (u, v) on it, before the fog: the forward fragment stage's light,
// once per pixel, in its two parts (`BladeLight`: the sky's, and the sun's times its
// visibility here); the point, the sky behind it (the fog's colour), and the albedo and
// ambient occlusion it was lit with.
struct VisLit {
    ambient: vec3<f32>,
    sun: vec3<f32>,
    point: vec3<f32>,
    sky: vec3<f32>,
    albedo: vec3<f32>,
    ao: f32,
}

fn vis_lit(index: u32, uv: vec2<f32>) -> VisLit {
    let blade = blades[index];
    let ctx = blade_ctx(blade);
    let point = blade_point(blade, ctx, index, uv.x, uv.y, 0.0);
    let sky = blade_sky(blade.v0_dir.xyz);
    return vis_lit_point(index, blade, ctx, uv, point, sky, blade_sun_visibility(index, uv.y, point.p));
}

// `vis_lit` where the pixel's world point is known (the one-sample visibility buffer keeps
// its depth), under the fog's `sky` found by the caller and with the sun `sun_lit` visible
// there (`sun_at`, from points along the blade): only the normal is taken from the
// curve. The blade's point at (u, v) would cost the thinning's widening, the shape
// and Eq. 24's width in pixels (two products with the view-projection), none of which
// changes the light; and the depth's point is the surface the draw rasterised, fold and
// all.
fn vis_lit_at(index: u32, uv: vec2<f32>, world: vec3<f32>, sky: vec3<f32>, sun_lit: f32) -> VisLit {
    let blade = blades[index];
    let ctx = light_ctx(blade);
    let centre = centre_line(blade, ctx, index, uv.y);
    let n = flat_normal(centre.t, blade.up_stiffness.xyz, ctx.side);
    return vis_lit_point(index, blade, ctx, uv, BladePoint(world, n), sky, sun_lit);
}

// What of `blade_ctx` the light and the centre line read: the blade's frame and CWD-Sim's
// wind; the rest is left neutral.
fn light_ctx(blade: Blade) -> BladeCtx {
    let axes = blade_frame(blade.up_stiffness.xyz, blade.v0_dir.w);
    var ctx = BladeCtx(axes[0], axes[1], 0u, vec3<f32>(0.0), 1.0, 0.0, vec4<f32>(0.0));
    if blade_model() == MODEL_CWD {
        ctx.cwd_wind = cwd_wind(blade.v0_dir.xyz, blade.v1_height.w);
    }
    return ctx;
}

// `vis_lit` of blade `index` at its `point` (u, v), with the sky behind it and the sun
// `sun_lit` visible there.
fn vis_lit_point(index: u32, blade: Blade, ctx: BladeCtx, uv: vec2<f32>, point: BladePoint, sky: vec3<f32>, sun_lit: f32) -> VisLit {
    // Two-sided, as the forward fragment stage lights it.
    var flat_n = normalize(point.n);
    if dot(flat_n, frame.camera_pos.xyz - point.p) < 0.0 {
        flat_n = -flat_n;
    }
    let albedo = vis_albedo(index, uv);
    let self_shade = blade_self_shade(blade, point.p);
    let l = blade_light(point.p, flat_n, ctx.side, uv, albedo, self_shade);
    let sun = sun_lit * l.sun;
    return VisLit(l.ambient, sun, point.p, sky, albedo, vis_ao(uv.y, self_shade));
}

// Blade `index`'s albedo at height v along it (`blade_albedos`, root to tip).
fn vis_albedo(index: u32, uv: vec2<f32>) -> vec3<f32> {
    let albedo = blade_albedos(index, blades[index]);
    return mix(albedo.root, albedo.tip.rgb, uv.y);
}

// `blade_light`'s ambient occlusion at height v (CWD-Sim's `self_shade` where chosen).
fn vis_ao(v: f32, self_shade: f32) -> f32 {
    let mode = u32(frame.debug.y);
    if mode == 1u {
        return self_shade;
    }
    if mode == 2u {
        return 1.0;
    }
    return mix(1.0, max(exp(-0.35 * light.shading_b.z * (1.0 - v)), 0.12), light.shading_a.w);
}

// The lit colour (fogged radiance) of blade `index` at (u, v) on it, at `world`, the fog
// turning it towards `sky`, the sun `sun_lit` visible there.
fn vis_colour(index: u32, uv: vec2<f32>, world: vec3<f32>, sky: vec3<f32>, sun_lit: f32) -> vec3<f32> {
    let lit = vis_lit_at(index, uv, world, sky, sun_lit);
    return fog_towards(lit.ambient + lit.sun, lit.point, lit.sky);
}

// Points along a blade at which `blade_sun` looks the sun up (twin: `deferred::SUN_POINTS`):
// at v = k / 7. A blade is narrower than a shadow texel, so only its length needs
// sampling, and the forward pass samples it at its 4 to 16 rows of vertices.
const SUN_POINTS: u32 = 8u;
// Invocations of `blade_sun` (twin: `deferred::SUN_INVOCATIONS`): 16 workgroups of 64,
// each invocation taking every SUN_INVOCATIONS-th drawn blade. Few, because a software
// rasteriser runs a loop's body once more with every lane off after its last blade: the
// frame pays SUN_INVOCATIONS of those whatever it draws.
const SUN_INVOCATIONS: u32 = 1024u;

// The drawn blades' sun (`blade_sun` above). One lookup per listed pixel cost four
// filtered taps and the cascade's choice for each of the 670,000 pixels the peer's 8,192
// blades cover at 1280 x 720; here one per row of each drawn blade (about 27,000). The slots visited
// are those the draw drew: each level's early list, then its late list (`blade_vertex`),
// the levels one after the other in one loop.
@compute @workgroup_size(64)
fn blade_sun_points(@builtin(global_invocation_id) gid: vec3<u32>) {
    // Multi-draw binds every level's region; one draw per level binds its own.
    var first = draw_level.x;
    var levels = 1u;
    var region = 0u;
    if first == FROM_INSTANCE {
        first = 0u;
        levels = 3u;
        region = max(draw_level.y, 1u);
    }
    // The blades of the levels bound, in order: level `first + k` holds `counts[k]`.
    var counts = vec3<u32>(0u);
    for (var k = 0u; k < levels; k++) {
        counts[k] = drawn.early[first + k] + drawn.late[first + k];
    }
    let total = counts.x + counts.y + counts.z;
    for (var i = gid.x; i < total; i += SUN_INVOCATIONS) {
        let k = u32(i >= counts.x) + u32(i >= counts.x + counts.y);
        let before = select(0u, counts.x, k >= 1u) + select(0u, counts.y, k >= 2u);
        let j = i - before;
        let early = drawn.early[first + k];
        let rel = select(j, late_start(early) + (j - early), j >= early);
        let index = visible[k * region + rel];
        // As many points as the level's mesh has rows of vertices (the forward pass's
        // lookups), SUN_POINTS at most.
        let points = min(cull.lod_segments[first + k] + 1u, SUN_POINTS);
        blade_sun[index] = sun_along(index, points);
    }
}

// The sun's visibility along blade `index`'s centre line, 8 bits at each of SUN_POINTS
// heights v = j / 7: looked up at `points` (2 to SUN_POINTS) evenly spaced heights, and
// linearly between them. Each value is packed as soon as the point above it is known
// (a software rasteriser keeps a private array indexed per lane in memory).
fn sun_along(index: u32, points: u32) -> vec2<u32> {
    let blade = blades[index];
    let ctx = light_ctx(blade);
    let steps = f32(max(points, 2u) - 1u);
    var words = vec2<u32>(0u);
    var below = 0.0;
    var slot = 0u;
    for (var k = 0u; k < points; k++) {
        let here = sun_visibility(centre_line(blade, ctx, index, f32(k) / steps).p);
        // The values at heights up to this point's (x = j · steps / 7 in points), between
        // the point below and this one.
        loop {
            let x = f32(slot) * steps / f32(SUN_POINTS - 1u);
            if slot >= SUN_POINTS || x > f32(k) {
                break;
            }
            let value = select(mix(below, here, x - f32(k) + 1.0), here, k == 0u);
            let byte = u32(round(clamp(value, 0.0, 1.0) * 255.0)) << (8u * (slot & 3u));
            if slot < 4u {
                words.x |= byte;
            } else {
                words.y |= byte;
            }
            slot += 1u;
        }
        below = here;
    }
    return words;
}

// Blade `index`'s sun at height `v` on it: `blade_sun`'s points, linearly between them.
fn sun_at(index: u32, v: f32) -> f32 {
    let w = blade_sun[index];
    let x = clamp(v, 0.0, 1.0) * f32(SUN_POINTS - 1u);
    let k = min(u32(x), SUN_POINTS - 2u);
    let a = (select(w.x, w.y, k >= 4u) >> (8u * (k & 3u))) & 0xffu;
    let b = (select(w.x, w.y, k + 1u >= 4u) >> (8u * ((k + 1u) & 3u))) & 0xffu;
    return mix(f32(a), f32(b), x - f32(k)) / 255.0;
}

// The sun's visibility at `world`, height `v` on blade `index`: looked up there, or from the
// values along the blade (`SUN_PER_PIXEL`).
fn blade_sun_visibility(index: u32, v: f32, world: vec3<f32>) -> f32 {
    if SUN_PER_PIXEL {
        return sun_visibility(world);
    }
    return sun_at(index, v);
}
