// The visibility buffer's shared half (`grass_deferred.wgsl` with one sample per pixel,
// `grass_deferred_msaa.wgsl` with several): the blades' geometry for the visibility draw,
// the pixel list and the shading of one blade point. Expects group 2's bindings of the
// including file.
//!include grass.wgsl

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

struct VisOut {
    // Invariant: the same depth as the lit pass and the coverage measurement.
    @builtin(position) @invariant clip: vec4<f32>,
    // At the pixel's centre; the multisampled draw moves it to a sample the blade covers
    // (`fs_vis_ms`).
    @location(0) uv: vec2<f32>,
    @location(1) @interpolate(flat) blade: u32,
}

@vertex
fn vs_vis(@builtin(vertex_index) batch_vid: u32, @builtin(instance_index) inst: u32) -> VisOut {
    let b = blade_vertex(batch_vid, inst);
    var out: VisOut;
    out.clip = b.out.clip;
    out.uv = b.out.uv;
    out.blade = b.index;
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
    return vis_lit_point(index, blade, ctx, uv, point, sky, sun_visibility(point.p));
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
    var ctx = BladeCtx(axes[0], axes[1], 0u, vec3<f32>(0.0), 1.0, vec4<f32>(0.0));
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
