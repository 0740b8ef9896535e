// Deferred grass shading (issue 26, point 5: the lit shading once per covered pixel;
// `render/deferred.rs`). A software rasteriser shades a fragment for every pixel of each
// 4 x 4 block a blade touches, and blades a pixel or two wide touch many blocks with few
// pixels each: the forward grass ran its lighting about 25 times per covered pixel. Here
// the draw only writes which blade and where on it (the visibility buffer), and the light
// runs once per grass pixel, in compute, which spreads over every core:
//
// 1. `vs_vis` / `fs_vis`: the blades' geometry as the lit pass builds it (`blade_vertex`);
//    each fragment writes (blade index, pack2x16unorm(u, v), its depth's bits, 1).
// 2. With `light.shadows.blade_lookup: PerRow`, `blade_sun_points` (grass_vis.wgsl): the
//    sun's visibility at each drawn blade's rows, kept in `blade_sun`; the shading
//    interpolates it at the pixel's height on the blade, as the forward pass interpolates
//    it between the blade's vertices (`PerPixel` looks it up at the pixel).
// 3. `grass_pixels`: one invocation per pixel keeps the pixels whose visibility texel is
//    grass and whose depth is still the grass's (an object or the ground drawn later in
//    front of it changed the depth), appending them to a list; every 256th appended pixel
//    adds a workgroup to the shading's indirect dispatch.
// 4. `shade_pixels`: one invocation per listed pixel rebuilds the blade's normal at (u, v)
//    on its curve (Eq. 21-24, as the vertex stage does) and its colours, lights it with
//    the forward pass's own `shade_blade` and fog, and writes the scene target.
//
// Used when the grass pipelines are specialised without flowers and debug views, with
// one sample per pixel and filled triangles; otherwise the grass is drawn forward.
//!include grass_vis.wgsl
//!include octahedral.wgsl

@group(2) @binding(0) var vis_buffer: texture_2d<u32>;
@group(2) @binding(1) var depth_buffer: texture_depth_2d;
@group(2) @binding(2) var scene_out: texture_storage_2d<rgba16float, write>;
@group(2) @binding(3) var<storage, read_write> pixel_list: PixelList;
// Bound to the pixel pass only: the shading pass reads it as its indirect arguments, which
// a storage binding in the same dispatch may not (it binds a stand-in).
@group(2) @binding(4) var<storage, read_write> shade_args: ShadeArgs;
// The sky's radiance over every direction (`sky_towards`), for the fog: written by
// `sky_directions` in the pixel pass, sampled by the shading. Each pass binds a stand-in
// texture in the other's place (one texture cannot be written and sampled in a dispatch).
@group(2) @binding(5) var sky_lut_out: texture_storage_2d<rgba16float, write>;
@group(2) @binding(6) var sky_lut: texture_2d<f32>;
@group(2) @binding(7) var sky_sampler: sampler;

// Texels per side of the sky's table (twin: `deferred::SKY_LUT_SIDE`).
const SKY_LUT_SIDE: u32 = 64u;

@fragment
fn fs_vis(in: VisOut) -> @location(0) vec4<u32> {
    var uv = clamp(in.uv, vec2<f32>(0.0), vec2<f32>(1.0));
    uv.y = lod_v(uv.y, in.chord);
    return vec4<u32>(in.blade, pack2x16unorm(uv), bitcast<u32>(in.clip.z), 1u);
}

// Pixels along a row that one `grass_pixels` invocation lists (twin: `deferred::LIST_RUN`).
// The pass's cost on llvmpipe is its invocations, one per pixel of the frame before
// (7-12 ms at 1280 x 720 with no grass at all); a run of four takes a quarter of them, with
// one atomic per run instead of one per pixel.
const LIST_RUN: u32 = 4u;

// Whether pixel `px` (in the target of `size`) is listed: grass whose depth is still the
// grass's (an object or the ground drawn later in front of it changed the depth).
fn listed(px: vec2<i32>, size: vec2<u32>) -> bool {
    if u32(px.x) >= size.x {
        return false;
    }
    let vis = textureLoad(vis_buffer, px, 0);
    return vis.w != 0u && bitcast<f32>(vis.z) == textureLoad(depth_buffer, px, 0);
}

@compute @workgroup_size(8, 8)
fn grass_pixels(@builtin(global_invocation_id) gid: vec3<u32>) {
    let size = textureDimensions(vis_buffer);
    let x0 = gid.x * LIST_RUN;
    if x0 >= size.x || gid.y >= size.y {
        return;
    }
    let y = i32(gid.y);
    let k0 = listed(vec2<i32>(i32(x0), y), size);
    let k1 = listed(vec2<i32>(i32(x0 + 1u), y), size);
    let k2 = listed(vec2<i32>(i32(x0 + 2u), y), size);
    let k3 = listed(vec2<i32>(i32(x0 + 3u), y), size);
    let n = u32(k0) + u32(k1) + u32(k2) + u32(k3);
    if n == 0u {
        return;
    }
    let i = atomicAdd(&pixel_list.count, n);
    // The shading's workgroups: one per SHADE_GROUP listed pixels, so this run adds those
    // whose first pixel it lists (their sum over the runs is the count's ceiling).
    let groups = (i + n + SHADE_GROUP - 1u) / SHADE_GROUP - (i + SHADE_GROUP - 1u) / SHADE_GROUP;
    if groups != 0u {
        atomicAdd(&shade_args.x, groups);
    }
    // Targets are at most 65536 wide (`DeferredTargets::fits`): 16 bits each.
    let row = gid.y << 16u;
    var at = i;
    if k0 {
        pixel_list.pixels[at] = row | x0;
        at += 1u;
    }
    if k1 {
        pixel_list.pixels[at] = row | (x0 + 1u);
        at += 1u;
    }
    if k2 {
        pixel_list.pixels[at] = row | (x0 + 2u);
        at += 1u;
    }
    if k3 {
        pixel_list.pixels[at] = row | (x0 + 3u);
    }
}

// One texel of the sky's table per invocation: `sky_radiance` at its centre's direction.
// The fog's sky was looked up per grass pixel (the Perez model's exponentials, an arc
// cosine and a matrix), about a tenth of the shading; the table costs 4,096 lookups a
// frame and one filtered read per pixel.
@compute @workgroup_size(8, 8)
fn sky_directions(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= SKY_LUT_SIDE || gid.y >= SKY_LUT_SIDE {
        return;
    }
    let uv = (vec2<f32>(gid.xy) + 0.5) / f32(SKY_LUT_SIDE);
    textureStore(sky_lut_out, vec2<i32>(gid.xy), vec4<f32>(sky_radiance(octahedral_direction(uv)), 1.0));
}

// The sky's radiance along `dir` from the table (bilinear between its texel centres).
fn sky_towards(dir: vec3<f32>) -> vec3<f32> {
    return textureSampleLevel(sky_lut, sky_sampler, octahedral_uv(dir), 0.0).rgb;
}

@compute @workgroup_size(256)
fn shade_pixels(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= atomicLoad(&pixel_list.count) {
        return;
    }
    let packed = pixel_list.pixels[gid.x];
    let px = vec2<i32>(vec2<u32>(packed & 0xffffu, packed >> 16u));
    let vis = textureLoad(vis_buffer, px, 0);
    let world = world_at(vec2<u32>(px), bitcast<f32>(vis.z));
    // The fog's sky behind the blade (`blade_sky`: towards its root).
    let sky = sky_towards(normalize(blades[vis.x].v0_dir.xyz - frame.camera_pos.xyz));
    let uv = unpack2x16unorm(vis.y);
    let sun = blade_sun_visibility(vis.x, uv.y, world);
    textureStore(scene_out, px, vec4<f32>(vis_colour(vis.x, uv, world, sky, sun), BLADE_ALPHA));
}
